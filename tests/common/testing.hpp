// Helpers shared by the tests.
#ifndef MULTICAGE_TESTING_HPP
#define MULTICAGE_TESTING_HPP

#include <gtest/gtest.h>

#include <opencv2/multicage.hpp>
#include <string>

#include "fixtures.hpp"

namespace multicage_testing {

/** Path of a file in samples/data. */
std::string samplePath(const std::string& name);
/** Reads samples/data/NAME, failing the test if it cannot. */
cv::Mat readSample(const std::string& name, int flags = 1 /* IMREAD_COLOR */);
/** Peak signal-to-noise ratio in dB (cv::PSNR with the type's range). */
double psnr(const cv::Mat& a, const cv::Mat& b);
/** A fresh empty folder under the build tree's temporary area. */
std::string tempDir(const std::string& name);

/** The butterfly of the paper: an outer polygon around the wings and an inner one around the
body, for butterfly.jpg (493x356). */
cv::multicage::Multicage butterflyCage(bool withBody);

/** Mean distance of `moved` from the best similarity transform of `rest` onto it
(cv::estimateAffinePartial2D over all points): 0 for a rigid motion plus uniform scale. */
double similarityResidual(const std::vector<cv::Point2f>& rest, const std::vector<cv::Point2f>& moved);

}  // namespace multicage_testing

#endif

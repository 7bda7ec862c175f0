// Helpers shared by the tests.
#ifndef MULTICAGE_TESTING_HPP
#define MULTICAGE_TESTING_HPP

#include <gtest/gtest.h>

#include <opencv2/multicage.hpp>
#include <string>

#include "fixtures.hpp"

namespace multicage_testing {

/** Whether this build writes .gif (giflib was found: MULTICAGE_WITH_GIF). */
constexpr bool kHaveGif = MULTICAGE_TEST_HAVE_GIF != 0;
/** The extension of an animation file this build writes: ".gif", or ".avi" without giflib. */
inline std::string animationExtension() {
    return kHaveGif ? ".gif" : ".avi";
}

/** Whether this build runs under AddressSanitizer (MULTICAGE_SANITIZE): the few tests that
repeat one path hundreds of times run fewer rounds there, where each is 5-20 times slower and a
memory error shows on the first. */
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kSanitized = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif
#else
constexpr bool kSanitized = false;
#endif

/** Path of a file in samples/data. */
std::string samplePath(const std::string& name);
/** Reads samples/data/NAME, failing the test if it cannot. */
cv::Mat readSample(const std::string& name, int flags = 1 /* IMREAD_COLOR */);
/** Peak signal-to-noise ratio in dB (cv::PSNR with the type's range). */
double psnr(const cv::Mat& a, const cv::Mat& b);
/** Same size, type and bytes, row by row (views included): "bit for bit". */
bool sameBits(const cv::Mat& a, const cv::Mat& b);
/** How far an inverse map (CV_32F) is from a reference of its size: pixels `uncovered` in one
and not the other, and the largest difference where both cover, in float roundings of the
reference value (FLT_EPSILON times its magnitude, at least 1). */
struct MapAgreement {
    int coverage = 0;
    double roundings = 0;
};
MapAgreement compareMaps(const cv::Mat& a, const cv::Mat& ref, float uncovered);
/** A fresh empty folder under the build tree's temporary area. */
std::string tempDir(const std::string& name);

/** The butterfly of the paper: an outer polygon around the wings and an inner one around the
body, for butterfly.jpg (493x356). */
cv::multicage::Multicage butterflyCage(bool withBody);

/** The one measure of "a face stays a face", shared with the demo and the proposal
benchmark (apps/common/fixtures). */
using multicage_fixtures::boxNodes;
using multicage_fixtures::boxResidual;
using multicage_fixtures::similarityResidual;

/** The worst errors of a binding's two defining properties over all its nodes: |sum_j CC_j - 1|
(partition of unity) and |sum_j CC_j v_j - x| in px (linear precision), in double. */
struct PartitionErrors {
    double sum = 0, position = 0;
};
PartitionErrors partitionErrors(const cv::multicage::Binding& b);

/** What a command-line tool printed: its std::system status, stdout and stderr. */
struct CliRun {
    int status;
    std::string out, err;
};
/** Runs `TOOL ARGS` with stdout and stderr caught in files of `dir`. */
CliRun runCli(const std::string& tool, const std::string& dir, const std::string& args);
/** The whole content of a file ("" when it cannot be read). */
std::string slurp(const std::string& path);

}  // namespace multicage_testing

#endif

// The CPU backend (private): node positions, mesh rasterised into inverse maps, cv::remap.
#ifndef MULTICAGE_CPU_DEFORMER_HPP
#define MULTICAGE_CPU_DEFORMER_HPP

#include <opencv2/multicage/deformer.hpp>

namespace cv {
namespace multicage {

Ptr<Deformer> createCpuDeformer(const Mat& image, const Binding& binding, const DeformParams& params);

/** Throws a cv::Exception unless image is a non-empty 8U/16U/32F image with 1, 3 or 4 channels. */
void checkImage(InputArray image);

}  // namespace multicage
}  // namespace cv

#endif

// multicage: multicage image deformation on the GPU, for OpenCV pipelines.
//   Multicage  -> bind() -> Binding -> Deformer (GPU or CPU) -> cv::Mat
//   proposeMulticage() makes a multicage from an image.
#ifndef OPENCV2_MULTICAGE_HPP
#define OPENCV2_MULTICAGE_HPP

#include <opencv2/multicage/multicage.hpp>
#include <opencv2/multicage/imageio.hpp>
#include <opencv2/multicage/coordinates.hpp>
#include <opencv2/multicage/packing.hpp>
#include <opencv2/multicage/deformer.hpp>
#include <opencv2/multicage/gpu.hpp>
#include <opencv2/multicage/propose.hpp>
#include <opencv2/multicage/animate.hpp>
#include <opencv2/multicage/augment.hpp>
#include <opencv2/multicage/resize.hpp>

#endif

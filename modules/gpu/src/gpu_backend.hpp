// The deform module's only door into the GPU module (private to the library).
#ifndef MULTICAGE_GPU_BACKEND_HPP
#define MULTICAGE_GPU_BACKEND_HPP

#include <opencv2/multicage/deformer.hpp>
#include <string>

namespace cv {
namespace multicage {
namespace gpu {

/** The GL deformer for image and binding, or nullptr with the reason in *why when no EGL
context can be made (no driver, no device, too old a GL). Other failures throw. */
Ptr<Deformer> createDeformer(const Mat& image, const Binding& binding, const DeformParams& params,
                             std::string* why);

/** As above, binding rest on the GPU (params.gpuBinding with mean value coordinates). */
Ptr<Deformer> createDeformer(const Mat& image, const Multicage& rest, const DeformParams& params,
                             std::string* why);

}  // namespace gpu
}  // namespace multicage
}  // namespace cv

#endif

// The deform module's only door into the GPU module (private to the library).
#ifndef MULTICAGE_GPU_BACKEND_HPP
#define MULTICAGE_GPU_BACKEND_HPP

#include <opencv2/multicage/deformer.hpp>
#include <string>

namespace cv {
namespace multicage {
namespace gpu {

/** Whether the process's shared EGL context is on a hardware device (not llvmpipe): what
BACKEND_AUTO and the default gpuBinding take as "a real GPU". *description: the device, or
why not. Probes once per process (EglContext::shared). */
bool hardwareGpu(std::string* description);

/** The GL deformer for image and binding, or nullptr with the reason in *why when no EGL
context can be made (no driver, no device, too old a GL), or when the only OpenGL is a software
renderer and params.backend is BACKEND_AUTO: llvmpipe runs the vertex shader on the CPU, 5 to 10
times slower than the CPU backend, so AUTO means "a real GPU, else the CPU backend".
BACKEND_GPU takes whatever OpenGL there is. Other failures throw. */
Ptr<Deformer> createDeformer(const Mat& image, const Binding& binding, const DeformParams& params,
                             std::string* why);

/** As above, binding rest on the GPU (params.gpuBinding with mean value coordinates). */
Ptr<Deformer> createDeformer(const Mat& image, const Multicage& rest, const DeformParams& params,
                             std::string* why);

}  // namespace gpu
}  // namespace multicage
}  // namespace cv

#endif

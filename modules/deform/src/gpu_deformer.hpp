// The GPU backend (private): a GLDeformer in the process's shared headless context. Built on
// the gpu module's public API only (gpu.hpp); the gpu module knows nothing of Deformer.
#ifndef MULTICAGE_GPU_DEFORMER_HPP
#define MULTICAGE_GPU_DEFORMER_HPP

#include <opencv2/multicage/deformer.hpp>
#include <string>

namespace cv {
namespace multicage {

/** The shared headless context when it is on a hardware device (not a software renderer),
else nullptr with the reason in *why: the "hardware GPU" of BACKEND_AUTO's rule
(deformer.hpp) and of the default gpuBinding. Probes once per process. */
HeadlessGLContext* hardwareContext(std::string* why);

/** The GPU deformer for image and binding, or nullptr with the reason in *why when no EGL
context can be made (no driver, no device, too old a GL), or when params.backend is
BACKEND_AUTO and hardwareContext() finds none. BACKEND_GPU takes whatever OpenGL there is.
Other failures throw. */
Ptr<Deformer> createGpuDeformer(const Mat& image, const Binding& binding,
                                const DeformParams& params, std::string* why);

/** As above, binding rest on the GPU (params.gpuBinding with mean value coordinates). */
Ptr<Deformer> createGpuDeformer(const Mat& image, const Multicage& rest, const DeformParams& params,
                                std::string* why);

}  // namespace multicage
}  // namespace cv

#endif

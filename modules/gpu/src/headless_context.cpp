// HeadlessGLContext (a made or the process's shared EGL context), and what runs on the shared
// one without a caller's context: bindOnGpu and gpuAvailable.
#include <opencv2/multicage/gpu.hpp>

#include "egl_context.hpp"

namespace cv {
namespace multicage {

HeadlessGLContext::HeadlessGLContext() {
    std::string why;
    owned_ = gpu::EglContext::create(&why);
    if (!owned_) CV_Error(Error::GpuNotSupported, "multicage: no headless OpenGL context: " + why);
    context_ = owned_.get();
}

HeadlessGLContext::HeadlessGLContext(gpu::EglContext* shared) : context_(shared) {}

HeadlessGLContext::~HeadlessGLContext() = default;

HeadlessGLContext* HeadlessGLContext::shared(std::string* why) {
    gpu::EglContext* context = gpu::EglContext::shared(why);
    if (!context) return nullptr;
    // Never destroyed, as the EGL context it wraps: Deformers may outlive static destruction.
    static HeadlessGLContext* const wrapper = new HeadlessGLContext(context);
    return wrapper;
}

std::string HeadlessGLContext::description() const {
    return context_->description();
}

bool HeadlessGLContext::software() const {
    return context_->software();
}

struct HeadlessGLContext::Scope::State {
    gpu::EglContext::Scope scope;
};

HeadlessGLContext::Scope::Scope(const HeadlessGLContext& c)
    : state_(new State{gpu::EglContext::Scope(*c.context_)}) {}

HeadlessGLContext::Scope::~Scope() = default;

Binding bindOnGpu(const Multicage& multicage, int gridStep) {
    std::string why;
    HeadlessGLContext* context = HeadlessGLContext::shared(&why);
    if (!context) CV_Error(Error::GpuNotSupported, "multicage: bindOnGpu: " + why);
    HeadlessGLContext::Scope scope(*context);
    // A blank single-channel image: the GLDeformer needs one, the binding does not.
    const Mat image(multicage.imageSize(), CV_8UC1, Scalar(0));
    GLDeformer d(image, multicage, gridStep);
    return d.binding();
}

bool gpuAvailable(std::string* description) {
    std::string why;
    const HeadlessGLContext* context = HeadlessGLContext::shared(&why);
    if (description) *description = context ? context->description() : why;
    return context != nullptr;
}

}  // namespace multicage
}  // namespace cv

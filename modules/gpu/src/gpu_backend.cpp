// The headless GPU Deformer: a GLDeformer in the process's shared EGL context, readback.
#include "gpu_backend.hpp"

#include <opencv2/multicage/gpu.hpp>

#include "egl_context.hpp"
#include "gl_util.hpp"

namespace cv {
namespace multicage {
namespace gpu {

namespace {

/** Every instance lives in the process's shared EGL context (EglContext::shared): one
context creation per process, and programs compiled once per layout. Every call makes the
context current on the calling thread under its mutex and releases it afterwards, so
Deformers on different threads take turns and never see each other's GL state. */
class GpuDeformer final : public Deformer {
  public:
    GpuDeformer(EglContext* context, const DeformParams& params)
        : context_(context), border_(params.borderValue) {}

    ~GpuDeformer() override {
        if (!gl_) return;
        try {
            EglContext::Scope scope(*context_);
            gl_.reset();
        } catch (...) {  // a destructor must not throw; the context goes away regardless
        }
    }

    template <typename Source>
    void init(const Mat& image, const Source& source, const DeformParams& params) {
        EglContext::Scope scope(*context_);
        GLDeformerParams p;
        p.halfFloat = params.halfFloat;
        p.pipeline = params.pipeline;
        make(image, source, params, p);
    }

    void deform(InputArray pose, OutputArray dst) override {
        EglContext::Scope scope(*context_);
        gl_->setPose(pose);
        gl_->render(border_);
        gl_->readOutput(dst);
    }

    void computeMaps(InputArray pose, OutputArray mapx, OutputArray mapy) override {
        EglContext::Scope scope(*context_);
        gl_->setPose(pose);
        gl_->renderMaps();
        gl_->readMaps(mapx, mapy);
    }

    int backend() const override { return BACKEND_GPU; }
    // A GPU binding is read back only when asked for (240 MB at 1024x768 with 68 vertices):
    // creating the Deformer does not pay for it.
    const Binding& binding() const override {
        EglContext::Scope scope(*context_);
        return gl_->binding();
    }
    String getDefaultName() const override { return "multicage.GpuDeformer"; }

  private:
    void make(const Mat& image, const Binding& b, const DeformParams&, const GLDeformerParams& p) {
        gl_.reset(new GLDeformer(image, b, p));
    }
    void make(const Mat& image, const Multicage& rest, const DeformParams& params,
              const GLDeformerParams& p) {
        gl_.reset(new GLDeformer(image, rest, params.gridStep, p));
    }

    EglContext* context_;
    std::unique_ptr<GLDeformer> gl_;
    Scalar border_;
};

// The shared context if AUTO would use it (a hardware device), else nullptr with *why.
EglContext* acceleratedContext(std::string* why) {
    EglContext* context = EglContext::shared(why);
    if (context && context->software()) {
        if (why) *why = "the only OpenGL here is a software renderer (" + context->description() +
                        "), slower than the CPU backend";
        return nullptr;
    }
    return context;
}

template <typename Source>
Ptr<Deformer> create(const Mat& image, const Source& source, const DeformParams& params,
                     std::string* why) {
    EglContext* context =
        params.backend == BACKEND_AUTO ? acceleratedContext(why) : EglContext::shared(why);
    if (!context) return Ptr<Deformer>();
    Ptr<GpuDeformer> d(new GpuDeformer(context, params));
    d->init(image, source, params);
    return d;
}

}  // namespace

Ptr<Deformer> createDeformer(const Mat& image, const Binding& binding, const DeformParams& params,
                             std::string* why) {
    return create(image, binding, params, why);
}

Ptr<Deformer> createDeformer(const Mat& image, const Multicage& rest, const DeformParams& params,
                             std::string* why) {
    CV_Assert(params.coordinates == MEAN_VALUE);
    // By default the GPU binds only where it is a real one: llvmpipe binds 15x slower than
    // the CPU backend (README), so there the CPU binds and the GPU (if asked for) deforms.
    if (params.gpuBinding < 0 && !acceleratedContext(why)) return Ptr<Deformer>();
    return create(image, rest, params, why);
}

}  // namespace gpu

Binding bindOnGpu(const Multicage& multicage, int gridStep) {
    std::string why;
    gpu::EglContext* context = gpu::EglContext::shared(&why);
    if (!context) CV_Error(Error::GpuNotSupported, "multicage: bindOnGpu: " + why);
    gpu::EglContext::Scope scope(*context);
    // A blank single-channel image: the GLDeformer needs one, the binding does not.
    const Mat image(multicage.imageSize(), CV_8UC1, Scalar(0));
    GLDeformer d(image, multicage, gridStep);
    return d.binding();
}

HeadlessGLContext::HeadlessGLContext() {
    std::string why;
    context_ = gpu::EglContext::create(&why);
    if (!context_)
        CV_Error(Error::GpuNotSupported, "multicage: no headless OpenGL context: " + why);
}

HeadlessGLContext::~HeadlessGLContext() = default;

std::string HeadlessGLContext::description() const {
    return context_->description();
}

struct HeadlessGLContext::Scope::State {
    gpu::EglContext::Scope scope;
};

HeadlessGLContext::Scope::Scope(const HeadlessGLContext& c)
    : state_(new State{gpu::EglContext::Scope(*c.context_)}) {}

HeadlessGLContext::Scope::~Scope() = default;

namespace gpu {
// Whether `pick` gives a context; *description: its device, or why there is none.
static bool answer(EglContext* (*pick)(std::string*), std::string* description) {
    std::string why;
    const EglContext* context = pick(&why);
    if (description) *description = context ? context->description() : why;
    return context != nullptr;
}

bool hardwareGpu(std::string* description) {
    return answer(acceleratedContext, description);
}
}  // namespace gpu

bool gpuAvailable(std::string* description) {
    return gpu::answer(gpu::EglContext::shared, description);
}

}  // namespace multicage
}  // namespace cv

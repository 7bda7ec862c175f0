// The headless GPU Deformer: a GLDeformer in the process's shared context, read back.
#include "gpu_deformer.hpp"

#include <opencv2/multicage/internal/point_input.hpp>

#include "batch.hpp"

namespace cv {
namespace multicage {

namespace {

/** Every instance lives in the process's shared context (HeadlessGLContext::shared): one
context creation per process, and programs compiled once per layout. Every call makes the
context current on the calling thread under its lock and releases it afterwards, so
Deformers on different threads take turns and never see each other's GL state. */
class GpuDeformer final : public Deformer {
  public:
    GpuDeformer(HeadlessGLContext* context, const DeformParams& params)
        : context_(context), border_(params.borderValue) {}

    ~GpuDeformer() override {
        if (!gl_) return;
        try {
            HeadlessGLContext::Scope scope(*context_);
            gl_.reset();
        } catch (...) {  // a destructor must not throw; the context goes away regardless
        }
    }

    template <typename Source>
    void init(const Mat& image, const Source& source, const DeformParams& params) {
        HeadlessGLContext::Scope scope(*context_);
        GLDeformerParams p;
        p.halfFloat = params.halfFloat;
        p.pipeline = params.pipeline;
        make(image, source, params, p);
        image_ = image.clone();
    }

    void deform(InputArray pose, OutputArray dst) override {
        HeadlessGLContext::Scope scope(*context_);
        restoreOwnImage();
        gl_->setPose(pose);
        gl_->render(border_);
        gl_->readOutput(dst);
    }

    void computeMaps(InputArray pose, OutputArray mapx, OutputArray mapy) override {
        HeadlessGLContext::Scope scope(*context_);
        gl_->setPose(pose);
        gl_->renderMaps();
        gl_->readMaps(mapx, mapy);
    }

    void setImage(InputArray image) override {
        checkSameImage(image, image_.size(), image_.type());
        HeadlessGLContext::Scope scope(*context_);
        gl_->setImage(image);
        image.getMat().copyTo(image_);
        foreignImage_ = false;
    }

    // One item after another in the shared context; another image is uploaded into the
    // image texture for its item, and the Deformer's own image goes back before the next
    // deform() of it.
    void deformBatch(InputArrayOfArrays posesIn, OutputArrayOfArrays dst,
                     InputArrayOfArrays imagesIn) override {
        std::vector<std::vector<Point2f>> poses;
        std::vector<Mat> images;
        // setPose checks each pose (count, finiteness): the binding is not read back for it.
        batchInputs(
            posesIn, imagesIn, [](InputArray p) { return toPoints(p, "pose"); }, image_.size(),
            image_.type(), poses, images);
        std::vector<Mat> out(poses.size());
        {
            HeadlessGLContext::Scope scope(*context_);
            if (images.empty()) restoreOwnImage();
            for (size_t k = 0; k < poses.size(); ++k) {
                if (!images.empty()) {
                    gl_->setImage(images[k]);
                    foreignImage_ = true;
                }
                try {
                    gl_->setPose(poses[k]);
                } catch (const Exception& e) {
                    rethrowForItem(e, static_cast<int>(k));
                }
                gl_->render(border_);
                gl_->readOutput(out[k]);
            }
        }
        setBatchOutput(dst, out);
    }

    int backend() const override { return BACKEND_GPU; }
    // A GPU binding is read back only when asked for (240 MB at 1024x768 with 68 vertices):
    // creating the Deformer does not pay for it.
    const Binding& binding() const override {
        HeadlessGLContext::Scope scope(*context_);
        return gl_->binding();
    }
    String getDefaultName() const override { return "multicage.GpuDeformer"; }

  private:
    void restoreOwnImage() {  // under the context's scope
        if (!foreignImage_) return;
        gl_->setImage(image_);
        foreignImage_ = false;
    }
    void make(const Mat& image, const Binding& b, const DeformParams&, const GLDeformerParams& p) {
        gl_.reset(new GLDeformer(image, b, p));
    }
    void make(const Mat& image, const Multicage& rest, const DeformParams& params,
              const GLDeformerParams& p) {
        gl_.reset(new GLDeformer(image, rest, params.gridStep, p));
    }

    HeadlessGLContext* context_;
    std::unique_ptr<GLDeformer> gl_;
    Scalar border_;
    Mat image_;  // the Deformer's own image (the texture holds another after a batch)
    bool foreignImage_ = false;  // the texture holds a batch's image, not image_
};

template <typename Source>
Ptr<Deformer> create(const Mat& image, const Source& source, const DeformParams& params,
                     std::string* why) {
    HeadlessGLContext* context =
        params.backend == BACKEND_AUTO ? hardwareContext(why) : HeadlessGLContext::shared(why);
    if (!context) return Ptr<Deformer>();
    Ptr<GpuDeformer> d(new GpuDeformer(context, params));
    d->init(image, source, params);
    return d;
}

}  // namespace

HeadlessGLContext* hardwareContext(std::string* why) {
    HeadlessGLContext* context = HeadlessGLContext::shared(why);
    if (context && context->software()) {
        if (why)
            *why = "the only OpenGL here is a software renderer (" + context->description() +
                   "), slower than the CPU backend";
        return nullptr;
    }
    return context;
}

Ptr<Deformer> createGpuDeformer(const Mat& image, const Binding& binding,
                                const DeformParams& params, std::string* why) {
    return create(image, binding, params, why);
}

Ptr<Deformer> createGpuDeformer(const Mat& image, const Multicage& rest, const DeformParams& params,
                                std::string* why) {
    CV_Assert(params.coordinates == MEAN_VALUE);
    // By default the GPU binds only where it is a real one: llvmpipe binds 15x slower than
    // the CPU backend (README), so there the CPU binds and the GPU (if asked for) deforms.
    if (params.gpuBinding < 0 && !hardwareContext(why)) return Ptr<Deformer>();
    return create(image, rest, params, why);
}

}  // namespace multicage
}  // namespace cv

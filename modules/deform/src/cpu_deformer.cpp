#include "cpu_deformer.hpp"

#include <opencv2/imgproc.hpp>

namespace cv {
namespace multicage {

namespace {

class CpuDeformer final : public Deformer {
public:
    CpuDeformer(const Mat& image, const Binding& binding, const DeformParams& params)
        : binding_(binding), border_(params.borderValue) {
        // Everything a pose writes is allocated and touched here, once, in 2 MB pages where
        // the kernel offers them: the first pose then costs what every later one does (no page
        // faults of fresh buffers, no allocations), and creation few page faults.
        image_ = hugePageMat(image.size(), image.type(), owners_);
        image.copyTo(image_);
        mesh_.reset(binding);
        mapx_ = hugePageMat(image.size(), CV_32F, owners_);
        mapy_ = hugePageMat(image.size(), CV_32F, owners_);
        mapx_.setTo(Scalar::all(0));
        mapy_.setTo(Scalar::all(0));
    }

    void deform(InputArray pose, OutputArray dst) override {
        drawMapsFor(pose);
        mesh_.draw(mapx_, mapy_);
        remap(image_, dst, mapx_, mapy_, INTER_LINEAR, BORDER_CONSTANT, border_);
    }

    void computeMaps(InputArray pose, OutputArray mapx, OutputArray mapy) override {
        drawMapsFor(pose);
        mapx.create(image_.size(), CV_32F);
        mapy.create(image_.size(), CV_32F);
        Mat mx = mapx.getMat(), my = mapy.getMat();
        mesh_.draw(mx, my);
    }

    int backend() const override { return BACKEND_CPU; }
    const Binding& binding() const override { return binding_; }
    String getDefaultName() const override { return "multicage.CpuDeformer"; }

private:
    // Node positions into the mesh, and the ring onto the pose's frame.
    void drawMapsFor(InputArray pose) {
        const std::vector<Point2f> vertices = binding_.completePose(pose);
        Mat nodes = mesh_.nodes();
        binding_.apply(vertices, nodes);
        mesh_.setFrame(&vertices[vertices.size() - 4]);
    }

    std::vector<Mat> owners_;  // the memory of image_, mapx_, mapy_
    Mat image_;
    Binding binding_;
    RasterMesh mesh_;
    Mat mapx_, mapy_;  // reused between poses
    Scalar border_;
};

}  // namespace

Ptr<Deformer> createCpuDeformer(const Mat& image, const Binding& binding, const DeformParams& params) {
    return makePtr<CpuDeformer>(image, binding, params);
}

}  // namespace multicage
}  // namespace cv

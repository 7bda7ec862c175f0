#include "cpu_deformer.hpp"

#include <opencv2/imgproc.hpp>

namespace cv {
namespace multicage {

namespace {

class CpuDeformer final : public Deformer {
public:
    CpuDeformer(const Mat& image, const Binding& binding, const DeformParams& params)
        : image_(image.clone()), binding_(binding), restNodes_(binding.nodes()),
          border_(params.borderValue) {}

    void deform(InputArray pose, OutputArray dst) override {
        Mat mapx, mapy;
        computeMaps(pose, mapx, mapy);
        remap(image_, dst, mapx, mapy, INTER_LINEAR, BORDER_CONSTANT, border_);
    }

    void computeMaps(InputArray pose, OutputArray mapx, OutputArray mapy) override {
        const std::vector<Point2f> vertices = binding_.completePose(pose);
        binding_.apply(vertices, positions_);
        rasterizeMaps(positions_, restNodes_, image_.size(), mapx, mapy,
                      Mat(std::vector<Point2f>(vertices.end() - 4, vertices.end()), true));
    }

    int backend() const override { return BACKEND_CPU; }
    const Binding& binding() const override { return binding_; }
    String getDefaultName() const override { return "multicage.CpuDeformer"; }

private:
    Mat image_;
    Binding binding_;
    Mat restNodes_;
    Mat positions_;  // reused between poses
    Scalar border_;
};

}  // namespace

void checkImage(InputArray image) {
    if (image.empty()) CV_Error(Error::StsBadArg, "multicage: the image is empty");
    const int depth = image.depth(), cn = image.channels();
    if ((depth != CV_8U && depth != CV_16U && depth != CV_32F) || (cn != 1 && cn != 3 && cn != 4))
        CV_Error_(Error::StsUnsupportedFormat,
                  ("multicage: unsupported image type %s; use CV_8U, CV_16U or CV_32F with 1, 3 or "
                   "4 channels", typeToString(image.type()).c_str()));
    if (image.dims() > 2) CV_Error(Error::StsBadArg, "multicage: the image must be 2-dimensional");
}

Ptr<Deformer> createCpuDeformer(const Mat& image, const Binding& binding, const DeformParams& params) {
    return makePtr<CpuDeformer>(image, binding, params);
}

}  // namespace multicage
}  // namespace cv

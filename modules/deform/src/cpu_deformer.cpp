#include "cpu_deformer.hpp"

#include <climits>
#include <memory>
#include <mutex>
#include <opencv2/imgproc.hpp>

#include "remap_linear.hpp"
#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace cv {
namespace multicage {

namespace {

class CpuDeformer final : public Deformer {
  public:
    CpuDeformer(const Mat& image, const Binding& binding, const DeformParams& params)
        : binding_(binding), border_(params.borderValue), mapStep_(params.mapStep) {
        // Everything a pose writes is allocated and touched here, once, in 2 MB pages where
        // the kernel offers them: the first pose then costs what every later one does (no page
        // faults of fresh buffers, no allocations), and creation few page faults.
        image_ = hugePageMat(image.size(), image.type(), owners_);
        image.copyTo(image_);
        mesh_.reset(binding);
        mesh_.setMapStep(mapStep_);
        mapx_ = hugePageMat(image.size(), CV_32F, mapOwners_);
        mapy_ = hugePageMat(image.size(), CV_32F, mapOwners_);
        mapx_.setTo(Scalar::all(0));
        mapy_.setTo(Scalar::all(0));
        // The first output too (what the CLI and deformImage return, and a fresh Deformer's
        // first deform): fresh memory costs a page fault per 4 KiB when written (~12 us each on
        // a VM, 7 ms for a 1024x768 BGR image), in 2 MB pages a few. Handed over, not shared.
        firstOutput_ = ownedHugePageMat(image.size(), image.type());
        firstOutput_.setTo(Scalar::all(0));
    }

    void deform(InputArray pose, OutputArray dst) override {
        drawMapsFor(pose);
        const Size size = mesh_.outputSize();
        const bool first = !firstOutput_.empty() && firstOutput_.size() == size &&
                           dst.kind() == _InputArray::MAT && dst.empty();
        Mat out = firstOutput_;
        if (!first) {
            dst.create(size, image_.type());
            out = dst.getMat();
        }
        drawAndSample(image_, out, mesh_, mapx_, mapy_);
        if (first) {
            dst.assign(firstOutput_);  // the caller's now (reference counted), no longer ours
            firstOutput_.release();
        }
    }

    void computeMaps(InputArray pose, OutputArray mapx, OutputArray mapy) override {
        drawMapsFor(pose);
        mapx.create(mesh_.outputSize(), CV_32F);
        mapy.create(mesh_.outputSize(), CV_32F);
        Mat mx = mapx.getMat(), my = mapy.getMat();
        mesh_.draw(mx, my);
    }

    int backend() const override { return BACKEND_CPU; }
    const Binding& binding() const override { return binding_; }
    String getDefaultName() const override { return "multicage.CpuDeformer"; }

    void setImage(InputArray image) override {
        checkSameImage(image, image_.size(), image_.type());
        image.getMat().copyTo(image_);
    }

    void deformBatch(InputArrayOfArrays posesIn, OutputArrayOfArrays dstIn,
                     InputArrayOfArrays imagesIn) override {
        std::vector<std::vector<Point2f>> poses;
        std::vector<Mat> images;
        batchInputs(
            posesIn, imagesIn, [this](InputArray p) { return binding_.completePose(p); },
            image_.size(), image_.type(), poses, images);
        const int count = static_cast<int>(poses.size());
        // Every item's output size (a resize pose renders into its own frame's size); one block
        // for the batch when they agree, as they do for the usual same-size poses.
        std::vector<Size> sizes(count);
        bool oneSize = true;
        for (int k = 0; k < count; ++k) {
            sizes[k] = frameOutputSize(&poses[k][poses[k].size() - 4], image_.size());
            oneSize = oneSize && sizes[k] == sizes[0];
        }
        std::vector<Mat> out = oneSize && count > 0 ? batchOutputs(count, sizes[0], image_.type())
                                                    : std::vector<Mat>(count);
        for (int k = 0; k < count; ++k) out[k].create(sizes[k], image_.type());
        if (count < 2 || getNumThreads() <= 1) {
            // One item (or one thread): in this Deformer's own mesh and maps, the loops inside
            // (apply, draw, remap) parallel as for deform().
            for (int k = 0; k < count; ++k) {
                const Mat& source = images.empty() ? image_ : images[k];
                drawMapsFor(poses[k]);
                drawAndSample(source, out[k], mesh_, mapx_, mapy_);
            }
            setBatchOutput(dstIn, out);
            return;
        }
        // Items in parallel, each worker with its own mesh and maps (the binding is shared,
        // read only); nested parallel_for_ calls inside an item (apply, draw, remap) run
        // serially, so each item stays on its worker's core.
        std::mutex poolMutex;
        parallel_for_(
            Range(0, count),
            [&](const Range& r) {
                std::unique_ptr<Workspace> ws;
                {
                    std::lock_guard<std::mutex> lock(poolMutex);
                    if (!pool_.empty()) ws = std::move(pool_.back()), pool_.pop_back();
                }
                if (!ws) ws.reset(new Workspace(binding_, mapStep_));
                for (int k = r.start; k < r.end; ++k) {
                    ws->mesh.pose(binding_, poses[k]);
                    CV_DbgAssert(ws->mesh.outputSize() == sizes[k]);
                    ws->mapx.create(sizes[k], CV_32F);
                    ws->mapy.create(sizes[k], CV_32F);
                    drawAndSample(images.empty() ? image_ : images[k], out[k], ws->mesh, ws->mapx,
                                  ws->mapy);
                }
                std::lock_guard<std::mutex> lock(poolMutex);
                pool_.push_back(std::move(ws));
            },
            count);
        setBatchOutput(dstIn, out);
    }

  private:
    /** What one batch worker writes: its own mesh and maps. Kept between batches. */
    struct Workspace {
        Workspace(const Binding& binding, int mapStep) {
            mesh.reset(binding);
            mesh.setMapStep(mapStep);
            mapx.create(binding.imageSize, CV_32F);
            mapy.create(binding.imageSize, CV_32F);
        }
        RasterMesh mesh;
        Mat mapx, mapy;
    };

    // The maps of the mesh's pose, and `out` (made: the maps' size, source's type) sampled from
    // source through them (cv::remap's bits), each band of rows as soon as it is drawn, while its
    // maps are still in cache (a whole 512x512 pair of maps is 2 MB, more than a core's L2).
    void drawAndSample(const Mat& source, Mat& out, RasterMesh& mesh, Mat& mapx, Mat& mapy) {
        mesh.draw(mapx, mapy, [&](int y0, int y1) {
            remapLinearRows(source, out, mapx, mapy, border_, y0, y1);
        });
    }

    // Node positions into the mesh, the ring onto the pose's frame, and maps of the size that
    // frame asks for (frameOutputSize: the image's own, or a resize pose's new size).
    void drawMapsFor(InputArray pose) {
        mesh_.pose(binding_, binding_.completePose(pose));
        const Size size = mesh_.outputSize();
        if (mapx_.size() != size) {  // kept for the next pose of this size
            std::vector<Mat>().swap(mapOwners_);
            mapx_ = hugePageMat(size, CV_32F, mapOwners_);
            mapy_ = hugePageMat(size, CV_32F, mapOwners_);
        }
    }

    std::vector<Mat> owners_;     // the memory of image_
    std::vector<Mat> mapOwners_;  // the memory of mapx_, mapy_
    Mat image_;
    Binding binding_;
    RasterMesh mesh_;
    Mat mapx_, mapy_;  // reused between poses
    Scalar border_;
    int mapStep_;      // DeformParams::mapStep
    Mat firstOutput_;  // touched at creation, given to the first deform() with an empty dst
    std::vector<std::unique_ptr<Workspace>> pool_;  // batch workers' meshes and maps
};

}  // namespace

Ptr<Deformer> createCpuDeformer(const Mat& image, const Binding& binding,
                                const DeformParams& params) {
    return makePtr<CpuDeformer>(image, binding, params);
}

}  // namespace multicage
}  // namespace cv

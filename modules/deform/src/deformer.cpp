// Deformer::create: validates, binds, and picks the backend.
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/multicage/deformer.hpp>

#include "cpu_deformer.hpp"
#include "gpu_deformer.hpp"

namespace cv {
namespace multicage {

const char* backendName(int backend) {
    switch (backend) {
        case BACKEND_AUTO:
            return "auto";
        case BACKEND_CPU:
            return "cpu";
        case BACKEND_GPU:
            return "gpu";
        default:
            return nullptr;
    }
}

bool parseBackend(const String& name, int& backend) {
    for (int b : {BACKEND_AUTO, BACKEND_CPU, BACKEND_GPU})
        if (name == backendName(b)) {
            backend = b;
            return true;
        }
    return false;
}

static std::string formatBytes(size_t bytes) {
    const double mib = bytes / (1024.0 * 1024.0);
    return mib >= 1024 ? format("%.1f GiB", mib / 1024) : format("%.0f MiB", mib);
}

bool autoBackendUsesGpu(std::string* description) {
    std::string why;
    const HeadlessGLContext* context = hardwareContext(&why);
    if (description) *description = context ? context->description() : why;
    return context != nullptr;
}

// Checked before any path is chosen: with a hardware GPU a multicage is bound on the GPU before
// the backend switch below is reached, and an unknown backend went through unrefused (an H100).
static void checkParams(const DeformParams& params) {
    if (params.backend != BACKEND_CPU && params.backend != BACKEND_GPU &&
        params.backend != BACKEND_AUTO)
        CV_Error_(Error::StsOutOfRange, ("multicage: unknown backend %d", params.backend));
    if (params.mapStep < 1 || params.mapStep > DeformParams::kMaxMapStep)
        CV_Error_(Error::StsOutOfRange, ("multicage: mapStep %d is outside [1, %d]", params.mapStep,
                                         DeformParams::kMaxMapStep));
}

Ptr<Deformer> Deformer::create(InputArray image, const Multicage& rest,
                               const DeformParams& params) {
    checkImage(image);
    checkParams(params);
    if (rest.imageSize() != image.size())
        CV_Error_(Error::StsBadSize,
                  ("multicage: the image is %dx%d but the multicage was made for %dx%d; use "
                   "Multicage::scaled(image.size())",
                   image.cols(), image.rows(), rest.imageSize().width, rest.imageSize().height));
    const int c = rest.vertexCount() + 4;
    DeformParams chosen = params;
    chosen.coordinates = resolveCoordinates(rest, params.coordinates);
    const size_t need = bindingMemory(image.size(), c, params.gridStep);
    if (params.memoryBudget > 0 && need > params.memoryBudget) {
        const int fits = gridStepForBudget(image.size(), c, params.memoryBudget, params.gridStep);
        const std::string what = format(
            "a %dx%d image with %d vertices needs %s of coefficients at grid step %d, over the "
            "%s budget (DeformParams::memoryBudget); grid step %d fits (%s)",
            image.cols(), image.rows(), rest.vertexCount(), formatBytes(need).c_str(),
            params.gridStep, formatBytes(params.memoryBudget).c_str(), fits,
            formatBytes(bindingMemory(image.size(), c, fits)).c_str());
        if (!params.autoGridStep) CV_Error(Error::StsNoMem, "multicage: " + what);
        CV_LOG_WARNING(NULL, "multicage: " << what << "; using grid step " << fits);
        chosen.gridStep = fits;
    }
    if (chosen.gpuBinding != 0 && chosen.coordinates == MEAN_VALUE &&
        params.backend != BACKEND_CPU) {
        std::string why;
        Ptr<Deformer> gpu = createGpuDeformer(image.getMat(), rest, chosen, &why);
        if (gpu) return gpu;
        if (chosen.gpuBinding > 0) {  // asked for explicitly: say why it did not happen
            if (params.backend == BACKEND_GPU)
                CV_Error(Error::StsNotImplemented, "multicage: BACKEND_GPU requested but " + why);
            CV_LOG_WARNING(NULL,
                           "multicage: no GPU for gpuBinding (" << why << "); binding on the CPU");
        }
    }
    return create(image, bind(rest, chosen.coordinates, chosen.gridStep, params.progress), chosen);
}

size_t bindingMemory(Size imageSize, int coefficientCount, int gridStep) {
    return size_t(gridSizeFor(imageSize, gridStep).area()) * size_t(coefficientCount) *
           sizeof(float);
}

int gridStepForBudget(Size imageSize, int coefficientCount, size_t budget, int minStep) {
    int step = std::max(1, minStep);
    if (budget == 0) return step;
    while (bindingMemory(imageSize, coefficientCount, step) > budget &&
           step < std::max(imageSize.width, imageSize.height))
        ++step;
    return step;
}

Ptr<Deformer> Deformer::create(InputArray imageIn, const Binding& binding,
                               const DeformParams& params) {
    checkImage(imageIn);
    checkParams(params);
    CV_Assert(!binding.empty());
    const Mat image = imageIn.getMat();
    if (binding.imageSize != image.size())
        CV_Error_(Error::StsBadSize,
                  ("multicage: the image is %dx%d but the binding is for %dx%d", image.cols,
                   image.rows, binding.imageSize.width, binding.imageSize.height));
    switch (params.backend) {
        case BACKEND_CPU:
            return createCpuDeformer(image, binding, params);
        case BACKEND_GPU:
        case BACKEND_AUTO: {
            std::string why;
            if (params.backend == BACKEND_AUTO && !autoBackendUsesGpu(&why)) {
                // The expected case on a machine without a GPU: no warning, no second probe.
                CV_LOG_INFO(NULL, "multicage: BACKEND_AUTO uses the CPU backend: " << why);
                return createCpuDeformer(image, binding, params);
            }
            Ptr<Deformer> gpu = createGpuDeformer(image, binding, params, &why);
            if (gpu) return gpu;
            if (params.backend == BACKEND_GPU)
                CV_Error(Error::StsNotImplemented, "multicage: BACKEND_GPU requested but " + why);
            CV_LOG_WARNING(NULL,
                           "multicage: no GPU backend (" << why << "); using the CPU backend");
            return createCpuDeformer(image, binding, params);
        }
        default:
            CV_Error(Error::StsInternal, "multicage: unreachable backend");  // checkParams
    }
}

int Deformer::foldedTriangles(InputArray pose) const {
    Mat positions;
    binding().apply(pose, positions);
    return countFoldedTriangles(positions, binding().nodes());
}

void deformImage(InputArray src, const Multicage& rest, InputArray pose, OutputArray dst,
                 const DeformParams& params) {
    Deformer::create(src, rest, params)->deform(pose, dst);
}

}  // namespace multicage
}  // namespace cv

// Deforming images with a bound multicage, on the GPU or the CPU.
#ifndef OPENCV2_MULTICAGE_DEFORMER_HPP
#define OPENCV2_MULTICAGE_DEFORMER_HPP

#include <opencv2/multicage/coordinates.hpp>
#include <opencv2/multicage/gpu.hpp>

namespace cv {
namespace multicage {

enum Backend {
    /** The GPU when autoBackendUsesGpu() (a hardware GPU; a software renderer such as Mesa's
    llvmpipe is slower than the CPU backend and does not count), else the CPU. The probe runs
    once per process; the choice is logged at INFO level, and Deformer::backend() says it. */
    BACKEND_AUTO = 0,
    BACKEND_CPU = 1,   //!< node positions, inverse maps by mesh rasterisation, cv::remap
    BACKEND_GPU = 2    //!< headless EGL + OpenGL 4.5, software renderers included; throws if no context can be made
};

/** Whether BACKEND_AUTO deforms on the GPU in this process: whether a headless EGL context on
a hardware GPU can be made. The first call probes EGL (on a machine without a GPU about 100 ms,
and the driver libraries stay loaded); the answer is kept for the life of the process, so
later calls and every Deformer::create with BACKEND_AUTO cost nothing more. Call it before
timing a Deformer::create to keep the probe out of the timing. *description gets the device
(vendor, renderer, GL version) or why AUTO uses the CPU ("the only OpenGL here is a software
renderer (llvmpipe ...)", "no EGL device ...").

Not the same question as gpuAvailable() (opencv2/multicage/gpu.hpp), which says whether any
EGL context, software included, can be made, i.e. whether BACKEND_GPU works. With llvmpipe only:
gpuAvailable() is true and autoBackendUsesGpu() false. Thread-safe. */
CV_EXPORTS bool autoBackendUsesGpu(std::string* description = nullptr);

/** The name of a Backend in the CLI, Python and editor ("auto", "cpu", "gpu"); nullptr for
any other value. */
CV_EXPORTS const char* backendName(int backend);
/** The Backend called name ("auto", "cpu", "gpu"). False, backend untouched, for any other. */
CV_EXPORTS bool parseBackend(const String& name, int& backend);

struct CV_EXPORTS DeformParams {
    /** CoordinateType. The default, COORDINATES_FROM_CAGE, binds with the multicage's own choice
    (Multicage::coordinates(): a cage file's `coordinates:`, mean value when it names none);
    MEAN_VALUE or HARMONIC overrides it. Ignored by the create() that takes a Binding. */
    int coordinates = COORDINATES_FROM_CAGE;
    int gridStep = 1;               //!< a mesh node every gridStep pixels; 1 is the paper's
    int backend = BACKEND_AUTO;     //!< Backend
    Scalar borderValue = Scalar();  //!< output pixels no deformed triangle covers
    /** GPU backend: store the packed coefficients as RGBA16F instead of RGBA32F (half the
    memory; positions use the displacement form, so the rest pose stays exact). */
    bool halfFloat = false;
    /** GPU backend: where the mean value binding is computed. -1 (default): in a compute
    shader when the GPU is a hardware one (autoBackendUsesGpu()), else on the CPU; 1: in a compute
    shader whenever the GPU backend is used; 0: always on the CPU (bind()). Harmonic
    coordinates always bind on the CPU. */
    int gpuBinding = -1;
    /** GPU backend: the GpuPipeline. GPU_PIPELINE_COMPUTE (default) does the whole pose update
    in compute shaders; GPU_PIPELINE_VERTEX_SHADER is the paper's vertex-shader program. */
    int pipeline = GPU_PIPELINE_COMPUTE;
    /** Most bytes the coefficients may take (nodes x coefficients x 4); 0 means no limit.
    The default, 1 GiB, holds a 4096x4096 image with 60 vertices at grid step 1. */
    size_t memoryBudget = size_t(1) << 30;
    /** When the coefficients at gridStep would exceed memoryBudget: true raises the grid step
    to the smallest that fits (and logs the choice); false throws, naming the memory needed
    and the grid step that would fit. */
    bool autoGridStep = true;
    /** Called while create() binds (see bind(..., BindProgress)): the fraction done, return
    false to cancel (create() then throws). Harmonic bindings of large images take seconds to
    minutes; empty: no reports. */
    BindProgress progress;
};

/** Bytes of the coefficients of a binding: nodes(imageSize, gridStep) x coefficientCount x 4. */
CV_EXPORTS size_t bindingMemory(Size imageSize, int coefficientCount, int gridStep);
/** The smallest grid step >= minStep whose binding fits in budget bytes (0: no limit). */
CV_EXPORTS int gridStepForBudget(Size imageSize, int coefficientCount, size_t budget, int minStep = 1);

/** Binds an image to a multicage once, then deforms it for any number of poses.

Input images: CV_8U, CV_16U or CV_32F with 1, 3 or 4 channels. Output: the same size and type.
A pose is a std::vector<Point2f> or an Nx2 CV_32F matrix of vertexCount() points, or
vertexCount()+4 with the frame corners last. */
class CV_EXPORTS Deformer : public Algorithm {
public:
    static Ptr<Deformer> create(InputArray image, const Multicage& rest,
                                const DeformParams& params = DeformParams());
    /** Uses an existing binding (for example one made once and shared by several images). */
    static Ptr<Deformer> create(InputArray image, const Binding& binding,
                                const DeformParams& params = DeformParams());

    /** The image deformed to pose. */
    virtual void deform(InputArray pose, OutputArray dst) = 0;
    /** Inverse maps for cv::remap: for each output pixel, the source position (CV_32F,
    image size); pixels no triangle covers get -1e4. Remap masks with INTER_NEAREST. */
    virtual void computeMaps(InputArray pose, OutputArray mapx, OutputArray mapy) = 0;
    /** The Backend actually in use (never BACKEND_AUTO). */
    virtual int backend() const = 0;
    virtual const Binding& binding() const = 0;
    /** Number of mesh triangles whose orientation the pose reversed (fold-over). */
    virtual int foldedTriangles(InputArray pose) const;
};

/** One-shot form: binds, deforms once, returns. Prefer a Deformer for several poses. */
CV_EXPORTS void deformImage(InputArray src, const Multicage& rest, InputArray pose,
                            OutputArray dst, const DeformParams& params = DeformParams());

/** Rasterises a deformed node grid into inverse maps (the CPU backend's core, exposed for
tests and tools). positions: deformed nodes, gridSize CV_32FC2; rest: their rest positions,
the same shape. A ring of nodes on the image frame surrounds the grid: they follow the frame
corners `frame` (4 CV_32FC2 points TL, TR, BR, BL; empty: the rest frame of outputSize)
linearly along each edge and sample the nearest border pixel, so the border is never left
uncovered by a few tenths of a pixel. Triangles per cell of the ringed grid (a=(x,y),
b=(x+1,y), c=(x,y+1), d=(x+1,y+1)): (a,b,c) and (b,d,c), drawn in row-major cell order, the
later one winning where they overlap. Source positions are clamped to the rest grid. */
CV_EXPORTS void rasterizeMaps(InputArray positions, InputArray rest, Size outputSize,
                              OutputArray mapx, OutputArray mapy, InputArray frame = noArray());

/** Counts triangles of the deformed grid whose orientation differs from the rest grid's. */
CV_EXPORTS int countFoldedTriangles(InputArray positions, InputArray rest);

}  // namespace multicage
}  // namespace cv

#endif

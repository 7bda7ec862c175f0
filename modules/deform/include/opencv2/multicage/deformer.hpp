/** @file
@brief Deforming images with a bound multicage, on the GPU or the CPU.
@ingroup multicage_deform
*/
#ifndef OPENCV2_MULTICAGE_DEFORMER_HPP
#define OPENCV2_MULTICAGE_DEFORMER_HPP

#include <opencv2/multicage/coordinates.hpp>
#include <opencv2/multicage/gpu.hpp>

namespace cv {
namespace multicage {

//! @addtogroup multicage_deform
//! @{

/** @brief Where a Deformer runs (DeformParams::backend).
@sa autoBackendUsesGpu, backendName, docs/gpu/README.md
*/
enum Backend {
    /** The GPU when autoBackendUsesGpu() (a hardware GPU; a software renderer such as Mesa's
    llvmpipe is slower than the CPU backend and does not count), else the CPU. The probe runs
    once per process; the choice is logged at INFO level, and Deformer::backend() says it. */
    BACKEND_AUTO = 0,
    BACKEND_CPU = 1,  //!< node positions, inverse maps by mesh rasterisation, cv::remap
    /** Headless EGL + OpenGL 4.5 (or 4.3), software renderers included; Deformer::create
    throws a cv::Exception (StsNotImplemented) if no context can be made. */
    BACKEND_GPU = 2
};

/** @brief Whether BACKEND_AUTO deforms on the GPU in this process: whether a headless EGL
context on a hardware GPU can be made.

The first call probes EGL (the driver libraries stay loaded; its cost is in
docs/gpu/README.md); the answer is kept for the life of the process, so later calls and every
Deformer::create with BACKEND_AUTO cost nothing more. Call it before timing a Deformer::create
to keep the probe out of the timing.

Not the same question as gpuAvailable(), which says whether any EGL context, software
included, can be made, i.e. whether BACKEND_GPU works. With llvmpipe only: gpuAvailable() is
true and autoBackendUsesGpu() false. Thread-safe.
@param[out] description when not null, receives the device (vendor, renderer, GL version) or
why AUTO uses the CPU ("the only OpenGL here is a software renderer (llvmpipe ...)", "no EGL
device ...").
@return true when BACKEND_AUTO picks the GPU.
*/
CV_EXPORTS bool autoBackendUsesGpu(std::string* description = nullptr);

/** @brief The name of a Backend in the CLI, Python and editor.
@param backend a Backend.
@return "auto", "cpu" or "gpu"; nullptr for any other value.
@sa parseBackend
*/
CV_EXPORTS const char* backendName(int backend);
/** @brief The Backend called name.
@param name "auto", "cpu" or "gpu".
@param[out] backend receives the Backend; untouched for any other name.
@return false for any other name.
@sa backendName
*/
CV_EXPORTS bool parseBackend(const String& name, int& backend);

/** @brief Options of Deformer::create and deformImage(). */
struct CV_EXPORTS DeformParams {
    /** CoordinateType. The default, COORDINATES_FROM_CAGE, binds with the multicage's own choice
    (Multicage::coordinates(): a cage file's `coordinates:`, mean value when it names none);
    MEAN_VALUE, HARMONIC or LOCAL_MEAN_VALUE overrides it. Ignored by the create() that takes a
    Binding. */
    int coordinates = COORDINATES_FROM_CAGE;
    int gridStep = 1;  //!< a mesh node every gridStep pixels; 1 is the paper's
    /** CPU backend: 1 (the default) finds the inverse maps at every pixel. From 2 up (at most
    64), where the pose folds the mesh nowhere, they are found exactly on a lattice of points at
    most mapStep pixels apart (the first and last on the border pixels) and interpolated
    bilinearly in between; a pose that folds is drawn at every pixel as with 1. The error is of
    the kind and size a grid step of mapStep makes (tests/deform/map_lattice_test.cpp bounds it),
    and the maps cost a fraction of the pixels' walks: for augmentation, where speed matters
    more than the last hundredth of a pixel. The GPU backend finds every pixel whatever it says. */
    int mapStep = 1;
    /** The largest mapStep: past it a lattice saves nothing more. */
    static constexpr int kMaxMapStep = 64;
    int backend = BACKEND_AUTO;     //!< Backend
    Scalar borderValue = Scalar();  //!< output pixels no deformed triangle covers
    /** GPU backend: store the packed coefficients as RGBA16F instead of RGBA32F (half the
    memory; positions use the displacement form, so the rest pose stays exact;
    GLDeformerParams::halfFloat). */
    bool halfFloat = false;
    /** GPU backend: where the mean value binding is computed. -1 (default): in a compute
    shader when the GPU is a hardware one (autoBackendUsesGpu()), else on the CPU; 1: in a compute
    shader whenever the GPU backend is used; 0: always on the CPU (bind()). Harmonic
    coordinates always bind on the CPU. */
    int gpuBinding = -1;
    /** GPU backend: the GpuPipeline. GPU_PIPELINE_COMPUTE (default) does the whole pose update
    in compute shaders; GPU_PIPELINE_VERTEX_SHADER is the paper's vertex-shader program. */
    int pipeline = GPU_PIPELINE_COMPUTE;
    /** Most bytes the coefficients may take (nodes x coefficients x 4, bindingMemory()); 0
    means no limit. The default, 1 GiB, holds a 2048x2048 image with 60 vertices (64
    coefficients with the frame) at grid step 1. */
    size_t memoryBudget = size_t(1) << 30;
    /** When the coefficients at gridStep would exceed memoryBudget: true raises the grid step
    to the smallest that fits (gridStepForBudget(); and logs the choice); false throws
    (StsNoMem), naming the memory needed and the grid step that would fit. */
    bool autoGridStep = true;
    /** Called while create() binds (see bind(..., BindProgress)): the fraction done, return
    false to cancel (create() then throws). Harmonic bindings of large images take seconds to
    minutes; empty: no reports. */
    BindProgress progress;
};

/** @brief Bytes of the coefficients of a binding.
@param imageSize the image size.
@param coefficientCount coefficients per node (vertexCount() + 4).
@param gridStep pixels between nodes, >= 1.
@return nodes(imageSize, gridStep) x coefficientCount x 4 (gridSizeFor()).
*/
CV_EXPORTS size_t bindingMemory(Size imageSize, int coefficientCount, int gridStep);
/** @brief The smallest grid step >= minStep whose binding fits in budget bytes.
@param imageSize the image size.
@param coefficientCount coefficients per node (vertexCount() + 4).
@param budget bytes (0: no limit, minStep is returned).
@param minStep the smallest step to consider (at least 1).
@return the grid step; it stops growing at the image's longer side, even when that does not
fit.
@sa bindingMemory, DeformParams::memoryBudget
*/
CV_EXPORTS int gridStepForBudget(Size imageSize, int coefficientCount, size_t budget,
                                 int minStep = 1);

/** @brief Binds an image to a multicage once, then deforms it for any number of poses.

Input images: CV_8U, CV_16U or CV_32F with 1, 3 or 4 channels. Output: the input's type, and
its size, or the new size of a resize pose (resizePose(): a pose whose frame corners lie on
another size's frame).
A pose is a std::vector<Point2f> or an Nx2 CV_32F matrix of vertexCount() points, or
vertexCount()+4 with the frame corners last.
@sa deformImage, GLDeformer, docs/ARCHITECTURE.md
*/
class CV_EXPORTS Deformer : public Algorithm {
  public:
    /** @brief Binds image to rest (bind(), or on the GPU: DeformParams::gpuBinding) and makes
    the Deformer of params.backend.
    @param image CV_8U, CV_16U or CV_32F, 1, 3 or 4 channels, of rest.imageSize() (else
    cv::Exception, StsBadSize: use Multicage::scaled()).
    @param rest the multicage at rest; it must pass validateGeometry().
    @param params the options; an unknown backend or a mapStep outside [1, kMaxMapStep]
    throws (StsOutOfRange).
    @return the Deformer.
    @throws cv::Exception as bind(), when the coefficients exceed memoryBudget with
    autoGridStep false (StsNoMem), and for BACKEND_GPU without a context (StsNotImplemented).
    */
    static Ptr<Deformer> create(InputArray image, const Multicage& rest,
                                const DeformParams& params = DeformParams());
    /** @brief Uses an existing binding (for example one made once and shared by several images).
    @param image as the other create(), of binding.imageSize.
    @param binding a non-empty binding.
    @param params the options; coordinates, gridStep, memoryBudget, autoGridStep, gpuBinding
    and progress are not used (the binding is made).
    @return the Deformer. */
    static Ptr<Deformer> create(InputArray image, const Binding& binding,
                                const DeformParams& params = DeformParams());

    /** @brief The image deformed to pose.

    The pose is not validated: one whose polygons cross, leave the frame or change nesting
    (validatePose() says which) is deformed as asked, and the image folds over itself where
    the mesh inverts (foldedTriangles() counts it); the multicage tools refuse such poses
    unless told --allow-invalid.
    @param pose vertexCount() or vertexCount()+4 points.
    @param[out] dst the deformed image: the input's type, its size or a resize pose's. */
    virtual void deform(InputArray pose, OutputArray dst) = 0;
    /** @brief Inverse maps for cv::remap: for each output pixel, the source position.

    Pixels no triangle covers get -1e4. Remap masks with INTER_NEAREST.
    @param pose as deform().
    @param[out] mapx source x, CV_32F of the output size (as deform()'s).
    @param[out] mapy source y, the same. */
    virtual void computeMaps(InputArray pose, OutputArray mapx, OutputArray mapy) = 0;
    /** @brief The Backend actually in use.
    @return BACKEND_CPU or BACKEND_GPU (never BACKEND_AUTO). */
    virtual int backend() const = 0;
    /** @brief The binding this Deformer deforms with.
    @return a reference valid for the Deformer's lifetime. */
    virtual const Binding& binding() const = 0;
    /** @brief Number of mesh triangles whose orientation the pose reversed (fold-over).
    @param pose as deform().
    @return the count; 0 for a pose that folds nothing.
    @sa countFoldedTriangles */
    virtual int foldedTriangles(InputArray pose) const;

    /** @brief Where rest points (keypoints, polygon annotations, box corners) land in the image
    deformed to pose.

    transformPoints(binding(), pose, points, dst), the free function (read its rule there).
    The GPU backend reads its binding back on first use.
    @param pose as deform().
    @param points std::vector<Point2f> (or Point2d, Point) or an Nx2 / Nx1 two-channel matrix
    (CV_32F, CV_64F, CV_32S).
    @param[out] dst N points, CV_32FC2 (a std::vector<Point2f> works). */
    virtual void transformPoints(InputArray pose, InputArray points, OutputArray dst) const;

    /** @brief Replaces the image this Deformer deforms by another of the same size and type,
    keeping the binding: a batch of images of one size shares one binding (no rebinding, no
    new Deformer).

    CPU: copies the image; GPU: uploads it into the image texture.
    @param image the same size and type; another size or type throws (StsBadSize,
    StsUnmatchedFormats). */
    virtual void setImage(InputArray image) = 0;

    /** @brief Deforms a batch, the same bits as deform() gives one at a time.

    dst[k] = images[k] (or this Deformer's own image when images is empty) deformed to
    poses[k]. The Deformer's own image is unchanged. CPU backend: items run in parallel on all
    cores (cv::parallel_for_, each worker with its own mesh and maps on the shared binding),
    the faster way to use several cores for small images. GPU backend: one after another in
    its context.
    @param poses a std::vector<std::vector<Point2f>> (or of Nx2 CV_32F matrices).
    @param[out] dst one deformed image per pose.
    @param images empty, or one image per pose, each of this Deformer's size and type. */
    virtual void deformBatch(InputArrayOfArrays poses, OutputArrayOfArrays dst,
                             InputArrayOfArrays images = noArray()) = 0;
};

/** @brief Where rest points land when a binding deforms to pose: the forward map of the image's
own mesh, made exact at the cage vertices.

Rule: a point follows the mesh the image is rendered from, i.e. the deformed node grid (node
`p' = x + sum_j CC_j (v'_j - v_j)`, as Binding::apply) interpolated linearly on the triangles
the rasteriser draws ((a,b,c) and (b,d,c) per cell), with the ring of nodes on the image frame
(rasterizeMaps()) for points between the frame and the outer nodes. So a feature of the image
at a point lands where the point lands, at any grid step (the inverse maps are this map's
inverse wherever the pose does not fold the mesh). The mesh interpolates the coordinates
between nodes, so a cage vertex that is not a node would land a little off its pose position
(docs/python.md, "Keypoints, boxes and polygons follow the image", gives the error per grid
step; none for a vertex on a node); a correction, the tent function of the cells around each
cage vertex (1 at the vertex, 0 on the boundary of the one or two cells in x and y around it,
so 0 at every node and wherever no cage vertex is near), weighted so that every cage vertex
lands exactly on its pose position, removes that. It changes points only within the cells
that hold a cage vertex, by at most that small amount. For mean value and harmonic bindings
alike (harmonic coordinates exist only on the grid).

Points outside the image frame (the rectangle (-0.5,-0.5)-(W-0.5,H-0.5)) follow the frame, as
the mesh's ring does: the bilinear map of the 4 frame corners (the pose's, or the rest frame),
continued outside; with the frame fixed (the usual pose) they stay where they are. The maps
never sample outside the image (source positions are clamped to it), so no image content lands
there.

Computed in double on the N points and the nodes around them only: cheap for thousands of
points.
@param binding a non-empty binding.
@param pose vertexCount() points or coefficientCount() (Binding::completePose).
@param points as Deformer::transformPoints; every point finite, else a cv::Exception naming
it.
@param[out] dst N points, CV_32FC2.
*/
CV_EXPORTS void transformPoints(const Binding& binding, InputArray pose, InputArray points,
                                OutputArray dst);

/** @brief One-shot form: binds, deforms once, returns. Prefer a Deformer for several poses.
@param src the image, as Deformer::create takes it.
@param rest the multicage at rest.
@param pose as Deformer::deform.
@param[out] dst the deformed image.
@param params the options.
*/
CV_EXPORTS void deformImage(InputArray src, const Multicage& rest, InputArray pose, OutputArray dst,
                            const DeformParams& params = DeformParams());

/** @brief Rasterises a deformed node grid into inverse maps (the CPU backend's core, exposed
for tests and tools).

A ring of nodes on the image frame surrounds the grid: they follow the frame corners `frame`
linearly along each edge and sample the nearest border pixel, so the border is never left
uncovered by a few tenths of a pixel. Triangles per cell of the ringed grid (a=(x,y),
b=(x+1,y), c=(x,y+1), d=(x+1,y+1)): (a,b,c) and (b,d,c), drawn in row-major cell order, the
later one winning where they overlap. Source positions are clamped to the rest grid.
@param positions deformed nodes, gridSize CV_32FC2.
@param rest their rest positions, the same shape.
@param outputSize the size of the maps.
@param[out] mapx source x per output pixel, CV_32F (-1e4 where uncovered).
@param[out] mapy source y per output pixel, CV_32F (-1e4 where uncovered).
@param frame 4 CV_32FC2 points TL, TR, BR, BL; empty: the rest frame of outputSize.
*/
CV_EXPORTS void rasterizeMaps(InputArray positions, InputArray rest, Size outputSize,
                              OutputArray mapx, OutputArray mapy, InputArray frame = noArray());

/** @brief Counts triangles of the deformed grid whose orientation differs from the rest grid's.
@param positions deformed nodes, gridSize CV_32FC2.
@param rest their rest positions, the same shape.
@return the number of reversed triangles.
*/
CV_EXPORTS int countFoldedTriangles(InputArray positions, InputArray rest);

//! @} multicage_deform

}  // namespace multicage
}  // namespace cv

#endif

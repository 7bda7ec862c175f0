/** @file
@brief The GPU deformation for callers that own an OpenGL context (an editor, a game engine),
and GPU binding (paper §4). All EGL/OpenGL code of the library lives in modules/gpu.

A library configured with `-DMULTICAGE_WITH_GPU=OFF` has no EGL or OpenGL at all, and the
same API: gpuAvailable() is false with the reason "built without GPU support
(MULTICAGE_WITH_GPU=OFF)", HeadlessGLContext::shared() is nullptr, and the constructors,
bindOnGpu() and Deformer::create with BACKEND_GPU throw cv::Exception saying so. Code that
must know at compile time tests #MULTICAGE_HAVE_GPU.
@ingroup multicage_gpu
*/
#ifndef OPENCV2_MULTICAGE_GPU_HPP
#define OPENCV2_MULTICAGE_GPU_HPP

#include <memory>
#include <opencv2/multicage/packing.hpp>

#ifdef CV_DOXYGEN
/** @brief 1 for a library built with the GPU backend, 0 for one configured with
`-DMULTICAGE_WITH_GPU=OFF` (no EGL, OpenGL or libepoxy; the API reports it at run time).

Defined by the CMake package: every target that links multicage::multicage compiles with it.
@ingroup multicage_gpu
*/
#define MULTICAGE_HAVE_GPU 1
#endif

namespace cv {
namespace multicage {

namespace gpu {
class EglContext;
}

//! @addtogroup multicage_gpu
//! @{

/** @brief A headless OpenGL 4.5 (or 4.3) core context through EGL, with no window and no X.

A hardware EGL device (EGL_EXT_platform_device, NVIDIA for instance) first, else Mesa's
surfaceless platform (llvmpipe where there is no GPU). For running GLDeformer without a
window.
@sa gpuAvailable, docs/gpu/README.md
*/
class CV_EXPORTS HeadlessGLContext {
  public:
    /** @brief Makes a new context.
    @throws cv::Exception (GpuNotSupported) saying why when none can be made. */
    HeadlessGLContext();
    /** @brief Destroys the context. */
    ~HeadlessGLContext();
    /** @brief Not copyable: the object owns its EGL context. */
    HeadlessGLContext(const HeadlessGLContext&) = delete;
    /** @brief Not copyable: the object owns its EGL context.
    @return nothing: deleted. */
    HeadlessGLContext& operator=(const HeadlessGLContext&) = delete;

    /** @brief The process's shared context, the one the process's GPU Deformers share.

    Made on the first call (EGL probed once per process), never destroyed, so creating a GPU
    Deformer costs no context creation and its programs are compiled once per process. The
    answer, a context or the reason there is none, is kept too. Its Scope takes a lock:
    threads using it take turns.
    @param[out] why when not null and no context can be made, receives the reason.
    @return the shared context, or nullptr when no context can be made.
    */
    static HeadlessGLContext* shared(std::string* why = nullptr);

    /** @brief Vendor, renderer, GL version and EGL platform.
    @return one line naming them. */
    std::string description() const;
    /** @brief Whether the renderer is a software one (Mesa llvmpipe or softpipe).

    OpenGL on the CPU is slower than the CPU backend, so BACKEND_AUTO does not count it as a
    GPU.
    @return true for a software renderer. */
    bool software() const;

    /** @brief Makes the context current on this thread for the scope's lifetime, then restores
    what was current before. A context can be current on only one thread at a time. */
    class CV_EXPORTS Scope {
      public:
        /** @brief Makes context current on this thread (taking its lock).
        @param context the context; it must outlive the scope. */
        explicit Scope(const HeadlessGLContext& context);
        /** @brief Restores what was current before (and releases the lock). */
        ~Scope();
        /** @brief Not copyable: one scope, one restore. */
        Scope(const Scope&) = delete;
        /** @brief Not copyable: one scope, one restore.
        @return nothing: deleted. */
        Scope& operator=(const Scope&) = delete;

      private:
        struct State;
        std::unique_ptr<State> state_;
    };

  private:
    explicit HeadlessGLContext(gpu::EglContext* shared);
    std::unique_ptr<gpu::EglContext> owned_;  // empty for the shared context
    gpu::EglContext* context_ = nullptr;
};

/** @brief How the GPU turns a pose into pixels.

Both give the same pictures: they cover the same pixels as the CPU backend and resolve
overlaps (fold-overs) the same way.
@sa GLDeformerParams::pipeline, DeformParams::pipeline, docs/gpu/README.md
*/
enum GpuPipeline {
    /** Everything in compute shaders, three passes that each touch a node, triangle or pixel
    once: the node positions (the coefficient sum, reading the Eq. 6-7 packed texture), the
    deformed mesh rasterised into a per-pixel triangle owner (atomicMax of the triangle number:
    the later triangle in drawing order wins, as on the CPU), and a gather that interpolates
    the inverse map and samples the image bilinearly. The default, because datacenter GPUs
    (the H100) run vertex, raster and fragment work on a few graphics-capable units only,
    while compute shaders use every multiprocessor. */
    GPU_PIPELINE_COMPUTE = 0,
    /** The paper's program (§4): the coefficient sum in a vertex shader generated per
    multicage, the GPU's rasteriser, and a fragment shader that samples the image. Desktop
    GPUs draw it well; GLDeformer::draw() always uses it. */
    GPU_PIPELINE_VERTEX_SHADER = 1
};

/** @brief Options of a GLDeformer. */
struct CV_EXPORTS GLDeformerParams {
    /** Store the packed coefficients as RGBA16F instead of RGBA32F: half the memory and
    bandwidth. The vertex shader uses the displacement form `p' = x + sum_j CC_j (v'_j - v_j)`,
    so the rest pose stays exact and the error scales with how far vertices moved (about
    `2^-11 |CC_j| |v'_j - v_j|` per term), not with their coordinates. The measured node
    position errors against float32 are in docs/gpu/README.md, "Half-float coefficients"
    (tests Packing.HalfFloatPositionErrorIsSmallInDisplacementForm and
    GpuDeform.HalfFloatCoefficients). */
    bool halfFloat = false;
    /** Largest texture side to use; 0 means GL_MAX_TEXTURE_SIZE. Smaller values force the
    texture-array fallback (choosePackLayout) and exist for tests. */
    int maxTextureSize = 0;
    /** GpuPipeline of render(), renderMaps() and the Deformer's deform() and computeMaps(). */
    int pipeline = GPU_PIPELINE_COMPUTE;
};

/** @brief The GPU multicage deformation inside the caller's own OpenGL context, without
readback.

Needs a desktop OpenGL 4.3+ core context current on the calling thread for the constructor,
every member function and the destructor (the context of a GLFW window, say). It changes
the bindings of the program, vertex array, textures 0-2, framebuffer (render* only) and
viewport (render* only); it restores none of them.

Construction uploads the image and the packed coefficients once (paper Eq. 6-7, or the
texture-array fallback when the layout exceeds the texture limit) and builds the programs
generated for this multicage. A pose update is then one small texture upload plus three
compute dispatches (GPU_PIPELINE_COMPUTE) or one draw call (GPU_PIPELINE_VERTEX_SHADER).

@code
    GLDeformer d(image, bind(cage));        // context current
    d.setPose(pose);
    glViewport(x, y, w, h); d.draw();       // into the bound framebuffer, or:
    GLuint tex = d.render();                // into d's own texture (outputSize())
@endcode
@sa Deformer (BACKEND_GPU) for the same on a headless context with readback.
*/
class CV_EXPORTS GLDeformer {
  public:
    /** @brief Uploads a binding made on the CPU (bind()).
    @param image 8U/16U/32F, 1, 3 or 4 channels, of binding.imageSize.
    @param binding a non-empty binding.
    @param params the options.
    @throws cv::Exception when no OpenGL 4.3 context is current (GpuNotSupported), or the
    image does not match. */
    GLDeformer(InputArray image, const Binding& binding, const GLDeformerParams& params = {});
    /** @brief Binds on the GPU: mean value coordinates in a compute shader (Algorithm 1, as
    bind()).

    The coefficients are written straight into the packed texture and never leave the GPU
    unless binding() is called.
    @param image as the other constructor, of rest.imageSize().
    @param rest the multicage; it must pass validateGeometry() (else cv::Exception, StsBadArg).
    @param gridStep pixels between nodes, >= 1.
    @param params the options. */
    GLDeformer(InputArray image, const Multicage& rest, int gridStep,
               const GLDeformerParams& params = {});
    /** @brief Deletes the GL objects (the context must be current). */
    ~GLDeformer();
    /** @brief Not copyable: the object owns GL objects. */
    GLDeformer(const GLDeformer&) = delete;
    /** @brief Not copyable: the object owns GL objects.
    @return nothing: deleted. */
    GLDeformer& operator=(const GLDeformer&) = delete;

    /** @brief Sets the pose that the next render(), renderMaps() or draw() shows.

    A pose whose frame corners lie on the frame of another size W'xH' (a resize pose,
    resizePose(); the rule is the CPU backend's) renders a W'xH' image: render(), renderMaps()
    and draw() then draw the new frame.
    @param pose vertexCount() points, or coefficientCount() with the frame corners last.
    @throws cv::Exception (StsOutOfRange) when W' or H' exceeds what this GPU draws
    (GL_MAX_TEXTURE_SIZE, GL_MAX_VIEWPORT_DIMS). */
    void setPose(InputArray pose);
    /** @brief Replaces the image.
    @param image the same size and type as before (else cv::Exception, StsBadArg). */
    void setImage(InputArray image);
    /** @brief Draws the deformed image into the bound framebuffer with the paper's
    vertex-shader program (whatever params.pipeline says: it draws into the caller's
    framebuffer).

    The pose's frame (the image's, or a resize pose's new one: outputSize()) fills the current
    viewport. Uncovered pixels are left untouched.
    @param flipY true puts image row 0 at the top (a window), false at the bottom (what
    glReadPixels returns first). */
    void draw(bool flipY = true);
    /** @brief Renders into outputTexture() (outputSize()).

    A pose of another size than the last render's makes a new texture of that size (the old
    one is deleted: ask outputTexture() again after each render).
    @param border the value of pixels no triangle covers.
    @return outputTexture(). */
    unsigned render(const Scalar& border = Scalar());
    /** @brief Renders the inverse maps (RG32F: source x, y per pixel; -1e4 where uncovered)
    into mapsTexture() (outputSize(), remade like outputTexture()).
    @return mapsTexture(). */
    unsigned renderMaps();
    /** @brief Reads outputTexture() back.
    @param[out] dst the size of the last render(), the input's type. */
    void readOutput(OutputArray dst);
    /** @brief Reads mapsTexture() back as two maps for cv::remap.
    @param[out] mapx source x per pixel, CV_32F of the last renderMaps()'s size.
    @param[out] mapy source y per pixel, the same. */
    void readMaps(OutputArray mapx, OutputArray mapy);
    /** @brief The deformed mesh of the last render() or renderMaps() in the compute pipeline
    (for overlays, and to compare with the CPU backend's mesh).
    @param[out] mesh (grid height + 2) x (grid width + 2) CV_32FC2: the binding's node grid
    inside a ring of vertices on the image frame.
    @throws cv::Exception (StsNotImplemented) in the vertex-shader pipeline, which keeps no
    mesh. */
    void readMesh(OutputArray mesh);
    /** @brief The size the current pose renders into.
    @return the image's size, or a resize pose's new size. */
    Size outputSize() const;

    /** @brief The GL name of the deformed image's texture (GL_TEXTURE_2D).
    @return the texture (0 until render() or readOutput() makes one). */
    unsigned outputTexture() const;
    /** @brief The GL name of the inverse maps' texture (GL_TEXTURE_2D, RG32F).
    @return the texture (0 until renderMaps() or readMaps() makes one). */
    unsigned mapsTexture() const;
    /** @brief The GL name of the packed coefficients' texture.
    @return GL_TEXTURE_2D, or GL_TEXTURE_2D_ARRAY if layered. */
    unsigned coefficientTexture() const;
    /** @brief The packing of the coefficient texture.
    @return the layout (PackLayout::layers > 1 for a texture array). */
    const PackLayout& layout() const;
    /** @brief GPU memory of the packed coefficients.
    @return bytes: texels x layers x 4 channels x 2 or 4 bytes. */
    size_t coefficientBytes() const;
    /** @brief The binding; when bound on the GPU, read back from the texture on first use.
    @return a reference valid for the GLDeformer's lifetime. */
    const Binding& binding();
    /** @brief Where construction spent its time, in milliseconds (for the bench). */
    struct Timings {
        double shaderBuild = 0;  //!< compiling and linking the generated shaders
        double packUpload = 0;   //!< packing a CPU binding and uploading it (0 if bound here)
        double binding = 0;      //!< the compute-shader binding (0 if given a CPU binding)
    };
    /** @brief Where construction spent its time.
    @return the times in milliseconds. */
    const Timings& timings() const;
    /** @brief glFinish(): waits until every command so far has run (for timing). */
    void finish();

    /** @brief GPU time of each stage of the last render()/renderMaps() and read*(), in ms, from
    GL_TIMESTAMP queries; -1 for a stage that did not run (or profiling off). The
    vertex-shader pipeline reports its one draw call as `raster`. */
    struct StageTimes {
        double positions = -1;  //!< compute: node positions (the coefficient sum)
        double raster = -1;     //!< compute: triangles to pixel owners; vertex shader: the draw
        double gather = -1;     //!< compute: inverse maps and image sampling
        double readback = -1;   //!< readOutput() / readMaps()
    };
    /** @brief Turns the timestamp queries on (they cost a little; off by default).
    @param on true to profile the following renders. */
    void setProfiling(bool on);
    /** @brief Waits for the last pose's queries and returns their times.
    @return the stage times (all -1 with profiling off). */
    StageTimes stageTimes() const;
    /** @brief The GpuPipeline in use.
    @return GPU_PIPELINE_COMPUTE or GPU_PIPELINE_VERTEX_SHADER. */
    int pipeline() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/** @brief Mean value binding (Algorithm 1, as bind()) computed in a compute shader on the
process's shared headless EGL context (HeadlessGLContext::shared()), read back to the CPU.
@param multicage the multicage; it must pass validateGeometry().
@param gridStep pixels between nodes, >= 1.
@return the binding, MEAN_VALUE coordinates.
@throws cv::Exception (GpuNotSupported) when no EGL context with OpenGL 4.3 can be made.
*/
CV_EXPORTS Binding bindOnGpu(const Multicage& multicage, int gridStep = 1);

/** @brief Whether a headless EGL context can be made here (any OpenGL 4.3, Mesa's llvmpipe
included), i.e. whether BACKEND_GPU works.

Probes once per process: later calls answer from the first. Always false in a library built
with MULTICAGE_WITH_GPU=OFF (#MULTICAGE_HAVE_GPU 0), the description then saying "built
without GPU support (MULTICAGE_WITH_GPU=OFF)".
@param[out] description when not null, receives the device (vendor, renderer, GL version,
platform) or the reason there is none.
@return true when a context can be made.
@sa autoBackendUsesGpu
*/
CV_EXPORTS bool gpuAvailable(std::string* description = nullptr);

//! @} multicage_gpu

}  // namespace multicage
}  // namespace cv

#endif

// The GPU deformation for callers that own an OpenGL context (an editor, a game engine), and
// GPU binding (paper §4). All EGL/OpenGL code of the library lives in modules/gpu.
#ifndef OPENCV2_MULTICAGE_GPU_HPP
#define OPENCV2_MULTICAGE_GPU_HPP

#include <memory>
#include <opencv2/multicage/packing.hpp>

namespace cv {
namespace multicage {

namespace gpu {
class EglContext;
}

/** A headless OpenGL 4.5 (or 4.3) core context through EGL, with no window and no X: a
hardware EGL device (EGL_EXT_platform_device, NVIDIA for instance) first, else Mesa's
surfaceless platform (llvmpipe where there is no GPU). For running GLDeformer without a
window. The constructor makes a new context and throws a cv::Exception saying why when none
can be made; shared() is the one the process's GPU Deformers share. */
class CV_EXPORTS HeadlessGLContext {
  public:
    HeadlessGLContext();
    ~HeadlessGLContext();
    HeadlessGLContext(const HeadlessGLContext&) = delete;
    HeadlessGLContext& operator=(const HeadlessGLContext&) = delete;

    /** The process's shared context: made on the first call (EGL probed once per process,
    about 100 ms without a GPU), never destroyed, so creating a GPU Deformer costs no context
    creation and its programs are compiled once per process. nullptr, with the reason in
    *why, when no context can be made (the answer is kept too). Its Scope takes a lock:
    threads using it take turns. */
    static HeadlessGLContext* shared(std::string* why = nullptr);

    /** Vendor, renderer, GL version and EGL platform. */
    std::string description() const;
    /** Whether the renderer is a software one (Mesa llvmpipe or softpipe): OpenGL on the CPU,
    slower than the CPU backend, so BACKEND_AUTO does not count it as a GPU. */
    bool software() const;

    /** Makes the context current on this thread for the scope's lifetime, then restores what
    was current before. A context can be current on only one thread at a time. */
    class CV_EXPORTS Scope {
      public:
        explicit Scope(const HeadlessGLContext& context);
        ~Scope();
        Scope(const Scope&) = delete;
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

/** How the GPU turns a pose into pixels. Both give the same pictures: they cover the same
pixels as the CPU backend and resolve overlaps (fold-overs) the same way. */
enum GpuPipeline {
    /** Everything in compute shaders, three passes that each touch a node, triangle or pixel
    once: the node positions (the coefficient sum, reading the Eq. 6-7 packed texture), the
    deformed mesh rasterised into a per-pixel triangle owner (atomicMax of the triangle number:
    the later triangle in drawing order wins, as on the CPU), and a gather that interpolates
    the inverse map and samples the image bilinearly. The default: datacenter GPUs (the H100)
    run vertex, raster and fragment work on a few graphics-capable units only, while compute
    shaders use every multiprocessor. */
    GPU_PIPELINE_COMPUTE = 0,
    /** The paper's program (§4): the coefficient sum in a vertex shader generated per
    multicage, the GPU's rasteriser, and a fragment shader that samples the image. Desktop
    GPUs draw it well; GLDeformer::draw() always uses it. */
    GPU_PIPELINE_VERTEX_SHADER = 1
};

struct CV_EXPORTS GLDeformerParams {
    /** Store the packed coefficients as RGBA16F instead of RGBA32F: half the memory and
    bandwidth. The vertex shader uses the displacement form p' = x + sum_j CC_j (v'_j - v_j),
    so the rest pose stays exact and the error scales with how far vertices moved (about
    2^-11 |CC_j| |v'_j - v_j| per term), not with their coordinates. Measured node position
    error against float32 (test Packing.HalfFloatPositionErrorIsSmallInDisplacementForm):
      1024x768, 68 vertices, moved up to 16.7 px: 0.0044 px  (plain form sum_j CC_j v'_j: 0.42 px)
      butterfly, 2 nested polygons, moved up to 28.8 px: 0.020 px  (plain form: 0.57 px)
    and 0.0045 px max difference of the GPU's inverse maps (GpuDeform.HalfFloatCoefficients). */
    bool halfFloat = false;
    /** Largest texture side to use; 0 means GL_MAX_TEXTURE_SIZE. Smaller values force the
    texture-array fallback (choosePackLayout) and exist for tests. */
    int maxTextureSize = 0;
    /** GpuPipeline of render(), renderMaps() and the Deformer's deform() and computeMaps(). */
    int pipeline = GPU_PIPELINE_COMPUTE;
};

/** The GPU multicage deformation inside the caller's own OpenGL context, without readback.

Needs a desktop OpenGL 4.3+ core context current on the calling thread for the constructor,
every member function and the destructor (the context of a GLFW window, say). It changes
the bindings of the program, vertex array, textures 0-2, framebuffer (render* only) and
viewport (render* only); it restores none of them.

Construction uploads the image and the packed coefficients once (paper Eq. 6-7, or the
texture-array fallback when the layout exceeds the texture limit) and builds the programs
generated for this multicage. A pose update is then one small texture upload plus three
compute dispatches (GPU_PIPELINE_COMPUTE) or one draw call (GPU_PIPELINE_VERTEX_SHADER).

    GLDeformer d(image, bind(cage));        // context current
    d.setPose(pose);
    glViewport(x, y, w, h); d.draw();       // into the bound framebuffer, or:
    GLuint tex = d.render();                // into d's own texture (outputSize()) */
class CV_EXPORTS GLDeformer {
  public:
    /** Uploads a binding made on the CPU (bind()). image: 8U/16U/32F, 1, 3 or 4 channels. */
    GLDeformer(InputArray image, const Binding& binding, const GLDeformerParams& params = {});
    /** Binds on the GPU (mean value coordinates in a compute shader, Algorithm 1): the
    coefficients are written straight into the packed texture and never leave the GPU
    unless binding() is called. */
    GLDeformer(InputArray image, const Multicage& rest, int gridStep,
               const GLDeformerParams& params = {});
    ~GLDeformer();
    GLDeformer(const GLDeformer&) = delete;
    GLDeformer& operator=(const GLDeformer&) = delete;

    /** The pose: vertexCount() points, or coefficientCount() with the frame corners last.
    A pose whose frame corners lie on the frame of another size W'xH' (a resize pose,
    resizePose() in resize.hpp; the rule is the CPU backend's) renders a W'xH' image: render(),
    renderMaps() and draw() then draw the new frame. Throws StsOutOfRange when W' or H' exceeds
    what this GPU draws (GL_MAX_TEXTURE_SIZE, GL_MAX_VIEWPORT_DIMS). */
    void setPose(InputArray pose);
    /** Replaces the image (same size and type as before). */
    void setImage(InputArray image);
    /** Draws the deformed image into the bound framebuffer with the paper's vertex-shader
    program (whatever params.pipeline says: it draws into the caller's framebuffer): the pose's
    frame (the image's, or a resize pose's new one: outputSize()) fills the current viewport; flipY
    puts image row 0 at the top (a window), false at the bottom (what glReadPixels returns first).
    Uncovered pixels are left untouched. */
    void draw(bool flipY = true);
    /** Renders into outputTexture() (outputSize(); border where no triangle covers a pixel)
    and returns it. A pose of another size than the last render's makes a new texture of that
    size (the old one is deleted: ask outputTexture() again after each render). */
    unsigned render(const Scalar& border = Scalar());
    /** Renders the inverse maps (RG32F: source x, y per pixel; -1e4 where uncovered) into
    mapsTexture() (outputSize(), remade like outputTexture()) and returns it. */
    unsigned renderMaps();
    /** Reads outputTexture() back: the size of the last render(), the input's type. */
    void readOutput(OutputArray dst);
    /** Reads mapsTexture() back as two CV_32F maps for cv::remap (the last renderMaps()'s size). */
    void readMaps(OutputArray mapx, OutputArray mapy);
    /** The deformed mesh of the last render() or renderMaps() in the compute pipeline:
    (grid height + 2) x (grid width + 2) CV_32FC2, the binding's node grid inside a ring of
    vertices on the image frame (for overlays, and to compare with the CPU backend's mesh).
    The vertex-shader pipeline keeps no mesh: StsNotImplemented. */
    void readMesh(OutputArray mesh);
    /** The size the current pose renders into: the image's, or a resize pose's new size. */
    Size outputSize() const;

    unsigned outputTexture() const;
    unsigned mapsTexture() const;
    unsigned coefficientTexture() const;  //!< GL_TEXTURE_2D, or GL_TEXTURE_2D_ARRAY if layered
    const PackLayout& layout() const;
    size_t coefficientBytes() const;  //!< GPU memory of the packed coefficients
    /** The binding (from the GPU texture when bound on the GPU: read back on first use). */
    const Binding& binding();
    /** Where construction spent its time, in milliseconds (for the bench). */
    struct Timings {
        double shaderBuild = 0;  //!< compiling and linking the generated shaders
        double packUpload = 0;   //!< packing a CPU binding and uploading it (0 if bound here)
        double binding = 0;      //!< the compute-shader binding (0 if given a CPU binding)
    };
    const Timings& timings() const;
    /** glFinish(): waits until every command so far has run (for timing). */
    void finish();

    /** GPU time of each stage of the last render()/renderMaps() and read*(), in ms, from
    GL_TIMESTAMP queries; -1 for a stage that did not run (or profiling off). The
    vertex-shader pipeline reports its one draw call as `raster`. */
    struct StageTimes {
        double positions = -1;  //!< compute: node positions (the coefficient sum)
        double raster = -1;     //!< compute: triangles to pixel owners; vertex shader: the draw
        double gather = -1;     //!< compute: inverse maps and image sampling
        double readback = -1;   //!< readOutput() / readMaps()
    };
    /** Turns the timestamp queries on (they cost a little; off by default). */
    void setProfiling(bool on);
    /** Waits for the last pose's queries and returns their times. */
    StageTimes stageTimes() const;
    /** The GpuPipeline in use. */
    int pipeline() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/** Mean value binding (Algorithm 1, as bind()) computed in a compute shader on a private
headless EGL context (the process's shared one), read back to the CPU. Throws a cv::Exception when no EGL context with
OpenGL 4.3 can be made. */
CV_EXPORTS Binding bindOnGpu(const Multicage& multicage, int gridStep = 1);

/** Whether a headless EGL context can be made here (any OpenGL 4.3, Mesa's llvmpipe
included); *description gets the device (vendor, renderer, GL version, platform) or the
reason there is none. Probes once per process: later calls answer from the first. */
CV_EXPORTS bool gpuAvailable(std::string* description = nullptr);

}  // namespace multicage
}  // namespace cv

#endif

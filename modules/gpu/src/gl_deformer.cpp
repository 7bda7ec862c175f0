// GLDeformer: the GPU deformation inside the caller's current GL context, by the compute
// pipeline (positions.comp, raster.comp, gather.comp) or the paper's vertex-shader program (§4).
#include <chrono>
#include <opencv2/core/utility.hpp>
#include <opencv2/multicage/gpu.hpp>
#include <opencv2/multicage/internal/backend_contract.hpp>

#include "gl_binding.hpp"
#include "gl_util.hpp"

namespace cv {
namespace multicage {

using gpu::buildComputeProgram;
using gpu::buildProgram;
using gpu::checkGl;
using gpu::glVersion;

namespace {

struct PixelFormat {
    GLenum internal, format, type;
    double scale;  // Scalar value -> what the shader writes (normalised formats)
};

// The image texture and the output FBO share a format matching the input depth. Three
// channels are stored as RGBA (RGB formats need not be colour-renderable) and read back as RGB.
PixelFormat pixelFormat(int type) {
    checkImageType(type);
    const int depth = CV_MAT_DEPTH(type), cn = CV_MAT_CN(type);
    const GLenum format = cn == 1 ? GL_RED : cn == 3 ? GL_RGB : GL_RGBA;
    switch (depth) {
        case CV_8U:
            return {cn == 1 ? GLenum(GL_R8) : GLenum(GL_RGBA8), format, GL_UNSIGNED_BYTE,
                    1.0 / 255};
        case CV_16U:
            return {cn == 1 ? GLenum(GL_R16) : GLenum(GL_RGBA16), format, GL_UNSIGNED_SHORT,
                    1.0 / 65535};
        case CV_32F:
            return {cn == 1 ? GLenum(GL_R32F) : GLenum(GL_RGBA32F), format, GL_FLOAT, 1.0};
    }
    CV_Error(Error::StsInternal, "multicage: pixelFormat");  // checkImageType let it through
}

GLuint makeTexture(GLenum target) {
    GLuint t;
    glGenTextures(1, &t);
    glBindTexture(target, t);
    glTexParameteri(target, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(target, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(target, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(target, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return t;
}

GLuint makeFramebuffer(GLuint texture, const char* what) {
    GLuint fbo;
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture, 0);
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
        CV_Error_(Error::GpuApiCallError,
                  ("multicage: the %s framebuffer is incomplete (status 0x%x)", what, status));
    return fbo;
}

// A texture and the framebuffer around it, of one size: the output of the sizes a pose asks for
// (frameOutputSize), remade when the size changes (immutable storage cannot be resized).
struct Target {
    Size size;
    GLuint texture = 0, fbo = 0;

    void ensure(Size s, GLenum internal, const char* what) {
        if (fbo && s == size) return;
        release();
        texture = makeTexture(GL_TEXTURE_2D);
        glTexStorage2D(GL_TEXTURE_2D, 1, internal, s.width, s.height);
        checkGl(what);
        fbo = makeFramebuffer(texture, what);
        size = s;
    }
    void release() {
        glDeleteTextures(1, &texture);
        glDeleteFramebuffers(1, &fbo);
        texture = fbo = 0;
        size = Size();
    }
};

double msSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

// GPU timestamps around the stages of a pose (GL_TIMESTAMP queries), read when asked for.
class StageClock {
  public:
    enum Mark { kStart, kPositions, kRaster, kGather, kReadStart, kReadEnd, kMarks };
    void enable(bool on) {
        if (on && !queries_[0]) glGenQueries(kMarks, queries_);
        on_ = on;
    }
    void reset() { std::fill(std::begin(marked_), std::end(marked_), false); }
    void mark(Mark m) {
        if (!on_) return;
        glQueryCounter(queries_[m], GL_TIMESTAMP);
        marked_[m] = true;
    }
    // Milliseconds between two marks of the last pose, or -1 if either was not taken.
    double between(Mark a, Mark b) const {
        if (!marked_[a] || !marked_[b]) return -1;
        GLuint64 ta = 0, tb = 0;
        glGetQueryObjectui64v(queries_[a], GL_QUERY_RESULT, &ta);
        glGetQueryObjectui64v(queries_[b], GL_QUERY_RESULT, &tb);
        return double(tb - ta) * 1e-6;
    }
    void release() {
        if (queries_[0]) glDeleteQueries(kMarks, queries_);
        queries_[0] = 0;
    }

  private:
    bool on_ = false;
    GLuint queries_[kMarks] = {};
    bool marked_[kMarks] = {};
};

struct GLDeformer::Impl {
    Binding binding;
    bool coefficientsOnCpu = true;
    bool half = false;
    int pipeline = GPU_PIPELINE_COMPUTE;
    PackLayout layout;
    int imageType = 0;
    PixelFormat fmt{};
    std::string defines;  // the per-multicage constants of every program
    // The paper's program (built on first use in the compute pipeline: only draw() needs it).
    GLuint imageProgram = 0, mapsProgram = 0, vao = 0, indices = 0;
    GLsizei indexCount = 0;
    // The compute pipeline: deformed mesh vertices, and per pixel the triangle that covers it.
    GLuint positionsProgram = 0, rasterProgram = 0, gatherImageProgram = 0, gatherMapsProgram = 0;
    GLuint positions = 0, owners = 0;
    size_t ownerCapacity = 0;  // pixels the owners buffer holds: the largest output so far
    int rasterSlices = 1;
    GLuint coefficients = 0, pose = 0, image = 0;
    // The size the current pose renders into (frameOutputSize), and the largest GL allows.
    Size outSize;
    int maxOutputSide = 0;
    Target output, maps;
    Timings timings;
    StageClock clock;

    Size size() const { return binding.imageSize; }
    Size meshSize() const { return binding.gridSize + Size(2, 2); }  // the nodes and the ring
    GLenum coefficientTarget() const {
        return layout.layers > 1 ? GL_TEXTURE_2D_ARRAY : GL_TEXTURE_2D;
    }

    void init(const Mat& img, const GLDeformerParams& params) {
        if (glVersion() < 43)
            CV_Error(Error::GpuNotSupported, "multicage: GLDeformer needs an OpenGL 4.3 context");
        if (params.pipeline != GPU_PIPELINE_COMPUTE &&
            params.pipeline != GPU_PIPELINE_VERTEX_SHADER)
            CV_Error_(Error::StsOutOfRange,
                      ("multicage: unknown GPU pipeline %d", params.pipeline));
        half = params.halfFloat;
        pipeline = params.pipeline;
        GLint maxTexture = 0, maxLayers = 0;
        glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTexture);
        glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &maxLayers);
        GLint viewport[2] = {0, 0};
        glGetIntegerv(GL_MAX_VIEWPORT_DIMS, viewport);
        maxOutputSide = std::min<int>(maxTexture, std::min(viewport[0], viewport[1]));
        if (params.maxTextureSize > 0) maxTexture = std::min(maxTexture, params.maxTextureSize);
        layout =
            choosePackLayout(binding.gridSize, binding.coefficientCount(), maxTexture, maxLayers);
        coefficients = makeTexture(coefficientTarget());
        const GLenum internal = half ? GL_RGBA16F : GL_RGBA32F;
        if (layout.layers > 1)
            glTexStorage3D(GL_TEXTURE_2D_ARRAY, 1, internal, layout.textureSize.width,
                           layout.textureSize.height, layout.layers);
        else
            glTexStorage2D(GL_TEXTURE_2D, 1, internal, layout.textureSize.width,
                           layout.textureSize.height);
        checkGl("allocating the coefficient texture");

        pose = makeTexture(GL_TEXTURE_1D);  // deltas, then the frame corners (mesh_positions.glsl)
        glTexStorage1D(GL_TEXTURE_1D, 1, GL_RGBA32F, 2 * layout.blocks + 2);

        imageType = img.type();
        fmt = pixelFormat(imageType);
        image = makeTexture(GL_TEXTURE_2D);
        glTexStorage2D(GL_TEXTURE_2D, 1, fmt.internal, img.cols, img.rows);
        upload(img);

        // The per-multicage program (paper §4): the constants of this binding and layout.
        const int m = binding.gridSize.width, n = binding.gridSize.height;
        rasterSlices = std::min(std::max(binding.gridStep, 1), 16);
        defines = cv::format(
            "#define GRID_W %d\n#define GRID_H %d\n#define GRID_STEP %d\n#define IMAGE_W %d\n"
            "#define IMAGE_H %d\n#define BLOCKS %d\n#define BLOCK_COLS %d\n"
            "#define BLOCKS_PER_LAYER %d\n#define LAYERED %d\n#define COEFFICIENTS %d\n"
            "#define RASTER_SLICES %d\n#define UNCOVERED %.1f\n",
            m, n, binding.gridStep, binding.imageSize.width, binding.imageSize.height,
            layout.blocks, layout.cols, layout.blocksPerLayer(), layout.layers > 1 ? 1 : 0,
            binding.coefficientCount(), rasterSlices, double(kUncovered));
        const auto t = std::chrono::steady_clock::now();
        if (pipeline == GPU_PIPELINE_COMPUTE)
            initCompute();
        else
            initVertexShader();
        timings.shaderBuild = msSince(t);
        setPose(std::vector<Point2f>(binding.restVertices));
    }

    void initCompute() {
        const Size mesh = meshSize();
        glGenBuffers(1, &positions);
        glBindBuffer(GL_SHADER_STORAGE_BUFFER, positions);
        glBufferData(GL_SHADER_STORAGE_BUFFER, size_t(mesh.area()) * 2 * sizeof(float), nullptr,
                     GL_DYNAMIC_COPY);
        glGenBuffers(1, &owners);
        ensureOwners(size());
        checkGl("allocating the compute pipeline's buffers");
        positionsProgram = buildComputeProgram(defines, "positions.comp");
        rasterProgram = buildComputeProgram(defines, "raster.comp");
        const char* format = imageFormatQualifier();
        gatherImageProgram = buildComputeProgram(
            defines + "#define GATHER_MAPS 0\n#define OUTPUT_FORMAT " + format + "\n",
            "gather.comp");
        gatherMapsProgram = buildComputeProgram(defines + "#define GATHER_MAPS 1\n", "gather.comp");
    }

    // Owners for every pixel of an output of size s. Zeroed when (re)allocated, and the gather
    // pass resets every owner it reads, so no pose needs a clear; a smaller output uses the
    // front of the buffer, whose owners its gather resets too.
    void ensureOwners(Size s) {
        const size_t need = size_t(s.width) * size_t(s.height);
        if (need <= ownerCapacity) return;
        glBindBuffer(GL_SHADER_STORAGE_BUFFER, owners);
        glBufferData(GL_SHADER_STORAGE_BUFFER, need * sizeof(GLuint), nullptr, GL_DYNAMIC_COPY);
        const GLuint zero = 0;
        glClearBufferData(GL_SHADER_STORAGE_BUFFER, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT,
                          &zero);
        checkGl("allocating the pixel owners");
        ownerCapacity = need;
    }

    // The layout qualifier of the output image for imageStore (GL 4.3 image formats).
    const char* imageFormatQualifier() const {
        switch (fmt.internal) {
            case GL_R8:
                return "r8";
            case GL_RGBA8:
                return "rgba8";
            case GL_R16:
                return "r16";
            case GL_RGBA16:
                return "rgba16";
            case GL_R32F:
                return "r32f";
            default:
                return "rgba32f";
        }
    }

    void initVertexShader() {
        if (imageProgram) return;
        // One mesh vertex per node plus the ring (mesh_grid.glsl); the cells' triangles in
        // the order the CPU backend draws them (kCellTriangles), so that fold-overs resolve
        // the same way (later triangle wins).
        const int em = meshSize().width, en = meshSize().height;
        std::vector<GLuint> idx;
        idx.reserve(size_t(em - 1) * (en - 1) * 6);
        for (int gy = 0; gy + 1 < en; ++gy)
            for (int gx = 0; gx + 1 < em; ++gx) {
                for (const auto& triangle : kCellTriangles)
                    for (const auto& corner : triangle)
                        idx.push_back(GLuint((gy + corner[1]) * em + gx + corner[0]));
            }
        indexCount = static_cast<GLsizei>(idx.size());
        glGenVertexArrays(1, &vao);
        glBindVertexArray(vao);
        glGenBuffers(1, &indices);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, indices);
        glBufferData(GL_ELEMENT_ARRAY_BUFFER, idx.size() * sizeof(GLuint), idx.data(),
                     GL_STATIC_DRAW);
        glBindVertexArray(0);
        checkGl("uploading the mesh");
        imageProgram = buildProgram(defines, "deform.vert", "deform_image.frag");
        mapsProgram = buildProgram(defines, "deform.vert", "deform_maps.frag");
    }

    // Packs the CPU binding straight into a mapped pixel buffer, in parallel, and uploads it
    // from there: one pass over the coefficients instead of pack, convert and copy.
    void uploadCoefficients() {
        const auto t = std::chrono::steady_clock::now();
        const int depth = half ? CV_16F : CV_32F;
        const Size full(layout.textureSize.width, layout.textureSize.height * layout.layers);
        const size_t bytes = size_t(full.area()) * 4 * CV_ELEM_SIZE1(depth);
        GLuint pbo;
        glGenBuffers(1, &pbo);
        glBindBuffer(GL_PIXEL_UNPACK_BUFFER, pbo);
        glBufferData(GL_PIXEL_UNPACK_BUFFER, bytes, nullptr, GL_STREAM_DRAW);
        void* mapped = glMapBufferRange(GL_PIXEL_UNPACK_BUFFER, 0, bytes,
                                        GL_MAP_WRITE_BIT | GL_MAP_INVALIDATE_BUFFER_BIT);
        try {
            if (!mapped)
                CV_Error(Error::GpuApiCallError, "multicage: cannot map the upload buffer");
            Mat packed(full, CV_MAKETYPE(depth, 4), mapped);
            packCoefficients(binding, layout, packed, depth);
            CV_Assert(packed.data == mapped);  // written in place
        } catch (...) {
            if (mapped) glUnmapBuffer(GL_PIXEL_UNPACK_BUFFER);
            glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
            glDeleteBuffers(1, &pbo);
            throw;
        }
        glUnmapBuffer(GL_PIXEL_UNPACK_BUFFER);
        glBindTexture(coefficientTarget(), coefficients);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
        glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
        const GLenum type = half ? GL_HALF_FLOAT : GL_FLOAT;
        if (layout.layers > 1)
            glTexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, 0, 0, 0, layout.textureSize.width,
                            layout.textureSize.height, layout.layers, GL_RGBA, type, nullptr);
        else
            glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, layout.textureSize.width,
                            layout.textureSize.height, GL_RGBA, type, nullptr);
        glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
        glDeleteBuffers(1, &pbo);
        checkGl("uploading the coefficients");
        glFinish();
        timings.packUpload = msSince(t);
    }

    void upload(const Mat& src) {
        if (src.type() != imageType || src.size() != size())
            CV_Error_(Error::StsBadArg,
                      ("multicage: setImage expects a %dx%d %s image, got %dx%d %s", size().width,
                       size().height, typeToString(imageType).c_str(), src.cols, src.rows,
                       typeToString(src.type()).c_str()));
        const Mat img = src.isContinuous() ? src : src.clone();
        glBindTexture(GL_TEXTURE_2D, image);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
        glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, img.cols, img.rows, fmt.format, fmt.type, img.data);
        checkGl("uploading the image");
    }

    void setPose(InputArray poseIn) {
        const std::vector<Point2f> p = binding.completePose(poseIn);
        const Size out = frameOutputSize(&p[p.size() - 4], size());
        if (out.width > maxOutputSide || out.height > maxOutputSide)
            CV_Error_(Error::StsOutOfRange,
                      ("multicage: the pose asks for a %dx%d output; this GPU draws at most %d "
                       "pixels a side",
                       out.width, out.height, maxOutputSide));
        // v'_j - v_j, 2 per texel, then the 4 posed frame corners, 2 per texel.
        std::vector<Vec4f> texels(2 * layout.blocks + 2, Vec4f::all(0.f));
        for (size_t j = 0; j < p.size(); ++j) {
            const Point2f d = p[j] - binding.restVertices[j];
            texels[j / 2][2 * (j % 2)] = d.x;
            texels[j / 2][2 * (j % 2) + 1] = d.y;
        }
        const Point2f* corners = &p[p.size() - 4];
        texels[2 * layout.blocks] = Vec4f(corners[0].x, corners[0].y, corners[1].x, corners[1].y);
        texels[2 * layout.blocks + 1] =
            Vec4f(corners[2].x, corners[2].y, corners[3].x, corners[3].y);
        glBindTexture(GL_TEXTURE_1D, pose);
        glTexSubImage1D(GL_TEXTURE_1D, 0, 0, int(texels.size()), GL_RGBA, GL_FLOAT, texels.data());
        checkGl("uploading the pose");
        outSize = out;
    }

    void bindCoefficientsAndPose() {
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(coefficientTarget(), coefficients);
        glActiveTexture(GL_TEXTURE1);
        glBindTexture(GL_TEXTURE_1D, pose);
        glActiveTexture(GL_TEXTURE2);
        glBindTexture(GL_TEXTURE_2D, image);
        glActiveTexture(GL_TEXTURE0);
    }

    void draw(GLuint program, bool flipY) {
        // The pose's frame fills the viewport: the input's frame, or a resize pose's new one.
        const float W = static_cast<float>(outSize.width), H = static_cast<float>(outSize.height);
        glUseProgram(program);
        // pixel centre x -> (x + 0.5) / W in [0, 1] -> clip [-1, 1]
        glUniform4f(0, 2.f / W, flipY ? -2.f / H : 2.f / H, 1.f / W - 1.f,
                    flipY ? 1.f - 1.f / H : 1.f / H - 1.f);
        bindCoefficientsAndPose();
        glDisable(GL_BLEND);
        glDisable(GL_DEPTH_TEST);
        glDisable(GL_CULL_FACE);  // folded triangles are drawn like the CPU backend draws them
        glDisable(GL_SCISSOR_TEST);
        glBindVertexArray(vao);
        glDrawElements(GL_TRIANGLES, indexCount, GL_UNSIGNED_INT, nullptr);
        glBindVertexArray(0);
        checkGl("drawing the deformed mesh");
    }

    // Compute pipeline passes 1 and 2: mesh positions, then each pixel's owning triangle.
    void rasterize() {
        const Size mesh = meshSize();
        ensureOwners(outSize);
        bindCoefficientsAndPose();
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, positions);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, owners);
        clock.mark(StageClock::kStart);
        glUseProgram(positionsProgram);
        glDispatchCompute((mesh.width + 15) / 16, (mesh.height + 15) / 16, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        clock.mark(StageClock::kPositions);
        glUseProgram(rasterProgram);
        glUniform2i(1, outSize.width, outSize.height);
        glDispatchCompute((2 * (mesh.width - 1) + 63) / 64, (mesh.height - 1) * rasterSlices, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        clock.mark(StageClock::kRaster);
        checkGl("rasterising the deformed mesh");
    }

    // Compute pipeline pass 3 into `target` (image unit 0, of `format`).
    void gather(GLuint program, GLuint target, GLenum format) {
        glUseProgram(program);
        glUniform2i(1, outSize.width, outSize.height);
        glBindImageTexture(0, target, 0, GL_FALSE, 0, GL_WRITE_ONLY, format);
        glDispatchCompute((outSize.width + 15) / 16, (outSize.height + 15) / 16, 1);
        // Owners reset for the next pose; the target read back or sampled next.
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT |
                        GL_TEXTURE_UPDATE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT |
                        GL_PIXEL_BUFFER_BARRIER_BIT);
        clock.mark(StageClock::kGather);
        checkGl("gathering the deformed image");
    }

    // The targets of the current pose's size: a new size costs one texture and framebuffer
    // each (the previous size's are freed), a pose of the same size nothing.
    void ensureOutput() { output.ensure(outSize, fmt.internal, "output"); }
    void ensureMaps() { maps.ensure(outSize, GL_RG32F, "maps"); }

    void release() {
        for (GLuint p : {imageProgram, mapsProgram, positionsProgram, rasterProgram,
                         gatherImageProgram, gatherMapsProgram})
            gpu::deleteProgram(p);
        const GLuint textures[] = {coefficients, pose, image};
        glDeleteTextures(3, textures);
        output.release();
        maps.release();
        const GLuint buffers[] = {indices, positions, owners};
        glDeleteBuffers(3, buffers);
        glDeleteVertexArrays(1, &vao);
        clock.release();
    }
};

GLDeformer::GLDeformer(InputArray image, const Binding& binding, const GLDeformerParams& params)
    : impl_(new Impl) {
    const Mat img = image.getMat();
    CV_Assert(!binding.empty() && binding.imageSize == img.size());
    impl_->binding = binding;
    try {
        impl_->init(img, params);
        impl_->uploadCoefficients();
    } catch (...) {
        impl_->release();
        throw;
    }
}

GLDeformer::GLDeformer(InputArray image, const Multicage& rest, int gridStep,
                       const GLDeformerParams& params)
    : impl_(new Impl) {
    const Mat img = image.getMat();
    std::string why;
    if (!rest.validateGeometry(&why)) CV_Error(Error::StsBadArg, "multicage: cannot bind: " + why);
    if (rest.imageSize() != img.size())
        CV_Error_(Error::StsBadSize,
                  ("multicage: the image is %dx%d but the multicage was made for %dx%d", img.cols,
                   img.rows, rest.imageSize().width, rest.imageSize().height));
    Binding& b = impl_->binding;
    b.imageSize = rest.imageSize();
    b.gridStep = gridStep;
    b.gridSize = gridSizeFor(b.imageSize, gridStep);
    b.coordinates = MEAN_VALUE;
    b.restVertices = rest.vertices();
    impl_->coefficientsOnCpu = false;
    try {
        impl_->init(img, params);
        glFinish();  // the image upload is not binding time
        const auto t = std::chrono::steady_clock::now();
        const double renderShaders = impl_->timings.shaderBuild;
        // It reads the conditioning back, so the dispatches have finished when it returns.
        gpu::bindMeanValue(rest, impl_->layout, impl_->coefficients, impl_->half, &b,
                           &impl_->timings.shaderBuild);
        impl_->timings.binding = msSince(t) - (impl_->timings.shaderBuild - renderShaders);
    } catch (...) {
        impl_->release();
        throw;
    }
}

GLDeformer::~GLDeformer() {
    impl_->release();
}

void GLDeformer::setPose(InputArray pose) {
    impl_->setPose(pose);
}
void GLDeformer::setImage(InputArray image) {
    impl_->upload(image.getMat());
}
void GLDeformer::draw(bool flipY) {
    impl_->initVertexShader();
    impl_->draw(impl_->imageProgram, flipY);
}

unsigned GLDeformer::render(const Scalar& border) {
    Impl& d = *impl_;
    d.ensureOutput();
    d.clock.reset();
    const float b[4] = {float(border[0] * d.fmt.scale), float(border[1] * d.fmt.scale),
                        float(border[2] * d.fmt.scale), float(border[3] * d.fmt.scale)};
    if (d.pipeline == GPU_PIPELINE_COMPUTE) {
        d.rasterize();
        glProgramUniform4fv(d.gatherImageProgram, 0, 1, b);  // programs are shared: set each time
        d.gather(d.gatherImageProgram, d.output.texture, d.fmt.internal);
        return d.output.texture;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, d.output.fbo);
    glViewport(0, 0, d.outSize.width, d.outSize.height);
    glClearBufferfv(GL_COLOR, 0, b);
    d.clock.mark(StageClock::kPositions);  // the vertex shader sums and draws in one pass
    d.draw(d.imageProgram, false);
    d.clock.mark(StageClock::kRaster);
    return d.output.texture;
}

unsigned GLDeformer::renderMaps() {
    Impl& d = *impl_;
    d.ensureMaps();
    d.clock.reset();
    if (d.pipeline == GPU_PIPELINE_COMPUTE) {
        d.rasterize();
        d.gather(d.gatherMapsProgram, d.maps.texture, GL_RG32F);
        return d.maps.texture;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, d.maps.fbo);
    glViewport(0, 0, d.outSize.width, d.outSize.height);
    const float clear[4] = {kUncovered, kUncovered, 0.f, 0.f};
    glClearBufferfv(GL_COLOR, 0, clear);
    d.clock.mark(StageClock::kPositions);
    d.draw(d.mapsProgram, false);
    d.clock.mark(StageClock::kRaster);
    return d.maps.texture;
}

void GLDeformer::readOutput(OutputArray dst) {
    if (!impl_->output.fbo) impl_->ensureOutput();
    dst.create(impl_->output.size, impl_->imageType);
    Mat out = dst.getMat();
    CV_Assert(out.isContinuous());
    impl_->clock.mark(StageClock::kReadStart);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, impl_->output.fbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glPixelStorei(GL_PACK_ROW_LENGTH, 0);
    // Row 0 of the Mat is the framebuffer's bottom row, where render() put image row 0.
    glReadPixels(0, 0, out.cols, out.rows, impl_->fmt.format, impl_->fmt.type, out.data);
    impl_->clock.mark(StageClock::kReadEnd);
    gpu::checkGl("reading the deformed image back");
}

void GLDeformer::readMaps(OutputArray mapx, OutputArray mapy) {
    if (!impl_->maps.fbo) impl_->ensureMaps();
    const Size size = impl_->maps.size;
    mapx.create(size, CV_32F);
    mapy.create(size, CV_32F);
    Mat x = mapx.getMat(), y = mapy.getMat();
    CV_Assert(x.isContinuous() && y.isContinuous());
    impl_->clock.mark(StageClock::kReadStart);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, impl_->maps.fbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glPixelStorei(GL_PACK_ROW_LENGTH, 0);
    // Each channel straight into its map: no interleaved copy to allocate and split (at
    // 4096x3072 that copy is 100 MB).
    glReadPixels(0, 0, size.width, size.height, GL_RED, GL_FLOAT, x.data);
    glReadPixels(0, 0, size.width, size.height, GL_GREEN, GL_FLOAT, y.data);
    impl_->clock.mark(StageClock::kReadEnd);
    gpu::checkGl("reading the maps back");
}

void GLDeformer::readMesh(OutputArray mesh) {
    if (!impl_->positions)
        CV_Error(Error::StsNotImplemented,
                 "multicage: GLDeformer::readMesh: the vertex-shader pipeline keeps no mesh");
    mesh.create(impl_->meshSize(), CV_32FC2);
    Mat out = mesh.getMat();
    CV_Assert(out.isContinuous());
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, impl_->positions);
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, GLsizeiptr(out.total() * out.elemSize()),
                       out.data);
    gpu::checkGl("reading the mesh back");
}

void GLDeformer::setProfiling(bool on) {
    impl_->clock.enable(on);
}

GLDeformer::StageTimes GLDeformer::stageTimes() const {
    const StageClock& c = impl_->clock;
    StageTimes t;
    t.positions = c.between(StageClock::kStart, StageClock::kPositions);
    t.raster = c.between(StageClock::kPositions, StageClock::kRaster);
    t.gather = c.between(StageClock::kRaster, StageClock::kGather);
    t.readback = c.between(StageClock::kReadStart, StageClock::kReadEnd);
    return t;
}

int GLDeformer::pipeline() const {
    return impl_->pipeline;
}

unsigned GLDeformer::outputTexture() const {
    return impl_->output.texture;
}
unsigned GLDeformer::mapsTexture() const {
    return impl_->maps.texture;
}
Size GLDeformer::outputSize() const {
    return impl_->outSize;
}
unsigned GLDeformer::coefficientTexture() const {
    return impl_->coefficients;
}
const PackLayout& GLDeformer::layout() const {
    return impl_->layout;
}
const GLDeformer::Timings& GLDeformer::timings() const {
    return impl_->timings;
}
void GLDeformer::finish() {
    glFinish();
}

size_t GLDeformer::coefficientBytes() const {
    const PackLayout& l = impl_->layout;
    return size_t(l.textureSize.area()) * l.layers * 4 * (impl_->half ? 2 : 4);
}

const Binding& GLDeformer::binding() {
    if (!impl_->coefficientsOnCpu) {
        const PackLayout& l = impl_->layout;
        Mat packed(l.textureSize.height * l.layers, l.textureSize.width, CV_32FC4);
        glBindTexture(impl_->coefficientTarget(), impl_->coefficients);
        glPixelStorei(GL_PACK_ALIGNMENT, 4);
        glPixelStorei(GL_PACK_ROW_LENGTH, 0);
        glGetTexImage(impl_->coefficientTarget(), 0, GL_RGBA, GL_FLOAT, packed.data);
        gpu::checkGl("reading the GPU binding back");
        unpackCoefficients(packed, l, impl_->binding.coefficientCount(),
                           impl_->binding.coefficients);
        impl_->coefficientsOnCpu = true;
    }
    return impl_->binding;
}

}  // namespace multicage
}  // namespace cv

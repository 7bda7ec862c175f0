// GLDeformer: the paper's GPU deformation (§4) inside the caller's current GL context.
#include <chrono>
#include <opencv2/multicage/gpu.hpp>

#include "gl_binding.hpp"
#include "gl_util.hpp"

namespace cv {
namespace multicage {

using gpu::buildProgram;
using gpu::checkGl;
using gpu::glVersion;

namespace {

constexpr float kUncovered = -1e4f;  // the CPU backend's value for pixels no triangle covers

struct PixelFormat {
    GLenum internal, format, type;
    double scale;  // Scalar value -> what the shader writes (normalised formats)
};

// The image texture and the output FBO share a format matching the input depth. Three
// channels are stored as RGBA (RGB formats need not be colour-renderable) and read back as RGB.
PixelFormat pixelFormat(int type) {
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
    CV_Error_(Error::StsUnsupportedFormat,
              ("multicage: unsupported image type %s; use CV_8U, CV_16U or CV_32F with 1, 3 or 4 "
               "channels",
               typeToString(type).c_str()));
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

double msSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

struct GLDeformer::Impl {
    Binding binding;
    bool coefficientsOnCpu = true;
    bool half = false;
    PackLayout layout;
    int imageType = 0;
    PixelFormat fmt{};
    GLuint imageProgram = 0, mapsProgram = 0, vao = 0, indices = 0;
    GLuint coefficients = 0, pose = 0, image = 0, output = 0, maps = 0, outputFbo = 0, mapsFbo = 0;
    GLsizei indexCount = 0;
    Timings timings;

    Size size() const { return binding.imageSize; }
    GLenum coefficientTarget() const {
        return layout.layers > 1 ? GL_TEXTURE_2D_ARRAY : GL_TEXTURE_2D;
    }

    void init(const Mat& img, const GLDeformerParams& params) {
        if (glVersion() < 43)
            CV_Error(Error::GpuNotSupported, "multicage: GLDeformer needs an OpenGL 4.3 context");
        half = params.halfFloat;
        GLint maxTexture = 0, maxLayers = 0;
        glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTexture);
        glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &maxLayers);
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

        pose = makeTexture(GL_TEXTURE_1D);
        glTexStorage1D(GL_TEXTURE_1D, 1, GL_RGBA32F, 2 * layout.blocks);

        imageType = img.type();
        fmt = pixelFormat(imageType);
        image = makeTexture(GL_TEXTURE_2D);
        glTexStorage2D(GL_TEXTURE_2D, 1, fmt.internal, img.cols, img.rows);
        upload(img);

        // One mesh vertex per node plus a ring of vertices on the image frame around them
        // (deform.vert); per cell (a,b,c) then (b,d,c), row-major, as the CPU backend draws
        // them, so that fold-overs resolve the same way (later triangle wins).
        const int m = binding.gridSize.width, n = binding.gridSize.height;
        const int em = m + 2, en = n + 2;
        std::vector<GLuint> idx;
        idx.reserve(size_t(em - 1) * (en - 1) * 6);
        for (int gy = 0; gy + 1 < en; ++gy)
            for (int gx = 0; gx + 1 < em; ++gx) {
                const GLuint a = gy * em + gx, b = a + 1, c = a + em, d = c + 1;
                idx.insert(idx.end(), {a, b, c, b, d, c});
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

        // The per-multicage shader (paper §4): the constants of this binding and layout.
        const auto t = std::chrono::steady_clock::now();
        const std::string defines = cv::format(
            "#define GRID_W %d\n#define GRID_H %d\n#define GRID_STEP %d\n#define IMAGE_W %d\n"
            "#define IMAGE_H %d\n#define BLOCKS %d\n#define BLOCK_COLS %d\n"
            "#define BLOCKS_PER_LAYER %d\n#define LAYERED %d\n#define COEFFICIENTS %d\n",
            m, n, binding.gridStep, binding.imageSize.width, binding.imageSize.height,
            layout.blocks, layout.cols, layout.blocksPerLayer(), layout.layers > 1 ? 1 : 0,
            binding.coefficientCount());
        imageProgram = buildProgram(defines, "deform.vert", "deform_image.frag");
        mapsProgram = buildProgram(defines, "deform.vert", "deform_maps.frag");
        timings.shaderBuild = msSince(t);
        setPose(std::vector<Point2f>(binding.restVertices));
    }

    void uploadCoefficients() {
        const auto t = std::chrono::steady_clock::now();
        Mat packed;
        packCoefficients(binding, layout, packed, half ? CV_16F : CV_32F);
        glBindTexture(coefficientTarget(), coefficients);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
        glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
        const GLenum type = half ? GL_HALF_FLOAT : GL_FLOAT;
        if (layout.layers > 1)
            glTexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, 0, 0, 0, layout.textureSize.width,
                            layout.textureSize.height, layout.layers, GL_RGBA, type, packed.data);
        else
            glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, layout.textureSize.width,
                            layout.textureSize.height, GL_RGBA, type, packed.data);
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
        std::vector<Vec4f> delta(2 * layout.blocks, Vec4f::all(0.f));  // v'_j - v_j, 2 per texel
        for (size_t j = 0; j < p.size(); ++j) {
            const Point2f d = p[j] - binding.restVertices[j];
            delta[j / 2][2 * (j % 2)] = d.x;
            delta[j / 2][2 * (j % 2) + 1] = d.y;
        }
        glBindTexture(GL_TEXTURE_1D, pose);
        glTexSubImage1D(GL_TEXTURE_1D, 0, 0, 2 * layout.blocks, GL_RGBA, GL_FLOAT, delta.data());
        checkGl("uploading the pose");
    }

    void draw(GLuint program, bool flipY) {
        const float W = static_cast<float>(size().width), H = static_cast<float>(size().height);
        glUseProgram(program);
        // pixel centre x -> (x + 0.5) / W in [0, 1] -> clip [-1, 1]
        glUniform4f(0, 2.f / W, flipY ? -2.f / H : 2.f / H, 1.f / W - 1.f,
                    flipY ? 1.f - 1.f / H : 1.f / H - 1.f);
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(coefficientTarget(), coefficients);
        glActiveTexture(GL_TEXTURE1);
        glBindTexture(GL_TEXTURE_1D, pose);
        glActiveTexture(GL_TEXTURE2);
        glBindTexture(GL_TEXTURE_2D, image);
        glActiveTexture(GL_TEXTURE0);
        glDisable(GL_BLEND);
        glDisable(GL_DEPTH_TEST);
        glDisable(GL_CULL_FACE);  // folded triangles are drawn like the CPU backend draws them
        glDisable(GL_SCISSOR_TEST);
        glBindVertexArray(vao);
        glDrawElements(GL_TRIANGLES, indexCount, GL_UNSIGNED_INT, nullptr);
        glBindVertexArray(0);
        checkGl("drawing the deformed mesh");
    }

    void ensureOutput() {
        if (outputFbo) return;
        output = makeTexture(GL_TEXTURE_2D);
        glTexStorage2D(GL_TEXTURE_2D, 1, fmt.internal, size().width, size().height);
        outputFbo = makeFramebuffer(output, "output");
    }

    void ensureMaps() {
        if (mapsFbo) return;
        maps = makeTexture(GL_TEXTURE_2D);
        glTexStorage2D(GL_TEXTURE_2D, 1, GL_RG32F, size().width, size().height);
        mapsFbo = makeFramebuffer(maps, "maps");
    }

    void release() {
        const GLuint programs[] = {imageProgram, mapsProgram};
        for (GLuint p : programs)
            if (p) glDeleteProgram(p);
        const GLuint textures[] = {coefficients, pose, image, output, maps};
        glDeleteTextures(5, textures);
        const GLuint fbos[] = {outputFbo, mapsFbo};
        glDeleteFramebuffers(2, fbos);
        glDeleteBuffers(1, &indices);
        glDeleteVertexArrays(1, &vao);
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
    impl_->draw(impl_->imageProgram, flipY);
}

unsigned GLDeformer::render(const Scalar& border) {
    impl_->ensureOutput();
    glBindFramebuffer(GL_FRAMEBUFFER, impl_->outputFbo);
    glViewport(0, 0, impl_->size().width, impl_->size().height);
    const float clear[4] = {
        float(border[0] * impl_->fmt.scale), float(border[1] * impl_->fmt.scale),
        float(border[2] * impl_->fmt.scale), float(border[3] * impl_->fmt.scale)};
    glClearBufferfv(GL_COLOR, 0, clear);
    impl_->draw(impl_->imageProgram, false);
    return impl_->output;
}

unsigned GLDeformer::renderMaps() {
    impl_->ensureMaps();
    glBindFramebuffer(GL_FRAMEBUFFER, impl_->mapsFbo);
    glViewport(0, 0, impl_->size().width, impl_->size().height);
    const float clear[4] = {kUncovered, kUncovered, 0.f, 0.f};
    glClearBufferfv(GL_COLOR, 0, clear);
    impl_->draw(impl_->mapsProgram, false);
    return impl_->maps;
}

void GLDeformer::readOutput(OutputArray dst) {
    impl_->ensureOutput();
    dst.create(impl_->size(), impl_->imageType);
    Mat out = dst.getMat();
    CV_Assert(out.isContinuous());
    glBindFramebuffer(GL_READ_FRAMEBUFFER, impl_->outputFbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glPixelStorei(GL_PACK_ROW_LENGTH, 0);
    // Row 0 of the Mat is the framebuffer's bottom row, where render() put image row 0.
    glReadPixels(0, 0, out.cols, out.rows, impl_->fmt.format, impl_->fmt.type, out.data);
    gpu::checkGl("reading the deformed image back");
}

void GLDeformer::readMaps(OutputArray mapx, OutputArray mapy) {
    impl_->ensureMaps();
    Mat xy(impl_->size(), CV_32FC2);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, impl_->mapsFbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glPixelStorei(GL_PACK_ROW_LENGTH, 0);
    glReadPixels(0, 0, xy.cols, xy.rows, GL_RG, GL_FLOAT, xy.data);
    gpu::checkGl("reading the maps back");
    mapx.create(xy.size(), CV_32F);
    mapy.create(xy.size(), CV_32F);
    Mat planes[] = {mapx.getMat(), mapy.getMat()};
    split(xy, planes);
}

unsigned GLDeformer::outputTexture() const {
    return impl_->output;
}
unsigned GLDeformer::mapsTexture() const {
    return impl_->maps;
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

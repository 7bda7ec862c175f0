#include "gl_binding.hpp"

#include <chrono>
#include <opencv2/multicage/internal/backend_contract.hpp>
#include <tuple>

namespace cv {
namespace multicage {
namespace gpu {

namespace {

void replaceAll(std::string& s, const std::string& from, const std::string& to) {
    for (size_t at = 0; (at = s.find(from, at)) != std::string::npos; at += to.size())
        s.replace(at, from.size(), to);
}

// The shader with its template kernel instantiated in float and in double.
std::string instantiate(std::string source) {
    const std::string begin = "//@template-begin", end = "//@template-end";
    const size_t b = source.find(begin), e = source.find(end);
    CV_Assert(b != std::string::npos && e != std::string::npos && b < e);
    const std::string kernel = source.substr(b + begin.size(), e - b - begin.size());
    std::string f = kernel, d = kernel;
    for (auto [s, real2, real, exact, prec] :
         {std::make_tuple(&f, "vec2", "float", "false", "_f"),
          std::make_tuple(&d, "dvec2", "double", "true", "_d")}) {
        replaceAll(*s, "REAL2", real2);
        replaceAll(*s, "REAL", real);
        replaceAll(*s, "EXACT", exact);
        replaceAll(*s, "_PREC", prec);
    }
    return source.substr(0, b) + f + d + source.substr(e + end.size());
}

}  // namespace

void bindMeanValue(const Multicage& multicage, const PackLayout& layout, GLuint texture, bool half,
                   Binding* b, double* shaderBuildMs) {
    const int c = b->coefficientCount(), m = b->gridSize.width, n = b->gridSize.height;
    // Vertices in coefficient order and each polygon's orientation sign, as bind() does.
    std::vector<Vec2f> vertices(b->restVertices.begin(), b->restVertices.end());
    std::vector<Vec4i> polygons;
    for (int p = 0; p < multicage.polygonCount(); ++p) {
        const int sign = orientationSign(multicage, p);
        polygons.emplace_back(multicage.polygonOffset(p),
                              static_cast<int>(multicage.polygon(p).size()), sign, 0);
    }
    polygons.emplace_back(c - 4, 4, 1, 0);  // the frame: depth 0, A > 0

    const std::string defines = cv::format(
        "#define GRID_W %d\n#define GRID_H %d\n#define GRID_STEP %d\n#define IMAGE_W %d\n"
        "#define IMAGE_H %d\n#define POLYGONS %d\n#define BLOCK_COLS %d\n#define BLOCKS_PER_LAYER "
        "%d\n#define LAYERED %d\n#define COEFF_FORMAT %s\n",
        m, n, b->gridStep, b->imageSize.width, b->imageSize.height,
        static_cast<int>(polygons.size()), layout.cols, layout.blocksPerLayer(),
        layout.layers > 1 ? 1 : 0, half ? "rgba16f" : "rgba32f");
    // Shaders come from shaders/, the float/double instantiation is done here.
    const auto t = std::chrono::steady_clock::now();
    const std::string source = instantiate(shaderSource("bind_mean_value.comp"));
    GLuint program = buildComputeProgramFromText(defines, source, "bind_mean_value.comp");
    if (shaderBuildMs)
        *shaderBuildMs +=
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();

    GLuint buffers[2], conditioning;
    glGenBuffers(2, buffers);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, buffers[0]);
    glBufferData(GL_SHADER_STORAGE_BUFFER, vertices.size() * sizeof(Vec2f), vertices.data(),
                 GL_STATIC_DRAW);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, buffers[1]);
    glBufferData(GL_SHADER_STORAGE_BUFFER, polygons.size() * sizeof(Vec4i), polygons.data(),
                 GL_STATIC_DRAW);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buffers[0]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, buffers[1]);
    glGenTextures(1, &conditioning);
    glBindTexture(GL_TEXTURE_2D, conditioning);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_R32F, m, n);
    glBindImageTexture(0, texture, 0, layout.layers > 1 ? GL_TRUE : GL_FALSE, 0, GL_WRITE_ONLY,
                       half ? GL_RGBA16F : GL_RGBA32F);
    glBindImageTexture(1, conditioning, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
    glUseProgram(program);
    checkGl("GPU binding setup");
    // Bands of rows: no single dispatch runs long enough to trip a display watchdog.
    const int rowsPerBand = std::max(8, (1 << 22) / std::max(1, m * c) / 8 * 8);
    for (int y = 0; y < n; y += rowsPerBand) {
        glUniform1i(0, y);
        glDispatchCompute((m + 7) / 8, (std::min(rowsPerBand, n - y) + 7) / 8, 1);
    }
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT |
                    GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    Mat kappa(n, m, CV_32F);
    glBindTexture(GL_TEXTURE_2D, conditioning);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glGetTexImage(GL_TEXTURE_2D, 0, GL_RED, GL_FLOAT, kappa.data);
    checkGl("GPU binding");
    double lo;
    Point at;
    minMaxLoc(kappa, &lo, nullptr, &at);
    b->minConditioning = std::min(lo, 1.0);
    b->worstNode = b->node(at.x, at.y);
    glDeleteTextures(1, &conditioning);
    glDeleteBuffers(2, buffers);
    deleteProgram(program);
}

}  // namespace gpu
}  // namespace multicage
}  // namespace cv

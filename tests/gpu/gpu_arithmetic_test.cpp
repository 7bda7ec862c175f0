// The arithmetic the compute pipeline's bit-exact agreement with the CPU rests on
// (mesh_positions.glsl, mesh_triangle.glsl): divisions rounded to nearest (division.glsl),
// `precise` sums of products that are not fused into multiply-adds, and a triangle set-up in
// true doubles. A GPU that breaks one fails here with the operation named, before the maps
// tests fail with pixels. The division and the set-up broke on an H100 (driver 580) before
// division.glsl and the dvec3 set-up; nothing breaks on llvmpipe (docs/gpu/README.md).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "gl_util.hpp"  // buildComputeProgramFromText, shaderSource (private to the gpu module)
#include "gpu_testing.hpp"

using namespace cv;
using namespace cv::multicage;

namespace {

const char* kBody = R"(
layout(std430, binding = 0) readonly buffer FloatsIn { vec4 fin[]; };
layout(std430, binding = 1) readonly buffer DoublesIn { dvec4 din[]; };
layout(std430, binding = 2) writeonly buffer FloatsOut { vec4 fout[]; };
layout(std430, binding = 3) writeonly buffer DoublesOut { dvec4 dout[]; };
void run(uint i) {
    const vec4 f = fin[i];
    precise float sum = f.z;  // the positions' sum, one product at a time
    sum += f.x * f.y;
    sum += f.w * f.x;
    fout[i] = vec4(divideRN(f.x, f.y), f.x / f.y, sum, 0.0);
    const dvec4 d = din[i];
    precise double cross = d.x * d.y - d.z * d.w;  // crossD
    dout[i] = dvec4(divideRN(d.x, d.y), d.x / d.y, cross, 0.0LF);
}
)";

GLuint storage(const void* data, size_t bytes, GLuint binding) {
    GLuint buffer = 0;
    glGenBuffers(1, &buffer);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, buffer);
    glBufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(bytes), data, GL_DYNAMIC_COPY);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, buffer);
    return buffer;
}

// Runs `program` once per item, n items (`count` at uniform location 0), and waits for its
// writes to the storage buffers.
void dispatch(GLuint program, size_t n) {
    glUseProgram(program);
    glUniform1ui(0, GLuint(n));
    glDispatchCompute(GLuint((n + 63) / 64), 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
}

// A compute program that runs body's `void run(uint item)` once per item (dispatch()), after
// `includes` (shader text), with `defines` after the #version line.
GLuint itemProgram(const std::string& defines, const std::string& includes, const char* body,
                   const char* name) {
    const std::string source =
        "#version 430 core\nlayout(local_size_x = 64) in;\n"
        "layout(location = 0) uniform uint count;\n" +
        includes + body +
        "void main() {\n"
        "    if (gl_GlobalInvocationID.x < count) run(gl_GlobalInvocationID.x);\n"
        "}\n";
    return gpu::buildComputeProgramFromText(defines, source, name);
}

template <typename T>
std::vector<T> readStorage(GLuint buffer, size_t n) {
    std::vector<T> out(n);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, buffer);
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, GLsizeiptr(n * sizeof(T)), out.data());
    return out;
}

// Each test runs its own programs in a headless context of its own (skipped without a GPU).
class GpuArithmetic : public ::testing::Test {
  protected:
    void SetUp() override {
        MULTICAGE_REQUIRE_GPU();
        context_ = std::make_unique<HeadlessGLContext>();
        scope_ = std::make_unique<HeadlessGLContext::Scope>(*context_);
    }
    void TearDown() override {
        scope_.reset();
        context_.reset();
    }

  private:
    std::unique_ptr<HeadlessGLContext> context_;
    std::unique_ptr<HeadlessGLContext::Scope> scope_;
};

// a * 2^e with a in [1, 2) and a random sign: floats and doubles of every mantissa.
template <typename T>
T randomValue(RNG& rng, int minExp, int maxExp) {
    T m = T(1) + T(rng.uniform(0.0, 1.0));
    if (sizeof(T) == 8) m += T(rng.uniform(0.0, 1.0)) * T(1.0 / (1 << 24));  // the low bits too
    const T v = std::ldexp(m, rng.uniform(minExp, maxExp + 1));
    return rng.uniform(0, 2) ? v : -v;
}

}  // namespace

// Random operands over 24 binades (float) and 60 (double), and the pipeline's own divisions.
// The plain `/` is counted for the record (GLSL lets it be inexact), not asserted.
TEST_F(GpuArithmetic, DivisionRoundsToNearestAndPreciseSumsAreNotFused) {
    // Random operands, then the divisions the pipeline makes: (x + 0.5) / W for ring vertices
    // and 1 / area for small integer areas.
    RNG rng(20261125);
    std::vector<Vec4f> floats;
    std::vector<Vec4d> doubles;
    for (int i = 0; i < 1 << 16; ++i) {
        floats.push_back({randomValue<float>(rng, -12, 12), randomValue<float>(rng, -12, 12),
                          randomValue<float>(rng, -4, 12), randomValue<float>(rng, -12, 12)});
        doubles.push_back({randomValue<double>(rng, -30, 30), randomValue<double>(rng, -30, 30),
                           randomValue<double>(rng, -30, 30), randomValue<double>(rng, -30, 30)});
    }
    for (int w = 1; w <= 4096; w += 1 + w / 64)
        for (int x = -1; x <= w; x += 1 + w / 16) {
            floats.push_back({float(x) + 0.5f, float(w), 0.f, 0.f});
            doubles.push_back({1.0, double(w * (x + 2)), 0.0, 0.0});  // 1 / area
        }
    const size_t n = floats.size();
    const GLuint program =
        itemProgram("", gpu::shaderSource("division.glsl"), kBody, "arithmetic test");
    GLuint buffers[4] = {
        storage(floats.data(), n * sizeof(Vec4f), 0), storage(doubles.data(), n * sizeof(Vec4d), 1),
        storage(nullptr, n * sizeof(Vec4f), 2), storage(nullptr, n * sizeof(Vec4d), 3)};
    dispatch(program, n);
    const std::vector<Vec4f> fout = readStorage<Vec4f>(buffers[2], n);
    const std::vector<Vec4d> dout = readStorage<Vec4d>(buffers[3], n);
    gpu::checkGl("arithmetic test");
    glDeleteBuffers(4, buffers);
    gpu::deleteProgram(program);

    int divideF = 0, plainF = 0, sumF = 0, divideD = 0, plainD = 0, crossD = 0;
    for (size_t i = 0; i < n; ++i) {
        const Vec4f& f = floats[i];
        const Vec4d& d = doubles[i];
        const float q = f[0] / f[1];
        float sum = f[2];
        sum += f[0] * f[1];
        sum += f[3] * f[0];
        const double qd = d[0] / d[1];
        const double products[2] = {d[0] * d[1], d[2] * d[3]};
        const double cross = products[0] - products[1];
        divideF += fout[i][0] != q, plainF += fout[i][1] != q, sumF += fout[i][2] != sum;
        if (dout[i][0] != qd && divideD < 5)
            std::printf("double %.17g / %.17g: %.17g, IEEE %.17g\n", d[0], d[1], dout[i][0], qd);
        divideD += dout[i][0] != qd, plainD += dout[i][1] != qd, crossD += dout[i][2] != cross;
    }
    std::printf(
        "%zu operand sets: divideRN differs from IEEE at %d (float) and %d (double); "
        "plain '/' at %d and %d; precise sums at %d, cross products at %d\n",
        n, divideF, divideD, plainF, plainD, sumF, crossD);
    EXPECT_EQ(divideF, 0);
    EXPECT_EQ(divideD, 0);
    EXPECT_EQ(sumF, 0);
    EXPECT_EQ(crossD, 0);
}

// divideRN's corrections move a quotient only where `/` is not exact, which neither llvmpipe
// nor NVIDIA's double `/` is: here they start from quotients 1 and 2 ulps off, on every GPU.
TEST_F(GpuArithmetic, DivisionStepsToTheNearestFromQuotientsUlpsOff) {
    RNG rng(1125);
    std::vector<Vec4d> in;
    std::vector<double> want;
    for (int i = 0; i < 1 << 14; ++i) {
        const double a = randomValue<double>(rng, -30, 30), b = randomValue<double>(rng, -30, 30);
        const double q = a / b;
        for (int off : {-2, -1, 1, 2}) {
            double start = q;
            for (int k = 0; k < std::abs(off); ++k)
                start = std::nextafter(start, off > 0 ? INFINITY : -INFINITY);
            in.push_back({a, b, start, 0.0});
            want.push_back(q);
        }
    }
    const char* body = R"(
layout(std430, binding = 0) readonly buffer In { dvec4 operands[]; };
layout(std430, binding = 1) writeonly buffer Out { double quotients[]; };
void run(uint i) {
    quotients[i] = divideRNFrom(operands[i].x, operands[i].y, operands[i].z);
}
)";
    const GLuint program =
        itemProgram("", gpu::shaderSource("division.glsl"), body, "division steps test");
    const size_t n = in.size();
    GLuint buffers[2] = {storage(in.data(), n * sizeof(Vec4d), 0),
                         storage(nullptr, n * sizeof(double), 1)};
    dispatch(program, n);
    const std::vector<double> got = readStorage<double>(buffers[1], n);
    gpu::checkGl("division steps test");
    glDeleteBuffers(2, buffers);
    gpu::deleteProgram(program);
    int differ = 0;
    for (size_t i = 0; i < n; ++i) differ += got[i] != want[i];
    std::printf("%zu quotients started 1 or 2 ulps off: %d not stepped to the nearest\n", n,
                differ);
    EXPECT_EQ(differ, 0);
}

namespace {

const char* kSetUpBody = R"(
layout(std430, binding = 1) writeonly buffer SetUps { double setUps[]; };  // 10 per triangle
void run(uint t) {
    Triangle tri;
    const bool ok = loadTriangle(t, tri) && setUpTriangle(tri);
    const dvec3 ax = ok ? tri.ax : dvec3(0.0LF), ay = ok ? tri.ay : dvec3(0.0LF),
                a0 = ok ? tri.a0 : dvec3(0.0LF);
    setUps[10 * t] = ax.x, setUps[10 * t + 1] = ay.x, setUps[10 * t + 2] = a0.x;
    setUps[10 * t + 3] = ax.y, setUps[10 * t + 4] = ay.y, setUps[10 * t + 5] = a0.y;
    setUps[10 * t + 6] = ax.z, setUps[10 * t + 7] = ay.z, setUps[10 * t + 8] = a0.z;
    setUps[10 * t + 9] = ok ? 1.0LF : 0.0LF;
}
)";

// The CPU rasteriser's set-up of one triangle (raster_kernels.hpp, setUpTriangles).
void cpuSetUp(const Point2f q[3], double out[10]) {
    const double q0x = q[0].x, q0y = q[0].y, q1x = q[1].x, q1y = q[1].y, q2x = q[2].x, q2y = q[2].y;
    const double area = (q1x - q0x) * (q2y - q0y) - (q1y - q0y) * (q2x - q0x);
    std::fill_n(out, 10, 0.0);
    if (!(std::abs(area) > 1e-12)) return;
    const double inv = 1.0 / area;
    const double ex[3][2] = {{q1x, q2x}, {q2x, q0x}, {q0x, q1x}};
    const double ey[3][2] = {{q1y, q2y}, {q2y, q0y}, {q0y, q1y}};
    for (int i = 0; i < 3; ++i) {
        out[3 * i] = (ey[i][0] - ey[i][1]) * inv;
        out[3 * i + 1] = (ex[i][1] - ex[i][0]) * inv;
        out[3 * i + 2] = (ex[i][0] * ey[i][1] - ey[i][0] * ex[i][1]) * inv;
    }
    out[9] = 1.0;
}

}  // namespace

// mesh_triangle.glsl's set-up of every triangle of a real mesh (the GPU's own, read back)
// against the CPU rasteriser's: the barycentric functions must be the same doubles.
TEST_F(GpuArithmetic, TriangleSetUpIsTheCpus) {
    Mat image(119, 161, CV_8UC3, Scalar(90, 120, 150));
    const Multicage cage = multicage_fixtures::lotusMulticage(image.size(), 16);
    const int step = 3;
    const Binding b = bind(cage, MEAN_VALUE, step);
    GLDeformer deformer(image, b);
    for (const std::vector<Point2f>& pose :
         {b.restVertices, multicage_fixtures::wavePose(cage, 8.f, 0.3f)}) {
        deformer.setPose(pose);
        deformer.renderMaps();
        Mat mesh;
        deformer.readMesh(mesh);
        const int cellsW = mesh.cols - 1, cellsH = mesh.rows - 1, triangles = 2 * cellsW * cellsH;
        const std::string defines = format(
            "#define GRID_W %d\n#define GRID_H %d\n#define GRID_STEP %d\n#define IMAGE_W %d\n"
            "#define IMAGE_H %d\n",
            b.gridSize.width, b.gridSize.height, step, image.cols, image.rows);
        const GLuint program = itemProgram(
            defines,
            gpu::shaderSource("mesh_grid.glsl") +
                "layout(std430, binding = 0) readonly buffer Positions { vec2 positions[]; };\n" +
                gpu::shaderSource("mesh_triangle.glsl"),
            kSetUpBody, "set-up test");
        GLuint buffers[2] = {storage(mesh.ptr(), mesh.total() * sizeof(Point2f), 0),
                             storage(nullptr, size_t(triangles) * 10 * sizeof(double), 1)};
        dispatch(program, size_t(triangles));
        const std::vector<double> gpuSetUps =
            readStorage<double>(buffers[1], size_t(triangles) * 10);
        gpu::checkGl("set-up test");
        glDeleteBuffers(2, buffers);
        gpu::deleteProgram(program);
        int differ = 0;
        for (int t = 0; t < triangles; ++t) {
            const int row = t / (2 * cellsW), i = t % (2 * cellsW), cx = i / 2;
            const Point2f a = mesh.at<Point2f>(row, cx), bb = mesh.at<Point2f>(row, cx + 1),
                          c = mesh.at<Point2f>(row + 1, cx), d = mesh.at<Point2f>(row + 1, cx + 1);
            const Point2f q[3] = {i % 2 == 0 ? a : bb, i % 2 == 0 ? bb : d, c};
            double want[10];
            cpuSetUp(q, want);
            const double* got = &gpuSetUps[size_t(t) * 10];
            if (std::equal(want, want + 10, got)) continue;
            if (differ < 3)
                for (int k = 0; k < 10; ++k)
                    if (got[k] != want[k])
                        std::printf("  triangle %d (cell %d, %d), value %d: GPU %.17g, CPU %.17g\n",
                                    t, cx, row, k, got[k], want[k]);
            ++differ;
        }
        std::printf("%d of %d triangles set up otherwise than on the CPU\n", differ, triangles);
        EXPECT_EQ(differ, 0);
    }
}

// Mean value binding in a compute shader (Algorithm 1) against the CPU bind().
#include "gpu_testing.hpp"

using namespace cv;
using namespace cv::multicage;
using namespace multicage_testing;

static void expectSameBinding(const Multicage& cage, int gridStep, const char* what) {
    const Binding cpu = bind(cage, MEAN_VALUE, gridStep);
    const Binding gpu = bindOnGpu(cage, gridStep);
    ASSERT_EQ(gpu.coefficients.size(), cpu.coefficients.size());
    ASSERT_EQ(gpu.gridSize, cpu.gridSize);
    const double diff = norm(gpu.coefficients, cpu.coefficients, NORM_INF);
    std::printf("%s: GPU vs CPU binding, max abs coefficient difference %.2e (%d x %d)\n", what,
                diff, cpu.coefficients.rows, cpu.coefficients.cols);
    EXPECT_LE(diff, 1e-4);
    EXPECT_NEAR(gpu.minConditioning, cpu.minConditioning, 1e-3);
    // Partition of unity holds on the GPU too.
    Mat sums;
    reduce(gpu.coefficients, sums, 0, REDUCE_SUM);
    double lo, hi;
    minMaxLoc(sums, &lo, &hi);
    EXPECT_NEAR(lo, 1.0, 1e-4);
    EXPECT_NEAR(hi, 1.0, 1e-4);
}

TEST(GpuBinding, EqualsCpuOnButterfly) {
    MULTICAGE_REQUIRE_GPU();
    // Integer vertices: many nodes lie exactly on vertices and on axis-aligned or diagonal
    // edges, so the exact vertex/edge policy runs on the GPU too.
    expectSameBinding(butterflyCage(true), 1, "butterfly, nested");
}

TEST(GpuBinding, EqualsCpuOnLotusAndRandomMulticages) {
    MULTICAGE_REQUIRE_GPU();
    expectSameBinding(multicage_fixtures::lotusMulticage(Size(1024, 768), 68), 4,
                      "lotus 1024x768/68");
    RNG rng(42);
    for (int i = 0; i < 3; ++i) {
        const Multicage cage = multicage_fixtures::randomMulticage(rng, Size(300, 220), 3, 3, 10);
        expectSameBinding(cage, 1, "random multicage");
    }
}

TEST(GpuBinding, ExactOnEdgesAndVertices) {
    MULTICAGE_REQUIRE_GPU();
    // A square whose edges run along node rows and columns, and a clockwise/anti-clockwise
    // nesting: nodes on the edges must follow the edge alone.
    Multicage cage(Size(64, 48));
    cage.addPolygon(std::vector<Point2f>{{10, 10}, {50, 10}, {50, 40}, {10, 40}});
    cage.addPolygon(std::vector<Point2f>{{20, 20}, {40, 20}, {30, 32}});
    cage.orient();
    expectSameBinding(cage, 1, "square + triangle");
    const Binding gpu = bindOnGpu(cage, 1);
    // Node (30, 10) is the midpoint of the top edge (10,10)-(50,10).
    const int node = 10 * 64 + 30;
    const std::vector<Point2f> v = cage.vertices();
    float sum = 0;
    for (int j = 0; j < gpu.coefficientCount(); ++j) {
        const float w = gpu.coefficients.at<float>(j, node);
        sum += w;
        if (v[j] == Point2f(10, 10) || v[j] == Point2f(50, 10))
            EXPECT_FLOAT_EQ(w, 0.5f);
        else
            EXPECT_EQ(w, 0.f) << "coefficient " << j;
    }
    EXPECT_FLOAT_EQ(sum, 1.f);
}

TEST(GpuBinding, DeformerWithGpuBindingMatchesCpuBinding) {
    MULTICAGE_REQUIRE_GPU();
    const Mat image = readSample("butterfly.jpg");
    const Multicage cage = butterflyCage(true);
    DeformParams params;
    params.backend = BACKEND_GPU;
    params.gpuBinding = true;
    params.gridStep = 2;
    Ptr<Deformer> gpu = Deformer::create(image, cage, params);
    ASSERT_EQ(gpu->backend(), BACKEND_GPU);
    const Binding cpuBinding = bind(cage, MEAN_VALUE, 2);
    EXPECT_LE(norm(gpu->binding().coefficients, cpuBinding.coefficients, NORM_INF), 1e-4);
    params.backend = BACKEND_CPU;
    Ptr<Deformer> cpu = Deformer::create(image, cage, params);
    const std::vector<Point2f> pose = multicage_fixtures::stretchPolygon(cage, 0, 1.1f, 0.9f);
    Mat g, c;
    gpu->deform(pose, g);
    cpu->deform(pose, c);
    EXPECT_GE(psnr(g, c), 40.0);
}

// A library configured with MULTICAGE_WITH_GPU=OFF (built in place of the GPU tests): the GPU
// API is all there and says why nothing runs on a GPU; BACKEND_GPU is refused with that
// reason, BACKEND_AUTO deforms on the CPU exactly as BACKEND_CPU does.
#include <opencv2/imgproc.hpp>
#include <opencv2/multicage/deformer.hpp>
#include <opencv2/multicage/gpu.hpp>

#include "fixtures.hpp"
#include "testing.hpp"

static_assert(MULTICAGE_HAVE_GPU == 0, "without_gpu_test.cpp is for MULTICAGE_WITH_GPU=OFF");

using namespace cv;
using namespace cv::multicage;

namespace {

const std::string kWhy = "built without GPU support (MULTICAGE_WITH_GPU=OFF)";

struct Scene {
    Mat image;
    Multicage cage;
    std::vector<Point2f> pose;
};

Scene scene() {
    Scene s;
    resize(multicage_testing::readSample("fruits.jpg"), s.image, Size(96, 72), 0, 0, INTER_AREA);
    s.cage = multicage_fixtures::lotusMulticage(s.image.size(), 20);
    s.pose = multicage_fixtures::wavePose(s.cage, 5.f, 0.3f);
    return s;
}

// Runs f, which must throw a cv::Exception with code `code` whose message holds `message`.
template <typename F>
void expectRefused(F f, int code, const std::string& message, const char* what) {
    try {
        f();
        ADD_FAILURE() << what << ": did not throw";
    } catch (const Exception& e) {
        EXPECT_EQ(e.code, code) << what << ": " << e.err;
        EXPECT_NE(e.err.find(message), std::string::npos) << what << ": " << e.err;
    }
}

}  // namespace

TEST(WithoutGpu, GpuIsUnavailableWithTheReason) {
    std::string description = "unchanged";
    EXPECT_FALSE(gpuAvailable(&description));
    EXPECT_EQ(description, kWhy);
    EXPECT_FALSE(autoBackendUsesGpu(&description));
    EXPECT_EQ(description, kWhy);
    std::string why;
    EXPECT_EQ(HeadlessGLContext::shared(&why), nullptr);
    EXPECT_EQ(why, kWhy);
    EXPECT_EQ(HeadlessGLContext::shared(), nullptr);
    EXPECT_FALSE(gpuAvailable());
}

TEST(WithoutGpu, BackendGpuIsRefusedWithTheReason) {
    const Scene s = scene();
    const Binding binding = bind(s.cage, MEAN_VALUE, 4);
    const std::string message = "multicage: BACKEND_GPU requested but " + kWhy;
    for (int gpuBinding : {-1, 0, 1}) {
        DeformParams p;
        p.backend = BACKEND_GPU;
        p.gridStep = 4;
        p.gpuBinding = gpuBinding;
        expectRefused([&] { Deformer::create(s.image, s.cage, p); }, Error::StsNotImplemented,
                      message, "create from a multicage");
        expectRefused([&] { Deformer::create(s.image, binding, p); }, Error::StsNotImplemented,
                      message, "create from a binding");
        expectRefused([&] { deformImage(s.image, s.cage, s.pose, noArray(), p); },
                      Error::StsNotImplemented, message, "deformImage");
    }
}

TEST(WithoutGpu, AutoDeformsOnTheCpuAsBackendCpuDoes) {
    const Scene s = scene();
    DeformParams cpu;
    cpu.backend = BACKEND_CPU;
    cpu.gridStep = 4;
    Mat want, wantX, wantY;
    Deformer::create(s.image, s.cage, cpu)->deform(s.pose, want);
    Deformer::create(s.image, s.cage, cpu)->computeMaps(s.pose, wantX, wantY);
    for (int gpuBinding : {-1, 0, 1}) {  // 1 asks for a GPU binding: AUTO binds on the CPU
        DeformParams p = cpu;
        p.backend = BACKEND_AUTO;
        p.gpuBinding = gpuBinding;
        Ptr<Deformer> d = Deformer::create(s.image, s.cage, p);
        ASSERT_EQ(d->backend(), BACKEND_CPU) << "gpuBinding " << gpuBinding;
        Mat got, gotX, gotY;
        d->deform(s.pose, got);
        d->computeMaps(s.pose, gotX, gotY);
        EXPECT_TRUE(multicage_testing::sameBits(got, want)) << "gpuBinding " << gpuBinding;
        EXPECT_TRUE(multicage_testing::sameBits(gotX, wantX)) << "gpuBinding " << gpuBinding;
        EXPECT_TRUE(multicage_testing::sameBits(gotY, wantY)) << "gpuBinding " << gpuBinding;
    }
    Mat viaFunction;
    DeformParams p = cpu;
    p.backend = BACKEND_AUTO;
    deformImage(s.image, s.cage, s.pose, viaFunction, p);
    EXPECT_TRUE(multicage_testing::sameBits(viaFunction, want));
}

TEST(WithoutGpu, ContextsGLDeformersAndGpuBindingThrowTheReason) {
    const Scene s = scene();
    const Binding binding = bind(s.cage, MEAN_VALUE, 4);
    const int code = Error::GpuNotSupported;
    expectRefused([] { HeadlessGLContext context; }, code,
                  "multicage: no headless OpenGL context: " + kWhy, "HeadlessGLContext");
    expectRefused([&] { GLDeformer d(s.image, binding); }, code, "multicage: GLDeformer: " + kWhy,
                  "GLDeformer from a binding");
    expectRefused([&] { GLDeformer d(s.image, s.cage, 4); }, code, "multicage: GLDeformer: " + kWhy,
                  "GLDeformer from a multicage");
    expectRefused([&] { bindOnGpu(s.cage, 4); }, code, "multicage: bindOnGpu: " + kWhy,
                  "bindOnGpu");
}

// Concurrency (issue 8, item 5): Deformers on different threads, each with its own state,
// give exactly what one thread gives. The GPU backend claims one EGL context per Deformer,
// made current around each call and released after (modules/gpu, docs/gpu/README.md); these
// tests check that claim from the outside.
#include <opencv2/imgproc.hpp>
#include <thread>

#include "gpu_testing.hpp"
#if MULTICAGE_HAVE_GPU  // multicage::multicage defines it; 0: no EGL to include
#include <epoxy/egl.h>
#endif

using namespace cv;
using namespace cv::multicage;
using multicage_testing::maxAbsDiff;
using multicage_testing::sameBits;

namespace {

struct Outputs {
    std::vector<Mat> images, mapx, mapy;
};

struct Scene {
    Mat image;
    Multicage cage;
    std::vector<std::vector<Point2f>> poses;
};

Scene scene(Size size) {
    Scene s;
    resize(multicage_testing::readSample("fruits.jpg"), s.image, size, 0, 0, INTER_AREA);
    s.cage = multicage_fixtures::lotusMulticage(size, 20);
    for (float amplitude : {3.f, 7.f, 12.f})
        s.poses.push_back(multicage_fixtures::wavePose(s.cage, amplitude, 0.3f));
    std::vector<Point2f> fold = s.cage.vertices();  // a fold-over pose too
    std::swap(fold[0], fold[2]);
    s.poses.push_back(fold);
    return s;
}

// Creates its own Deformer (binding included) and runs every pose, in `order`.
Outputs run(const Scene& s, const DeformParams& params, bool reverse) {
    Ptr<Deformer> d = Deformer::create(s.image, s.cage, params);
    EXPECT_EQ(d->backend(), params.backend);
    const size_t n = s.poses.size();
    Outputs o{std::vector<Mat>(n), std::vector<Mat>(n), std::vector<Mat>(n)};
    for (size_t k = 0; k < n; ++k) {
        const size_t i = reverse ? n - 1 - k : k;
        d->deform(s.poses[i], o.images[i]);
        d->computeMaps(s.poses[i], o.mapx[i], o.mapy[i]);
    }
    return o;
}

void expectSame(const Outputs& got, const Outputs& want, const char* who) {
    ASSERT_EQ(got.images.size(), want.images.size());
    for (size_t i = 0; i < want.images.size(); ++i) {
        EXPECT_TRUE(sameBits(got.images[i], want.images[i]))
            << who << ", pose " << i << ": image differs by up to "
            << maxAbsDiff(got.images[i], want.images[i]);
        EXPECT_TRUE(sameBits(got.mapx[i], want.mapx[i]))
            << who << ", pose " << i << ": mapx differs";
        EXPECT_TRUE(sameBits(got.mapy[i], want.mapy[i]))
            << who << ", pose " << i << ": mapy differs";
    }
}

DeformParams params(int backend) {
    DeformParams p;
    p.backend = backend;
    return p;
}

void twoThreadsMatchOne(int backend, Size size) {
    const Scene s = scene(size);
    const Outputs reference = run(s, params(backend), false);
    Outputs results[2];
    std::thread threads[2];
    for (int t = 0; t < 2; ++t)
        threads[t] = std::thread([&, t] { results[t] = run(s, params(backend), t == 1); });
    for (std::thread& t : threads) t.join();
    expectSame(results[0], reference, "thread 0");
    expectSame(results[1], reference, "thread 1 (poses in reverse order)");
}

}  // namespace

TEST(Concurrency, TwoCpuDeformersOnTwoThreadsMatchOneThreadBitForBit) {
    twoThreadsMatchOne(BACKEND_CPU, Size(160, 120));
}

TEST(Concurrency, TwoGpuDeformersOnTwoThreadsMatchOneThreadBitForBit) {
    MULTICAGE_REQUIRE_GPU();
    twoThreadsMatchOne(BACKEND_GPU, Size(96, 72));
}

// A GPU and a CPU Deformer at the same time: each gives what it gives alone.
TEST(Concurrency, GpuAndCpuDeformersSideBySide) {
    MULTICAGE_REQUIRE_GPU();
    const Scene s = scene(Size(96, 72));
    const Outputs gpu = run(s, params(BACKEND_GPU), false),
                  cpu = run(s, params(BACKEND_CPU), false);
    Outputs results[2];
    std::thread a([&] { results[0] = run(s, params(BACKEND_GPU), true); });
    std::thread b([&] { results[1] = run(s, params(BACKEND_CPU), true); });
    a.join();
    b.join();
    expectSame(results[0], gpu, "GPU thread");
    expectSame(results[1], cpu, "CPU thread");
}

// "May be used from any thread, one thread at a time": made on this thread, used on two
// others in turn, destroyed on a third.
TEST(Concurrency, GpuDeformerHandedFromThreadToThread) {
    MULTICAGE_REQUIRE_GPU();
    const Scene s = scene(Size(96, 72));
    const Outputs reference = run(s, params(BACKEND_GPU), false);
    Ptr<Deformer> d = Deformer::create(s.image, s.cage, params(BACKEND_GPU));
    Mat out[2];
    for (int t = 0; t < 2; ++t) std::thread([&, t] { d->deform(s.poses[t], out[t]); }).join();
    EXPECT_TRUE(sameBits(out[0], reference.images[0]));
    EXPECT_TRUE(sameBits(out[1], reference.images[1]));
    std::thread([&] { d.release(); }).join();
    EXPECT_TRUE(d.empty());
}

// Each call makes the Deformer's own context current and restores what was current before:
// nothing on a plain thread, the application's context inside its scope.
TEST(Concurrency, GpuDeformerRestoresTheCallersContext) {
#if !MULTICAGE_HAVE_GPU
    GTEST_SKIP() << "built without GPU support (MULTICAGE_WITH_GPU=OFF)";
#else
    MULTICAGE_REQUIRE_GPU();
    const Scene s = scene(Size(64, 48));
    Ptr<Deformer> d = Deformer::create(s.image, s.cage, params(BACKEND_GPU));
    Mat out;
    d->deform(s.poses[0], out);
    eglBindAPI(EGL_OPENGL_API);
    EXPECT_EQ(eglGetCurrentContext(), EGL_NO_CONTEXT) << "a Deformer left its context current";
    HeadlessGLContext app;
    HeadlessGLContext::Scope scope(app);
    const EGLContext mine = eglGetCurrentContext();
    ASSERT_NE(mine, EGL_NO_CONTEXT);
    Ptr<Deformer> inside = Deformer::create(s.image, s.cage, params(BACKEND_GPU));
    inside->deform(s.poses[0], out);
    Mat mapx, mapy;
    d->computeMaps(s.poses[1], mapx, mapy);
    EXPECT_EQ(eglGetCurrentContext(), mine) << "the application's context was not restored";
#endif
}

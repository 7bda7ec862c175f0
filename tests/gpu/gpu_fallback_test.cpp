// Where no EGL context can be made: BACKEND_AUTO falls back to the CPU, BACKEND_GPU throws
// saying why. The headless display is chosen once per process, so the no-EGL case runs in a
// child process of this test executable with libglvnd pointed at no vendor library.
#include <cstdlib>
#include <filesystem>

#include "gpu_testing.hpp"

using namespace cv;
using namespace cv::multicage;

static const char* kNoVendor = "__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent/multicage_no_egl.json";

// Runs only as that child (disabled, so neither gtest nor CTest runs it on its own).
TEST(GpuFallback, DISABLED_ChildWithoutEgl) {
    const char* v = std::getenv("__EGL_VENDOR_LIBRARY_FILENAMES");
    if (!v || std::string(v).find("multicage_no_egl") == std::string::npos)
        GTEST_SKIP() << "runs as the child of GpuFallback.NoEglMeansCpuOrAnError";
    std::string why;
    ASSERT_FALSE(gpuAvailable(&why));
    EXPECT_FALSE(why.empty());
    const Mat image(60, 80, CV_8UC3, Scalar(1, 2, 3));
    Multicage cage(image.size());
    cage.addPolygon(std::vector<Point2f>{{20, 20}, {60, 20}, {60, 40}, {20, 40}});
    cage.orient();
    DeformParams params;  // BACKEND_AUTO
    EXPECT_EQ(Deformer::create(image, cage, params)->backend(), BACKEND_CPU);
    params.backend = BACKEND_GPU;
    try {
        Deformer::create(image, cage, params);
        ADD_FAILURE() << "BACKEND_GPU without EGL did not throw";
    } catch (const cv::Exception& e) {
        EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
    }
    EXPECT_THROW(HeadlessGLContext(), cv::Exception);
}

TEST(GpuFallback, NoEglMeansCpuOrAnError) {
    const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
    const std::string cmd =
        std::string(kNoVendor) + " '" + self +
        "' --gtest_also_run_disabled_tests --gtest_filter=GpuFallback.DISABLED_ChildWithoutEgl "
        "> /dev/null 2>&1";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << "the child test failed: run " << cmd;
}

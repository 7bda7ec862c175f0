// Memory budget: the coefficients are estimated before binding, and the grid step is raised
// (or an error names what would fit) when they would not fit.
#include <sys/resource.h>

#include "testing.hpp"

using namespace cv;
using namespace cv::multicage;

TEST(MemoryBudget, EstimateMatchesTheBinding) {
    const Multicage cage = multicage_fixtures::lotusMulticage(Size(300, 200), 20);
    for (int step : {1, 2, 5}) {
        const Binding b = bind(cage, MEAN_VALUE, step);
        EXPECT_EQ(bindingMemory(cage.imageSize(), 24, step),
                  b.coefficients.total() * sizeof(float));
    }
    const size_t budget = bindingMemory(cage.imageSize(), 24, 3);
    EXPECT_EQ(gridStepForBudget(cage.imageSize(), 24, budget), 3);
    EXPECT_EQ(gridStepForBudget(cage.imageSize(), 24, budget - 1), 4);
    EXPECT_EQ(gridStepForBudget(cage.imageSize(), 24, 0, 2), 2);
}

TEST(MemoryBudget, OverBudgetWithoutAutoStepNamesWhatFits) {
    const Mat image(600, 800, CV_8UC3, Scalar::all(128));
    const Multicage cage = multicage_fixtures::lotusMulticage(image.size(), 40);
    DeformParams params;
    params.backend = BACKEND_CPU;
    params.memoryBudget = 25u << 20;  // 25 MiB: step 1 needs 81 MiB, step 2 20 MiB
    params.autoGridStep = false;
    try {
        Deformer::create(image, cage, params);
        FAIL() << "no error over budget";
    } catch (const cv::Exception& e) {
        EXPECT_NE(e.err.find("needs 81 MiB of coefficients at grid step 1"), std::string::npos)
            << e.err;
        EXPECT_NE(e.err.find("grid step 2 fits (20 MiB)"), std::string::npos) << e.err;
    }
    params.autoGridStep = true;
    Ptr<Deformer> d = Deformer::create(image, cage, params);
    EXPECT_EQ(d->binding().gridStep, 2);
}

TEST(MemoryBudget, Image8192SquaredWith128VerticesStaysWithin4GiB) {
    const Mat image(8192, 8192, CV_8UC3, Scalar(40, 90, 160));
    const Multicage cage = multicage_fixtures::lotusMulticage(image.size(), 128);
    DeformParams params;
    params.backend = BACKEND_CPU;  // default budget, automatic grid step
    Ptr<Deformer> d = Deformer::create(image, cage, params);
    EXPECT_GT(d->binding().gridStep, 1);
    EXPECT_LE(d->binding().coefficients.total() * sizeof(float), params.memoryBudget);
    Mat out;
    d->deform(multicage_fixtures::wavePose(cage, 40.f), out);
    EXPECT_EQ(out.size(), image.size());
    EXPECT_EQ(out.at<Vec3b>(4096, 4096), Vec3b(40, 90, 160));
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    const double peakGiB = usage.ru_maxrss / (1024.0 * 1024.0);  // ru_maxrss is in KiB
    std::cout << "[ memory ] grid step " << d->binding().gridStep << ", coefficients "
              << d->binding().coefficients.total() * 4 / (1 << 20) << " MiB, peak RSS " << peakGiB
              << " GiB" << std::endl;
    EXPECT_LT(peakGiB, 4.0);
}

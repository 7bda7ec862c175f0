// Issue 15 on the GPU backend: another image without rebinding (the image texture re-uploaded),
// batches, and points that follow the image (the binding read back).
#include <opencv2/imgproc.hpp>
#include <opencv2/multicage/augment.hpp>

#include "gpu_testing.hpp"

using namespace cv;
using namespace cv::multicage;

namespace {
bool same(const Mat& a, const Mat& b) {
    return a.size() == b.size() && a.type() == b.type() && norm(a, b, NORM_INF) == 0;
}
}  // namespace

TEST(GpuBatch, SetImageAndBatchesMatchOneAtATime) {
    MULTICAGE_REQUIRE_GPU();
    const Multicage cage = multicage_testing::butterflyCage(true);
    const Mat photo = multicage_testing::readSample("butterfly.jpg");
    Mat flipped, inverted;
    flip(photo, flipped, 1);
    bitwise_not(photo, inverted);
    const Binding binding = bind(cage, MEAN_VALUE, 2);
    Ptr<Deformer> gpu, cpu;
    multicage_testing::gpuAndCpu(photo, binding, &gpu, &cpu);
    RNG rng(1);
    std::vector<std::vector<Point2f>> poses;
    for (int k = 0; k < 3; ++k) poses.push_back(randomPose(cage, binding, 12, rng));
    Mat own;
    gpu->deform(poses[0], own);

    // A batch of other images: each as a GPU deformer made for it gives, and close to the CPU's.
    const std::vector<Mat> images = {flipped, inverted, photo};
    std::vector<Mat> batch;
    gpu->deformBatch(poses, batch, images);
    ASSERT_EQ(batch.size(), 3u);
    for (size_t k = 0; k < images.size(); ++k) {
        Mat alone, onCpu;
        DeformParams p;
        p.backend = BACKEND_GPU;
        Deformer::create(images[k], binding, p)->deform(poses[k], alone);
        EXPECT_TRUE(same(batch[k], alone)) << k;
        cpu->setImage(images[k]);
        cpu->deform(poses[k], onCpu);
        EXPECT_GT(multicage_testing::psnr(batch[k], onCpu), 40) << k;
    }
    // The deformer's own image is back for the next deform.
    Mat again;
    gpu->deform(poses[0], again);
    EXPECT_TRUE(same(again, own));
    // setImage replaces it.
    gpu->setImage(inverted);
    Mat replaced;
    gpu->deform(poses[1], replaced);
    EXPECT_TRUE(same(replaced, batch[1]));
    EXPECT_THROW(gpu->setImage(Mat(10, 10, CV_8UC3)), cv::Exception);
    std::vector<Mat> ownBatch;
    gpu->deformBatch(poses, ownBatch);
    EXPECT_TRUE(same(ownBatch[1], replaced));
}

TEST(GpuBatch, TransformPointsAgreesWithTheCpuBackend) {
    MULTICAGE_REQUIRE_GPU();
    const Multicage cage = multicage_testing::butterflyCage(true);
    const Mat photo = multicage_testing::readSample("butterfly.jpg");
    DeformParams p;
    p.backend = BACKEND_GPU;
    p.gridStep = 3;
    p.gpuBinding = 1;  // bound in a compute shader: transformPoints reads the binding back
    Ptr<Deformer> gpu = Deformer::create(photo, cage, p);
    p.backend = BACKEND_CPU;
    Ptr<Deformer> cpu = Deformer::create(photo, cage, p);
    RNG rng(2);
    const std::vector<Point2f> pose = randomPose(cage, 12, rng);
    std::vector<Point2f> points = {{10, 10}, {120.5f, 80.25f}, {300, 200}, {480, 340}}, a, b;
    gpu->transformPoints(pose, points, a);
    cpu->transformPoints(pose, points, b);
    for (size_t i = 0; i < points.size(); ++i) EXPECT_LT(norm(a[i] - b[i]), 0.01) << i;
}

// Batches (issue 15, item 3): images of one size share one binding.
#include <opencv2/imgproc.hpp>

#include "testing.hpp"

using namespace cv;
using namespace cv::multicage;

namespace {

DeformParams cpu(int gridStep) {
    DeformParams p;
    p.backend = BACKEND_CPU;
    p.gridStep = gridStep;
    return p;
}

std::vector<Point2f> shiftedPose(const Multicage& cage, float amount) {
    std::vector<Point2f> pose = cage.vertices();
    pose.resize(cage.vertexCount());
    for (size_t j = 0; j < pose.size(); ++j)
        pose[j] += Point2f(amount * std::sin(0.7f * j), amount * std::cos(1.3f * j));
    return pose;
}

bool same(const Mat& a, const Mat& b) {
    return a.size() == b.size() && a.type() == b.type() && norm(a, b, NORM_INF) == 0;
}

/** Four different images of the butterfly's size: the photo, flipped, inverted, blurred. */
std::vector<Mat> images() {
    const Mat photo = multicage_testing::readSample("butterfly.jpg");
    std::vector<Mat> out(4);
    out[0] = photo;
    flip(photo, out[1], 1);
    bitwise_not(photo, out[2]);
    GaussianBlur(photo, out[3], Size(7, 7), 2);
    return out;
}

}  // namespace

TEST(Batch, SetImageDeformsAnotherImageWithoutRebinding) {
    const Multicage cage = multicage_testing::butterflyCage(true);
    const std::vector<Mat> imgs = images();
    Ptr<Deformer> d = Deformer::create(imgs[0], cage, cpu(2));
    const uchar* coefficients = d->binding().coefficients.data;
    const std::vector<Point2f> pose = shiftedPose(cage, 6);
    for (size_t k = 1; k < imgs.size(); ++k) {
        d->setImage(imgs[k]);
        Mat out, expected;
        d->deform(pose, out);
        Deformer::create(imgs[k], d->binding(), cpu(2))->deform(pose, expected);
        EXPECT_TRUE(same(out, expected)) << "image " << k;
    }
    EXPECT_EQ(d->binding().coefficients.data, coefficients) << "the binding was not replaced";
}

TEST(Batch, SetImageRefusesAnotherSizeOrType) {
    const Multicage cage = multicage_testing::butterflyCage(true);
    const Mat photo = multicage_testing::readSample("butterfly.jpg");
    Ptr<Deformer> d = Deformer::create(photo, cage, cpu(4));
    try {
        d->setImage(Mat(100, 100, CV_8UC3, Scalar::all(0)));
        FAIL();
    } catch (const cv::Exception& e) {
        EXPECT_EQ(e.code, Error::StsBadSize);
        EXPECT_NE(e.err.find("100x100"), std::string::npos) << e.err;
    }
    try {
        d->setImage(Mat(photo.size(), CV_8UC1, Scalar(0)));
        FAIL();
    } catch (const cv::Exception& e) {
        EXPECT_EQ(e.code, Error::StsUnmatchedFormats);
        EXPECT_NE(e.err.find("CV_8UC1"), std::string::npos) << e.err;
    }
    EXPECT_THROW(d->setImage(Mat()), cv::Exception);
    // A failed setImage leaves the Deformer as it was.
    Mat a, b;
    d->deform(shiftedPose(cage, 4), a);
    Deformer::create(photo, cage, cpu(4))->deform(shiftedPose(cage, 4), b);
    EXPECT_TRUE(same(a, b));
}

TEST(Batch, DeformBatchGivesTheBitsOfOneAtATime) {
    const Multicage cage = multicage_testing::butterflyCage(true);
    const std::vector<Mat> imgs = images();
    for (int step : {1, 3}) {
        Ptr<Deformer> d = Deformer::create(imgs[0], cage, cpu(step));
        std::vector<std::vector<Point2f>> poses;
        for (int k = 0; k < 7; ++k) poses.push_back(shiftedPose(cage, 2.f * k - 6));
        std::vector<Mat> batch;
        d->deformBatch(poses, batch);  // the Deformer's own image
        ASSERT_EQ(batch.size(), poses.size());
        for (size_t k = 0; k < poses.size(); ++k) {
            Mat one;
            d->deform(poses[k], one);
            EXPECT_TRUE(same(batch[k], one)) << "step " << step << ", pose " << k;
        }
        std::vector<Mat> inputs(poses.size()), others;
        for (size_t k = 0; k < poses.size(); ++k) inputs[k] = imgs[k % imgs.size()];
        d->deformBatch(poses, others, inputs);
        Ptr<Deformer> fresh = Deformer::create(imgs[0], d->binding(), cpu(step));
        for (size_t k = 0; k < poses.size(); ++k) {
            Mat one;
            fresh->setImage(inputs[k]);
            fresh->deform(poses[k], one);
            EXPECT_TRUE(same(others[k], one)) << "step " << step << ", image " << k;
        }
        // The Deformer's own image is unchanged by a batch of other images.
        Mat after;
        d->deform(poses[2], after);
        EXPECT_TRUE(same(after, batch[2]));
    }
}

TEST(Batch, DeformBatchNamesTheBadItem) {
    const Multicage cage = multicage_testing::butterflyCage(true);
    const std::vector<Mat> imgs = images();
    Ptr<Deformer> d = Deformer::create(imgs[0], cage, cpu(4));
    std::vector<std::vector<Point2f>> poses = {
        shiftedPose(cage, 1), shiftedPose(cage, 2), {{1, 2}}};
    std::vector<Mat> out;
    try {
        d->deformBatch(poses, out);
        FAIL();
    } catch (const cv::Exception& e) {
        EXPECT_NE(e.err.find("batch item 2"), std::string::npos) << e.err;
    }
    poses.pop_back();
    try {
        d->deformBatch(poses, out, std::vector<Mat>{imgs[0]});
        FAIL();
    } catch (const cv::Exception& e) {
        EXPECT_NE(e.err.find("2 poses but 1 images"), std::string::npos) << e.err;
    }
    try {
        d->deformBatch(poses, out, std::vector<Mat>{imgs[0], Mat(10, 10, CV_8UC3)});
        FAIL();
    } catch (const cv::Exception& e) {
        EXPECT_NE(e.err.find("batch item 1"), std::string::npos) << e.err;
    }
    d->deformBatch(std::vector<std::vector<Point2f>>(), out);
    EXPECT_TRUE(out.empty());
}

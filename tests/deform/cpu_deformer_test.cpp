// The CPU backend: node positions, mesh rasterised into inverse maps, cv::remap.
#include <opencv2/imgproc.hpp>

#include "testing.hpp"

using namespace cv;
using namespace cv::multicage;

namespace {
DeformParams cpuParams(int gridStep = 1) {
    DeformParams p;
    p.backend = BACKEND_CPU;
    p.gridStep = gridStep;
    return p;
}
Mat asType(const Mat& bgr, int depth, int channels) {
    Mat img;
    if (channels == 1)
        cvtColor(bgr, img, COLOR_BGR2GRAY);
    else if (channels == 4)
        cvtColor(bgr, img, COLOR_BGR2BGRA);
    else
        img = bgr.clone();
    const double scale = depth == CV_16U ? 257.0 : depth == CV_32F ? 1.0 / 255 : 1.0;
    img.convertTo(img, depth, scale);
    return img;
}
}  // namespace

class RestPose : public ::testing::TestWithParam<std::tuple<int, int, int>> {};

TEST_P(RestPose, ReproducesTheInput) {
    const auto [depth, channels, gridStep] = GetParam();
    const Mat image = asType(multicage_testing::readSample("butterfly.jpg"), depth, channels);
    const Multicage cage = multicage_testing::butterflyCage(true);
    Mat out;
    deformImage(image, cage, cage.vertices(), out, cpuParams(gridStep));
    ASSERT_EQ(out.size(), image.size());
    ASSERT_EQ(out.type(), image.type());
    Mat diff;
    absdiff(image, out, diff);
    double maxDiff;
    minMaxLoc(diff.reshape(1), nullptr, &maxDiff);
    const double meanDiff = mean(diff.reshape(1))[0];
    const double unit = depth == CV_16U   ? 257.0
                        : depth == CV_32F ? 1.0 / 255
                                          : 1.0;  // one 8-bit level
    EXPECT_LE(maxDiff, 1.0 * unit);
    EXPECT_LT(meanDiff, 0.01 * unit);
}

INSTANTIATE_TEST_SUITE_P(AllTypes, RestPose,
                         ::testing::Combine(::testing::Values(CV_8U, CV_16U, CV_32F),
                                            ::testing::Values(1, 3, 4), ::testing::Values(1, 3)));

TEST(CpuDeformer, UncoveredPixelsGetTheBorderValue) {
    const Mat image = multicage_testing::readSample("HappyFish.jpg");
    Multicage cage(image.size());
    cage.addPolygon(std::vector<Point2f>{{60, 60}, {60, 130}, {200, 130}, {200, 60}});
    std::vector<Point2f> pose = cage.vertices();  // with frame corners: pull them inwards
    const Point2f centre(image.cols / 2.f, image.rows / 2.f);
    for (int i = cage.vertexCount(); i < cage.vertexCount() + 4; ++i)
        pose[i] = centre + 0.8f * (pose[i] - centre);
    DeformParams params = cpuParams();
    params.borderValue = Scalar(1, 2, 3);
    Mat out;
    deformImage(image, cage, pose, out, params);
    EXPECT_EQ(out.at<Vec3b>(0, 0), Vec3b(1, 2, 3));
    EXPECT_EQ(out.at<Vec3b>(image.rows - 1, image.cols / 2), Vec3b(1, 2, 3));
    EXPECT_NE(out.at<Vec3b>(image.rows / 2, image.cols / 2), Vec3b(1, 2, 3));
}

TEST(CpuDeformer, MapsReproduceDeformAndCarryMasks) {
    const Mat image = multicage_testing::readSample("butterfly.jpg");
    const Multicage cage = multicage_testing::butterflyCage(true);
    Ptr<Deformer> d = Deformer::create(image, cage, cpuParams(2));
    EXPECT_EQ(d->backend(), BACKEND_CPU);
    const std::vector<Point2f> pose = multicage_fixtures::stretchPolygon(cage, 0, 1.08f, 0.92f);
    Mat out, mapx, mapy, remapped;
    d->deform(pose, out);
    d->computeMaps(pose, mapx, mapy);
    ASSERT_EQ(mapx.type(), CV_32F);
    remap(image, remapped, mapx, mapy, INTER_LINEAR, BORDER_CONSTANT);
    EXPECT_EQ(norm(out, remapped, NORM_INF), 0.0);
    // A label mask of the body polygon, warped with INTER_NEAREST, lands where the body lands.
    Mat mask = Mat::zeros(image.size(), CV_8U), warpedMask;
    std::vector<Point> body;
    for (Point2f p : cage.polygon(1)) body.emplace_back(cvRound(p.x), cvRound(p.y));
    fillPoly(mask, std::vector<std::vector<Point>>{body}, Scalar(255));
    remap(mask, warpedMask, mapx, mapy, INTER_NEAREST, BORDER_CONSTANT);
    EXPECT_NEAR(countNonZero(warpedMask), countNonZero(mask), 0.02 * countNonZero(mask));
}

TEST(CpuDeformer, FoldOverIsCounted) {
    const Mat image = multicage_testing::readSample("HappyFish.jpg");
    Multicage cage(image.size());
    cage.addPolygon(std::vector<Point2f>{{60, 60}, {60, 130}, {200, 130}, {200, 60}});
    Ptr<Deformer> d = Deformer::create(image, cage, cpuParams(4));
    EXPECT_EQ(d->foldedTriangles(cage.vertices()), 0);
    std::vector<Point2f> pose = cage.vertices();
    std::swap(pose[0], pose[2]);  // pulls two corners through each other
    EXPECT_GT(d->foldedTriangles(pose), 0);
}

// What deform() documents: a pose validatePose() refuses is deformed as asked, not refused,
// and the image folds over itself where the polygons cross.
TEST(CpuDeformer, ACrossingPoseIsDeformedAsAskedAndFolds) {
    const Mat image = multicage_testing::readSample("HappyFish.jpg");
    Multicage cage(image.size());
    cage.addPolygon(std::vector<Point2f>{{40, 40}, {40, 150}, {220, 150}, {220, 40}});
    cage.addPolygon(std::vector<Point2f>{{100, 80}, {100, 110}, {150, 110}, {150, 80}});
    cage.orient();
    Ptr<Deformer> d = Deformer::create(image, cage, cpuParams(4));
    std::vector<Point2f> pose = cage.vertices();
    pose.resize(cage.vertexCount());
    for (int i = 4; i < 8; ++i)
        pose[i].x += 100;  // the inner square across the outline's right edge
    std::string why;
    EXPECT_FALSE(validatePose(cage, pose, &why));
    EXPECT_NE(why.find("polygon"), std::string::npos) << why;
    EXPECT_GT(d->foldedTriangles(pose), 0);
    Mat out;
    ASSERT_NO_THROW(d->deform(pose, out));
    EXPECT_EQ(out.size(), image.size());
    EXPECT_EQ(out.type(), image.type());
}

TEST(CpuDeformer, BadInputIsRefusedWithAReason) {
    const Mat image = multicage_testing::readSample("HappyFish.jpg");
    const Multicage cage = [&] {
        Multicage c(image.size());
        c.addPolygon(std::vector<Point2f>{{60, 60}, {60, 130}, {200, 130}, {200, 60}});
        return c;
    }();
    auto message = [&](auto&& f) -> std::string {
        try {
            f();
        } catch (const cv::Exception& e) {
            return e.err;
        }
        return "no exception";
    };
    Mat out;
    EXPECT_NE(message([&] { deformImage(Mat(), cage, cage.vertices(), out); }).find("empty"),
              std::string::npos);
    EXPECT_NE(message([&] {
                  deformImage(Mat(image.size(), CV_64FC3), cage, cage.vertices(), out);
              }).find("unsupported image type"),
              std::string::npos);
    EXPECT_NE(message([&] {
                  deformImage(Mat(image.size(), CV_8UC2), cage, cage.vertices(), out);
              }).find("unsupported image type"),
              std::string::npos);
    Mat half;
    resize(image, half, Size(), 0.5, 0.5);
    EXPECT_NE(message([&] { deformImage(half, cage, cage.vertices(), out); }).find("scaled"),
              std::string::npos);
    Ptr<Deformer> d = Deformer::create(image, cage, cpuParams(4));
    EXPECT_NE(message([&] { d->deform(std::vector<Point2f>(3), out); }).find("has 3 vertices"),
              std::string::npos);
    std::vector<Point2f> nanPose = cage.vertices();
    nanPose[1].y = NAN;
    EXPECT_NE(message([&] { d->deform(nanPose, out); }).find("vertex 1 is not a finite number"),
              std::string::npos);
    DeformParams bad = cpuParams();
    bad.backend = 7;
    EXPECT_NE(message([&] { Deformer::create(image, cage, bad); }).find("unknown backend"),
              std::string::npos);
}

TEST(CpuDeformer, PoseAsMatrixEqualsPoseAsVector) {
    const Mat image = multicage_testing::readSample("HappyFish.jpg");
    Multicage cage(image.size());
    cage.addPolygon(std::vector<Point2f>{{60, 60}, {60, 130}, {200, 130}, {200, 60}});
    std::vector<Point2f> pose = cage.vertices();
    pose.resize(4);
    pose[0] += Point2f(-20, -10);
    Ptr<Deformer> d = Deformer::create(image, cage, cpuParams(2));
    Mat a, b;
    d->deform(pose, a);
    d->deform(Mat(pose).reshape(1), b);  // N x 2 CV_32F
    EXPECT_EQ(norm(a, b, NORM_INF), 0.0);
    EXPECT_GT(norm(a, image, NORM_L1), 0.0);
}

TEST(CpuDeformer, FixedFrameKeepsEveryBorderPixelCovered) {
    // Border nodes sit half a pixel inside the frame and move with the pose; the frame ring of
    // the mesh must keep the border covered (no line of border colour at the image edge).
    const Size size(320, 240);
    const Multicage cage = multicage_fixtures::lotusMulticage(size, 40);
    for (int step : {1, 3}) {
        Ptr<Deformer> d =
            Deformer::create(Mat(size, CV_8UC3, Scalar::all(200)), cage, cpuParams(step));
        for (float amplitude : {10.f, 30.f}) {
            Mat mapx, mapy;
            d->computeMaps(multicage_fixtures::wavePose(cage, amplitude, 0.3f), mapx, mapy);
            EXPECT_EQ(countNonZero(mapx < -1), 0) << "step " << step << " amplitude " << amplitude;
            Mat out;
            d->deform(multicage_fixtures::wavePose(cage, amplitude, 0.3f), out);
            EXPECT_EQ(countNonZero(out.reshape(1) != 200), 0);
        }
    }
}

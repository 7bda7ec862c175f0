// Deformer::transformPoints (issue 15, item 1): points follow the image, exact at cage vertices.
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "testing.hpp"

using namespace cv;
using namespace cv::multicage;

namespace {

DeformParams params(int gridStep, int coordinates = MEAN_VALUE) {
    DeformParams p;
    p.backend = BACKEND_CPU;
    p.gridStep = gridStep;
    p.coordinates = coordinates;
    return p;
}

/** A smooth pose of the butterfly multicage: every vertex moved by a few pixels of a wave. */
std::vector<Point2f> wavePose(const Multicage& cage) {
    std::vector<Point2f> pose = cage.vertices();
    pose.resize(cage.vertexCount());
    for (Point2f& v : pose) v += Point2f(9.f * std::sin(v.y / 37.f), 7.f * std::cos(v.x / 53.f));
    return pose;
}

/** Gaussian dots (sigma 1.3) at points, on a black float image. */
Mat dots(Size size, const std::vector<Point2f>& points) {
    Mat image(size, CV_32F, Scalar(0));
    for (const Point2f& p : points)
        for (int y = std::max(0, int(p.y) - 6); y <= std::min(size.height - 1, int(p.y) + 6); ++y)
            for (int x = std::max(0, int(p.x) - 6); x <= std::min(size.width - 1, int(p.x) + 6);
                 ++x) {
                const float dx = x - p.x, dy = y - p.y;
                image.at<float>(y, x) += std::exp(-(dx * dx + dy * dy) / (2 * 1.3f * 1.3f));
            }
    return image;
}

/** Where a dot of the deformed image is: its brightest point, to a fraction of a pixel (the
maximum pixel near `near`, refined by a Gaussian fit through it and its neighbours in x and in
y). A dot's peak is the feature: the deformation is one-to-one, so the brightest point of the
deformed dot is the image of the brightest point of the dot, whereas its centroid moves where
the map bends within the dot's footprint (at a cage vertex, say). */
Point2d peak(const Mat& image, Point2f near, int r = 4) {
    Point best(cvRound(near.x), cvRound(near.y));
    const Point centre = best;
    for (int y = centre.y - r; y <= centre.y + r; ++y)
        for (int x = centre.x - r; x <= centre.x + r; ++x)
            if (image.at<float>(y, x) > image.at<float>(best)) best = Point(x, y);
    auto fit = [](double a, double b, double c) {  // vertex of the parabola through log values
        a = std::log(std::max(a, 1e-6)), b = std::log(std::max(b, 1e-6)),
        c = std::log(std::max(c, 1e-6));
        const double d = a - 2 * b + c;
        return d < 0 ? 0.5 * (a - c) / d : 0.0;
    };
    const float v = image.at<float>(best);
    return Point2d(
        best.x + fit(image.at<float>(best.y, best.x - 1), v, image.at<float>(best.y, best.x + 1)),
        best.y + fit(image.at<float>(best.y - 1, best.x), v, image.at<float>(best.y + 1, best.x)));
}

std::vector<Point2f> jitteredGrid(Size size, int spacing, int border, RNG& rng) {
    std::vector<Point2f> points;
    for (int y = border; y < size.height - border; y += spacing)
        for (int x = border; x < size.width - border; x += spacing)
            points.emplace_back(x + rng.uniform(-0.5f, 0.5f), y + rng.uniform(-0.5f, 0.5f));
    return points;
}

}  // namespace

class TransformPointsDots : public ::testing::TestWithParam<int> {};

// A feature at a point lands where the point lands: dots drawn at rest points, deformed with
// the image, are found where transformPoints puts the points. At grid step 1 every dot counts;
// at coarser steps, dots in the cells around a cage vertex are left out: there the points are
// corrected to land exactly on the cage vertices while the image keeps the mesh's interpolation.
TEST_P(TransformPointsDots, DrawnDotsLandWhereThePointsLand) {
    const int step = GetParam();
    const Multicage cage = multicage_testing::butterflyCage(true);
    RNG rng(15);
    const std::vector<Point2f> points = jitteredGrid(cage.imageSize(), 18, 12, rng);
    const Mat image = dots(cage.imageSize(), points);
    Ptr<Deformer> d = Deformer::create(image, cage, params(step));
    const std::vector<Point2f> pose = wavePose(cage);
    Mat out;
    d->deform(pose, out);
    ASSERT_EQ(d->foldedTriangles(pose), 0);
    std::vector<Point2f> landed;
    d->transformPoints(pose, points, landed);
    ASSERT_EQ(landed.size(), points.size());
    double worst = 0, total = 0;
    int measured = 0;
    for (size_t i = 0; i < points.size(); ++i) {
        const Point2f q = landed[i];
        if (q.x < 8 || q.y < 8 || q.x > image.cols - 9 || q.y > image.rows - 9) continue;
        bool nearVertex = false;
        for (int j = 0; j < cage.vertexCount(); ++j)
            nearVertex |= step > 1 && norm(points[i] - cage.vertices()[j]) < 2 * step;
        if (nearVertex) continue;
        const double e = norm(peak(out, q) - Point2d(q));
        worst = std::max(worst, e), total += e, ++measured;
    }
    ASSERT_GT(measured, 450);
    std::printf("grid step %d: %d dots, error mean %.4f px, max %.4f px\n", step, measured,
                total / measured, worst);
    EXPECT_LT(worst, 0.5);
    EXPECT_LT(total / measured, 0.1);
}

INSTANTIATE_TEST_SUITE_P(GridSteps, TransformPointsDots, ::testing::Values(1, 4));

class TransformPointsExact : public ::testing::TestWithParam<std::tuple<int, int>> {};

TEST_P(TransformPointsExact, CageVerticesLandExactlyOnThePose) {
    const auto [coordinates, step] = GetParam();
    const Multicage cage = multicage_testing::butterflyCage(true);
    const Binding binding = bind(cage, coordinates, step);
    const std::vector<Point2f> pose = wavePose(cage);
    std::vector<Point2f> rest = cage.vertices(), landed;
    rest.resize(cage.vertexCount());
    transformPoints(binding, pose, rest, landed);
    double worst = 0;
    for (size_t j = 0; j < rest.size(); ++j)
        worst = std::max(worst, double(norm(landed[j] - pose[j])));
    EXPECT_LT(worst, 1e-3) << "the worst cage vertex lands " << worst
                           << " px off its pose position";
}

INSTANTIATE_TEST_SUITE_P(CoordinatesAndSteps, TransformPointsExact,
                         ::testing::Combine(::testing::Values(int(MEAN_VALUE), int(HARMONIC)),
                                            ::testing::Values(1, 5)));

// Away from cage vertices, transformPoints is the exact inverse of the maps the image is
// drawn with: the source position a pixel reads, moved forward, lands on that pixel.
TEST(TransformPoints, InvertsTheInverseMapsAtAnyGridStep) {
    const Multicage cage = multicage_testing::butterflyCage(true);
    for (int step : {1, 4, 7}) {
        const Binding binding = bind(cage, MEAN_VALUE, step);
        Ptr<Deformer> d =
            Deformer::create(Mat(cage.imageSize(), CV_8U, Scalar(0)), binding, params(step));
        const std::vector<Point2f> pose = wavePose(cage);
        Mat mapx, mapy;
        d->computeMaps(pose, mapx, mapy);
        std::vector<Point2f> sources, pixels;
        for (int y = 3; y < mapx.rows - 3; y += 3)
            for (int x = 3; x < mapx.cols - 3; x += 3) {
                const Point2f p(mapx.at<float>(y, x), mapy.at<float>(y, x));
                if (p.x <= 0 || p.y <= 0 || p.x >= mapx.cols - 1 || p.y >= mapx.rows - 1)
                    continue;             // clamped
                bool nearVertex = false;  // the correction's cells
                for (const Point2f& v : binding.restVertices)
                    nearVertex |= std::abs(v.x - p.x) <= step && std::abs(v.y - p.y) <= step;
                if (!nearVertex) sources.push_back(p), pixels.emplace_back(float(x), float(y));
            }
        std::vector<Point2f> landed;
        d->transformPoints(pose, sources, landed);
        double worst = 0;
        for (size_t i = 0; i < sources.size(); ++i)
            worst = std::max(worst, double(norm(landed[i] - pixels[i])));
        EXPECT_GT(sources.size(), 4000u);
        EXPECT_LT(worst, 2e-3) << "grid step " << step;
    }
}

TEST(TransformPoints, RestPoseIsTheIdentity) {
    const Multicage cage = multicage_testing::butterflyCage(true);
    RNG rng(3);
    std::vector<Point2f> points;
    for (int i = 0; i < 500; ++i)
        points.emplace_back(rng.uniform(-0.5f, cage.imageSize().width - 0.5f),
                            rng.uniform(-0.5f, cage.imageSize().height - 0.5f));
    for (int coordinates : {int(MEAN_VALUE), int(HARMONIC)}) {
        const Binding binding = bind(cage, coordinates, 3);
        std::vector<Point2f> landed;
        transformPoints(binding, cage.vertices(), points, landed);
        for (size_t i = 0; i < points.size(); ++i)
            ASSERT_LT(norm(landed[i] - points[i]), 1e-3) << i;
    }
}

TEST(TransformPoints, PointsOutsideTheImageFollowTheFrame) {
    const Multicage cage = multicage_testing::butterflyCage(true);
    const Size size = cage.imageSize();
    const Binding binding = bind(cage, MEAN_VALUE, 4);
    const std::vector<Point2f> outside = {
        {-30, 50}, {size.width + 10.f, -4}, {100, size.height + 0.f}};
    std::vector<Point2f> landed;
    // The frame fixed (the usual pose): they stay where they are.
    transformPoints(binding, wavePose(cage), outside, landed);
    for (size_t i = 0; i < outside.size(); ++i) EXPECT_LT(norm(landed[i] - outside[i]), 1e-4);
    // The frame moved: the bilinear map of its corners, continuous across the frame.
    std::vector<Point2f> pose = wavePose(cage);
    const Point2f shift(6, -4);
    for (const Point2f& corner : cage.frame()) pose.push_back(corner + shift);
    transformPoints(binding, pose, outside, landed);
    for (size_t i = 0; i < outside.size(); ++i)
        EXPECT_LT(norm(landed[i] - (outside[i] + shift)), 1e-3);
    // Far away too, to float precision: the corners' bilinear weights are huge there and of both
    // signs, and summed as such they cancelled the shift away (1e20 px: 0 instead of -4).
    const std::vector<Point2f> far = {{1e20f, 3}, {-1e15f, 1e15f}, {7, -1e12f}};
    transformPoints(binding, pose, far, landed);
    for (size_t i = 0; i < far.size(); ++i) {
        const Point2d expected = Point2d(far[i]) + Point2d(shift);
        for (int axis = 0; axis < 2; ++axis) {
            const double want = axis ? expected.y : expected.x,
                         got = axis ? landed[i].y : landed[i].x;
            EXPECT_NEAR(got, want, std::max(1e-3, 1e-6 * std::abs(want))) << i << " axis " << axis;
        }
    }
    const std::vector<Point2f> across = {{-0.5f - 1e-3f, 100},
                                         {-0.5f + 1e-3f, 100},
                                         {200, size.height - 0.5f + 1e-3f},
                                         {200, size.height - 0.5f - 1e-3f}};
    transformPoints(binding, pose, across, landed);
    EXPECT_LT(norm(landed[0] - landed[1]), 0.01);
    EXPECT_LT(norm(landed[2] - landed[3]), 0.01);
}

TEST(TransformPoints, TakesPointsInTheFormsOpenCVUses) {
    const Multicage cage = multicage_testing::butterflyCage(true);
    Ptr<Deformer> d =
        Deformer::create(Mat(cage.imageSize(), CV_8UC3, Scalar::all(0)), cage, params(4));
    const std::vector<Point2f> pose = wavePose(cage);
    const std::vector<Point2f> points = {{100.25f, 80.5f}, {300, 200}, {10, 340}};
    std::vector<Point2f> a;
    d->transformPoints(pose, points, a);
    Mat asMat = Mat(points).reshape(1).clone(), b;  // Nx2 CV_32F
    d->transformPoints(pose, asMat, b);
    Mat asDouble;
    asMat.convertTo(asDouble, CV_64F);
    std::vector<Point2f> c;
    d->transformPoints(pose, asDouble, c);
    ASSERT_EQ(b.total(), points.size());
    for (size_t i = 0; i < points.size(); ++i) {
        EXPECT_EQ(a[i], b.at<Point2f>(int(i)));
        EXPECT_EQ(a[i], c[i]);
    }
    std::vector<Point2f> none;
    d->transformPoints(pose, std::vector<Point2f>(), none);
    EXPECT_TRUE(none.empty());
}

TEST(TransformPoints, BadInputThrowsClearErrors) {
    const Multicage cage = multicage_testing::butterflyCage(true);
    Ptr<Deformer> d = Deformer::create(Mat(cage.imageSize(), CV_8U, Scalar(0)), cage, params(4));
    std::vector<Point2f> out;
    const std::vector<Point2f> pose = wavePose(cage);
    try {
        d->transformPoints(pose, std::vector<Point2f>{{1, 2}, {NAN, 3}}, out);
        FAIL() << "a NaN point must throw";
    } catch (const cv::Exception& e) {
        EXPECT_NE(e.err.find("point 1"), std::string::npos) << e.err;
    }
    try {
        d->transformPoints(std::vector<Point2f>(3), std::vector<Point2f>{{1, 2}}, out);
        FAIL() << "a pose of the wrong size must throw";
    } catch (const cv::Exception& e) {
        EXPECT_NE(e.err.find("the pose has 3 vertices"), std::string::npos) << e.err;
    }
    EXPECT_THROW(d->transformPoints(pose, Mat(4, 3, CV_32F, Scalar(1)), out), cv::Exception);
    EXPECT_THROW(transformPoints(Binding(), pose, std::vector<Point2f>{{1, 2}}, out),
                 cv::Exception);
}

// Mean value coordinates of one polygon (Hormann & Floater 2006).
#include <opencv2/imgproc.hpp>

#include "testing.hpp"

using namespace cv;
using namespace cv::multicage;

namespace {
// A non-convex polygon (an arrow), clockwise on screen.
const std::vector<Point2f> kArrow = {{10, 40},  {60, 40}, {60, 10}, {110, 60},
                                     {60, 110}, {60, 80}, {10, 80}};

std::vector<Point2f> samplePoints(RNG& rng, int n) {
    std::vector<Point2f> pts;
    for (int i = 0; i < n; ++i)
        pts.emplace_back(rng.uniform(-50.f, 170.f), rng.uniform(-50.f, 170.f));
    return pts;
}
}  // namespace

TEST(MeanValue, PartitionOfUnityAndLinearPrecisionInsideAndOutside) {
    RNG rng(7);
    const std::vector<Point2f> pts = samplePoints(rng, 2000);
    Mat w;
    meanValueCoordinates(kArrow, pts, w);
    ASSERT_EQ(w.size(), Size(7, 2000));
    ASSERT_EQ(w.type(), CV_32F);
    for (int k = 0; k < w.rows; ++k) {
        double sum = 0, x = 0, y = 0;
        for (int i = 0; i < w.cols; ++i) {
            const double c = w.at<float>(k, i);
            sum += c, x += c * kArrow[i].x, y += c * kArrow[i].y;
        }
        EXPECT_NEAR(sum, 1.0, 1e-5) << pts[k];
        EXPECT_NEAR(x, pts[k].x, 1e-3) << pts[k];
        EXPECT_NEAR(y, pts[k].y, 1e-3) << pts[k];
    }
}

TEST(MeanValue, RawWeightsArePositiveInsideNegativeOutsideForPositiveArea) {
    ASSERT_GT(contourArea(kArrow, true), 0);
    RNG rng(8);
    const std::vector<Point2f> pts = samplePoints(rng, 2000);
    Mat w;
    meanValueCoordinates(kArrow, pts, w, false);
    for (int k = 0; k < w.rows; ++k) {
        const double inside = pointPolygonTest(kArrow, pts[k], true);
        if (std::abs(inside) < 1e-2) continue;
        const double sum = cv::sum(w.row(k))[0];
        EXPECT_EQ(sum > 0, inside > 0) << pts[k] << " sum " << sum;
    }
}

TEST(MeanValue, LagrangePropertyAtVertices) {
    Mat w;
    meanValueCoordinates(kArrow, kArrow, w);
    for (int k = 0; k < w.rows; ++k)
        for (int i = 0; i < w.cols; ++i) EXPECT_EQ(w.at<float>(k, i), i == k ? 1.f : 0.f);
}

TEST(MeanValue, ExactLinearInterpolationOnEdges) {
    std::vector<Point2f> pts;
    std::vector<std::pair<int, float>> where;
    for (int i = 0; i < 7; ++i)
        for (float s : {0.25f, 0.5f, 0.9f}) {
            pts.push_back(kArrow[i] * (1 - s) + kArrow[(i + 1) % 7] * s);
            where.emplace_back(i, s);
        }
    Mat w, raw;
    meanValueCoordinates(kArrow, pts, w);
    meanValueCoordinates(kArrow, pts, raw, false);  // the same exact values, by policy
    for (int k = 0; k < w.rows; ++k) {
        const int i = where[k].first;
        const float s = where[k].second;
        for (int j = 0; j < 7; ++j) {
            const float expected = j == i ? 1 - s : j == (i + 1) % 7 ? s : 0.f;
            EXPECT_NEAR(w.at<float>(k, j), expected, 1e-6) << "edge " << i << " s " << s;
            EXPECT_EQ(w.at<float>(k, j), raw.at<float>(k, j));
        }
    }
}

TEST(MeanValue, CollinearPointsBeyondAnEdgeAreFinite) {
    // On the line of an edge but outside it: A_i = 0 with D_i > 0, the 0/0 case of the naive
    // formula.
    const std::vector<Point2f> pts = {{0, 40}, {120, 40}, {10, 100}, {-30, 80}};
    Mat w;
    meanValueCoordinates(kArrow, pts, w);
    for (int k = 0; k < w.rows; ++k) {
        EXPECT_TRUE(checkRange(w.row(k)));
        EXPECT_NEAR(sum(w.row(k))[0], 1.0, 1e-5);
    }
}

TEST(MeanValue, BadInputThrows) {
    Mat w;
    EXPECT_THROW(meanValueCoordinates(std::vector<Point2f>{{0, 0}, {1, 1}}, kArrow, w),
                 cv::Exception);
    EXPECT_THROW(meanValueCoordinates(kArrow, Mat(4, 3, CV_32F), w), cv::Exception);
    EXPECT_THROW(meanValueCoordinates(kArrow, Mat(4, 2, CV_8U), w), cv::Exception);
}

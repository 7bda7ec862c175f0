// Binding a node grid to a multicage (paper Algorithm 1).
#include "testing.hpp"

using namespace cv;
using namespace cv::multicage;

namespace {

float coefficient(const Binding& b, int j, Point node) {
    return b.coefficients.at<float>(j, node.y * b.gridSize.width + node.x);
}

// Integer-vertex multicage whose vertices and edges fall on nodes: an outer octagon and an
// inner axis-aligned rectangle around (100, 80), in a 200x160 image.
Multicage gridAlignedCage() {
    Multicage cage(Size(200, 160));
    cage.addPolygon(std::vector<Point2f>{
        {40, 10}, {160, 10}, {190, 50}, {190, 110}, {160, 150}, {40, 150}, {10, 110}, {10, 50}});
    cage.addPolygon(std::vector<Point2f>{{80, 60}, {120, 60}, {120, 100}, {80, 100}});
    cage.orient();
    return cage;
}

}  // namespace

TEST(Binding, PartitionOfUnityAndLinearPrecisionOnRandomMulticages) {
    RNG rng(20261122);
    for (int trial = 0; trial < 8; ++trial) {
        const Size size =
            trial < 2 ? Size(1024, 1024) : Size(rng.uniform(64, 1025), rng.uniform(64, 1025));
        const Multicage cage = multicage_fixtures::randomMulticage(rng, size, 3, 3, 10);
        ASSERT_TRUE(cage.validate());
        const int step = trial < 2 ? 1 : rng.uniform(1, 4);
        const Binding b = bind(cage, MEAN_VALUE, step);
        ASSERT_EQ(b.coefficientCount(), cage.vertexCount() + 4);
        ASSERT_EQ(b.coefficients.size(), Size(b.nodeCount(), b.coefficientCount()));
        const multicage_testing::PartitionErrors e = multicage_testing::partitionErrors(b);
        EXPECT_LE(e.sum, 1e-5) << "trial " << trial << " " << size;
        EXPECT_LE(e.position, 1e-3) << "trial " << trial << " " << size;
        EXPECT_TRUE(checkRange(b.coefficients));
        EXPECT_GT(b.minConditioning, 0.0);
        EXPECT_LE(b.minConditioning, 1.0);
        EXPECT_TRUE(Rect2f(0, 0, size.width, size.height).contains(b.worstNode));
    }
}

TEST(Binding, MatchesDoublePrecisionAlgorithm1) {
    // Reference: raw weights per polygon (double) over their total; the cage is oriented, so
    // every polygon's raw weights already carry the orientation rule's sign.
    RNG rng(3);
    const Multicage cage = multicage_fixtures::randomMulticage(rng, Size(300, 200), 2, 3, 9);
    const Binding b = bind(cage, MEAN_VALUE, 1);
    ASSERT_TRUE(cage.validate());
    std::vector<std::vector<Point2f>> polygons;
    for (int p = 0; p < cage.polygonCount(); ++p) polygons.push_back(cage.polygon(p));
    polygons.push_back(cage.frame());
    double worst = 0;
    for (int trial = 0; trial < 300; ++trial) {
        const Point node(rng.uniform(0, b.gridSize.width), rng.uniform(0, b.gridSize.height));
        std::vector<double> ref;
        for (size_t p = 0; p < polygons.size(); ++p) {
            Mat w;
            meanValueCoordinates(polygons[p], std::vector<Point2f>{b.node(node.x, node.y)}, w,
                                 false);
            for (int i = 0; i < w.cols; ++i) ref.push_back(w.at<float>(0, i));
        }
        double total = 0;
        for (double r : ref) total += r;
        for (size_t j = 0; j < ref.size(); ++j)
            worst = std::max(worst, std::abs(ref[j] / total - coefficient(b, int(j), node)));
    }
    EXPECT_LE(worst, 1e-5);
}

TEST(Binding, LagrangePropertyAtVertices) {
    const Multicage cage = gridAlignedCage();
    const Binding b = bind(cage, MEAN_VALUE, 1);
    const std::vector<Point2f> v = cage.vertices();
    for (int j = 0; j < cage.vertexCount(); ++j) {
        const Point node(cvRound(v[j].x), cvRound(v[j].y));
        for (int i = 0; i < b.coefficientCount(); ++i)
            EXPECT_EQ(coefficient(b, i, node), i == j ? 1.f : 0.f)
                << "vertex " << j << " coefficient " << i;
    }
}

TEST(Binding, NodesOnEdgesInterpolateTheEdge) {
    const Multicage cage = gridAlignedCage();
    const Binding b = bind(cage, MEAN_VALUE, 1);
    const int inner = cage.polygonOffset(1);
    const std::vector<Point2f> v = cage.vertices();
    int checked = 0;
    for (int e = 0; e < 4; ++e) {  // the inner rectangle's edges lie on grid lines
        const int i = inner + e, j = inner + (e + 1) % 4;
        for (float s = 0.05f; s < 1.f; s += 0.05f) {
            const Point2f p = v[i] * (1 - s) + v[j] * s;
            if (p.x != std::round(p.x) || p.y != std::round(p.y)) continue;
            const Point node(cvRound(p.x), cvRound(p.y));
            for (int k = 0; k < b.coefficientCount(); ++k) {
                const float expected = k == i ? 1 - s : k == j ? s : 0.f;
                EXPECT_NEAR(coefficient(b, k, node), expected, 1e-6);
            }
            ++checked;
        }
    }
    EXPECT_GT(checked, 40);
}

TEST(Binding, InnerPolygonStaysPutWhenOnlyOuterMoves) {
    const Multicage cage = gridAlignedCage();
    const Binding b = bind(cage, MEAN_VALUE, 1);
    const std::vector<Point2f> pose =
        multicage_fixtures::stretchPolygon(cage, 0, 1.1f, 0.9f, {5, -3});
    Mat positions;
    b.apply(pose, positions);
    // Nodes on the inner polygon follow it exactly, and it did not move.
    for (int x = 80; x <= 120; ++x)
        for (int y : {60, 100}) {
            EXPECT_EQ(positions.at<Point2f>(y, x), Point2f(float(x), float(y)));
        }
    for (int y = 60; y <= 100; ++y)
        for (int x : {80, 120}) EXPECT_EQ(positions.at<Point2f>(y, x), Point2f(float(x), float(y)));
    // While the outer polygon's nodes did move.
    EXPECT_GT(norm(positions.at<Point2f>(10, 100) - Point2f(100, 10)), 2.0);
}

TEST(Binding, NegativeCoefficientsInsideInnerPolygonForOuterVertices) {
    // Paper Fig. 5: inside the inner polygon the outer polygon's coefficients are negative.
    const Multicage cage = gridAlignedCage();
    const Binding b = bind(cage, MEAN_VALUE, 1);
    const int outer = static_cast<int>(cage.polygon(0).size());
    int negative = 0, total = 0;
    for (int y = 65; y <= 95; y += 5)
        for (int x = 85; x <= 115; x += 5) {
            double outerSum = 0;
            for (int j = 0; j < outer; ++j) {
                const float c = coefficient(b, j, Point(x, y));
                outerSum += c;
                negative += c < 0, ++total;
            }
            EXPECT_LT(outerSum, 0.0) << Point(x, y);
        }
    EXPECT_GT(negative, total / 2);
}

TEST(Binding, GridStepSamplesTheSameField) {
    RNG rng(11);
    const Multicage cage = multicage_fixtures::randomMulticage(rng, Size(257, 190), 2, 2, 8);
    const Binding fine = bind(cage, MEAN_VALUE, 1), coarse = bind(cage, MEAN_VALUE, 4);
    EXPECT_EQ(coarse.gridSize, Size(65, 49));
    EXPECT_EQ(coarse.node(64, 48), Point2f(256, 189));  // last row and column on the border
    double worst = 0;
    for (int gy = 0; gy < coarse.gridSize.height; ++gy)
        for (int gx = 0; gx < coarse.gridSize.width; ++gx) {
            const Point2f p = coarse.node(gx, gy);
            for (int j = 0; j < coarse.coefficientCount(); ++j)
                worst = std::max(worst,
                                 double(std::abs(coefficient(coarse, j, Point(gx, gy)) -
                                                 coefficient(fine, j, Point(int(p.x), int(p.y))))));
        }
    EXPECT_LE(worst, 1e-6);
}

TEST(Binding, RestPoseIsIdentityAndBadPosesThrow) {
    const Multicage cage = gridAlignedCage();
    const Binding b = bind(cage, MEAN_VALUE, 3);
    Mat positions;
    b.apply(cage.vertices(), positions);
    EXPECT_EQ(norm(positions, b.nodes(), NORM_INF), 0.0);
    std::vector<Point2f> user = cage.vertices();
    user.resize(cage.vertexCount());
    b.apply(user, positions);  // frame corners may be omitted
    EXPECT_EQ(norm(positions, b.nodes(), NORM_INF), 0.0);
    user.pop_back();
    EXPECT_THROW(b.apply(user, positions), cv::Exception);
    user.push_back(Point2f(NAN, 0));
    EXPECT_THROW(b.apply(user, positions), cv::Exception);
}

TEST(Binding, InvalidMulticageIsRefusedWithTheReason) {
    Multicage cage(Size(100, 100));
    cage.addPolygon(std::vector<Point2f>{{10, 10}, {60, 60}, {60, 10}, {10, 70}});
    try {
        bind(cage);
        FAIL() << "bound a self-intersecting polygon";
    } catch (const cv::Exception& e) {
        EXPECT_NE(e.err.find("polygon 0 intersects itself"), std::string::npos) << e.err;
    }
    EXPECT_THROW(bind(gridAlignedCage(), MEAN_VALUE, 0), cv::Exception);
}

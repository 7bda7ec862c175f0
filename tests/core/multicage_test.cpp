// The multicage: frame, depth, orientation rule, validation messages.
#include <opencv2/imgproc.hpp>

#include "testing.hpp"

using namespace cv;
using namespace cv::multicage;

namespace {
std::vector<Point2f> square(Point2f c, float half) {  // clockwise on screen: A > 0
    return {{c.x - half, c.y - half},
            {c.x + half, c.y - half},
            {c.x + half, c.y + half},
            {c.x - half, c.y + half}};
}
std::vector<Point2f> reversed(std::vector<Point2f> p) {
    std::reverse(p.begin() + 1, p.end());
    return p;
}
std::string why(const Multicage& cage) {
    std::string reason;
    EXPECT_FALSE(cage.validate(&reason));
    return reason;
}
}  // namespace

TEST(Multicage, FrameIsDepthZeroAndLastInVertices) {
    Multicage cage(Size(200, 100));
    cage.addPolygon(square({50, 50}, 20));
    const std::vector<Point2f> v = cage.vertices();
    ASSERT_EQ(v.size(), 8u);
    EXPECT_EQ(cage.vertexCount(), 4);
    EXPECT_EQ(v[4], Point2f(-0.5f, -0.5f));
    EXPECT_EQ(v[5], Point2f(199.5f, -0.5f));
    EXPECT_EQ(v[6], Point2f(199.5f, 99.5f));
    EXPECT_EQ(v[7], Point2f(-0.5f, 99.5f));
    // The frame obeys the depth-0 rule (A > 0) by construction.
    EXPECT_GT(cv::contourArea(cage.frame(), true), 0);
}

TEST(Multicage, DepthCountsContainingPolygons) {
    Multicage cage(Size(300, 300));
    cage.addPolygon(square({150, 150}, 120));  // 0: depth 1
    cage.addPolygon(square({110, 150}, 30));   // 1: inside 0
    cage.addPolygon(square({110, 150}, 10));   // 2: inside 1 and 0
    cage.addPolygon(square({200, 150}, 30));   // 3: inside 0, beside 1
    EXPECT_EQ(cage.depth(0), 1);
    EXPECT_EQ(cage.depth(1), 2);
    EXPECT_EQ(cage.depth(2), 3);
    EXPECT_EQ(cage.depth(3), 2);
}

TEST(Multicage, OrientAppliesAlternatingRuleAndReordersPoses) {
    Multicage cage(Size(300, 300));
    cage.addPolygon(square({150, 150}, 120));           // depth 1 wants A < 0: will flip
    cage.addPolygon(reversed(square({150, 150}, 40)));  // depth 2 wants A > 0: will flip
    cage.addPolygon(reversed(square({285, 15}, 10)));   // depth 1, already A < 0
    std::vector<Point2f> pose = cage.vertices();
    pose.resize(cage.vertexCount());
    for (size_t i = 0; i < pose.size(); ++i) pose[i] += Point2f(float(i), 0.f);  // tag each vertex
    cage.addPose("tagged", pose);
    const std::vector<Point2f> p0 = cage.polygon(0), p2 = cage.polygon(2);
    EXPECT_FALSE(cage.validate());
    cage.orient();
    EXPECT_TRUE(cage.validate());
    EXPECT_LT(cage.signedArea(0), 0);
    EXPECT_GT(cage.signedArea(1), 0);
    EXPECT_LT(cage.signedArea(2), 0);
    EXPECT_EQ(cage.polygon(2), p2);        // untouched
    EXPECT_EQ(cage.polygon(0)[0], p0[0]);  // vertex 0 stays first
    EXPECT_EQ(cage.polygon(0)[1], p0[3]);
    // Every pose vertex still belongs to the rest vertex it belonged to.
    const std::vector<Point2f> rest = cage.vertices();
    for (int i = 0; i < cage.vertexCount(); ++i) {
        const Point2f d = cage.pose(0).vertices[i] - rest[i];
        EXPECT_EQ(d.y, 0.f);
        EXPECT_GE(d.x, 0.f);
    }
    EXPECT_EQ(cage.pose(0).vertices[1] - rest[1], Point2f(3.f, 0.f));  // was vertex 3
}

TEST(Multicage, ValidateNamesCrossingPolygonsAndEdge) {
    Multicage cage(Size(300, 300));
    cage.addPolygon(square({100, 100}, 50));
    cage.addPolygon(square({250, 250}, 20));
    cage.addPolygon(std::vector<Point2f>{
        {100, 100}, {170, 160}, {180, 200}, {140, 190}});  // starts inside polygon 0
    EXPECT_EQ(why(cage), "polygon 2 crosses polygon 0 at edge 0 (edge 1 of polygon 0)");
    Multicage touching(Size(300, 300));
    touching.addPolygon(square({100, 100}, 50));
    touching.addPolygon(square({170, 100}, 20));  // shares the line x = 150
    EXPECT_NE(why(touching).find("polygon 1 crosses polygon 0"), std::string::npos);
}

TEST(Multicage, ValidateRejectsFewerThanThreeVertices) {
    Multicage cage(Size(100, 100));
    cage.addPolygon(square({50, 50}, 20));
    cage.addPolygon(std::vector<Point2f>{{10, 10}, {20, 10}});
    EXPECT_EQ(why(cage), "polygon 1 has fewer than 3 vertices (2)");
}

TEST(Multicage, ValidateRejectsNaN) {
    Multicage cage(Size(100, 100));
    std::vector<Point2f> p = square({50, 50}, 20);
    p.push_back(Point2f(std::nanf(""), 40.f));
    cage.addPolygon(p);
    EXPECT_NE(why(cage).find("polygon 0, vertex 4 is not a finite number"), std::string::npos);
}

TEST(Multicage, ValidateRejectsPolygonOutsideFrame) {
    Multicage cage(Size(100, 100));
    cage.addPolygon(square({50, 50}, 20));
    cage.addPolygon(square({10, 90}, 5));
    cage.addPolygon(square({10, 10}, 5));
    cage.addPolygon(std::vector<Point2f>{{80, 80}, {99.6f, 80}, {90, 90}});  // x > W - 0.5
    EXPECT_NE(why(cage).find("polygon 3 is not inside the image frame: vertex 1"),
              std::string::npos);
}

TEST(Multicage, ValidateRejectsSelfIntersectionAndSpikes) {
    Multicage bowtie(Size(100, 100));
    bowtie.addPolygon(std::vector<Point2f>{{10, 10}, {60, 60}, {60, 10}, {10, 70}});
    EXPECT_NE(why(bowtie).find("polygon 0 intersects itself at edges"), std::string::npos);
    Multicage spike(Size(100, 100));  // goes out along a line and comes back: zero-width spike
    spike.addPolygon(
        std::vector<Point2f>{{10, 10}, {50, 10}, {50, 50}, {50, 70}, {50, 40}, {10, 50}});
    EXPECT_NE(why(spike).find("intersects itself"), std::string::npos);
    Multicage repeated(Size(100, 100));
    repeated.addPolygon(std::vector<Point2f>{{10, 10}, {50, 10}, {50, 10}, {10, 50}});
    EXPECT_NE(why(repeated).find("repeats vertex 1"), std::string::npos);
    Multicage flat(Size(100, 100));
    flat.addPolygon(std::vector<Point2f>{{10, 10}, {20, 20}, {30, 30}});
    EXPECT_FALSE(flat.validate());
}

TEST(Multicage, ValidateRejectsWrongOrientationButGeometryPasses) {
    Multicage cage(Size(100, 100));
    cage.addPolygon(square({50, 50}, 20));  // depth 1 with A > 0
    std::string reason;
    EXPECT_TRUE(cage.validateGeometry(&reason)) << reason;
    EXPECT_NE(why(cage).find("orientation rule"), std::string::npos);
}

TEST(Multicage, ValidateRejectsBadSizeAndPoses) {
    Multicage empty;
    EXPECT_NE(why(empty).find("image size"), std::string::npos);
    Multicage cage(Size(100, 100));
    cage.addPolygon(reversed(square({50, 50}, 20)));
    std::vector<Point2f> pose = cage.polygon(0);
    pose[2].x = INFINITY;
    cage.addPose("bad", pose);
    EXPECT_NE(why(cage).find("pose 0 (\"bad\"), vertex 2 is not a finite number"),
              std::string::npos);
    EXPECT_THROW(cage.addPose("short", std::vector<Point2f>(3)), cv::Exception);
}

TEST(Multicage, EditsKeepPosesInStep) {
    Multicage cage(Size(100, 100));
    cage.addPolygon(reversed(square({30, 30}, 10)));
    std::vector<Point2f> pose = cage.polygon(0);
    for (Point2f& p : pose) p.x += 1;
    cage.addPose("p", pose);
    cage.addPolygon(reversed(square({70, 70}, 10)));  // new vertices enter poses at rest
    EXPECT_EQ(cage.pose(0).vertices.size(), 8u);
    EXPECT_EQ(cage.pose(0).vertices[4], cage.polygon(1)[0]);
    cage.removePolygon(0);
    EXPECT_EQ(cage.pose(0).vertices, cage.polygon(0));
    EXPECT_THROW(cage.addPolygon(Mat(3, 3, CV_32F)), cv::Exception);  // not N x 2
}

TEST(Multicage, ScaledMapsFrameOntoFrame) {
    Multicage cage(Size(100, 50));
    cage.addPolygon(std::vector<Point2f>{{-0.4f, 10}, {49.5f, 10}, {49.5f, 40}});
    const Multicage big = cage.scaled(Size(400, 200));
    EXPECT_EQ(big.imageSize(), Size(400, 200));
    EXPECT_NEAR(big.polygon(0)[0].x, -0.5f + 0.1f * 4, 1e-4);
    EXPECT_NEAR(big.polygon(0)[1].x, 199.5f, 1e-4);  // the image centre stays the centre
    EXPECT_NEAR(big.polygon(0)[1].y, 41.5f, 1e-4);
}

TEST(Multicage, PosedMovesPolygonsToThePose) {
    Multicage cage(Size(100, 100));
    cage.addPolygon(reversed(square({30, 30}, 10)));
    cage.addPolygon(reversed(square({70, 70}, 10)));
    std::vector<Point2f> pose = cage.vertices();  // with the frame corners
    for (Point2f& p : pose) p += Point2f(1, 2);
    const Multicage posed = cage.posed(pose);
    ASSERT_EQ(posed.polygonCount(), 2);
    EXPECT_EQ(posed.polygon(1)[2], cage.polygon(1)[2] + Point2f(1, 2));
    EXPECT_EQ(posed.poseCount(), 0);
    EXPECT_THROW(cage.posed(std::vector<Point2f>(5)), cv::Exception);
}

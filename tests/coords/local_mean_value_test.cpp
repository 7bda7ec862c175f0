// Local mean value coordinates (LOCAL_MEAN_VALUE): Algorithm 1 summed, node by node, over the
// polygons bounding the node's region only.
#include "testing.hpp"

using namespace cv;
using namespace cv::multicage;

namespace {

// A 300x240 multicage: an outline (octagon), a "face" square inside it, and an "eye" triangle
// inside the face (depth 3), so every kind of region is there.
Multicage nestedCage() {
    Multicage cage(Size(300, 240));
    cage.addPolygon(std::vector<Point2f>{
        {60, 20}, {240, 20}, {285, 80}, {285, 170}, {240, 225}, {60, 225}, {15, 170}, {15, 80}});
    cage.addPolygon(
        std::vector<Point2f>{{100.5f, 70.5f}, {190.5f, 70.5f}, {190.5f, 160.5f}, {100.5f, 160.5f}});
    cage.addPolygon(std::vector<Point2f>{{120.25f, 90.25f}, {150.25f, 95.75f}, {130.5f, 120.5f}});
    cage.orient();
    return cage;
}

// p' = c + s R (p - c) + t: a similarity with rotation.
struct Similarity {
    Point2d c, t;
    double s, angle;
    Point2f operator()(Point2f p) const {
        const double x = p.x - c.x, y = p.y - c.y, cs = std::cos(angle), sn = std::sin(angle);
        return Point2f(float(c.x + t.x + s * (cs * x - sn * y)),
                       float(c.y + t.y + s * (sn * x + cs * y)));
    }
};

// The worst distance, over nodes strictly inside the axis-aligned box, between where the pose
// moves them and where the similarity does.
double worstOffInside(const Binding& b, const std::vector<Point2f>& pose, Rect2f box,
                      const Similarity& sim) {
    Mat positions;
    b.apply(pose, positions);
    double worst = 0;
    for (int gy = 0; gy < b.gridSize.height; ++gy)
        for (int gx = 0; gx < b.gridSize.width; ++gx) {
            const Point2f x = b.node(gx, gy);
            if (!(x.x > box.x && x.y > box.y && x.x < box.br().x && x.y < box.br().y)) continue;
            worst = std::max(worst, double(norm(positions.at<Point2f>(gy, gx) - sim(x))));
        }
    return worst;
}

}  // namespace

TEST(LocalMeanValue, PartitionOfUnityAndLinearPrecisionOnRandomMulticages) {
    RNG rng(20261124);
    for (int trial = 0; trial < 6; ++trial) {
        const Size size(rng.uniform(64, 700), rng.uniform(64, 700));
        const Multicage cage = multicage_fixtures::randomMulticage(rng, size, 3, 3, 10);
        ASSERT_TRUE(cage.validate());
        const Binding b = bind(cage, LOCAL_MEAN_VALUE, rng.uniform(1, 4));
        EXPECT_EQ(b.coordinates, LOCAL_MEAN_VALUE);
        const multicage_testing::PartitionErrors e = multicage_testing::partitionErrors(b);
        EXPECT_LE(e.sum, 1e-5) << "trial " << trial;
        EXPECT_LE(e.position, 1e-3) << "trial " << trial;
        EXPECT_TRUE(checkRange(b.coefficients)) << "trial " << trial;
    }
}

TEST(LocalMeanValue, EachRegionSeesOnlyThePolygonsBoundingIt) {
    const Multicage cage = nestedCage();
    const Binding b = bind(cage, LOCAL_MEAN_VALUE, 1);
    const int face = cage.polygonOffset(1), eye = cage.polygonOffset(2);
    const int frame = cage.vertexCount();
    struct Probe {
        Point node;
        std::vector<std::pair<int, int>> bounding;  // vertex ranges [first, last)
    };
    const std::vector<Probe> probes = {
        {{5, 5}, {{0, face}, {frame, frame + 4}}},    // frame region: frame + outline
        {{50, 120}, {{0, face}, {face, eye}}},        // outline's region: outline + face
        {{170, 140}, {{face, eye}, {eye, eye + 3}}},  // face's region: face + eye
        {{132, 100}, {{eye, eye + 3}}}};              // eye's region: the eye alone
    for (const Probe& p : probes) {
        double inside = 0;
        for (int j = 0; j < b.coefficientCount(); ++j) {
            bool bounding = false;
            for (const auto& range : p.bounding) bounding |= j >= range.first && j < range.second;
            const float cc = b.coefficients.at<float>(j, p.node.y * b.gridSize.width + p.node.x);
            if (bounding)
                inside += cc;
            else
                EXPECT_EQ(cc, 0.f) << "vertex " << j << " at " << p.node;
        }
        EXPECT_NEAR(inside, 1.0, 1e-5) << p.node;
    }
    // Inside the eye, its own mean value coordinates (meanValueCoordinates of it alone).
    Mat own;
    meanValueCoordinates(cage.polygon(2), std::vector<Point2f>{{132, 100}}, own);
    for (int i = 0; i < 3; ++i)
        EXPECT_NEAR(b.coefficients.at<float>(eye + i, 100 * b.gridSize.width + 132),
                    own.at<float>(0, i), 1e-5);
}

TEST(LocalMeanValue, AProtectedPolygonMovedBySimilarityMovesItsContentExactly) {
    // The face and the eye move by one similarity; the outline is stretched 20% and the frame
    // squeezed. Local coordinates keep the face's inside on the similarity; Algorithm 1's
    // global sums leak the outline's and the frame's moves into it (the case they fail).
    const Multicage cage = nestedCage();
    const Similarity sim{{145, 115}, {6, -4}, 1.1, 0.15};
    std::vector<Point2f> pose = multicage_fixtures::stretchPolygon(cage, 0, 1.2f, 1.0f, {0, 0});
    for (int k = cage.polygonOffset(1); k < cage.vertexCount(); ++k)
        pose[k] = sim(cage.vertices()[k]);
    pose.resize(cage.vertexCount());
    const std::vector<Point2f> frame = {{-10, -0.5f}, {305, 3}, {299.5f, 239.5f}, {-0.5f, 250}};
    pose.insert(pose.end(), frame.begin(), frame.end());
    const Rect2f faceBox(100.5f, 70.5f, 90, 90);
    for (int step : {1, 3}) {
        const double local = worstOffInside(bind(cage, LOCAL_MEAN_VALUE, step), pose, faceBox, sim);
        const double global = worstOffInside(bind(cage, MEAN_VALUE, step), pose, faceBox, sim);
        EXPECT_LE(local, 2e-3) << "grid step " << step;
        EXPECT_GT(global, 0.5) << "grid step " << step;  // what the local variant removes
    }
}

TEST(LocalMeanValue, ContinuousAcrossEveryEdge) {
    // Nodes on either side of an edge follow the edge's interpolation as they approach it: under
    // a pose that moves every polygon differently, no two neighbouring nodes jump apart by more
    // than the pose's own gradient allows (here: 4x the grid spacing), on the local grid as on
    // Algorithm 1's.
    const Multicage cage = nestedCage();
    RNG rng(7);
    std::vector<Point2f> pose = cage.vertices();
    for (Point2f& p : pose) p += Point2f(rng.uniform(-6.f, 6.f), rng.uniform(-6.f, 6.f));
    for (int coords : {LOCAL_MEAN_VALUE, MEAN_VALUE}) {
        const Binding b = bind(cage, coords, 1);
        Mat positions;
        b.apply(pose, positions);
        double worst = 0;
        for (int y = 0; y + 1 < positions.rows; ++y)
            for (int x = 0; x + 1 < positions.cols; ++x) {
                const Point2f p = positions.at<Point2f>(y, x);
                worst = std::max({worst, double(norm(positions.at<Point2f>(y, x + 1) - p)),
                                  double(norm(positions.at<Point2f>(y + 1, x) - p))});
            }
        EXPECT_LE(worst, 4.0) << coordinateTypeName(coords);
    }
}

TEST(LocalMeanValue, NamedInCageFilesThePythonAndTheCli) {
    int type = -5;
    ASSERT_TRUE(parseCoordinateType("local_mvc", type));
    EXPECT_EQ(type, LOCAL_MEAN_VALUE);
    ASSERT_TRUE(parseCoordinateType("local_mean_value", type));
    EXPECT_EQ(type, LOCAL_MEAN_VALUE);
    EXPECT_STREQ(coordinateTypeName(LOCAL_MEAN_VALUE), "local_mvc");
    Multicage cage = nestedCage();
    cage.setCoordinates(LOCAL_MEAN_VALUE);
    FileStorage out(".yml", FileStorage::WRITE | FileStorage::MEMORY);
    cage.write(out);
    const std::string text = out.releaseAndGetString();
    EXPECT_NE(text.find("coordinates: local_mean_value"), std::string::npos) << text;
    FileStorage in(text, FileStorage::READ | FileStorage::MEMORY);
    Multicage back;
    back.read(in.root());
    EXPECT_EQ(back.coordinates(), LOCAL_MEAN_VALUE);
    // The default binding of such a cage is local.
    EXPECT_EQ(bind(back, COORDINATES_FROM_CAGE, 8).coordinates, LOCAL_MEAN_VALUE);
}

// The pull kernel (mesh_pull.cpp) against the rasteriser. Where a binding's mesh folds nowhere the
// CPU backend finds each pixel's triangle instead of drawing every triangle: it must cover the
// same pixels with the same rest points, within float rounding. Where the mesh folds, a node is
// not finite, the frame is not convex, or the frame runs through pixel centres, the rasteriser
// decides, bit for bit.
#include "mesh_pull.hpp"

#include <cstdlib>
#include <cstring>
#include <functional>
#include <opencv2/multicage/internal/cpu_dispatch.hpp>

#include "cpu_deformer.hpp"
#include "testing.hpp"

using namespace cv;
using namespace cv::multicage;
using multicage_testing::compareMaps;
using multicage_testing::MapAgreement;
using multicage_testing::sameBits;

namespace {

struct Maps {
    Mat x, y;
    bool pulled = false;  // RasterMesh::pulls() before drawing
};

// The maps of a pose of a binding, pulled where the mesh lets it (pull) or drawn; `edit` may
// change the nodes (ring included) before they are drawn, `frame` replace the pose's frame.
Maps drawMaps(const Binding& b, const std::vector<Point2f>& pose, bool pull,
              const std::vector<Point2f>& frame = {},
              const std::function<void(Mat& nodes)>& edit = {}) {
    RasterMesh mesh;
    mesh.reset(b);
    std::vector<Point2f> v = b.completePose(pose);
    if (!frame.empty()) std::copy(frame.begin(), frame.end(), v.end() - 4);
    Mat nodes = mesh.nodes();
    b.apply(v, nodes);
    const Point2f* corners = &v[v.size() - 4];
    mesh.setFrame(corners);
    mesh.setOutputSize(frameOutputSize(corners, b.imageSize));
    if (edit) {
        Mat whole = nodes;  // the view's parent: the mesh with its ring
        Size parent;
        Point offset;
        whole.locateROI(parent, offset);
        whole.adjustROI(offset.y, parent.height - offset.y - nodes.rows, offset.x,
                        parent.width - offset.x - nodes.cols);
        edit(whole);
    }
    mesh.setPullPreferred(pull);
    Maps m;
    m.pulled = mesh.pulls();
    m.x.create(mesh.outputSize(), CV_32F);
    m.y.create(mesh.outputSize(), CV_32F);
    mesh.draw(m.x, m.y);
    return m;
}

// Both maps of a pose against the rasteriser's (compareMaps): pixels covered by one only, and the
// largest difference in float roundings.
MapAgreement compare(const Maps& a, const Maps& ref) {
    const MapAgreement x = compareMaps(a.x, ref.x, kUncovered);
    const MapAgreement y = compareMaps(a.y, ref.y, kUncovered);
    return {x.coverage + y.coverage, std::max(x.roundings, y.roundings)};
}

}  // namespace

// Smooth poses of the paper's lotus multicage, grid steps 1 and 2, rows of 97 and 33 px (part-
// filled vectors of 16 pixels) and a frame moved as content-aware resizing moves it.
TEST(MeshPull, PulledMapsAreTheRastersWithinFloatRounding) {
    if (!raster::havePullKernel())
        GTEST_SKIP() << "no pull kernel here (AVX2 or AVX-512): every mesh is drawn";
    int pulledCases = 0;
    for (const Size size : {Size(320, 240), Size(97, 33), Size(33, 120)}) {
        const Multicage cage = multicage_fixtures::lotusMulticage(size, 24);
        for (int step : {1, 2}) {
            const Binding b = bind(cage, MEAN_VALUE, step);
            for (float amplitude : {0.f, 1.5f, 4.f}) {
                const std::vector<Point2f> wave =
                    multicage_fixtures::wavePose(cage, amplitude, 0.7f);
                // The same wave in an image 5/4 as wide, as content-aware resizing poses it: every
                // vertex and the frame stretched together.
                const Size wider(size.width * 5 / 4, size.height);
                std::vector<Point2f> stretched = wave;
                for (Point2f& v : stretched) v.x = (v.x + 0.5f) * wider.width / size.width - 0.5f;
                const std::array<Point2f, 4> wide = frameCorners(wider);
                for (const std::vector<Point2f>& frame :
                     {std::vector<Point2f>{}, std::vector<Point2f>(wide.begin(), wide.end())}) {
                    const std::vector<Point2f>& pose = frame.empty() ? wave : stretched;
                    const Maps pulled = drawMaps(b, pose, true, frame);
                    const Maps drawn = drawMaps(b, pose, false, frame);
                    const std::string what =
                        format("%dx%d step %d amplitude %.1f%s", size.width, size.height, step,
                               amplitude, frame.empty() ? "" : " resize frame");
                    ASSERT_FALSE(drawn.pulled) << what;
                    ASSERT_EQ(pulled.x.size(), drawn.x.size()) << what;
                    if (!pulled.pulled) continue;  // folded: drawn (checked below)
                    ++pulledCases;
                    const MapAgreement a = compare(pulled, drawn);
                    EXPECT_EQ(a.coverage, 0) << what << ": pixels covered by one map only";
                    EXPECT_LE(a.roundings, 4.0) << what;
                }
            }
        }
    }
    EXPECT_GE(pulledCases, 30) << "the pull kernel was hardly used: the test would prove nothing";
}

// Where the CPU has AVX-512, the AVX2 walk (what CPUs without it run) against the AVX-512 one on
// the poses above: the same pixels covered, and each pixel in the same triangle, so the same
// values, but where a pixel on an edge shared by two triangles settles in the other, or a band
// one kernel could not pull is drawn (the guesses of pixels outside the frame differ: each
// goes on with its own vector's walk): within the float roundings the pull keeps to the raster.
TEST(MeshPull, TheAvx2WalkFindsWhatTheAvx512WalkFinds) {
    if (std::string(raster::pullKernelName()) != "AVX-512")
        GTEST_SKIP() << "no AVX-512 here: only the " << raster::pullKernelName() << " walk";
    int cases = 0;
    for (const Size size : {Size(320, 240), Size(97, 33)}) {
        const Multicage cage = multicage_fixtures::lotusMulticage(size, 24);
        for (int step : {1, 2})
            for (float amplitude : {0.f, 1.5f, 4.f}) {
                const Binding b = bind(cage, MEAN_VALUE, step);
                const std::vector<Point2f> pose =
                    multicage_fixtures::wavePose(cage, amplitude, 0.7f);
                const Maps wide = drawMaps(b, pose, true);
                raster::preferAvx2Pull(true);
                const Maps narrow = drawMaps(b, pose, true);
                raster::preferAvx2Pull(false);
                if (!wide.pulled) continue;
                ++cases;
                const MapAgreement a = compare(narrow, wide);
                const std::string what = format("%dx%d step %d amplitude %.1f", size.width,
                                                size.height, step, amplitude);
                EXPECT_EQ(a.coverage, 0) << what;
                EXPECT_LE(a.roundings, 4.0) << what;
            }
    }
    EXPECT_GE(cases, 6);
}

// What the pull kernel must leave to the rasteriser, and then gives the rasteriser's bits.
TEST(MeshPull, FoldsBadNodesAndOddFramesAreDrawnBitForBit) {
    if (!raster::havePullKernel())
        GTEST_SKIP() << "no pull kernel here (AVX2 or AVX-512): every mesh is drawn";
    const Size size(97, 64);
    const Multicage cage = multicage_fixtures::lotusMulticage(size, 24);
    const Binding b = bind(cage, MEAN_VALUE, 1);
    const std::vector<Point2f> smooth = multicage_fixtures::wavePose(cage, 2.f, 0.3f);
    ASSERT_TRUE(drawMaps(b, smooth, true).pulled) << "the smooth pose itself must be pullable";

    struct Case {
        const char* what;
        std::vector<Point2f> pose, frame;
        std::function<void(Mat&)> edit;
        bool pullable;  // RasterMesh::pulls() (the band may still be drawn)
    };
    const std::vector<Point2f> foldedFrame = {
        {-0.5f, -0.5f}, {size.width - 0.5f, -0.5f}, {20.f, 30.f}, {-0.5f, size.height - 0.5f}};
    const std::vector<Point2f> throughCentres = {{0.f, 0.f},
                                                 {size.width - 1.f, 0.f},
                                                 {size.width - 1.f, size.height - 1.f},
                                                 {0.f, size.height - 1.f}};
    const Case cases[] = {
        {"a folded pose", multicage_fixtures::wavePose(cage, 30.f, 0.3f), {}, {}, false},
        {"one node swapped with its neighbour",
         smooth,
         {},
         [](Mat& n) { std::swap(n.at<Point2f>(30, 40), n.at<Point2f>(30, 41)); },
         false},
        {"a NaN node", smooth, {}, [](Mat& n) { n.at<Point2f>(10, 10).x = NAN; }, false},
        {"an infinite node", smooth, {}, [](Mat& n) { n.at<Point2f>(12, 50).y = INFINITY; }, false},
        {"a node 1e30 px away", smooth, {}, [](Mat& n) { n.at<Point2f>(40, 5).x = 1e30f; }, false},
        {"a concave frame", smooth, foldedFrame, {}, false},
        // convex and fold-free, but its edges run through pixel centres: pulled, and those
        // pixels covered as the rasteriser's edge tolerance covers them
        {"a frame through pixel centres", smooth, throughCentres, {}, true},
    };
    for (const Case& c : cases) {
        const Maps pulled = drawMaps(b, c.pose, true, c.frame, c.edit);
        const Maps drawn = drawMaps(b, c.pose, false, c.frame, c.edit);
        EXPECT_EQ(pulled.pulled, c.pullable) << c.what;
        if (c.pullable) {
            const MapAgreement a = compare(pulled, drawn);
            EXPECT_EQ(a.coverage, 0) << c.what << ": pixels covered by one map only";
            EXPECT_LE(a.roundings, 4.0) << c.what;
            continue;
        }
        EXPECT_TRUE(sameBits(pulled.x, drawn.x)) << c.what << ": mapx is not the rasteriser's";
        EXPECT_TRUE(sameBits(pulled.y, drawn.y)) << c.what << ": mapy is not the rasteriser's";
    }
}

// The pull kernel is not used where it does not pay (grid steps above 2) or for meshes that are not
// a binding's regular grid (rasterizeMaps, the reference of raster_reference_test).
TEST(MeshPull, OnlyBindingsOfSmallSteps) {
    const Size size(120, 80);
    const Multicage cage = multicage_fixtures::lotusMulticage(size, 16);
    const std::vector<Point2f> pose = multicage_fixtures::wavePose(cage, 1.f, 0.f);
    EXPECT_EQ(drawMaps(bind(cage, MEAN_VALUE, 2), pose, true).pulled, raster::havePullKernel());
    EXPECT_FALSE(drawMaps(bind(cage, MEAN_VALUE, 4), pose, true).pulled);
    const Binding b = bind(cage, MEAN_VALUE, 1);
    RasterMesh general;
    general.reset(b.nodes(), size);
    Mat nodes = general.nodes();
    b.apply(pose, nodes);
    general.setFrame(nullptr);
    EXPECT_FALSE(general.pulls());
}

// Where a pixel lies on an edge two cells share, the walk settles it in whichever cell it reaches
// first, and the two may give values a rounding apart: that choice must not depend on how the
// rows were split into bands (4 per thread), or the bits would depend on the thread count. A pose
// moving vertices along x only leaves every node on its row, so every pixel lies on such an edge.
TEST(MeshPull, TheSameBitsHoweverTheRowsAreSplit) {
    if (!raster::havePullKernel())
        GTEST_SKIP() << "no pull kernel here (AVX2 or AVX-512): every mesh is drawn";
    const Size size(301, 203);
    const Multicage cage = multicage_fixtures::lotusMulticage(size, 24);
    std::vector<Point2f> pose = multicage_fixtures::wavePose(cage, 3.f, 0.4f);
    const std::vector<Point2f> rest = cage.vertices();
    for (size_t i = 0; i < pose.size(); ++i) pose[i].y = rest[i].y;
    for (int step : {1, 2}) {
        const Binding b = bind(cage, MEAN_VALUE, step);
        Mat mesh;  // the nodes with their ring, as RasterMesh holds them
        ASSERT_TRUE(drawMaps(b, pose, true, {}, [&](Mat& whole) { mesh = whole.clone(); }).pulled);
        const raster::PullMesh pull{mesh.ptr<Point2f>(),
                                    mesh.cols,
                                    mesh.rows,
                                    b.gridSize,
                                    float(step),
                                    Point2f(0, 0),
                                    Point2f(size.width - 1.f, size.height - 1.f)};
        auto pulled = [&](const std::vector<int>& cuts, Mat& mapx, Mat& mapy) {
            mapx.create(size, CV_32F), mapy.create(size, CV_32F);
            for (size_t i = 0; i + 1 < cuts.size(); ++i)
                ASSERT_TRUE(raster::pullRows(pull, cuts[i], cuts[i + 1], mapx, mapy));
        };
        Mat wholeX, wholeY;
        pulled({0, size.height}, wholeX, wholeY);
        for (const std::vector<int>& cuts :
             {std::vector<int>{0, 16, 64, 80, size.height}, {0, 48, 96, 192, size.height}}) {
            Mat x, y;
            pulled(cuts, x, y);
            EXPECT_TRUE(sameBits(x, wholeX)) << "step " << step << ", split at " << cuts[1];
            EXPECT_TRUE(sameBits(y, wholeY)) << "step " << step << ", split at " << cuts[1];
        }
    }
}

// RasterMesh::pose checks for folds while Binding::apply writes the nodes, block by block of rows
// (applyRows), and the cell rows no block holds whole afterwards: the ring's, and those across two
// blocks. A fold in any one cell row must be found, wherever the blocks begin. One node of the
// binding is given a coefficient of 60 on one vertex, and that vertex moved 1 px: the node moves
// 60 px up or down, past its neighbour row, and every triangle it shares with that row flips (the
// ones on its other side only stretch). So each node row, moved each way, folds exactly one cell
// row: every cell row of the mesh, ring rows included, is the only fold of some case.
TEST(MeshPull, PoseFindsAFoldInEveryCellRow) {
    if (!raster::havePullKernel())
        GTEST_SKIP() << "no pull kernel here (AVX2 or AVX-512): every mesh is drawn";
    const Size size(41, 37);
    const Multicage cage = multicage_fixtures::lotusMulticage(size, 24);
    const Binding b = bind(cage, MEAN_VALUE, 1);
    const int j = 0;  // the vertex moved
    std::vector<Point2f> pose = b.completePose(cage.vertices());
    auto posed = [&](const Binding& binding) {
        RasterMesh mesh;
        mesh.reset(binding);
        mesh.pose(binding, pose);
        return mesh;
    };
    // The nodes written through nodes() instead: pulls() then reads every node back.
    auto written = [&](const Binding& binding) {
        RasterMesh mesh;
        mesh.reset(binding);
        Mat nodes = mesh.nodes();
        binding.apply(pose, nodes);
        mesh.setFrame(&pose[pose.size() - 4]);
        return mesh;
    };
    pose[j] += Point2f(0.f, 1.f);
    ASSERT_TRUE(posed(b).pulls()) << "moving one vertex 1 px folds nothing by itself";
    int folds = 0;
    for (int gy = 0; gy < b.gridSize.height; ++gy)
        for (float dy : {1.f, -1.f}) {
            Binding boosted = b;
            boosted.coefficients = b.coefficients.clone();
            boosted.coefficients.at<float>(j, gy * b.gridSize.width + b.gridSize.width / 2) = 60.f;
            pose[j] = cage.vertices()[j] + Point2f(0.f, dy);
            const bool pulls = posed(boosted).pulls();
            EXPECT_EQ(pulls, written(boosted).pulls()) << "node row " << gy << " moved " << dy;
            EXPECT_FALSE(pulls) << "node row " << gy << " moved " << 60 * dy << " px";
            folds += !pulls;
        }
    EXPECT_EQ(folds, 2 * b.gridSize.height);
}

// What pose() found about folds holds for that pose only: a mesh made again, or nodes written
// through nodes(), or a new frame, is checked again when drawn.
TEST(MeshPull, WhatPoseFoundIsForgottenWhenTheMeshChanges) {
    if (!raster::havePullKernel())
        GTEST_SKIP() << "no pull kernel here (AVX2 or AVX-512): every mesh is drawn";
    const Size size(64, 48);
    const Multicage cage = multicage_fixtures::lotusMulticage(size, 24);
    const Binding b = bind(cage, MEAN_VALUE, 1);
    const std::vector<Point2f> smooth =
        b.completePose(multicage_fixtures::wavePose(cage, 1.f, 0.f));
    RasterMesh mesh;
    mesh.reset(b);
    mesh.pose(b, smooth);
    ASSERT_TRUE(mesh.pulls());
    mesh.reset(b);  // every node at 0: nothing is pullable
    EXPECT_FALSE(mesh.pulls());
    mesh.pose(b, smooth);
    mesh.nodes().at<Point2f>(10, 10) = Point2f(NAN, 0.f);
    EXPECT_FALSE(mesh.pulls());
    mesh.pose(b, smooth);
    const Point2f concave[4] = {{-0.5f, -0.5f}, {63.5f, -0.5f}, {20.f, 20.f}, {-0.5f, 47.5f}};
    mesh.setFrame(concave);
    EXPECT_FALSE(mesh.pulls());
}

// The fold check (raster::positiveRows) against its rule restated here: a triangle is clearly
// positive when cross(e1, e2) > 1e-4 (|e1.x e2.y| + |e1.y e2.x|) in float. Meshes of 2 rows and
// 2 to 40 cells (every lane of a vector of 8 or 16 cells, and the scalar tail), each with one
// cell made a sliver, folded or NaN, or none: the AVX2 kernel (and AVX-512 where there is one)
// gives the rule's answer.
TEST(MeshPull, TheFoldCheckFollowsItsRuleOnEveryKernel) {
    if (!raster::havePullKernel()) GTEST_SKIP() << "no pull kernel here: no fold check is asked";
    auto clearlyPositive = [](float e1x, float e1y, float e2x, float e2y) {
        const float l = e1x * e2y, r = e1y * e2x;
        return l - r > 1e-4f * (std::abs(l) + std::abs(r));
    };
    RNG rng(17);
    int cases = 0, folded = 0;
    for (bool avx2 : {false, true}) {
        raster::preferAvx2Pull(avx2);
        for (int cells = 1; cells <= 40; ++cells)
            for (int bad = -1; bad < cells; ++bad)
                for (int kind = 0; kind < 3; ++kind) {
                    Mat nodes(2, cells + 1, CV_32FC2);
                    for (int y = 0; y < 2; ++y)
                        for (int x = 0; x <= cells; ++x)
                            nodes.at<Point2f>(y, x) =
                                Point2f(x + rng.uniform(-0.2f, 0.2f), y + rng.uniform(-0.2f, 0.2f));
                    if (bad >= 0) {
                        Point2f& b = nodes.at<Point2f>(0, bad + 1);
                        const Point2f a = nodes.at<Point2f>(0, bad), c = nodes.at<Point2f>(1, bad);
                        if (kind == 0) b = a + (c - a) * 0.5f + Point2f(1e-6f, 0.f);  // a sliver
                        if (kind == 1) b.x = a.x - 0.5f;                              // folded
                        if (kind == 2) b.y = NAN;
                    }
                    bool expected = true;
                    for (int k = 0; k < cells; ++k) {
                        const Point2f a = nodes.at<Point2f>(0, k), b = nodes.at<Point2f>(0, k + 1),
                                      c = nodes.at<Point2f>(1, k), d = nodes.at<Point2f>(1, k + 1);
                        expected = expected &&
                                   clearlyPositive(b.x - a.x, b.y - a.y, c.x - a.x, c.y - a.y) &&
                                   clearlyPositive(d.x - b.x, d.y - b.y, c.x - b.x, c.y - b.y);
                    }
                    const raster::PullMesh mesh{nodes.ptr<Point2f>(),
                                                cells + 1,
                                                2,
                                                Size(cells - 1, 0),
                                                1.f,
                                                Point2f(),
                                                Point2f()};
                    EXPECT_EQ(raster::positiveRows(mesh, 0, 1), expected)
                        << raster::pullKernelName() << ": " << cells << " cells, cell " << bad
                        << " kind " << kind;
                    ++cases, folded += !expected;
                }
    }
    raster::preferAvx2Pull(false);
    EXPECT_GT(folded, cases / 2) << "most cases should have a bad cell";
    EXPECT_LT(folded, cases) << "and some none";
}

// MULTICAGE_CPU caps the kernels (internal/cpu_dispatch.hpp), so that a machine with AVX-512 runs
// and times the AVX2 and portable ones end to end too: the deform tests run again under each cap
// (tests/deform/CMakeLists.txt, DeformKernels.*), and this checks the cap took hold there.
TEST(CpuLevel, TheEnvironmentCapsTheKernels) {
    const char* cap = std::getenv("MULTICAGE_CPU");
    if (!cap) GTEST_SKIP() << "MULTICAGE_CPU unset: the CPU's own kernels";
    if (std::strcmp(cap, "baseline") == 0) {
        EXPECT_FALSE(cpuHasX86_64_v3());
        EXPECT_FALSE(cpuHasX86_64_v4());
        EXPECT_FALSE(raster::havePullKernel());
        EXPECT_STREQ(raster::pullKernelName(), "none");
    } else if (std::strcmp(cap, "avx2") == 0) {
        EXPECT_FALSE(cpuHasX86_64_v4());
        EXPECT_STRNE(raster::pullKernelName(), "AVX-512");
        if (cpuHasX86_64_v3()) EXPECT_STREQ(raster::pullKernelName(), "AVX2");
    }
}

// DeformParams::mapStep (mesh_lattice.hpp): inverse maps found on a lattice and interpolated
// where the pose folds nowhere, drawn at every pixel where it folds.
#include <opencv2/imgproc.hpp>
#include <opencv2/multicage/augment.hpp>
#include <opencv2/multicage/internal/backend_contract.hpp>

#include "mesh_pull.hpp"
#include "testing.hpp"

using namespace cv;
using namespace cv::multicage;
using multicage_testing::compareMaps;
using multicage_testing::sameBits;

namespace {

struct LatticeMaps {
    Mat x, y;
};

LatticeMaps mapsOf(Deformer& d, const std::vector<Point2f>& pose) {
    LatticeMaps m;
    d.computeMaps(pose, m.x, m.y);
    return m;
}

Ptr<Deformer> cpuDeformer(const Mat& image, const Binding& b, int mapStep) {
    DeformParams p;
    p.backend = BACKEND_CPU;
    p.mapStep = mapStep;
    return Deformer::create(image, b, p);
}

// Distances between two pairs of maps, pixel by pixel (both covered everywhere).
Mat distances(const LatticeMaps& a, const LatticeMaps& b) {
    Mat dx = a.x - b.x, dy = a.y - b.y, d;
    magnitude(dx, dy, d);
    return d;
}

// A map's pixels at multiples of `step` in x and y: the lattice's points where its spans are
// multiples of the step.
Mat everyStep(const Mat& map, int step) {
    Mat out((map.rows - 1) / step + 1, (map.cols - 1) / step + 1, CV_32F);
    for (int j = 0; j < out.rows; ++j)
        for (int i = 0; i < out.cols; ++i) out.at<float>(j, i) = map.at<float>(j * step, i * step);
    return out;
}

// Every vertex and frame corner (Multicage::vertices) through the same affine map about the
// image centre.
std::vector<Point2f> affinePose(const Multicage& cage, Size size, const Matx22f& A, Point2f t) {
    const Point2f c((size.width - 1) / 2.f, (size.height - 1) / 2.f);
    std::vector<Point2f> pose = cage.vertices();
    for (Point2f& v : pose) v = c + A * (v - c) + t;
    return pose;
}

}  // namespace

// Linear precision: where the pose is affine, so is the mesh and its inverse, and bilinear
// interpolation of an affine map is the map itself: the lattice's maps are the exact ones
// within float rounding at every pixel, whatever the spacing (sizes whose border-to-border
// span is and is not a multiple of the step). The map enlarges a little, so that the moved
// frame still holds every pixel (latticeFits).
TEST(MapLattice, AnAffinePoseIsInterpolatedExactly) {
    if (!raster::havePullKernel()) GTEST_SKIP() << "no pull kernel here: every pixel is drawn";
    for (const Size size : {Size(161, 121), Size(97, 33), Size(40, 130)}) {
        const Multicage cage = multicage_fixtures::lotusMulticage(size, 24);
        const Mat image(size, CV_8UC3, Scalar(1, 2, 3));
        for (int grid : {1, 4}) {
            const Binding b = bind(cage, MEAN_VALUE, grid);
            const std::vector<Point2f> pose =
                affinePose(cage, size, Matx22f(1.06f, 0.01f, -0.01f, 1.05f), Point2f(0.2f, -0.1f));
            const LatticeMaps exact = mapsOf(*cpuDeformer(image, b, 1), pose);
            for (int step : {2, 4, 7}) {
                const LatticeMaps lattice = mapsOf(*cpuDeformer(image, b, step), pose);
                const std::string what =
                    format("%dx%d grid step %d map step %d", size.width, size.height, grid, step);
                const auto ax = compareMaps(lattice.x, exact.x, kUncovered);
                const auto ay = compareMaps(lattice.y, exact.y, kUncovered);
                EXPECT_EQ(ax.coverage + ay.coverage, 0) << what << ": pixels covered by one only";
                double worst = 0;
                minMaxLoc(distances(lattice, exact), nullptr, &worst);
                EXPECT_LT(worst, 1e-3) << what;
            }
        }
    }
}

// Random poses as augmentation draws them: the lattice's maps are the exact ones at the lattice
// points (a span that is a multiple of the step puts them on pixels), and elsewhere off by the
// bend of the map across triangle edges, the kind of error the grid step itself makes: on
// average a few thousandths of a pixel, and the deformed images 50 dB and more apart.
TEST(MapLattice, RandomPosesStayWithinTheGridStepsOwnError) {
    if (!raster::havePullKernel()) GTEST_SKIP() << "no pull kernel here: every pixel is drawn";
    const Size size(257, 193);  // spans of 256 and 192 px: lattice points every 4 px on pixels
    const Multicage cage = multicage_fixtures::lotusMulticage(size, 30);
    Mat image(size, CV_8UC3);
    randu(image, Scalar::all(0), Scalar::all(255));
    GaussianBlur(image, image, Size(), 2.0);  // detail at the scale of a photograph's
    const Binding fine = bind(cage, MEAN_VALUE, 1);
    int compared = 0;
    for (int grid : {2, 4}) {
        const Binding b = bind(cage, MEAN_VALUE, grid);
        Ptr<Deformer> exact = cpuDeformer(image, b, 1), lattice = cpuDeformer(image, b, grid);
        Ptr<Deformer> paper = cpuDeformer(image, fine, 1);
        RNG rng(11);
        for (int k = 0; k < 6; ++k) {
            const std::vector<Point2f> pose = randomPose(cage, 6.0, rng);
            const std::string what = format("grid step %d pose %d", grid, k);
            const LatticeMaps e = mapsOf(*exact, pose), l = mapsOf(*lattice, pose),
                              f = mapsOf(*paper, pose);
            ASSERT_EQ(exact->foldedTriangles(pose), 0) << what;
            ++compared;
            // At the lattice points: the pull's values, within a few float roundings of the
            // raster's (8: the pull walks cells of one lattice unit, the raster of 4 pixels).
            EXPECT_LE(compareMaps(everyStep(l.x, grid), everyStep(e.x, grid), kUncovered).roundings,
                      8.0)
                << what;
            EXPECT_LE(compareMaps(everyStep(l.y, grid), everyStep(e.y, grid), kUncovered).roundings,
                      8.0)
                << what;
            // Everywhere: no worse on average than twice the grid step's own distance from the
            // paper's grid step 1, and a few thousandths of a pixel.
            const double own = mean(distances(e, f))[0], off = mean(distances(l, e))[0];
            EXPECT_LT(off, 2 * own + 1e-4) << what << " (grid step's own " << own << ")";
            EXPECT_LT(off, 0.01) << what;
            Mat a, c;
            exact->deform(pose, a);
            lattice->deform(pose, c);
            EXPECT_GT(PSNR(a, c), 50.0) << what;
        }
    }
    EXPECT_EQ(compared, 12);
}

// A pose that folds the mesh has no continuous inverse to interpolate, and a frame moved inwards
// leaves pixels uncovered: both are drawn at every pixel, the bits of map step 1.
TEST(MapLattice, FoldsAndUncoveredPixelsAreDrawnAtEveryPixel) {
    const Size size(97, 64);
    const Multicage cage = multicage_fixtures::lotusMulticage(size, 24);
    const Mat image(size, CV_8UC1, Scalar(9));
    const Binding b = bind(cage, MEAN_VALUE, 2);
    const std::vector<Point2f> folded = multicage_fixtures::wavePose(cage, 30.f, 0.3f);
    std::vector<Point2f> shrunk = cage.vertices();  // the frame last, 2 px in on every side
    const Point2f c((size.width - 1) / 2.f, (size.height - 1) / 2.f);
    for (Point2f& v : shrunk) v = c + (v - c) * (1.f - 4.f / size.height);
    Ptr<Deformer> exact = cpuDeformer(image, b, 1), lattice = cpuDeformer(image, b, 4);
    ASSERT_GT(exact->foldedTriangles(folded), 0);
    ASSERT_EQ(exact->foldedTriangles(shrunk), 0);
    for (int k = 0; k < 2; ++k) {
        const std::vector<Point2f>& pose = k == 0 ? folded : shrunk;
        const std::string what = k == 0 ? "folded" : "frame moved inwards";
        const LatticeMaps e = mapsOf(*exact, pose), l = mapsOf(*lattice, pose);
        EXPECT_TRUE(sameBits(l.x, e.x)) << what;
        EXPECT_TRUE(sameBits(l.y, e.y)) << what;
    }
    Mat uncovered = mapsOf(*exact, shrunk).x == kUncovered;
    EXPECT_GT(countNonZero(uncovered), 0) << "the shrunk frame should leave pixels uncovered";
}

// A batch with a map step gives what deform gives one at a time (each worker's mesh has it),
// and a resize pose (another output size) is interpolated over its own frame.
TEST(MapLattice, BatchesAndResizePosesUseTheLattice) {
    if (!raster::havePullKernel()) GTEST_SKIP() << "no pull kernel here: every pixel is drawn";
    const Size size(200, 150);
    const Multicage cage = multicage_fixtures::lotusMulticage(size, 24);
    Mat image(size, CV_8UC3);
    randu(image, Scalar::all(0), Scalar::all(255));
    const Binding b = bind(cage, MEAN_VALUE, 4);
    Ptr<Deformer> exact = cpuDeformer(image, b, 1), lattice = cpuDeformer(image, b, 4);
    RNG rng(5);
    std::vector<std::vector<Point2f>> poses;
    for (int k = 0; k < 6; ++k) poses.push_back(randomPose(cage, 5.0, rng));
    std::vector<Mat> batch;
    lattice->deformBatch(poses, batch);
    ASSERT_EQ(batch.size(), poses.size());
    for (size_t k = 0; k < poses.size(); ++k) {
        Mat one, drawn;
        lattice->deform(poses[k], one);
        exact->deform(poses[k], drawn);
        EXPECT_TRUE(sameBits(batch[k], one)) << "item " << k;
        EXPECT_FALSE(sameBits(one, drawn)) << "item " << k << ": the lattice was not used";
    }
    // A resize pose: the frame (and every vertex with it) stretched to 5/4 of the width.
    const Size wider(size.width * 5 / 4, size.height);
    std::vector<Point2f> stretched = b.completePose(poses[0]);
    for (Point2f& v : stretched) v.x = (v.x + 0.5f) * wider.width / size.width - 0.5f;
    const LatticeMaps e = mapsOf(*exact, stretched), l = mapsOf(*lattice, stretched);
    ASSERT_EQ(l.x.size(), wider);
    EXPECT_EQ(compareMaps(l.x, e.x, kUncovered).coverage, 0);
    EXPECT_LT(mean(distances(l, e))[0], 0.01);
}

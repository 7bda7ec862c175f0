// Harmonic coordinates of a multicage on the node grid (DeRose & Meyer 2006).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "testing.hpp"

using namespace cv;
using namespace cv::multicage;

namespace {

struct Errors {
    double partition = 0;  // max |sum_j CC_j - 1|
    double position = 0;   // max |sum_j CC_j v_j - x|
    double minimum = 1;    // min_j CC_j
    double maximum = 0;    // max_j CC_j
};

Errors measure(const Binding& b) {
    const int c = b.coefficientCount(), N = b.nodeCount(), m = b.gridSize.width;
    std::vector<double> sum(N, 0.0), x(N, 0.0), y(N, 0.0);
    Errors e;
    for (int j = 0; j < c; ++j) {
        const float* cc = b.coefficients.ptr<float>(j);
        const Point2d v = b.restVertices[j];
        for (int k = 0; k < N; ++k) {
            sum[k] += cc[k], x[k] += cc[k] * v.x, y[k] += cc[k] * v.y;
            e.minimum = std::min(e.minimum, double(cc[k]));
            e.maximum = std::max(e.maximum, double(cc[k]));
        }
    }
    for (int k = 0; k < N; ++k) {
        const Point2f node = b.node(k % m, k / m);
        e.partition = std::max(e.partition, std::abs(sum[k] - 1.0));
        e.position = std::max(e.position, std::hypot(x[k] - node.x, y[k] - node.y));
    }
    return e;
}

float coefficient(const Binding& b, int j, int gx, int gy) {
    return b.coefficients.at<float>(j, gy * b.gridSize.width + gx);
}

// Index of the innermost user polygon strictly containing point p (by more than `margin`
// pixels), or -1 for the outer region. Nested polygons have greater depth.
int innermost(const Multicage& cage, Point2f p, double margin) {
    int best = -1;
    for (int i = 0; i < cage.polygonCount(); ++i)
        if (pointPolygonTest(cage.polygon(i), p, true) > margin &&
            (best < 0 || cage.depth(i) > cage.depth(best)))
            best = i;
    return best;
}

// Polygon i's children: the polygons directly inside it (-1: those directly in the frame).
std::vector<int> children(const Multicage& cage, int i) {
    std::vector<int> out;
    for (int q = 0; q < cage.polygonCount(); ++q) {
        if (q == i) continue;
        const bool inside =
            i < 0 || pointPolygonTest(cage.polygon(i), cage.polygon(q)[0], false) > 0;
        if (inside && cage.depth(q) == (i < 0 ? 1 : cage.depth(i) + 1)) out.push_back(q);
    }
    return out;
}

// Locality: every node off the edges has zero coefficients for all vertices except those of
// the polygons bounding its region (its innermost polygon and that polygon's children; the
// frame and the top-level polygons outside them all). Returns {nodes checked, inside some polygon}.
std::pair<int, int> expectLocality(const Multicage& cage, const Binding& b,
                                   const std::string& what) {
    const int c = b.coefficientCount();
    std::vector<std::vector<bool>> allowed(cage.polygonCount() + 1, std::vector<bool>(c, false));
    for (int p = -1; p < cage.polygonCount(); ++p) {
        std::vector<int> bounding = children(cage, p);
        std::vector<bool>& ok = allowed[p + 1];
        if (p >= 0)
            bounding.push_back(p);
        else
            for (int j = c - 4; j < c; ++j) ok[j] = true;
        for (int q : bounding)
            for (size_t v = 0; v < cage.polygon(q).size(); ++v)
                ok[cage.polygonOffset(q) + v] = true;
    }
    int checked = 0, inner = 0;
    for (int gy = 0; gy < b.gridSize.height; ++gy)
        for (int gx = 0; gx < b.gridSize.width; ++gx) {
            const Point2f x = b.node(gx, gy);
            const int region = innermost(cage, x, 1e-3);
            // Skip nodes on or within 1e-3 of an edge: they belong to the edge.
            bool onEdge = false;
            for (int q = 0; q < cage.polygonCount(); ++q)
                onEdge = onEdge || std::abs(pointPolygonTest(cage.polygon(q), x, true)) <= 1e-3;
            if (onEdge) continue;
            ++checked, inner += region >= 0;
            for (int j = 0; j < c; ++j)
                if (!allowed[region + 1][j]) {
                    EXPECT_EQ(coefficient(b, j, gx, gy), 0.f)
                        << what << ": node " << x << " in polygon " << region << " sees vertex "
                        << j;
                    if (coefficient(b, j, gx, gy) != 0.f) return {checked, inner};
                }
        }
    return {checked, inner};
}

}  // namespace

TEST(Harmonic, BindReturnsAHarmonicBinding) {
    const Multicage cage = multicage_testing::butterflyCage(true);
    const Binding b = bind(cage, HARMONIC, 3);
    EXPECT_EQ(b.coordinates, HARMONIC);
    EXPECT_EQ(b.imageSize, cage.imageSize());
    EXPECT_EQ(b.gridStep, 3);
    EXPECT_EQ(b.gridSize, gridSizeFor(cage.imageSize(), 3));
    EXPECT_EQ(b.restVertices, cage.vertices());
    EXPECT_EQ(b.minConditioning, 1.0);
    ASSERT_EQ(b.coefficients.type(), CV_32F);
    ASSERT_EQ(b.coefficients.size(), Size(b.nodeCount(), b.coefficientCount()));
    EXPECT_TRUE(checkRange(b.coefficients));
}

TEST(Harmonic, PartitionOfUnityAndNonNegativityOnRandomMulticages) {
    RNG rng(61);
    for (int trial = 0; trial < 10; ++trial) {
        // Odd sizes and steps: the last row and column are closer than the grid step.
        const Size size(rng.uniform(40, 301), rng.uniform(40, 301));
        const Multicage cage = multicage_fixtures::randomMulticage(rng, size, 3, 3, 10);
        ASSERT_TRUE(cage.validate());
        const int step = rng.uniform(1, 5);
        const Errors e = measure(bind(cage, HARMONIC, step));
        EXPECT_LE(e.partition, 1e-5) << "trial " << trial << " " << size << " step " << step;
        EXPECT_GE(e.minimum, 0.0) << "trial " << trial;
        EXPECT_LE(e.maximum, 1.0) << "trial " << trial;
        EXPECT_LE(e.position, 1e-3) << "trial " << trial;
    }
}

TEST(Harmonic, LinearPrecisionOn512Grid) {
    RNG rng(512);
    const Multicage cage = multicage_fixtures::randomMulticage(rng, Size(512, 512), 3, 3, 16);
    ASSERT_TRUE(cage.validate());
    const Binding b = bind(cage, HARMONIC, 1);
    const Errors e = measure(b);
    std::printf(
        "[ measured ] 512x512 step 1: max |sum CC - 1| = %.3g, min CC = %.3g, "
        "max |sum CC v - x| = %.3g px\n",
        e.partition, e.minimum, e.position);
    EXPECT_LE(e.position, 0.5);   // what the issue asks
    EXPECT_LE(e.position, 1e-3);  // what the symmetric cut-cell stencil gives: linear is exact
    EXPECT_LE(e.partition, 1e-5);
    EXPECT_GE(e.minimum, 0.0);
}

TEST(Harmonic, NodesInsideAPolygonSeeOnlyItAndItsChildren) {
    RNG rng(7);
    for (int trial = 0; trial < 4; ++trial) {
        const Multicage cage =
            trial == 0 ? multicage_fixtures::lotusMulticage(Size(240, 180), 40)
                       : multicage_fixtures::randomMulticage(rng, Size(220, 200), 3, 3, 8);
        const auto [checked, inner] =
            expectLocality(cage, bind(cage, HARMONIC, 2), "trial " + std::to_string(trial));
        EXPECT_GT(inner, 0);
        EXPECT_GT(checked, inner);
    }
}

TEST(Harmonic, GapsNarrowerThanTheGridStepStillSeparateRegions) {
    // At grid step 4, links cross two edges: a ring 1.2 px wide between two squares, and a
    // triangle 0.1 px from the frame whose node (0, 28) links to the frame through its edge.
    // Each node must take the first boundary its link meets.
    Multicage cage(Size(64, 64));
    cage.addPolygon(
        std::vector<Point2f>{{10.3f, 10.3f}, {49.7f, 10.3f}, {49.7f, 49.7f}, {10.3f, 49.7f}});
    cage.addPolygon(
        std::vector<Point2f>{{11.5f, 11.5f}, {48.5f, 11.5f}, {48.5f, 48.5f}, {11.5f, 48.5f}});
    cage.addPolygon(std::vector<Point2f>{{-0.4f, 20}, {6, 28}, {-0.4f, 36}});
    cage.orient();
    ASSERT_TRUE(cage.validate());
    const Binding b = bind(cage, HARMONIC, 4);
    const auto [checked, inner] = expectLocality(cage, b, "narrow gaps");
    EXPECT_GT(inner, 70);
    EXPECT_GT(checked, inner);
    const Errors e = measure(b);
    EXPECT_LE(e.partition, 1e-5);
    EXPECT_LE(e.position, 1e-3);
    EXPECT_GE(e.minimum, 0.0);
}

TEST(Harmonic, NodesOnAnEdgeInterpolateItExactly) {
    // Vertices off the grid, edges through nodes: along the row y = 20, a slope-2 edge
    // through (71, 21), (72, 23), ..., and the diagonal x = y of the inner polygon.
    Multicage cage(Size(120, 110));
    cage.addPolygon(std::vector<Point2f>{
        {10.5f, 20}, {70.5f, 20}, {90.5f, 60}, {50.5f, 90.5f}, {15.5f, 84.5f}});
    cage.addPolygon(
        std::vector<Point2f>{{30.5f, 30.5f}, {55.5f, 55.5f}, {35.5f, 64.5f}, {28.5f, 45}});
    cage.orient();
    ASSERT_TRUE(cage.validate());
    const Binding b = bind(cage, HARMONIC, 1);
    const int c = b.coefficientCount();
    int onEdges = 0;
    for (int p = 0; p < cage.polygonCount(); ++p) {
        const std::vector<Point2f> v = cage.polygon(p);
        const int n = static_cast<int>(v.size()), first = cage.polygonOffset(p);
        for (int i = 0; i < n; ++i) {
            const Point2d a = v[i], e = Point2d(v[(i + 1) % n]) - a;
            for (int gy = 0; gy < b.gridSize.height; ++gy)
                for (int gx = 0; gx < b.gridSize.width; ++gx) {
                    const Point2d d = Point2d(gx, gy) - a;
                    const double t = d.dot(e) / e.dot(e);
                    if (t < 0 || t > 1 || std::abs(d.cross(e)) > 1e-9) continue;  // exactly on it
                    ++onEdges;
                    for (int j = 0; j < c; ++j) {
                        const double want = j == first + i             ? 1 - t
                                            : j == first + (i + 1) % n ? t
                                                                       : 0.0;
                        ASSERT_NEAR(coefficient(b, j, gx, gy), want, 1e-6)
                            << "node (" << gx << ", " << gy << ") on edge " << i << " of polygon "
                            << p;
                    }
                }
        }
    }
    EXPECT_GT(onEdges, 100);
}

TEST(Harmonic, TriangleGivesBarycentricCoordinates) {
    // Hat functions on a triangle's edges are the restrictions of its barycentric
    // coordinates, which are linear and therefore discretely harmonic: the solve must return
    // them exactly, however the edges cut the grid.
    Multicage cage(Size(100, 90));
    const std::vector<Point2f> t = {{12.3f, 8.7f}, {91.1f, 30.4f}, {27.6f, 80.2f}};
    cage.addPolygon(t);
    cage.orient();
    const std::vector<Point2f> v = cage.polygon(0);
    for (int step : {1, 3}) {
        const Binding b = bind(cage, HARMONIC, step);
        const double area = (v[1] - v[0]).cross(v[2] - v[0]);
        int inside = 0;
        for (int gy = 0; gy < b.gridSize.height; ++gy)
            for (int gx = 0; gx < b.gridSize.width; ++gx) {
                const Point2f x = b.node(gx, gy);
                if (pointPolygonTest(v, x, false) <= 0) continue;
                ++inside;
                for (int i = 0; i < 3; ++i) {
                    const Point2f p = v[(i + 1) % 3], q = v[(i + 2) % 3];
                    EXPECT_NEAR(coefficient(b, i, gx, gy), (p - x).cross(q - x) / area, 1e-5)
                        << "step " << step << " node " << x << " vertex " << i;
                }
            }
        EXPECT_GT(inside, 100);
    }
}

TEST(Harmonic, FrameAloneGivesBilinearCoordinates) {
    // Bilinear interpolation of the frame corners is linear on each frame edge and harmonic
    // (u = xy has zero Laplacian, also on the 5-point stencil).
    const Multicage cage(Size(37, 23));
    const Binding b = bind(cage, HARMONIC, 2);
    for (int gy = 0; gy < b.gridSize.height; ++gy)
        for (int gx = 0; gx < b.gridSize.width; ++gx) {
            const Point2f x = b.node(gx, gy);
            const double s = (x.x + 0.5) / 37, t = (x.y + 0.5) / 23;
            const double want[4] = {(1 - s) * (1 - t), s * (1 - t), s * t,
                                    (1 - s) * t};  // TL TR BR BL
            for (int j = 0; j < 4; ++j) EXPECT_NEAR(coefficient(b, j, gx, gy), want[j], 1e-5) << x;
        }
}

TEST(Harmonic, RestPoseIsTheIdentityOnTheCpuDeformer) {
    const Mat image = multicage_testing::readSample("butterfly.jpg");
    const Multicage cage = multicage_testing::butterflyCage(true);
    DeformParams params;
    params.coordinates = HARMONIC;
    params.backend = BACKEND_CPU;
    params.gridStep = 2;
    Ptr<Deformer> d = Deformer::create(image, cage, params);
    ASSERT_EQ(d->backend(), BACKEND_CPU);
    EXPECT_EQ(d->binding().coordinates, HARMONIC);
    Mat out, mapx, mapy;
    d->deform(cage.vertices(), out);
    d->computeMaps(cage.vertices(), mapx, mapy);
    Mat idx(image.size(), CV_32F), idy(image.size(), CV_32F);
    for (int y = 0; y < image.rows; ++y)
        for (int x = 0; x < image.cols; ++x)
            idx.at<float>(y, x) = float(x), idy.at<float>(y, x) = float(y);
    // The rasteriser may nudge the outer ring of nodes by a fraction of a pixel; the binding
    // itself must put every node back where it was.
    EXPECT_LE(norm(mapx, idx, NORM_INF), 0.05);
    EXPECT_LE(norm(mapy, idy, NORM_INF), 0.05);
    Mat positions;
    d->binding().apply(cage.vertices(), positions);
    EXPECT_LE(norm(positions, d->binding().nodes(), NORM_INF), 1e-3);
    EXPECT_GE(multicage_testing::psnr(image, out), 50.0);
}

TEST(Harmonic, MovingTheOuterPolygonLeavesTheProtectedRegionAlone) {
    // With harmonic coordinates the body polygon's region sees only the body: moving the
    // wings alone must not move any node inside it (mean value coordinates would).
    const Multicage cage = multicage_testing::butterflyCage(true);
    const Binding b = bind(cage, HARMONIC, 4);
    const std::vector<Point2f> pose =
        multicage_fixtures::stretchPolygon(cage, 0, 1.1f, 0.9f, {5, -3});
    Mat moved, rest = b.nodes();
    b.apply(pose, moved);
    int inside = 0;
    for (int gy = 0; gy < b.gridSize.height; ++gy)
        for (int gx = 0; gx < b.gridSize.width; ++gx)
            if (pointPolygonTest(cage.polygon(1), b.node(gx, gy), false) > 0) {
                ++inside;
                EXPECT_EQ(moved.at<Point2f>(gy, gx), rest.at<Point2f>(gy, gx));
            }
    EXPECT_GT(inside, 50);
}

// Writes docs/harmonic/mvc_vs_harmonic.png when MULTICAGE_HARMONIC_PICTURE names the output:
// the same pose with mean value coordinates (left) and harmonic coordinates (right); below
// each, how far every pixel moved (|p' - x|, dark = still, bright = 30 px or more).
TEST(Harmonic, SideBySidePicture) {
    const char* path = std::getenv("MULTICAGE_HARMONIC_PICTURE");
    if (!path) GTEST_SKIP() << "set MULTICAGE_HARMONIC_PICTURE=out.png to write the picture";
    const Mat image = multicage_testing::readSample("butterfly.jpg");
    const Multicage cage = multicage_testing::butterflyCage(true);
    // Only the wings polygon moves: turned 10 degrees about the body and flattened; the body
    // polygon stays where it is.
    std::vector<Point2f> pose = cage.vertices();
    pose.resize(cage.vertexCount());
    const Point2f centre(246, 180);
    const float a = static_cast<float>(10 * CV_PI / 180);
    for (size_t i = 0; i < cage.polygon(0).size(); ++i) {
        const Point2f d = pose[i] - centre;
        pose[i] = centre + Point2f(std::cos(a) * d.x - std::sin(a) * d.y,
                                   0.85f * (std::sin(a) * d.x + std::cos(a) * d.y));
    }
    Mat panels[2], motion[2];
    for (int k = 0; k < 2; ++k) {
        DeformParams params;
        params.coordinates = k == 0 ? MEAN_VALUE : HARMONIC;
        params.backend = BACKEND_CPU;
        params.borderValue = Scalar(255, 255, 255);
        Ptr<Deformer> d = Deformer::create(image, cage, params);
        Mat out, positions, offset[2], magnitude;
        d->deform(pose, out);
        Multicage posed(cage.imageSize());
        for (int p = 0; p < cage.polygonCount(); ++p) {
            const int first = cage.polygonOffset(p), n = static_cast<int>(cage.polygon(p).size());
            posed.addPolygon(std::vector<Point2f>(pose.begin() + first, pose.begin() + first + n));
        }
        posed.draw(out, 1, true);
        const char* name = k == 0 ? "mean value" : "harmonic";
        putText(out, name, Point(8, 22), FONT_HERSHEY_SIMPLEX, 0.7, Scalar::all(0), 2, LINE_AA);
        panels[k] = out;
        d->binding().apply(pose, positions);
        split(positions - d->binding().nodes(), offset);
        magnitude = offset[0].mul(offset[0]) + offset[1].mul(offset[1]);
        sqrt(magnitude, magnitude);
        double bodyMotion = 0;
        for (int y = 0; y < image.rows; ++y)
            for (int x = 0; x < image.cols; ++x)
                if (pointPolygonTest(cage.polygon(1), Point2f(x, y), false) > 0)
                    bodyMotion = std::max(bodyMotion, double(magnitude.at<float>(y, x)));
        std::printf("[ measured ] %s: largest motion inside the body polygon %.3f px\n", name,
                    bodyMotion);
        magnitude.convertTo(motion[k], CV_8U, 255.0 / 30.0);
        applyColorMap(motion[k], motion[k], COLORMAP_VIRIDIS);
        posed.draw(motion[k], 1, false);
        putText(motion[k],
                format("%s: motion |p' - x|, 0 to 30 px; body: %.1f px", name, bodyMotion),
                Point(8, 22), FONT_HERSHEY_SIMPLEX, 0.55, Scalar::all(0), 2, LINE_AA);
    }
    const Mat gapV(image.rows, 8, CV_8UC3, Scalar::all(255));
    Mat top, bottom, picture;
    hconcat(std::vector<Mat>{panels[0], gapV, panels[1]}, top);
    hconcat(std::vector<Mat>{motion[0], gapV, motion[1]}, bottom);
    vconcat(std::vector<Mat>{top, Mat(8, top.cols, CV_8UC3, Scalar::all(255)), bottom}, picture);
    ASSERT_TRUE(imwrite(path, picture));
}

// Issue 13 item 9: a harmonic binding of a large image ran for tens of seconds with no sign of
// progress and no way to stop it. The progress callback rises from 0 to 1 in many steps, and
// returning false stops the binding with an exception that says so, long before the end.
TEST(Harmonic, ProgressRisesToOneAndCancellingStopsEarly) {
    // Twice the sample; the sample itself under a sanitizer (390 s there otherwise).
    const Size size = multicage_testing::kSanitized ? Size(493, 356) : Size(986, 712);
    Multicage big = multicage_testing::butterflyCage(true).scaled(size);
    std::vector<std::pair<double, double>> log;  // (seconds, fraction)
    const auto t0 = std::chrono::steady_clock::now();
    auto seconds = [&] {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    };
    const Binding whole = bind(big, HARMONIC, 1, [&](double f) {
        log.emplace_back(seconds(), f);
        return true;
    });
    const double total = seconds();
    ASSERT_GE(log.size(), 10u);
    EXPECT_EQ(log.front().second, 0.0);
    EXPECT_EQ(log.back().second, 1.0);
    for (size_t i = 1; i < log.size(); ++i)
        EXPECT_GE(log[i].second, log[i - 1].second) << "report " << i;
    // How well the fraction tracks time: the largest gap between reports, and where the
    // fraction stands at half time.
    double gap = 0, atHalf = 0;
    for (size_t i = 1; i < log.size(); ++i) gap = std::max(gap, log[i].first - log[i - 1].first);
    for (const auto& [t, f] : log)
        if (t <= total / 2) atHalf = f;
    std::printf(
        "harmonic bind of %dx%d: %.2f s, %zu reports, largest gap %.2f s, %.0f%% reported at "
        "half time\n",
        size.width, size.height, total, log.size(), gap, 100 * atHalf);
    EXPECT_EQ(whole.coordinates, HARMONIC);

    // Cancel at the first report after the start: it throws, saying so, and stops there: no
    // report comes after the one answered false, so the work after it (the factorisation of
    // the largest region, most of the time) is never done. Counted, not timed: a time bar
    // fails on a loaded machine (issue 22 item 4); the time is printed.
    const auto t1 = std::chrono::steady_clock::now();
    std::vector<double> reports;
    try {
        bind(big, HARMONIC, 1, [&](double f) {
            reports.push_back(f);
            return f == 0.0;
        });
        ADD_FAILURE() << "a cancelled binding returned";
    } catch (const cv::Exception& e) {
        EXPECT_NE(e.err.find(kBindCancelled), std::string::npos) << e.err;
    }
    const double cancelled =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
    std::printf("cancelled after %.2f s (the whole binding %.2f s)\n", cancelled, total);
    ASSERT_EQ(reports.size(), 2u) << "reports went on after the binding was cancelled";
    EXPECT_EQ(reports[0], 0.0);
    EXPECT_GT(reports[1], 0.0);
    EXPECT_LT(reports[1], 0.5) << "cancelled only after half the work";
    // Nothing is left in a bad state: binding again gives the same result.
    const Binding again = bind(big, HARMONIC, 1, [](double) { return true; });
    EXPECT_EQ(norm(again.coefficients, whole.coefficients, NORM_INF), 0.0);
}

// Issue 13 item 6: `coordinates: harmonic` in a cage file was followed by `deform` only. The
// library's rule: the multicage's choice unless the caller names a type.
TEST(Harmonic, CoordinatesComeFromTheCageUnlessTheCallerNamesThem) {
    const Mat image = multicage_testing::readSample("butterfly.jpg");
    Multicage cage = multicage_testing::butterflyCage(true);
    cage.setCoordinates(HARMONIC);
    DeformParams params;
    params.backend = BACKEND_CPU;
    params.gridStep = 4;
    EXPECT_EQ(params.coordinates, COORDINATES_FROM_CAGE);
    EXPECT_EQ(Deformer::create(image, cage, params)->binding().coordinates, HARMONIC);
    EXPECT_EQ(bind(cage, COORDINATES_FROM_CAGE, 4).coordinates, HARMONIC);
    EXPECT_EQ(bind(cage).coordinates, HARMONIC);
    params.coordinates = MEAN_VALUE;  // the caller says otherwise
    EXPECT_EQ(Deformer::create(image, cage, params)->binding().coordinates, MEAN_VALUE);
    cage.setCoordinates(MEAN_VALUE);
    params.coordinates = COORDINATES_FROM_CAGE;
    EXPECT_EQ(Deformer::create(image, cage, params)->binding().coordinates, MEAN_VALUE);
    params.coordinates = HARMONIC;
    EXPECT_EQ(Deformer::create(image, cage, params)->binding().coordinates, HARMONIC);
}

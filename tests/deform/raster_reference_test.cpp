// The CPU rasteriser and the reuse of its buffers against a plain reference: the rasteriser of
// before the set-up was vectorised (one triangle at a time, everything in double), kept here
// verbatim. Coverage, tie rules and values are a contract the GPU backend reproduces, so the
// fast one must give the same bits on every pixel, folds, degenerate and far-away nodes included.
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "testing.hpp"

using namespace cv;
using namespace cv::multicage;
using multicage_testing::sameBits;

// From the CPU backend's private raster_kernels.hpp (whose other contents need internal headers).
namespace cv {
namespace multicage {
namespace raster {
enum class RasterKernel { best, avx2, baseline };
bool preferRasterKernel(RasterKernel kernel);
}  // namespace raster
}  // namespace multicage
}  // namespace cv

namespace {

namespace reference {

constexpr float kUncovered = -1e4f;  // far outside any image: cv::remap gives the border value

inline double cross(Point2d a, Point2d b) {
    return a.x * b.y - a.y * b.x;
}

// Writes, for every pixel centre of rows [y0, y1) inside triangle q (deformed), the matching
// point of triangle p (rest). Inside a triangle the inverse map is affine, so each row is a
// span [xl, xr] found from the three barycentric edge functions, filled by a straight loop.
// Edges are inclusive with a small tolerance so that neighbouring triangles leave no crack;
// on a shared edge both write almost the same value.
void drawTriangle(const Point2f q[3], const Point2f p[3], int y0, int y1, Point2f lo, Point2f hi,
                  Mat& mapx, Mat& mapy) {
    const Point2d q0 = q[0], q1 = q[1], q2 = q[2];
    // Bounds are clamped in double before they become ints: a pose may put nodes 1e30 px
    // away or at infinity, and converting such a value to int is undefined (fuzz_deform).
    // The negated tests also drop NaN coordinates.
    const double minY = std::min({q0.y, q1.y, q2.y}), maxY = std::max({q0.y, q1.y, q2.y});
    if (!(maxY >= y0 && minY <= y1 - 1)) return;
    const int ya = static_cast<int>(std::ceil(std::max(minY, double(y0))));
    const int yb = static_cast<int>(std::floor(std::min(maxY, double(y1 - 1))));
    if (ya > yb) return;
    const double minX = std::min({q0.x, q1.x, q2.x}), maxX = std::max({q0.x, q1.x, q2.x});
    if (!(maxX >= 0 && minX <= mapx.cols - 1)) return;
    const int xa = static_cast<int>(std::ceil(std::max(minX, 0.0)));
    const int xb = static_cast<int>(std::floor(std::min(maxX, double(mapx.cols - 1))));
    if (xa > xb) return;
    const double area = cross(q1 - q0, q2 - q0);
    // Degenerate, NaN, or infinite (a node at infinity: the affine map would be NaN).
    if (!(std::abs(area) > 1e-12) || !std::isfinite(area)) return;
    const double inv = 1.0 / area;
    // Barycentric l_i(x, y) = (cross(a, b) + x (a.y - b.y) + y (b.x - a.x)) / area for the
    // edge (a, b) opposite vertex i.
    const Point2d e[3][2] = {{q1, q2}, {q2, q0}, {q0, q1}};
    double ax[3], ay[3], a0[3];
    for (int i = 0; i < 3; ++i) {
        const Point2d a = e[i][0], b = e[i][1];
        ax[i] = (a.y - b.y) * inv, ay[i] = (b.x - a.x) * inv, a0[i] = cross(a, b) * inv;
    }
    // The rest position as an affine function of the output pixel: r = p2 + l0 (p0-p2) + l1
    // (p1-p2).
    const Point2d d0 = Point2d(p[0]) - Point2d(p[2]), d1 = Point2d(p[1]) - Point2d(p[2]);
    const double mxx = ax[0] * d0.x + ax[1] * d1.x, mxy = ay[0] * d0.x + ay[1] * d1.x;
    const double mx0 = p[2].x + a0[0] * d0.x + a0[1] * d1.x;
    const double myx = ax[0] * d0.y + ax[1] * d1.y, myy = ay[0] * d0.y + ay[1] * d1.y;
    const double my0 = p[2].y + a0[0] * d0.y + a0[1] * d1.y;
    constexpr double eps = -1e-7;
    double invAx[3];  // once per triangle, not per row
    for (int i = 0; i < 3; ++i) invAx[i] = ax[i] != 0 ? 1.0 / ax[i] : 0.0;
    for (int y = ya; y <= yb; ++y) {
        double left = xa, right = xb;
        for (int i = 0; i < 3; ++i) {  // l_i(x) = ax x + c >= eps
            const double c = a0[i] + ay[i] * y;
            if (ax[i] > 0)
                left = std::max(left, (eps - c) * invAx[i]);
            else if (ax[i] < 0)
                right = std::min(right, (eps - c) * invAx[i]);
            else if (c < eps)
                right = -1;
        }
        if (!(left <= right)) continue;  // empty span (or NaN) before converting to int
        const int xl = static_cast<int>(std::ceil(left)), xr = static_cast<int>(std::floor(right));
        if (xl > xr) continue;
        float* mx = mapx.ptr<float>(y);
        float* my = mapy.ptr<float>(y);
        const double bx = mxy * y + mx0, by = myy * y + my0;
        for (int x = xl; x <= xr; ++x) {
            mx[x] = std::min(std::max(static_cast<float>(mxx * x + bx), lo.x), hi.x);
            my[x] = std::min(std::max(static_cast<float>(myx * x + by), lo.y), hi.y);
        }
    }
}

void rasterize(InputArray positionsIn, InputArray restIn, Size outputSize, OutputArray mapxOut,
               OutputArray mapyOut, InputArray frameIn) {
    Mat P = positionsIn.getMat(), R = restIn.getMat();
    CV_Assert(P.type() == CV_32FC2 && R.type() == CV_32FC2 && P.size() == R.size());
    CV_Assert(P.rows >= 2 && P.cols >= 2 && outputSize.area() > 0);
    // The mesh gets a ring of nodes on the image frame, around the node grid (whose outer nodes
    // sit on the border pixel centres, half a pixel inside the frame). A ring node follows the
    // frame as mean value coordinates do on a polygon edge (the frame corners interpolated
    // linearly) and samples the border pixel next to it. So the half-pixel band between the
    // frame and the border nodes is always covered: when border nodes move inwards the border
    // pixels stretch instead of leaving a line of border colour. deform.vert builds the same ring.
    const Point2f lo = R.at<Point2f>(0, 0), hi = R.at<Point2f>(R.rows - 1, R.cols - 1);
    std::vector<Point2f> corners;
    if (!frameIn.empty()) {
        Mat f = frameIn.getMat();
        CV_Assert(f.total() == 4 && f.type() == CV_32FC2);
        corners.assign(f.ptr<Point2f>(), f.ptr<Point2f>() + 4);
    } else {
        const float W = outputSize.width - 0.5f, H = outputSize.height - 0.5f;
        corners = {{-0.5f, -0.5f}, {W, -0.5f}, {W, H}, {-0.5f, H}};
    }
    {
        const int m = P.cols, n = P.rows;
        Mat Pe(n + 2, m + 2, CV_32FC2), Re(n + 2, m + 2, CV_32FC2);
        P.copyTo(Pe(Rect(1, 1, m, n)));
        R.copyTo(Re(Rect(1, 1, m, n)));
        const float W = static_cast<float>(outputSize.width),
                    H = static_cast<float>(outputSize.height);
        for (int ey = 0; ey < n + 2; ++ey)
            for (int ex = 0; ex < m + 2; ++ex) {
                if (ex > 0 && ex < m + 1 && ey > 0 && ey < n + 1) continue;
                const Point2f source = R.at<Point2f>(std::min(std::max(ey - 1, 0), n - 1),
                                                     std::min(std::max(ex - 1, 0), m - 1));
                const float rx = ex == 0 ? -0.5f : ex == m + 1 ? W - 0.5f : source.x;
                const float ry = ey == 0 ? -0.5f : ey == n + 1 ? H - 0.5f : source.y;
                const float u = (rx + 0.5f) / W, v = (ry + 0.5f) / H;
                Pe.at<Point2f>(ey, ex) = (1 - u) * (1 - v) * corners[0] + u * (1 - v) * corners[1] +
                                         u * v * corners[2] + (1 - u) * v * corners[3];
                Re.at<Point2f>(ey, ex) = source;
            }
        P = Pe, R = Re;
    }
    mapxOut.create(outputSize, CV_32F);
    mapyOut.create(outputSize, CV_32F);
    Mat mapx = mapxOut.getMat(), mapy = mapyOut.getMat();
    mapx.setTo(kUncovered);
    mapy.setTo(kUncovered);

    // Vertical extent of each row of cells, so that a band of output rows skips whole cell rows.
    std::vector<float> rowMin(P.rows - 1), rowMax(P.rows - 1);
    for (int gy = 0; gy + 1 < P.rows; ++gy) {
        float lo = INFINITY, hi = -INFINITY;
        for (int r = gy; r <= gy + 1; ++r)
            for (int gx = 0; gx < P.cols; ++gx) {
                const float y = P.at<Point2f>(r, gx).y;
                lo = std::min(lo, y), hi = std::max(hi, y);
            }
        rowMin[gy] = lo, rowMax[gy] = hi;
    }
    // Bands of output rows in parallel; each walks the cells in the same order, so where the
    // mesh folds over, the later triangle wins exactly as in a GPU draw call.
    const int bands = std::max(1, std::min(outputSize.height, getNumThreads() * 4));
    parallel_for_(Range(0, bands), [&](const Range& range) {
        for (int band = range.start; band < range.end; ++band) {
            const int y0 = outputSize.height * band / bands,
                      y1 = outputSize.height * (band + 1) / bands;
            for (int gy = 0; gy + 1 < P.rows; ++gy) {
                if (rowMax[gy] < y0 - 1 || rowMin[gy] > y1 + 1) continue;
                const Point2f* p0 = P.ptr<Point2f>(gy);
                const Point2f* p1 = P.ptr<Point2f>(gy + 1);
                const Point2f* r0 = R.ptr<Point2f>(gy);
                const Point2f* r1 = R.ptr<Point2f>(gy + 1);
                for (int gx = 0; gx + 1 < P.cols; ++gx) {
                    const Point2f qa[3] = {p0[gx], p0[gx + 1], p1[gx]};
                    const Point2f ra[3] = {r0[gx], r0[gx + 1], r1[gx]};
                    drawTriangle(qa, ra, y0, y1, lo, hi, mapx, mapy);
                    const Point2f qb[3] = {p0[gx + 1], p1[gx + 1], p1[gx]};
                    const Point2f rb[3] = {r0[gx + 1], r1[gx + 1], r1[gx]};
                    drawTriangle(qb, rb, y0, y1, lo, hi, mapx, mapy);
                }
            }
        }
    });
}

}  // namespace reference

// The same pixels covered (kUncovered elsewhere), and values equal within a few float roundings.
bool sameCoverageAndNearlyTheValues(const Mat& a, const Mat& ref) {
    if (a.size() != ref.size() || a.type() != CV_32F || ref.type() != CV_32F) return false;
    const multicage_testing::MapAgreement d =
        multicage_testing::compareMaps(a, ref, reference::kUncovered);
    return d.coverage == 0 && d.roundings <= 4.0;
}

// A grid of nodes every `step` pixels over `size`, moved by noise of amplitude `jitter` px
// (large amplitudes fold the mesh over itself) and a smooth swirl.
void randomMesh(RNG& rng, Size size, int step, float jitter, Mat& positions, Mat& rest) {
    const Size grid = gridSizeFor(size, step);
    rest.create(grid, CV_32FC2);
    positions.create(grid, CV_32FC2);
    for (int gy = 0; gy < grid.height; ++gy)
        for (int gx = 0; gx < grid.width; ++gx) {
            const Point2f r(float(std::min(gx * step, size.width - 1)),
                            float(std::min(gy * step, size.height - 1)));
            rest.at<Point2f>(gy, gx) = r;
            const float swirl = 3.f * std::sin(r.x * 0.05f + r.y * 0.03f);
            positions.at<Point2f>(gy, gx) = r + Point2f(swirl + rng.uniform(-jitter, jitter),
                                                        -swirl + rng.uniform(-jitter, jitter));
        }
}

void expectSameAsReference(const Mat& positions, const Mat& rest, Size size, InputArray frame,
                           const std::string& what) {
    Mat refx, refy;
    reference::rasterize(positions, rest, size, refx, refy, frame);
    // Every kernel this CPU can run: its own (AVX-512 where it has it), AVX2, and the baseline.
    using raster::RasterKernel;
    for (RasterKernel k : {RasterKernel::best, RasterKernel::avx2, RasterKernel::baseline}) {
        if (!raster::preferRasterKernel(k)) continue;
        Mat mapx, mapy;
        rasterizeMaps(positions, rest, size, mapx, mapy, frame);
        raster::preferRasterKernel(RasterKernel::best);
        const char* kernel = k == RasterKernel::avx2       ? " (AVX2 kernel)"
                             : k == RasterKernel::baseline ? " (baseline kernel)"
                                                           : " (kernel of this CPU)";
        EXPECT_TRUE(sameBits(mapx, refx)) << what << kernel << ": mapx differs from the reference";
        EXPECT_TRUE(sameBits(mapy, refy)) << what << kernel << ": mapy differs from the reference";
    }
}

}  // namespace

// Steps 1 to 16: the AVX-512 kernel draws a group of 8 cells pixel by pixel when it lies within
// 64 columns (steps up to 7 unless stretched) and span by span otherwise, the AVX2 kernel 4 cells
// within 32 columns, else a triangle at a time; rows of 97 and 33 px end in part-filled groups,
// and the AVX2 kernel draws the last columns of a row, and every column of a row of 6 px, one by
// one.
TEST(RasterReference, RandomAndFoldedMeshesBitForBit) {
    RNG rng(17);
    const Size sizes[] = {{97, 64}, {160, 120}, {33, 250}, {6, 9}};
    for (const Size size : sizes)
        for (int step : {1, 3, 7, 8, 16})
            for (float jitter : {0.f, 0.3f, 2.f, 12.f}) {
                Mat positions, rest;
                randomMesh(rng, size, step, jitter * step, positions, rest);
                const std::string what =
                    format("%dx%d step %d jitter %.1f", size.width, size.height, step, jitter);
                expectSameAsReference(positions, rest, size, noArray(), what);
                const std::vector<Point2f> frame = {{-3.f, 1.f},
                                                    {size.width + 2.f, -2.f},
                                                    {size.width - 4.f, size.height + 1.f},
                                                    {2.f, size.height - 3.f}};
                expectSameAsReference(positions, rest, size, frame, what + " moved frame");
            }
}

// Triangles wider than 256 px (a coarse grid, or a cell stretched that far): the AVX-512 kernel
// fills a long span 8 pixels at a time, and a chunk whose remaining length was 256..263 px once
// got the mask of length mod 256 (BZHI reads 8 bits of its index): 8 pixels left undrawn.
TEST(RasterReference, SpansLongerThan256PixelsBitForBit) {
    RNG rng(5);
    const Size size(700, 40);
    for (int step : {300, 350, 699})
        for (float jitter : {0.f, 3.f}) {
            Mat positions, rest;
            randomMesh(rng, size, step, jitter, positions, rest);
            expectSameAsReference(positions, rest, size, noArray(),
                                  format("700x40 step %d jitter %.0f", step, jitter));
        }
}

TEST(RasterReference, DegenerateFarAndNonFiniteNodesBitForBit) {
    RNG rng(4);
    const Size size(120, 90);
    Mat positions, rest;
    randomMesh(rng, size, 2, 0.5f, positions, rest);
    const Point2f special[] = {{1e30f, 5.f}, {-1e30f, -1e30f}, {INFINITY, 3.f}, {NAN, 10.f},
                               {5.f, NAN},   {0.f, 0.f},       {60.f, 45.f}};
    for (int i = 0; i < 40; ++i) {
        const int gx = rng.uniform(0, positions.cols), gy = rng.uniform(0, positions.rows);
        positions.at<Point2f>(gy, gx) = special[i % 7];
    }
    // a collapsed cell: four nodes on one point, and a row squashed onto a line
    positions.at<Point2f>(10, 10) = positions.at<Point2f>(10, 11) = positions.at<Point2f>(11, 10) =
        positions.at<Point2f>(11, 11) = Point2f(21.f, 21.f);
    for (int gx = 0; gx < positions.cols; ++gx) positions.at<Point2f>(20, gx).y = 40.f;
    expectSameAsReference(positions, rest, size, noArray(), "special nodes");
}

// The CPU Deformer reuses its mesh and maps between poses: every pose gives what a fresh
// Deformer gives, whatever came before, and deform is remap of computeMaps. Its maps are the
// rasteriser's: bit for bit where the mesh folds (drawn), within float rounding where it folds
// nowhere (pulled pixel by pixel, mesh_pull_test.cpp).
TEST(RasterReference, ReusedBuffersGiveWhatAFreshDeformerGives) {
    const Size size(150, 110);
    const Multicage cage = multicage_fixtures::lotusMulticage(size, 24);
    Mat image(size, CV_8UC3);
    randu(image, 0, 256);
    DeformParams params;
    params.backend = BACKEND_CPU;
    const std::vector<Point2f> poses[] = {multicage_fixtures::wavePose(cage, 6.f, 0.f),
                                          multicage_fixtures::wavePose(cage, 25.f, 1.f),
                                          multicage_fixtures::wavePose(cage, 3.f, 2.f)};
    Ptr<Deformer> reused = Deformer::create(image, cage, params);
    for (int round = 0; round < 2; ++round)
        for (const auto& pose : poses) {
            Ptr<Deformer> fresh = Deformer::create(image, reused->binding(), params);
            Mat a, b, mapx, mapy, refx, refy, positions;
            reused->deform(pose, a);
            fresh->deform(pose, b);
            EXPECT_TRUE(sameBits(a, b));
            reused->computeMaps(pose, mapx, mapy);
            // the public pieces: node positions, then the rasteriser
            reused->binding().apply(pose, positions);
            const std::vector<Point2f> full = reused->binding().completePose(pose);
            rasterizeMaps(positions, reused->binding().nodes(), size, refx, refy,
                          Mat(std::vector<Point2f>(full.end() - 4, full.end()), true));
            const int folds = countFoldedTriangles(positions, reused->binding().nodes());
            if (folds > 0) {
                EXPECT_TRUE(sameBits(mapx, refx));
                EXPECT_TRUE(sameBits(mapy, refy));
            }
            EXPECT_TRUE(sameCoverageAndNearlyTheValues(mapx, refx));
            EXPECT_TRUE(sameCoverageAndNearlyTheValues(mapy, refy));
            Mat remapped;
            remap(image, remapped, mapx, mapy, INTER_LINEAR, BORDER_CONSTANT, params.borderValue);
            EXPECT_TRUE(sameBits(a, remapped));
        }
}

// Binding::apply writes into a view of a larger matrix (the CPU backend's mesh) exactly what
// it writes into a matrix of its own.
TEST(RasterReference, ApplyIntoAViewEqualsApplyIntoAMatrix) {
    const Size size(90, 70);
    const Multicage cage = multicage_fixtures::lotusMulticage(size, 16);
    for (int step : {1, 4}) {
        const Binding b = bind(cage, MEAN_VALUE, step);
        const std::vector<Point2f> pose = multicage_fixtures::wavePose(cage, 5.f, 0.3f);
        Mat own, big(b.gridSize.height + 2, b.gridSize.width + 2, CV_32FC2, Scalar::all(7));
        b.apply(pose, own);
        Mat view = big(Rect(1, 1, b.gridSize.width, b.gridSize.height));
        b.apply(pose, view);
        EXPECT_EQ(view.data, big.ptr(1) + 8) << "apply reallocated the view";
        EXPECT_TRUE(sameBits(own, view));
        EXPECT_EQ(big.at<Point2f>(0, 0), Point2f(7, 7)) << "apply wrote outside the view";
        EXPECT_EQ(big.at<Point2f>(big.rows - 1, big.cols - 1), Point2f(7, 7));
    }
}

// The CPU rasteriser's triangle kernels (private): the set-up of a run of triangles, the span of
// a row and a triangle's drawing, for the baseline kernel (raster_kernels.cpp); the AVX2 and
// AVX-512 ones (raster_avx2.cpp, raster_avx512.cpp) compute the same values 4 and 8 triangles at
// a time, in the same order.
#ifndef MULTICAGE_RASTER_KERNELS_HPP
#define MULTICAGE_RASTER_KERNELS_HPP

// A file that includes this includes raster_options.hpp first, before any other header.
#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/multicage/internal/backend_contract.hpp>

namespace cv {
namespace multicage {
namespace raster {

// The triangles of a run of cells, two per cell ((a,b,c) then (b,d,c)), in drawing order.
constexpr int kRunCells = 64, kRunTriangles = 2 * kRunCells;

// Per triangle of a run, everything drawTriangle needs that does not depend on the output
// rows: bounds, the barycentric edge functions, and the affine inverse map. One structure of
// arrays, so the set-up of a run vectorises across triangles.
struct TriangleSetup {
    float qx[3][kRunTriangles], qy[3][kRunTriangles], px[3][kRunTriangles], py[3][kRunTriangles];
    double minY[kRunTriangles], maxY[kRunTriangles], minX[kRunTriangles], maxX[kRunTriangles];
    double area[kRunTriangles];
    double ax[3][kRunTriangles], ay[3][kRunTriangles], a0[3][kRunTriangles],
        invAx[3][kRunTriangles];
    double mxx[kRunTriangles], mxy[kRunTriangles], mx0[kRunTriangles];
    double myx[kRunTriangles], myy[kRunTriangles], my0[kRunTriangles];
};

// The helpers below have internal linkage on purpose: each kernel's file compiles its own copy
// for its own instruction set (and inlines it). Shared inline functions would be merged by the
// linker into one copy, possibly the baseline one, out of line, under the AVX-512 kernel.
namespace {

// std::min / std::max of three, with their exact comparisons (so NaN behaves as it always did),
// written as selects so that a loop of them vectorises.
inline double min3(double a, double b, double c) {
    double r = a;
    r = b < r ? b : r;
    return c < r ? c : r;
}
inline double max3(double a, double b, double c) {
    double r = a;
    r = r < b ? b : r;
    return r < c ? c : r;
}

// Set-up of triangles [0, count) from their corners qx/qy (deformed) and px/py (rest). Every
// value is computed with the same operations, in the same order, as for one triangle at a time.
inline void setUpTriangles(TriangleSetup& s, int count) {
    for (int t = 0; t < count; ++t) {
        const double q0x = s.qx[0][t], q0y = s.qy[0][t], q1x = s.qx[1][t], q1y = s.qy[1][t];
        const double q2x = s.qx[2][t], q2y = s.qy[2][t];
        s.minY[t] = min3(q0y, q1y, q2y), s.maxY[t] = max3(q0y, q1y, q2y);
        s.minX[t] = min3(q0x, q1x, q2x), s.maxX[t] = max3(q0x, q1x, q2x);
        // area = cross(q1 - q0, q2 - q0)
        const double area = (q1x - q0x) * (q2y - q0y) - (q1y - q0y) * (q2x - q0x);
        s.area[t] = area;
        const double inv = 1.0 / area;
        // Barycentric l_i(x, y) = (cross(a, b) + x (a.y - b.y) + y (b.x - a.x)) / area for the
        // edge (a, b) opposite vertex i: (q1, q2), (q2, q0), (q0, q1).
        const double ex[3][2] = {{q1x, q2x}, {q2x, q0x}, {q0x, q1x}};
        const double ey[3][2] = {{q1y, q2y}, {q2y, q0y}, {q0y, q1y}};
        double ax[3], ay[3], a0[3];
        for (int i = 0; i < 3; ++i) {
            ax[i] = (ey[i][0] - ey[i][1]) * inv, ay[i] = (ex[i][1] - ex[i][0]) * inv;
            a0[i] = (ex[i][0] * ey[i][1] - ey[i][0] * ex[i][1]) * inv;
            const double r = 1.0 / ax[i];
            s.ax[i][t] = ax[i], s.ay[i][t] = ay[i], s.a0[i][t] = a0[i];
            s.invAx[i][t] = ax[i] != 0 ? r : 0.0;
        }
        // The rest position as an affine function of the output pixel: r = p2 + l0 (p0-p2) + l1
        // (p1-p2).
        const double p2x = s.px[2][t], p2y = s.py[2][t];
        const double d0x = double(s.px[0][t]) - p2x, d0y = double(s.py[0][t]) - p2y;
        const double d1x = double(s.px[1][t]) - p2x, d1y = double(s.py[1][t]) - p2y;
        s.mxx[t] = ax[0] * d0x + ax[1] * d1x, s.mxy[t] = ay[0] * d0x + ay[1] * d1x;
        s.mx0[t] = p2x + a0[0] * d0x + a0[1] * d1x;
        s.myx[t] = ax[0] * d0y + ax[1] * d1y, s.myy[t] = ay[0] * d0y + ay[1] * d1y;
        s.my0[t] = p2y + a0[0] * d0y + a0[1] * d1y;
    }
}

// Gathers the corners of the triangles of cells [first, first + n) of one mesh row into s and
// sets them up: cell by cell, its kCellTriangles in turn.
inline void prepareRun(const Point2f* p0, const Point2f* p1, const Point2f* r0, const Point2f* r1,
                       int first, int n, TriangleSetup& s) {
    for (int k = 0; k < n; ++k) {
#pragma GCC unroll 6
        for (int i = 0; i < 6; ++i) {  // triangle t = i / 3 of cell first + k, its vertex v
            const int t = i / 3, v = i % 3, tri = 2 * k + t;
            const int x = first + k + kCellTriangles[t][v][0];
            const bool below = kCellTriangles[t][v][1] != 0;
            const Point2f q = (below ? p1 : p0)[x], r = (below ? r1 : r0)[x];
            s.qx[v][tri] = q.x, s.qy[v][tri] = q.y, s.px[v][tri] = r.x, s.py[v][tri] = r.y;
        }
    }
    setUpTriangles(s, 2 * n);
}

// Rows [ya, yb] and columns [xa, xb] of triangle t inside rows [y0, y1) and columns [0, cols),
// or false when it draws nothing: outside, degenerate, NaN, or infinite (a node at infinity: the
// affine map would be NaN). Bounds are clamped in double before they become ints: a pose may put
// nodes 1e30 px away or at infinity, and converting such a value to int is undefined
// (fuzz_deform). The negated tests also drop NaN coordinates.
inline bool triangleBounds(const TriangleSetup& s, int t, int y0, int y1, int cols, int& ya,
                           int& yb, int& xa, int& xb) {
    const double minY = s.minY[t], maxY = s.maxY[t];
    if (!(maxY >= y0 && minY <= y1 - 1)) return false;
    ya = static_cast<int>(std::ceil(std::max(minY, double(y0))));
    yb = static_cast<int>(std::floor(std::min(maxY, double(y1 - 1))));
    if (ya > yb) return false;
    const double minX = s.minX[t], maxX = s.maxX[t];
    if (!(maxX >= 0 && minX <= cols - 1)) return false;
    xa = static_cast<int>(std::ceil(std::max(minX, 0.0)));
    xb = static_cast<int>(std::floor(std::min(maxX, double(cols - 1))));
    if (xa > xb) return false;
    const double area = s.area[t];
    return std::abs(area) > 1e-12 && std::isfinite(area);
}

// The pixels [xl, xr] of row y inside triangle t (within its columns [xa, xb]), or false when
// there are none. Edges are inclusive with a small tolerance (eps), so that neighbouring
// triangles leave no crack: l_i(x) = ax x + c >= eps for the three barycentric edge functions.
// Selects, not branches (a triangle is a few rows, so the branches of each edge's side
// mispredict): an edge bounds the left (ax > 0), the right (ax < 0), or, neither, empties the
// row when c < eps (NaN ax included).
constexpr double kEdgeTolerance = -1e-7;
inline bool rowSpan(const TriangleSetup& s, int t, int y, int xa, int xb, int& xl, int& xr) {
    constexpr double eps = kEdgeTolerance;
    double left = xa, right = xb;
    for (int i = 0; i < 3; ++i) {
        const double ax = s.ax[i][t], c = s.a0[i][t] + s.ay[i][t] * y;
        const double v = (eps - c) * s.invAx[i][t];
        left = std::max(left, ax > 0 ? v : -INFINITY);
        right = std::min(right, ax < 0 ? v : INFINITY);
        right = !(ax > 0) && !(ax < 0) && c < eps ? -1.0 : right;
    }
    if (!(left <= right)) return false;  // empty span (or NaN) before converting to int
    xl = static_cast<int>(std::ceil(left)), xr = static_cast<int>(std::floor(right));
    return xl <= xr;
}

// Writes, for every pixel centre of rows [y0, y1) inside triangle t (deformed), the matching
// point of its rest triangle. Inside a triangle the inverse map is affine, so each row is a
// span [xl, xr] found from the three barycentric edge functions, filled by a straight loop.
// Edges are inclusive with a small tolerance so that neighbouring triangles leave no crack;
// on a shared edge both write almost the same value.
inline void drawTriangle(const TriangleSetup& s, int t, int y0, int y1, Point2f lo, Point2f hi,
                         Mat& mapx, Mat& mapy) {
    int ya, yb, xa, xb;
    if (!triangleBounds(s, t, y0, y1, mapx.cols, ya, yb, xa, xb)) return;
    const double mxx = s.mxx[t], mxy = s.mxy[t], mx0 = s.mx0[t];
    const double myx = s.myx[t], myy = s.myy[t], my0 = s.my0[t];
    for (int y = ya; y <= yb; ++y) {
        int xl, xr;
        if (!rowSpan(s, t, y, xa, xb, xl, xr)) continue;
        float* mx = mapx.ptr<float>(y);
        float* my = mapy.ptr<float>(y);
        const double bx = mxy * y + mx0, by = myy * y + my0;
        for (int x = xl; x <= xr; ++x) {
            mx[x] = std::min(std::max(static_cast<float>(mxx * x + bx), lo.x), hi.x);
            my[x] = std::min(std::max(static_cast<float>(myx * x + by), lo.y), hi.y);
        }
    }
}

}  // namespace

// Draws the cells of one row of the mesh (nodes rows p0/p1 deformed, r0/r1 rest, `cells`
// cells) into output rows [y0, y1) of the maps, in order: cell by cell, its kCellTriangles in
// turn, a later triangle overwriting an earlier one. s: the baseline kernel's scratch.
using DrawCellRowFn = void (*)(const Point2f* p0, const Point2f* p1, const Point2f* r0,
                               const Point2f* r1, int cells, int y0, int y1, Point2f lo, Point2f hi,
                               Mat& mapx, Mat& mapy, TriangleSetup& s);

/** The kernel for this CPU: AVX-512 where it has it, else AVX2, else the baseline (all give the
same bits). */
DrawCellRowFn cellRowKernel();

/** The kernels, for tests that compare them: `best` is this CPU's own. */
enum class RasterKernel { best, avx2, baseline };

/** Makes cellRowKernel() return `kernel` (RasterKernel::best: choose again); false, changing
nothing, where this CPU or build cannot run it. */
bool preferRasterKernel(RasterKernel kernel);

/** The AVX2 kernel (raster_avx2.cpp); only for CPUs with AVX2 (x86-64-v3). */
void drawCellRowAvx2(const Point2f* p0, const Point2f* p1, const Point2f* r0, const Point2f* r1,
                     int cells, int y0, int y1, Point2f lo, Point2f hi, Mat& mapx, Mat& mapy,
                     TriangleSetup& s);
/** Whether drawCellRowAvx2 exists in this build. */
bool haveAvx2Kernel();

/** The AVX-512 kernel (raster_avx512.cpp); only for CPUs with AVX-512 F, BW, DQ, VL. */
void drawCellRowAvx512(const Point2f* p0, const Point2f* p1, const Point2f* r0, const Point2f* r1,
                       int cells, int y0, int y1, Point2f lo, Point2f hi, Mat& mapx, Mat& mapy,
                       TriangleSetup& s);
/** Whether drawCellRowAvx512 exists in this build. */
bool haveAvx512Kernel();

}  // namespace raster
}  // namespace multicage
}  // namespace cv

#endif

// Rasterising the deformed node mesh into inverse maps (the CPU backend's "draw call").

// For the whole file (before any header, so that every function here, inlined ones included,
// has the same options): no fused multiply-adds, so the AVX2 clone of the triangle kernel gives
// the same bits as the baseline one; and no floating-point traps assumed (nothing here enables
// them), so that the selects of the triangle set-up vectorise.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC optimize("fp-contract=off", "no-trapping-math")
#elif defined(__clang__)
#pragma clang fp contract(off)
#endif
#include <climits>
#include <cmath>
#include <memory>
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
// GCC 12's AVX-512 headers start vectors from _mm512_undefined_*(), which -W(maybe-)uninitialized
// reports at every use.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#include <immintrin.h>
#endif
#include <opencv2/core/utility.hpp>
#include <opencv2/multicage/deformer.hpp>

#include "cpu_deformer.hpp"
#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace cv {
namespace multicage {

namespace {

inline double cross(Point2d a, Point2d b) {
    return a.x * b.y - a.y * b.x;
}

// The triangle kernel is compiled twice, for AVX2 and for the baseline (GCC function
// multiversioning), without fused multiply-adds: both give the same bits.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && \
    !defined(__SANITIZE_ADDRESS__)
#define MULTICAGE_TARGET_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define MULTICAGE_TARGET_CLONES
#endif

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

// Writes, for every pixel centre of rows [y0, y1) inside triangle t (deformed), the matching
// point of its rest triangle. Inside a triangle the inverse map is affine, so each row is a
// span [xl, xr] found from the three barycentric edge functions, filled by a straight loop.
// Edges are inclusive with a small tolerance so that neighbouring triangles leave no crack;
// on a shared edge both write almost the same value.
inline void drawTriangle(const TriangleSetup& s, int t, int y0, int y1, Point2f lo, Point2f hi,
                         Mat& mapx, Mat& mapy) {
    // Bounds are clamped in double before they become ints: a pose may put nodes 1e30 px
    // away or at infinity, and converting such a value to int is undefined (fuzz_deform).
    // The negated tests also drop NaN coordinates.
    const double minY = s.minY[t], maxY = s.maxY[t];
    if (!(maxY >= y0 && minY <= y1 - 1)) return;
    const int ya = static_cast<int>(std::ceil(std::max(minY, double(y0))));
    const int yb = static_cast<int>(std::floor(std::min(maxY, double(y1 - 1))));
    if (ya > yb) return;
    const double minX = s.minX[t], maxX = s.maxX[t];
    if (!(maxX >= 0 && minX <= mapx.cols - 1)) return;
    const int xa = static_cast<int>(std::ceil(std::max(minX, 0.0)));
    const int xb = static_cast<int>(std::floor(std::min(maxX, double(mapx.cols - 1))));
    if (xa > xb) return;
    const double area = s.area[t];
    // Degenerate, NaN, or infinite (a node at infinity: the affine map would be NaN).
    if (!(std::abs(area) > 1e-12) || !std::isfinite(area)) return;
    const double ax[3] = {s.ax[0][t], s.ax[1][t], s.ax[2][t]};
    const double ay[3] = {s.ay[0][t], s.ay[1][t], s.ay[2][t]};
    const double a0[3] = {s.a0[0][t], s.a0[1][t], s.a0[2][t]};
    const double invAx[3] = {s.invAx[0][t], s.invAx[1][t], s.invAx[2][t]};
    const double mxx = s.mxx[t], mxy = s.mxy[t], mx0 = s.mx0[t];
    const double myx = s.myx[t], myy = s.myy[t], my0 = s.my0[t];
    constexpr double eps = -1e-7;
    for (int y = ya; y <= yb; ++y) {
        double left = xa, right = xb;
        for (int i = 0; i < 3; ++i) {  // l_i(x) = ax x + c >= eps
            // Selects, not branches (a triangle is a few rows, so the branches of each edge's
            // side mispredict); the same values: an edge bounds the left (ax > 0), the right
            // (ax < 0), or, neither, empties the row when c < eps (NaN ax included).
            const double c = a0[i] + ay[i] * y;
            const double v = (eps - c) * invAx[i];
            left = std::max(left, ax[i] > 0 ? v : -INFINITY);
            right = std::min(right, ax[i] < 0 ? v : INFINITY);
            right = !(ax[i] > 0) && !(ax[i] < 0) && c < eps ? -1.0 : right;
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

// Draws the cells of one row of the mesh (nodes rows p0/p1 deformed, r0/r1 rest, `cells`
// cells) into output rows [y0, y1), in order: cell by cell, its kCellTriangles in turn.
MULTICAGE_TARGET_CLONES
void drawCellRow(const Point2f* p0, const Point2f* p1, const Point2f* r0, const Point2f* r1,
                 int cells, int y0, int y1, Point2f lo, Point2f hi, Mat& mapx, Mat& mapy,
                 TriangleSetup& s) {
    for (int first = 0; first < cells; first += kRunCells) {
        const int n = std::min(kRunCells, cells - first);
        prepareRun(p0, p1, r0, r1, first, n, s);
        for (int t = 0; t < 2 * n; ++t) drawTriangle(s, t, y0, y1, lo, hi, mapx, mapy);
    }
}

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define MULTICAGE_HAVE_V4 1
#define MULTICAGE_V4 __attribute__((target("arch=x86-64-v4")))

// drawTriangle with AVX-512, in two passes over a run of triangles. The first finds the spans
// of up to 8 rows of each triangle at once (one row per lane); the second fills them, 8 pixels
// at a time with masked stores, triangle after triangle in drawing order. The same double
// operations in the same order as drawTriangle (no fused multiply-adds in this file), so the
// same bits. What it saves: the branches of short spans (cells of 4x4 pixels make spans of 1 to
// 5 pixels, whose loops mispredict) and the scalar span arithmetic per row. The passes are apart
// so that the second reads what the first stored long after (a scalar load of a lane just stored
// from a vector register waits for the store to complete).
struct SpanRows {
    double bx[kRunTriangles][8], by[kRunTriangles][8];  // the inverse map's constant per row
    int xl[kRunTriangles][8], xr[kRunTriangles][8];     // the span of each row
    int ya[kRunTriangles], yb[kRunTriangles];           // rows of the triangle (yb < ya: none)
    unsigned char rows[kRunTriangles];                  // bit k: row ya + k has a span
};

// Rows [ya, yb] of triangle t inside rows [y0, y1) and columns [xa, xb] of the output, or false
// when it draws nothing (outside, degenerate, NaN or infinite), as drawTriangle decides.
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

// The spans of rows [ya, ya + 8) of triangle t (lanes past yb are left out of `rows`).
MULTICAGE_V4 inline void spansOf8Rows(const TriangleSetup& s, int t, int ya, int yb, int xa, int xb,
                                      SpanRows& out) {
    const __m512d yv = _mm512_cvtepi32_pd(
        _mm256_add_epi32(_mm256_set1_epi32(ya), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7)));
    const __m512d eps = _mm512_set1_pd(-1e-7);
    __m512d left = _mm512_set1_pd(xa), right = _mm512_set1_pd(xb);
    for (int i = 0; i < 3; ++i) {  // l_i(x) = ax x + c >= eps, as in drawTriangle
        const double ax = s.ax[i][t];
        const __m512d c = _mm512_add_pd(_mm512_set1_pd(s.a0[i][t]),
                                        _mm512_mul_pd(_mm512_set1_pd(s.ay[i][t]), yv));
        const __m512d v = _mm512_mul_pd(_mm512_sub_pd(eps, c), _mm512_set1_pd(s.invAx[i][t]));
        if (ax > 0)
            left = _mm512_max_pd(v, left);  // left < v ? v : left: a NaN v keeps left
        else if (ax < 0)
            right = _mm512_min_pd(v, right);  // v < right ? v : right
        else
            right = _mm512_mask_mov_pd(right, _mm512_cmp_pd_mask(c, eps, _CMP_LT_OQ),
                                       _mm512_set1_pd(-1.0));
    }
    const int count = std::min(8, yb - ya + 1);
    __mmask8 rows =
        _mm512_cmp_pd_mask(left, right, _CMP_LE_OQ) & static_cast<__mmask8>((1u << count) - 1);
    // Spans whose bounds round past each other (xl > xr) are empty too.
    const __m256i xl = _mm512_cvtpd_epi32(_mm512_roundscale_pd(left, _MM_FROUND_TO_POS_INF));
    const __m256i xr = _mm512_cvtpd_epi32(_mm512_roundscale_pd(right, _MM_FROUND_TO_NEG_INF));
    rows &= ~_mm256_cmpgt_epi32_mask(xl, xr);
    out.rows[t] = rows;
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out.xl[t]), xl);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out.xr[t]), xr);
    _mm512_storeu_pd(out.bx[t], _mm512_add_pd(_mm512_mul_pd(_mm512_set1_pd(s.mxy[t]), yv),
                                              _mm512_set1_pd(s.mx0[t])));
    _mm512_storeu_pd(out.by[t], _mm512_add_pd(_mm512_mul_pd(_mm512_set1_pd(s.myy[t]), yv),
                                              _mm512_set1_pd(s.my0[t])));
}

// Pixels xl..xr of one row of triangle t: mxx x + bx and myx x + by, clamped to [lo, hi].
MULTICAGE_V4 inline void fillSpan(const TriangleSetup& s, int t, int xl, int xr, double bx,
                                  double by, Point2f lo, Point2f hi, float* mx, float* my) {
    const __m256i iota = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    const __m512d mxx = _mm512_set1_pd(s.mxx[t]), myx = _mm512_set1_pd(s.myx[t]);
    const __m512d bxv = _mm512_set1_pd(bx), byv = _mm512_set1_pd(by);
    for (int x = xl; x <= xr; x += 8) {
        const __mmask8 lanes = static_cast<__mmask8>(_bzhi_u32(0xff, unsigned(xr - x + 1)));
        const __m512d xv = _mm512_cvtepi32_pd(_mm256_add_epi32(_mm256_set1_epi32(x), iota));
        // std::min(std::max(v, lo), hi): max_ps(lo, v) and min_ps(hi, .) pick v when it is NaN,
        // as std::max and std::min do.
        const __m256 vx = _mm512_cvtpd_ps(_mm512_add_pd(_mm512_mul_pd(mxx, xv), bxv));
        const __m256 vy = _mm512_cvtpd_ps(_mm512_add_pd(_mm512_mul_pd(myx, xv), byv));
        _mm256_mask_storeu_ps(
            mx + x, lanes,
            _mm256_min_ps(_mm256_set1_ps(hi.x), _mm256_max_ps(_mm256_set1_ps(lo.x), vx)));
        _mm256_mask_storeu_ps(
            my + x, lanes,
            _mm256_min_ps(_mm256_set1_ps(hi.y), _mm256_max_ps(_mm256_set1_ps(lo.y), vy)));
    }
}

// Rows ya..yb of triangle t one at a time (the rows past the first 8 of a tall triangle).
MULTICAGE_V4 inline void fillRows(const TriangleSetup& s, int t, int ya, int yb, int xa, int xb,
                                  Point2f lo, Point2f hi, Mat& mapx, Mat& mapy) {
    constexpr double eps = -1e-7;
    for (int y = ya; y <= yb; ++y) {
        double left = xa, right = xb;
        for (int i = 0; i < 3; ++i) {
            const double ax = s.ax[i][t], c = s.a0[i][t] + s.ay[i][t] * y;
            const double v = (eps - c) * s.invAx[i][t];
            left = std::max(left, ax > 0 ? v : -INFINITY);
            right = std::min(right, ax < 0 ? v : INFINITY);
            right = !(ax > 0) && !(ax < 0) && c < eps ? -1.0 : right;
        }
        if (!(left <= right)) continue;
        const int xl = static_cast<int>(std::ceil(left)), xr = static_cast<int>(std::floor(right));
        fillSpan(s, t, xl, xr, s.mxy[t] * y + s.mx0[t], s.myy[t] * y + s.my0[t], lo, hi,
                 mapx.ptr<float>(y), mapy.ptr<float>(y));
    }
}

MULTICAGE_V4
void drawCellRowV4(const Point2f* p0, const Point2f* p1, const Point2f* r0, const Point2f* r1,
                   int cells, int y0, int y1, Point2f lo, Point2f hi, Mat& mapx, Mat& mapy,
                   TriangleSetup& s) {
    thread_local std::unique_ptr<SpanRows> spansOwner;
    if (!spansOwner) spansOwner.reset(new SpanRows);
    SpanRows& spans = *spansOwner;
    int xa[kRunTriangles], xb[kRunTriangles];
    for (int first = 0; first < cells; first += kRunCells) {
        const int n = std::min(kRunCells, cells - first);
        prepareRun(p0, p1, r0, r1, first, n, s);
        for (int t = 0; t < 2 * n; ++t) {
            spans.rows[t] = 0, spans.ya[t] = 0, spans.yb[t] = -1;
            if (!triangleBounds(s, t, y0, y1, mapx.cols, spans.ya[t], spans.yb[t], xa[t], xb[t])) {
                spans.yb[t] = spans.ya[t] - 1;
                continue;
            }
            spansOf8Rows(s, t, spans.ya[t], spans.yb[t], xa[t], xb[t], spans);
        }
        for (int t = 0; t < 2 * n; ++t) {
            const int ya = spans.ya[t];
            for (unsigned m = spans.rows[t]; m; m &= m - 1) {
                const int k = __builtin_ctz(m), y = ya + k;
                fillSpan(s, t, spans.xl[t][k], spans.xr[t][k], spans.bx[t][k], spans.by[t][k], lo,
                         hi, mapx.ptr<float>(y), mapy.ptr<float>(y));
            }
            if (spans.yb[t] >= ya + 8)
                fillRows(s, t, ya + 8, spans.yb[t], xa[t], xb[t], lo, hi, mapx, mapy);
        }
    }
}
#endif

using DrawCellRowFn = void (*)(const Point2f*, const Point2f*, const Point2f*, const Point2f*, int,
                               int, int, Point2f, Point2f, Mat&, Mat&, TriangleSetup&);

// The AVX-512 kernel where the CPU has it (same bits as the others), else drawCellRow's clones.
DrawCellRowFn cellRowKernel() {
#if defined(MULTICAGE_HAVE_V4)
    static const bool v4 = __builtin_cpu_supports("avx512f") &&
                           __builtin_cpu_supports("avx512vl") &&
                           __builtin_cpu_supports("avx512dq") &&
                           __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("bmi2");
    if (v4) return drawCellRowV4;
#endif
    return drawCellRow;
}

}  // namespace

Mat hugePageMat(Size size, int type, std::vector<Mat>& owners) {
    const size_t bytes = size_t(size.area()) * CV_ELEM_SIZE(type);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    constexpr size_t kHuge = size_t(2) << 20;
    if (bytes >= kHuge) {
        const size_t span = (bytes + kHuge - 1) & ~(kHuge - 1);
        Mat block(1, static_cast<int>(std::min<size_t>(span + kHuge, INT_MAX)), CV_8U);
        if (block.total() == span + kHuge) {
            uchar* aligned = alignPtr(block.data, static_cast<int>(kHuge));
            madvise(aligned, span, MADV_HUGEPAGE);
            owners.push_back(block);
            return Mat(size, type, aligned);
        }
    }
#endif
    (void)owners;
    return Mat(size, type);
}

template <typename RestNode>
void RasterMesh::resetWith(Size grid, Size outputSize, bool separable, RestNode&& rest) {
    CV_Assert(grid.width >= 2 && grid.height >= 2 && outputSize.area() > 0);
    const int m = grid.width, n = grid.height;
    rest_ = out_ = outputSize;
    lo_ = rest(0, 0), hi_ = rest(m - 1, n - 1);
    owners_.clear();
    P_ = hugePageMat(Size(m + 2, n + 2), CV_32FC2, owners_);
    // Touched here, once: a first pose does not pay for the page faults of a fresh buffer.
    P_.setTo(Scalar::all(0));
    // Rest mesh: interior the rest nodes, ring the nearest one. A regular grid needs only its
    // column x and row y (the rows are made when drawn); any other rest mesh is stored whole.
    restX_.assign(m + 2, 0.f), restY_.assign(n + 2, 0.f);
    R_.release();
    if (separable) {
        for (int ex = 0; ex < m + 2; ++ex)
            restX_[ex] = rest(std::min(std::max(ex - 1, 0), m - 1), 0).x;
        for (int ey = 0; ey < n + 2; ++ey)
            restY_[ey] = rest(0, std::min(std::max(ey - 1, 0), n - 1)).y;
    } else {
        R_ = hugePageMat(Size(m + 2, n + 2), CV_32FC2, owners_);
        for (int ey = 0; ey < n + 2; ++ey) {
            Point2f* row = R_.ptr<Point2f>(ey);
            const int gy = std::min(std::max(ey - 1, 0), n - 1);
            for (int ex = 0; ex < m + 2; ++ex)
                row[ex] = rest(std::min(std::max(ex - 1, 0), m - 1), gy);
        }
    }
    rowMin_.resize(n + 1), rowMax_.resize(n + 1);
}

const Point2f* RasterMesh::restRow(int ey, std::vector<Point2f>& buffer) const {
    if (!R_.empty()) return R_.ptr<Point2f>(ey);
    buffer.resize(restX_.size());
    const float y = restY_[ey];
    for (size_t ex = 0; ex < restX_.size(); ++ex) buffer[ex] = Point2f(restX_[ex], y);
    return buffer.data();
}

void RasterMesh::reset(const Mat& rest, Size outputSize) {
    CV_Assert(rest.type() == CV_32FC2 && rest.rows >= 2 && rest.cols >= 2);
    resetWith(rest.size(), outputSize, false,
              [&](int gx, int gy) { return rest.at<Point2f>(gy, gx); });
}

void RasterMesh::reset(const Binding& binding) {
    // Node (gx, gy) rests at (x of column gx, y of row gy): two short tables instead of the
    // whole node grid.
    std::vector<float> xs(binding.gridSize.width), ys(binding.gridSize.height);
    for (int gx = 0; gx < binding.gridSize.width; ++gx) xs[gx] = binding.node(gx, 0).x;
    for (int gy = 0; gy < binding.gridSize.height; ++gy) ys[gy] = binding.node(0, gy).y;
    resetWith(binding.gridSize, binding.imageSize, true,
              [&](int gx, int gy) { return Point2f(xs[gx], ys[gy]); });
}

template <typename F>
void RasterMesh::forEachRingNode(F&& f) const {
    const int m = P_.cols - 2, n = P_.rows - 2;
    for (int ex = 0; ex < m + 2; ++ex) f(ex, 0);
    for (int ey = 1; ey < n + 1; ++ey) f(0, ey), f(m + 1, ey);
    for (int ex = 0; ex < m + 2; ++ex) f(ex, n + 1);
}

void RasterMesh::setFrame(const Point2f* frame) {
    // The mesh gets a ring of nodes on the image frame, around the node grid (whose outer nodes
    // sit on the border pixel centres, half a pixel inside the frame). A ring node follows the
    // frame as mean value coordinates do on a polygon edge (the frame corners interpolated
    // linearly) and samples the border pixel next to it. So the half-pixel band between the
    // frame and the border nodes is always covered: when border nodes move inwards the border
    // pixels stretch instead of leaving a line of border colour. deform.vert builds the same ring.
    const float W = static_cast<float>(rest_.width), H = static_cast<float>(rest_.height);
    std::array<Point2f, 4> corners = frameCorners(rest_);
    if (frame) std::copy(frame, frame + 4, corners.begin());
    const int m = P_.cols - 2, n = P_.rows - 2;
    forEachRingNode([&](int ex, int ey) {
        const Point2f source =
            R_.empty() ? Point2f(restX_[ex], restY_[ey]) : R_.at<Point2f>(ey, ex);
        const float rx = ex == 0 ? -0.5f : ex == m + 1 ? W - 0.5f : source.x;
        const float ry = ey == 0 ? -0.5f : ey == n + 1 ? H - 0.5f : source.y;
        const float u = (rx + 0.5f) / W, v = (ry + 0.5f) / H;
        P_.at<Point2f>(ey, ex) = (1 - u) * (1 - v) * corners[0] + u * (1 - v) * corners[1] +
                                 u * v * corners[2] + (1 - u) * v * corners[3];
    });
}

void RasterMesh::setOutputSize(Size outputSize) {
    CV_Assert(outputSize.area() > 0);
    out_ = outputSize;
}

void RasterMesh::draw(Mat& mapx, Mat& mapy) {
    CV_Assert(mapx.type() == CV_32F && mapy.type() == CV_32F && mapx.size() == out_ &&
              mapy.size() == out_);
    const Mat& P = P_;
    // Vertical extent of each row of cells, so that a band of output rows skips whole cell
    // rows: each node row's extent first (in parallel), then pairs of rows.
    std::vector<float> nodeMin(P.rows), nodeMax(P.rows);
    parallel_for_(
        Range(0, P.rows),
        [&](const Range& r) {
            for (int gy = r.start; gy < r.end; ++gy) {
                const Point2f* p = P.ptr<Point2f>(gy);
                float lo = INFINITY, hi = -INFINITY;
                for (int gx = 0; gx < P.cols; ++gx)
                    lo = std::min(lo, p[gx].y), hi = std::max(hi, p[gx].y);
                nodeMin[gy] = lo, nodeMax[gy] = hi;
            }
        },
        std::max(1.0, P.rows / 64.0));
    for (int gy = 0; gy + 1 < P.rows; ++gy)
        rowMin_[gy] = std::min(nodeMin[gy], nodeMin[gy + 1]),
        rowMax_[gy] = std::max(nodeMax[gy], nodeMax[gy + 1]);
    const std::vector<float>& rowMin = rowMin_;
    const std::vector<float>& rowMax = rowMax_;
    const Point2f lo = lo_, hi = hi_;
    const Size outputSize = out_;
    // Bands of output rows in parallel; each clears its rows, then walks the cells in the same
    // order, so where the mesh folds over, the later triangle wins exactly as in a GPU draw call.
    // Bands of 64 rows (two maps of 512 px: 256 KB, in cache while drawn) or more: the cell
    // rows across a band's edge are set up by both bands, so narrower ones repeat more work.
    const int bands = std::max(
        1, std::min(outputSize.height, std::max(getNumThreads() * 4, outputSize.height / 64)));
    const DrawCellRowFn kernel = cellRowKernel();
    parallel_for_(Range(0, bands), [&](const Range& range) {
        std::unique_ptr<TriangleSetup> setup(new TriangleSetup);
        std::vector<Point2f> rest0, rest1;  // rest rows of a regular grid
        for (int band = range.start; band < range.end; ++band) {
            const int y0 = outputSize.height * band / bands,
                      y1 = outputSize.height * (band + 1) / bands;
            for (int y = y0; y < y1; ++y) {
                std::fill_n(mapx.ptr<float>(y), outputSize.width, kUncovered);
                std::fill_n(mapy.ptr<float>(y), outputSize.width, kUncovered);
            }
            for (int gy = 0; gy + 1 < P.rows; ++gy) {
                if (rowMax[gy] < y0 - 1 || rowMin[gy] > y1 + 1) continue;
                const Point2f* p0 = P.ptr<Point2f>(gy);
                const Point2f* p1 = P.ptr<Point2f>(gy + 1);
                const Point2f* r0 = restRow(gy, rest0);
                const Point2f* r1 = restRow(gy + 1, rest1);
                kernel(p0, p1, r0, r1, P.cols - 1, y0, y1, lo, hi, mapx, mapy, *setup);
            }
        }
    });
}

void rasterizeMaps(InputArray positionsIn, InputArray restIn, Size outputSize, OutputArray mapxOut,
                   OutputArray mapyOut, InputArray frameIn) {
    Mat P = positionsIn.getMat(), R = restIn.getMat();
    CV_Assert(P.type() == CV_32FC2 && R.type() == CV_32FC2 && P.size() == R.size());
    CV_Assert(P.rows >= 2 && P.cols >= 2 && outputSize.area() > 0);
    Point2f corners[4];
    if (!frameIn.empty()) {
        Mat f = frameIn.getMat();
        CV_Assert(f.total() == 4 && f.type() == CV_32FC2);
        if (!f.isContinuous()) f = f.clone();
        std::copy(f.ptr<Point2f>(), f.ptr<Point2f>() + 4, corners);
    }
    RasterMesh mesh;
    mesh.reset(R, outputSize);
    P.copyTo(mesh.nodes());
    mesh.setFrame(frameIn.empty() ? nullptr : corners);
    mapxOut.create(outputSize, CV_32F);
    mapyOut.create(outputSize, CV_32F);
    Mat mapx = mapxOut.getMat(), mapy = mapyOut.getMat();
    mesh.draw(mapx, mapy);
}

namespace {

// The triangles of one row of cells (node rows p0/p1 deformed, r0/r1 rest) whose orientation
// differs between the two meshes. A loop over cells without branches, so that it vectorises: a
// random pose is checked on every node of a mesh, once per drawn pose.
MULTICAGE_TARGET_CLONES
int foldedInRow(const Point2f* p0, const Point2f* p1, const Point2f* r0, const Point2f* r1,
                int cells) {
    // The sign of cross(b - a, c - a): differences in float, products and their difference in
    // double (exact products of floats; no fused multiply-add in this file).
    auto orientation = [](Point2f a, Point2f b, Point2f c) {
        const double ux = b.x - a.x, uy = b.y - a.y, vx = c.x - a.x, vy = c.y - a.y;
        const double d = ux * vy - uy * vx;
        return (d > 0) - (d < 0);
    };
    int folded = 0;
    for (int gx = 0; gx < cells; ++gx) {
        const Point2f* p[2] = {p0 + gx, p1 + gx};
        const Point2f* r[2] = {r0 + gx, r1 + gx};
#pragma GCC unroll 2
        for (int t = 0; t < 2; ++t) {
            const auto& c = kCellTriangles[t];
            folded += orientation(p[c[0][1]][c[0][0]], p[c[1][1]][c[1][0]], p[c[2][1]][c[2][0]]) !=
                      orientation(r[c[0][1]][c[0][0]], r[c[1][1]][c[1][0]], r[c[2][1]][c[2][0]]);
        }
    }
    return folded;
}

}  // namespace

int countFoldedTriangles(InputArray positionsIn, InputArray restIn) {
    const Mat P = positionsIn.getMat(), R = restIn.getMat();
    CV_Assert(P.type() == CV_32FC2 && R.type() == CV_32FC2 && P.size() == R.size());
    int folded = 0;
    for (int gy = 0; gy + 1 < P.rows; ++gy)
        folded += foldedInRow(P.ptr<Point2f>(gy), P.ptr<Point2f>(gy + 1), R.ptr<Point2f>(gy),
                              R.ptr<Point2f>(gy + 1), P.cols - 1);
    return folded;
}

}  // namespace multicage
}  // namespace cv

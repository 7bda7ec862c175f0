// The pull kernel: inverse maps found pixel by pixel, each pixel walking to its triangle.
//
// Why: at grid step 1 a cell covers about one pixel, so the raster kernel spends its time on
// what a triangle costs whatever it covers (set-up, bounds, spans): 1.57 M triangles at
// 1024x768, about as long as reading all the coefficients. Where the mesh folds nowhere a pixel
// lies in exactly one triangle (pullable), so it can be found from the pixel instead: 16 pixels
// in lanes, a guess extrapolated from the two rows above, and Newton's method on the piecewise
// linear map, each step one cell's 4 nodes per pixel: 1.13 steps per vector at 1024x768 (bench
// --augment's pose). The 16 pixels' cells mostly lie in one or two rows of cells within 31
// columns (a quarter of the vectors span two): their nodes come from runs of 32 nodes loaded
// whole and looked up in registers, gathers (slow; 0.6% of the steps) only otherwise; the rows
// three ahead are prefetched, since the nodes were written by Binding::apply long enough ago to
// have left the cache. Four vectors are walked together, stage by stage: one vector's walk is a
// chain of dependent steps about as long as the core's reorder window, so walked one at a time
// the chains hardly overlap (together: 2.55-2.70 ms against 2.99-3.34 ms for 1024x768 on one
// thread, 2.4-2.5 ms with the frame test only near the border; 3 together were about as fast,
// 6 and 8 slower, their registers spilling). The cost is
// per pixel whatever the cell size, so at grid steps above 2 the raster is faster
// (RasterMesh::draw). Where the CPU has no AVX-512, the same walk runs in AVX2, 8 pixels at a
// time (pullRowsAvx2, below).

// First, before any other header (clang-format would sort it among them): the rasteriser's
// floating-point options.
// clang-format off
#include "raster_options.hpp"
// clang-format on

#include "mesh_pull.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <opencv2/core/utility.hpp>
#include <opencv2/multicage/internal/backend_contract.hpp>
#include <vector>

#include "cpu_level.hpp"

#if defined(__GNUC__) && defined(__x86_64__)
#if !defined(__clang__)
// GCC 12's AVX-512 headers start vectors from _mm512_undefined_*(), which -W(maybe-)uninitialized
// reports at every use.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif
#include <immintrin.h>
#define MULTICAGE_AVX512_PULL 1
#define MULTICAGE_PULL_TARGET __attribute__((target("avx512f,avx512vl,avx512dq,avx512bw,bmi2")))
// No "fma": the AVX2 walk computes each lane as the AVX-512 one does (raster_options.hpp).
#define MULTICAGE_AVX2_TARGET __attribute__((target("avx2")))
#if !defined(__clang__) && !defined(__SANITIZE_ADDRESS__)
#define MULTICAGE_TARGET_CLONES_PULL __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define MULTICAGE_TARGET_CLONES_PULL
#endif
#endif

namespace cv {
namespace multicage {
namespace raster {

#if defined(MULTICAGE_AVX512_PULL)
namespace {

// A triangle is pullable when cross(e1, e2) exceeds this part of |e1.x e2.y| + |e1.y e2.x|: its
// angles are not within 1e-4 rad of 0 or pi, so the float barycentrics of the walk hold 3 digits
// more than the edge tolerance needs.
constexpr float kSliver = 1e-4f;

// 16 points (x, y interleaved in lo, then hi) as x and y planes.
MULTICAGE_PULL_TARGET inline void deinterleave(__m512 lo, __m512 hi, __m512& x, __m512& y) {
    const __m512i even =
        _mm512_setr_epi32(0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30);
    x = _mm512_permutex2var_ps(lo, even, hi);
    y = _mm512_permutex2var_ps(lo, _mm512_add_epi32(even, _mm512_set1_epi32(1)), hi);
}

// Nodes p[0..n) (n <= 16) as x and y planes (0 past n); masked loads read nothing past p[n - 1].
MULTICAGE_PULL_TARGET inline void loadPlanes(const Point2f* p, int n, __m512& x, __m512& y) {
    const float* f = &p->x;
    if (n >= 16) return deinterleave(_mm512_loadu_ps(f), _mm512_loadu_ps(f + 16), x, y);
    const unsigned lo = 2u * std::min(std::max(n, 0), 8), hi = 2u * std::max(n - 8, 0);
    deinterleave(_mm512_maskz_loadu_ps(static_cast<__mmask16>(_bzhi_u32(0xffff, lo)), f),
                 _mm512_maskz_loadu_ps(static_cast<__mmask16>(_bzhi_u32(0xffff, hi)), f + 16), x,
                 y);
}

// Whether cross(e1, e2) is clearly positive (kSliver), per lane.
MULTICAGE_PULL_TARGET inline __mmask16 positive(__m512 e1x, __m512 e1y, __m512 e2x, __m512 e2y) {
    const __m512 l = _mm512_mul_ps(e1x, e2y), r = _mm512_mul_ps(e1y, e2x);
    return _mm512_cmp_ps_mask(
        _mm512_sub_ps(l, r),
        _mm512_mul_ps(_mm512_set1_ps(kSliver), _mm512_add_ps(_mm512_abs_ps(l), _mm512_abs_ps(r))),
        _CMP_GT_OQ);
}

// The triangles of cells [0, cells) of node rows p0, p1 (kCellTriangles: (a,b,c) and (b,d,c))
// that are not clearly positive; NaN and infinite nodes count (their tests are false).
MULTICAGE_PULL_TARGET int notPositiveInRow(const Point2f* p0, const Point2f* p1, int cells) {
    static_assert(kCellTriangles[0][1][0] == 1 && kCellTriangles[0][2][1] == 1 &&
                      kCellTriangles[1][0][0] == 1 && kCellTriangles[1][1][0] == 1 &&
                      kCellTriangles[1][1][1] == 1 && kCellTriangles[1][2][1] == 1,
                  "the legs below follow kCellTriangles");
    int bad = 0;
    for (int k = 0; k < cells; k += 16) {
        const int n = std::min(16, cells - k);
        __m512 ax, ay, bx, by, cx, cy, dx, dy;
        loadPlanes(p0 + k, n, ax, ay), loadPlanes(p0 + k + 1, n, bx, by);
        loadPlanes(p1 + k, n, cx, cy), loadPlanes(p1 + k + 1, n, dx, dy);
        const __mmask16 good = positive(_mm512_sub_ps(bx, ax), _mm512_sub_ps(by, ay),
                                        _mm512_sub_ps(cx, ax), _mm512_sub_ps(cy, ay)) &
                               positive(_mm512_sub_ps(dx, bx), _mm512_sub_ps(dy, by),
                                        _mm512_sub_ps(cx, bx), _mm512_sub_ps(cy, by));
        bad += _mm_popcnt_u32(_bzhi_u32(~unsigned(good), unsigned(n)));
    }
    return bad;
}

constexpr int kMaxSteps = 12;          // then the band is drawn by the raster kernel
constexpr int kTogether = 4;           // vectors of 16 pixels walked together (pullRows)
constexpr float kEdge = 1e-6f;         // barycentric tolerance: shared edges leave no crack
constexpr float kFrameMargin = 2e-3f;  // px: nearer the frame than this, the raster decides

// The x and y planes of 16 nodes gathered from P at idx (lanes of `lanes`).
MULTICAGE_PULL_TARGET inline void gatherNodes(const double* P, __m512i idx, __mmask16 lanes,
                                              __m512& x, __m512& y) {
    const __m512d lo = _mm512_mask_i32gather_pd(_mm512_setzero_pd(), static_cast<__mmask8>(lanes),
                                                _mm512_castsi512_si256(idx), P, 8);
    const __m512d hi =
        _mm512_mask_i32gather_pd(_mm512_setzero_pd(), static_cast<__mmask8>(lanes >> 8),
                                 _mm512_extracti64x4_epi64(idx, 1), P, 8);
    deinterleave(_mm512_castpd_ps(lo), _mm512_castpd_ps(hi), x, y);
}

// Up to 32 consecutive nodes of a row as x and y planes (two registers each), and lookups in them.
struct NodeRun {
    __m512 x0, x1, y0, y1;
    // Nodes p[0..min(32, available)).
    MULTICAGE_PULL_TARGET inline void load(const Point2f* p, int available) {
        loadPlanes(p, std::min(available, 16), x0, y0);
        loadPlanes(p + 16, std::min(available - 16, 16), x1, y1);
    }
    // Nodes i (0..31) of the run.
    MULTICAGE_PULL_TARGET inline void lookup(__m512i i, __m512& x, __m512& y) const {
        x = _mm512_permutex2var_ps(x0, i, x1), y = _mm512_permutex2var_ps(y0, i, y1);
    }
    // The same into the lanes of `lanes` of x and y.
    MULTICAGE_PULL_TARGET inline void lookupInto(__m512i i, __mmask16 lanes, __m512& x,
                                                 __m512& y) const {
        x = _mm512_mask_mov_ps(x, lanes, _mm512_permutex2var_ps(x0, i, x1));
        y = _mm512_mask_mov_ps(y, lanes, _mm512_permutex2var_ps(y0, i, y1));
    }
};

// (u, v) with p = o + u (p1 - o) + v (p2 - o), per lane: cross(p - o, p2 - o) and
// cross(p1 - o, p - o) over cross(p1 - o, p2 - o).
MULTICAGE_PULL_TARGET inline void barycentric(__m512 ox, __m512 oy, __m512 p1x, __m512 p1y,
                                              __m512 p2x, __m512 p2y, __m512 px, __m512 py,
                                              __m512& u, __m512& v) {
    const __m512 e1x = _mm512_sub_ps(p1x, ox), e1y = _mm512_sub_ps(p1y, oy);
    const __m512 e2x = _mm512_sub_ps(p2x, ox), e2y = _mm512_sub_ps(p2y, oy);
    const __m512 qx = _mm512_sub_ps(px, ox), qy = _mm512_sub_ps(py, oy);
    const __m512 inv = _mm512_div_ps(
        _mm512_set1_ps(1.f), _mm512_sub_ps(_mm512_mul_ps(e1x, e2y), _mm512_mul_ps(e1y, e2x)));
    u = _mm512_mul_ps(_mm512_sub_ps(_mm512_mul_ps(qx, e2y), _mm512_mul_ps(qy, e2x)), inv);
    v = _mm512_mul_ps(_mm512_sub_ps(_mm512_mul_ps(e1x, qy), _mm512_mul_ps(e1y, qx)), inv);
}

// Barycentric coordinates (a, b) of the third point 1 - a - b: inside the triangle, within the
// edge tolerance.
MULTICAGE_PULL_TARGET inline __mmask16 inTriangle(__m512 a, __m512 b) {
    const __m512 lo = _mm512_set1_ps(-kEdge), hi = _mm512_set1_ps(1.f + kEdge);
    return static_cast<__mmask16>(_mm512_cmp_ps_mask(a, lo, _CMP_GE_OQ) &
                                  _mm512_cmp_ps_mask(b, lo, _CMP_GE_OQ) &
                                  _mm512_cmp_ps_mask(_mm512_add_ps(a, b), hi, _CMP_LE_OQ));
}

// The rest coordinate of mesh column (or row) `node` of a binding's grid of `count` nodes every
// `step` px up to `last`: node min(max(node - 1, 0), count - 1)'s (the ring rests on its nearest).
MULTICAGE_PULL_TARGET inline __m512 restOf(__m512i node, int count, float step, float last) {
    const __m512i k = _mm512_min_epi32(_mm512_max_epi32(node, _mm512_setzero_si512()),
                                       _mm512_set1_epi32(count - 1));
    return _mm512_min_ps(_mm512_mul_ps(_mm512_cvtepi32_ps(k), _mm512_set1_ps(step)),
                         _mm512_set1_ps(last));
}

// The cell (column or row) of a point at cell `cell` plus `offset` cells, clamped to [0, last].
MULTICAGE_PULL_TARGET inline __m512i cellOf(__m512i cell, __m512 offset, __m512i last) {
    const __m512i whole = _mm512_cvttps_epi32(_mm512_roundscale_ps(offset, _MM_FROUND_TO_NEG_INF));
    return _mm512_min_epi32(_mm512_max_epi32(_mm512_add_epi32(cell, whole), _mm512_setzero_si512()),
                            last);
}

// The frame's edges as lines n.p + c (n a unit normal pointing inside): signed distances.
struct FrameLines {
    float nx[4], ny[4], c[4];
};

// The ring's corner nodes TL, TR, BR, BL: the frame the mesh's outer boundary runs along.
std::array<Point2d, 4> ringCorners(const PullMesh& m) {
    const Point2f* P = m.nodes;
    const size_t C = m.cols, last = size_t(m.rows - 1) * C;
    return {Point2d(P[0]), Point2d(P[C - 1]), Point2d(P[last + C - 1]), Point2d(P[last])};
}

// The frame's edges (the ring's outer boundary) as lines.
FrameLines frameLines(const PullMesh& m) {
    FrameLines frame;
    const std::array<Point2d, 4> q = ringCorners(m);
    for (int i = 0; i < 4; ++i) {
        const Point2d e = q[(i + 1) % 4] - q[i];
        const double len = std::sqrt(e.dot(e));
        const double nx = -e.y / len, ny = e.x / len;
        frame.nx[i] = float(nx), frame.ny[i] = float(ny);
        frame.c[i] = float(-(nx * q[i].x + ny * q[i].y));
    }
    return frame;
}
}  // namespace

bool frameConvex(const PullMesh& m) {
    if (m.cols < 2 || m.rows < 2) return false;
    // The ring's outer boundary: the frame quadrilateral TL, TR, BR, BL, convex and turning as
    // the rest grid does (cross((1,0), (0,1)) > 0 in the y-down image).
    const std::array<Point2d, 4> q = ringCorners(m);
    for (int i = 0; i < 4; ++i) {
        const Point2d u = q[(i + 1) % 4] - q[i], v = q[(i + 2) % 4] - q[(i + 1) % 4];
        if (!(u.x * v.y - u.y * v.x > 0)) return false;
    }
    return true;
}

MULTICAGE_PULL_TARGET
bool positiveRowsAvx512(const PullMesh& m, int ey0, int ey1) {
    const Point2f* P = m.nodes;
    const size_t C = m.cols;
    for (int ey = std::max(ey0, 0); ey < std::min(ey1, m.rows - 1); ++ey)
        if (notPositiveInRow(P + size_t(ey) * C, P + size_t(ey + 1) * C, m.cols - 1) > 0)
            return false;
    return true;
}

bool pullable(const PullMesh& m) {
    if (!frameConvex(m)) return false;
    // Every triangle, in parallel. (A pose drawn by RasterMesh::pose is checked while
    // Binding::apply writes its nodes instead, block by block of rows in cache.)
    std::atomic<bool> good{true};
    parallel_for_(
        Range(0, m.rows - 1),
        [&](const Range& r) {
            if (good && !positiveRows(m, r.start, r.end)) good = false;
        },
        std::max(1.0, (m.rows - 1) / 64.0));
    return good;
}

MULTICAGE_PULL_TARGET
bool pullRowsAvx512(const PullMesh& m, int y0, int y1, Mat& mapx, Mat& mapy) {
    CV_Assert(y0 % kPullRun == 0);
    const int W = mapx.cols, H = mapx.rows, C = m.cols;
    const int cellsX = m.cols - 1, cellsY = m.rows - 1;
    const double* P = reinterpret_cast<const double*>(m.nodes);
    const FrameLines frame = frameLines(m);
    // A guess for the first row: nodes 1..cols-2 rest on pixels 0..W-1 of a frame at rest.
    const float sx = W > 1 ? float(m.cols - 3) / float(W - 1) : 0.f;
    const float sy = H > 1 ? float(m.rows - 3) / float(H - 1) : 0.f;
    // Where each pixel of the two rows above ended, in cell coordinates (cell + barycentric).
    thread_local std::vector<float> estimates;
    // (padded: the last vectors of a group of kTogether may start past the row's end, and each
    // reads 16 estimates)
    estimates.resize(4 * (size_t(W) + 16 * kTogether));
    float* e1x = estimates.data();
    float* e1y = e1x + W + 16 * kTogether;
    float* e2x = e1y + W + 16 * kTogether;
    float* e2y = e2x + W + 16 * kTogether;

    const __m512 iota = _mm512_setr_ps(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    const __m512 zero = _mm512_setzero_ps(), one = _mm512_set1_ps(1.f);
    const __m512i cols = _mm512_set1_epi32(C);
    for (int y = y0; y < y1; ++y) {
        float* mx = mapx.ptr<float>(y);
        float* my = mapy.ptr<float>(y);
        const int seen = y % kPullRun;  // rows of this run already pulled
        const __m512 py = _mm512_set1_ps(float(y) * m.spacing.y);
        // kTogether vectors of 16 pixels at a time, each stage for all of them before the next (the
        // chains of dependent steps, cell, node loads, barycentrics with a division, then
        // overlap). Each vector's walk is the same as alone, step for step: a vector whose walk
        // has ended skips the stages while the others go on.
        for (int x0 = 0; x0 < W; x0 += 16 * kTogether) {
            __mmask16 lanes[kTogether], active[kTogether], covered[kTogether];
            __m512 px[kTogether], gu[kTogether], gv[kTogether], fu[kTogether], fv[kTogether];
            __m512i gcx[kTogether], gcy[kTogether], cellX[kTogether], cellY[kTogether];
            for (int v = 0; v < kTogether; ++v) {
                const int xv = x0 + 16 * v;
                // (at most 16: BZHI reads only the low 8 bits of its index)
                lanes[v] =
                    xv < W
                        ? static_cast<__mmask16>(_bzhi_u32(0xffff, unsigned(std::min(W - xv, 16))))
                        : 0;
                const __m512 ix = _mm512_add_ps(_mm512_set1_ps(float(xv)), iota);
                px[v] = _mm512_mul_ps(ix, _mm512_set1_ps(m.spacing.x));
                __m512 gx, gy;
                if (seen >= 2) {  // extrapolated from the two rows above
                    const __m512 ax = _mm512_loadu_ps(e1x + xv), ay = _mm512_loadu_ps(e1y + xv);
                    gx = _mm512_sub_ps(_mm512_add_ps(ax, ax), _mm512_loadu_ps(e2x + xv));
                    gy = _mm512_sub_ps(_mm512_add_ps(ay, ay), _mm512_loadu_ps(e2y + xv));
                } else if (seen == 1) {
                    gx = _mm512_loadu_ps(e1x + xv);
                    gy = _mm512_add_ps(_mm512_loadu_ps(e1y + xv), _mm512_set1_ps(sy));
                } else {
                    gx = _mm512_add_ps(one, _mm512_mul_ps(ix, _mm512_set1_ps(sx)));
                    gy = _mm512_set1_ps(1.f + float(y) * sy);
                }
                // The guess as a cell and coordinates in it: a walk's step is then decided by its
                // own cell's coordinates (a pixel 1e-6 left of a cell, whose absolute coordinate
                // 634 - 1e-6 rounds to 634 in float, still goes left).
                const __m512 big = _mm512_set1_ps(float(std::max(cellsX, cellsY) + 1));
                gx = _mm512_min_ps(_mm512_max_ps(gx, _mm512_set1_ps(-1.f)), big);  // NaN: -1
                gy = _mm512_min_ps(_mm512_max_ps(gy, _mm512_set1_ps(-1.f)), big);
                const __m512 fx = _mm512_roundscale_ps(gx, _MM_FROUND_TO_NEG_INF);
                const __m512 fy = _mm512_roundscale_ps(gy, _MM_FROUND_TO_NEG_INF);
                gcx[v] = _mm512_cvttps_epi32(fx), gcy[v] = _mm512_cvttps_epi32(fy);
                gu[v] = _mm512_sub_ps(gx, fx), gv[v] = _mm512_sub_ps(gy, fy);
                active[v] = lanes[v], covered[v] = 0;
                cellX[v] = cellY[v] = _mm512_setzero_si512();
                fu[v] = fv[v] = zero;
            }
            const __m512i zeroI = _mm512_setzero_si512(), oneI = _mm512_set1_epi32(1);
            const __m512i lastXi = _mm512_set1_epi32(cellsX - 1),
                          lastYi = _mm512_set1_epi32(cellsY - 1);
            const __m512i edgeX = _mm512_set1_epi32(cellsX - 2),
                          edgeY = _mm512_set1_epi32(cellsY - 2);
            auto anyActive = [&] {
                unsigned any = 0;
                for (int v = 0; v < kTogether; ++v) any |= active[v];
                return any != 0;
            };
            for (int step = 0; anyActive(); ++step) {
                if (step == kMaxSteps) return false;
                __m512i cx[kTogether], cy[kTogether];
                __m512 ax[kTogether], ay[kTogether], bx[kTogether], by[kTogether];
                __m512 cxv[kTogether], cyv[kTogether], dx[kTogether], dy[kTogether];
                for (int v = 0; v < kTogether; ++v) {
                    // The cell of the guess, clamped to the mesh.
                    cx[v] = cellOf(gcx[v], gu[v], lastXi);
                    cy[v] = cellOf(gcy[v], gv[v], lastYi);
                }
                for (int v = 0; v < kTogether; ++v) {
                    if (!active[v]) continue;  // walked to its end (or past the row's end)
                    // The cells of 16 neighbouring pixels mostly lie in one row of cells, within
                    // 31 cells: their nodes are then read from two runs of 32 nodes (loads and
                    // in-register lookups), else gathered one by one.
                    const int firstX = _mm512_mask_reduce_min_epi32(active[v], cx[v]);
                    const int row = _mm512_mask_reduce_min_epi32(active[v], cy[v]);
                    const __m512i local = _mm512_sub_epi32(cx[v], _mm512_set1_epi32(firstX));
                    const __mmask16 lower = _mm512_cmpgt_epi32_mask(cy[v], _mm512_set1_epi32(row));
                    if (!(active[v] & ~(_mm512_cmple_epi32_mask(cy[v], _mm512_set1_epi32(row + 1)) &
                                        _mm512_cmple_epi32_mask(local, _mm512_set1_epi32(30))))) {
                        // Cells in rows `row` and `row + 1`: node runs of rows row..row+2, the
                        // lanes of the lower cell row taking theirs from the runs one row down.
                        const __m512i local1 = _mm512_add_epi32(local, oneI);
                        if (step == 0 && row + 3 < m.rows) {  // the next rows' nodes, on their way
                            const char* ahead = reinterpret_cast<const char*>(
                                m.nodes + size_t(row + 3) * C + firstX);
                            for (int line = 0; line < 4; ++line)
                                _mm_prefetch(ahead + 64 * line, _MM_HINT_T0);
                        }
                        NodeRun r0, r1;
                        r0.load(m.nodes + size_t(row) * C + firstX, C - firstX);
                        r1.load(m.nodes + size_t(row + 1) * C + firstX, C - firstX);
                        r0.lookup(local, ax[v], ay[v]), r0.lookup(local1, bx[v], by[v]);
                        r1.lookup(local, cxv[v], cyv[v]), r1.lookup(local1, dx[v], dy[v]);
                        if (active[v] & lower) {
                            NodeRun r2;
                            r2.load(m.nodes + size_t(row + 2) * C + firstX, C - firstX);
                            r1.lookupInto(local, lower, ax[v], ay[v]);
                            r1.lookupInto(local1, lower, bx[v], by[v]);
                            r2.lookupInto(local, lower, cxv[v], cyv[v]);
                            r2.lookupInto(local1, lower, dx[v], dy[v]);
                        }
                    } else {
                        const __m512i ia = _mm512_add_epi32(_mm512_mullo_epi32(cy[v], cols), cx[v]);
                        const __m512i ic = _mm512_add_epi32(ia, cols);
                        gatherNodes(P, ia, active[v], ax[v], ay[v]);
                        gatherNodes(P, _mm512_add_epi32(ia, oneI), active[v], bx[v], by[v]);
                        gatherNodes(P, ic, active[v], cxv[v], cyv[v]);
                        gatherNodes(P, _mm512_add_epi32(ic, oneI), active[v], dx[v], dy[v]);
                    }
                }
                // Triangle 0 (a, b, c): p = a + u (b - a) + v (c - a); triangle 1 (b, d, c):
                // p = d + s (c - d) + t (b - d).
                __m512 u[kTogether], w[kTogether], s[kTogether], t[kTogether];
                for (int v = 0; v < kTogether; ++v) {
                    if (!active[v]) continue;
                    barycentric(ax[v], ay[v], bx[v], by[v], cxv[v], cyv[v], px[v], py, u[v], w[v]);
                    barycentric(dx[v], dy[v], cxv[v], cyv[v], bx[v], by[v], px[v], py, s[v], t[v]);
                }
                __mmask16 leaving[kTogether];
                for (int v = 0; v < kTogether; ++v) {
                    leaving[v] = 0;
                    if (!active[v]) continue;  // its walk has ended: its state stays as it ended
                    const __mmask16 in0 = inTriangle(u[v], w[v]), in1 = inTriangle(s[v], t[v]);
                    // Cell coordinates of p by triangle 1 where it holds p (later in drawing
                    // order, so it wins a shared edge as in the raster) or, neither holding it,
                    // where p lies on its side of the diagonal; else by triangle 0.
                    const __mmask16 half0 =
                        _mm512_cmp_ps_mask(_mm512_add_ps(u[v], w[v]), one, _CMP_LE_OQ);
                    const __mmask16 by1 = in1 | (static_cast<__mmask16>(~in0) & ~half0);
                    const __m512 U = _mm512_mask_sub_ps(u[v], by1, one, s[v]);
                    const __m512 V = _mm512_mask_sub_ps(w[v], by1, one, t[v]);
                    const __mmask16 found = active[v] & (in0 | in1);
                    cellX[v] = _mm512_mask_mov_epi32(cellX[v], found, cx[v]);
                    cellY[v] = _mm512_mask_mov_epi32(cellY[v], found, cy[v]);
                    fu[v] = _mm512_mask_mov_ps(fu[v], found, U);
                    fv[v] = _mm512_mask_mov_ps(fv[v], found, V);
                    covered[v] |= found;
                    active[v] &= static_cast<__mmask16>(~found);
                    // Newton's step: the cell coordinates of p by this cell's affine map, at most
                    // a few cells away (then one) so that a poor guess cannot oscillate far.
                    const float reach = step < 6 ? 4.f : 1.f;
                    gcx[v] = cx[v], gcy[v] = cy[v];
                    gu[v] = _mm512_min_ps(_mm512_max_ps(U, _mm512_set1_ps(-reach)),
                                          _mm512_set1_ps(1.f + reach));
                    gv[v] = _mm512_min_ps(_mm512_max_ps(V, _mm512_set1_ps(-reach)),
                                          _mm512_set1_ps(1.f + reach));
                    // A walk that would leave the mesh from its border cells: p is outside the
                    // frame (uncovered, done), clearly inside (it goes on along the border), or
                    // on it.
                    // (cx - 1 as unsigned: at least cellsX - 2 only for the first and last
                    // column of cells, the same for rows)
                    const __mmask16 edge =
                        active[v] & (_mm512_cmpge_epu32_mask(_mm512_sub_epi32(cx[v], oneI), edgeX) |
                                     _mm512_cmpge_epu32_mask(_mm512_sub_epi32(cy[v], oneI), edgeY));
                    if (!edge) continue;
                    leaving[v] = active[v] & ((_mm512_cmpeq_epi32_mask(cx[v], zeroI) &
                                               _mm512_cmp_ps_mask(gu[v], zero, _CMP_LT_OQ)) |
                                              (_mm512_cmpeq_epi32_mask(cx[v], lastXi) &
                                               _mm512_cmp_ps_mask(gu[v], one, _CMP_GE_OQ)) |
                                              (_mm512_cmpeq_epi32_mask(cy[v], zeroI) &
                                               _mm512_cmp_ps_mask(gv[v], zero, _CMP_LT_OQ)) |
                                              (_mm512_cmpeq_epi32_mask(cy[v], lastYi) &
                                               _mm512_cmp_ps_mask(gv[v], one, _CMP_GE_OQ)));
                }
                for (int v = 0; v < kTogether; ++v) {
                    if (!leaving[v]) continue;
                    __mmask16 outside = 0, inside = 0xffff;
                    for (int i = 0; i < 4; ++i) {
                        const __m512 d = _mm512_add_ps(
                            _mm512_add_ps(_mm512_mul_ps(_mm512_set1_ps(frame.nx[i]), px[v]),
                                          _mm512_mul_ps(_mm512_set1_ps(frame.ny[i]), py)),
                            _mm512_set1_ps(frame.c[i]));
                        outside |= _mm512_cmp_ps_mask(d, _mm512_set1_ps(-kFrameMargin), _CMP_LT_OQ);
                        inside &= _mm512_cmp_ps_mask(d, _mm512_set1_ps(kFrameMargin), _CMP_GT_OQ);
                    }
                    if (leaving[v] & ~outside & ~inside) return false;  // on the frame
                    active[v] &= static_cast<__mmask16>(~(leaving[v] & outside));
                }
            }
            for (int v = 0; v < kTogether; ++v) {
                if (!lanes[v]) continue;
                const int xv = x0 + 16 * v;
                // Rest points: X0 + U (X1 - X0), Y0 + V (Y1 - Y0) of the cell each pixel lies in.
                const __m512 X0 =
                    restOf(_mm512_sub_epi32(cellX[v], oneI), m.gridSize.width, m.step, m.hi.x);
                const __m512 X1 = restOf(cellX[v], m.gridSize.width, m.step, m.hi.x);
                const __m512 Y0 =
                    restOf(_mm512_sub_epi32(cellY[v], oneI), m.gridSize.height, m.step, m.hi.y);
                const __m512 Y1 = restOf(cellY[v], m.gridSize.height, m.step, m.hi.y);
                const __m512 rx = _mm512_add_ps(X0, _mm512_mul_ps(fu[v], _mm512_sub_ps(X1, X0)));
                const __m512 ry = _mm512_add_ps(Y0, _mm512_mul_ps(fv[v], _mm512_sub_ps(Y1, Y0)));
                const __m512 none = _mm512_set1_ps(kUncovered);
                const __m512 outX =
                    _mm512_mask_mov_ps(none, covered[v],
                                       _mm512_min_ps(_mm512_set1_ps(m.hi.x),
                                                     _mm512_max_ps(_mm512_set1_ps(m.lo.x), rx)));
                const __m512 outY =
                    _mm512_mask_mov_ps(none, covered[v],
                                       _mm512_min_ps(_mm512_set1_ps(m.hi.y),
                                                     _mm512_max_ps(_mm512_set1_ps(m.lo.y), ry)));
                _mm512_mask_storeu_ps(mx + xv, lanes[v], outX);
                _mm512_mask_storeu_ps(my + xv, lanes[v], outY);
                // Where each pixel ended, for the guesses of the next rows (uncovered: the last
                // guess).
                const __m512 ex =
                    _mm512_mask_add_ps(_mm512_add_ps(_mm512_cvtepi32_ps(gcx[v]), gu[v]), covered[v],
                                       _mm512_cvtepi32_ps(cellX[v]), fu[v]);
                const __m512 ey =
                    _mm512_mask_add_ps(_mm512_add_ps(_mm512_cvtepi32_ps(gcy[v]), gv[v]), covered[v],
                                       _mm512_cvtepi32_ps(cellY[v]), fv[v]);
                _mm512_mask_storeu_ps(e2x + xv, lanes[v], ex);
                _mm512_mask_storeu_ps(e2y + xv, lanes[v], ey);
            }
        }
        std::swap(e1x, e2x), std::swap(e1y, e2y);  // this row's estimates become the row above
    }
    return true;
}

// ---- The AVX2 walk: the same walk, 8 pixels in lanes, one vector at a time, every node
// gathered (AVX2 has no two-register lookups). Each lane's arithmetic is the AVX-512 kernel's,
// operation for operation, so a pixel walks the same steps to the same triangle; only the
// guesses of pixels outside the frame (whose last guess goes on with their vector's walk) may
// differ, and with them, rarely, which of two triangles sharing an edge a pixel below them
// settles in (values within a float rounding of each other).
namespace {

// 8 points (x, y interleaved in lo, then hi) as x and y planes.
MULTICAGE_AVX2_TARGET inline void deinterleave8(__m256 lo, __m256 hi, __m256& x, __m256& y) {
    // shuffle: x0 x1 x4 x5 | x2 x3 x6 x7; the 64-bit permute puts the pairs in order.
    x = _mm256_castpd_ps(
        _mm256_permute4x64_pd(_mm256_castps_pd(_mm256_shuffle_ps(lo, hi, _MM_SHUFFLE(2, 0, 2, 0))),
                              _MM_SHUFFLE(3, 1, 2, 0)));
    y = _mm256_castpd_ps(
        _mm256_permute4x64_pd(_mm256_castps_pd(_mm256_shuffle_ps(lo, hi, _MM_SHUFFLE(3, 1, 3, 1))),
                              _MM_SHUFFLE(3, 1, 2, 0)));
}

// The x and y planes of 8 nodes gathered from P at idx (lanes of `lanes`, all ones or zero).
MULTICAGE_AVX2_TARGET inline void gather8(const double* P, __m256i idx, __m256i lanes, __m256& x,
                                          __m256& y) {
    const __m256d m0 = _mm256_castsi256_pd(_mm256_cvtepi32_epi64(_mm256_castsi256_si128(lanes)));
    const __m256d m1 =
        _mm256_castsi256_pd(_mm256_cvtepi32_epi64(_mm256_extracti128_si256(lanes, 1)));
    const __m256d lo =
        _mm256_mask_i32gather_pd(_mm256_setzero_pd(), P, _mm256_castsi256_si128(idx), m0, 8);
    const __m256d hi =
        _mm256_mask_i32gather_pd(_mm256_setzero_pd(), P, _mm256_extracti128_si256(idx, 1), m1, 8);
    deinterleave8(_mm256_castpd_ps(lo), _mm256_castpd_ps(hi), x, y);
}

// The least and the most of 8 ints.
MULTICAGE_AVX2_TARGET inline int hmin8(__m256i v) {
    __m128i m = _mm_min_epi32(_mm256_castsi256_si128(v), _mm256_extracti128_si256(v, 1));
    m = _mm_min_epi32(m, _mm_shuffle_epi32(m, _MM_SHUFFLE(1, 0, 3, 2)));
    return _mm_cvtsi128_si32(_mm_min_epi32(m, _mm_shuffle_epi32(m, _MM_SHUFFLE(2, 3, 0, 1))));
}
MULTICAGE_AVX2_TARGET inline int hmax8(__m256i v) {
    __m128i m = _mm_max_epi32(_mm256_castsi256_si128(v), _mm256_extracti128_si256(v, 1));
    m = _mm_max_epi32(m, _mm_shuffle_epi32(m, _MM_SHUFFLE(1, 0, 3, 2)));
    return _mm_cvtsi128_si32(_mm_max_epi32(m, _mm_shuffle_epi32(m, _MM_SHUFFLE(2, 3, 0, 1))));
}

// 16 consecutive nodes of a row as x and y planes (two registers each), and lookups in them.
struct NodeRun16 {
    __m256 x0, x1, y0, y1;
    MULTICAGE_AVX2_TARGET explicit NodeRun16(const Point2f* p) {
        const float* f = &p->x;
        deinterleave8(_mm256_loadu_ps(f), _mm256_loadu_ps(f + 8), x0, y0);
        deinterleave8(_mm256_loadu_ps(f + 16), _mm256_loadu_ps(f + 24), x1, y1);
    }
    // Nodes i (0..15) of the run.
    MULTICAGE_AVX2_TARGET inline void lookup(__m256i i, __m256& x, __m256& y) const {
        const __m256 upper = _mm256_castsi256_ps(_mm256_cmpgt_epi32(i, _mm256_set1_epi32(7)));
        x = _mm256_blendv_ps(_mm256_permutevar8x32_ps(x0, i), _mm256_permutevar8x32_ps(x1, i),
                             upper);
        y = _mm256_blendv_ps(_mm256_permutevar8x32_ps(y0, i), _mm256_permutevar8x32_ps(y1, i),
                             upper);
    }
};

// barycentric() of the AVX-512 kernel.
MULTICAGE_AVX2_TARGET inline void barycentric8(__m256 ox, __m256 oy, __m256 p1x, __m256 p1y,
                                               __m256 p2x, __m256 p2y, __m256 px, __m256 py,
                                               __m256& u, __m256& v) {
    const __m256 e1x = _mm256_sub_ps(p1x, ox), e1y = _mm256_sub_ps(p1y, oy);
    const __m256 e2x = _mm256_sub_ps(p2x, ox), e2y = _mm256_sub_ps(p2y, oy);
    const __m256 qx = _mm256_sub_ps(px, ox), qy = _mm256_sub_ps(py, oy);
    const __m256 inv = _mm256_div_ps(
        _mm256_set1_ps(1.f), _mm256_sub_ps(_mm256_mul_ps(e1x, e2y), _mm256_mul_ps(e1y, e2x)));
    u = _mm256_mul_ps(_mm256_sub_ps(_mm256_mul_ps(qx, e2y), _mm256_mul_ps(qy, e2x)), inv);
    v = _mm256_mul_ps(_mm256_sub_ps(_mm256_mul_ps(e1x, qy), _mm256_mul_ps(e1y, qx)), inv);
}

// inTriangle() of the AVX-512 kernel, as a lane mask (all ones or zero).
MULTICAGE_AVX2_TARGET inline __m256 inTriangle8(__m256 a, __m256 b) {
    const __m256 lo = _mm256_set1_ps(-kEdge), hi = _mm256_set1_ps(1.f + kEdge);
    return _mm256_and_ps(
        _mm256_and_ps(_mm256_cmp_ps(a, lo, _CMP_GE_OQ), _mm256_cmp_ps(b, lo, _CMP_GE_OQ)),
        _mm256_cmp_ps(_mm256_add_ps(a, b), hi, _CMP_LE_OQ));
}

// restOf() of the AVX-512 kernel.
MULTICAGE_AVX2_TARGET inline __m256 restOf8(__m256i node, int count, float step, float last) {
    const __m256i k = _mm256_min_epi32(_mm256_max_epi32(node, _mm256_setzero_si256()),
                                       _mm256_set1_epi32(count - 1));
    return _mm256_min_ps(_mm256_mul_ps(_mm256_cvtepi32_ps(k), _mm256_set1_ps(step)),
                         _mm256_set1_ps(last));
}

// cellOf() of the AVX-512 kernel.
MULTICAGE_AVX2_TARGET inline __m256i cellOf8(__m256i cell, __m256 offset, __m256i last) {
    const __m256i whole = _mm256_cvttps_epi32(_mm256_floor_ps(offset));
    return _mm256_min_epi32(_mm256_max_epi32(_mm256_add_epi32(cell, whole), _mm256_setzero_si256()),
                            last);
}

MULTICAGE_AVX2_TARGET inline __m256 asMask(__m256i m) {
    return _mm256_castsi256_ps(m);
}
MULTICAGE_AVX2_TARGET inline __m256i asInt(__m256 m) {
    return _mm256_castps_si256(m);
}
MULTICAGE_AVX2_TARGET inline bool none(__m256 m) {
    return _mm256_testz_ps(m, m) != 0;
}

// One vector's walk: its 8 pixels' guesses, where they settled, and which are still walking.
struct Walk8 {
    __m256i lanesI;  // the vector's pixels in the row (all ones), the rest zero
    __m256 px;
    __m256i gcx, gcy, cellX, cellY;
    __m256 gu, gv, fu, fv, active, covered;
};

// What a pull of rows needs besides the walks: the mesh and the constants of its frame.
struct Pull8 {
    const PullMesh& m;
    const double* P;
    FrameLines frame;
    __m256i cols, lastXi, lastYi;

    // One step of a walk for row y (step: how many it made before): the cell of each walking
    // pixel's guess, that cell's two triangles, then settled, left the frame, or the next guess.
    // False when a pixel is on the frame (the raster decides).
    MULTICAGE_AVX2_TARGET __attribute__((always_inline)) inline bool step(Walk8& k, __m256 py,
                                                                          int step) const {
        const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.f);
        const __m256i zeroI = _mm256_setzero_si256(), oneI = _mm256_set1_epi32(1);
        const __m256i cx = cellOf8(k.gcx, k.gu, lastXi), cy = cellOf8(k.gcy, k.gv, lastYi);
        __m256 ax, ay, bx, by, cxv, cyv, dx, dy;
        // The cells of 8 neighbouring pixels mostly lie in one row of cells within 15 columns
        // (89% of the steps at 1024x768): their nodes are then read as runs of 16 and looked up
        // in registers, else gathered (gathering all, with masked stores: 15.0-15.5 ms against
        // 13.0-14.1 ms for the pull of 1024x768 on one thread of this project's AMD machine).
        const __m256i act = asInt(k.active);
        const __m256i most = _mm256_set1_epi32(INT32_MAX), least = _mm256_set1_epi32(INT32_MIN);
        const int firstX = hmin8(_mm256_blendv_epi8(most, cx, act));
        const int lastX = hmax8(_mm256_blendv_epi8(least, cx, act));
        const int row = hmin8(_mm256_blendv_epi8(most, cy, act));
        const int lastRow = hmax8(_mm256_blendv_epi8(least, cy, act));
        if (row == lastRow && lastX - firstX <= 14 && firstX + 16 <= m.cols) {
            const __m256i local = _mm256_sub_epi32(cx, _mm256_set1_epi32(firstX));
            const __m256i local1 = _mm256_add_epi32(local, oneI);
            const NodeRun16 r0(m.nodes + size_t(row) * m.cols + firstX);
            const NodeRun16 r1(m.nodes + size_t(row + 1) * m.cols + firstX);
            r0.lookup(local, ax, ay), r0.lookup(local1, bx, by);
            r1.lookup(local, cxv, cyv), r1.lookup(local1, dx, dy);
        } else {
            const __m256i ia = _mm256_add_epi32(_mm256_mullo_epi32(cy, cols), cx);
            const __m256i ic = _mm256_add_epi32(ia, cols);
            gather8(P, ia, act, ax, ay);
            gather8(P, _mm256_add_epi32(ia, oneI), act, bx, by);
            gather8(P, ic, act, cxv, cyv);
            gather8(P, _mm256_add_epi32(ic, oneI), act, dx, dy);
        }
        __m256 u, w, s, t;
        barycentric8(ax, ay, bx, by, cxv, cyv, k.px, py, u, w);
        barycentric8(dx, dy, cxv, cyv, bx, by, k.px, py, s, t);
        const __m256 in0 = inTriangle8(u, w), in1 = inTriangle8(s, t);
        const __m256 half0 = _mm256_cmp_ps(_mm256_add_ps(u, w), one, _CMP_LE_OQ);
        // in1 | (~in0 & ~half0)
        const __m256 by1 = _mm256_or_ps(
            in1, _mm256_andnot_ps(_mm256_or_ps(in0, half0), asMask(_mm256_set1_epi32(-1))));
        const __m256 U = _mm256_blendv_ps(u, _mm256_sub_ps(one, s), by1);
        const __m256 V = _mm256_blendv_ps(w, _mm256_sub_ps(one, t), by1);
        const __m256 found = _mm256_and_ps(k.active, _mm256_or_ps(in0, in1));
        k.cellX = asInt(_mm256_blendv_ps(asMask(k.cellX), asMask(cx), found));
        k.cellY = asInt(_mm256_blendv_ps(asMask(k.cellY), asMask(cy), found));
        k.fu = _mm256_blendv_ps(k.fu, U, found);
        k.fv = _mm256_blendv_ps(k.fv, V, found);
        k.covered = _mm256_or_ps(k.covered, found);
        k.active = _mm256_andnot_ps(found, k.active);
        const float reach = step < 6 ? 4.f : 1.f;
        k.gcx = cx, k.gcy = cy;
        k.gu = _mm256_min_ps(_mm256_max_ps(U, _mm256_set1_ps(-reach)), _mm256_set1_ps(1.f + reach));
        k.gv = _mm256_min_ps(_mm256_max_ps(V, _mm256_set1_ps(-reach)), _mm256_set1_ps(1.f + reach));
        const __m256 leaving = _mm256_and_ps(
            k.active,
            _mm256_or_ps(_mm256_or_ps(_mm256_and_ps(asMask(_mm256_cmpeq_epi32(cx, zeroI)),
                                                    _mm256_cmp_ps(k.gu, zero, _CMP_LT_OQ)),
                                      _mm256_and_ps(asMask(_mm256_cmpeq_epi32(cx, lastXi)),
                                                    _mm256_cmp_ps(k.gu, one, _CMP_GE_OQ))),
                         _mm256_or_ps(_mm256_and_ps(asMask(_mm256_cmpeq_epi32(cy, zeroI)),
                                                    _mm256_cmp_ps(k.gv, zero, _CMP_LT_OQ)),
                                      _mm256_and_ps(asMask(_mm256_cmpeq_epi32(cy, lastYi)),
                                                    _mm256_cmp_ps(k.gv, one, _CMP_GE_OQ)))));
        if (none(leaving)) return true;
        __m256 outside = zero, inside = asMask(_mm256_set1_epi32(-1));
        for (int i = 0; i < 4; ++i) {
            const __m256 d =
                _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(_mm256_set1_ps(frame.nx[i]), k.px),
                                            _mm256_mul_ps(_mm256_set1_ps(frame.ny[i]), py)),
                              _mm256_set1_ps(frame.c[i]));
            outside =
                _mm256_or_ps(outside, _mm256_cmp_ps(d, _mm256_set1_ps(-kFrameMargin), _CMP_LT_OQ));
            inside =
                _mm256_and_ps(inside, _mm256_cmp_ps(d, _mm256_set1_ps(kFrameMargin), _CMP_GT_OQ));
        }
        if (!none(_mm256_andnot_ps(_mm256_or_ps(outside, inside), leaving))) return false;
        k.active = _mm256_andnot_ps(_mm256_and_ps(leaving, outside), k.active);
        return true;
    }
};

// One vector at a time: walking 2, 3 or 4 side by side, as the AVX-512 kernel does, made no
// difference on this project's AMD machine (1024x768, one thread: 13.6-14.0 ms each).
MULTICAGE_AVX2_TARGET
bool pullRowsAvx2(const PullMesh& m, int y0, int y1, Mat& mapx, Mat& mapy) {
    CV_Assert(y0 % kPullRun == 0);
    const int W = mapx.cols, H = mapx.rows;
    const int cellsX = m.cols - 1, cellsY = m.rows - 1;
    const Pull8 pull{m,
                     reinterpret_cast<const double*>(m.nodes),
                     frameLines(m),
                     _mm256_set1_epi32(m.cols),
                     _mm256_set1_epi32(cellsX - 1),
                     _mm256_set1_epi32(cellsY - 1)};
    const float sx = W > 1 ? float(m.cols - 3) / float(W - 1) : 0.f;
    const float sy = H > 1 ? float(m.rows - 3) / float(H - 1) : 0.f;
    // As the AVX-512 kernel's, padded: a row's last vector reads and writes 8 estimates.
    thread_local std::vector<float> estimates;
    const size_t pad = 8;
    estimates.resize(4 * (size_t(W) + pad));
    float* e1x = estimates.data();
    float* e1y = e1x + W + pad;
    float* e2x = e1y + W + pad;
    float* e2y = e2x + W + pad;

    const __m256 iota = _mm256_setr_ps(0, 1, 2, 3, 4, 5, 6, 7);
    const __m256i iotaI = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.f);
    const __m256i oneI = _mm256_set1_epi32(1), zeroI = _mm256_setzero_si256();
    const __m256 big = _mm256_set1_ps(float(std::max(cellsX, cellsY) + 1));
    for (int y = y0; y < y1; ++y) {
        float* mx = mapx.ptr<float>(y);
        float* my = mapy.ptr<float>(y);
        const int seen = y % kPullRun;
        const __m256 py = _mm256_set1_ps(float(y) * m.spacing.y);
        for (int xv = 0; xv < W; xv += 8) {
            Walk8 k;
            {
                k.lanesI = _mm256_cmpgt_epi32(_mm256_set1_epi32(std::min(W - xv, 8)), iotaI);
                const __m256 ix = _mm256_add_ps(_mm256_set1_ps(float(xv)), iota);
                k.px = _mm256_mul_ps(ix, _mm256_set1_ps(m.spacing.x));
                __m256 gx, gy;
                if (seen >= 2) {
                    const __m256 ax = _mm256_loadu_ps(e1x + xv), ay = _mm256_loadu_ps(e1y + xv);
                    gx = _mm256_sub_ps(_mm256_add_ps(ax, ax), _mm256_loadu_ps(e2x + xv));
                    gy = _mm256_sub_ps(_mm256_add_ps(ay, ay), _mm256_loadu_ps(e2y + xv));
                } else if (seen == 1) {
                    gx = _mm256_loadu_ps(e1x + xv);
                    gy = _mm256_add_ps(_mm256_loadu_ps(e1y + xv), _mm256_set1_ps(sy));
                } else {
                    gx = _mm256_add_ps(one, _mm256_mul_ps(ix, _mm256_set1_ps(sx)));
                    gy = _mm256_set1_ps(1.f + float(y) * sy);
                }
                gx = _mm256_min_ps(_mm256_max_ps(gx, _mm256_set1_ps(-1.f)), big);  // NaN: -1
                gy = _mm256_min_ps(_mm256_max_ps(gy, _mm256_set1_ps(-1.f)), big);
                const __m256 fx = _mm256_floor_ps(gx), fy = _mm256_floor_ps(gy);
                k.gcx = _mm256_cvttps_epi32(fx), k.gcy = _mm256_cvttps_epi32(fy);
                k.gu = _mm256_sub_ps(gx, fx), k.gv = _mm256_sub_ps(gy, fy);
                k.active = asMask(k.lanesI), k.covered = zero;
                k.cellX = k.cellY = zeroI;
                k.fu = k.fv = zero;
            }
            for (int step = 0; !none(k.active); ++step)
                if (step == kMaxSteps || !pull.step(k, py, step)) return false;
            {
                const __m256 X0 =
                    restOf8(_mm256_sub_epi32(k.cellX, oneI), m.gridSize.width, m.step, m.hi.x);
                const __m256 X1 = restOf8(k.cellX, m.gridSize.width, m.step, m.hi.x);
                const __m256 Y0 =
                    restOf8(_mm256_sub_epi32(k.cellY, oneI), m.gridSize.height, m.step, m.hi.y);
                const __m256 Y1 = restOf8(k.cellY, m.gridSize.height, m.step, m.hi.y);
                const __m256 rx = _mm256_add_ps(X0, _mm256_mul_ps(k.fu, _mm256_sub_ps(X1, X0)));
                const __m256 ry = _mm256_add_ps(Y0, _mm256_mul_ps(k.fv, _mm256_sub_ps(Y1, Y0)));
                const __m256 noneV = _mm256_set1_ps(kUncovered);
                const __m256 outX =
                    _mm256_blendv_ps(noneV,
                                     _mm256_min_ps(_mm256_set1_ps(m.hi.x),
                                                   _mm256_max_ps(_mm256_set1_ps(m.lo.x), rx)),
                                     k.covered);
                const __m256 outY =
                    _mm256_blendv_ps(noneV,
                                     _mm256_min_ps(_mm256_set1_ps(m.hi.y),
                                                   _mm256_max_ps(_mm256_set1_ps(m.lo.y), ry)),
                                     k.covered);
                // (masked stores only for a row's last pixels: on AMD they are slow)
                const bool whole = xv + 8 <= W;
                if (whole) {
                    _mm256_storeu_ps(mx + xv, outX), _mm256_storeu_ps(my + xv, outY);
                } else {
                    _mm256_maskstore_ps(mx + xv, k.lanesI, outX);
                    _mm256_maskstore_ps(my + xv, k.lanesI, outY);
                }
                // Where each pixel ended, for the guesses of the next rows (uncovered: the last
                // guess).
                const __m256 ex =
                    _mm256_blendv_ps(_mm256_add_ps(_mm256_cvtepi32_ps(k.gcx), k.gu),
                                     _mm256_add_ps(_mm256_cvtepi32_ps(k.cellX), k.fu), k.covered);
                const __m256 ey =
                    _mm256_blendv_ps(_mm256_add_ps(_mm256_cvtepi32_ps(k.gcy), k.gv),
                                     _mm256_add_ps(_mm256_cvtepi32_ps(k.cellY), k.fv), k.covered);
                _mm256_storeu_ps(e2x + xv, ex), _mm256_storeu_ps(e2y + xv, ey);  // (padded)
            }
        }
        std::swap(e1x, e2x), std::swap(e1y, e2y);
    }
    return true;
}

// Whether cross(e1, e2) is clearly positive (kSliver), per lane: positive() of the AVX-512 kernel,
// the same float operations (all ones where it is).
MULTICAGE_AVX2_TARGET inline __m256 positive8(__m256 e1x, __m256 e1y, __m256 e2x, __m256 e2y) {
    const __m256 l = _mm256_mul_ps(e1x, e2y), r = _mm256_mul_ps(e1y, e2x);
    const __m256 sign = _mm256_set1_ps(-0.f);
    const __m256 magnitude = _mm256_add_ps(_mm256_andnot_ps(sign, l), _mm256_andnot_ps(sign, r));
    return _mm256_cmp_ps(_mm256_sub_ps(l, r), _mm256_mul_ps(_mm256_set1_ps(kSliver), magnitude),
                         _CMP_GT_OQ);
}

// notPositiveInRow one cell at a time, with the same float operations: the fold check where
// there is no AVX-512.
inline bool clearlyPositive(float e1x, float e1y, float e2x, float e2y) {
    const float l = e1x * e2y, r = e1y * e2x;
    return l - r > kSliver * (std::abs(l) + std::abs(r));
}

// Whether both triangles of cells [k0, k1) of node rows p0, p1 are clearly positive.
inline bool cellsPositive(const Point2f* p0, const Point2f* p1, int k0, int k1) {
    bool good = true;
    for (int k = k0; k < k1; ++k) {
        const Point2f a = p0[k], b = p0[k + 1], c = p1[k], d = p1[k + 1];
        good &= clearlyPositive(b.x - a.x, b.y - a.y, c.x - a.x, c.y - a.y) &
                clearlyPositive(d.x - b.x, d.y - b.y, c.x - b.x, c.y - b.y);
    }
    return good;
}

MULTICAGE_TARGET_CLONES_PULL
bool positiveRowsPortable(const PullMesh& m, int ey0, int ey1) {
    const Point2f* P = m.nodes;
    const size_t C = m.cols;
    for (int ey = std::max(ey0, 0); ey < std::min(ey1, m.rows - 1); ++ey)
        if (!cellsPositive(P + size_t(ey) * C, P + size_t(ey + 1) * C, 0, m.cols - 1)) return false;
    return true;
}

// The fold check of rows [ey0, ey1) 8 cells at a time where the CPU has AVX2 but not AVX-512:
// notPositiveInRow's float operations, so the same answer as positiveRowsPortable (one cell at a
// time it was 5-6% of a 1024x768 deform's CPU time at grid step 1).
MULTICAGE_AVX2_TARGET bool positiveRowsAvx2(const PullMesh& m, int ey0, int ey1) {
    const Point2f* P = m.nodes;
    const size_t C = m.cols;
    const int cells = m.cols - 1;
    for (int ey = std::max(ey0, 0); ey < std::min(ey1, m.rows - 1); ++ey) {
        const Point2f* p0 = P + size_t(ey) * C;
        const Point2f* p1 = p0 + C;
        __m256 good = _mm256_castsi256_ps(_mm256_set1_epi32(-1));
        int k = 0;
        // (cells k..k+7 read nodes k..k+8 of both rows)
        for (; k + 8 <= cells; k += 8) {
            __m256 ax, ay, bx, by, cx, cy, dx, dy;
            const float *f0 = &p0[k].x, *f1 = &p1[k].x;
            deinterleave8(_mm256_loadu_ps(f0), _mm256_loadu_ps(f0 + 8), ax, ay);
            deinterleave8(_mm256_loadu_ps(f0 + 2), _mm256_loadu_ps(f0 + 10), bx, by);
            deinterleave8(_mm256_loadu_ps(f1), _mm256_loadu_ps(f1 + 8), cx, cy);
            deinterleave8(_mm256_loadu_ps(f1 + 2), _mm256_loadu_ps(f1 + 10), dx, dy);
            good = _mm256_and_ps(
                good, _mm256_and_ps(positive8(_mm256_sub_ps(bx, ax), _mm256_sub_ps(by, ay),
                                              _mm256_sub_ps(cx, ax), _mm256_sub_ps(cy, ay)),
                                    positive8(_mm256_sub_ps(dx, bx), _mm256_sub_ps(dy, by),
                                              _mm256_sub_ps(cx, bx), _mm256_sub_ps(cy, by))));
        }
        if (_mm256_movemask_ps(good) != 0xff || !cellsPositive(p0, p1, k, cells)) return false;
    }
    return true;
}

enum class PullIsa { none, avx2, avx512 };
std::atomic<bool> avx2Preferred{false};

PullIsa pullIsa() {
    static const PullIsa isa =
        cpuLevelCap() >= 4 && __builtin_cpu_supports("avx512f") &&
                __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512dq") &&
                __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("bmi2")
            ? PullIsa::avx512
        : cpuLevelCap() >= 3 && __builtin_cpu_supports("avx2") ? PullIsa::avx2
                                                               : PullIsa::none;
    return isa == PullIsa::avx512 && avx2Preferred ? PullIsa::avx2 : isa;
}
}  // namespace

bool positiveRows(const PullMesh& m, int ey0, int ey1) {
    switch (pullIsa()) {
        case PullIsa::avx512:
            return positiveRowsAvx512(m, ey0, ey1);
        case PullIsa::avx2:
            return positiveRowsAvx2(m, ey0, ey1);
        default:
            return positiveRowsPortable(m, ey0, ey1);
    }
}

bool pullRows(const PullMesh& m, int y0, int y1, Mat& mapx, Mat& mapy) {
    switch (pullIsa()) {
        case PullIsa::avx512:
            return pullRowsAvx512(m, y0, y1, mapx, mapy);
        case PullIsa::avx2:
            return pullRowsAvx2(m, y0, y1, mapx, mapy);
        default:
            return false;
    }
}

bool havePullKernel() {
    return pullIsa() != PullIsa::none;
}

const char* pullKernelName() {
    static const char* const names[] = {"none", "AVX2", "AVX-512"};
    return names[int(pullIsa())];
}

void preferAvx2Pull(bool avx2) {
    avx2Preferred = avx2;
}
#else
bool frameConvex(const PullMesh&) {
    return false;
}
bool positiveRows(const PullMesh&, int, int) {
    return false;
}
bool pullable(const PullMesh&) {
    return false;
}
bool pullRows(const PullMesh&, int, int, Mat&, Mat&) {
    return false;
}
bool havePullKernel() {
    return false;
}
const char* pullKernelName() {
    return "none";
}
void preferAvx2Pull(bool) {}
#endif

}  // namespace raster
}  // namespace multicage
}  // namespace cv

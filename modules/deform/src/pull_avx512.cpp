// The pull's AVX-512 kernel: 16 pixels in lanes, four vectors walked together.
//
// Why: at grid step 1 a cell covers about one pixel, so the raster kernel spends its time on
// what a triangle costs whatever it covers (set-up, bounds, spans). Where the mesh folds nowhere
// a pixel lies in exactly one triangle, so it can be found from the pixel instead: a guess
// extrapolated from the two rows above, then Newton's method on the piecewise linear map, each
// step one cell's 4 nodes per pixel. The 16 pixels' cells mostly lie in one or two rows of cells
// within 31 columns: their nodes come from runs of 32 nodes loaded whole and looked up in
// registers, gathers (slow) only otherwise; the rows three ahead are prefetched. One vector's
// walk is a chain of dependent steps about as long as the core's reorder window, so four are
// walked together, stage by stage, and their chains overlap. The measurements behind these
// choices: docs/cpu-kernels.md.

// First, before any other header (clang-format would sort it among them): the rasteriser's
// floating-point options.
// clang-format off
#include "raster_options.hpp"
// clang-format on

#include <algorithm>
#include <opencv2/multicage/internal/backend_contract.hpp>
#include <opencv2/multicage/internal/cpu_dispatch.hpp>

#include "pull_kernels.hpp"

#if defined(MULTICAGE_TARGET_X86_64_V4)
#if !defined(__clang__)
// GCC 12's AVX-512 headers start vectors from _mm512_undefined_*(), which -W(maybe-)uninitialized
// reports at every use.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif
#include <immintrin.h>
#define MULTICAGE_PULL_TARGET MULTICAGE_TARGET_X86_64_V4
#endif

namespace cv {
namespace multicage {
namespace raster {

#if defined(MULTICAGE_PULL_TARGET)
namespace {

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
constexpr int kTogether = 4;  // vectors of 16 pixels walked together

// kTogether vectors of 16 pixels of a row: their guesses (cell and coordinates in it), where
// they settled, and which are still walking. A vector whose walk has ended keeps its state.
struct Walks {
    __mmask16 lanes[kTogether], active[kTogether], covered[kTogether];
    __m512 px[kTogether], gu[kTogether], gv[kTogether], fu[kTogether], fv[kTogether];
    __m512i gcx[kTogether], gcy[kTogether], cellX[kTogether], cellY[kTogether];
    bool anyActive() const {
        unsigned any = 0;
        for (int v = 0; v < kTogether; ++v) any |= active[v];
        return any != 0;
    }
};

// The four nodes a, b (upper row), c, d (lower row) of each pixel's cell, as x and y planes.
struct CellNodes {
    __m512 ax, ay, bx, by, cx, cy, dx, dy;
};

// What a pull of rows needs besides the walks: the mesh, its frame, the constants of its cells.
struct Pull16 {
    const PullMesh& m;
    const double* P;  // the nodes as doubles (x, y pairs), for gathers
    FrameLines frame;
    FirstGuess first;
    int W;
    __m512i cols, lastXi, lastYi, edgeX, edgeY;
    __m512 big;  // guesses are clamped to [-1, big] (NaN: -1)

    MULTICAGE_PULL_TARGET Pull16(const PullMesh& mesh, Size maps)
        : m(mesh),
          P(reinterpret_cast<const double*>(mesh.nodes)),
          frame(frameLines(mesh)),
          first(mesh, maps),
          W(maps.width),
          cols(_mm512_set1_epi32(mesh.cols)),
          lastXi(_mm512_set1_epi32(mesh.cols - 2)),
          lastYi(_mm512_set1_epi32(mesh.rows - 2)),
          edgeX(_mm512_set1_epi32(mesh.cols - 3)),
          edgeY(_mm512_set1_epi32(mesh.rows - 3)),
          big(_mm512_set1_ps(float(std::max(mesh.cols, mesh.rows)))) {}

    // Vector v of pixels xv..xv+15 of row y starts its walk: its guess, from the two rows above
    // (`seen` of this run already pulled), one row above, or the frame at rest.
    MULTICAGE_PULL_TARGET MULTICAGE_ALWAYS_INLINE void start(Walks& w, int v, int xv, int y,
                                                             int seen, const Estimates& e) const {
        // (at most 16: BZHI reads only the low 8 bits of its index)
        w.lanes[v] =
            xv < W ? static_cast<__mmask16>(_bzhi_u32(0xffff, unsigned(std::min(W - xv, 16)))) : 0;
        const __m512 iota = _mm512_setr_ps(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
        const __m512 ix = _mm512_add_ps(_mm512_set1_ps(float(xv)), iota);
        w.px[v] = _mm512_mul_ps(ix, _mm512_set1_ps(m.spacing.x));
        __m512 gx, gy;
        if (seen >= 2) {  // extrapolated from the two rows above
            const __m512 ax = _mm512_loadu_ps(e.e1x + xv), ay = _mm512_loadu_ps(e.e1y + xv);
            gx = _mm512_sub_ps(_mm512_add_ps(ax, ax), _mm512_loadu_ps(e.e2x + xv));
            gy = _mm512_sub_ps(_mm512_add_ps(ay, ay), _mm512_loadu_ps(e.e2y + xv));
        } else if (seen == 1) {
            gx = _mm512_loadu_ps(e.e1x + xv);
            gy = _mm512_add_ps(_mm512_loadu_ps(e.e1y + xv), _mm512_set1_ps(first.sy));
        } else {
            gx = _mm512_add_ps(_mm512_set1_ps(1.f), _mm512_mul_ps(ix, _mm512_set1_ps(first.sx)));
            gy = _mm512_set1_ps(1.f + float(y) * first.sy);
        }
        // The guess as a cell and coordinates in it: a walk's step is then decided by its own
        // cell's coordinates (a pixel 1e-6 left of a cell, whose absolute coordinate 634 - 1e-6
        // rounds to 634 in float, still goes left).
        gx = _mm512_min_ps(_mm512_max_ps(gx, _mm512_set1_ps(-1.f)), big);  // NaN: -1
        gy = _mm512_min_ps(_mm512_max_ps(gy, _mm512_set1_ps(-1.f)), big);
        const __m512 fx = _mm512_roundscale_ps(gx, _MM_FROUND_TO_NEG_INF);
        const __m512 fy = _mm512_roundscale_ps(gy, _MM_FROUND_TO_NEG_INF);
        w.gcx[v] = _mm512_cvttps_epi32(fx), w.gcy[v] = _mm512_cvttps_epi32(fy);
        w.gu[v] = _mm512_sub_ps(gx, fx), w.gv[v] = _mm512_sub_ps(gy, fy);
        w.active[v] = w.lanes[v], w.covered[v] = 0;
        w.cellX[v] = w.cellY[v] = _mm512_setzero_si512();
        w.fu[v] = w.fv[v] = _mm512_setzero_ps();
    }

    // The nodes of the cells (cx, cy) of vector v's walking pixels. They mostly lie in one row
    // of cells, within 31 cells: their nodes are then read from two runs of 32 nodes (loads and
    // in-register lookups), else gathered one by one.
    MULTICAGE_PULL_TARGET MULTICAGE_ALWAYS_INLINE void nodesOf(__mmask16 active, __m512i cx,
                                                               __m512i cy, int step,
                                                               CellNodes& n) const {
        const __m512i oneI = _mm512_set1_epi32(1);
        const int firstX = _mm512_mask_reduce_min_epi32(active, cx);
        const int row = _mm512_mask_reduce_min_epi32(active, cy);
        const __m512i local = _mm512_sub_epi32(cx, _mm512_set1_epi32(firstX));
        const __mmask16 lower = _mm512_cmpgt_epi32_mask(cy, _mm512_set1_epi32(row));
        if (active & ~(_mm512_cmple_epi32_mask(cy, _mm512_set1_epi32(row + 1)) &
                       _mm512_cmple_epi32_mask(local, _mm512_set1_epi32(30)))) {
            const __m512i ia = _mm512_add_epi32(_mm512_mullo_epi32(cy, cols), cx);
            const __m512i ic = _mm512_add_epi32(ia, cols);
            gatherNodes(P, ia, active, n.ax, n.ay);
            gatherNodes(P, _mm512_add_epi32(ia, oneI), active, n.bx, n.by);
            gatherNodes(P, ic, active, n.cx, n.cy);
            gatherNodes(P, _mm512_add_epi32(ic, oneI), active, n.dx, n.dy);
            return;
        }
        // Cells in rows `row` and `row + 1`: node runs of rows row..row+2, the lanes of the lower
        // cell row taking theirs from the runs one row down.
        const __m512i local1 = _mm512_add_epi32(local, oneI);
        const int C = m.cols;
        if (step == 0 && row + 3 < m.rows) {  // the next rows' nodes, on their way
            const char* ahead =
                reinterpret_cast<const char*>(m.nodes + size_t(row + 3) * C + firstX);
            for (int line = 0; line < 4; ++line) _mm_prefetch(ahead + 64 * line, _MM_HINT_T0);
        }
        NodeRun r0, r1;
        r0.load(m.nodes + size_t(row) * C + firstX, C - firstX);
        r1.load(m.nodes + size_t(row + 1) * C + firstX, C - firstX);
        r0.lookup(local, n.ax, n.ay), r0.lookup(local1, n.bx, n.by);
        r1.lookup(local, n.cx, n.cy), r1.lookup(local1, n.dx, n.dy);
        if (active & lower) {
            NodeRun r2;
            r2.load(m.nodes + size_t(row + 2) * C + firstX, C - firstX);
            r1.lookupInto(local, lower, n.ax, n.ay), r1.lookupInto(local1, lower, n.bx, n.by);
            r2.lookupInto(local, lower, n.cx, n.cy), r2.lookupInto(local1, lower, n.dx, n.dy);
        }
    }

    // Vector v's pixels in cell (cx, cy), with barycentrics (u, w) in triangle 0 (a, b, c) and
    // (s, t) in triangle 1 (d, c, b): the pixels the cell holds settle; the others take Newton's
    // step. Returns the pixels whose step would leave the mesh from a border cell.
    MULTICAGE_PULL_TARGET MULTICAGE_ALWAYS_INLINE __mmask16 settle(Walks& k, int v, __m512i cx,
                                                                   __m512i cy, __m512 u, __m512 w,
                                                                   __m512 s, __m512 t,
                                                                   int step) const {
        const __m512 zero = _mm512_setzero_ps(), one = _mm512_set1_ps(1.f);
        const __m512i zeroI = _mm512_setzero_si512(), oneI = _mm512_set1_epi32(1);
        const __mmask16 in0 = inTriangle(u, w), in1 = inTriangle(s, t);
        // Cell coordinates of p by triangle 1 where it holds p (later in drawing order, so it
        // wins a shared edge as in the raster) or, neither holding it, where p lies on its side
        // of the diagonal; else by triangle 0.
        const __mmask16 half0 = _mm512_cmp_ps_mask(_mm512_add_ps(u, w), one, _CMP_LE_OQ);
        const __mmask16 by1 = in1 | (static_cast<__mmask16>(~in0) & ~half0);
        const __m512 U = _mm512_mask_sub_ps(u, by1, one, s);
        const __m512 V = _mm512_mask_sub_ps(w, by1, one, t);
        const __mmask16 found = k.active[v] & (in0 | in1);
        k.cellX[v] = _mm512_mask_mov_epi32(k.cellX[v], found, cx);
        k.cellY[v] = _mm512_mask_mov_epi32(k.cellY[v], found, cy);
        k.fu[v] = _mm512_mask_mov_ps(k.fu[v], found, U);
        k.fv[v] = _mm512_mask_mov_ps(k.fv[v], found, V);
        k.covered[v] |= found;
        k.active[v] &= static_cast<__mmask16>(~found);
        // Newton's step: the cell coordinates of p by this cell's affine map, at most a few
        // cells away (then one) so that a poor guess cannot oscillate far.
        const float reach = step < 6 ? 4.f : 1.f;
        k.gcx[v] = cx, k.gcy[v] = cy;
        k.gu[v] =
            _mm512_min_ps(_mm512_max_ps(U, _mm512_set1_ps(-reach)), _mm512_set1_ps(1.f + reach));
        k.gv[v] =
            _mm512_min_ps(_mm512_max_ps(V, _mm512_set1_ps(-reach)), _mm512_set1_ps(1.f + reach));
        // (cx - 1 as unsigned: at least cellsX - 2 only for the first and last column of cells,
        // the same for rows)
        const __mmask16 edge =
            k.active[v] & (_mm512_cmpge_epu32_mask(_mm512_sub_epi32(cx, oneI), edgeX) |
                           _mm512_cmpge_epu32_mask(_mm512_sub_epi32(cy, oneI), edgeY));
        if (!edge) return 0;
        return k.active[v] & ((_mm512_cmpeq_epi32_mask(cx, zeroI) &
                               _mm512_cmp_ps_mask(k.gu[v], zero, _CMP_LT_OQ)) |
                              (_mm512_cmpeq_epi32_mask(cx, lastXi) &
                               _mm512_cmp_ps_mask(k.gu[v], one, _CMP_GE_OQ)) |
                              (_mm512_cmpeq_epi32_mask(cy, zeroI) &
                               _mm512_cmp_ps_mask(k.gv[v], zero, _CMP_LT_OQ)) |
                              (_mm512_cmpeq_epi32_mask(cy, lastYi) &
                               _mm512_cmp_ps_mask(k.gv[v], one, _CMP_GE_OQ)));
    }

    // Pixels of vector v leaving the mesh: outside the frame (uncovered, done), clearly inside
    // (they go on along the border), or on it: false (the raster decides).
    MULTICAGE_PULL_TARGET MULTICAGE_ALWAYS_INLINE bool leave(Walks& k, int v, __mmask16 leaving,
                                                             __m512 py) const {
        __mmask16 outside = 0, inside = 0xffff;
        for (int i = 0; i < 4; ++i) {
            const __m512 d =
                _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(_mm512_set1_ps(frame.nx[i]), k.px[v]),
                                            _mm512_mul_ps(_mm512_set1_ps(frame.ny[i]), py)),
                              _mm512_set1_ps(frame.c[i]));
            outside |= _mm512_cmp_ps_mask(d, _mm512_set1_ps(-kFrameMargin), _CMP_LT_OQ);
            inside &= _mm512_cmp_ps_mask(d, _mm512_set1_ps(kFrameMargin), _CMP_GT_OQ);
        }
        if (leaving & ~outside & ~inside) return false;  // on the frame
        k.active[v] &= static_cast<__mmask16>(~(leaving & outside));
        return true;
    }

    // One step of every walking vector for row py (step: how many they made before), each stage
    // for all of them before the next, so that their chains of dependent steps (cell, node
    // loads, barycentrics with a division) overlap. False when a pixel is on the frame.
    MULTICAGE_PULL_TARGET MULTICAGE_ALWAYS_INLINE bool step(Walks& k, __m512 py, int step) const {
        __m512i cx[kTogether], cy[kTogether];
        CellNodes n[kTogether];
        for (int v = 0; v < kTogether; ++v) {  // the cell of the guess, clamped to the mesh
            cx[v] = cellOf(k.gcx[v], k.gu[v], lastXi);
            cy[v] = cellOf(k.gcy[v], k.gv[v], lastYi);
        }
        for (int v = 0; v < kTogether; ++v)
            if (k.active[v]) nodesOf(k.active[v], cx[v], cy[v], step, n[v]);
        // Triangle 0 (a, b, c): p = a + u (b - a) + w (c - a); triangle 1 (b, d, c):
        // p = d + s (c - d) + t (b - d).
        __m512 u[kTogether], w[kTogether], s[kTogether], t[kTogether];
        for (int v = 0; v < kTogether; ++v) {
            if (!k.active[v]) continue;
            barycentric(n[v].ax, n[v].ay, n[v].bx, n[v].by, n[v].cx, n[v].cy, k.px[v], py, u[v],
                        w[v]);
            barycentric(n[v].dx, n[v].dy, n[v].cx, n[v].cy, n[v].bx, n[v].by, k.px[v], py, s[v],
                        t[v]);
        }
        __mmask16 leaving[kTogether];
        for (int v = 0; v < kTogether; ++v)
            leaving[v] = k.active[v] ? settle(k, v, cx[v], cy[v], u[v], w[v], s[v], t[v], step) : 0;
        for (int v = 0; v < kTogether; ++v)
            if (leaving[v] && !leave(k, v, leaving[v], py)) return false;
        return true;
    }

    // Vector v's pixels xv..xv+15 into the maps (the rest point X0 + U (X1 - X0), Y0 + V (Y1 -
    // Y0) of the cell each lies in, or kUncovered), and where each ended into the estimates
    // (uncovered: the last guess).
    MULTICAGE_PULL_TARGET MULTICAGE_ALWAYS_INLINE void finish(const Walks& k, int v, int xv,
                                                              float* mx, float* my,
                                                              const Estimates& e) const {
        const __m512i oneI = _mm512_set1_epi32(1);
        const __m512 X0 =
            restOf(_mm512_sub_epi32(k.cellX[v], oneI), m.gridSize.width, m.step, m.hi.x);
        const __m512 X1 = restOf(k.cellX[v], m.gridSize.width, m.step, m.hi.x);
        const __m512 Y0 =
            restOf(_mm512_sub_epi32(k.cellY[v], oneI), m.gridSize.height, m.step, m.hi.y);
        const __m512 Y1 = restOf(k.cellY[v], m.gridSize.height, m.step, m.hi.y);
        const __m512 rx = _mm512_add_ps(X0, _mm512_mul_ps(k.fu[v], _mm512_sub_ps(X1, X0)));
        const __m512 ry = _mm512_add_ps(Y0, _mm512_mul_ps(k.fv[v], _mm512_sub_ps(Y1, Y0)));
        const __m512 none = _mm512_set1_ps(kUncovered);
        const __m512 outX = _mm512_mask_mov_ps(
            none, k.covered[v],
            _mm512_min_ps(_mm512_set1_ps(m.hi.x), _mm512_max_ps(_mm512_set1_ps(m.lo.x), rx)));
        const __m512 outY = _mm512_mask_mov_ps(
            none, k.covered[v],
            _mm512_min_ps(_mm512_set1_ps(m.hi.y), _mm512_max_ps(_mm512_set1_ps(m.lo.y), ry)));
        _mm512_mask_storeu_ps(mx + xv, k.lanes[v], outX);
        _mm512_mask_storeu_ps(my + xv, k.lanes[v], outY);
        const __m512 ex = _mm512_mask_add_ps(_mm512_add_ps(_mm512_cvtepi32_ps(k.gcx[v]), k.gu[v]),
                                             k.covered[v], _mm512_cvtepi32_ps(k.cellX[v]), k.fu[v]);
        const __m512 ey = _mm512_mask_add_ps(_mm512_add_ps(_mm512_cvtepi32_ps(k.gcy[v]), k.gv[v]),
                                             k.covered[v], _mm512_cvtepi32_ps(k.cellY[v]), k.fv[v]);
        _mm512_mask_storeu_ps(e.e2x + xv, k.lanes[v], ex);
        _mm512_mask_storeu_ps(e.e2y + xv, k.lanes[v], ey);
    }
};

}  // namespace

bool haveAvx512Pull() {
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

MULTICAGE_PULL_TARGET
bool pullRowsAvx512(const PullMesh& m, int y0, int y1, Mat& mapx, Mat& mapy) {
    CV_Assert(y0 % kPullRun == 0);
    const Pull16 pull(m, mapx.size());
    const int W = mapx.cols;
    // (padded: the last vectors of a group may start past the row's end, and each reads 16)
    Estimates e(W, 16 * kTogether);
    for (int y = y0; y < y1; ++y) {
        float* mx = mapx.ptr<float>(y);
        float* my = mapy.ptr<float>(y);
        const int seen = y % kPullRun;  // rows of this run already pulled
        const __m512 py = _mm512_set1_ps(float(y) * m.spacing.y);
        for (int x0 = 0; x0 < W; x0 += 16 * kTogether) {
            Walks k;
            for (int v = 0; v < kTogether; ++v) pull.start(k, v, x0 + 16 * v, y, seen, e);
            for (int step = 0; k.anyActive(); ++step)
                if (step == kMaxSteps || !pull.step(k, py, step)) return false;
            for (int v = 0; v < kTogether; ++v)
                if (k.lanes[v]) pull.finish(k, v, x0 + 16 * v, mx, my, e);
        }
        e.nextRow();
    }
    return true;
}
#else
bool haveAvx512Pull() {
    return false;
}
bool positiveRowsAvx512(const PullMesh&, int, int) {
    return false;
}
bool pullRowsAvx512(const PullMesh&, int, int, Mat&, Mat&) {
    return false;
}
#endif

}  // namespace raster
}  // namespace multicage
}  // namespace cv

// The pull's AVX2 kernel, for CPUs without AVX-512: the walk of pull_avx512.cpp, 8 pixels in
// lanes, one vector at a time, nodes looked up in runs of 16 or gathered. Each lane's arithmetic
// is the AVX-512 kernel's, operation for operation, so a pixel walks the same steps to the same
// triangle; only the guesses of pixels outside the frame (whose last guess goes on with their
// vector's walk) may differ, and with them, rarely, which of two triangles sharing an edge a
// pixel below them settles in (values within a float rounding of each other).

// First, before any other header (clang-format would sort it among them): the rasteriser's
// floating-point options.
// clang-format off
#include "raster_options.hpp"
// clang-format on

#include <algorithm>
#include <climits>
#include <opencv2/multicage/internal/backend_contract.hpp>
#include <opencv2/multicage/internal/cpu_dispatch.hpp>

#include "pull_kernels.hpp"

#if defined(MULTICAGE_TARGET_X86_64_V3)
#include <immintrin.h>
#define MULTICAGE_AVX2_TARGET MULTICAGE_TARGET_X86_64_V3
#endif

namespace cv {
namespace multicage {
namespace raster {

#if defined(MULTICAGE_AVX2_TARGET)
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
    const double* P;  // the nodes as doubles (x, y pairs), for gathers
    FrameLines frame;
    FirstGuess first;
    int W;
    __m256i cols, lastXi, lastYi;

    MULTICAGE_AVX2_TARGET Pull8(const PullMesh& mesh, Size maps)
        : m(mesh),
          P(reinterpret_cast<const double*>(mesh.nodes)),
          frame(frameLines(mesh)),
          first(mesh, maps),
          W(maps.width),
          cols(_mm256_set1_epi32(mesh.cols)),
          lastXi(_mm256_set1_epi32(mesh.cols - 2)),
          lastYi(_mm256_set1_epi32(mesh.rows - 2)) {}

    // Pixels xv..xv+7 of row y start their walk: their guess, from the two rows above (`seen` of
    // this run already pulled), one row above, or the frame at rest (Pull16::start).
    MULTICAGE_AVX2_TARGET MULTICAGE_ALWAYS_INLINE void start(Walk8& k, int xv, int y, int seen,
                                                             const Estimates& e) const {
        const __m256 one = _mm256_set1_ps(1.f);
        const __m256i iotaI = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
        k.lanesI = _mm256_cmpgt_epi32(_mm256_set1_epi32(std::min(W - xv, 8)), iotaI);
        const __m256 ix = _mm256_add_ps(_mm256_set1_ps(float(xv)), _mm256_cvtepi32_ps(iotaI));
        k.px = _mm256_mul_ps(ix, _mm256_set1_ps(m.spacing.x));
        __m256 gx, gy;
        if (seen >= 2) {
            const __m256 ax = _mm256_loadu_ps(e.e1x + xv), ay = _mm256_loadu_ps(e.e1y + xv);
            gx = _mm256_sub_ps(_mm256_add_ps(ax, ax), _mm256_loadu_ps(e.e2x + xv));
            gy = _mm256_sub_ps(_mm256_add_ps(ay, ay), _mm256_loadu_ps(e.e2y + xv));
        } else if (seen == 1) {
            gx = _mm256_loadu_ps(e.e1x + xv);
            gy = _mm256_add_ps(_mm256_loadu_ps(e.e1y + xv), _mm256_set1_ps(first.sy));
        } else {
            gx = _mm256_add_ps(one, _mm256_mul_ps(ix, _mm256_set1_ps(first.sx)));
            gy = _mm256_set1_ps(1.f + float(y) * first.sy);
        }
        const __m256 big = _mm256_set1_ps(float(std::max(m.cols, m.rows)));
        gx = _mm256_min_ps(_mm256_max_ps(gx, _mm256_set1_ps(-1.f)), big);  // NaN: -1
        gy = _mm256_min_ps(_mm256_max_ps(gy, _mm256_set1_ps(-1.f)), big);
        const __m256 fx = _mm256_floor_ps(gx), fy = _mm256_floor_ps(gy);
        k.gcx = _mm256_cvttps_epi32(fx), k.gcy = _mm256_cvttps_epi32(fy);
        k.gu = _mm256_sub_ps(gx, fx), k.gv = _mm256_sub_ps(gy, fy);
        k.active = asMask(k.lanesI), k.covered = _mm256_setzero_ps();
        k.cellX = k.cellY = _mm256_setzero_si256();
        k.fu = k.fv = _mm256_setzero_ps();
    }

    // One step of a walk for row y (step: how many it made before): the cell of each walking
    // pixel's guess, that cell's two triangles, then settled, left the frame, or the next guess.
    // False when a pixel is on the frame (the raster decides).
    MULTICAGE_AVX2_TARGET __attribute__((always_inline)) inline bool step(Walk8& k, __m256 py,
                                                                          int step) const {
        const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.f);
        const __m256i zeroI = _mm256_setzero_si256(), oneI = _mm256_set1_epi32(1);
        const __m256i cx = cellOf8(k.gcx, k.gu, lastXi), cy = cellOf8(k.gcy, k.gv, lastYi);
        __m256 ax, ay, bx, by, cxv, cyv, dx, dy;
        // The cells of 8 neighbouring pixels mostly lie in one row of cells within 15 columns:
        // their nodes are then read as runs of 16 and looked up in registers, else gathered
        // (gathering all is slower: docs/cpu-kernels.md).
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

    // Pixels xv..xv+7 into the maps and the estimates (Pull16::finish).
    MULTICAGE_AVX2_TARGET MULTICAGE_ALWAYS_INLINE void finish(const Walk8& k, int xv, float* mx,
                                                              float* my, const Estimates& e) const {
        const __m256i oneI = _mm256_set1_epi32(1);
        const __m256 X0 =
            restOf8(_mm256_sub_epi32(k.cellX, oneI), m.gridSize.width, m.step, m.hi.x);
        const __m256 X1 = restOf8(k.cellX, m.gridSize.width, m.step, m.hi.x);
        const __m256 Y0 =
            restOf8(_mm256_sub_epi32(k.cellY, oneI), m.gridSize.height, m.step, m.hi.y);
        const __m256 Y1 = restOf8(k.cellY, m.gridSize.height, m.step, m.hi.y);
        const __m256 rx = _mm256_add_ps(X0, _mm256_mul_ps(k.fu, _mm256_sub_ps(X1, X0)));
        const __m256 ry = _mm256_add_ps(Y0, _mm256_mul_ps(k.fv, _mm256_sub_ps(Y1, Y0)));
        const __m256 noneV = _mm256_set1_ps(kUncovered);
        const __m256 outX = _mm256_blendv_ps(
            noneV, _mm256_min_ps(_mm256_set1_ps(m.hi.x), _mm256_max_ps(_mm256_set1_ps(m.lo.x), rx)),
            k.covered);
        const __m256 outY = _mm256_blendv_ps(
            noneV, _mm256_min_ps(_mm256_set1_ps(m.hi.y), _mm256_max_ps(_mm256_set1_ps(m.lo.y), ry)),
            k.covered);
        // (masked stores only for a row's last pixels: on AMD they are slow)
        if (xv + 8 <= W) {
            _mm256_storeu_ps(mx + xv, outX), _mm256_storeu_ps(my + xv, outY);
        } else {
            _mm256_maskstore_ps(mx + xv, k.lanesI, outX);
            _mm256_maskstore_ps(my + xv, k.lanesI, outY);
        }
        // Where each pixel ended, for the guesses of the next rows (uncovered: the last guess).
        const __m256 ex =
            _mm256_blendv_ps(_mm256_add_ps(_mm256_cvtepi32_ps(k.gcx), k.gu),
                             _mm256_add_ps(_mm256_cvtepi32_ps(k.cellX), k.fu), k.covered);
        const __m256 ey =
            _mm256_blendv_ps(_mm256_add_ps(_mm256_cvtepi32_ps(k.gcy), k.gv),
                             _mm256_add_ps(_mm256_cvtepi32_ps(k.cellY), k.fv), k.covered);
        _mm256_storeu_ps(e.e2x + xv, ex), _mm256_storeu_ps(e.e2y + xv, ey);  // (padded)
    }
};

// One vector at a time: walking 2, 3 or 4 side by side, as the AVX-512 kernel does, made no

// Whether cross(e1, e2) is clearly positive (kSliver), per lane: positive() of the AVX-512 kernel,
// the same float operations (all ones where it is).
MULTICAGE_AVX2_TARGET inline __m256 positive8(__m256 e1x, __m256 e1y, __m256 e2x, __m256 e2y) {
    const __m256 l = _mm256_mul_ps(e1x, e2y), r = _mm256_mul_ps(e1y, e2x);
    const __m256 sign = _mm256_set1_ps(-0.f);
    const __m256 magnitude = _mm256_add_ps(_mm256_andnot_ps(sign, l), _mm256_andnot_ps(sign, r));
    return _mm256_cmp_ps(_mm256_sub_ps(l, r), _mm256_mul_ps(_mm256_set1_ps(kSliver), magnitude),
                         _CMP_GT_OQ);
}

}  // namespace

bool haveAvx2Pull() {
    return true;
}

// One vector at a time: walking 2, 3 or 4 side by side, as the AVX-512 kernel does, made no
// difference (docs/cpu-kernels.md).
MULTICAGE_AVX2_TARGET
bool pullRowsAvx2(const PullMesh& m, int y0, int y1, Mat& mapx, Mat& mapy) {
    CV_Assert(y0 % kPullRun == 0);
    const Pull8 pull(m, mapx.size());
    const int W = mapx.cols;
    Estimates e(W, 8);  // (padded: a row's last vector reads and writes 8)
    for (int y = y0; y < y1; ++y) {
        float* mx = mapx.ptr<float>(y);
        float* my = mapy.ptr<float>(y);
        const int seen = y % kPullRun;  // rows of this run already pulled
        const __m256 py = _mm256_set1_ps(float(y) * m.spacing.y);
        for (int xv = 0; xv < W; xv += 8) {
            Walk8 k;
            pull.start(k, xv, y, seen, e);
            for (int step = 0; !none(k.active); ++step)
                if (step == kMaxSteps || !pull.step(k, py, step)) return false;
            pull.finish(k, xv, mx, my, e);
        }
        e.nextRow();
    }
    return true;
}

// The fold check of rows [ey0, ey1) 8 cells at a time where the CPU has AVX2 but not AVX-512:
// notPositiveInRow's float operations, so the same answer as positiveRowsPortable.
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

#else
bool haveAvx2Pull() {
    return false;
}
bool positiveRowsAvx2(const PullMesh&, int, int) {
    return false;
}
bool pullRowsAvx2(const PullMesh&, int, int, Mat&, Mat&) {
    return false;
}
#endif

}  // namespace raster
}  // namespace multicage
}  // namespace cv

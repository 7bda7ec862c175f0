// The AVX2 triangle kernel, for CPUs without AVX-512: triangles in lanes, pixels owned in bytes.
// The triangles of 4 cells are set up at once (4 doubles per vector), and each output row they
// touch is drawn at once: the triangle each pixel gets, then the pixels 8 at a time.

// First, before any other header (clang-format would sort it among them): the rasteriser's
// floating-point options.
// clang-format off
#include "raster_options.hpp"
// clang-format on

#include <opencv2/multicage/internal/cpu_dispatch.hpp>

#include "raster_kernels.hpp"

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#include <immintrin.h>
#define MULTICAGE_AVX2_RASTER 1
#define MULTICAGE_V3 MULTICAGE_TARGET_X86_64_V3
#endif

namespace cv {
namespace multicage {
namespace raster {

#if defined(MULTICAGE_AVX2_RASTER)
namespace {

// Why: the baseline kernel draws a triangle at a time, and at grid step 4 (a triangle is about 8
// pixels in 3-4 short spans) its time goes to what a triangle costs whatever it covers: set-up,
// bounds, a span per row, and branches on span lengths that a predictor cannot learn. The
// AVX-512 kernel (raster_avx512.cpp) fixes this with 8 triangles per vector and masks; this is
// the same idea in AVX2's 4 doubles and without masks: every triangle of a group finds its span
// of a row at once, then each pixel of the row learns which triangle owns it (the last one in
// drawing order whose span holds it: 32 pixels per byte compare), and the pixels are computed
// 8 at a time from their owner's affine map (looked up in registers). No branch depends on a
// span's length. Every value is computed with the double operations of setUpTriangles,
// triangleBounds, rowSpan and drawTriangle, in their order (no fused multiply-adds in this file),
// so the bits are the baseline kernel's (tests/deform/raster_reference_test.cpp). Its timings
// against the baseline: docs/cpu-kernels.md.

constexpr int kCells = 4;        // cells per group: two triangles each, 8 triangles
constexpr int kOwnedWidth = 32;  // the columns one byte vector of owners holds
constexpr int kNobody = 255;     // the owner of a pixel no triangle of the group holds

// One of the two triangles (kind 0: (a,b,c), kind 1: (b,d,c)) of 4 cells, set up. Masks are
// lanes of all-one bits.
struct Lanes {
    __m256d a0[3], ay[3], invAx[3];        // the barycentric edge functions (rowSpan's)
    __m256d pos[3], neg[3];                // ax > 0 (bounds the left), ax < 0 (the right)
    __m256d flat[3];                       // neither (ax is 0 or NaN), in valid lanes
    __m256d xa, xb, ya, yb;                // triangleBounds, integral values
    __m256d valid;                         // triangleBounds returned true
    __m256d mxx, mxy, mx0, myx, myy, my0;  // the inverse map (drawTriangle's)
    int validBits;
    bool anyFlat;
};

// Nodes [first, first + 4) of a row of points: x and y as doubles (lanes past `count` are 0).
MULTICAGE_V3 inline void loadNodes(const Point2f* p, int first, int count, __m256d& x, __m256d& y) {
    __m256 v;
    if (count >= kCells) {
        v = _mm256_loadu_ps(&p[first].x);
    } else {
        alignas(32) float part[2 * kCells] = {};
        for (int k = 0; k < count; ++k)
            part[2 * k] = p[first + k].x, part[2 * k + 1] = p[first + k].y;
        v = _mm256_load_ps(part);
    }
    const __m256 split = _mm256_permutevar8x32_ps(v, _mm256_setr_epi32(0, 2, 4, 6, 1, 3, 5, 7));
    x = _mm256_cvtps_pd(_mm256_castps256_ps128(split));
    y = _mm256_cvtps_pd(_mm256_extractf128_ps(split, 1));
}

MULTICAGE_V3 inline __m256d lessEqual(__m256d a, __m256d b) {
    return _mm256_cmp_pd(a, b, _CMP_LE_OQ);
}

// a0 d0 + a1 d1: setUpTriangles' inverse map.
MULTICAGE_V3 inline __m256d combine(const __m256d a[3], __m256d d0, __m256d d1) {
    return _mm256_add_pd(_mm256_mul_pd(a[0], d0), _mm256_mul_pd(a[1], d1));
}

// setUpTriangles and triangleBounds for 4 triangles with deformed corners q and rest corners p.
MULTICAGE_V3 inline void setUp(const __m256d qx[3], const __m256d qy[3], const __m256d px[3],
                               const __m256d py[3], __m256d cells, int y0, int y1, int cols,
                               Lanes& l) {
    // min3 / max3: r = a; r = b < r ? b : r; ... (min_pd(b, r) is b < r ? b : r)
    const __m256d minY = _mm256_min_pd(qy[2], _mm256_min_pd(qy[1], qy[0]));
    const __m256d maxY = _mm256_max_pd(qy[2], _mm256_max_pd(qy[1], qy[0]));
    const __m256d minX = _mm256_min_pd(qx[2], _mm256_min_pd(qx[1], qx[0]));
    const __m256d maxX = _mm256_max_pd(qx[2], _mm256_max_pd(qx[1], qx[0]));
    const __m256d top = _mm256_set1_pd(y0), bottom = _mm256_set1_pd(y1 - 1);
    const __m256d zero = _mm256_setzero_pd(), right = _mm256_set1_pd(cols - 1);
    __m256d valid = _mm256_and_pd(
        _mm256_and_pd(cells, _mm256_cmp_pd(maxY, top, _CMP_GE_OQ)),
        _mm256_and_pd(lessEqual(minY, bottom), _mm256_and_pd(_mm256_cmp_pd(maxX, zero, _CMP_GE_OQ),
                                                             lessEqual(minX, right))));
    // std::max(v, bound) is v < bound ? bound : v, max_pd(bound, v) bound > v ? bound : v.
    l.ya = _mm256_round_pd(_mm256_max_pd(top, minY), _MM_FROUND_TO_POS_INF | _MM_FROUND_NO_EXC);
    l.yb = _mm256_round_pd(_mm256_min_pd(bottom, maxY), _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
    l.xa = _mm256_round_pd(_mm256_max_pd(zero, minX), _MM_FROUND_TO_POS_INF | _MM_FROUND_NO_EXC);
    l.xb = _mm256_round_pd(_mm256_min_pd(right, maxX), _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
    valid = _mm256_and_pd(valid, _mm256_and_pd(lessEqual(l.ya, l.yb), lessEqual(l.xa, l.xb)));
    const __m256d area =
        _mm256_sub_pd(_mm256_mul_pd(_mm256_sub_pd(qx[1], qx[0]), _mm256_sub_pd(qy[2], qy[0])),
                      _mm256_mul_pd(_mm256_sub_pd(qy[1], qy[0]), _mm256_sub_pd(qx[2], qx[0])));
    const __m256d absArea = _mm256_andnot_pd(_mm256_set1_pd(-0.0), area);
    valid = _mm256_and_pd(
        valid, _mm256_and_pd(_mm256_cmp_pd(absArea, _mm256_set1_pd(1e-12), _CMP_GT_OQ),
                             _mm256_cmp_pd(absArea, _mm256_set1_pd(INFINITY), _CMP_LT_OQ)));
    l.valid = valid;
    l.validBits = _mm256_movemask_pd(valid);
    l.anyFlat = false;
    if (!l.validBits) {  // drawRow still finds this half's (empty) spans: defined values
        const __m256d z = _mm256_setzero_pd();
        for (int i = 0; i < 3; ++i)
            l.a0[i] = l.ay[i] = l.invAx[i] = l.pos[i] = l.neg[i] = l.flat[i] = z;
        l.mxx = l.mxy = l.mx0 = l.myx = l.myy = l.my0 = z;
        return;
    }
    const __m256d one = _mm256_set1_pd(1.0), inv = _mm256_div_pd(one, area);
    __m256d ax[3], ay[3], a0[3];
    __m256d anyFlat = _mm256_setzero_pd();
    for (int i = 0; i < 3; ++i) {  // the edge (e0, e1) opposite vertex i
        const int e0 = (i + 1) % 3, e1 = (i + 2) % 3;
        ax[i] = _mm256_mul_pd(_mm256_sub_pd(qy[e0], qy[e1]), inv);
        ay[i] = _mm256_mul_pd(_mm256_sub_pd(qx[e1], qx[e0]), inv);
        a0[i] = _mm256_mul_pd(
            _mm256_sub_pd(_mm256_mul_pd(qx[e0], qy[e1]), _mm256_mul_pd(qy[e0], qx[e1])), inv);
        l.ay[i] = ay[i], l.a0[i] = a0[i];
        // ax != 0 ? 1 / ax : 0, NaN counting as not 0
        l.invAx[i] =
            _mm256_and_pd(_mm256_cmp_pd(ax[i], zero, _CMP_NEQ_UQ), _mm256_div_pd(one, ax[i]));
        l.pos[i] = _mm256_cmp_pd(ax[i], zero, _CMP_GT_OQ);
        l.neg[i] = _mm256_cmp_pd(ax[i], zero, _CMP_LT_OQ);
        l.flat[i] = _mm256_andnot_pd(_mm256_or_pd(l.pos[i], l.neg[i]), valid);
        anyFlat = _mm256_or_pd(anyFlat, l.flat[i]);
    }
    l.anyFlat = _mm256_movemask_pd(anyFlat) != 0;
    const __m256d d0x = _mm256_sub_pd(px[0], px[2]), d0y = _mm256_sub_pd(py[0], py[2]);
    const __m256d d1x = _mm256_sub_pd(px[1], px[2]), d1y = _mm256_sub_pd(py[1], py[2]);
    l.mxx = combine(ax, d0x, d1x), l.mxy = combine(ay, d0x, d1x);
    l.myx = combine(ax, d0y, d1y), l.myy = combine(ay, d0y, d1y);
    l.mx0 =
        _mm256_add_pd(_mm256_add_pd(px[2], _mm256_mul_pd(a0[0], d0x)), _mm256_mul_pd(a0[1], d1x));
    l.my0 =
        _mm256_add_pd(_mm256_add_pd(py[2], _mm256_mul_pd(a0[0], d0y)), _mm256_mul_pd(a0[1], d1y));
}

// rowSpan of row y for the 4 triangles, as columns relative to x0: [xl, xr] where the row has
// pixels, [127, -1] (nothing) where it has none. Flat: whether some edge is horizontal (ax = 0:
// it empties the row or bounds nothing); without one, rowSpan's third select changes nothing.
template <bool Flat>
MULTICAGE_V3 inline void spans(const Lanes& l, __m256d y, __m256d x0, __m128i& xl, __m128i& xr) {
    __m256d rows = _mm256_and_pd(l.valid, _mm256_and_pd(lessEqual(l.ya, y), lessEqual(y, l.yb)));
    const __m256d eps = _mm256_set1_pd(kEdgeTolerance);
    __m256d left = l.xa, right = l.xb;
    for (int i = 0; i < 3; ++i) {
        const __m256d c = _mm256_add_pd(l.a0[i], _mm256_mul_pd(l.ay[i], y));
        const __m256d v = _mm256_mul_pd(_mm256_sub_pd(eps, c), l.invAx[i]);
        // max_pd(v, left) keeps left when v is NaN, as std::max(left, v) does.
        left = _mm256_blendv_pd(left, _mm256_max_pd(v, left), l.pos[i]);
        right = _mm256_blendv_pd(right, _mm256_min_pd(v, right), l.neg[i]);
        if (Flat)
            right = _mm256_blendv_pd(right, _mm256_set1_pd(-1.0),
                                     _mm256_and_pd(l.flat[i], _mm256_cmp_pd(c, eps, _CMP_LT_OQ)));
    }
    rows = _mm256_and_pd(rows, lessEqual(left, right));
    const __m256d l0 = _mm256_round_pd(left, _MM_FROUND_TO_POS_INF | _MM_FROUND_NO_EXC);
    const __m256d r0 = _mm256_round_pd(right, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
    rows = _mm256_and_pd(rows, lessEqual(l0, r0));
    xl = _mm256_cvtpd_epi32(_mm256_blendv_pd(_mm256_set1_pd(127), _mm256_sub_pd(l0, x0), rows));
    xr = _mm256_cvtpd_epi32(_mm256_blendv_pd(_mm256_set1_pd(-1), _mm256_sub_pd(r0, x0), rows));
}

// A quantity of the 8 triangles (kind 0's lanes, then kind 1's) as two tables of 32-bit halves,
// low and high, indexed by the owner 4 kind + cell: looked up for 8 pixels with one permute each.
struct Table {
    __m256i low, high;
};

MULTICAGE_V3 inline Table table(__m256d kind0, __m256d kind1) {
    const __m256i lowFirst = _mm256_setr_epi32(0, 2, 4, 6, 0, 2, 4, 6);
    const __m256i highFirst = _mm256_setr_epi32(1, 3, 5, 7, 1, 3, 5, 7);
    const __m256i k0 = _mm256_castpd_si256(kind0), k1 = _mm256_castpd_si256(kind1);
    return {_mm256_blend_epi32(_mm256_permutevar8x32_epi32(k0, lowFirst),
                               _mm256_permutevar8x32_epi32(k1, lowFirst), 0xF0),
            _mm256_blend_epi32(_mm256_permutevar8x32_epi32(k0, highFirst),
                               _mm256_permutevar8x32_epi32(k1, highFirst), 0xF0)};
}

// The doubles of 8 pixels' owners: pixels 0, 1, 4, 5 in `a`, 2, 3, 6, 7 in `b` (the order
// unpacking the halves gives; the pixels' columns come in the same order).
MULTICAGE_V3 inline void lookUp(const Table& t, __m256i owner, __m256d& a, __m256d& b) {
    const __m256i low = _mm256_permutevar8x32_epi32(t.low, owner);
    const __m256i high = _mm256_permutevar8x32_epi32(t.high, owner);
    a = _mm256_castsi256_pd(_mm256_unpacklo_epi32(low, high));
    b = _mm256_castsi256_pd(_mm256_unpackhi_epi32(low, high));
}

// float(m x + b) of pixels (0, 1, 4, 5) and (2, 3, 6, 7), clamped to [lo, hi], in pixel order.
MULTICAGE_V3 inline __m256 mapValues(__m256d ma, __m256d mb, __m256d ba, __m256d bb, __m256d xa,
                                     __m256d xb, __m256 lo, __m256 hi) {
    const __m128 fa = _mm256_cvtpd_ps(_mm256_add_pd(_mm256_mul_pd(ma, xa), ba));
    const __m128 fb = _mm256_cvtpd_ps(_mm256_add_pd(_mm256_mul_pd(mb, xb), bb));
    const __m256 v = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_movelh_ps(fa, fb)),
                                          _mm_movehl_ps(fb, fa), 1);
    // std::min(std::max(v, lo), hi): max_ps(lo, v) and min_ps(hi, .) pick v when it is NaN, as
    // std::max and std::min do.
    return _mm256_min_ps(hi, _mm256_max_ps(lo, v));
}

// Row y of a group: the owner of each pixel of columns [x0, x1] (4 kind + cell, kNobody where
// none), then those pixels' map values, 8 at a time, each from its owner's affine map.
// mxx, myx: the group's tables of mxx and myx.
template <bool Flat>
MULTICAGE_V3 inline void drawRow(const Lanes (&lanes)[2], const Table& mxx, const Table& myx, int y,
                                 int x0, int x1, Point2f lo, Point2f hi, float* mx, float* my,
                                 int cols) {
    const __m256d yv = _mm256_set1_pd(y), x0v = _mm256_set1_pd(x0);
    __m128i xl0, xr0, xl1, xr1;
    spans<Flat>(lanes[0], yv, x0v, xl0, xr0);
    spans<Flat>(lanes[1], yv, x0v, xl1, xr1);
    // Bytes 4 kind + cell of both halves: the spans' ends, relative to x0.
    const __m256i left = _mm256_broadcastsi128_si256(
        _mm_packs_epi16(_mm_packs_epi32(xl0, xl1), _mm_setzero_si128()));
    const __m256i right = _mm256_broadcastsi128_si256(
        _mm_packs_epi16(_mm_packs_epi32(xr0, xr1), _mm_setzero_si128()));
    const __m256i column =
        _mm256_setr_epi8(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20,
                         21, 22, 23, 24, 25, 26, 27, 28, 29, 30, 31);
    __m256i owner = _mm256_set1_epi8(static_cast<char>(kNobody));
    // Drawing order: cell by cell, kind 0 then kind 1; a later triangle overwrites an earlier one.
#pragma GCC unroll 8
    for (int d = 0; d < 2 * kCells; ++d) {
        const int t = 4 * (d & 1) + (d >> 1);
        const __m256i which = _mm256_set1_epi8(static_cast<char>(t));
        const __m256i l = _mm256_shuffle_epi8(left, which), r = _mm256_shuffle_epi8(right, which);
        const __m256i outside =
            _mm256_or_si256(_mm256_cmpgt_epi8(l, column), _mm256_cmpgt_epi8(column, r));
        owner = _mm256_blendv_epi8(which, owner, outside);
    }
    // The maps' offsets for row y: bx = mxy y + mx0, by = myy y + my0 (drawTriangle's).
    const __m256d bx0 = _mm256_add_pd(_mm256_mul_pd(lanes[0].mxy, yv), lanes[0].mx0);
    const __m256d bx1 = _mm256_add_pd(_mm256_mul_pd(lanes[1].mxy, yv), lanes[1].mx0);
    const __m256d by0 = _mm256_add_pd(_mm256_mul_pd(lanes[0].myy, yv), lanes[0].my0);
    const __m256d by1 = _mm256_add_pd(_mm256_mul_pd(lanes[1].myy, yv), lanes[1].my0);
    const Table bx = table(bx0, bx1), by = table(by0, by1);
    const __m256 lox = _mm256_set1_ps(lo.x), loy = _mm256_set1_ps(lo.y);
    const __m256 hix = _mm256_set1_ps(hi.x), hiy = _mm256_set1_ps(hi.y);
    const __m256i nobody = _mm256_set1_epi32(kNobody);
    // Chunks of 8 columns with no owner (a group's first and last rows hold few pixels) are
    // skipped; x stops at the first column a whole vector cannot reach (the image's last ones).
    const unsigned held = ~unsigned(_mm256_movemask_epi8(
        _mm256_cmpeq_epi8(owner, _mm256_set1_epi8(static_cast<char>(kNobody)))));
    const int vectorEnd = std::min(x1 + 1, cols - 7);
    const __m256d xa0 = _mm256_add_pd(_mm256_set1_pd(x0), _mm256_setr_pd(0, 1, 4, 5));
    const __m256d xb0 = _mm256_add_pd(_mm256_set1_pd(x0), _mm256_setr_pd(2, 3, 6, 7));
    int x = x0;
    for (int chunk = 0; x < vectorEnd; ++chunk, x += 8) {
        if (!((held >> (8 * chunk)) & 0xff)) continue;
        const __m128i half =
            chunk < 2 ? _mm256_castsi256_si128(owner) : _mm256_extracti128_si256(owner, 1);
        const __m256i t = _mm256_cvtepu8_epi32(chunk & 1 ? _mm_srli_si128(half, 8) : half);
        __m256d mxxA, mxxB, bxA, bxB, myxA, myxB, byA, byB;
        lookUp(mxx, t, mxxA, mxxB), lookUp(bx, t, bxA, bxB);
        lookUp(myx, t, myxA, myxB), lookUp(by, t, byA, byB);
        const __m256d offset = _mm256_set1_pd(8 * chunk);
        const __m256d xa = _mm256_add_pd(xa0, offset), xb = _mm256_add_pd(xb0, offset);
        const __m256 keep = _mm256_castsi256_ps(_mm256_cmpeq_epi32(t, nobody));
        const __m256 vx = mapValues(mxxA, mxxB, bxA, bxB, xa, xb, lox, hix);
        const __m256 vy = mapValues(myxA, myxB, byA, byB, xa, xb, loy, hiy);
        _mm256_storeu_ps(mx + x, _mm256_blendv_ps(vx, _mm256_loadu_ps(mx + x), keep));
        _mm256_storeu_ps(my + x, _mm256_blendv_ps(vy, _mm256_loadu_ps(my + x), keep));
    }
    if (x > x1) return;
    // The last columns of the image, fewer than 8 (a vector would pass the row's end): one by one.
    alignas(32) unsigned char owners[kOwnedWidth];
    alignas(32) double mxxOf[8], myxOf[8], bxOf[8], byOf[8];
    _mm256_store_si256(reinterpret_cast<__m256i*>(owners), owner);
    _mm256_store_pd(mxxOf, lanes[0].mxx), _mm256_store_pd(mxxOf + 4, lanes[1].mxx);
    _mm256_store_pd(myxOf, lanes[0].myx), _mm256_store_pd(myxOf + 4, lanes[1].myx);
    _mm256_store_pd(bxOf, bx0), _mm256_store_pd(bxOf + 4, bx1);
    _mm256_store_pd(byOf, by0), _mm256_store_pd(byOf + 4, by1);
    for (; x <= x1; ++x) {
        const int t = owners[x - x0];
        if (t == kNobody) continue;
        mx[x] = std::min(std::max(static_cast<float>(mxxOf[t] * x + bxOf[t]), lo.x), hi.x);
        my[x] = std::min(std::max(static_cast<float>(myxOf[t] * x + byOf[t]), lo.y), hi.y);
    }
}

// The least (most) value of valid lanes of both kinds.
MULTICAGE_V3 inline double least(const Lanes (&l)[2], __m256d Lanes::*v) {
    const __m256d big = _mm256_set1_pd(INFINITY);
    __m256d m = _mm256_min_pd(_mm256_blendv_pd(big, l[0].*v, l[0].valid),
                              _mm256_blendv_pd(big, l[1].*v, l[1].valid));
    m = _mm256_min_pd(m, _mm256_permute2f128_pd(m, m, 1));
    return _mm_cvtsd_f64(
        _mm_min_pd(_mm256_castpd256_pd128(m), _mm_permute_pd(_mm256_castpd256_pd128(m), 1)));
}
MULTICAGE_V3 inline double most(const Lanes (&l)[2], __m256d Lanes::*v) {
    const __m256d small = _mm256_set1_pd(-INFINITY);
    __m256d m = _mm256_max_pd(_mm256_blendv_pd(small, l[0].*v, l[0].valid),
                              _mm256_blendv_pd(small, l[1].*v, l[1].valid));
    m = _mm256_max_pd(m, _mm256_permute2f128_pd(m, m, 1));
    return _mm_cvtsd_f64(
        _mm_max_pd(_mm256_castpd256_pd128(m), _mm_permute_pd(_mm256_castpd256_pd128(m), 1)));
}

}  // namespace

MULTICAGE_V3
void drawCellRowAvx2(const Point2f* p0, const Point2f* p1, const Point2f* r0, const Point2f* r1,
                     int cells, int y0, int y1, Point2f lo, Point2f hi, Mat& mapx, Mat& mapy,
                     TriangleSetup& s) {
    static_assert(kCellTriangles[0][0][0] == 0 && kCellTriangles[0][1][0] == 1 &&
                      kCellTriangles[0][2][1] == 1 && kCellTriangles[1][0][0] == 1 &&
                      kCellTriangles[1][1][1] == 1 && kCellTriangles[1][2][0] == 0,
                  "the kernel's corners are kCellTriangles' (a,b,c), (b,d,c)");
    const int cols = mapx.cols;
    const __m256d lane = _mm256_setr_pd(0, 1, 2, 3);
    for (int first = 0; first < cells; first += kCells) {
        const int n = std::min(kCells, cells - first);
        const __m256d cellMask = _mm256_cmp_pd(lane, _mm256_set1_pd(n), _CMP_LT_OQ);
        // Corners a = p0[x], b = p0[x + 1], c = p1[x], d = p1[x + 1] of cells x = first + lane.
        __m256d ax, ay, bx, by, cx, cy, dx, dy, rax, ray, rbx, rby, rcx, rcy, rdx, rdy;
        loadNodes(p0, first, n, ax, ay), loadNodes(p0, first + 1, n, bx, by);
        loadNodes(p1, first, n, cx, cy), loadNodes(p1, first + 1, n, dx, dy);
        loadNodes(r0, first, n, rax, ray), loadNodes(r0, first + 1, n, rbx, rby);
        loadNodes(r1, first, n, rcx, rcy), loadNodes(r1, first + 1, n, rdx, rdy);
        Lanes lanes[2];
        {
            const __m256d qx0[3] = {ax, bx, cx}, qy0[3] = {ay, by, cy};
            const __m256d px0[3] = {rax, rbx, rcx}, py0[3] = {ray, rby, rcy};
            setUp(qx0, qy0, px0, py0, cellMask, y0, y1, cols, lanes[0]);
            const __m256d qx1[3] = {bx, dx, cx}, qy1[3] = {by, dy, cy};
            const __m256d px1[3] = {rbx, rdx, rcx}, py1[3] = {rby, rdy, rcy};
            setUp(qx1, qy1, px1, py1, cellMask, y0, y1, cols, lanes[1]);
        }
        if (!(lanes[0].validBits | lanes[1].validBits)) continue;
        const int x0 = static_cast<int>(least(lanes, &Lanes::xa));
        const int x1 = static_cast<int>(most(lanes, &Lanes::xb));
        if (x1 - x0 >= kOwnedWidth) {
            // Wider than a vector of owners (a coarse grid, or cells stretched far): one triangle
            // at a time, as the baseline kernel draws them.
            prepareRun(p0, p1, r0, r1, first, n, s);
            for (int t = 0; t < 2 * n; ++t) drawTriangle(s, t, y0, y1, lo, hi, mapx, mapy);
            continue;
        }
        const int ya = static_cast<int>(least(lanes, &Lanes::ya));
        const int yb = static_cast<int>(most(lanes, &Lanes::yb));
        const bool flat = lanes[0].anyFlat || lanes[1].anyFlat;
        const Table mxx = table(lanes[0].mxx, lanes[1].mxx),
                    myx = table(lanes[0].myx, lanes[1].myx);
        for (int y = ya; y <= yb; ++y) {
            float* mx = mapx.ptr<float>(y);
            float* my = mapy.ptr<float>(y);
            if (flat)
                drawRow<true>(lanes, mxx, myx, y, x0, x1, lo, hi, mx, my, cols);
            else
                drawRow<false>(lanes, mxx, myx, y, x0, x1, lo, hi, mx, my, cols);
        }
    }
}

bool haveAvx2Kernel() {
    return true;
}
#else
void drawCellRowAvx2(const Point2f*, const Point2f*, const Point2f*, const Point2f*, int, int, int,
                     Point2f, Point2f, Mat&, Mat&, TriangleSetup&) {
    CV_Error(Error::StsNotImplemented, "multicage: no AVX2 raster kernel in this build");
}
bool haveAvx2Kernel() {
    return false;
}
#endif

}  // namespace raster
}  // namespace multicage
}  // namespace cv

// The AVX-512 triangle kernel: triangles in lanes. The triangles of 8 cells are set up at once,
// then each output row they touch gets their 16 spans at once, filled in drawing order.

// First, before any other header (clang-format would sort it among them): the rasteriser's
// floating-point options.
// clang-format off
#include "raster_options.hpp"
// clang-format on

#include <opencv2/multicage/internal/cpu_dispatch.hpp>
#include <vector>

#include "raster_kernels.hpp"

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
// GCC 12's AVX-512 headers start vectors from _mm512_undefined_*(), which -W(maybe-)uninitialized
// reports at every use.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#include <immintrin.h>
#define MULTICAGE_AVX512_RASTER 1
#define MULTICAGE_V4 MULTICAGE_TARGET_X86_64_V4
#endif

namespace cv {
namespace multicage {
namespace raster {

#if defined(MULTICAGE_AVX512_RASTER)
namespace {

// Why lanes hold triangles rather than rows or pixels: a cell of a grid of step 4 covers about
// 16 px, of step 1 about one, so a triangle is a few short spans (or none) and its fixed costs
// (set-up, bounds, a span per row) are what a one-triangle-at-a-time kernel spends its time on.
// Here the set-up and the spans of 8 triangles cost what one did. Every value is computed with
// the double operations of setUpTriangles, triangleBounds and rowSpan, in their order (no fused
// multiply-adds in this file), so the bits are those of the baseline kernel. Pixel order: a
// pixel of row y is written by the triangles of a group in drawing order (cell by cell, its
// kCellTriangles in turn), and groups of a cell row, and cell rows, come in order, so where the
// mesh folds the later triangle still wins.

// One of the two triangles (kind 0: (a,b,c), kind 1: (b,d,c)) of 8 cells, set up.
struct Lanes {
    __m512d a0[3], ay[3], invAx[3];  // the barycentric edge functions (rowSpan's)
    __mmask8 pos[3], neg[3];         // ax > 0 (bounds the left), ax < 0 (the right)
    __mmask8 flat[3];                // neither (ax is 0 or NaN), in valid lanes
    bool anyFlat;                    // some flat[i] is not 0
    __m512d xa, xb, ya, yb;          // triangleBounds, integral values
    __mmask8 valid;                  // triangleBounds returned true
};

// The inverse map of each triangle of a group, for the fills: index 8 kind + cell.
struct GroupMaps {
    alignas(64) double mxx[16], myx[16], mxy[16], mx0[16], myy[16], my0[16];
};

// Nodes [first, first + 8) of a row of points: x and y as doubles (lanes past `count` are 0).
MULTICAGE_V4 inline void loadNodes(const Point2f* p, int first, int count, __m512d& x, __m512d& y) {
    const __m512 v = count >= 8 ? _mm512_loadu_ps(&p[first].x)
                                : _mm512_maskz_loadu_ps(
                                      static_cast<__mmask16>((1u << (2 * count)) - 1), &p[first].x);
    const __m512i even = _mm512_setr_epi32(0, 2, 4, 6, 8, 10, 12, 14, 0, 0, 0, 0, 0, 0, 0, 0);
    const __m512i odd = _mm512_setr_epi32(1, 3, 5, 7, 9, 11, 13, 15, 0, 0, 0, 0, 0, 0, 0, 0);
    x = _mm512_cvtps_pd(_mm512_castps512_ps256(_mm512_permutexvar_ps(even, v)));
    y = _mm512_cvtps_pd(_mm512_castps512_ps256(_mm512_permutexvar_ps(odd, v)));
}

// setUpTriangles and triangleBounds for 8 triangles with deformed corners q and rest corners p.
MULTICAGE_V4 inline void setUp(const __m512d qx[3], const __m512d qy[3], const __m512d px[3],
                               const __m512d py[3], __mmask8 cells, int y0, int y1, int cols,
                               Lanes& l, GroupMaps& maps, int kind) {
    // min3 / max3: r = a; r = b < r ? b : r; ... (min_pd(b, r) is b < r ? b : r)
    const __m512d minY = _mm512_min_pd(qy[2], _mm512_min_pd(qy[1], qy[0]));
    const __m512d maxY = _mm512_max_pd(qy[2], _mm512_max_pd(qy[1], qy[0]));
    const __m512d minX = _mm512_min_pd(qx[2], _mm512_min_pd(qx[1], qx[0]));
    const __m512d maxX = _mm512_max_pd(qx[2], _mm512_max_pd(qx[1], qx[0]));
    const __m512d top = _mm512_set1_pd(y0), bottom = _mm512_set1_pd(y1 - 1);
    const __m512d zero = _mm512_setzero_pd(), right = _mm512_set1_pd(cols - 1);
    __mmask8 valid = cells & _mm512_cmp_pd_mask(maxY, top, _CMP_GE_OQ) &
                     _mm512_cmp_pd_mask(minY, bottom, _CMP_LE_OQ) &
                     _mm512_cmp_pd_mask(maxX, zero, _CMP_GE_OQ) &
                     _mm512_cmp_pd_mask(minX, right, _CMP_LE_OQ);
    // std::max(v, bound) is v < bound ? bound : v, max_pd(bound, v) bound > v ? bound : v.
    l.ya = _mm512_roundscale_pd(_mm512_max_pd(top, minY), _MM_FROUND_TO_POS_INF);
    l.yb = _mm512_roundscale_pd(_mm512_min_pd(bottom, maxY), _MM_FROUND_TO_NEG_INF);
    l.xa = _mm512_roundscale_pd(_mm512_max_pd(zero, minX), _MM_FROUND_TO_POS_INF);
    l.xb = _mm512_roundscale_pd(_mm512_min_pd(right, maxX), _MM_FROUND_TO_NEG_INF);
    valid &=
        _mm512_cmp_pd_mask(l.ya, l.yb, _CMP_LE_OQ) & _mm512_cmp_pd_mask(l.xa, l.xb, _CMP_LE_OQ);
    const __m512d area =
        _mm512_sub_pd(_mm512_mul_pd(_mm512_sub_pd(qx[1], qx[0]), _mm512_sub_pd(qy[2], qy[0])),
                      _mm512_mul_pd(_mm512_sub_pd(qy[1], qy[0]), _mm512_sub_pd(qx[2], qx[0])));
    const __m512d absArea = _mm512_abs_pd(area);
    valid &= _mm512_cmp_pd_mask(absArea, _mm512_set1_pd(1e-12), _CMP_GT_OQ) &
             _mm512_cmp_pd_mask(absArea, _mm512_set1_pd(INFINITY), _CMP_LT_OQ);
    l.valid = valid;
    // A half with no valid lane is still asked whether it has flat edges (drawCellRowAvx512
    // picks findSpans' variant from both halves): an uninitialised bool there is undefined
    // (UBSan in a GCC build, where this kernel is compiled).
    l.anyFlat = false;
    l.flat[0] = l.flat[1] = l.flat[2] = 0;
    if (!valid) return;
    const __m512d one = _mm512_set1_pd(1.0), inv = _mm512_div_pd(one, area);
    __m512d ax[3], ay[3], a0[3];
    for (int i = 0; i < 3; ++i) {  // the edge (e0, e1) opposite vertex i
        const int e0 = (i + 1) % 3, e1 = (i + 2) % 3;
        ax[i] = _mm512_mul_pd(_mm512_sub_pd(qy[e0], qy[e1]), inv);
        ay[i] = _mm512_mul_pd(_mm512_sub_pd(qx[e1], qx[e0]), inv);
        a0[i] = _mm512_mul_pd(
            _mm512_sub_pd(_mm512_mul_pd(qx[e0], qy[e1]), _mm512_mul_pd(qy[e0], qx[e1])), inv);
        l.ay[i] = ay[i], l.a0[i] = a0[i];
        // ax != 0 ? 1 / ax : 0, NaN counting as not 0
        l.invAx[i] = _mm512_maskz_div_pd(_mm512_cmp_pd_mask(ax[i], zero, _CMP_NEQ_UQ), one, ax[i]);
        l.pos[i] = _mm512_cmp_pd_mask(ax[i], zero, _CMP_GT_OQ);
        l.neg[i] = _mm512_cmp_pd_mask(ax[i], zero, _CMP_LT_OQ);
        l.flat[i] = valid & static_cast<__mmask8>(~(l.pos[i] | l.neg[i]));
    }
    l.anyFlat = (l.flat[0] | l.flat[1] | l.flat[2]) != 0;
    const __m512d d0x = _mm512_sub_pd(px[0], px[2]), d0y = _mm512_sub_pd(py[0], py[2]);
    const __m512d d1x = _mm512_sub_pd(px[1], px[2]), d1y = _mm512_sub_pd(py[1], py[2]);
    auto combine = [&](const __m512d a[3], __m512d d0, __m512d d1) {
        return _mm512_add_pd(_mm512_mul_pd(a[0], d0), _mm512_mul_pd(a[1], d1));
    };
    _mm512_store_pd(maps.mxx + 8 * kind, combine(ax, d0x, d1x));
    _mm512_store_pd(maps.mxy + 8 * kind, combine(ay, d0x, d1x));
    _mm512_store_pd(maps.myx + 8 * kind, combine(ax, d0y, d1y));
    _mm512_store_pd(maps.myy + 8 * kind, combine(ay, d0y, d1y));
    _mm512_store_pd(
        maps.mx0 + 8 * kind,
        _mm512_add_pd(_mm512_add_pd(px[2], _mm512_mul_pd(a0[0], d0x)), _mm512_mul_pd(a0[1], d1x)));
    _mm512_store_pd(
        maps.my0 + 8 * kind,
        _mm512_add_pd(_mm512_add_pd(py[2], _mm512_mul_pd(a0[0], d0y)), _mm512_mul_pd(a0[1], d1y)));
}

// rowSpan of row y for the 8 triangles: the lanes with pixels, and their [xl, xr]. Flat: whether
// some edge is horizontal (ax = 0: it empties the row or bounds nothing), rare but for the ring
// and the rest pose; without one, rowSpan's third select never changes a value.
template <bool Flat>
MULTICAGE_V4 inline __mmask8 spans(const Lanes& l, __m512d y, __m256i& xl, __m256i& xr) {
    __mmask8 rows =
        l.valid & _mm512_cmp_pd_mask(l.ya, y, _CMP_LE_OQ) & _mm512_cmp_pd_mask(y, l.yb, _CMP_LE_OQ);
    if (!rows) return 0;
    const __m512d eps = _mm512_set1_pd(kEdgeTolerance);
    __m512d left = l.xa, right = l.xb;
    for (int i = 0; i < 3; ++i) {
        const __m512d c = _mm512_add_pd(l.a0[i], _mm512_mul_pd(l.ay[i], y));
        const __m512d v = _mm512_mul_pd(_mm512_sub_pd(eps, c), l.invAx[i]);
        left = _mm512_mask_max_pd(left, l.pos[i], v, left);  // a NaN v keeps left
        right = _mm512_mask_min_pd(right, l.neg[i], v, right);
        if (Flat)
            right =
                _mm512_mask_mov_pd(right, _mm512_mask_cmp_pd_mask(l.flat[i], c, eps, _CMP_LT_OQ),
                                   _mm512_set1_pd(-1.0));
    }
    rows &= _mm512_cmp_pd_mask(left, right, _CMP_LE_OQ);
    xl = _mm512_cvtpd_epi32(_mm512_roundscale_pd(left, _MM_FROUND_TO_POS_INF));
    xr = _mm512_cvtpd_epi32(_mm512_roundscale_pd(right, _MM_FROUND_TO_NEG_INF));
    return rows & static_cast<__mmask8>(~_mm256_cmpgt_epi32_mask(xl, xr));
}

// Pixels xl..xr of row y of one triangle: mxx x + bx and myx x + by, clamped to [lo, hi].
MULTICAGE_V4 inline void fillSpan(double mxx, double myx, double bx, double by, int xl, int xr,
                                  Point2f lo, Point2f hi, float* mx, float* my) {
    const __m256i iota = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    const __m512d mxxv = _mm512_set1_pd(mxx), myxv = _mm512_set1_pd(myx);
    const __m512d bxv = _mm512_set1_pd(bx), byv = _mm512_set1_pd(by);
    for (int x = xl; x <= xr; x += 8) {
        // At most 8: BZHI reads only the low 8 bits of its index (a remaining 256 would give 0).
        const __mmask8 lanes =
            static_cast<__mmask8>(_bzhi_u32(0xff, unsigned(std::min(xr - x + 1, 8))));
        const __m512d xv = _mm512_cvtepi32_pd(_mm256_add_epi32(_mm256_set1_epi32(x), iota));
        // std::min(std::max(v, lo), hi): max_ps(lo, v) and min_ps(hi, .) pick v when it is NaN,
        // as std::max and std::min do.
        const __m256 vx = _mm512_cvtpd_ps(_mm512_add_pd(_mm512_mul_pd(mxxv, xv), bxv));
        const __m256 vy = _mm512_cvtpd_ps(_mm512_add_pd(_mm512_mul_pd(myxv, xv), byv));
        _mm256_mask_storeu_ps(
            mx + x, lanes,
            _mm256_min_ps(_mm256_set1_ps(hi.x), _mm256_max_ps(_mm256_set1_ps(lo.x), vx)));
        _mm256_mask_storeu_ps(
            my + x, lanes,
            _mm256_min_ps(_mm256_set1_ps(hi.y), _mm256_max_ps(_mm256_set1_ps(lo.y), vy)));
    }
}

// The spans of a group's rows, in drawing order (row by row, cell by cell, kind 0 then 1).
// Stored by one pass and read by the next (a scalar load of a lane just stored from a vector
// register waits for the store to complete): a group's spans are drawn after the next group's
// have been found.
struct SpanList {
    struct Row {
        int y, begin, end;  // spans [begin, end) of row y
    };
    std::vector<int> xl, xr, tri;  // tri: 8 kind + cell
    std::vector<Row> rows;
    int count = 0, rowCount = 0;
    int x0 = 0, x1 = -1;  // the columns the group's triangles may cover
    GroupMaps maps;
    void reserve(int rowsAtMost) {
        const size_t entries = 16 * size_t(rowsAtMost) + 16;
        if (xl.size() < entries) xl.resize(entries), xr.resize(entries), tri.resize(entries);
        if (rows.size() < size_t(rowsAtMost)) rows.resize(rowsAtMost);
    }
};

// Finds the spans of the group's triangles in rows [ya, yb].
template <bool Flat>
MULTICAGE_V4 inline void findSpans(const Lanes (&lanes)[2], int ya, int yb, SpanList& list) {
    // 16 lanes in drawing order: lane 2 cell + kind.
    const __m512i interleave =
        _mm512_setr_epi32(0, 16, 1, 17, 2, 18, 3, 19, 4, 20, 5, 21, 6, 22, 7, 23);
    const __m512i triangle =
        _mm512_setr_epi32(0, 8, 1, 9, 2, 10, 3, 11, 4, 12, 5, 13, 6, 14, 7, 15);
    list.count = list.rowCount = 0;
    list.reserve(yb - ya + 1);
    for (int y = ya; y <= yb; ++y) {
        const __m512d yv = _mm512_set1_pd(y);
        __m256i l0, r0, l1, r1;
        const unsigned rows0 = spans<Flat>(lanes[0], yv, l0, r0);
        const unsigned rows1 = spans<Flat>(lanes[1], yv, l1, r1);
        const __mmask16 rows =
            static_cast<__mmask16>(_pdep_u32(rows0, 0x5555u) | _pdep_u32(rows1, 0xaaaau));
        if (!rows) continue;
        const __m512i xl = _mm512_permutex2var_epi32(_mm512_castsi256_si512(l0), interleave,
                                                     _mm512_castsi256_si512(l1));
        const __m512i xr = _mm512_permutex2var_epi32(_mm512_castsi256_si512(r0), interleave,
                                                     _mm512_castsi256_si512(r1));
        const int at = list.count;
        _mm512_storeu_si512(&list.xl[at], _mm512_maskz_compress_epi32(rows, xl));
        _mm512_storeu_si512(&list.xr[at], _mm512_maskz_compress_epi32(rows, xr));
        _mm512_storeu_si512(&list.tri[at], _mm512_maskz_compress_epi32(rows, triangle));
        list.count = at + _mm_popcnt_u32(rows);
        list.rows[list.rowCount++] = {y, at, list.count};
    }
}

// Draws a list's spans. When the group's triangles lie within 64 columns, each row is drawn pixel
// by pixel: the triangle each pixel gets (the last in drawing order whose span holds it) is found
// in one register of 64 bytes, then the pixels are computed 8 at a time with their triangle's map.
// That costs per pixel, not per span: at grid step 1 most spans are one pixel.
MULTICAGE_V4 inline void fillSpans(const SpanList& list, Point2f lo, Point2f hi, Mat& mapx,
                                   Mat& mapy) {
    const GroupMaps& m = list.maps;
    const __m512d mxx0 = _mm512_load_pd(m.mxx), mxx1 = _mm512_load_pd(m.mxx + 8);
    const __m512d myx0 = _mm512_load_pd(m.myx), myx1 = _mm512_load_pd(m.myx + 8);
    const __m256i iota = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    const __m256 lox = _mm256_set1_ps(lo.x), loy = _mm256_set1_ps(lo.y);
    const __m256 hix = _mm256_set1_ps(hi.x), hiy = _mm256_set1_ps(hi.y);
    for (int r = 0; r < list.rowCount; ++r) {
        const SpanList::Row& row = list.rows[r];
        const int y = row.y;
        float* mx = mapx.ptr<float>(y);
        float* my = mapy.ptr<float>(y);
        if (list.x1 - list.x0 >= 64) {
            for (int i = row.begin; i < row.end; ++i) {
                const int t = list.tri[i];
                fillSpan(m.mxx[t], m.myx[t], m.mxy[t] * y + m.mx0[t], m.myy[t] * y + m.my0[t],
                         list.xl[i], list.xr[i], lo, hi, mx, my);
            }
            continue;
        }
        __m512i owner = _mm512_set1_epi8(-1);
        for (int i = row.begin; i < row.end; ++i) {
            const unsigned len = unsigned(list.xr[i] - list.xl[i] + 1);
            const __mmask64 px = _bzhi_u64(~0ull, len) << (list.xl[i] - list.x0);
            owner =
                _mm512_mask_mov_epi8(owner, px, _mm512_set1_epi8(static_cast<char>(list.tri[i])));
        }
        const __m512d yv = _mm512_set1_pd(y);
        const __m512d bx0 =
            _mm512_add_pd(_mm512_mul_pd(_mm512_load_pd(m.mxy), yv), _mm512_load_pd(m.mx0));
        const __m512d bx1 =
            _mm512_add_pd(_mm512_mul_pd(_mm512_load_pd(m.mxy + 8), yv), _mm512_load_pd(m.mx0 + 8));
        const __m512d by0 =
            _mm512_add_pd(_mm512_mul_pd(_mm512_load_pd(m.myy), yv), _mm512_load_pd(m.my0));
        const __m512d by1 =
            _mm512_add_pd(_mm512_mul_pd(_mm512_load_pd(m.myy + 8), yv), _mm512_load_pd(m.my0 + 8));
        for (int x = list.x0, c = 0; x <= list.x1; x += 8, c += 8) {
            // bytes c..c+7 of the owners, one per qword lane
            const __m512i t = _mm512_cvtepu8_epi64(
                _mm512_castsi512_si128(_mm512_permutexvar_epi64(_mm512_set1_epi64(c >> 3), owner)));
            const __mmask8 covered = _mm512_cmplt_epu64_mask(t, _mm512_set1_epi64(16));
            const __m512d xv = _mm512_cvtepi32_pd(_mm256_add_epi32(_mm256_set1_epi32(x), iota));
            const __m512d vxd =
                _mm512_add_pd(_mm512_mul_pd(_mm512_permutex2var_pd(mxx0, t, mxx1), xv),
                              _mm512_permutex2var_pd(bx0, t, bx1));
            const __m512d vyd =
                _mm512_add_pd(_mm512_mul_pd(_mm512_permutex2var_pd(myx0, t, myx1), xv),
                              _mm512_permutex2var_pd(by0, t, by1));
            _mm256_mask_storeu_ps(mx + x, covered,
                                  _mm256_min_ps(hix, _mm256_max_ps(lox, _mm512_cvtpd_ps(vxd))));
            _mm256_mask_storeu_ps(my + x, covered,
                                  _mm256_min_ps(hiy, _mm256_max_ps(loy, _mm512_cvtpd_ps(vyd))));
        }
    }
}

}  // namespace

MULTICAGE_V4
void drawCellRowAvx512(const Point2f* p0, const Point2f* p1, const Point2f* r0, const Point2f* r1,
                       int cells, int y0, int y1, Point2f lo, Point2f hi, Mat& mapx, Mat& mapy,
                       TriangleSetup&) {
    thread_local SpanList listsOfThread[2];
    SpanList* lists = listsOfThread;  // (each access to a thread_local may call into the loader)
    Lanes lanes[2];
    int current = 0;
    lists[0].count = lists[1].count = lists[0].rowCount = lists[1].rowCount = 0;
    for (int first = 0; first < cells; first += 8) {
        const int n = std::min(8, cells - first);
        const __mmask8 cellMask = static_cast<__mmask8>((1u << n) - 1);
        // Corners a = p0[x], b = p0[x + 1], c = p1[x], d = p1[x + 1] of cells x = first + lane.
        __m512d ax, ay, bx, by, cx, cy, dx, dy, rax, ray, rbx, rby, rcx, rcy, rdx, rdy;
        loadNodes(p0, first, n, ax, ay), loadNodes(p0, first + 1, n, bx, by);
        loadNodes(p1, first, n, cx, cy), loadNodes(p1, first + 1, n, dx, dy);
        loadNodes(r0, first, n, rax, ray), loadNodes(r0, first + 1, n, rbx, rby);
        loadNodes(r1, first, n, rcx, rcy), loadNodes(r1, first + 1, n, rdx, rdy);
        SpanList& list = lists[current];
        {
            static_assert(kCellTriangles[0][0][0] == 0 && kCellTriangles[0][1][0] == 1 &&
                              kCellTriangles[0][2][1] == 1 && kCellTriangles[1][0][0] == 1 &&
                              kCellTriangles[1][1][1] == 1 && kCellTriangles[1][2][0] == 0,
                          "the kernel's corners are kCellTriangles' (a,b,c), (b,d,c)");
            const __m512d qx0[3] = {ax, bx, cx}, qy0[3] = {ay, by, cy};
            const __m512d px0[3] = {rax, rbx, rcx}, py0[3] = {ray, rby, rcy};
            setUp(qx0, qy0, px0, py0, cellMask, y0, y1, mapx.cols, lanes[0], list.maps, 0);
            const __m512d qx1[3] = {bx, dx, cx}, qy1[3] = {by, dy, cy};
            const __m512d px1[3] = {rbx, rdx, rcx}, py1[3] = {rby, rdy, rcy};
            setUp(qx1, qy1, px1, py1, cellMask, y0, y1, mapx.cols, lanes[1], list.maps, 1);
        }
        if (!(lanes[0].valid | lanes[1].valid)) continue;
        // The rows and columns any of the group's triangles touches.
        const __m512d big = _mm512_set1_pd(INFINITY);
        auto least = [&](__m512d Lanes::*v) {
            return _mm512_reduce_min_pd(
                _mm512_min_pd(_mm512_mask_mov_pd(big, lanes[0].valid, lanes[0].*v),
                              _mm512_mask_mov_pd(big, lanes[1].valid, lanes[1].*v)));
        };
        auto most = [&](__m512d Lanes::*v) {
            return _mm512_reduce_max_pd(
                _mm512_max_pd(_mm512_mask_mov_pd(-big, lanes[0].valid, lanes[0].*v),
                              _mm512_mask_mov_pd(-big, lanes[1].valid, lanes[1].*v)));
        };
        const double ya = least(&Lanes::ya), yb = most(&Lanes::yb);
        list.x0 = static_cast<int>(least(&Lanes::xa)), list.x1 = static_cast<int>(most(&Lanes::xb));
        if (lanes[0].anyFlat || lanes[1].anyFlat)
            findSpans<true>(lanes, static_cast<int>(ya), static_cast<int>(yb), list);
        else
            findSpans<false>(lanes, static_cast<int>(ya), static_cast<int>(yb), list);
        current ^= 1;
        fillSpans(lists[current], lo, hi, mapx, mapy);  // the previous group's
        lists[current].count = lists[current].rowCount = 0;
    }
    fillSpans(lists[current ^ 1], lo, hi, mapx, mapy);
}

bool haveAvx512Kernel() {
    return true;
}
#else
void drawCellRowAvx512(const Point2f*, const Point2f*, const Point2f*, const Point2f*, int, int,
                       int, Point2f, Point2f, Mat&, Mat&, TriangleSetup&) {
    CV_Error(Error::StsNotImplemented, "multicage: no AVX-512 raster kernel in this build");
}
bool haveAvx512Kernel() {
    return false;
}
#endif

}  // namespace raster
}  // namespace multicage
}  // namespace cv

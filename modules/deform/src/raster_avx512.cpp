// The AVX-512 triangle kernel: the spans of 8 rows of a triangle at once, pixels 8 at a time.

// First, before any other header (clang-format would sort it among them): the rasteriser's
// floating-point options.
// clang-format off
#include "raster_options.hpp"
// clang-format on

#include <memory>

#include "raster_kernels.hpp"

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
// GCC 12's AVX-512 headers start vectors from _mm512_undefined_*(), which -W(maybe-)uninitialized
// reports at every use.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#include <immintrin.h>
#define MULTICAGE_AVX512_RASTER 1
#define MULTICAGE_V4 __attribute__((target("arch=x86-64-v4")))
#endif

namespace cv {
namespace multicage {
namespace raster {

#if defined(MULTICAGE_AVX512_RASTER)
namespace {

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

// The spans of rows [ya, ya + 8) of triangle t (lanes past yb are left out of `rows`).
MULTICAGE_V4 inline void spansOf8Rows(const TriangleSetup& s, int t, int ya, int yb, int xa, int xb,
                                      SpanRows& out) {
    const __m512d yv = _mm512_cvtepi32_pd(
        _mm256_add_epi32(_mm256_set1_epi32(ya), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7)));
    const __m512d eps = _mm512_set1_pd(kEdgeTolerance);
    __m512d left = _mm512_set1_pd(xa), right = _mm512_set1_pd(xb);
    for (int i = 0; i < 3; ++i) {  // rowSpan, 8 rows at once
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
    for (int y = ya; y <= yb; ++y) {
        int xl, xr;
        if (rowSpan(s, t, y, xa, xb, xl, xr))
            fillSpan(s, t, xl, xr, s.mxy[t] * y + s.mx0[t], s.myy[t] * y + s.my0[t], lo, hi,
                     mapx.ptr<float>(y), mapy.ptr<float>(y));
    }
}

}  // namespace

MULTICAGE_V4
void drawCellRowAvx512(const Point2f* p0, const Point2f* p1, const Point2f* r0, const Point2f* r1,
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

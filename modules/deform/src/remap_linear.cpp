// Bilinear sampling with float maps and a constant border, as cv::remap computes it.
//
// cv::remap turns each map value v into fixed point: s = round(32 v) (to nearest even), the
// sample column X = s >> 5 (saturated to 16 bits), the fraction a = s & 31, and the same for y.
// Its weights are the products of (32 - a, a) and (32 - b, b) times 32, so a channel is
// (sum of p_k w_k + 2^14) >> 15 = (sum of p_k u_k + 512) >> 10 with u_k = w_k / 32, exactly (the
// one weight of 32768, at a = b = 0, is stored as 32767 and still gives p). A sample outside the
// image reads the border value. The vector path below computes exactly this, so deform() gives
// the bits of cv::remap on computeMaps() (tests/deform/remap_linear_test.cpp).
#include "remap_linear.hpp"

#include <climits>
#include <opencv2/imgproc.hpp>
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
// GCC 12's AVX-512 headers start vectors from _mm512_undefined_*(), which -W(maybe-)uninitialized
// reports at every use.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#include <immintrin.h>
#define MULTICAGE_REMAP_V4 1
#endif

namespace cv {
namespace multicage {

namespace {

// One pixel of a 3-channel image, each of its four samples read from the image or the border.
inline void samplePixel3(const uchar* src, size_t step, int W, int H, float mx, float my,
                         const uchar* border, uchar* d) {
    const int sx = cvRound(mx * 32.f), sy = cvRound(my * 32.f);
    const int X = saturate_cast<short>(sx >> 5), Y = saturate_cast<short>(sy >> 5);
    const int a = sx & 31, b = sy & 31;
    const int u[4] = {(32 - a) * (32 - b), a * (32 - b), (32 - a) * b, a * b};
    const bool x0 = X >= 0 && X < W, x1 = X + 1 >= 0 && X + 1 < W;
    const bool y0 = Y >= 0 && Y < H, y1 = Y + 1 >= 0 && Y + 1 < H;
    const uchar* row0 = src + size_t(std::max(Y, 0)) * step;
    const uchar* row1 = src + size_t(std::max(Y + 1, 0)) * step;
    const uchar* p[4] = {x0 && y0 ? row0 + X * 3 : border, x1 && y0 ? row0 + (X + 1) * 3 : border,
                         x0 && y1 ? row1 + X * 3 : border, x1 && y1 ? row1 + (X + 1) * 3 : border};
    for (int k = 0; k < 3; ++k)
        d[k] = static_cast<uchar>(
            (p[0][k] * u[0] + p[1][k] * u[1] + p[2][k] * u[2] + p[3][k] * u[3] + 512) >> 10);
}

#if defined(MULTICAGE_REMAP_V4)
#define MULTICAGE_V4 __attribute__((target("arch=x86-64-v4")))

// One output row of a 3-channel image, 16 pixels at a time where all of their samples lie
// inside the image (X in [0, W-2], Y in [0, H-2]); other pixels one by one.
MULTICAGE_V4 void remapRow3(const uchar* src, size_t step, int W, int H, const float* mx,
                            const float* my, uchar* d, int cols, const uchar* border) {
    const __m512 scale = _mm512_set1_ps(32.f);
    const __m512i lastX = _mm512_set1_epi32(W - 1), lastY = _mm512_set1_epi32(H - 1);
    const __m512i fraction = _mm512_set1_epi32(31), thirtyTwo = _mm512_set1_epi32(32);
    const __m512i stepV = _mm512_set1_epi32(static_cast<int>(step));
    const __m512i half = _mm512_set1_epi32(512);
    // Each 128-bit lane ends with 4 pixels of 4 bytes (b, g, r, junk): keep 12 bytes per lane,
    // then the 4 lanes' 12 bytes together.
    const __m512i keep3 =
        _mm512_broadcast_i32x4(_mm_setr_epi8(0, 1, 2, 4, 5, 6, 8, 9, 10, 12, 13, 14, 3, 7, 11, 15));
    const __m512i lanes = _mm512_setr_epi32(0, 1, 2, 4, 5, 6, 8, 9, 10, 12, 13, 14, 3, 7, 11, 15);
    int x = 0;
    for (; x + 16 <= cols; x += 16) {
        const __m512i sx = _mm512_cvtps_epi32(_mm512_mul_ps(_mm512_loadu_ps(mx + x), scale));
        const __m512i sy = _mm512_cvtps_epi32(_mm512_mul_ps(_mm512_loadu_ps(my + x), scale));
        const __m512i X = _mm512_srai_epi32(sx, 5), Y = _mm512_srai_epi32(sy, 5);
        // W and H are below 2^15 (remapLinear), so 16-bit saturation changes no inside test.
        if ((_mm512_cmplt_epu32_mask(X, lastX) & _mm512_cmplt_epu32_mask(Y, lastY)) != 0xFFFF) {
            for (int k = x; k < x + 16; ++k)
                samplePixel3(src, step, W, H, mx[k], my[k], border, d + 3 * k);
            continue;
        }
        const __m512i a = _mm512_and_si512(sx, fraction), b = _mm512_and_si512(sy, fraction);
        const __m512i top = _mm512_add_epi32(_mm512_mullo_epi32(Y, stepV),
                                             _mm512_add_epi32(_mm512_add_epi32(X, X), X));
        const __m512i bottom = _mm512_add_epi32(top, stepV);
        // 4 bytes from each sample: (b, g, r, next byte); the right-hand samples are read from
        // 2 bytes earlier and shifted, so that no read passes the image's last byte.
        const __m512i two = _mm512_set1_epi32(2);
        const __m512i tl = _mm512_i32gather_epi32(top, src, 1);
        const __m512i tr =
            _mm512_srli_epi32(_mm512_i32gather_epi32(_mm512_add_epi32(top, two), src, 1), 8);
        const __m512i bl = _mm512_i32gather_epi32(bottom, src, 1);
        const __m512i br =
            _mm512_srli_epi32(_mm512_i32gather_epi32(_mm512_add_epi32(bottom, two), src, 1), 8);
        // Along x, in 16 bits: (32 - a) left + a right, the byte pair (32 - a, a) in both words
        // of each pixel's dword.
        const __m512i pairX =
            _mm512_or_si512(_mm512_sub_epi32(thirtyTwo, a), _mm512_slli_epi32(a, 8));
        const __m512i wx = _mm512_or_si512(pairX, _mm512_slli_epi32(pairX, 16));
        const __m512i wxLo = _mm512_unpacklo_epi32(wx, wx), wxHi = _mm512_unpackhi_epi32(wx, wx);
        const __m512i t0 = _mm512_maddubs_epi16(_mm512_unpacklo_epi8(tl, tr), wxLo);
        const __m512i t1 = _mm512_maddubs_epi16(_mm512_unpackhi_epi8(tl, tr), wxHi);
        const __m512i b0 = _mm512_maddubs_epi16(_mm512_unpacklo_epi8(bl, br), wxLo);
        const __m512i b1 = _mm512_maddubs_epi16(_mm512_unpackhi_epi8(bl, br), wxHi);
        // Along y, in 32 bits: (32 - b) top + b bottom; pixel k of each lane in r_k.
        const __m512i wy =
            _mm512_or_si512(_mm512_sub_epi32(thirtyTwo, b), _mm512_slli_epi32(b, 16));
        __m512i r0 = _mm512_madd_epi16(_mm512_unpacklo_epi16(t0, b0),
                                       _mm512_shuffle_epi32(wy, _MM_PERM_AAAA));
        __m512i r1 = _mm512_madd_epi16(_mm512_unpackhi_epi16(t0, b0),
                                       _mm512_shuffle_epi32(wy, _MM_PERM_BBBB));
        __m512i r2 = _mm512_madd_epi16(_mm512_unpacklo_epi16(t1, b1),
                                       _mm512_shuffle_epi32(wy, _MM_PERM_CCCC));
        __m512i r3 = _mm512_madd_epi16(_mm512_unpackhi_epi16(t1, b1),
                                       _mm512_shuffle_epi32(wy, _MM_PERM_DDDD));
        r0 = _mm512_srli_epi32(_mm512_add_epi32(r0, half), 10);
        r1 = _mm512_srli_epi32(_mm512_add_epi32(r1, half), 10);
        r2 = _mm512_srli_epi32(_mm512_add_epi32(r2, half), 10);
        r3 = _mm512_srli_epi32(_mm512_add_epi32(r3, half), 10);
        const __m512i bytes =
            _mm512_packus_epi16(_mm512_packs_epi32(r0, r1), _mm512_packs_epi32(r2, r3));
        const __m512i packed = _mm512_permutexvar_epi32(lanes, _mm512_shuffle_epi8(bytes, keep3));
        _mm512_mask_storeu_epi32(d + 3 * x, 0x0FFF, packed);
    }
    for (; x < cols; ++x) samplePixel3(src, step, W, H, mx[x], my[x], border, d + 3 * x);
}

bool haveV4() {
    static const bool v4 = __builtin_cpu_supports("avx512f") &&
                           __builtin_cpu_supports("avx512bw") &&
                           __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512dq");
    return v4;
}
#endif

}  // namespace

bool remapLinearOwnPath(int type) {
#if defined(MULTICAGE_REMAP_V4)
    return type == CV_8UC3 && haveV4();
#else
    (void)type;
    return false;
#endif
}

void remapLinear(const Mat& src, OutputArray dstOut, const Mat& mapx, const Mat& mapy,
                 const Scalar& border) {
    const bool own = remapLinearOwnPath(src.type()) && mapx.type() == CV_32F &&
                     mapy.type() == CV_32F && mapx.size() == mapy.size() && src.cols < SHRT_MAX &&
                     src.rows < SHRT_MAX && src.cols >= 2 && src.rows >= 2 &&
                     src.step < size_t(INT_MAX) / 4 && src.step * src.rows < size_t(INT_MAX) / 2;
    if (!own) {
        remap(src, dstOut, mapx, mapy, INTER_LINEAR, BORDER_CONSTANT, border);
        return;
    }
#if defined(MULTICAGE_REMAP_V4)
    CV_Assert(dstOut.getObj() != &src);
    dstOut.create(mapx.size(), src.type());
    Mat dst = dstOut.getMat();
    CV_Assert(dst.data != src.data);
    uchar cval[4];
    for (int k = 0; k < 4; ++k) cval[k] = saturate_cast<uchar>(border[k]);
    parallel_for_(
        Range(0, dst.rows),
        [&](const Range& r) {
            for (int y = r.start; y < r.end; ++y)
                remapRow3(src.data, src.step, src.cols, src.rows, mapx.ptr<float>(y),
                          mapy.ptr<float>(y), dst.ptr(y), dst.cols, cval);
        },
        std::max(1.0, dst.rows / 16.0));
#endif
}

}  // namespace multicage
}  // namespace cv

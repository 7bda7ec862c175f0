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

#include <atomic>
#include <climits>
#include <opencv2/imgproc.hpp>
#include <opencv2/multicage/internal/cpu_dispatch.hpp>
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

// One pixel of a 3-channel image, each of its four samples read from the image or the border
// (unused where no vector path is compiled: clang builds).
[[maybe_unused]] inline void samplePixel3(const uchar* src, size_t step, int W, int H, float mx,
                                          float my, const uchar* border, uchar* d) {
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
#define MULTICAGE_V4 MULTICAGE_TARGET_X86_64_V4
#define MULTICAGE_V3 MULTICAGE_TARGET_X86_64_V3

// (AVX2 functions inline into the AVX-512 ones: x86-64-v4 holds all of x86-64-v3.)
MULTICAGE_V3 inline __m128i load16(const uchar* p) {
    return _mm_loadu_si128(reinterpret_cast<const __m128i*>(p));
}

MULTICAGE_V3 inline __m128i load8(const uchar* p) {
    return _mm_loadl_epi64(reinterpret_cast<const __m128i*>(p));
}

// What a row of remapRow3 needs: the image, and the constants of its vector path.
struct Sampler3x16 {
    const uchar* src;
    size_t step;
    int W, H;
    const uchar* border;
    __m512i lastX, lastY, stepV, keep3, lanes, order, pairs, evenOfPair, pairsAt0, spread;
    __m512i lastRead, lastWindow;

    MULTICAGE_V4 Sampler3x16(const uchar* src_, size_t step_, int W_, int H_, const uchar* border_)
        : src(src_),
          step(step_),
          W(W_),
          H(H_),
          border(border_),
          lastX(_mm512_set1_epi32(W - 1)),
          lastY(_mm512_set1_epi32(H - 1)),
          stepV(_mm512_set1_epi32(static_cast<int>(step))),
          // Each 128-bit lane ends with 4 pixels of 4 bytes (b, g, r, junk): keep 12 bytes per
          // lane, then the 4 lanes' 12 bytes together.
          keep3(_mm512_broadcast_i32x4(
              _mm_setr_epi8(0, 1, 2, 4, 5, 6, 8, 9, 10, 12, 13, 14, 3, 7, 11, 15))),
          lanes(_mm512_setr_epi32(0, 1, 2, 4, 5, 6, 8, 9, 10, 12, 13, 14, 3, 7, 11, 15)),
          order(_mm512_setr_epi32(0, 1, 4, 5, 8, 9, 12, 13, 2, 3, 6, 7, 10, 11, 14, 15)),
          pairs(_mm512_broadcast_i32x4(
              _mm_setr_epi8(0, 3, 1, 4, 2, 5, -1, -1, 8, 11, 9, 12, 10, 13, -1, -1))),
          evenOfPair(_mm512_setr_epi32(0, 0, 2, 2, 4, 4, 6, 6, 8, 8, 10, 10, 12, 12, 14, 14)),
          // pairs for a 16-byte window: bytes 8-13 get where the lane's second pixel starts
          // (`spread`: byte 0 of each odd qword lane to bytes 0-5 of it; even lanes hold 0 there).
          pairsAt0(_mm512_broadcast_i32x4(
              _mm_setr_epi8(0, 3, 1, 4, 2, 5, -1, -1, 0, 3, 1, 4, 2, 5, -1, -1))),
          spread(_mm512_broadcast_i32x4(
              _mm_setr_epi8(-1, -1, -1, -1, -1, -1, -1, -1, 8, 8, 8, 8, 8, 8, -1, -1))),
          // The last offset an 8-byte read may start at.
          lastRead(_mm512_set1_epi32(static_cast<int>(step * (H - 1) + 3 * W - 8))),
          // The last offset a 16-byte read may start at (negative for images of under 6 pixels).
          lastWindow(_mm512_set1_epi32(static_cast<int>(step * (H - 1) + 3 * W) - 16)) {}

    // Byte offset of sample (X, Y).
    MULTICAGE_V4 MULTICAGE_ALWAYS_INLINE __m512i offsetOf(__m512i X, __m512i Y) const {
        return _mm512_add_epi32(_mm512_mullo_epi32(Y, stepV),
                                _mm512_add_epi32(_mm512_add_epi32(X, X), X));
    }

    // Half h (pixels 8h..8h+7) of the 16: each channel's left and right samples side by side,
    // (b0 b1 g0 g1 r0 r1 0 0) per pixel, of the top (t) and bottom (u) sample rows. 8 bytes from
    // each sample row: (b, g, r) of the left and the right sample and 2 more, which may pass the
    // image's last byte only at its bottom-right pixel (that one goes the slow way). Where each
    // pair of neighbouring output pixels samples one source row at most 3 pixels apart (a smooth
    // warp: nearly always), one 16-byte load serves both (4 loads per 8 pixels and row, where a
    // gather is 8 and costs more).
    MULTICAGE_V4 MULTICAGE_ALWAYS_INLINE void samples(int h, __m512i top, bool window,
                                                      const int* offsets, __m512i& t,
                                                      __m512i& u) const {
        const __m256i topH = h ? _mm512_extracti64x4_epi64(top, 1) : _mm512_castsi512_si256(top);
        if (!window) {
            const __m256i bottomH = _mm256_add_epi32(topH, _mm512_castsi512_si256(stepV));
            t = _mm512_shuffle_epi8(_mm512_i32gather_epi64(topH, src, 1), pairs);
            u = _mm512_shuffle_epi8(_mm512_i32gather_epi64(bottomH, src, 1), pairs);
            return;
        }
        // Lane i: 16 bytes from pixel 2i's samples; pixel 2i+1's start `d` bytes later.
        const __m256i d = _mm256_sub_epi32(
            topH, _mm256_permutevar8x32_epi32(topH, _mm512_castsi512_si256(evenOfPair)));
        const __m512i control =
            _mm512_add_epi8(pairsAt0, _mm512_shuffle_epi8(_mm512_cvtepu32_epi64(d), spread));
        const uchar* o[4] = {src + offsets[8 * h], src + offsets[8 * h + 2],
                             src + offsets[8 * h + 4], src + offsets[8 * h + 6]};
        __m512i w = _mm512_castsi128_si512(load16(o[0]));
        __m512i v = _mm512_castsi128_si512(load16(o[0] + step));
        for (int i = 1; i < 4; ++i) {
            w = _mm512_inserti32x4(w, load16(o[i]), i);
            v = _mm512_inserti32x4(v, load16(o[i] + step), i);
        }
        t = _mm512_shuffle_epi8(w, control);
        u = _mm512_shuffle_epi8(v, control);
    }

    // Half h's 8 pixels from their samples t, u and fractions a, b (16 x 32 bits): (b, g, r, 0)
    // as 16-bit words, the lane's first pixel then its second.
    MULTICAGE_V4 MULTICAGE_ALWAYS_INLINE __m512i blend(int h, __m512i t, __m512i u, __m512i a,
                                                       __m512i b) const {
        const __m512i thirtyTwo64 = _mm512_set1_epi64(32), half = _mm512_set1_epi32(512);
        const __m512i aH =
            _mm512_cvtepi32_epi64(h ? _mm512_extracti64x4_epi64(a, 1) : _mm512_castsi512_si256(a));
        const __m512i bH =
            _mm512_cvtepi32_epi64(h ? _mm512_extracti64x4_epi64(b, 1) : _mm512_castsi512_si256(b));
        // Along x, in 16 bits: (32 - a) left + a right, bytes (32 - a, a) three times.
        const __m512i pairX =
            _mm512_or_si512(_mm512_sub_epi64(thirtyTwo64, aH), _mm512_slli_epi64(aH, 8));
        const __m512i wx = _mm512_or_si512(_mm512_or_si512(pairX, _mm512_slli_epi64(pairX, 16)),
                                           _mm512_slli_epi64(pairX, 32));
        const __m512i ht = _mm512_maddubs_epi16(t, wx), hb = _mm512_maddubs_epi16(u, wx);
        // Along y, in 32 bits: (32 - b) top + b bottom.
        const __m512i wy =
            _mm512_or_si512(_mm512_sub_epi64(thirtyTwo64, bH), _mm512_slli_epi64(bH, 16));
        __m512i r0 = _mm512_madd_epi16(_mm512_unpacklo_epi16(ht, hb),
                                       _mm512_shuffle_epi32(wy, _MM_PERM_AAAA));
        __m512i r1 = _mm512_madd_epi16(_mm512_unpackhi_epi16(ht, hb),
                                       _mm512_shuffle_epi32(wy, _MM_PERM_CCCC));
        r0 = _mm512_srli_epi32(_mm512_add_epi32(r0, half), 10);
        r1 = _mm512_srli_epi32(_mm512_add_epi32(r1, half), 10);
        return _mm512_packs_epi32(r0, r1);
    }

    // Pixels 0..15 of mx, my into d, when at least 8 have all their samples inside the image
    // (X in [0, W-2], Y in [0, H-2]); false (nothing written) otherwise.
    MULTICAGE_V4 MULTICAGE_ALWAYS_INLINE bool sample16(const float* mx, const float* my,
                                                       uchar* d) const {
        const __m512 scale = _mm512_set1_ps(32.f);
        const __m512i fraction = _mm512_set1_epi32(31);
        __m512i sx = _mm512_cvtps_epi32(_mm512_mul_ps(_mm512_loadu_ps(mx), scale));
        __m512i sy = _mm512_cvtps_epi32(_mm512_mul_ps(_mm512_loadu_ps(my), scale));
        __m512i X = _mm512_srai_epi32(sx, 5), Y = _mm512_srai_epi32(sy, 5);
        // W and H are below 2^15 (remapLinear), so 16-bit saturation changes no inside test.
        const __mmask16 inside =
            _mm512_cmplt_epu32_mask(X, lastX) & _mm512_cmplt_epu32_mask(Y, lastY);
        if (_mm_popcnt_u32(inside) < 8 ||
            _mm512_mask_cmpgt_epi32_mask(inside, _mm512_add_epi32(offsetOf(X, Y), stepV), lastRead))
            return false;
        // A few pixels with a sample outside (the last column of a warp that keeps the border,
        // say: one per row) are computed from the image's first pixel here, then one by one.
        const __mmask16 outside = static_cast<__mmask16>(~inside);
        if (outside) {
            sx = _mm512_maskz_mov_epi32(inside, sx), sy = _mm512_maskz_mov_epi32(inside, sy);
            X = _mm512_srai_epi32(sx, 5), Y = _mm512_srai_epi32(sy, 5);
        }
        const __m512i a = _mm512_and_si512(sx, fraction), b = _mm512_and_si512(sy, fraction);
        const __m512i top = offsetOf(X, Y);
        const __m512i prevX = _mm512_permutexvar_epi32(evenOfPair, X);
        const __m512i prevY = _mm512_permutexvar_epi32(evenOfPair, Y);
        const __mmask16 pairsOk =
            _mm512_cmpeq_epi32_mask(Y, prevY) &
            _mm512_cmple_epu32_mask(_mm512_sub_epi32(X, prevX), _mm512_set1_epi32(3)) &
            ~_mm512_cmpgt_epi32_mask(_mm512_add_epi32(top, stepV), lastWindow);
        const bool windowsOf[2] = {(pairsOk & 0xFF) == 0xFF, (pairsOk >> 8) == 0xFF};
        alignas(64) int offsets[16];
        if (windowsOf[0] || windowsOf[1]) _mm512_store_si512(offsets, top);
        __m512i words[2];
        for (int h = 0; h < 2; ++h) {
            __m512i t, u;
            samples(h, top, windowsOf[h], offsets, t, u);
            words[h] = blend(h, t, u, a, b);
        }
        // Lane i now holds pixels 2i, 2i+1, 8+2i, 9+2i as (b, g, r, 0): in order, 3 bytes each.
        const __m512i bytes =
            _mm512_permutexvar_epi32(order, _mm512_packus_epi16(words[0], words[1]));
        const __m512i packed = _mm512_permutexvar_epi32(lanes, _mm512_shuffle_epi8(bytes, keep3));
        _mm512_mask_storeu_epi32(d, 0x0FFF, packed);
        for (unsigned m = outside; m; m &= m - 1) {
            const int k = __builtin_ctz(m);
            samplePixel3(src, step, W, H, mx[k], my[k], border, d + 3 * k);
        }
        return true;
    }
};

// One output row of a 3-channel image, 16 pixels at a time where at least 8 of them have all
// their samples inside the image; other pixels one by one.
MULTICAGE_V4 void remapRow3(const uchar* src, size_t step, int W, int H, const float* mx,
                            const float* my, uchar* d, int cols, const uchar* border) {
    const Sampler3x16 sampler(src, step, W, H, border);
    int x = 0;
    for (; x + 16 <= cols; x += 16)
        if (!sampler.sample16(mx + x, my + x, d + 3 * x))
            for (int k = x; k < x + 16; ++k)
                samplePixel3(src, step, W, H, mx[k], my[k], border, d + 3 * k);
    for (; x < cols; ++x) samplePixel3(src, step, W, H, mx[x], my[x], border, d + 3 * x);
}

// remapRow3 for CPUs without AVX-512: the same arithmetic, 8 pixels at a time where at least 4
// of them have all their samples inside the image. Each 128-bit lane holds two pixels' samples,
// from one 16-byte load per sample row where the two sample one source row at most 3 pixels apart
// (a smooth warp: nearly always), else from an 8-byte load per pixel and row. The source row two
// below each group's first sample is prefetched: the next output row starts on it, and without
// that the loads stalled (docs/cpu-kernels.md).
struct Sampler3x8 {
    const uchar* src;
    size_t step;
    int W, H;
    const uchar* border;
    __m256i lastX, lastY, stepV, lastRead, lastWindow, evenOfPair;
    __m256i pairs, pairsAt0, spread, order, keep3, together;

    MULTICAGE_V3 Sampler3x8(const uchar* src_, size_t step_, int W_, int H_, const uchar* border_)
        : src(src_),
          step(step_),
          W(W_),
          H(H_),
          border(border_),
          lastX(_mm256_set1_epi32(W - 1)),
          lastY(_mm256_set1_epi32(H - 1)),
          stepV(_mm256_set1_epi32(static_cast<int>(step))),
          // The last offset an 8-byte read may start at, and a 16-byte one (negative for images
          // of under 6 pixels).
          lastRead(_mm256_set1_epi32(static_cast<int>(step * (H - 1) + 3 * W - 8))),
          lastWindow(_mm256_set1_epi32(static_cast<int>(step * (H - 1) + 3 * W) - 16)),
          evenOfPair(_mm256_setr_epi32(0, 0, 2, 2, 4, 4, 6, 6)),
          // (b0 b1 g0 g1 r0 r1 0 0) from 8 bytes of one pixel's samples (left at 0, right at 3),
          // in each 64-bit lane; for a 16-byte window, bytes 8-13 also get where the lane's second
          // pixel starts (`spread`: byte 8 of the lane to bytes 8-13; 0 in the first pixel's).
          pairs(_mm256_setr_epi8(0, 3, 1, 4, 2, 5, -1, -1, 8, 11, 9, 12, 10, 13, -1, -1, 0, 3, 1, 4,
                                 2, 5, -1, -1, 8, 11, 9, 12, 10, 13, -1, -1)),
          pairsAt0(_mm256_setr_epi8(0, 3, 1, 4, 2, 5, -1, -1, 0, 3, 1, 4, 2, 5, -1, -1, 0, 3, 1, 4,
                                    2, 5, -1, -1, 0, 3, 1, 4, 2, 5, -1, -1)),
          spread(_mm256_setr_epi8(-1, -1, -1, -1, -1, -1, -1, -1, 8, 8, 8, 8, 8, 8, -1, -1, -1, -1,
                                  -1, -1, -1, -1, -1, -1, 8, 8, 8, 8, 8, 8, -1, -1)),
          // Pixels (b, g, r, 0) in 32-bit lanes 0, 1, 4, 5 | 2, 3, 6, 7 after the pack: in order,
          // then 3 bytes each (12 per 128-bit lane), then the two lanes' 12 bytes together.
          order(_mm256_setr_epi32(0, 1, 4, 5, 2, 3, 6, 7)),
          keep3(_mm256_setr_epi8(0, 1, 2, 4, 5, 6, 8, 9, 10, 12, 13, 14, -1, -1, -1, -1, 0, 1, 2, 4,
                                 5, 6, 8, 9, 10, 12, 13, 14, -1, -1, -1, -1)),
          together(_mm256_setr_epi32(0, 1, 2, 4, 5, 6, 7, 7)) {}

    // Byte offset of sample (X, Y).
    MULTICAGE_V3 MULTICAGE_ALWAYS_INLINE __m256i offsetOf(__m256i X, __m256i Y) const {
        return _mm256_add_epi32(_mm256_mullo_epi32(Y, stepV),
                                _mm256_add_epi32(_mm256_add_epi32(X, X), X));
    }

    // Half h (pixels 4h..4h+3): (b0 b1 g0 g1 r0 r1 0 0) per pixel of the top (t) and bottom (u)
    // sample rows, from two 16-byte windows where `window`, else four 8-byte loads per row.
    MULTICAGE_V3 MULTICAGE_ALWAYS_INLINE void samples(int h, __m256i top, bool window,
                                                      const int* offsets, __m256i& t,
                                                      __m256i& u) const {
        const int* o = offsets + 4 * h;
        if (window) {
            const __m128i topH = h ? _mm256_extracti128_si256(top, 1) : _mm256_castsi256_si128(top);
            // Lane i: 16 bytes from pixel 2i's samples; pixel 2i+1's start `dd` bytes later.
            const __m128i dd =
                _mm_sub_epi32(topH, _mm_shuffle_epi32(topH, _MM_SHUFFLE(2, 2, 0, 0)));
            const __m256i control =
                _mm256_add_epi8(pairsAt0, _mm256_shuffle_epi8(_mm256_cvtepu32_epi64(dd), spread));
            const __m256i w = _mm256_inserti128_si256(_mm256_castsi128_si256(load16(src + o[0])),
                                                      load16(src + o[2]), 1);
            const __m256i v = _mm256_inserti128_si256(
                _mm256_castsi128_si256(load16(src + o[0] + step)), load16(src + o[2] + step), 1);
            t = _mm256_shuffle_epi8(w, control);
            u = _mm256_shuffle_epi8(v, control);
            return;
        }
        const __m256i w = _mm256_inserti128_si256(
            _mm256_castsi128_si256(_mm_unpacklo_epi64(load8(src + o[0]), load8(src + o[1]))),
            _mm_unpacklo_epi64(load8(src + o[2]), load8(src + o[3])), 1);
        const __m256i v = _mm256_inserti128_si256(
            _mm256_castsi128_si256(
                _mm_unpacklo_epi64(load8(src + o[0] + step), load8(src + o[1] + step))),
            _mm_unpacklo_epi64(load8(src + o[2] + step), load8(src + o[3] + step)), 1);
        t = _mm256_shuffle_epi8(w, pairs);
        u = _mm256_shuffle_epi8(v, pairs);
    }

    // Half h's 4 pixels from their samples t, u and fractions a, b (8 x 32 bits): (b, g, r, 0) as
    // 16-bit words, the lane's first pixel then its second.
    MULTICAGE_V3 MULTICAGE_ALWAYS_INLINE __m256i blend(int h, __m256i t, __m256i u, __m256i a,
                                                       __m256i b) const {
        const __m256i thirtyTwo64 = _mm256_set1_epi64x(32), half = _mm256_set1_epi32(512);
        const __m256i aH =
            _mm256_cvtepu32_epi64(h ? _mm256_extracti128_si256(a, 1) : _mm256_castsi256_si128(a));
        const __m256i bH =
            _mm256_cvtepu32_epi64(h ? _mm256_extracti128_si256(b, 1) : _mm256_castsi256_si128(b));
        // Along x, in 16 bits: (32 - a) left + a right, bytes (32 - a, a) three times.
        const __m256i pairX =
            _mm256_or_si256(_mm256_sub_epi64(thirtyTwo64, aH), _mm256_slli_epi64(aH, 8));
        const __m256i wx = _mm256_or_si256(_mm256_or_si256(pairX, _mm256_slli_epi64(pairX, 16)),
                                           _mm256_slli_epi64(pairX, 32));
        const __m256i ht = _mm256_maddubs_epi16(t, wx), hb = _mm256_maddubs_epi16(u, wx);
        // Along y, in 32 bits: (32 - b) top + b bottom.
        const __m256i wy =
            _mm256_or_si256(_mm256_sub_epi64(thirtyTwo64, bH), _mm256_slli_epi64(bH, 16));
        __m256i r0 = _mm256_madd_epi16(_mm256_unpacklo_epi16(ht, hb),
                                       _mm256_shuffle_epi32(wy, _MM_SHUFFLE(0, 0, 0, 0)));
        __m256i r1 = _mm256_madd_epi16(_mm256_unpackhi_epi16(ht, hb),
                                       _mm256_shuffle_epi32(wy, _MM_SHUFFLE(2, 2, 2, 2)));
        r0 = _mm256_srli_epi32(_mm256_add_epi32(r0, half), 10);
        r1 = _mm256_srli_epi32(_mm256_add_epi32(r1, half), 10);
        return _mm256_packs_epi32(r0, r1);
    }

    // Pixels 0..7 of mx, my into d, when at least 4 have all their samples inside the image;
    // false (nothing written) otherwise.
    MULTICAGE_V3 MULTICAGE_ALWAYS_INLINE bool sample8(const float* mx, const float* my,
                                                      uchar* d) const {
        const __m256 scale = _mm256_set1_ps(32.f);
        const __m256i minusOne = _mm256_set1_epi32(-1), fraction = _mm256_set1_epi32(31);
        __m256i sx = _mm256_cvtps_epi32(_mm256_mul_ps(_mm256_loadu_ps(mx), scale));
        __m256i sy = _mm256_cvtps_epi32(_mm256_mul_ps(_mm256_loadu_ps(my), scale));
        __m256i X = _mm256_srai_epi32(sx, 5), Y = _mm256_srai_epi32(sy, 5);
        // 0 <= X < W - 1 and 0 <= Y < H - 1; W and H are below 2^15 (remapLinear), so 16-bit
        // saturation changes no inside test.
        const __m256i insideV = _mm256_and_si256(
            _mm256_and_si256(_mm256_cmpgt_epi32(X, minusOne), _mm256_cmpgt_epi32(lastX, X)),
            _mm256_and_si256(_mm256_cmpgt_epi32(Y, minusOne), _mm256_cmpgt_epi32(lastY, Y)));
        const unsigned inside = unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(insideV)));
        const __m256i pastEnd =
            _mm256_cmpgt_epi32(_mm256_add_epi32(offsetOf(X, Y), stepV), lastRead);
        if (_mm_popcnt_u32(inside) < 4 ||
            _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_and_si256(insideV, pastEnd))) != 0)
            return false;
        // A few pixels with a sample outside are computed from the image's first pixel here,
        // then one by one.
        const unsigned outside = ~inside & 0xFFu;
        if (outside) {
            sx = _mm256_and_si256(insideV, sx), sy = _mm256_and_si256(insideV, sy);
            X = _mm256_srai_epi32(sx, 5), Y = _mm256_srai_epi32(sy, 5);
        }
        const __m256i a = _mm256_and_si256(sx, fraction), b = _mm256_and_si256(sy, fraction);
        const __m256i top = offsetOf(X, Y);
        const __m256i dx = _mm256_sub_epi32(X, _mm256_permutevar8x32_epi32(X, evenOfPair));
        const __m256i pairsOkV = _mm256_andnot_si256(
            _mm256_cmpgt_epi32(_mm256_add_epi32(top, stepV), lastWindow),
            _mm256_and_si256(_mm256_cmpeq_epi32(Y, _mm256_permutevar8x32_epi32(Y, evenOfPair)),
                             _mm256_cmpeq_epi32(_mm256_min_epu32(dx, _mm256_set1_epi32(3)), dx)));
        const unsigned pairsOk = unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(pairsOkV)));
        alignas(32) int offsets[8];
        _mm256_store_si256(reinterpret_cast<__m256i*>(offsets), top);
        _mm_prefetch(reinterpret_cast<const char*>(src + offsets[0] + 2 * step), _MM_HINT_T0);
        __m256i words[2];
        for (int h = 0; h < 2; ++h) {
            __m256i t, u;
            samples(h, top, ((pairsOk >> (4 * h)) & 0xFu) == 0xFu, offsets, t, u);
            words[h] = blend(h, t, u, a, b);
        }
        // Lane 0 now holds pixels 0, 1, 4, 5 and lane 1 pixels 2, 3, 6, 7 as (b, g, r, 0).
        const __m256i bytes =
            _mm256_permutevar8x32_epi32(_mm256_packus_epi16(words[0], words[1]), order);
        const __m256i packed =
            _mm256_permutevar8x32_epi32(_mm256_shuffle_epi8(bytes, keep3), together);
        _mm_storeu_si128(reinterpret_cast<__m128i*>(d), _mm256_castsi256_si128(packed));
        _mm_storel_epi64(reinterpret_cast<__m128i*>(d + 16), _mm256_extracti128_si256(packed, 1));
        for (unsigned m = outside; m; m &= m - 1) {
            const int k = __builtin_ctz(m);
            samplePixel3(src, step, W, H, mx[k], my[k], border, d + 3 * k);
        }
        return true;
    }
};

MULTICAGE_V3 void remapRow3Avx2(const uchar* src, size_t step, int W, int H, const float* mx,
                                const float* my, uchar* d, int cols, const uchar* border) {
    const Sampler3x8 sampler(src, step, W, H, border);
    int x = 0;
    for (; x + 8 <= cols; x += 8)
        if (!sampler.sample8(mx + x, my + x, d + 3 * x))
            for (int k = x; k < x + 8; ++k)
                samplePixel3(src, step, W, H, mx[k], my[k], border, d + 3 * k);
    for (; x < cols; ++x) samplePixel3(src, step, W, H, mx[x], my[x], border, d + 3 * x);
}

#endif

}  // namespace

namespace {

// The row sampler of the own path on this CPU (AVX-512, else AVX2), or null: cv::remap's.
using RowFn = void (*)(const uchar*, size_t, int, int, const float*, const float*, uchar*, int,
                       const uchar*);
std::atomic<RemapPath> preferredPath{RemapPath::best};

RowFn rowSampler() {
#if defined(MULTICAGE_REMAP_V4)
    if (preferredPath == RemapPath::avx2) return cpuHasX86_64_v3() ? remapRow3Avx2 : nullptr;
    return cpuHasX86_64_v4() ? remapRow3 : cpuHasX86_64_v3() ? remapRow3Avx2 : nullptr;
#endif
    return nullptr;
}

}  // namespace

bool remapLinearOwnPath(int type) {
    return type == CV_8UC3 && rowSampler() != nullptr;
}

bool preferRemapPath(RemapPath path) {
#if defined(MULTICAGE_REMAP_V4)
    if (path == RemapPath::avx2 && !cpuHasX86_64_v3()) return false;
#else
    if (path == RemapPath::avx2) return false;
#endif
    preferredPath = path;
    return true;
}

namespace {

bool ownPathFor(const Mat& src, const Mat& mapx, const Mat& mapy) {
    return remapLinearOwnPath(src.type()) && mapx.type() == CV_32F && mapy.type() == CV_32F &&
           mapx.size() == mapy.size() && src.cols < SHRT_MAX && src.rows < SHRT_MAX &&
           src.cols >= 2 && src.rows >= 2 && src.step < size_t(INT_MAX) / 4 &&
           src.step * src.rows < size_t(INT_MAX) / 2;
}

}  // namespace

void remapLinearRows(const Mat& src, Mat& dst, const Mat& mapx, const Mat& mapy,
                     const Scalar& border, int y0, int y1) {
    CV_Assert(dst.size() == mapx.size() && dst.type() == src.type() && dst.data != src.data);
    CV_Assert(0 <= y0 && y0 <= y1 && y1 <= dst.rows);
    if (y0 == y1) return;
    if (!ownPathFor(src, mapx, mapy)) {
        Mat rows = dst.rowRange(y0, y1);
        remap(src, rows, mapx.rowRange(y0, y1), mapy.rowRange(y0, y1), INTER_LINEAR,
              BORDER_CONSTANT, border);
        return;
    }
    const RowFn sampleRow = rowSampler();
    uchar cval[4];
    for (int k = 0; k < 4; ++k) cval[k] = saturate_cast<uchar>(border[k]);
    for (int y = y0; y < y1; ++y)
        sampleRow(src.data, src.step, src.cols, src.rows, mapx.ptr<float>(y), mapy.ptr<float>(y),
                  dst.ptr(y), dst.cols, cval);
}

void remapLinear(const Mat& src, OutputArray dstOut, const Mat& mapx, const Mat& mapy,
                 const Scalar& border) {
    if (!ownPathFor(src, mapx, mapy)) {
        remap(src, dstOut, mapx, mapy, INTER_LINEAR, BORDER_CONSTANT, border);
        return;
    }
    CV_Assert(dstOut.getObj() != &src);
    dstOut.create(mapx.size(), src.type());
    Mat dst = dstOut.getMat();
    parallel_for_(
        Range(0, dst.rows),
        [&](const Range& r) { remapLinearRows(src, dst, mapx, mapy, border, r.start, r.end); },
        std::max(1.0, dst.rows / 16.0));
}

}  // namespace multicage
}  // namespace cv

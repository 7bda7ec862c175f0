// Compiled for AVX-512, AVX2 and the baseline (MULTICAGE_CPU_CLONES), with fused multiply-add
// off: the baseline (SSE2) has none, and the draws must not depend on the CPU.
#include "fan_sums.hpp"

#include <opencv2/multicage/internal/cpu_dispatch.hpp>

namespace cv {
namespace multicage {

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC push_options
#pragma GCC optimize("fp-contract=off")
#elif defined(__clang__)
#pragma clang fp contract(off)
#endif
namespace {
MULTICAGE_ALWAYS_INLINE void accumulateFanSumsKernel(const double* const* rows, const double* dx,
                                                     const double* dy, int moved, int count,
                                                     double* __restrict sx, double* __restrict sy) {
    int q = 0;
    // Four vertices per pass over the sums (each sum still adds its terms one at a time, in
    // vertex order).
    for (; q + 4 <= moved; q += 4) {
        const double* __restrict c0 = rows[q];
        const double* __restrict c1 = rows[q + 1];
        const double* __restrict c2 = rows[q + 2];
        const double* __restrict c3 = rows[q + 3];
        const double x0 = dx[q], x1 = dx[q + 1], x2 = dx[q + 2], x3 = dx[q + 3];
        const double y0 = dy[q], y1 = dy[q + 1], y2 = dy[q + 2], y3 = dy[q + 3];
        for (int i = 0; i < count; ++i) {
            double x = sx[i], y = sy[i];
            x += c0[i] * x0, y += c0[i] * y0;
            x += c1[i] * x1, y += c1[i] * y1;
            x += c2[i] * x2, y += c2[i] * y2;
            x += c3[i] * x3, y += c3[i] * y3;
            sx[i] = x, sy[i] = y;
        }
    }
    for (; q < moved; ++q) {
        const double* __restrict c = rows[q];
        const double x0 = dx[q], y0 = dy[q];
        for (int i = 0; i < count; ++i) sx[i] += c[i] * x0, sy[i] += c[i] * y0;
    }
}
}  // namespace

MULTICAGE_CPU_CLONES(void, accumulateFanSums,
                     (const double* const* rows, const double* dx, const double* dy, int moved,
                      int count, double* __restrict sx, double* __restrict sy),
                     (rows, dx, dy, moved, count, sx, sy))
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC pop_options
#elif defined(__clang__)
#pragma clang fp contract(on)
#endif

}  // namespace multicage
}  // namespace cv

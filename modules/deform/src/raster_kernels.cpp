// The baseline triangle kernel: one triangle at a time, a span per row (AVX2 and baseline clones).

// First, before any other header (clang-format would sort it among them): the rasteriser's
// floating-point options.
// clang-format off
#include "raster_options.hpp"
// clang-format on

#include "raster_kernels.hpp"

#include <atomic>

namespace cv {
namespace multicage {
namespace raster {

namespace {

// Writes, for every pixel centre of rows [y0, y1) inside triangle t (deformed), the matching
// point of its rest triangle. Inside a triangle the inverse map is affine, so each row is a
// span [xl, xr] found from the three barycentric edge functions, filled by a straight loop.
// Edges are inclusive with a small tolerance so that neighbouring triangles leave no crack;
// on a shared edge both write almost the same value.
inline void drawTriangle(const TriangleSetup& s, int t, int y0, int y1, Point2f lo, Point2f hi,
                         Mat& mapx, Mat& mapy) {
    int ya, yb, xa, xb;
    if (!triangleBounds(s, t, y0, y1, mapx.cols, ya, yb, xa, xb)) return;
    const double mxx = s.mxx[t], mxy = s.mxy[t], mx0 = s.mx0[t];
    const double myx = s.myx[t], myy = s.myy[t], my0 = s.my0[t];
    for (int y = ya; y <= yb; ++y) {
        int xl, xr;
        if (!rowSpan(s, t, y, xa, xb, xl, xr)) continue;
        float* mx = mapx.ptr<float>(y);
        float* my = mapy.ptr<float>(y);
        const double bx = mxy * y + mx0, by = myy * y + my0;
        for (int x = xl; x <= xr; ++x) {
            mx[x] = std::min(std::max(static_cast<float>(mxx * x + bx), lo.x), hi.x);
            my[x] = std::min(std::max(static_cast<float>(myx * x + by), lo.y), hi.y);
        }
    }
}

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

}  // namespace

namespace {
std::atomic<bool> baselinePreferred{false};
}  // namespace

void preferBaselineKernel(bool baseline) {
    baselinePreferred = baseline;
}

DrawCellRowFn cellRowKernel() {
    if (baselinePreferred) return drawCellRow;
    static const bool avx512 = haveAvx512Kernel() && __builtin_cpu_supports("avx512f") &&
                               __builtin_cpu_supports("avx512vl") &&
                               __builtin_cpu_supports("avx512dq") &&
                               __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("bmi2");
    return avx512 ? drawCellRowAvx512 : drawCellRow;
}

}  // namespace raster
}  // namespace multicage
}  // namespace cv

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
    // Bounds are clamped in double before they become ints: a pose may put nodes 1e30 px
    // away or at infinity, and converting such a value to int is undefined (fuzz_deform).
    // The negated tests also drop NaN coordinates.
    const double minY = s.minY[t], maxY = s.maxY[t];
    if (!(maxY >= y0 && minY <= y1 - 1)) return;
    const int ya = static_cast<int>(std::ceil(std::max(minY, double(y0))));
    const int yb = static_cast<int>(std::floor(std::min(maxY, double(y1 - 1))));
    if (ya > yb) return;
    const double minX = s.minX[t], maxX = s.maxX[t];
    if (!(maxX >= 0 && minX <= mapx.cols - 1)) return;
    const int xa = static_cast<int>(std::ceil(std::max(minX, 0.0)));
    const int xb = static_cast<int>(std::floor(std::min(maxX, double(mapx.cols - 1))));
    if (xa > xb) return;
    const double area = s.area[t];
    // Degenerate, NaN, or infinite (a node at infinity: the affine map would be NaN).
    if (!(std::abs(area) > 1e-12) || !std::isfinite(area)) return;
    const double ax[3] = {s.ax[0][t], s.ax[1][t], s.ax[2][t]};
    const double ay[3] = {s.ay[0][t], s.ay[1][t], s.ay[2][t]};
    const double a0[3] = {s.a0[0][t], s.a0[1][t], s.a0[2][t]};
    const double invAx[3] = {s.invAx[0][t], s.invAx[1][t], s.invAx[2][t]};
    const double mxx = s.mxx[t], mxy = s.mxy[t], mx0 = s.mx0[t];
    const double myx = s.myx[t], myy = s.myy[t], my0 = s.my0[t];
    constexpr double eps = -1e-7;
    for (int y = ya; y <= yb; ++y) {
        double left = xa, right = xb;
        for (int i = 0; i < 3; ++i) {  // l_i(x) = ax x + c >= eps
            // Selects, not branches (a triangle is a few rows, so the branches of each edge's
            // side mispredict); the same values: an edge bounds the left (ax > 0), the right
            // (ax < 0), or, neither, empties the row when c < eps (NaN ax included).
            const double c = a0[i] + ay[i] * y;
            const double v = (eps - c) * invAx[i];
            left = std::max(left, ax[i] > 0 ? v : -INFINITY);
            right = std::min(right, ax[i] < 0 ? v : INFINITY);
            right = !(ax[i] > 0) && !(ax[i] < 0) && c < eps ? -1.0 : right;
        }
        if (!(left <= right)) continue;  // empty span (or NaN) before converting to int
        const int xl = static_cast<int>(std::ceil(left)), xr = static_cast<int>(std::floor(right));
        if (xl > xr) continue;
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

// First, before any other header (clang-format would sort it among them): the rasteriser's
// floating-point options, so that the AVX2 and the portable interpolation give the same bits.
// clang-format off
#include "raster_options.hpp"
// clang-format on

#include "mesh_lattice.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <opencv2/core/utility.hpp>
#include <opencv2/multicage/internal/cpu_dispatch.hpp>
#include <vector>
#if defined(__GNUC__) && defined(__x86_64__)
#include <immintrin.h>
#endif

namespace cv {
namespace multicage {
namespace raster {

Lattice Lattice::of(Size size, int step) {
    CV_Assert(step >= 2 && size.width >= 2 && size.height >= 2);
    // Intervals of at most `step` pixels, as many as that takes, spread evenly between the border
    // pixels' centres: the lattice is then a uniformly scaled pixel grid, which the pull kernel
    // walks as it walks pixels.
    const int ix = (size.width - 2) / step + 1, iy = (size.height - 2) / step + 1;
    return {Size(ix + 1, iy + 1),
            Point2d(double(size.width - 1) / ix, double(size.height - 1) / iy)};
}

bool latticeFits(const PullMesh& mesh, Size size, int step) {
    if (step < 2 || size.width < 2 || size.height < 2 || mesh.cols < 2 || mesh.rows < 2)
        return false;
    // The frame TL, TR, BR, BL turns as the rest grid does, so a point is inside where it lies
    // left of every edge (cross(edge, point - start) > 0 in the y-down image); the four corner
    // pixels inside (by a hundredth of a pixel, well above the pull's frame margin) put every
    // pixel centre inside.
    const Point2f* P = mesh.nodes;
    const size_t C = mesh.cols, last = size_t(mesh.rows - 1) * C;
    const Point2d q[4] = {Point2d(P[0]), Point2d(P[C - 1]), Point2d(P[last + C - 1]),
                          Point2d(P[last])};
    const Point2d corners[4] = {{0, 0},
                                {size.width - 1.0, 0},
                                {size.width - 1.0, size.height - 1.0},
                                {0, size.height - 1.0}};
    constexpr double kRoom = 0.01;  // px
    for (int i = 0; i < 4; ++i) {
        const Point2d e = q[(i + 1) % 4] - q[i];
        const double length = std::sqrt(e.dot(e));
        for (const Point2d& p : corners)
            if (!(e.cross(p - q[i]) > kRoom * length)) return false;  // (NaN: false)
    }
    return true;
}

bool pullLattice(const PullMesh& mesh, const Lattice& lattice, Mat& lx, Mat& ly) {
    // Lattice point (i, j) is pixel (i, j) of the pull, at (i spacing.x, j spacing.y) in the
    // output: the pull walks to the triangle holding it and returns its rest point.
    PullMesh m = mesh;
    m.spacing = Point2f(float(lattice.spacing.x), float(lattice.spacing.y));
    lx.create(lattice.points, CV_32F);
    ly.create(lattice.points, CV_32F);
    const int runs = (lattice.points.height + kPullRun - 1) / kPullRun;
    std::atomic<bool> settled{true};
    parallel_for_(Range(0, runs), [&](const Range& r) {
        for (int run = r.start; run < r.end && settled; ++run) {
            const int y0 = run * kPullRun, y1 = std::min(y0 + kPullRun, lattice.points.height);
            if (!pullRows(m, y0, y1, lx, ly)) settled = false;
        }
    });
    return settled;
}

namespace {

// The lattice row at some y (values r, differences d = r[i + 1] - r[i], padded by 8) along the
// output row: out[x] = r[i] + w[x] d[i], i = left[x].
void expandRow(const float* r, const float* d, const int* left, const float* weight, int W,
               float* out) {
    for (int x = 0; x < W; ++x) out[x] = r[left[x]] + weight[x] * d[left[x]];
}

#if defined(__GNUC__) && defined(__x86_64__)
// The same 8 pixels at a time: 8 neighbouring pixels lie in at most 8 lattice intervals (the
// spacing is at least 1 px), so their values come from one load of 8 and a permutation in
// registers (`local`: each pixel's interval less the first's), not from 8 loads.
MULTICAGE_TARGET_X86_64_V3 void expandRowAvx2(const float* r, const float* d, const int* left,
                                              const float* weight, const int* local, int W,
                                              float* out) {
    int x = 0;
    for (; x + 8 <= W; x += 8) {
        const __m256i idx = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(local + x));
        const __m256 rv = _mm256_permutevar8x32_ps(_mm256_loadu_ps(r + left[x]), idx);
        const __m256 dv = _mm256_permutevar8x32_ps(_mm256_loadu_ps(d + left[x]), idx);
        _mm256_storeu_ps(out + x,
                         _mm256_add_ps(rv, _mm256_mul_ps(_mm256_loadu_ps(weight + x), dv)));
    }
    expandRow(r, d, left + x, weight + x, W - x, out + x);
}
#endif

}  // namespace

LatticeColumns LatticeColumns::of(const Lattice& lattice, int width) {
    LatticeColumns c;
    const int last = lattice.points.width - 2;
    c.left.resize(width), c.local.resize(width), c.weight.resize(width);
    for (int x = 0; x < width; ++x) {
        const double t = x / lattice.spacing.x;
        const int i = std::min(static_cast<int>(t), last);
        c.left[x] = i, c.weight[x] = float(t - i);
        c.local[x] = i - c.left[x - x % 8];
    }
    return c;
}

void interpolateRows(const Lattice& lattice, const LatticeColumns& columns, const Mat& lx,
                     const Mat& ly, int y0, int y1, Mat& mapx, Mat& mapy) {
    const int W = mapx.cols, cols = lattice.points.width;
    CV_Assert(columns.left.size() == size_t(W));
    const int *left = columns.left.data(), *local = columns.local.data();
    const float* weight = columns.weight.data();
    thread_local std::vector<float> rx, dx, ry, dy;
    // (padded: a vector of 8 reads up to 8 values from its first pixel's interval)
    for (auto* v : {&rx, &dx, &ry, &dy}) v->assign(cols + 8, 0.f);
#if defined(__GNUC__) && defined(__x86_64__)
    const bool avx2 = cpuHasX86_64_v3();
#endif
    for (int y = y0; y < y1; ++y) {
        const double t = y / lattice.spacing.y;
        const int j = std::min(static_cast<int>(t), lattice.points.height - 2);
        const float f = float(t - j);
        const float *ax = lx.ptr<float>(j), *bx = lx.ptr<float>(j + 1);
        const float *ay = ly.ptr<float>(j), *by = ly.ptr<float>(j + 1);
        // The lattice row at y, and its differences along x.
        for (int i = 0; i < cols; ++i)
            rx[i] = ax[i] + f * (bx[i] - ax[i]), ry[i] = ay[i] + f * (by[i] - ay[i]);
        for (int i = 0; i + 1 < cols; ++i) dx[i] = rx[i + 1] - rx[i], dy[i] = ry[i + 1] - ry[i];
        float* mx = mapx.ptr<float>(y);
        float* my = mapy.ptr<float>(y);
#if defined(__GNUC__) && defined(__x86_64__)
        if (avx2) {
            expandRowAvx2(rx.data(), dx.data(), left, weight, local, W, mx);
            expandRowAvx2(ry.data(), dy.data(), left, weight, local, W, my);
            continue;
        }
#endif
        expandRow(rx.data(), dx.data(), left, weight, W, mx);
        expandRow(ry.data(), dy.data(), left, weight, W, my);
    }
}

}  // namespace raster
}  // namespace multicage
}  // namespace cv

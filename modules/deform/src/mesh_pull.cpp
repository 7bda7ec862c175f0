// The pull kernel: inverse maps found pixel by pixel, each pixel walking to its triangle; what
// its two kernels (pull_avx512.cpp, pull_avx2.cpp) share, and the choice between them.
//
// Where the mesh folds nowhere a pixel lies in exactly one triangle (pullable), so it can be
// found from the pixel instead of drawing every triangle: at grid step 1, where a cell covers
// about a pixel, that is several times faster than the raster kernel. The cost is per pixel
// whatever the cell size, so at grid steps above 2 the raster is faster (RasterMesh::draw).

// First, before any other header (clang-format would sort it among them): the rasteriser's
// floating-point options.
// clang-format off
#include "raster_options.hpp"
// clang-format on

#include "mesh_pull.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <opencv2/core/utility.hpp>
#include <opencv2/multicage/internal/cpu_dispatch.hpp>

#include "pull_kernels.hpp"

namespace cv {
namespace multicage {
namespace raster {

namespace {

// The ring's corner nodes TL, TR, BR, BL: the frame the mesh's outer boundary runs along.
std::array<Point2d, 4> ringCorners(const PullMesh& m) {
    const Point2f* P = m.nodes;
    const size_t C = m.cols, last = size_t(m.rows - 1) * C;
    return {Point2d(P[0]), Point2d(P[C - 1]), Point2d(P[last + C - 1]), Point2d(P[last])};
}

// Whether this build has a pull kernel at all (x86-64, GCC or clang).
bool pullBuilt() {
    return haveAvx512Pull() || haveAvx2Pull();
}

// The fold check of rows [ey0, ey1) one cell at a time, where the CPU has neither kernel (so
// only the baseline runs it: no copies per level).
bool positiveRowsPortable(const PullMesh& m, int ey0, int ey1) {
    const Point2f* P = m.nodes;
    const size_t C = m.cols;
    for (int ey = std::max(ey0, 0); ey < std::min(ey1, m.rows - 1); ++ey)
        if (!cellsPositive(P + size_t(ey) * C, P + size_t(ey + 1) * C, 0, m.cols - 1)) return false;
    return true;
}

enum class PullKernel { none, avx2, avx512 };
std::atomic<bool> avx2Preferred{false};

// The kernel this CPU's level runs (internal/cpu_dispatch.hpp), or AVX2 where a test asks.
PullKernel pullKernel() {
    static const PullKernel best = haveAvx512Pull() && cpuHasX86_64_v4() ? PullKernel::avx512
                                   : haveAvx2Pull() && cpuHasX86_64_v3() ? PullKernel::avx2
                                                                         : PullKernel::none;
    return best == PullKernel::avx512 && avx2Preferred ? PullKernel::avx2 : best;
}

}  // namespace

// The frame's edges (the ring's outer boundary) as lines.
FrameLines frameLines(const PullMesh& m) {
    FrameLines frame;
    const std::array<Point2d, 4> q = ringCorners(m);
    for (int i = 0; i < 4; ++i) {
        const Point2d e = q[(i + 1) % 4] - q[i];
        const double len = std::sqrt(e.dot(e));
        const double nx = -e.y / len, ny = e.x / len;
        frame.nx[i] = float(nx), frame.ny[i] = float(ny);
        frame.c[i] = float(-(nx * q[i].x + ny * q[i].y));
    }
    return frame;
}

bool frameConvex(const PullMesh& m) {
    if (!pullBuilt()) return false;
    if (m.cols < 2 || m.rows < 2) return false;
    // The ring's outer boundary: the frame quadrilateral TL, TR, BR, BL, convex and turning as
    // the rest grid does (cross((1,0), (0,1)) > 0 in the y-down image).
    const std::array<Point2d, 4> q = ringCorners(m);
    for (int i = 0; i < 4; ++i) {
        const Point2d u = q[(i + 1) % 4] - q[i], v = q[(i + 2) % 4] - q[(i + 1) % 4];
        if (!(u.x * v.y - u.y * v.x > 0)) return false;
    }
    return true;
}

bool pullable(const PullMesh& m) {
    if (!frameConvex(m)) return false;
    // Every triangle, in parallel. (A pose drawn by RasterMesh::pose is checked while
    // Binding::apply writes its nodes instead, block by block of rows in cache.)
    std::atomic<bool> good{true};
    parallel_for_(
        Range(0, m.rows - 1),
        [&](const Range& r) {
            if (good && !positiveRows(m, r.start, r.end)) good = false;
        },
        std::max(1.0, (m.rows - 1) / 64.0));
    return good;
}

bool positiveRows(const PullMesh& m, int ey0, int ey1) {
    switch (pullKernel()) {
        case PullKernel::avx512:
            return positiveRowsAvx512(m, ey0, ey1);
        case PullKernel::avx2:
            return positiveRowsAvx2(m, ey0, ey1);
        default:
            return pullBuilt() && positiveRowsPortable(m, ey0, ey1);
    }
}

bool pullRows(const PullMesh& m, int y0, int y1, Mat& mapx, Mat& mapy) {
    switch (pullKernel()) {
        case PullKernel::avx512:
            return pullRowsAvx512(m, y0, y1, mapx, mapy);
        case PullKernel::avx2:
            return pullRowsAvx2(m, y0, y1, mapx, mapy);
        default:
            return false;
    }
}

bool havePullKernel() {
    return pullKernel() != PullKernel::none;
}

const char* pullKernelName() {
    static const char* const names[] = {"none", "AVX2", "AVX-512"};
    return names[int(pullKernel())];
}

void preferAvx2Pull(bool avx2) {
    avx2Preferred = avx2;
}

}  // namespace raster
}  // namespace multicage
}  // namespace cv

// The baseline triangle kernel: one triangle at a time, a span per row (a copy per CPU level).

// First, before any other header (clang-format would sort it among them): the rasteriser's
// floating-point options.
// clang-format off
#include "raster_options.hpp"
// clang-format on

#include "raster_kernels.hpp"

#include <atomic>
#include <opencv2/multicage/internal/cpu_dispatch.hpp>

namespace cv {
namespace multicage {
namespace raster {

namespace {

MULTICAGE_ALWAYS_INLINE void drawCellRowKernel(const Point2f* p0, const Point2f* p1,
                                               const Point2f* r0, const Point2f* r1, int cells,
                                               int y0, int y1, Point2f lo, Point2f hi, Mat& mapx,
                                               Mat& mapy, TriangleSetup& s) {
    for (int first = 0; first < cells; first += kRunCells) {
        const int n = std::min(kRunCells, cells - first);
        prepareRun(p0, p1, r0, r1, first, n, s);
        for (int t = 0; t < 2 * n; ++t) drawTriangle(s, t, y0, y1, lo, hi, mapx, mapy);
    }
}

MULTICAGE_CPU_CLONES(void, drawCellRow,
                     (const Point2f* p0, const Point2f* p1, const Point2f* r0, const Point2f* r1,
                      int cells, int y0, int y1, Point2f lo, Point2f hi, Mat& mapx, Mat& mapy,
                      TriangleSetup& s),
                     (p0, p1, r0, r1, cells, y0, y1, lo, hi, mapx, mapy, s))

DrawCellRowFn bestKernel() {
    if (haveAvx512Kernel() && cpuHasX86_64_v4()) return drawCellRowAvx512;
    if (haveAvx2Kernel() && cpuHasX86_64_v3()) return drawCellRowAvx2;
    return drawCellRow;
}

std::atomic<DrawCellRowFn> preferred{nullptr};

}  // namespace

bool preferRasterKernel(RasterKernel kernel) {
    switch (kernel) {
        case RasterKernel::best:
            preferred = nullptr;
            return true;
        case RasterKernel::avx2:
            if (!haveAvx2Kernel() || !cpuHasX86_64_v3()) return false;
            preferred = drawCellRowAvx2;
            return true;
        case RasterKernel::baseline:
            preferred = drawCellRow;
            return true;
    }
    return false;
}

DrawCellRowFn cellRowKernel() {
    if (const DrawCellRowFn k = preferred.load()) return k;
    static const DrawCellRowFn best = bestKernel();
    return best;
}

}  // namespace raster
}  // namespace multicage
}  // namespace cv

// The CPU backend's kernels side by side, one thread, in the same run: the raster's triangle
// kernels (this CPU's own, AVX2, the baseline), the bilinear sampler's paths (own, AVX2,
// cv::remap) and the pull (this CPU's own, AVX2). A kernel this CPU cannot run is skipped with a
// message. White-box: it reaches the deform module's private headers.
//
//   bench_kernels --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
//
// What it times: rasterizeMaps of a smooth 512x512 mesh (grid steps 4 and 1), a smooth 512x512
// warp of a BGR image, and the pull of a smooth 1024x768 mesh of grid step 1.
#include <benchmark/benchmark.h>

#include <opencv2/imgproc.hpp>
#include <opencv2/multicage.hpp>

#include "mesh_pull.hpp"
#include "raster_kernels.hpp"
#include "remap_linear.hpp"

namespace {

using namespace cv;
using namespace cv::multicage;

// A smooth wave of amplitude `amplitude` px, zero on the image frame.
Point2f wave(float x, float y, Size size, float amplitude) {
    const float env = std::sin(float(CV_PI) * x / (size.width - 1)) *
                      std::sin(float(CV_PI) * y / (size.height - 1));
    return {amplitude * env * std::sin(y * 0.013f), 0.8f * amplitude * env * std::sin(x * 0.011f)};
}

void BM_Raster(benchmark::State& state) {
    const auto kernel = static_cast<raster::RasterKernel>(state.range(0));
    const int step = static_cast<int>(state.range(1));
    const Size size(512, 512);
    const Size grid = gridSizeFor(size, step);
    Mat positions(grid, CV_32FC2), rest(grid, CV_32FC2);
    for (int gy = 0; gy < grid.height; ++gy)
        for (int gx = 0; gx < grid.width; ++gx) {
            const Point2f r(float(std::min(gx * step, size.width - 1)),
                            float(std::min(gy * step, size.height - 1)));
            rest.at<Point2f>(gy, gx) = r;
            positions.at<Point2f>(gy, gx) = r + wave(r.x, r.y, size, 9.f);
        }
    if (!raster::preferRasterKernel(kernel)) {
        state.SkipWithError("this CPU or build has no such kernel");
        return;
    }
    setNumThreads(1);
    Mat mapx, mapy;
    for (auto _ : state) {
        rasterizeMaps(positions, rest, size, mapx, mapy);
        benchmark::DoNotOptimize(mapx.data);
    }
    raster::preferRasterKernel(raster::RasterKernel::best);
}

// Paths: 0 this CPU's own, 1 AVX2, 2 cv::remap.
void BM_Sample(benchmark::State& state) {
    const int path = static_cast<int>(state.range(0));
    const Size size(512, 512);
    Mat src(size, CV_8UC3);
    randu(src, 0, 256);
    Mat mapx(size, CV_32F), mapy(size, CV_32F);
    for (int y = 0; y < size.height; ++y)
        for (int x = 0; x < size.width; ++x) {
            const Point2f d = wave(float(x), float(y), size, 9.f);
            mapx.at<float>(y, x) = x + d.x, mapy.at<float>(y, x) = y + d.y;
        }
    if (path < 2 && (!preferRemapPath(path == 0 ? RemapPath::best : RemapPath::avx2) ||
                     !remapLinearOwnPath(CV_8UC3))) {
        preferRemapPath(RemapPath::best);
        state.SkipWithError("this CPU or build has no such path");
        return;
    }
    setNumThreads(1);
    Mat out;
    for (auto _ : state) {
        if (path == 2)
            remap(src, out, mapx, mapy, INTER_LINEAR, BORDER_CONSTANT, Scalar(1, 2, 3));
        else
            remapLinear(src, out, mapx, mapy, Scalar(1, 2, 3));
        benchmark::DoNotOptimize(out.data);
    }
    preferRemapPath(RemapPath::best);
}

// Kernels: 0 this CPU's own, 1 AVX2.
void BM_Pull(benchmark::State& state) {
    const bool avx2 = state.range(0) == 1;
    const Size size(1024, 768);
    const int step = 1;
    const Size grid = gridSizeFor(size, step);
    // RasterMesh's layout: the grid inside a ring of nodes on the frame.
    Mat nodes(grid.height + 2, grid.width + 2, CV_32FC2);
    for (int r = 0; r < nodes.rows; ++r)
        for (int c = 0; c < nodes.cols; ++c) {
            const int gx = std::min(std::max(c - 1, 0), grid.width - 1);
            const int gy = std::min(std::max(r - 1, 0), grid.height - 1);
            float x = float(std::min(gx * step, size.width - 1));
            float y = float(std::min(gy * step, size.height - 1));
            const bool ring = r == 0 || c == 0 || r == nodes.rows - 1 || c == nodes.cols - 1;
            const Point2f d = ring ? Point2f() : wave(x, y, size, 6.f);
            if (c == 0) x = -0.5f;
            if (c == nodes.cols - 1) x = size.width - 0.5f;
            if (r == 0) y = -0.5f;
            if (r == nodes.rows - 1) y = size.height - 0.5f;
            nodes.at<Point2f>(r, c) = Point2f(x, y) + d;
        }
    const raster::PullMesh mesh{nodes.ptr<Point2f>(),
                                nodes.cols,
                                nodes.rows,
                                grid,
                                float(step),
                                Point2f(0, 0),
                                Point2f(size.width - 1.f, size.height - 1.f)};
    raster::preferAvx2Pull(avx2);
    if (!raster::havePullKernel() || (avx2 && std::string(raster::pullKernelName()) != "AVX2") ||
        !raster::pullable(mesh)) {
        raster::preferAvx2Pull(false);
        state.SkipWithError("this CPU or build has no such kernel");
        return;
    }
    Mat mapx(size, CV_32F), mapy(size, CV_32F);
    for (auto _ : state) {
        bool settled = true;
        for (int y = 0; y < size.height; y += raster::kPullRun)
            settled &=
                raster::pullRows(mesh, y, std::min(size.height, y + raster::kPullRun), mapx, mapy);
        if (!settled) state.SkipWithError("a walk did not settle");
        benchmark::DoNotOptimize(mapx.data);
    }
    state.SetLabel(raster::pullKernelName());
    raster::preferAvx2Pull(false);
}

}  // namespace

BENCHMARK(BM_Raster)
    ->ArgNames({"kernel", "step"})
    ->ArgsProduct({{int(raster::RasterKernel::best), int(raster::RasterKernel::avx2),
                    int(raster::RasterKernel::baseline)},
                   {4, 1}})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Sample)->ArgName("path")->DenseRange(0, 2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Pull)->ArgName("kernel")->DenseRange(0, 1)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();

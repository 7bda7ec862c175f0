// Speed of proposeMulticage on a 1024x768 photograph (fruits.jpg and smarties.png scaled up),
// one benchmark per method. Built with the tools (apps/bench), run by hand:
//   bench_propose --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/multicage.hpp>

namespace {

cv::Mat sample1024(const char* name) {
    cv::Mat img = cv::imread(std::string(MULTICAGE_SAMPLES_DIR) + "/" + name, cv::IMREAD_COLOR);
    if (img.empty()) throw std::runtime_error(std::string("cannot read ") + name);
    cv::resize(img, img, cv::Size(1024, 768), 0, 0, cv::INTER_CUBIC);
    return img;
}

void propose(benchmark::State& state, const char* image, int method) {
    const cv::Mat img = sample1024(image);
    cv::multicage::ProposeParams params;
    params.method = method;
    int vertices = 0;
    for (auto _ : state) {
        const cv::multicage::Multicage cage = cv::multicage::proposeMulticage(img, params);
        vertices = cage.vertexCount();
        benchmark::DoNotOptimize(vertices);
    }
    state.counters["vertices"] = vertices;
}

void segmentOnly(benchmark::State& state, const char* image, int method) {
    const cv::Mat img = sample1024(image);
    cv::multicage::ProposeParams params;
    params.method = method;
    cv::Mat mask;
    for (auto _ : state) cv::multicage::proposeSegmentation(img, mask, params);
}

// Issue 16: faces on messi5.jpg scaled to 1024x768 (cascades loaded before timing). The face
// search runs beside the segmentation and on several threads: wall time (UseRealTime) is the
// figure; the CPU column is the calling thread only.
void detectFacesOnly(benchmark::State& state) {
    const cv::Mat img = sample1024("messi5.jpg");
    cv::multicage::detectFaces(img);
    for (auto _ : state) benchmark::DoNotOptimize(cv::multicage::detectFaces(img).size());
}

void proposeProtected(benchmark::State& state, int detector) {
    const cv::Mat img = sample1024("messi5.jpg");
    cv::multicage::ProposeParams params;
    params.protect = detector;
    if (detector != cv::multicage::PROTECT_SALIENCY) cv::multicage::detectFaces(img);
    int vertices = 0;
    for (auto _ : state) {
        vertices = cv::multicage::proposeProtectedMulticage(img, params).vertexCount();
        benchmark::DoNotOptimize(vertices);
    }
    state.counters["vertices"] = vertices;
}

using namespace cv::multicage;
BENCHMARK(detectFacesOnly)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(proposeProtected, faces_messi, PROTECT_FACES)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(proposeProtected, all_messi, PROTECT_ALL)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(proposeProtected, saliency_messi, PROTECT_SALIENCY)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(propose, threshold_smarties, "smarties.png", PROPOSE_THRESHOLD)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(propose, adaptive_smarties, "smarties.png", PROPOSE_ADAPTIVE)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(propose, saliency_fruits, "fruits.jpg", PROPOSE_SALIENCY)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(propose, spectral_fruits, "fruits.jpg", PROPOSE_SPECTRAL_RESIDUAL)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(propose, grabcut_fruits, "fruits.jpg", PROPOSE_GRABCUT)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(propose, auto_butterfly, "butterfly.jpg", PROPOSE_AUTO)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(segmentOnly, saliency_fruits, "fruits.jpg", PROPOSE_SALIENCY)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(segmentOnly, grabcut_fruits, "fruits.jpg", PROPOSE_GRABCUT)
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();

// The proposal's GrabCut (modules/propose/src/grabcut.hpp) against cv::grabCut in the same run,
// one thread, on benchmark photos at GrabCut's working size (240 px): the same labels (tests
// GrabCut.*), so only the time differs. White-box: it reaches the propose module's private
// headers.
//
//   bench_grabcut --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
//
// What it times: five iterations from the frame inward (the start of subject.cpp, where
// GrabCut runs until its labels settle) and two from a rectangle (the person prior's count).
#include <benchmark/benchmark.h>

#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "grabcut.hpp"

namespace {

using namespace cv;

const char* const kPhotos[] = {"baboon", "squirrel", "messi5"};

Mat photo240(int i) {
    const std::string path =
        std::string(MULTICAGE_SAMPLES_DIR) + "/propose_bench/" + kPhotos[i] + ".jpg";
    const Mat img = imread(path, IMREAD_COLOR);
    if (img.empty()) throw std::runtime_error("cannot read " + path);
    Mat small;
    const double s = 240.0 / std::max(img.cols, img.rows);
    resize(img, small, Size(), s, s, INTER_AREA);
    return small;
}

Mat start(Size size, bool fromFrame) {
    Mat labels(size, CV_8U, Scalar(GC_BGD));
    const int b = cvRound(0.03 * std::max(size.width, size.height));
    const Rect inner =
        fromFrame ? Rect(b, b, size.width - 2 * b, size.height - 2 * b)
                  : Rect(size.width / 5, size.height / 6, size.width / 2, size.height * 2 / 3);
    labels(inner).setTo(GC_PR_FGD);
    return labels;
}

// range(0): photo; range(1): 1 from the frame (5 iterations), 0 from a rectangle (2).
void BM_GrabCut(benchmark::State& state, bool ours) {
    setNumThreads(1);
    const Mat img = photo240(static_cast<int>(state.range(0)));
    const bool fromFrame = state.range(1) != 0;
    const int iterations = fromFrame ? 5 : 2;
    const Mat first = start(img.size(), fromFrame);
    for (auto _ : state) {
        Mat labels = first.clone();
        theRNG() = RNG(5);
        if (ours) {
            multicage::propose_detail::GrabCut grabCut(img, labels);
            for (int i = 0; i < iterations; ++i) grabCut.iterate(labels);
        } else {
            Mat bgd, fgd;
            grabCut(img, labels, Rect(), bgd, fgd, iterations, GC_INIT_WITH_MASK);
        }
        benchmark::DoNotOptimize(labels.data);
    }
    state.SetLabel(std::string(kPhotos[state.range(0)]) +
                   (fromFrame ? ", frame, 5 it" : ", rect, 2 it"));
    setNumThreads(-1);
}

}  // namespace

BENCHMARK_CAPTURE(BM_GrabCut, opencv, false)
    ->ArgNames({"photo", "frame"})
    ->ArgsProduct({{0, 1, 2}, {1, 0}})
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_GrabCut, ours, true)
    ->ArgNames({"photo", "frame"})
    ->ArgsProduct({{0, 1, 2}, {1, 0}})
    ->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();

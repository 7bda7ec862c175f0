// multicage bench: the paper's Table 1 cases timed with this library and with a peer
// (OpenCV's thin-plate spline warp on the same points), medians of repeated runs.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/shape/shape_transformer.hpp>

#include "cli_util.hpp"
#include "fixtures.hpp"

namespace multicage_cli {

namespace {

struct BenchCase {
    cv::Size size;
    int vertices;
    double paperBindSeconds;  // Table 1 of the paper; < 0 where we do not quote it
};

// The paper's Table 1 image sizes and user vertex counts.
const BenchCase kPaperCases[] = {{{1024, 768}, 68, 9.034}, {{800, 600}, 44, -1},
                                 {{500, 333}, 40, -1},     {{375, 500}, 35, -1},
                                 {{701, 525}, 29, -1},     {{1000, 701}, 41, -1}};

struct BenchOptions {
    int repeats = 7;
    bool paperOnly = false, noPeer = false;
    std::string image;
};

template <typename F>
double medianMs(int repeats, F&& f) {
    std::vector<double> ms;
    f();  // warm-up: first-touch page faults and lazy allocations are not what we measure
    for (int i = 0; i < repeats; ++i) {
        const auto t = std::chrono::steady_clock::now();
        f();
        ms.push_back(msSince(t));
    }
    return median(ms);
}

cv::Mat benchImage(const std::string& path, cv::Size size) {
    cv::Mat img;
    if (!path.empty()) img = readImage(path);
    if (img.empty()) {  // a smooth colourful pattern when no photograph is given
        img.create(512, 512, CV_8UC3);
        for (int y = 0; y < img.rows; ++y)
            for (int x = 0; x < img.cols; ++x)
                img.at<cv::Vec3b>(y, x) = cv::Vec3b(x / 2, y / 2, (x ^ y) & 255);
    }
    cv::resize(img, img, size, 0, 0, cv::INTER_AREA);
    return img;
}

void runBench(const BenchOptions& o) {
    using namespace cv::multicage;
    std::printf("multicage bench: medians of %d runs, %d threads, OpenCV %s\n", o.repeats,
                cv::getNumThreads(), CV_VERSION);
    std::printf("%-10s %4s | %9s %9s | %9s %9s %9s | %9s %7s | %8s\n", "image", "V", "bind s=1",
                "paper", "pose s=1", "pose s=4", "maps s=1", "TPS warp", "TPS/us", "coef MB");
    std::printf("%-10s %4s | %9s %9s | %9s %9s %9s | %9s %7s | %8s\n", "", "", "(ms)", "(ms)",
                "(ms)", "(ms)", "(ms)", "(ms)", "(s=1)", "(s=1)");
    for (const BenchCase& c : kPaperCases) {
        const cv::Mat image = benchImage(o.image, c.size);
        const Multicage cage = multicage_fixtures::lotusMulticage(c.size, c.vertices);
        const std::vector<cv::Point2f> pose = multicage_fixtures::wavePose(cage, 12.f, 0.5f);
        Binding binding;
        const double bindMs = medianMs(o.repeats, [&] { binding = bind(cage, MEAN_VALUE, 1); });
        DeformParams cpu;
        cpu.backend = BACKEND_CPU;
        cv::Ptr<Deformer> d1 = Deformer::create(image, binding, cpu);
        cv::Mat out, mapx, mapy;
        const double pose1 = medianMs(o.repeats, [&] { d1->deform(pose, out); });
        const double maps1 = medianMs(o.repeats, [&] { d1->computeMaps(pose, mapx, mapy); });
        cpu.gridStep = 4;
        cv::Ptr<Deformer> d4 = Deformer::create(image, cage, cpu);
        const double pose4 = medianMs(o.repeats, [&] { d4->deform(pose, out); });

        double tpsMs = -1;
        if (!o.noPeer) {
            // The peer: one thin-plate spline through the same vertices (rest -> pose).
            std::vector<cv::Point2f> rest = cage.vertices();
            rest.resize(cage.vertexCount());
            std::vector<cv::DMatch> matches;
            for (int i = 0; i < cage.vertexCount(); ++i) matches.emplace_back(i, i, 0.f);
            cv::Ptr<cv::ThinPlateSplineShapeTransformer> tps = cv::createThinPlateSplineShapeTransformer();
            cv::Mat tpsOut;
            // warpImage maps output to input, so the estimate goes from pose to rest.
            tpsMs = medianMs(std::max(1, o.repeats / 2), [&] {
                tps->estimateTransformation(cv::Mat(pose).reshape(2, 1), cv::Mat(rest).reshape(2, 1), matches);
                tps->warpImage(image, tpsOut);
            });
        }
        const double coefMB = binding.coefficients.total() * sizeof(float) / (1024.0 * 1024.0);
        char paper[32] = "-";
        if (c.paperBindSeconds > 0) std::snprintf(paper, sizeof paper, "%.0f", c.paperBindSeconds * 1000);
        std::printf("%4dx%-5d %4d | %9.1f %9s | %9.1f %9.2f %9.1f | %9.1f %7.1f | %8.1f\n",
                    c.size.width, c.size.height, c.vertices, bindMs, paper, pose1, pose4, maps1,
                    tpsMs, tpsMs > 0 ? tpsMs / pose1 : 0.0, coefMB);
        std::fflush(stdout);
        if (o.paperOnly) break;
    }
    std::printf("bind: Algorithm 1 over every pixel (grid step 1), all threads; pose: one pose to a "
                "finished cv::Mat on the CPU backend; maps: inverse maps only; TPS: "
                "cv::ThinPlateSplineShapeTransformer estimate + warpImage with the same points.\n");
}
}  // namespace

void addBenchCommand(CLI::App& app) {
    auto o = std::make_shared<BenchOptions>();
    CLI::App* cmd = app.add_subcommand(
        "bench",
        "Time binding and pose updates on the paper's Table 1 cases (two 'lotus' multicages of "
        "68, 44, 40, 35, 29 and 41 vertices) next to OpenCV's thin-plate spline warp.");
    cmd->add_option("--repeats", o->repeats, "Timed runs per figure (the median is printed)")->capture_default_str()
        ->check(CLI::Range(1, 1000));
    cmd->add_flag("--first", o->paperOnly, "Only the first case (1024x768, 68 vertices)");
    cmd->add_flag("--no-peer", o->noPeer, "Skip the thin-plate spline peer");
    cmd->add_option("--image", o->image, "Photograph to resize for every case (default: a pattern)");
    cmd->callback([o] { runBench(*o); });
}

}  // namespace multicage_cli

// Content-aware resizing against its anchors, in one run on one photo (issue 25, item 6):
//   bench_resize [IMAGE] [--repeats N] [--threads T] [--no-liquid]
// Binds once (ResizeParams' coordinates), then times each target size as resizePose + deform on
// the CPU, next to a pose at the original size (every user vertex moved: a pose pays for its
// moved vertices, and the rest pose moves none), cv::resize at the same sizes, and ImageMagick's
// -liquid-rescale (seam carving through liblqr; Debian package imagemagick) where installed.
// Medians; ratios printed.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/multicage.hpp>
#include <string>

#include "fixtures.hpp"

namespace {

using Clock = std::chrono::steady_clock;

double ms(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

template <typename F>
double medianMs(int repeats, F&& f) {
    std::vector<double> t;
    for (int i = 0; i < repeats; ++i) {
        const auto t0 = Clock::now();
        f();
        t.push_back(ms(t0));
    }
    std::nth_element(t.begin(), t.begin() + t.size() / 2, t.end());
    return t[t.size() / 2];
}

double loadAverage() {
    double load[1] = {-1};
    return getloadavg(load, 1) == 1 ? load[0] : -1;
}

bool haveLiquidRescale() {
    return std::system("convert -list format > /dev/null 2>&1") == 0 &&
           std::system("convert -size 8x8 xc:gray -liquid-rescale 12x8! null: > /dev/null 2>&1") ==
               0;
}

}  // namespace

int main(int argc, char** argv) {
    std::string path = std::string(MULTICAGE_SAMPLES_DIR) + "/messi5.jpg";
    int repeats = 9, threads = 2;
    bool liquid = true;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--repeats" && i + 1 < argc)
            repeats = std::max(1, std::atoi(argv[++i]));
        else if (a == "--threads" && i + 1 < argc)
            threads = std::max(1, std::atoi(argv[++i]));
        else if (a == "--no-liquid")
            liquid = false;
        else if (a == "--help" || a == "-h") {
            std::cout << "bench_resize [IMAGE] [--repeats N] [--threads T] [--no-liquid]\n"
                         "IMAGE (default messi5.jpg) is scaled to 1024x768.\n";
            return 0;
        } else
            path = a;
    }
    using namespace cv::multicage;
    cv::setNumThreads(threads);
    cv::Mat image = cv::imread(path, cv::IMREAD_COLOR);
    if (image.empty()) {
        std::cerr << "bench_resize: cannot read " << path << "\n";
        return 1;
    }
    cv::resize(image, image, cv::Size(1024, 768), 0, 0, cv::INTER_AREA);

    auto t0 = Clock::now();
    const Multicage cage = resizeCage(image);
    const double proposeMs = ms(t0);
    DeformParams params;
    params.backend = BACKEND_CPU;
    params.coordinates = ResizeParams().coordinates;
    t0 = Clock::now();
    cv::Ptr<Deformer> d = Deformer::create(image, cage, params);
    const Binding& binding = d->binding();
    const double bindMs = ms(t0);
    std::printf(
        "bench_resize: %s at 1024x768, %d threads, CPU backend, %d polygons, %d vertices; "
        "%s coordinates, propose %.0f ms, bind %.0f ms (once); load average %.1f\n",
        std::filesystem::path(path).filename().c_str(), threads, cage.polygonCount(),
        cage.vertexCount(), coordinateTypeDescription(binding.coordinates), proposeMs, bindMs,
        loadAverage());

    cv::Mat out;
    const std::vector<cv::Point2f> rest = cage.vertices();
    const std::vector<cv::Point2f> wave = multicage_fixtures::wavePose(cage, 12.f);
    const double restMs = medianMs(repeats, [&] { d->deform(rest, out); });
    const double poseMs = medianMs(repeats, [&] { d->deform(wave, out); });
    const bool lqr = liquid && haveLiquidRescale();
    const std::string dir =
        (std::filesystem::temp_directory_path() / ("bench_resize_" + std::to_string(::getpid())))
            .string();
    std::filesystem::create_directories(dir);
    const std::string in = dir + "/in.png";
    cv::imwrite(in, image);
    // ImageMagick's own read, plain resize and write: what its liquid rescale time includes
    // besides the seam carving.
    double imResizeMs = 0;
    if (lqr)
        imResizeMs = medianMs(3, [&] {
            std::system(("convert " + in + " -resize 1536x768! " + dir + "/r.png").c_str());
        });

    std::printf(
        "\n| target | ours: resizePose + deform | resizePose alone | / pose at 1024x768 | "
        "cv::resize | liquid rescale (ImageMagick) | liquid / ours |\n");
    std::printf("|---|---|---|---|---|---|---|\n");
    std::printf("| 1024x768, a pose moving every vertex | %.1f ms | | 1.00 | | | |\n", poseMs);
    std::printf("| 1024x768, the rest pose | %.1f ms | | %.2f | | | |\n", restMs, restMs / poseMs);
    for (const cv::Size target :
         {cv::Size(1536, 768), cv::Size(717, 768), cv::Size(1365, 768), cv::Size(1024, 1024)}) {
        const double oursMs =
            medianMs(repeats, [&] { d->deform(resizePose(cage, binding, target), out); });
        const double resizePoseMs =
            medianMs(repeats, [&] { (void)resizePose(cage, binding, target); });
        const double cvMs =
            medianMs(repeats, [&] { cv::resize(image, out, target, 0, 0, cv::INTER_LINEAR); });
        double lqrMs = 0;
        if (lqr) {
            const std::string cmd = "convert " + in + " -liquid-rescale " +
                                    std::to_string(target.width) + "x" +
                                    std::to_string(target.height) + "! " + dir + "/l.png";
            lqrMs = medianMs(3, [&] { std::system(cmd.c_str()); });
        }
        std::printf("| %dx%d | %.1f ms | %.1f ms | %.2f | %.2f ms | %s | %s |\n", target.width,
                    target.height, oursMs, resizePoseMs, oursMs / poseMs, cvMs,
                    lqr ? cv::format("%.0f ms", lqrMs).c_str() : "not installed",
                    lqr ? cv::format("%.0fx", lqrMs / oursMs).c_str() : "");
    }
    if (lqr)
        std::printf(
            "\nImageMagick's read + plain -resize + write of the same file: %.0f ms (part of each "
            "liquid "
            "rescale figure).\n",
            imResizeMs);
    std::filesystem::remove_all(dir);
    return 0;
}

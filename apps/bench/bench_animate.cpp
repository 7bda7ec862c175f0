// Frames per second of a whole animation render on 1024x768: the paper's lotus multicage
// (68 user vertices), four wave poses as keyframes, Catmull-Rom, looped.
// Usage: bench_animate [cpu|gpu|both] [GRID_STEP] [FRAMES] [OUTDIR]   (run by hand, not by ctest)
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgproc.hpp>
#include <opencv2/multicage/animate.hpp>
#include <string>

#include "fixtures.hpp"

using namespace cv::multicage;

namespace {
double msSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

// A busy 1024x768 test card: gradients, rings and a grid, so every codec has work to do.
cv::Mat testCard(cv::Size size) {
    cv::Mat img(size, CV_8UC3);
    for (int y = 0; y < size.height; ++y)
        for (int x = 0; x < size.width; ++x)
            img.at<cv::Vec3b>(y, x) = cv::Vec3b(
                static_cast<uchar>(x * 255 / size.width), static_cast<uchar>(y * 255 / size.height),
                static_cast<uchar>(128 + 127 * std::sin(std::hypot(x - 512, y - 384) / 9.0)));
    for (int x = 0; x < size.width; x += 32)
        cv::line(img, {x, 0}, {x, size.height}, cv::Scalar::all(255), 1);
    for (int y = 0; y < size.height; y += 32)
        cv::line(img, {0, y}, {size.width, y}, cv::Scalar::all(255), 1);
    return img;
}
}  // namespace

int main(int argc, char** argv) {
    std::setvbuf(stdout, nullptr, _IOLBF, 0);  // one line at a time, also into a file
    const std::string which = argc > 1 ? argv[1] : "both";
    const int gridStep = argc > 2 ? std::atoi(argv[2]) : 1;
    const int frames = argc > 3 ? std::atoi(argv[3]) : 50;
    const std::string outDir =
        argc > 4 ? argv[4] : (std::filesystem::temp_directory_path() / "bench_animate").string();
    std::filesystem::create_directories(outDir);

    const cv::Size size(1024, 768);
    Multicage cage = multicage_fixtures::lotusMulticage(size, 68);
    for (int k = 0; k < 4; ++k)
        addKeyframe(cage, multicage_fixtures::wavePose(cage, 12.f, 1.3f * k), 0.5 * k);
    const cv::Mat image = testCard(size);
    AnimationParams params;
    params.loop = true;
    params.fps = frames / animationDuration(cage, true);  // `frames` frames in one cycle

    std::printf(
        "1024x768, %d user vertices, %d keyframes, %d frames, grid step %d, Catmull-Rom, looped\n",
        cage.vertexCount(), cage.poseCount(), frames, gridStep);
    std::printf("%-4s %-10s %9s %10s %10s %10s %10s\n", "", "output", "bind ms", "deform ms",
                "write ms", "total ms", "frames/s");
    for (const std::string backend : {"cpu", "gpu"}) {
        if (which != "both" && which != backend) continue;
        DeformParams dp;
        dp.backend = backend == "gpu" ? BACKEND_GPU : BACKEND_CPU;
        dp.gridStep = gridStep;
        const auto tb = std::chrono::steady_clock::now();
        cv::Ptr<Deformer> deformer = Deformer::create(image, cage, dp);
        const double bindMs = msSince(tb);
        // Deform only: the ceiling any output format can reach.
        {
            const std::vector<double> times = animationFrameTimes(cage, params);
            cv::Mat frame;
            deformer->deform(samplePose(cage, 0, params.interpolation, true), frame);  // warm up
            const auto t = std::chrono::steady_clock::now();
            for (double time : times)
                deformer->deform(samplePose(cage, time, params.interpolation, true), frame);
            const double ms = msSince(t);
            std::printf("%-4s %-10s %9.0f %10.1f %10s %10.0f %10.1f\n", backend.c_str(), "(none)",
                        bindMs, ms / times.size(), "-", ms, 1000.0 * times.size() / ms);
        }
        for (const std::string out : {"frames/", "anim.mp4", "anim.avi", "anim.gif"}) {
            const AnimationStats s = renderAnimation(*deformer, cage, outDir + "/" + out, params);
            std::printf("%-4s %-10s %9.0f %10.1f %10.1f %10.0f %10.1f\n", backend.c_str(),
                        out.c_str(), bindMs, s.deformMs / s.frames, s.writeMs / s.frames, s.totalMs,
                        s.fps());
        }
    }
    std::printf("(total and frames/s: the render after binding; add bind ms once per animation)\n");
    return 0;
}

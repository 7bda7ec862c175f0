// renderAnimation: bind once, then sample, deform and write every frame.
#include <chrono>
#include <opencv2/multicage/animate.hpp>

namespace cv {
namespace multicage {

namespace {
double msSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}
}  // namespace

AnimationStats renderAnimation(Deformer& deformer, const Multicage& cage, const String& path,
                               const AnimationParams& params, const AnimationProgress& progress) {
    using clock = std::chrono::steady_clock;
    const auto start = clock::now();
    AnimationStats stats;
    stats.backend = deformer.backend();
    const std::vector<double> times =
        animationFrameTimes(cage, params);  // checks the keyframes first
    Ptr<AnimationWriter> writer = AnimationWriter::create(path, params.fps);
    const int n = static_cast<int>(times.size());
    Mat frame;
    for (int f = 0; f < n; ++f) {
        auto t = clock::now();
        const std::vector<Point2f> pose =
            samplePose(cage, times[f], params.interpolation, params.loop);
        stats.sampleMs += msSince(t);
        t = clock::now();
        deformer.deform(pose, frame);
        stats.deformMs += msSince(t);
        t = clock::now();
        writer->write(frame);
        stats.writeMs += msSince(t);
        ++stats.frames;
        if (progress) progress(f + 1, n);
    }
    const auto t = clock::now();
    writer->finish();
    stats.writeMs += msSince(t);
    stats.note = writer->note();
    stats.totalMs = msSince(start);
    return stats;
}

AnimationStats renderAnimation(InputArray image, const Multicage& cage, const String& path,
                               const AnimationParams& params, const DeformParams& deformParams,
                               const AnimationProgress& progress) {
    const auto start = std::chrono::steady_clock::now();
    // Fail on the keyframes and the output path before the (slow) binding.
    animationFrameTimes(cage, params);
    checkAnimationOutput(path);
    Ptr<Deformer> deformer = Deformer::create(image, cage, deformParams);
    const double bindMs = msSince(start);
    AnimationStats stats = renderAnimation(*deformer, cage, path, params, progress);
    stats.bindMs = bindMs;
    stats.totalMs = msSince(start);
    return stats;
}

}  // namespace multicage
}  // namespace cv

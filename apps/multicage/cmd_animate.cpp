// multicage animate IMAGE CAGE.yml -o OUT: keyframed poses to video, GIF or PNG frames.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <iostream>

#include "cli_util.hpp"

namespace multicage_cli {

namespace {
struct AnimateOptions {
    std::string image, cage, output, interpolation = "catmull-rom";
    double fps = 25, duration = 0;
    bool loop = false, quiet = false, allowInvalid = false;
    DeformOptions deform;
};

void runAnimate(const AnimateOptions& o) {
    using namespace cv::multicage;
    checkAnimationOutput(o.output);  // before any work: a typo costs nothing
    const cv::Mat image = readImage(o.image);
    const Multicage cage = loadCage(o.cage, image.size());
    std::string why;
    if (!validateKeyframes(cage, &why)) throw Failure(o.cage + ": " + why);
    for (int i = 0; i < cage.poseCount(); ++i)
        checkPose("animate", o.cage, cage, i, o.allowInvalid);

    AnimationParams params;
    params.fps = o.fps;
    params.duration = o.duration;
    params.loop = o.loop;
    params.interpolation =
        o.interpolation == "linear" ? INTERPOLATE_LINEAR : INTERPOLATE_CATMULL_ROM;
    std::string stepChange;
    DeformParams deformation = deformParams(o.deform, "animate", image.size(), cage, &stepChange);
    probeAutoBackend(deformation.backend);  // once, and not counted as bind time

    FrameProgress progress("animate", o.quiet);
    AnimationStats s;
    {
        BindProgressLine bindProgress("animate", o.quiet);
        deformation.progress = bindProgress.callback();
        try {
            s = renderAnimation(image, cage, o.output, params, deformation,
                                [&progress](int done, int total) { progress(done, total); });
        } catch (const cv::Exception& e) {
            bindProgress.rethrow(e);
        }
    }
    const double n = s.frames;
    std::printf(
        "wrote %s (%d frames, %dx%d, %g fps, %.2f s of animation, %s, %s coordinates, "
        "grid step %d%s)\n"
        "render: %.1f frames/s over %.0f ms (bind %.0f ms; per frame: pose %.2f ms, "
        "deform %.1f ms, write %.1f ms)\n",
        o.output.c_str(), s.frames, image.cols, image.rows, o.fps, s.frames / o.fps,
        backendName(s.backend), coordinateTypeDescription(deformation.coordinates),
        deformation.gridStep, stepChange.empty() ? "" : (" (" + stepChange + ")").c_str(), s.fps(),
        s.totalMs, s.bindMs, s.sampleMs / n, s.deformMs / n, s.writeMs / n);
    if (!s.note.empty())
        std::fprintf(stderr, "multicage animate: note: %s: %s\n", o.output.c_str(), s.note.c_str());
}
}  // namespace

void addAnimateCommand(CLI::App& app) {
    auto o = std::make_shared<AnimateOptions>();
    CLI::App* cmd = app.add_subcommand(
        "animate",
        "Animate IMAGE through the timed poses (keyframes) of CAGE.yml and write OUT.\n"
        "Each pose's `time:` (seconds) says when it is reached; between keyframes the vertices "
        "move "
        "along Catmull-Rom splines (or straight lines). The image is bound once; every frame is "
        "one "
        "deformation. OUT is a video (.mp4: H.264, .avi: Motion JPEG), a .gif, or a folder ending "
        "in / "
        "for PNG frames (frame_0000.png, ...); it is written completely or not at all.\n"
        "Example: multicage animate butterfly.jpg butterfly_flap.yml -o flap.gif --loop --fps 20");
    cmd->add_option("image", o->image, "Input image (8/16-bit or float, 1, 3 or 4 channels)")
        ->required();
    cmd->add_option("cage", o->cage,
                    "Cage file with at least two timed poses (.yml, .yaml or .json)")
        ->required();
    cmd->add_option("-o,--output", o->output, "OUT.mp4, OUT.avi, OUT.gif or FRAMES_DIR/")
        ->required();
    cmd->add_option("--fps", o->fps, "Frames per second of the output")
        ->capture_default_str()
        ->check(CLI::Range(0.1, 1000.0));
    cmd->add_option(
           "--duration", o->duration,
           "Seconds of output (default: from the first keyframe to the last, or one cycle with "
           "--loop); longer holds the last pose, or repeats the cycle with --loop")
        ->check(CLI::Range(0.001, 36000.0));
    cmd->add_flag(
        "--loop", o->loop,
        "Cycle: after the last keyframe, move back to the first (taking the mean keyframe "
        "spacing), so the output can play on repeat without a jump");
    cmd->add_option("--interpolation", o->interpolation, "catmull-rom (smooth) or linear")
        ->capture_default_str()
        ->check(CLI::IsMember({"linear", "catmull-rom"}));
    addDeformOptions(cmd, o->deform);
    addAllowInvalidFlag(cmd, o->allowInvalid);
    cmd->add_flag("-q,--quiet", o->quiet, "No progress output");
    cmd->callback([o] { runAnimate(*o); });
}

}  // namespace multicage_cli

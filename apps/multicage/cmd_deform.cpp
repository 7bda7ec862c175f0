// multicage deform IMAGE CAGE.yml -o OUT.png: apply a saved pose to an image.
#include <chrono>
#include <climits>
#include <iostream>

#include "cli_util.hpp"
#include "clip_io.hpp"
#include "deform_clip.hpp"

namespace multicage_cli {

namespace {
struct DeformCommandOptions {
    std::string image, cage, output, pose;
    int frame = -1;  // clips: -1, the cage file's clip_frame
    DeformOptions deform;
    bool quiet = false, allowInvalid = false;
};

void runDeform(const DeformCommandOptions& o) {
    using namespace cv::multicage;
    if (isVideoPath(o.image)) {
        if (!isVideoPath(o.output))
            throw UsageError(
                "-o: a clip is written as a video (.mp4, .m4v, .mov, .mkv, .avi or "
                ".webm), not '" +
                o.output + "'");
        ClipDeformJob job{o.image, o.cage,   o.output, o.pose,
                          o.frame, o.deform, o.quiet,  o.allowInvalid};
        return deformClip(job);
    }
    if (o.frame >= 0)
        throw UsageError("--frame: names a frame of a clip; " + o.image + " is an image");
    const auto t0 = std::chrono::steady_clock::now();
    checkImageOutput(o.output);
    const cv::Mat image = readImage(o.image);
    const Multicage cage = loadCage(o.cage, image.size());
    if (cage.poseCount() == 0)
        throw Failure(
            o.cage +
            ": has no poses; add one under `poses:`, e.g. `- { name: stretch, vertices: "
            "[ x0, y0, x1, y1, ... ] }` with every vertex in order (see multicage deform --help)");
    int poseIndex = 0;
    if (!o.pose.empty()) {
        poseIndex = cage.findPose(o.pose);
        if (poseIndex < 0) {
            std::string names;
            for (int i = 0; i < cage.poseCount(); ++i) names += (i ? ", " : "") + cage.pose(i).name;
            throw Failure(o.cage + ": no pose named '" + o.pose + "' (it has: " + names + ")");
        }
    }
    checkPose("deform", o.cage, cage, poseIndex, o.allowInvalid);
    std::string stepChange;
    DeformParams params = deformParams(o.deform, "deform", image.size(), cage, &stepChange);

    probeAutoBackend(params.backend);  // once, and not counted as bind time
    const auto tb = std::chrono::steady_clock::now();
    const cv::Ptr<Deformer> deformer = createWithProgress("deform", o.quiet, image, cage, params);
    const double bindMs = msSince(tb);
    const Binding& binding = deformer->binding();
    if (binding.minConditioning < kConditioningWarning)
        std::cerr << "multicage deform: warning: the binding is ill-conditioned near ("
                  << binding.worstNode.x << ", " << binding.worstNode.y << ") (min conditioning "
                  << binding.minConditioning << " < " << kConditioningWarning
                  << "): polygons there may spring up; move them apart or add vertices\n";
    const Pose& pose = cage.pose(poseIndex);
    const int folded = deformer->foldedTriangles(pose.vertices);
    if (folded > 0)
        std::cerr << "multicage deform: warning: pose '" << pose.name
                  << "' folds the image over itself (" << folded << " mesh triangles inverted)\n";
    const auto td = std::chrono::steady_clock::now();
    cv::Mat out;
    deformer->deform(pose.vertices, out);
    const double deformMs = msSince(td);
    writeImage("deform", o.output, out);
    std::cout << "wrote " << o.output << " (" << out.cols << "x" << out.rows << ", pose '"
              << pose.name << "', " << backendName(deformer->backend())
              << (params.backend == BACKEND_AUTO ? " (auto)" : "") << ", "
              << coordinateTypeDescription(binding.coordinates) << " coordinates, grid step "
              << binding.gridStep << (stepChange.empty() ? "" : " (" + stepChange + ")")
              << (params.mapStep > 1 && deformer->backend() == BACKEND_CPU
                      ? ", map step " + std::to_string(params.mapStep)
                      : std::string())
              << ", bind " << cvRound(bindMs) << " ms, deform " << cvRound(deformMs)
              << " ms, total " << cvRound(msSince(t0)) << " ms)" << std::endl;
}
}  // namespace

void addDeformCommand(CLI::App& app) {
    auto o = std::make_shared<DeformCommandOptions>();
    CLI::App* cmd = app.add_subcommand(
        "deform",
        "Deform IMAGE to a pose stored in CAGE.yml and write OUT.\n"
        "The cage file holds rest polygons and named poses (`multicage propose` writes a pose "
        "named `rest`; the editor saves the poses you drag); a cage made for another image size "
        "is scaled to this image. A pose lists every vertex of every polygon, in order, as x y "
        "pairs in pixels:\n"
        "  polygons:\n"
        "     - [ 100, 80, 300, 80, 300, 240, 100, 240 ]\n"
        "  poses:\n"
        "     - { name: stretch, time: 1.0, vertices: [ 90, 70, 330, 75, 310, 250, 100, 240 ] }\n"
        "A clip (.mp4, .m4v, .mov, .mkv, .avi, .webm) with a cage drawn on its first frame (or "
        "on frame N: --frame N, or `clip_frame: N` in the cage file): the cage follows its "
        "subjects and the pose moves, turns and scales with each polygon; "
        "the frame rate and audio are carried over (grid step 2 unless given).\n"
        "Examples:\n"
        "  multicage deform photo.jpg cage.yml -o out.png --pose stretch --grid-step 2\n"
        "  multicage deform clip.mp4 cage.yml -o edited.mp4 --pose stretch\n"
        "  multicage deform clip.mp4 cage.yml -o edited.mp4 --frame 120  # drawn on frame 120");
    cmd->add_option("image", o->image,
                    "Input image (8/16-bit or float, 1, 3 or 4 channels), or clip")
        ->required();
    cmd->add_option("cage", o->cage, "Cage file (.yml, .yaml or .json)")->required();
    cmd->add_option("-o,--output", o->output, "Output image or clip; written only when complete")
        ->required();
    cmd->add_option("--pose", o->pose, "Pose name in the cage file (default: the first pose)");
    cmd->add_option("--frame", o->frame,
                    "Clips: the frame the cage was drawn on, 0 the first (default: the cage "
                    "file's clip_frame, else 0); the cage is followed backward and forward from it")
        ->check(wholeNumber(0, INT_MAX));
    addDeformOptions(cmd, o->deform);
    addAllowInvalidFlag(cmd, o->allowInvalid);
    cmd->add_flag("-q,--quiet", o->quiet, "No progress line while binding");
    cmd->callback([o] { runDeform(*o); });
}

}  // namespace multicage_cli

// multicage deform IN.mp4: CageTracker moves the rest cage, carryPose the edit, a binding per
// frame.
#include "deform_clip.hpp"

#include <iostream>
#include <opencv2/multicage/augment.hpp>
#include <opencv2/multicage/track.hpp>

#include "clip_io.hpp"

namespace multicage_cli {

void deformClip(const ClipDeformJob& job) {
    using namespace cv::multicage;
    const auto t0 = std::chrono::steady_clock::now();
    ClipReader reader(job.input);
    const ClipInfo& info = reader.info();
    const Multicage cage = loadCage(job.cage, info.size);
    const int poseIndex = job.pose.empty() ? 0 : cage.findPose(job.pose);
    if (cage.poseCount() == 0 || poseIndex < 0)
        throw Failure(job.cage + (cage.poseCount() == 0 ? ": has no poses"
                                                        : ": no pose named '" + job.pose + "'"));
    checkPose("deform", job.cage, cage, poseIndex, job.allowInvalid);
    const std::vector<cv::Point2f> pose = cage.pose(poseIndex).vertices;
    std::string stepChange;
    DeformParams params = deformParams(job.deform, "deform", info.size, cage, &stepChange);
    // A binding per frame: step 2 unless one was typed (faces stay within a pixel, docs/video).
    if (!(job.deform.gridStepOption && job.deform.gridStepOption->count() > 0))
        params.gridStep = std::max(params.gridStep, 2);
    probeAutoBackend(params.backend);
    const InterruptGuard guard;  // before the writer makes its temporary files
    ClipWriter writer(job.output, info.fps, info.size, job.input);
    FrameProgress progress("deform", job.quiet);
    cv::Ptr<CageTracker> tracker;
    int written = 0, lost = 0, unposed = 0;
    double trackMs = 0, bindMs = 0, deformMs = 0;
    cv::Mat frame, out;
    while (reader.read(frame)) {
        if (guard.interrupted())
            throw Failure("interrupted at frame " + std::to_string(written) + "; nothing written");
        auto t = std::chrono::steady_clock::now();
        // The cage lies on the first frame; a frame where it cannot be followed keeps it where
        // it was (the tracker moves nothing then), and the edit with it.
        if (!tracker)
            tracker = cv::makePtr<CageTracker>(cage, frame);
        else
            lost += tracker->track(frame).state != TRACK_OK;
        const Multicage& rest = tracker->multicage();
        std::vector<cv::Point2f> carried = carryPose(cage, pose, rest);
        if (!job.allowInvalid && !validatePose(rest, carried)) {
            carried = rest.vertices();  // as it is: the carried edit would cross
            ++unposed;
        }
        trackMs += msSince(t);
        t = std::chrono::steady_clock::now();
        const cv::Ptr<Deformer> deformer = Deformer::create(frame, rest, params);
        bindMs += msSince(t);
        t = std::chrono::steady_clock::now();
        deformer->deform(carried, out);
        deformMs += msSince(t);
        writer.write(out);
        progress(++written, info.frameCount);
    }
    if (reader.truncated())
        throw Failure(job.input + ": only " + std::to_string(reader.framesRead()) + " of " +
                      std::to_string(info.frameCount) +
                      " frames could be decoded (the file is truncated or damaged); nothing "
                      "written");
    if (info.frameCount < 0) progress(written, written);
    const std::string note = writer.finish();
    if (!note.empty()) std::cerr << "multicage deform: note: " << note << std::endl;
    if (unposed > 0)
        std::cerr << "multicage deform: note: " << plural(unposed, "frame")
                  << " left as they are: the carried pose would cross there (--allow-invalid "
                     "deforms them anyway)"
                  << std::endl;
    const double n = std::max(1, written);
    if (!job.quiet)
        std::cout << "multicage deform: " << job.input << ", pose '" << cage.pose(poseIndex).name
                  << "' carried through " << plural(written, "frame") << " ("
                  << plural(lost, "frame") << " where the cage could not be followed); grid step "
                  << params.gridStep << (stepChange.empty() ? "" : " (" + stepChange + ")")
                  << cv::format("; per frame: track %.1f ms, bind %.1f, deform %.1f; %.1f frames/s",
                                trackMs / n, bindMs / n, deformMs / n,
                                written / std::max(1e-9, msSince(t0) / 1000))
                  << std::endl;
    std::cout << "wrote " << job.output << " (" << plural(written, "frame") << ", "
              << cv::format("%.2f", written / info.fps) << " s"
              << (info.hasAudio ? ", with the audio" : "") << ")" << std::endl;
}

}  // namespace multicage_cli

// multicage deform IN.mp4: CageTracker moves the rest cage, carryPose the edit, a binding per
// frame.
#include "deform_clip.hpp"

#include <iostream>
#include <opencv2/imgproc.hpp>
#include <opencv2/multicage/augment.hpp>
#include <opencv2/multicage/track.hpp>

#include "clip_io.hpp"

namespace multicage_cli {

namespace {

using cv::multicage::Multicage;

// The frame as the tracker works on it: grey, its longer side at most TrackParams::workingSize
// (what CageTracker makes of a frame itself), so a lead-in kept in memory stays small (230 KB a
// frame at 640x360).
cv::Mat trackingCopy(const cv::Mat& frame, int workingSize) {
    cv::Mat grey;
    cv::cvtColor(frame, grey, cv::COLOR_BGR2GRAY);
    const int side = std::max(grey.cols, grey.rows);
    if (workingSize > 0 && side > workingSize) {
        const double f = double(workingSize) / side;
        cv::resize(
            grey, grey,
            cv::Size(std::max(1, cvRound(grey.cols * f)), std::max(1, cvRound(grey.rows * f))), 0,
            0, cv::INTER_AREA);
    }
    return grey;
}

Failure tooShort(const std::string& input, int first, int frames) {
    return Failure(input + ": the cage lies on frame " + std::to_string(first) +
                   " (--frame, or the cage file's clip_frame), but the clip has only " +
                   plural(frames, "frame") + " (the first is 0)");
}

// The rest cage on each frame before `first`, where it was drawn: followed backward from there
// over the frames' tracking copies. A frame where it cannot be followed keeps it where it was.
std::vector<Multicage> cagesBefore(const ClipDeformJob& job, const Multicage& cage, int first,
                                   const InterruptGuard& guard, FrameProgress& progress, int total,
                                   int& lost) {
    ClipReader reader(job.input);
    const int workingSize = cv::multicage::TrackParams().workingSize;
    std::vector<cv::Mat> copies;
    cv::Mat frame;
    while (int(copies.size()) <= first && reader.read(frame)) {
        if (guard.interrupted()) throw Failure("interrupted while tracking back; nothing written");
        copies.push_back(trackingCopy(frame, workingSize));
    }
    if (int(copies.size()) <= first) throw tooShort(job.input, first, int(copies.size()));
    const cv::Size size = copies[0].size(), frameSize = cage.imageSize();
    cv::multicage::CageTracker back(size == frameSize ? cage : cage.scaled(size), copies[first]);
    std::vector<Multicage> cages(first, cage);
    for (int f = first - 1; f >= 0; --f) {
        if (guard.interrupted()) throw Failure("interrupted while tracking back; nothing written");
        lost += back.track(copies[f]).state != cv::multicage::TRACK_OK;
        cages[f] = size == frameSize ? back.multicage() : back.multicage().scaled(frameSize);
        copies[f + 1].release();
        progress(first - f, total);
    }
    return cages;
}

}  // namespace

void deformClip(const ClipDeformJob& job) {
    using namespace cv::multicage;
    const auto t0 = std::chrono::steady_clock::now();
    ClipReader reader(job.input);
    const ClipInfo& info = reader.info();
    const Multicage cage = loadCage(job.cage, info.size);
    const int first = job.frame >= 0 ? job.frame : cage.clipFrame();
    const int poseIndex = job.pose.empty() ? 0 : cage.findPose(job.pose);
    if (cage.poseCount() == 0 || poseIndex < 0)
        throw Failure(job.cage + (cage.poseCount() == 0 ? ": has no poses"
                                                        : ": no pose named '" + job.pose + "'"));
    if (info.frameCount >= 0 && first >= info.frameCount)
        throw tooShort(job.input, first, info.frameCount);
    checkPose("deform", job.cage, cage, poseIndex, job.allowInvalid);
    const std::vector<cv::Point2f> pose = cage.pose(poseIndex).vertices;
    std::string stepChange;
    DeformParams params = deformParams(job.deform, "deform", info.size, cage, &stepChange);
    // A binding per frame: step 2 unless one was typed (faces stay within a pixel, docs/video).
    if (!(job.deform.gridStepOption && job.deform.gridStepOption->count() > 0))
        params.gridStep = std::max(params.gridStep, 2);
    probeAutoBackend(params.backend);
    const InterruptGuard guard;  // before the writer makes its temporary files
    ClipWriter writer(job.output, info.fps, info.size, job.input);  // refused before any work
    FrameProgress progress("deform", job.quiet);
    // Frames before the one the cage lies on come first in the bar (tracked back, then deformed).
    const int total = info.frameCount < 0 ? -1 : info.frameCount + first;
    int written = 0, lost = 0, unposed = 0;
    const auto tb = std::chrono::steady_clock::now();
    const std::vector<Multicage> before =
        first > 0 ? cagesBefore(job, cage, first, guard, progress, total, lost)
                  : std::vector<Multicage>();
    double trackMs = msSince(tb), bindMs = 0, deformMs = 0;
    cv::Ptr<CageTracker> tracker;
    cv::Mat frame, out;
    while (reader.read(frame)) {
        if (guard.interrupted())
            throw Failure("interrupted at frame " + std::to_string(written) + "; nothing written");
        auto t = std::chrono::steady_clock::now();
        // The cage lies on frame `first`; a frame where it cannot be followed keeps it where it
        // was (the tracker moves nothing then), and the edit with it.
        if (written == first)
            tracker = cv::makePtr<CageTracker>(cage, frame);
        else if (written > first)
            lost += tracker->track(frame).state != TRACK_OK;
        const Multicage& rest = written < first ? before[written] : tracker->multicage();
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
        ++written;
        progress(written + first, total);
    }
    if (reader.truncated())
        throw Failure(job.input + ": only " + std::to_string(reader.framesRead()) + " of " +
                      std::to_string(info.frameCount) +
                      " frames could be decoded (the file is truncated or damaged); nothing "
                      "written");
    if (total < 0) progress(written + first, written + first);
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
                  << "' carried through " << plural(written, "frame")
                  << (first > 0 ? " from frame " + std::to_string(first) + " both ways" : "")
                  << " (" << plural(lost, "frame")
                  << " where the cage could not be followed); grid step " << params.gridStep
                  << (stepChange.empty() ? "" : " (" + stepChange + ")")
                  << cv::format("; per frame: track %.1f ms, bind %.1f, deform %.1f; %.1f frames/s",
                                trackMs / n, bindMs / n, deformMs / n,
                                written / std::max(1e-9, msSince(t0) / 1000))
                  << std::endl;
    std::cout << "wrote " << job.output << " (" << plural(written, "frame") << ", "
              << cv::format("%.2f", written / info.fps) << " s"
              << (info.hasAudio ? ", with the audio" : "") << ")" << std::endl;
}

}  // namespace multicage_cli

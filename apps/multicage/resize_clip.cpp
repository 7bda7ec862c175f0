// multicage resize IN.mp4 -o OUT.mp4: VideoReframer between a ClipReader and a ClipWriter.
#include "resize_clip.hpp"

#include <iostream>

#include "cli_util.hpp"
#include "clip_io.hpp"

namespace multicage_cli {

namespace {

using Clock = std::chrono::steady_clock;

// Where the time went, per frame: the reframer's stages and the codec's.
std::string timeLine(const cv::multicage::ReframeStats& s, double decodeMs, double encodeMs) {
    const double n = std::max(1, s.framesOut);
    return cv::format(
        "per frame: decode %.1f ms, track %.1f, propose %.1f, bind %.1f, pose %.1f, deform %.1f, "
        "encode %.1f",
        decodeMs / n, s.trackMs / n, s.proposeMs / n, s.bindMs / n, s.poseMs / n, s.deformMs / n,
        encodeMs / n);
}

std::string proposalLine(const cv::multicage::ReframeStats& s) {
    std::string line = plural(s.proposals, "proposal");
    std::vector<std::string> why;
    if (s.cuts > 0) why.push_back(plural(s.cuts, "cut"));
    if (s.lost > 0) why.push_back(plural(s.lost, "frame") + " with a subject lost");
    for (size_t i = 0; i < why.size(); ++i) line += (i ? ", " : " (") + why[i];
    return line + (why.empty() ? "" : ")");
}

}  // namespace

void resizeClip(const ClipResizeJob& job) {
    using namespace cv::multicage;
    const auto t0 = Clock::now();
    ClipReader reader(job.input);
    const ClipInfo& info = reader.info();
    const cv::Size size = job.targetSize(info.size);
    const Multicage cage = job.cage.empty() ? Multicage() : loadCage(job.cage, info.size);
    const InterruptGuard guard;  // before the writer makes its temporary files
    // The writer checks the output before any work, and puts it in place only at the end.
    ClipWriter writer(job.output, info.fps, size, job.input);
    VideoReframer reframer(size, job.params, cage);
    FrameProgress progress("resize", job.quiet);
    double decodeMs = 0, encodeMs = 0;
    int written = 0;
    ReframedFrame out;
    auto drain = [&]() {
        while (reframer.pop(out)) {
            const auto t = Clock::now();
            writer.write(out.image);
            encodeMs += msSince(t);
            progress(++written, info.frameCount);
        }
    };
    cv::Mat frame;
    for (;;) {
        if (guard.interrupted())
            throw Failure("interrupted at frame " + std::to_string(reader.framesRead()) +
                          "; nothing written");
        const auto t = Clock::now();
        const bool more = reader.read(frame);
        decodeMs += msSince(t);
        if (!more) break;
        reframer.push(frame);
        drain();
    }
    if (reader.truncated())
        throw Failure(job.input + ": only " + std::to_string(reader.framesRead()) + " of " +
                      std::to_string(info.frameCount) +
                      " frames could be decoded (the file is truncated or damaged); nothing "
                      "written");
    reframer.finish();
    drain();
    if (info.frameCount < 0 || written < info.frameCount) progress(written, written);
    const auto te = Clock::now();
    const std::string note = writer.finish();
    encodeMs += msSince(te);
    const ReframeStats& s = reframer.stats();
    const double seconds = msSince(t0) / 1000;
    if (!note.empty()) std::cerr << "multicage resize: note: " << note << std::endl;
    if (!job.quiet) {
        std::cout << "multicage resize: " << job.input << " " << info.size.width << "x"
                  << info.size.height << " at " << cv::format("%.4g", info.fps) << " fps -> "
                  << size.width << "x" << size.height << ": " << proposalLine(s) << "; "
                  << cv::format("%.1f", written / std::max(1e-9, seconds)) << " frames/s"
                  << std::endl;
        std::cout << "  " << timeLine(s, decodeMs, encodeMs) << " ms" << std::endl;
    }
    std::cout << "wrote " << job.output << " (" << plural(written, "frame") << ", "
              << cv::format("%.2f", written / info.fps) << " s"
              << (info.hasAudio ? ", with the audio" : "") << ")" << std::endl;
}

}  // namespace multicage_cli

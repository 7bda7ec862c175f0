// multicage resize IN.mp4: a clip reframed to another size (VideoReframer), with its frame rate
// and audio carried over.
#ifndef MULTICAGE_RESIZE_CLIP_HPP
#define MULTICAGE_RESIZE_CLIP_HPP

#include <functional>
#include <opencv2/multicage/reframe.hpp>
#include <string>

namespace multicage_cli {

/** What `multicage resize` asks of a clip. */
struct ClipResizeJob {
    std::string input, output, cage;  // cage: "" for proposals
    /** The output size for the clip's frame size (checked as for photos: a UsageError). */
    std::function<cv::Size(cv::Size)> targetSize;
    cv::multicage::ReframeParams params;
    bool quiet = false;
};

/** Reframes job.input into job.output: decode, track, bind, pose, deform, encode per frame, a
progress line on a terminal, the audio copied in at the end. Ctrl-C, an error or a truncated input
leave no output file (a Failure says why). */
void resizeClip(const ClipResizeJob& job);

}  // namespace multicage_cli

#endif

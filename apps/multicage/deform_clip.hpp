// multicage deform IN.mp4 CAGE.yml --pose NAME -o OUT.mp4: an edit drawn on a clip's first frame
// carried through the clip with its subjects.
#ifndef MULTICAGE_DEFORM_CLIP_HPP
#define MULTICAGE_DEFORM_CLIP_HPP

#include <string>

#include "cli_util.hpp"

namespace multicage_cli {

/** What `multicage deform` asks of a clip. */
struct ClipDeformJob {
    std::string input, cage, output;
    std::string pose;  // "": the first pose
    int frame = -1;    // the frame the cage lies on; -1: the cage file's clip_frame
    DeformOptions deform;
    bool quiet = false, allowInvalid = false;
};

/** Tracks the cage (which lies on frame job.frame, else its clip_frame: the first by default)
through job.input, backward to the first frame and forward to the last, and deforms each frame to
the pose carried with its polygons (cv::multicage::carryPose). Frames before the cage's are kept
in memory as the tracker's grey copies (230 KB a frame at 640x360) and decoded twice. A frame where
the carried pose crosses is left as it is (a note says how many), unless allowInvalid. Ctrl-C or an
error leaves no output file. */
void deformClip(const ClipDeformJob& job);

}  // namespace multicage_cli

#endif

// Reading and writing clips for the commands that take videos (resize, deform): frames through
// OpenCV's videoio (its FFmpeg backend), the audio track carried over with libavformat.
#ifndef MULTICAGE_CLIP_IO_HPP
#define MULTICAGE_CLIP_IO_HPP

#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/videoio.hpp>
#include <string>
#include <vector>

namespace multicage_cli {

struct ClipInfo {
    cv::Size size;        // frame size (as decoded: OpenCV applies the rotation the file asks)
    double fps = 0;       // frames per second (as the container says; > 0)
    int frameCount = -1;  // as the container says; -1 when it does not say (.mkv, .webm)
    bool hasAudio = false;
};

/** True when path's extension names a video container this tool reads/writes: .mp4 .m4v .mov
.mkv .avi .webm (case-insensitive). */
bool isVideoPath(const std::string& path);

/** The frames of a video file, 8-bit BGR. All errors are Failures naming the path. */
class ClipReader {
  public:
    /** Opens path and decodes its first frame (handed out by the first read()). Throws a
    Failure: "PATH: no such file", "PATH: the file is empty", "PATH: not a video OpenCV's FFmpeg
    backend can read", "PATH: has no video track", "PATH: the video has no frames", "PATH: the
    video does not say its frame rate". */
    explicit ClipReader(const std::string& path);
    const ClipInfo& info() const { return info_; }
    /** The next frame, or false at the end. OpenCV reports a truncated or damaged file as an
    early end, not an error: see truncated(). Throws a Failure for a frame whose size differs
    from the first one's (a clip that changes size mid-way). */
    bool read(cv::Mat& frame);
    /** Frames handed out by read() so far. */
    int framesRead() const { return framesRead_; }
    /** After read() returned false: true when the clip ended before the frame count its
    container states (truncated or damaged; OpenCV stops quietly at the first frame it cannot
    decode). Always false when frameCount is -1. The command decides: say e.g. "IN: only 12 of
    50 frames could be decoded (the file is truncated or damaged)", or fail. */
    bool truncated() const {
        return ended_ && info_.frameCount >= 0 && framesRead_ < info_.frameCount;
    }

  private:
    std::string path_;
    cv::VideoCapture capture_;
    ClipInfo info_;
    cv::Mat first_;  // decoded at open, handed out by the first read()
    int framesRead_ = 0;
    bool ended_ = false;
};

/** Writes a video file atomically: everything goes to hidden temporary files beside outPath
(".OUT.mp4.part-PID-N.mp4"), and only finish() renames the result into place, so an exception
or a Ctrl-C that the command catches never leaves a partial OUT (a crash leaves only a hidden
temporary file). Video codec: H.264 ('avc1', else 'mp4v') for .mp4/.m4v/.mov/.mkv, Motion JPEG
for .avi, VP8 for .webm. */
class ClipWriter {
  public:
    /** Starts writing outPath at fps and size. audioFrom: a video file whose audio tracks
    finish() copies into the output ("" for none; outPath itself is fine: it is read before
    the output replaces it). An odd width or height is padded to even with repeated edge
    pixels (the codecs store 4:2:0 chroma), which finish()'s note says: pick even sizes to
    avoid it. fps is stored as OpenCV rounds it (29.97... as 2997/100). Throws a Failure up
    front: "cannot write OUT: no folder DIR" / ": folder DIR is not writable" / ": is a folder" /
    ": unknown video extension '.xyz' (use ...)" / ": OpenCV's video I/O cannot open a WxH
    .EXT writer here (tried avc1, mp4v)", or ClipReader's words for an unreadable audioFrom. */
    ClipWriter(const std::string& outPath, double fps, cv::Size size, const std::string& audioFrom);
    ClipWriter(const ClipWriter&) = delete;
    ClipWriter& operator=(const ClipWriter&) = delete;
    /** Removes the temporary files unless finish() completed. */
    ~ClipWriter();

    /** Appends a frame: 8-bit BGR of the constructor's size (a Failure otherwise). */
    void write(const cv::Mat& frame);
    /** Closes the video, copies audioFrom's audio tracks in (stream copy when the container
    takes the codec, else re-encoded to the container's default audio codec, e.g. AAC for
    .mp4; cut at the video's length), and renames the file into place. Stream copy cuts
    at a whole packet (up to ~25 ms over). Returns a one-line note for the user about what
    was changed or left out ("the audio track (pcm_s16le) re-encoded to aac: .mp4 cannot hold
    it", "the audio track (X) cannot go into .EXT: left out (no X encoder)"; several joined by
    "; "), or "". Throws a Failure naming outPath when the video cannot be written; nothing is
    left at outPath then. */
    std::string finish();

  private:
    std::filesystem::path out_, videoTemp_, muxTemp_;
    std::string audioFrom_;
    std::vector<int> audioStreams_;  // audioFrom's audio stream indices
    double fps_;
    cv::Size size_, encoded_;  // as asked, and padded to even
    cv::VideoWriter writer_;
    int framesWritten_ = 0;
    bool finished_ = false;
};

}  // namespace multicage_cli

#endif

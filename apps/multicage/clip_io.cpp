// ClipReader and ClipWriter: frames through OpenCV's videoio, outputs put in place only when
// complete; the audio side is clip_remux.cpp.
#include "clip_io.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstring>
#include <opencv2/core/utils/logger.hpp>

#include "cli_util.hpp"
#include "clip_remux.hpp"

namespace fs = std::filesystem;

namespace multicage_cli {
namespace {

std::string sizeText(cv::Size s) {
    return std::to_string(s.width) + "x" + std::to_string(s.height);
}

std::string joinNotes(const std::vector<std::string>& notes) {
    std::string all;
    for (const std::string& n : notes) all += (all.empty() ? "" : "; ") + n;
    return all;
}

/** OpenCV's log quiet while it lives: a writer that cannot open logs "[ERROR:0@0.001] ..."
lines, and the Failure says it in one. */
class QuietOpenCV {
  public:
    QuietOpenCV()
        : previous_(cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT)) {}
    ~QuietOpenCV() { cv::utils::logging::setLogLevel(previous_); }

  private:
    cv::utils::logging::LogLevel previous_;
};
// ---- temporary files ----------------------------------------------------------------------

/** A new empty hidden file beside target (".OUT.mp4.part-PID-N.EXT"), created here so that no
other process takes the name; mode 0666 less the umask, as the output would have. */
fs::path reserveTemp(const fs::path& target, const std::string& ext) {
    static int counter = 0;
    const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
    for (;;) {
        const fs::path p =
            dir / ("." + target.filename().string() + ".part-" + std::to_string(::getpid()) + "-" +
                   std::to_string(counter++) + ext);
        const int fd = ::open(p.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0) {
            ::close(fd);
            return p;
        }
        if (errno != EEXIST)
            throw Failure("cannot write " + target.string() + ": " + std::strerror(errno));
    }
}

void removeQuietly(const fs::path& p) {
    std::error_code ec;
    if (!p.empty()) fs::remove(p, ec);
}

/** Throws a Failure unless outPath can be a video: a known extension, an existing writable
folder, not a folder itself. */
void checkVideoOutput(const fs::path& out) {
    const std::string path = out.string();
    std::error_code ec;
    if (fs::is_directory(out, ec)) throw Failure("cannot write " + path + ": is a folder");
    if (!isVideoPath(path))
        throw Failure("cannot write " + path + ": unknown video extension '" +
                      out.extension().string() + "' (use .mp4, .m4v, .mov, .mkv, .avi or .webm)");
    const fs::path dir = out.has_parent_path() ? out.parent_path() : fs::path(".");
    if (!fs::is_directory(dir, ec))
        throw Failure("cannot write " + path + ": no folder " + dir.string());
    if (::access(dir.c_str(), W_OK | X_OK) != 0)
        throw Failure("cannot write " + path + ": folder " + dir.string() + " is not writable");
}

}  // namespace

bool isVideoPath(const std::string& path) {
    const std::string ext = lowerExtension(path);
    for (const char* e : {".mp4", ".m4v", ".mov", ".mkv", ".avi", ".webm"})
        if (ext == e) return true;
    return false;
}

// ---- ClipReader ---------------------------------------------------------------------------

ClipReader::ClipReader(const std::string& path) : path_(path) {
    silenceLibav();
    const ClipProbe p = probeClip(path);
    if (p.videoStream < 0) throw Failure(path + ": has no video track");
    info_.frameCount = p.videoFrames > 0 && p.videoFrames <= INT_MAX ? int(p.videoFrames) : -1;
    info_.hasAudio = !p.audioStreams.empty();
    try {
        const QuietOpenCV quiet;
        if (!capture_.open(path, cv::CAP_FFMPEG))
            throw Failure(path + ": not a video OpenCV's FFmpeg backend can read");
        info_.fps = capture_.get(cv::CAP_PROP_FPS);
        if (!(info_.fps > 0) || !std::isfinite(info_.fps))
            throw Failure(path + ": the video does not say its frame rate");
        if (!capture_.read(first_) || first_.empty())
            throw Failure(path + ": the video has no frames");
    } catch (const cv::Exception& e) {
        throw Failure(path + ": " + e.err);
    }
    // OpenCV's FFmpeg backend converts every pixel format to 8-bit BGR.
    if (first_.type() != CV_8UC3)
        throw Failure(path + ": OpenCV decodes it as " + cv::typeToString(first_.type()) +
                      ", not 8-bit BGR");
    info_.size = first_.size();
}

bool ClipReader::read(cv::Mat& frame) {
    if (ended_) return false;
    if (!first_.empty()) {
        frame = first_;
        first_ = cv::Mat();
    } else if (!capture_.read(frame) || frame.empty()) {
        ended_ = true;
        return false;
    }
    if (frame.size() != info_.size || frame.type() != CV_8UC3)
        throw Failure(path_ + ": frame " + std::to_string(framesRead_ + 1) + " is " +
                      sizeText(frame.size()) + ", the first one " + sizeText(info_.size) +
                      " (clips that change size are not supported)");
    ++framesRead_;
    return true;
}

// ---- ClipWriter ---------------------------------------------------------------------------

ClipWriter::ClipWriter(const std::string& outPath, double fps, cv::Size size,
                       const std::string& audioFrom)
    : out_(outPath),
      audioFrom_(audioFrom),
      fps_(fps),
      size_(size),
      encoded_((size.width + 1) & ~1, (size.height + 1) & ~1) {
    silenceLibav();
    checkVideoOutput(out_);
    if (!(fps > 0) || size.width <= 0 || size.height <= 0)
        throw Failure("cannot write " + outPath + ": no frame rate or frame size given");
    if (!audioFrom.empty()) audioStreams_ = probeClip(audioFrom).audioStreams;

    // OpenCV writes .webm with a warning on stderr about VP8's tag: it writes Matroska here,
    // and finish() remuxes it into WebM (a subset of Matroska).
    const std::string ext = lowerExtension(out_);
    videoTemp_ = reserveTemp(out_, ext == ".webm" ? ".mkv" : ext);
    std::vector<std::string> codecs = {"avc1", "mp4v"};
    if (ext == ".avi") codecs = {"MJPG"};
    if (ext == ".webm") codecs = {"VP80"};
    try {
        const QuietOpenCV quiet;
        for (const std::string& c : codecs)
            if (writer_.open(videoTemp_.string(), cv::CAP_FFMPEG,
                             cv::VideoWriter::fourcc(c[0], c[1], c[2], c[3]), fps, encoded_, true))
                return;
    } catch (const cv::Exception&) {
    }
    removeQuietly(videoTemp_);
    std::string tried;
    for (const std::string& c : codecs) tried += (tried.empty() ? "" : ", ") + c;
    throw Failure("cannot write " + outPath + ": OpenCV's video I/O cannot open a " +
                  sizeText(encoded_) + " " + ext + " writer here (tried " + tried + ")");
}

ClipWriter::~ClipWriter() {
    if (finished_) return;
    writer_.release();
    removeQuietly(videoTemp_);
    removeQuietly(muxTemp_);
}

void ClipWriter::write(const cv::Mat& frame) {
    if (finished_) throw Failure("cannot write " + out_.string() + ": the video is finished");
    if (frame.type() != CV_8UC3 || frame.size() != size_)
        throw Failure("cannot write " + out_.string() + ": frame " +
                      std::to_string(framesWritten_ + 1) + " is " + cv::typeToString(frame.type()) +
                      " " + sizeText(frame.size()) + ", not 8-bit BGR " + sizeText(size_));
    if (encoded_ == size_) {
        writer_.write(frame);
    } else {
        cv::Mat padded;
        cv::copyMakeBorder(frame, padded, 0, encoded_.height - size_.height, 0,
                           encoded_.width - size_.width, cv::BORDER_REPLICATE);
        writer_.write(padded);
    }
    ++framesWritten_;
}

std::string ClipWriter::finish() {
    if (finished_) return "";
    const std::string path = out_.string();
    writer_.release();
    std::error_code ec;
    if (framesWritten_ == 0) throw Failure("cannot write " + path + ": no frames were given");
    if (fs::file_size(videoTemp_, ec) == 0 || ec)
        throw Failure("cannot write " + path + ": the video encoder wrote nothing");

    std::vector<std::string> notes;
    if (encoded_ != size_)
        notes.push_back("frames padded from " + sizeText(size_) + " to " + sizeText(encoded_) +
                        " (edge pixels repeated: the codec needs even sizes)");
    fs::path result = videoTemp_;
    // Without audio the file OpenCV wrote is the output, unless its container is a stand-in.
    if (!audioStreams_.empty() || lowerExtension(videoTemp_) != lowerExtension(out_)) {
        if (muxTemp_.empty()) muxTemp_ = reserveTemp(out_, lowerExtension(out_));
        try {
            for (std::string& note : remuxWithAudio(videoTemp_, audioFrom_, audioStreams_, muxTemp_,
                                                    framesWritten_, fps_))
                notes.push_back(std::move(note));
        } catch (const Failure& e) {
            throw Failure("cannot write " + path + ": " + e.what());
        }
        result = muxTemp_;
    }
    fs::rename(result, out_, ec);
    if (ec) throw Failure("cannot write " + path + ": " + ec.message());
    finished_ = true;
    removeQuietly(videoTemp_ == result ? fs::path() : videoTemp_);
    return joinNotes(notes);
}

}  // namespace multicage_cli

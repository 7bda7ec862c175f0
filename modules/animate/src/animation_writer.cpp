// Animation output: PNG frames, video through OpenCV's videoio, GIF through giflib. Every
// writer works on a temporary file or folder beside the target and renames it at the end.
#if MULTICAGE_HAVE_GIF
#include <gif_lib.h>
#endif
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/multicage/animate.hpp>
#include <opencv2/videoio.hpp>
#include <regex>

namespace cv {
namespace multicage {

namespace fs = std::filesystem;

namespace {
bool endsWithSlash(const std::string& p) {
    return !p.empty() && (p.back() == '/' || p.back() == '\\');
}

std::string lowerExtension(const fs::path& p) {
    std::string e = p.extension().string();
    for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return e;
}

// The folder path without trailing slashes ("out/" -> "out").
fs::path folderPath(const std::string& path) {
    std::string p = path;
    while (p.size() > 1 && endsWithSlash(p)) p.pop_back();
    return fs::path(p);
}

bool isFrameName(const std::string& name) {
    static const std::regex frame("frame_[0-9]{4,}\\.png");
    return std::regex_match(name, frame);
}

// "dir/.name.tmp-PID-N.ext": hidden, unique, the same folder (so rename is atomic), and the
// same extension (videoio picks the container from it).
fs::path tempSibling(const fs::path& target, const std::string& ext) {
    static std::atomic<int> counter{0};
    const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
    return dir / ("." + target.filename().string() + ".tmp-" + std::to_string(::getpid()) + "-" +
                  std::to_string(counter++) + ext);
}

void checkFolderWritable(const fs::path& dir, const std::string& path) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec))
        CV_Error(Error::StsBadArg, "cannot write " + path + ": no folder " + dir.string());
    if (::access(dir.c_str(), W_OK | X_OK) != 0)
        CV_Error(Error::StsBadArg,
                 "cannot write " + path + ": folder " + dir.string() + " is not writable");
}

// Whether float frames hold values in [0, 1] (scaled up to integers) or 0-255, decided on the
// first frame so that every frame is scaled alike. Lossy float codecs (TIFF's SGILOG) overshoot
// 1 a little: up to 2 still counts as [0, 1], as in convertForImageFormat().
bool unitFloatRange(const Mat& frame) {
    double lo, hi;
    minMaxLoc(frame.reshape(1), &lo, &hi);
    return hi <= 2.0;
}

// 8-bit BGR for video and GIF. floatScale: 0 until the first float frame decides it.
Mat toBgr8(const Mat& frame, double& floatScale, std::string& note) {
    Mat m = frame;
    if (m.depth() == CV_16U) {
        m.convertTo(m, CV_8U, 1.0 / 257);
        if (note.empty()) note = "the 16-bit frames were scaled by 1/257 to 8 bits";
    } else if (m.depth() == CV_32F || m.depth() == CV_64F) {
        if (floatScale <= 0) {
            const bool unit = unitFloatRange(m);
            floatScale = unit ? 255.0 : 1.0;
            note = unit ? "the float frames (values 0-1) were scaled by 255 to 8 bits"
                        : "the float frames (values taken as 0-255) were stored as 8 bits";
        }
        m.convertTo(m, CV_8U, floatScale);
    } else if (m.depth() != CV_8U) {
        CV_Error(Error::StsBadArg, "animation frames must be 8-bit, 16-bit or float images");
    }
    if (m.channels() == 1)
        cvtColor(m, m, COLOR_GRAY2BGR);
    else if (m.channels() == 4)
        cvtColor(m, m, COLOR_BGRA2BGR);
    else if (m.channels() != 3)
        CV_Error(Error::StsBadArg, "animation frames must have 1, 3 or 4 channels");
    return m;
}

class WriterBase : public AnimationWriter {
  public:
    WriterBase(int format, double fps) : format_(format), fps_(fps) {}
    int frameCount() const override { return frames_; }
    int format() const override { return format_; }
    String note() const override { return note_; }
    void write(InputArray frameIn) override {
        CV_Assert(!finished_);
        const Mat frame = frameIn.getMat();
        if (frame.empty()) CV_Error(Error::StsBadArg, "AnimationWriter::write: empty frame");
        if (frames_ == 0)
            size_ = frame.size();
        else if (frame.size() != size_)
            CV_Error(Error::StsBadArg, "AnimationWriter::write: frame " + std::to_string(frames_) +
                                           " is " + std::to_string(frame.cols) + "x" +
                                           std::to_string(frame.rows) + ", the first was " +
                                           std::to_string(size_.width) + "x" +
                                           std::to_string(size_.height));
        writeFrame(frame);
        ++frames_;
    }
    void finish() override {
        CV_Assert(!finished_);
        if (frames_ == 0)
            CV_Error(Error::StsBadArg, "AnimationWriter::finish: no frames were written");
        commit();
        finished_ = true;
    }

  protected:
    virtual void writeFrame(const Mat& frame) = 0;
    virtual void commit() = 0;
    int format_;
    double fps_;
    int frames_ = 0;
    bool finished_ = false;
    Size size_;
    std::string note_;
    double floatScale_ = 0;  // float frames: decided on the first one
};

// ---- PNG frames in a folder ----------------------------------------------------------
class FramesWriter : public WriterBase {
  public:
    FramesWriter(const std::string& path, double fps)
        : WriterBase(ANIMATION_FRAMES, fps),
          target_(folderPath(path)),
          temp_(tempSibling(target_, "")) {
        fs::create_directory(temp_);
    }
    ~FramesWriter() override {
        std::error_code ec;
        if (!finished_) fs::remove_all(temp_, ec);
    }

  protected:
    void writeFrame(const Mat& frame) override {
        char name[32];
        std::snprintf(name, sizeof(name), "frame_%04d.png", frames_);
        const std::string file = (temp_ / name).string();
        Mat stored = frame;
        if (frame.depth() == CV_32F || frame.depth() == CV_64F) {  // PNG: 8 or 16 bits
            if (floatScale_ <= 0) {
                const bool unit = unitFloatRange(frame);
                floatScale_ = unit ? 65535.0 : 257.0;
                note_ = unit ? "PNG does not store float pixels: the float frames (values 0-1) "
                               "were scaled by "
                               "65535 to 16 bits"
                             : "PNG does not store float pixels: the float frames (values taken as "
                               "0-255) were "
                               "scaled by 257 to 16 bits";
            }
            frame.convertTo(stored, CV_16U, floatScale_);
        }
        if (!imwrite(file, stored, {IMWRITE_PNG_COMPRESSION, 1}))
            CV_Error(Error::StsError, "cannot write " + file);
    }
    void commit() override {
        std::error_code ec;
        if (!fs::exists(target_, ec)) {
            fs::rename(temp_, target_);
            return;
        }
        // Replace an earlier render: move it aside, move the new one in, drop the old one.
        const fs::path old = tempSibling(target_, ".old");
        fs::rename(target_, old);
        fs::rename(temp_, target_);
        fs::remove_all(old, ec);
    }

  private:
    fs::path target_, temp_;
};

// ---- video through OpenCV's videoio ---------------------------------------------------
class VideoFileWriter : public WriterBase {
  public:
    VideoFileWriter(const std::string& path, int format, double fps)
        : WriterBase(format, fps),
          target_(path),
          temp_(tempSibling(target_, lowerExtension(target_))) {}
    ~VideoFileWriter() override {
        writer_.release();
        std::error_code ec;
        if (!finished_) fs::remove(temp_, ec);
    }

  protected:
    void writeFrame(const Mat& frame) override {
        Mat bgr = toBgr8(frame, floatScale_, note_);
        if (frames_ == 0) {
            open(bgr.size());
            if (encoded_ != bgr.size())
                note_ += std::string(note_.empty() ? "" : "; ") + "frames padded from " +
                         std::to_string(bgr.cols) + "x" + std::to_string(bgr.rows) + " to " +
                         std::to_string(encoded_.width) + "x" + std::to_string(encoded_.height) +
                         " (edge pixels repeated: the codec needs even sizes)";
        }
        if (bgr.size() != encoded_)
            copyMakeBorder(bgr, bgr, 0, encoded_.height - bgr.rows, 0, encoded_.width - bgr.cols,
                           BORDER_REPLICATE);
        writer_.write(bgr);
    }
    void commit() override {
        writer_.release();
        std::error_code ec;
        if (fs::file_size(temp_, ec) == 0 || ec)
            CV_Error(Error::StsError, "the video encoder wrote nothing to " + target_.string());
        fs::rename(temp_, target_);
    }

  private:
    void open(Size size) {
        // H.264, MPEG-4 and FFmpeg's Motion JPEG store 4:2:0 chroma and would drop an odd
        // last column or row: pad to even sizes instead.
        encoded_ = Size((size.width + 1) & ~1, (size.height + 1) & ~1);
        std::vector<std::string> codecs;
        if (format_ == ANIMATION_MP4)
            codecs = {"avc1", "mp4v"};
        else
            codecs = {"MJPG"};
        for (const std::string& c : codecs) {
            if (writer_.open(temp_.string(), CAP_FFMPEG,
                             VideoWriter::fourcc(c[0], c[1], c[2], c[3]), fps_, encoded_, true))
                return;
        }
        std::error_code ec;
        fs::remove(temp_, ec);
        std::string list;
        for (const std::string& c : codecs) list += (list.empty() ? "" : " or ") + c;
        CV_Error(Error::StsError,
                 "cannot write " + target_.string() + ": OpenCV's video I/O has no " + list +
                     " encoder here (write a .gif or a folder of PNG frames instead)");
    }
    fs::path target_, temp_;
    VideoWriter writer_;
    Size encoded_;
};

#if MULTICAGE_HAVE_GIF
// ---- GIF through giflib -----------------------------------------------------------------
// One palette for the whole animation: k-means on the first frame's colours (a deformation
// moves pixels, it makes no new colours), a 64^3 lookup cube from colour to palette index,
// index 255 reserved as the transparent "unchanged since the last frame" colour.
class GifWriter : public WriterBase {
  public:
    GifWriter(const std::string& path, double fps)
        : WriterBase(ANIMATION_GIF, fps), target_(path), temp_(tempSibling(target_, ".gif")) {}
    ~GifWriter() override {
        close();
        std::error_code ec;
        if (!finished_) fs::remove(temp_, ec);
    }

  protected:
    void writeFrame(const Mat& frame) override {
        const Mat bgr = toBgr8(frame, floatScale_, note_);
        if (frames_ == 0) open(bgr);
        Mat index(bgr.size(), CV_8U);
        parallel_for_(Range(0, bgr.rows), [&](const Range& r) {
            for (int y = r.start; y < r.end; ++y) {
                const Vec3b* in = bgr.ptr<Vec3b>(y);
                uchar* out = index.ptr<uchar>(y);
                for (int x = 0; x < bgr.cols; ++x)
                    out[x] = cube_[(in[x][2] >> 2) << 12 | (in[x][1] >> 2) << 6 | (in[x][0] >> 2)];
            }
        });
        // Later frames: only the rectangle that changed, unchanged pixels transparent.
        Rect box(0, 0, index.cols, index.rows);
        Mat pixels = index;
        if (frames_ > 0) {
            Mat changed = index != previous_;
            box = boundingRect(changed);
            if (box.empty()) box = Rect(0, 0, 1, 1);
            pixels = index(box).clone();
            pixels.setTo(kTransparent, ~changed(box));
        }
        // Delays are in 1/100 s: round the running total so the length stays right.
        const int delay = static_cast<int>(std::lround((frames_ + 1) * 100.0 / fps_) -
                                           std::lround(frames_ * 100.0 / fps_));
        GraphicsControlBlock gcb;
        gcb.DisposalMode = DISPOSE_DO_NOT;
        gcb.UserInputFlag = false;
        gcb.DelayTime = std::max(delay, 2);  // viewers slow down anything faster than 2/100 s
        gcb.TransparentColor = frames_ > 0 ? kTransparent : NO_TRANSPARENT_COLOR;
        GifByteType ext[4];
        EGifGCBToExtension(&gcb, ext);
        check(EGifPutExtension(gif_, GRAPHICS_EXT_FUNC_CODE, 4, ext));
        check(EGifPutImageDesc(gif_, box.x, box.y, box.width, box.height, false, nullptr));
        for (int y = 0; y < pixels.rows; ++y)
            check(EGifPutLine(gif_, pixels.ptr<GifPixelType>(y), pixels.cols));
        previous_ = index;
    }
    void commit() override {
        close();
        // giflib creates the file 0600; give it the permissions of any new file.
        const mode_t mask = ::umask(0);
        ::umask(mask);
        fs::permissions(temp_, static_cast<fs::perms>(0666 & ~mask));
        fs::rename(temp_, target_);
    }

  private:
    static constexpr int kTransparent = 255;

    void check(int status) {
        if (status != GIF_ERROR) return;
        const int code = gif_ ? gif_->Error : 0;
        CV_Error(Error::StsError,
                 "cannot write " + target_.string() + ": " +
                     (GifErrorString(code) ? GifErrorString(code) : "giflib error"));
    }

    void close() {
        if (!gif_) return;
        int error = 0;
        const int status = EGifCloseFile(gif_, &error);  // frees gif_ either way
        gif_ = nullptr;
        if (status == GIF_ERROR)
            CV_Error(Error::StsError,
                     "cannot write " + target_.string() + ": " + GifErrorString(error));
    }

    void open(const Mat& bgr) {
        if (bgr.cols > 65535 || bgr.rows > 65535)
            CV_Error(Error::StsBadArg, "GIF frames are at most 65535 pixels wide");
        // Palette: k-means++ on up to 20000 pixels of the first frame (a fixed stride, so the
        // result does not depend on a random seed).
        const int total = static_cast<int>(bgr.total());
        const int stride = std::max(1, total / 20000);
        Mat samples(0, 3, CV_32F);
        const Mat flat = bgr.reshape(3, 1);
        for (int i = 0; i < total; i += stride) {
            const Vec3b c = flat.at<Vec3b>(0, i);
            const float row[3] = {float(c[0]), float(c[1]), float(c[2])};
            samples.push_back(Mat(1, 3, CV_32F, const_cast<float*>(row)));
        }
        const int k = std::min(kTransparent, samples.rows);
        Mat labels, centres;
        const uint64 saved = theRNG().state;
        theRNG().state = 0x6d756c7469636167ULL;  // deterministic k-means++ seeding
        kmeans(samples, k, labels, TermCriteria(TermCriteria::COUNT + TermCriteria::EPS, 8, 0.5), 1,
               KMEANS_PP_CENTERS, centres);
        theRNG().state = saved;
        std::vector<GifColorType> colours(256, GifColorType{0, 0, 0});
        for (int i = 0; i < k; ++i) {
            colours[i].Blue = saturate_cast<uchar>(centres.at<float>(i, 0));
            colours[i].Green = saturate_cast<uchar>(centres.at<float>(i, 1));
            colours[i].Red = saturate_cast<uchar>(centres.at<float>(i, 2));
        }
        // The lookup cube: nearest palette colour to the centre of each 4x4x4 cell.
        cube_.assign(64 * 64 * 64, 0);
        parallel_for_(Range(0, 64), [&](const Range& r) {
            for (int ri = r.start; ri < r.end; ++ri)
                for (int gi = 0; gi < 64; ++gi)
                    for (int bi = 0; bi < 64; ++bi) {
                        const int rr = ri * 4 + 2, gg = gi * 4 + 2, bb = bi * 4 + 2;
                        int best = 0, bestD = INT_MAX;
                        for (int i = 0; i < k; ++i) {
                            const int dr = rr - colours[i].Red, dg = gg - colours[i].Green,
                                      db = bb - colours[i].Blue;
                            const int d = 3 * dr * dr + 4 * dg * dg +
                                          2 * db * db;  // rough perceptual weights
                            if (d < bestD) bestD = d, best = i;
                        }
                        cube_[ri << 12 | gi << 6 | bi] = static_cast<uchar>(best);
                    }
        });

        int error = 0;
        gif_ = EGifOpenFileName(temp_.c_str(), false, &error);
        if (!gif_)
            CV_Error(Error::StsError,
                     "cannot write " + target_.string() + ": " + GifErrorString(error));
        EGifSetGifVersion(gif_, true);
        ColorMapObject* map = GifMakeMapObject(256, colours.data());
        const int status = EGifPutScreenDesc(gif_, bgr.cols, bgr.rows, 8, 0, map);
        GifFreeMapObject(map);
        check(status);
        // NETSCAPE2.0 application extension: repeat forever.
        check(EGifPutExtensionLeader(gif_, APPLICATION_EXT_FUNC_CODE));
        check(EGifPutExtensionBlock(gif_, 11, "NETSCAPE2.0"));
        const unsigned char repeat[3] = {1, 0, 0};
        check(EGifPutExtensionBlock(gif_, 3, repeat));
        check(EGifPutExtensionTrailer(gif_));
    }

    fs::path target_, temp_;
    GifFileType* gif_ = nullptr;
    std::vector<uchar> cube_;
    Mat previous_;
};
#endif  // MULTICAGE_HAVE_GIF
}  // namespace

#if MULTICAGE_HAVE_GIF
constexpr bool kHaveGif = true;
#else
constexpr bool kHaveGif = false;
#endif

int checkAnimationOutput(const String& path) {
    if (path.empty()) CV_Error(Error::StsBadArg, "no output path");
    std::error_code ec;
    if (endsWithSlash(path) || fs::is_directory(path, ec)) {
        const fs::path folder = folderPath(path);
        checkFolderWritable(folder.has_parent_path() ? folder.parent_path() : fs::path("."), path);
        if (fs::exists(folder, ec)) {
            if (!fs::is_directory(folder, ec))
                CV_Error(Error::StsBadArg,
                         "cannot write frames to " + path + ": it is a file, not a folder");
            for (const fs::directory_entry& e : fs::directory_iterator(folder, ec))
                if (!isFrameName(e.path().filename().string()))
                    CV_Error(Error::StsBadArg,
                             "cannot write frames to " + path + ": the folder holds other files (" +
                                 e.path().filename().string() + "); name a new or empty folder");
        }
        return ANIMATION_FRAMES;
    }
    const fs::path p(path);
    const std::string ext = lowerExtension(p);
    int format;
    if (ext == ".mp4")
        format = ANIMATION_MP4;
    else if (ext == ".avi")
        format = ANIMATION_AVI;
    else if (ext == ".gif" && kHaveGif)
        format = ANIMATION_GIF;
    else if (ext == ".gif")
        CV_Error(
            Error::StsNotImplemented,
            "cannot write " + path +
                ": this build of multicage has no GIF writer (giflib was "
                "not found when it was built: install libgif-dev and build again); write .mp4, "
                ".avi or a folder ending in / for PNG frames");
    else
        CV_Error(Error::StsBadArg,
                 "cannot write " + path + ": unknown animation type '" + ext +
                     "' (use .mp4, .avi, .gif, or a folder ending in / for PNG frames)");
    checkFolderWritable(p.has_parent_path() ? p.parent_path() : fs::path("."), path);
    return format;
}

AnimationWriter::~AnimationWriter() = default;

Ptr<AnimationWriter> AnimationWriter::create(const String& path, double fps) {
    if (!(std::isfinite(fps) && fps > 0))
        CV_Error(Error::StsBadArg, "the frame rate must be a positive number");
    switch (checkAnimationOutput(path)) {
        case ANIMATION_FRAMES:
            return makePtr<FramesWriter>(path, fps);
#if MULTICAGE_HAVE_GIF
        case ANIMATION_GIF:
            return makePtr<GifWriter>(path, fps);
#endif
        default:
            return makePtr<VideoFileWriter>(path, checkAnimationOutput(path), fps);
    }
}

}  // namespace multicage
}  // namespace cv

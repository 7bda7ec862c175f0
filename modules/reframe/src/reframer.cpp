// VideoReframer: per frame the tracked multicage, the window and the resize pose; windows and
// poses averaged over nearby frames of the same shot and multicage before each frame is deformed.
#include <chrono>
#include <cmath>
#include <deque>
#include <opencv2/imgproc.hpp>
#include <opencv2/multicage/reframe.hpp>

namespace cv {
namespace multicage {

namespace {

constexpr double kCropSlack = 0.05;  // pixels a window may lie outside the crop kept for it

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// A frame on its way through: tracked, then windowed and bound, then smoothed and deformed.
struct Entry {
    int index = 0, shot = 0, generation = 0;
    Mat frame;
    Multicage cage;  // tracked, on the whole frame
    Rect2d rawWindow, window;
    bool posed = false;
    Rect crop;
    Multicage cropped;
    std::string key;  // the multicage generation and the polygons the crop keeps
    Ptr<Deformer> deformer;
    std::vector<Point2f> rawPose;
};

// The Gaussian weight of a frame d frames away, for a smoothing radius r (standard deviation r/2).
double weight(int d, int r) {
    const double s = std::max(0.5, r / 2.0);
    return std::exp(-0.5 * d * d / (s * s));
}

// Whether the polygons of `cage` posed by `pose` lie in the output frame without crossing or
// changing their nesting, and the mesh folds nowhere.
bool usable(const Multicage& cage, const std::vector<Point2f>& pose, Size newSize,
            const Deformer& deformer) {
    Multicage moved = cage.posed(pose);
    moved.setImageSize(newSize);
    return moved.validateGeometry() && deformer.foldedTriangles(pose) == 0;
}

}  // namespace

struct VideoReframer::Impl {
    Size newSize;
    ReframeParams params;
    Multicage firstCage;
    Ptr<CageTracker> tracker;
    Size frameSize;
    int frameType = -1, shot = 0, generation = 0, sinceProposal = 0, nextOut = 0;
    bool finished = false;
    std::deque<Entry> entries;  // context before nextOut, and the frames still to come out
    std::deque<ReframedFrame> ready;
    ReframeStats stats;

    Multicage propose(const Mat& frame, const std::string& why) {
        const auto t0 = std::chrono::steady_clock::now();
        Multicage cage(frame.size());
        bool constant = false;
        try {
            cage = resizeCage(frame, params.resize);
        } catch (const Exception& e) {
            // A frame with nothing to segment (a black frame of a fade) has no subject: it is
            // cropped plainly, and the next frame is tried (that test is quick).
            if (e.code != Error::StsBadArg) throw;
            constant = true;
        }
        stats.proposeMs += msSince(t0);
        ++stats.proposals, ++generation;
        sinceProposal = constant ? std::max(0, params.retryEmptyEvery - 1) : 0;
        stats.lastWhy = why;
        return cage;
    }

    // The multicage on the next frame: given or proposed on the first, tracked after.
    Multicage cageOn(const Mat& frame) {
        if (!tracker) {
            Multicage cage = firstCage.polygonCount() > 0 ? firstCage.scaled(frame.size())
                                                          : propose(frame, "the first frame");
            if (firstCage.polygonCount() > 0) ++generation;
            tracker = makePtr<CageTracker>(cage, frame, params.track);
            return tracker->multicage();
        }
        const auto t0 = std::chrono::steady_clock::now();
        const TrackReport r = tracker->track(frame);
        stats.trackMs += msSince(t0);
        ++sinceProposal;
        if (r.state == TRACK_CUT) ++stats.cuts, ++shot;
        if (r.state == TRACK_LOST) ++stats.lost;
        const bool retry = tracker->multicage().polygonCount() == 0 && params.retryEmptyEvery > 0 &&
                           sinceProposal >= params.retryEmptyEvery;
        if (r.state != TRACK_OK || retry)
            tracker->reset(propose(frame, retry ? "no subject yet: looking again" : r.why), frame);
        return tracker->multicage();
    }

    int radius() const { return std::max(0, params.smoothing); }

    // How far the average around entry k reaches: up to radius() frames, as far on both sides
    // as the frames `alike` it go (entries are consecutive), so that a subject moving steadily
    // is averaged to where it is, at the ends of a clip, shot or multicage too.
    template <typename Alike>
    int reach(size_t k, Alike alike) const {
        int r = 0;
        while (r < radius() && k >= size_t(r + 1) && k + r + 1 < entries.size() &&
               alike(entries[k - r - 1]) && alike(entries[k + r + 1]))
            ++r;
        return r;
    }

    // The window of entry k: its raw window averaged over the frames of its shot nearby.
    void place(size_t k) {
        Entry& e = entries[k];
        const int r = reach(k, [&](const Entry& o) { return o.shot == e.shot; });
        double sum = 0, x = 0, y = 0, w = 0, h = 0;
        for (const Entry& o : entries) {
            const int d = o.index - e.index;
            if (std::abs(d) > r) continue;
            const double g = weight(d, radius());
            sum += g, x += g * o.rawWindow.x, y += g * o.rawWindow.y;
            w += g * o.rawWindow.width, h += g * o.rawWindow.height;
        }
        e.window = Rect2d(x / sum, y / sum, w / sum, h / sum) &
                   Rect2d(0, 0, frameSize.width, frameSize.height);
        e.crop = windowCrop(e.window, frameSize);
        // A window that stays on a pixel boundary (a still shot through a codec: 106.0, then
        // 105.998) keeps the crop before it where that holds it within kCropSlack: a crop one
        // pixel wider moves the whole picture.
        if (k > 0 && entries[k - 1].shot == e.shot && !entries[k - 1].crop.empty()) {
            const Rect& before = entries[k - 1].crop;
            if (e.window.x >= before.x - kCropSlack && e.window.y >= before.y - kCropSlack &&
                e.window.br().x <= before.br().x + kCropSlack &&
                e.window.br().y <= before.br().y + kCropSlack &&
                std::abs(e.window.width - before.width) < 1 &&
                std::abs(e.window.height - before.height) < 1)
                e.crop = before;
        }
        std::vector<int> kept;
        e.cropped = cropMulticage(e.cage, e.crop, &kept);
        e.key = std::to_string(e.generation);
        for (int i : kept) e.key += "," + std::to_string(i);
        DeformParams deform;
        deform.coordinates = params.resize.coordinates;
        deform.gridStep = params.resize.gridStep;
        deform.backend = params.resize.backend;
        auto t0 = std::chrono::steady_clock::now();
        e.deformer = Deformer::create(e.frame(e.crop), e.cropped, deform);
        stats.bindMs += msSince(t0);
        t0 = std::chrono::steady_clock::now();
        // The crop's own pose, its polygons moved to follow the fractional window where that
        // keeps it valid.
        const std::vector<Point2f> cropPose =
            resizePose(e.cropped, e.deformer->binding(), newSize, params.resize);
        e.rawPose = windowPose(cropPose, newSize, e.crop, e.window);
        if (!usable(e.cropped, e.rawPose, newSize, *e.deformer)) e.rawPose = cropPose;
        stats.poseMs += msSince(t0);
        e.posed = true;
    }

    // Entry k's pose averaged over nearby frames with the same multicage on their crops (the
    // frame corners its own: each crop's frame goes to its own place), then deformed.
    void emit(size_t k) {
        Entry& e = entries[k];
        ReframedFrame out;
        out.pose = e.rawPose;
        const size_t corners = out.pose.size() - 4;
        std::vector<Point2d> sum(corners);
        double total = 0;
        const int r = reach(k, [&](const Entry& o) { return o.posed && o.key == e.key; });
        for (const Entry& o : entries) {
            const int d = o.index - e.index;
            if (std::abs(d) > r) continue;
            const double g = weight(d, radius());
            total += g;
            for (size_t v = 0; v < corners; ++v) sum[v] += g * Point2d(o.rawPose[v]);
        }
        for (size_t v = 0; v < corners; ++v) out.pose[v] = Point2f(sum[v] / total);
        out.smoothed = usable(e.cropped, out.pose, newSize, *e.deformer);
        if (!out.smoothed) out.pose = e.rawPose, ++stats.unsmoothed;
        const auto t0 = std::chrono::steady_clock::now();
        e.deformer->deform(out.pose, out.image);
        stats.deformMs += msSince(t0);
        out.index = e.index, out.shot = e.shot, out.window = e.window, out.crop = e.crop;
        out.cage = e.cropped, out.tracked = e.cage;
        ready.push_back(std::move(out));
        ++stats.framesOut, ++nextOut;
        e.frame.release(), e.deformer.release();
    }

    // Windows, poses and output frames for every entry whose neighbours are known: a window
    // waits for the raw windows `radius` frames ahead, an output frame for their poses.
    void advance() {
        const int r = radius();
        const int newest = entries.empty() ? -1 : entries.back().index;
        int lastPosed = -1;
        for (size_t k = 0; k < entries.size(); ++k) {
            if (!entries[k].posed && (finished || entries[k].index + r <= newest)) place(k);
            if (entries[k].posed) lastPosed = entries[k].index;
        }
        for (size_t k = 0; k < entries.size(); ++k) {
            const Entry& e = entries[k];
            if (e.index < nextOut) continue;
            if (!e.posed || (!finished && lastPosed < e.index + r)) break;
            emit(k);
        }
        while (!entries.empty() && entries.front().index < nextOut - r) entries.pop_front();
    }
};

VideoReframer::VideoReframer(Size newSize, const ReframeParams& params, const Multicage& cage)
    : impl_(makePtr<Impl>()) {
    if (newSize.width < 1 || newSize.height < 1)
        CV_Error(Error::StsBadSize, "multicage: VideoReframer: the output size is empty");
    impl_->newSize = newSize, impl_->params = params, impl_->firstCage = cage;
}

VideoReframer::~VideoReframer() = default;

void VideoReframer::push(InputArray frame) {
    Impl& s = *impl_;
    if (s.finished) CV_Error(Error::StsError, "multicage: VideoReframer: push() after finish()");
    if (frame.empty()) CV_Error(Error::StsBadArg, "multicage: VideoReframer: the frame is empty");
    if (frame.depth() != CV_8U || frame.channels() == 2 || frame.channels() > 4)
        CV_Error(Error::StsBadArg,
                 "multicage: VideoReframer: frames must be 8-bit with 1, 3 or 4 "
                 "channels");
    if (s.frameType < 0) {
        checkResizeSize(frame.size(), s.newSize, s.params.resize.maxScale);
        s.frameSize = frame.size(), s.frameType = frame.type();
    } else if (frame.size() != s.frameSize || frame.type() != s.frameType) {
        CV_Error(Error::StsBadArg,
                 format("multicage: VideoReframer: frame %d is %dx%d, %d channels; the first was "
                        "%dx%d, %d channels",
                        s.stats.framesIn, frame.cols(), frame.rows(), frame.channels(),
                        s.frameSize.width, s.frameSize.height, CV_MAT_CN(s.frameType)));
    }
    Entry e;
    e.frame = frame.getMat().clone();
    e.cage = s.cageOn(e.frame);
    e.index = s.stats.framesIn++, e.shot = s.shot, e.generation = s.generation;
    e.rawWindow = reframeWindow(e.cage, s.newSize, s.params.resize);
    s.entries.push_back(std::move(e));
    s.advance();
}

bool VideoReframer::pop(ReframedFrame& out) {
    if (impl_->ready.empty()) return false;
    out = std::move(impl_->ready.front());
    impl_->ready.pop_front();
    return true;
}

void VideoReframer::finish() {
    impl_->finished = true;
    impl_->advance();
}

int VideoReframer::lag() const {
    return 2 * impl_->radius();
}

Size VideoReframer::size() const {
    return impl_->newSize;
}

const ReframeStats& VideoReframer::stats() const {
    return impl_->stats;
}

}  // namespace multicage
}  // namespace cv

// VideoReframer: a clip to another size or aspect ratio, frame by frame (reframe.hpp), and the
// crop and warp helpers reframe_window() and crop_multicage() (resize.hpp).
#include <mutex>
#include <opencv2/multicage/reframe.hpp>

#include "common.hpp"

namespace multicage_py {
namespace {

using namespace cv::multicage;

/** A VideoReframer behind a mutex: the GIL is released while it tracks, binds and deforms, and
it holds the frames in flight, so Python threads sharing it take turns (as Deformer's). */
struct PyReframer {
    PyReframer(cv::Size size, const ReframeParams& params, const Multicage& cage)
        : reframer(size, params, cage) {}
    VideoReframer reframer;
    std::mutex mutex;
};

/** ReframeParams from keyword arguments: smoothing, retry_empty_every, the resize keywords
(content_aware_resize's, resizeParam) and the track keywords (CageTracker's, trackParam). */
ReframeParams reframeParams(const py::kwargs& kwargs) {
    ReframeParams p;
    for (const auto& item : kwargs) {
        const std::string key = item.first.cast<std::string>();
        const py::handle v = item.second;
        if (key == "smoothing") {
            p.smoothing = intArg(v, key);
            if (p.smoothing < 0)
                throw py::value_error("smoothing: must be >= 0 (0: no smoothing), got " +
                                      std::to_string(p.smoothing));
        } else if (key == "retry_empty_every") {
            p.retryEmptyEvery = intArg(v, key);
            if (p.retryEmptyEvery < 0)
                throw py::value_error("retry_empty_every: must be >= 0 (0: never), got " +
                                      std::to_string(p.retryEmptyEvery));
        } else if (!resizeParam(p.resize, key, v) && !trackParam(p.track, key, v)) {
            throw py::type_error("VideoReframer: unexpected keyword '" + key +
                                 "' (smoothing, retry_empty_every, " + kResizeKeywords + ", " +
                                 kTrackKeywords + ")");
        }
    }
    checkSegmenterPair(p.resize.segmenter, p.resize.segmenterModel);
    return p;
}

py::dict statsDict(const ReframeStats& s) {
    py::dict d;
    d["frames_in"] = s.framesIn;
    d["frames_out"] = s.framesOut;
    d["proposals"] = s.proposals;
    d["cuts"] = s.cuts;
    d["lost"] = s.lost;
    d["unsmoothed"] = s.unsmoothed;
    d["propose_ms"] = s.proposeMs;
    d["track_ms"] = s.trackMs;
    d["bind_ms"] = s.bindMs;
    d["pose_ms"] = s.poseMs;
    d["deform_ms"] = s.deformMs;
    d["last_why"] = s.lastWhy;
    return d;
}

py::dict frameDict(const ReframedFrame& f) {
    py::dict d;
    d["image"] = arrayFromMat(f.image);
    d["index"] = f.index;
    d["shot"] = f.shot;
    d["window"] = py::make_tuple(f.window.x, f.window.y, f.window.width, f.window.height);
    d["crop"] = py::make_tuple(f.crop.x, f.crop.y, f.crop.width, f.crop.height);
    d["cage"] = f.cage;
    d["tracked"] = f.tracked;
    d["pose"] = arrayFromPoints(f.pose);
    d["smoothed"] = f.smoothed;
    return d;
}

/** Throws a ValueError for a multicage without an image size (the functions below read it). */
void checkSized(const Multicage& cage) {
    if (cage.imageSize().empty())
        throw py::value_error(
            "cage: the multicage has no image size; make it with Multicage((width, height)) "
            "or Multicage.for_image(image)");
}

}  // namespace

void defineReframe(py::module_& m) {
    py::class_<PyReframer>(m, "VideoReframer", R"doc(
Reframes a clip to another size or aspect ratio, frame by frame (C++ VideoReframer).

VideoReframer(size, cage=None, **params): frames come out of size (w, h). push(frame) adds the
next frame (uint8, HxW, HxWx3 or HxWx4; every frame of the first's shape); pop() returns the
next output frame as a dict, or None when none is ready: image (h x w, the frames' channels),
index (the input frame's, 0 first), shot (a cut starts the next), window (x, y, w, h: the part
of the input frame shown, smoothed over time), crop (x, y, w, h: the whole pixels bound),
cage (the multicage on the crop, at rest), tracked (the one on the whole frame), pose (cage's
vertices on the output, frame corners last, float32) and smoothed (False where the frame's own
pose was used). Frames come out lag
frames after they go in; finish() marks the end of the clip and lets the last ones out.
reframe(frames) does all of it as a generator of output images.

On the first frame (cage, or a proposal: content_aware_resize's), at every cut and where a
subject is lost, the multicage is proposed afresh; otherwise it is tracked (CageTracker), and
windows and poses are averaged over nearby frames so that subjects glide instead of jumping.
params: smoothing (6 frames each side; 0: none, no lag), retry_empty_every (30 frames), the
keywords of content_aware_resize (coordinates, grid_step (2 here), backend, protect, margin,
segmenter, segmenter_model, max_scale, max_warp) and those of CageTracker (points_per_polygon,
min_agreement, min_points, agreement_px, max_round_trip_px, min_histogram_correlation,
max_thumbnail_difference, working_size).
stats: what was done so far and where the time went (docs/video/README.md).
)doc")
        .def(py::init(
                 [](const py::handle& size, const py::object& cageObj, const py::kwargs& kwargs) {
                     const cv::Size newSize = sizeFromObject(size, "size");
                     Multicage cage;
                     if (!cageObj.is_none()) cage = multicageArg(cageObj, "cage");
                     return new PyReframer(newSize, reframeParams(kwargs), cage);
                 }),
             py::arg("size"), py::arg("cage") = py::none())
        .def(
            "push",
            [](PyReframer& self, const py::handle& frame) {
                py::object keep;
                const cv::Mat image = imageFromArray(frame, "frame", keep);
                py::gil_scoped_release release;
                std::lock_guard<std::mutex> lock(self.mutex);
                self.reframer.push(image);
            },
            py::arg("frame"),
            "Adds the next frame of the clip (uint8, 1, 3 or 4 channels, the first's shape); "
            "tracks it, and deforms the frames that are then ready to pop().")
        .def(
            "pop",
            [](PyReframer& self) -> py::object {
                ReframedFrame out;
                bool got;
                {
                    py::gil_scoped_release release;
                    std::lock_guard<std::mutex> lock(self.mutex);
                    got = self.reframer.pop(out);
                }
                if (!got) return py::none();
                return frameDict(out);
            },
            "The next output frame as a dict (image, index, shot, window, crop, cage, pose, "
            "smoothed), or None when none is ready (push more, or finish()).")
        .def(
            "finish",
            [](PyReframer& self) {
                py::gil_scoped_release release;
                std::lock_guard<std::mutex> lock(self.mutex);
                self.reframer.finish();
            },
            "Marks the end of the clip: every frame pushed is deformed and ready to pop(); "
            "push() after it raises multicage.Error.")
        .def_property_readonly(
            "lag", [](const PyReframer& self) { return self.reframer.lag(); },
            "How many frames the output runs behind the input (2 x smoothing).")
        .def_property_readonly(
            "size", [](const PyReframer& self) { return sizeTuple(self.reframer.size()); },
            "The output size (width, height).")
        .def_property_readonly(
            "stats",
            [](PyReframer& self) {
                ReframeStats s;
                {
                    py::gil_scoped_release release;
                    std::lock_guard<std::mutex> lock(self.mutex);
                    s = self.reframer.stats();
                }
                return statsDict(s);
            },
            "What was done so far, and where the time went, as a dict: frames_in, frames_out, "
            "proposals, cuts, lost, unsmoothed, propose_ms, track_ms, bind_ms, pose_ms, "
            "deform_ms (milliseconds, summed), last_why (why the last proposal was made).");

    m.def(
        "reframe_window",
        [](const Multicage& cage, const py::handle& size, const py::handle& maxWarp) {
            checkSized(cage);
            const cv::Size newSize = sizeFromObject(size, "size");
            ResizeParams params;
            params.maxWarp = numberArg(maxWarp, "max_warp");
            const cv::Rect2d w = reframeWindow(cage, newSize, params);
            return py::make_tuple(w.x, w.y, w.width, w.height);
        },
        py::arg("cage"), py::arg("size"), py::arg("max_warp") = 1.5,
        R"doc(The part (x, y, w, h) of an image bound to cage that an output of size (w, h) shows.

The whole image (0, 0, W, H) when the two scales of the frame differ by at most max_warp (below
1: never a window); otherwise a window of the target's aspect or wider, holding the outlines (or
the faces and features of a wider one), in pixel edges, fractional. content_aware_resize and
VideoReframer crop to it and warp the rest.)doc");
    m.def(
        "crop_multicage",
        [](const Multicage& cage, const py::handle& cropObj) {
            checkSized(cage);
            if (py::isinstance<py::str>(cropObj) || !py::isinstance<py::sequence>(cropObj) ||
                py::len(cropObj) != 4)
                throw py::type_error("crop: expected (x, y, w, h), got " + shortValue(cropObj));
            const py::sequence s = py::reinterpret_borrow<py::sequence>(cropObj);
            const cv::Rect crop(intArg(s[0], "crop x"), intArg(s[1], "crop y"),
                                intArg(s[2], "crop w"), intArg(s[3], "crop h"));
            const cv::Size image = cage.imageSize();
            if (crop.width < 1 || crop.height < 1 || crop.x < 0 || crop.y < 0 ||
                crop.x > image.width - crop.width || crop.y > image.height - crop.height)
                throw py::value_error(
                    "crop: (" + std::to_string(crop.x) + ", " + std::to_string(crop.y) + ", " +
                    std::to_string(crop.width) + ", " + std::to_string(crop.height) +
                    ") is not a non-empty rectangle inside the " + sizeString(image) + " image");
            return cropMulticage(cage, crop);
        },
        py::arg("cage"), py::arg("crop"),
        R"doc(The multicage on a crop (x, y, w, h) of its image (integers, inside it).

Each polygon inside the crop (half a pixel within it), moved to the crop's pixels; a polygon
the crop cuts is dropped, so what it held becomes an outline of its own. Oriented, of image size
(w, h), with the cage's coordinates.)doc");
}

}  // namespace multicage_py

// CageTracker: a multicage that follows its subject through a clip (track.hpp).
#include <opencv2/multicage/track.hpp>

#include "common.hpp"

namespace multicage_py {

using namespace cv::multicage;

const char* const kTrackKeywords =
    "points_per_polygon, min_agreement, min_points, agreement_px, max_round_trip_px, "
    "min_histogram_correlation, max_thumbnail_difference, working_size";

bool trackParam(TrackParams& p, const std::string& key, const py::handle& v) {
    if (key == "points_per_polygon")
        p.pointsPerPolygon = intArg(v, key);
    else if (key == "min_agreement")
        p.minAgreement = numberArg(v, key);
    else if (key == "min_points")
        p.minPoints = intArg(v, key);
    else if (key == "agreement_px")
        p.agreementPx = numberArg(v, key);
    else if (key == "max_round_trip_px")
        p.maxRoundTripPx = numberArg(v, key);
    else if (key == "min_histogram_correlation")
        p.minHistogramCorrelation = numberArg(v, key);
    else if (key == "max_thumbnail_difference")
        p.maxThumbnailDifference = numberArg(v, key);
    else if (key == "working_size")
        p.workingSize = intArg(v, key);
    else
        return false;
    return true;
}

namespace {

/** TrackParams from keyword arguments named as its fields, in snake case. */
TrackParams trackParams(const py::kwargs& kwargs) {
    TrackParams p;
    for (const auto& item : kwargs) {
        const std::string key = item.first.cast<std::string>();
        if (!trackParam(p, key, item.second))
            throw py::type_error("CageTracker: unexpected keyword '" + key + "' (" +
                                 kTrackKeywords + ")");
    }
    return p;
}

const char* stateName(TrackState s) {
    return s == TRACK_OK ? "ok" : s == TRACK_CUT ? "cut" : "lost";
}

}  // namespace

void defineTrack(py::module_& m) {
    py::class_<CageTracker>(m, "CageTracker", R"doc(
A multicage that follows its subject from frame to frame of a clip (C++ CageTracker).

CageTracker(cage, frame, **params): cage lies on frame (uint8, HxW, HxWx3 or HxWx4).
track(frame) moves each polygon with what it encloses and returns a dict: state ('ok',
'cut' or 'lost'), lost (polygon indices), histogram_correlation, thumbnail_difference and why.
Unless the state is 'ok' nothing moved: propose again and call reset(cage, frame). multicage is
the cage on the last frame. params: points_per_polygon, min_agreement, min_points,
agreement_px, max_round_trip_px, min_histogram_correlation, max_thumbnail_difference,
working_size (docs/video/README.md).
)doc")
        .def(py::init([](const Multicage& cage, const py::handle& frame, const py::kwargs& kwargs) {
                 py::object keep;
                 const cv::Mat image = imageFromArray(frame, "frame", keep);
                 const TrackParams params = trackParams(kwargs);
                 py::gil_scoped_release release;
                 return new CageTracker(cage, image, params);
             }),
             py::arg("cage"), py::arg("frame"))
        .def(
            "track",
            [](CageTracker& self, const py::handle& frame) {
                py::object keep;
                const cv::Mat image = imageFromArray(frame, "frame", keep);
                TrackReport r;
                {
                    py::gil_scoped_release release;
                    r = self.track(image);
                }
                py::dict d;
                d["state"] = stateName(r.state);
                d["lost"] = r.lost;
                d["histogram_correlation"] = r.histogramCorrelation;
                d["thumbnail_difference"] = r.thumbnailDifference;
                d["why"] = r.why;
                return d;
            },
            py::arg("frame"))
        .def(
            "reset",
            [](CageTracker& self, const Multicage& cage, const py::handle& frame) {
                py::object keep;
                const cv::Mat image = imageFromArray(frame, "frame", keep);
                py::gil_scoped_release release;
                self.reset(cage, image);
            },
            py::arg("cage"), py::arg("frame"))
        .def_property_readonly("multicage",
                               [](const CageTracker& self) { return self.multicage(); });
    m.def(
        "carry_pose",
        [](const Multicage& from, const py::handle& pose, const Multicage& to) {
            return arrayFromPoints(carryPose(from, pointsFromArray(pose, "pose"), to));
        },
        py::arg("from_cage"), py::arg("pose"), py::arg("to_cage"),
        "A pose drawn on from_cage's frame, carried to where the same multicage lies on another "
        "frame (to_cage, e.g. CageTracker.multicage): each polygon's posed vertices move by its "
        "similarity (C++ carryPose). Nx2 float32, as many points as pose.");
}

}  // namespace multicage_py

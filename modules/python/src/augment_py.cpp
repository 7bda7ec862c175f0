// random_pose() and validate_pose(): random poses for data augmentation (augment.hpp).
#include <random>

#include "common.hpp"

namespace multicage_py {
namespace {

using namespace cv::multicage;

/** splitmix64 (Steele, Lea, Flood 2014): cv::RNG is a multiply-with-carry generator whose first
draws from seeds s and s + 1 are nearly equal, so the seed a user gives is mixed first: seeds
0, 1, 2, ... then give unrelated poses. */
uint64_t mixSeed(uint64_t x) {
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    x ^= x >> 31;
    return x ? x : 1;  // cv::RNG treats 0 as "use the default state"
}

/** A seed: a non-negative Python int (any size: taken modulo 2**64) or a numpy integer; None
draws one from the operating system. */
uint64_t seedArg(const py::handle& v) {
    if (v.is_none()) {
        std::random_device device;
        return (uint64_t(device()) << 32) ^ device();
    }
    if (py::isinstance<py::bool_>(v) || !PyIndex_Check(v.ptr()))
        throw py::type_error("seed: expected an integer or None, got " + shortValue(v));
    const py::int_ i = py::reinterpret_steal<py::int_>(PyNumber_Index(v.ptr()));
    if (i.attr("__lt__")(0).cast<bool>())
        throw py::value_error("seed: must be >= 0, got " + py::repr(i).cast<std::string>());
    return i.attr("__and__")(py::int_(0xFFFFFFFFFFFFFFFFull)).cast<uint64_t>();
}

/** The poses' multicage from `cage`, `binding` or `deformer`, one of them. */
const Binding* checkBinding(const Multicage& cage, const py::object& bindingObj,
                            const py::object& deformerObj, Binding& storage) {
    if (!bindingObj.is_none() && !deformerObj.is_none())
        throw py::value_error(
            "binding, deformer: give one of them (the mesh fold-over is checked on), not both");
    if (!bindingObj.is_none()) {
        if (!py::isinstance<Binding>(bindingObj))
            throw py::type_error("binding: expected a multicage.Binding, got " +
                                 shortValue(bindingObj));
        storage = bindingObj.cast<const Binding&>();
    } else if (!deformerObj.is_none()) {
        if (!py::hasattr(deformerObj, "binding") || !py::hasattr(deformerObj, "deform_many"))
            throw py::type_error("deformer: expected a multicage.Deformer, got " +
                                 shortValue(deformerObj));
        storage = deformerObj.attr("binding").cast<const Binding&>();
    } else {
        return nullptr;
    }
    if (storage.imageSize != cage.imageSize())
        throw py::value_error(
            "binding: made for a " + sizeString(storage.imageSize) +
            " image but the multicage is " + sizeString(cage.imageSize()) +
            " (a Deformer of a scaled multicage); draw for the "
            "multicage scaled to the image (cage.scaled(size)), or leave binding out");
    return &storage;
}

template <typename T>
void optional(const py::object& v, const char* name, T& field);
template <>
void optional<double>(const py::object& v, const char* name, double& field) {
    if (!v.is_none()) field = numberArg(v, name);
}
template <>
void optional<int>(const py::object& v, const char* name, int& field) {
    if (!v.is_none()) field = intArg(v, name);
}

const char* kRandomPoseDoc =
    R"doc(A smooth random pose of cage: every vertex at most `amplitude` pixels from rest.

random_pose(cage, amplitude, seed=None, *, binding=None, deformer=None, max_rotation=None,
            max_scale=None, jitter=None, frame_margin=None, attempts=None, scale_downs=None,
            check_grid_step=None)

Each polygon moves by its own small rotation, scale and shift, added to the motion of the polygon
containing it (nested polygons move together; polygons close together nearly as one), plus a
small jitter; vertices near the image border move less. Every pose keeps each polygon simple,
the polygons nested as at rest and disjoint, and folds no mesh triangle over: a draw that would
is drawn again, then the amplitude is halved, and at last the rest pose is returned.

seed          an integer: the same seed gives the same pose on every run (seeds 0, 1, 2, ...
              give unrelated poses: the seed is mixed, splitmix64, before it seeds cv::RNG);
              None: a random one
binding       check fold-over on this Binding (the one the poses will deform with) ...
deformer      ... or on this Deformer's binding; neither: a binding of about 160 nodes along
              the longer side, made once per thread and multicage
max_rotation .. check_grid_step: RandomPoseParams (None: the library's defaults: 8 degrees,
              0.08, 0.25 of the amplitude, the amplitude, 8 attempts, 6 halvings, auto)

Returns vertex_count x 2 float32 (no frame corners: the frame stays fixed). The GIL is released
while it draws.)doc";

}  // namespace

void defineAugment(py::module_& m) {
    m.def(
        "random_pose",
        [](const py::object& cageObj, const py::object& amplitudeObj, const py::object& seedObj,
           const py::object& bindingObj, const py::object& deformerObj,
           const py::object& maxRotation, const py::object& maxScale, const py::object& jitter,
           const py::object& frameMargin, const py::object& attempts, const py::object& scaleDowns,
           const py::object& checkGridStep) {
            const Multicage& cage = multicageArg(cageObj, "cage");
            const double amplitude = numberArg(amplitudeObj, "amplitude");
            RandomPoseParams params;
            optional(maxRotation, "max_rotation", params.maxRotation);
            optional(maxScale, "max_scale", params.maxScale);
            optional(jitter, "jitter", params.jitter);
            optional(frameMargin, "frame_margin", params.frameMargin);
            optional(attempts, "attempts", params.attempts);
            optional(scaleDowns, "scale_downs", params.scaleDowns);
            optional(checkGridStep, "check_grid_step", params.checkGridStep);
            cv::RNG rng(mixSeed(seedArg(seedObj)));
            Binding storage;
            const Binding* binding = checkBinding(cage, bindingObj, deformerObj, storage);
            std::vector<cv::Point2f> pose;
            {
                py::gil_scoped_release release;
                pose = binding ? randomPose(cage, *binding, amplitude, rng, params)
                               : randomPose(cage, amplitude, rng, params);
            }
            return arrayFromPoints(pose);
        },
        py::arg("cage"), py::arg("amplitude"), py::arg("seed") = py::none(), py::kw_only(),
        py::arg("binding") = py::none(), py::arg("deformer") = py::none(),
        py::arg("max_rotation") = py::none(), py::arg("max_scale") = py::none(),
        py::arg("jitter") = py::none(), py::arg("frame_margin") = py::none(),
        py::arg("attempts") = py::none(), py::arg("scale_downs") = py::none(),
        py::arg("check_grid_step") = py::none(), kRandomPoseDoc);
    m.def(
        "validate_pose",
        [](const py::object& cageObj, const py::object& pose) {
            const Multicage& cage = multicageArg(cageObj, "cage");
            const std::vector<cv::Point2f> p = pointsFromArray(pose, "pose");
            std::string why;
            const bool ok = validatePose(cage, p, &why);
            return py::make_tuple(ok, why);
        },
        py::arg("cage"), py::arg("pose"),
        "(ok, why): whether pose keeps the multicage valid (every posed polygon simple and inside "
        "the image, none touching another, each nested as at rest); why says what is wrong. "
        "Fold-over is Deformer.folded_triangles(pose).");
}

}  // namespace multicage_py

// The Python module `multicage._multicage`: bindings over the C++ library, nothing more.
// Conventions follow cv2: images are numpy arrays (HxW, HxWx3 BGR, HxWx4 BGRA; uint8, uint16,
// float32), points are Nx2 arrays of (x, y), sizes are (width, height). The GIL is released
// while the library binds, deforms, proposes or computes coordinates.
#include "convert.hpp"

#include <opencv2/multicage.hpp>
#include <pybind11/stl.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <mutex>
#include <sstream>
#include <type_traits>

namespace multicage_py {
namespace {

using namespace cv::multicage;

PyObject* errorType = nullptr;          // multicage.Error, alive as long as the interpreter
PyObject* noObjectErrorType = nullptr;  // multicage.NoObjectFoundError, a multicage.Error

[[noreturn]] void raise(PyObject* type, const std::string& message) {
    PyErr_SetString(type, message.c_str());
    throw py::error_already_set();
}

// --- argument parsing -----------------------------------------------------------------------

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}

/** A short description of a value for messages: its type, and its repr when that is short
(never a whole image array). */
std::string shortValue(const py::handle& v) {
    if (py::isinstance<py::array>(v)) {
        const py::array a = py::reinterpret_borrow<py::array>(v);
        std::string shape = "(";
        for (py::ssize_t i = 0; i < a.ndim(); ++i) shape += (i ? ", " : "") + std::to_string(a.shape(i));
        shape += a.ndim() == 1 ? ",)" : ")";
        return "numpy.ndarray of shape " + shape + " and dtype " + py::str(a.dtype()).cast<std::string>();
    }
    std::string r = py::repr(v).cast<std::string>();
    if (r.size() > 40) r = r.substr(0, 37) + "...";
    return typeName(v) + " " + r;
}

/** Python's int (or a numpy integer) as an int; bool, float and str are TypeErrors, as
Python itself treats them where an index is needed. */
int intArg(const py::handle& v, const std::string& name) {
    if (PyBool_Check(v.ptr()) || !PyIndex_Check(v.ptr()))
        throw py::type_error(name + ": expected an integer, got " + shortValue(v));
    const long long x = PyLong_AsLongLong(py::reinterpret_steal<py::object>(PyNumber_Index(v.ptr())).ptr());
    if (PyErr_Occurred() || x < INT_MIN || x > INT_MAX) {
        PyErr_Clear();
        throw py::value_error(name + ": " + py::repr(v).cast<std::string>() + " is out of range");
    }
    return static_cast<int>(x);
}

/** A real number (int, float, numpy scalar); str, bytes, bool and None are TypeErrors. */
double numberArg(const py::handle& v, const std::string& name) {
    if (PyBool_Check(v.ptr()) || PyUnicode_Check(v.ptr()) || PyBytes_Check(v.ptr()) || v.is_none() ||
        PyComplex_Check(v.ptr()))
        throw py::type_error(name + ": expected a number, got " + shortValue(v));
    const double x = PyFloat_AsDouble(v.ptr());
    if (x == -1.0 && PyErr_Occurred()) {
        PyErr_Clear();
        throw py::type_error(name + ": expected a number, got " + shortValue(v));
    }
    return x;
}

/** True or False (or a numpy bool); 1, 'yes' and None are TypeErrors: a flag is a flag. */
bool boolArg(const py::handle& v, const std::string& name) {
    if (PyBool_Check(v.ptr())) return v.ptr() == Py_True;
    const py::object npBool = py::module_::import("numpy").attr("bool_");
    if (py::isinstance(v, npBool)) return v.cast<bool>();
    throw py::type_error(name + ": expected True or False, got " + shortValue(v));
}

/** A string name, one of the enum's members, or its integer value (not a float: 2.0 is
more likely a mistake than a method). */
int enumFromObject(const py::handle& obj, const char* what,
                   const std::vector<std::pair<std::string, int>>& names, int count) {
    if (py::isinstance<py::str>(obj)) {
        const std::string s = lower(obj.cast<std::string>());
        std::string known;
        for (const auto& n : names) {
            if (n.first == s) return n.second;
            known += (known.empty() ? "'" : ", '") + n.first + "'";
        }
        throw py::value_error(std::string(what) + ": '" + obj.cast<std::string>() + "' is not one of " + known);
    }
    // pybind11 enums convert through int(); ints and numpy integers through __index__.
    const bool isEnum = py::hasattr(obj, "__members__") && py::hasattr(obj, "value");
    if (PyBool_Check(obj.ptr()) || !(isEnum || PyIndex_Check(obj.ptr())))
        throw py::type_error(std::string(what) + ": expected a name or an enum value, got " + shortValue(obj));
    const int v = isEnum ? obj.attr("value").cast<int>() : intArg(obj, what);
    if (v < 0 || v >= count)
        throw py::value_error(std::string(what) + ": " + std::to_string(v) + " is out of range");
    return v;
}

int parseBackend(const py::handle& obj) {
    return enumFromObject(obj, "backend", {{"auto", BACKEND_AUTO}, {"cpu", BACKEND_CPU}, {"gpu", BACKEND_GPU}}, 3);
}

int parseCoordinates(const py::handle& obj) {
    return enumFromObject(obj, "coordinates",
                          {{"mvc", MEAN_VALUE}, {"mean_value", MEAN_VALUE}, {"harmonic", HARMONIC}}, 2);
}

const char* coordinatesName(int c) { return c == HARMONIC ? "harmonic" : "mvc"; }

/** DeformParams from the Python keywords. coordinates None follows the multicage's own
choice (the cage file's `coordinates:`), as `multicage deform` does without --coords. */
DeformParams deformParams(const py::object& coordinates, const py::object& gridStep, const py::object& backend,
                          const py::object& borderValue, const py::object& halfFloat,
                          const py::object& gpuBinding, const py::object& memoryBudget, int cageCoordinates) {
    DeformParams p;
    p.coordinates = coordinates.is_none() ? cageCoordinates : parseCoordinates(coordinates);
    p.gridStep = intArg(gridStep, "grid_step");
    if (p.gridStep < 1) throw py::value_error("grid_step: must be >= 1, got " + std::to_string(p.gridStep));
    p.backend = parseBackend(backend);
    p.borderValue = scalarFromObject(borderValue, "border_value");
    p.halfFloat = boolArg(halfFloat, "half_float");
    // None: the library's default (on the GPU where it is a hardware one); True/False force it.
    p.gpuBinding = gpuBinding.is_none() ? -1 : boolArg(gpuBinding, "gpu_binding") ? 1 : 0;
    if (!memoryBudget.is_none()) {
        const double budget = numberArg(memoryBudget, "memory_budget");
        if (!(budget >= 0) || budget > 9.0e18 || budget != std::floor(budget))
            throw py::value_error("memory_budget: expected a whole number of bytes >= 0 (0: no limit), got " +
                                  py::repr(memoryBudget).cast<std::string>());
        p.memoryBudget = static_cast<size_t>(budget);
    }
    return p;
}

/** The keywords of propose_multicage and friends. They are the CLI's options with '-' as
'_' (`--min-region-area` is min_region_area); min_area is accepted too, as the CLI's older
`--min-area`. */
struct ProposeOptions {
    ProposeParams params;
    /** As `multicage propose`: inner polygons protect the features inside each outline
    (proposeProtectedMulticage) unless protect=False. */
    bool protect = true;
};

const char* kProposeKeywords =
    "method, max_vertices, max_polygon_vertices, max_polygons, max_depth, margin, min_region_area, "
    "working_size, rect, protect, cascade_dir, morphology_radius, grabcut_iterations, grabcut_max_side";

ProposeOptions proposeOptions(const py::kwargs& kwargs, const char* function, bool takesProtect) {
    ProposeOptions o;
    ProposeParams& p = o.params;
    bool haveMinArea = false;
    for (const auto& item : kwargs) {
        const std::string key = item.first.cast<std::string>();
        const py::handle v = item.second;
        if (key == "method") {
            if (py::isinstance<py::str>(v)) {
                p.method = parseProposeMethod(v.cast<std::string>());
                if (p.method < 0)
                    throw py::value_error("method: '" + v.cast<std::string>() +
                                          "' is not one of auto, threshold, adaptive, grabcut, saliency, "
                                          "spectral, mask, labels");
            } else {
                p.method = enumFromObject(v, "method", {}, PROPOSE_LABELS + 1);
            }
        } else if (key == "max_vertices") p.maxVertices = intArg(v, key);
        else if (key == "max_polygon_vertices") p.maxPolygonVertices = intArg(v, key);
        else if (key == "max_polygons") p.maxPolygons = intArg(v, key);
        else if (key == "max_depth") p.maxDepth = intArg(v, key);
        else if (key == "margin") p.margin = static_cast<float>(numberArg(v, key));
        else if (key == "min_region_area" || key == "min_area") {
            if (haveMinArea)
                throw py::type_error(std::string(function) + "() got both min_region_area and min_area "
                                     "(the same keyword; use min_region_area)");
            haveMinArea = true;
            p.minRegionArea = numberArg(v, key);
        } else if (key == "morphology_radius") p.morphologyRadius = intArg(v, key);
        else if (key == "working_size") p.workingSize = intArg(v, key);
        else if (key == "grabcut_iterations") p.grabCutIterations = intArg(v, key);
        else if (key == "grabcut_max_side") p.grabCutMaxSide = intArg(v, key);
        else if (key == "protect" && takesProtect) {
            // True/False as --protect/--no-protect, or a detector name as --protect DETECTOR.
            if (py::isinstance<py::str>(v)) {
                const std::string name = v.cast<std::string>();
                const int detector = parseProtectDetector(name);
                if (detector < 0)
                    throw py::value_error("protect: '" + name + "' is not one of saliency, faces, all");
                o.protect = true;
                p.protect = detector;
            } else {
                o.protect = boolArg(v, key);
            }
        } else if (key == "cascade_dir") {
            if (!py::isinstance<py::str>(v))
                throw py::type_error("cascade_dir: expected a folder name (str), got " + shortValue(v));
            p.cascadeDir = v.cast<std::string>();
        }
        else if (key == "rect") {
            if (py::isinstance<py::str>(v) || !py::isinstance<py::sequence>(v))
                throw py::type_error("rect: expected (x, y, width, height), got " + shortValue(v));
            const py::sequence r = py::reinterpret_borrow<py::sequence>(v);
            if (py::len(r) != 4)
                throw py::value_error("rect: expected (x, y, width, height), got " + std::to_string(py::len(r)) +
                                      " values");
            p.rect = cv::Rect(intArg(r[0], "rect[0]"), intArg(r[1], "rect[1]"), intArg(r[2], "rect[2]"),
                              intArg(r[3], "rect[3]"));
        } else {
            throw py::type_error(std::string(function) + "() got an unexpected keyword argument '" + key +
                                 "' (it takes " + kProposeKeywords + ")");
        }
    }
    if (!std::isfinite(p.margin)) throw py::value_error("margin: must be finite");
    if (!std::isfinite(p.minRegionArea)) throw py::value_error("min_region_area: must be finite");
    return o;
}

/** The multicage `multicage propose` gives for the same options: protected by default, and a
mask or label input (no photo to find features in) only when protect=True is explicit. */
Multicage proposeProtected(const cv::Mat& image, const ProposeOptions& o, bool protectGiven) {
    const bool maskInput = o.params.method == PROPOSE_MASK || o.params.method == PROPOSE_LABELS;
    if (!o.protect || (maskInput && !protectGiven)) return proposeMulticage(image, o.params);
    if (!maskInput) return proposeProtectedMulticage(image, o.params);
    Multicage cage = proposeMulticage(image, o.params);
    const int top = cage.polygonCount();
    for (int p = 0; p < top; ++p)
        if (cage.depth(p) == 1) cage = protectFeatures(image, cage, p, o.params);
    return cage;
}

/** The defaults of the propose keywords: the library's ProposeParams(). */
py::dict proposeDefaults() {
    const ProposeOptions o;
    const ProposeParams& p = o.params;
    py::dict d;
    d["method"] = proposeMethodName(p.method);
    d["max_vertices"] = p.maxVertices;
    d["max_polygon_vertices"] = p.maxPolygonVertices;
    d["max_polygons"] = p.maxPolygons;
    d["max_depth"] = p.maxDepth;
    d["margin"] = p.margin;
    d["min_region_area"] = p.minRegionArea;
    d["working_size"] = p.workingSize;
    d["rect"] = py::make_tuple(p.rect.x, p.rect.y, p.rect.width, p.rect.height);
    d["protect"] = o.protect;
    d["cascade_dir"] = std::string(p.cascadeDir);
    d["morphology_radius"] = p.morphologyRadius;
    d["grabcut_iterations"] = p.grabCutIterations;
    d["grabcut_max_side"] = p.grabCutMaxSide;
    return d;
}

void checkIndex(int i, int count, const char* what) {
    if (i < 0 || i >= count)
        throw py::index_error(std::string(what) + " " + std::to_string(i) + " does not exist (there " +
                              (count == 1 ? "is 1 " : "are " + std::to_string(count) + " ") + what +
                              (count == 1 ? ")" : "s)"));
}

py::tuple sizeTuple(cv::Size s) { return py::make_tuple(s.width, s.height); }

/** validate()/validateGeometry() as (ok, reason), or raising multicage.Error. */
py::tuple validation(bool ok, const std::string& why, bool raiseError) {
    if (!ok && raiseError) {
        PyErr_SetString(errorType, why.c_str());
        throw py::error_already_set();
    }
    return py::make_tuple(ok, why);
}

// --- GPU probes ------------------------------------------------------------------------
// Made once per process: a probe makes an EGL context (about 100 ms and tens of MB on Mesa),
// and the answer does not change while the process runs.

struct GpuProbe {
    bool available = false;
    std::string description;
};

std::mutex probeMutex;

const GpuProbe& gpuProbe() {
    static GpuProbe probe;
    static bool done = false;
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(probeMutex);
    if (!done) {
        probe.available = gpuAvailable(&probe.description);
        done = true;
    }
    return probe;
}

/** What BACKEND_AUTO takes here, asked of the library with a 2x2 image and no polygon, so
that the answer is the library's own rule (software renderers skipped), not a copy of it. */
int autoBackend() {
    static int backend = -1;
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(probeMutex);
    if (backend < 0) {
        DeformParams params;
        params.backend = BACKEND_AUTO;
        const cv::Mat image(2, 2, CV_8UC1, cv::Scalar(0));
        backend = Deformer::create(image, Multicage(image.size()), params)->backend();
    }
    return backend;
}

// --- pickling ----------------------------------------------------------------------------
// States are tuples of Python numbers, strings and numpy arrays (no raw C++ memory), first
// a version number, so that a pickle travels between processes and machines (multiprocessing
// with 'spawn', Dask) and a later module can still read it or say why not.

constexpr int kPickleVersion = 1;

void checkState(const py::tuple& state, size_t size, const char* what) {
    if (state.size() != size || !py::isinstance<py::int_>(state[0]))
        throw py::value_error(std::string("cannot unpickle a multicage.") + what + ": the state is not one this "
                              "module writes");
    const int version = state[0].cast<int>();
    if (version != kPickleVersion)
        throw py::value_error(std::string("cannot unpickle a multicage.") + what + ": it was pickled in format " +
                              std::to_string(version) + ", this module (" MULTICAGE_VERSION ") reads format " +
                              std::to_string(kPickleVersion));
}

py::tuple poseState(const Pose& p) {
    return py::make_tuple(p.name, arrayFromPoints(p.vertices), p.time);
}

Pose poseFromState(const py::handle& name, const py::handle& vertices, const py::handle& time) {
    Pose p;
    p.name = name.cast<std::string>();
    p.vertices = pointsFromArray(vertices, "Pose state: vertices");
    p.time = time.cast<double>();
    return p;
}

py::tuple multicageState(const Multicage& c) {
    py::list polygons, poses;
    for (int i = 0; i < c.polygonCount(); ++i) polygons.append(arrayFromPoints(c.polygon(i)));
    for (int i = 0; i < c.poseCount(); ++i) poses.append(poseState(c.pose(i)));
    return py::make_tuple(kPickleVersion, py::make_tuple(c.imageSize().width, c.imageSize().height), polygons,
                          poses, c.coordinates());
}

Multicage multicageFromState(const py::tuple& state) {
    checkState(state, 5, "Multicage");
    const auto size = state[1].cast<std::pair<int, int>>();
    Multicage c(cv::Size(size.first, size.second));
    for (const py::handle polygon : state[2]) c.addPolygon(pointsFromArray(polygon, "Multicage state: polygon", -1, false));
    for (const py::handle pose : state[3]) {
        const py::tuple t = pose.cast<py::tuple>();
        const Pose p = poseFromState(t[0], t[1], t[2]);
        c.addPose(p.name, p.vertices, p.time);
    }
    c.setCoordinates(state[4].cast<int>());
    return c;
}

py::tuple bindingState(const Binding& b) {
    return py::make_tuple(kPickleVersion, sizeTuple(b.imageSize), b.gridStep, sizeTuple(b.gridSize), b.coordinates,
                          arrayFromMat(b.coefficients, false), arrayFromPoints(b.restVertices), b.minConditioning,
                          py::make_tuple(b.worstNode.x, b.worstNode.y));
}

Binding bindingFromState(const py::tuple& state) {
    checkState(state, 9, "Binding");
    Binding b;
    b.imageSize = sizeFromObject(state[1], "Binding state: image size");
    b.gridStep = state[2].cast<int>();
    b.gridSize = sizeFromObject(state[3], "Binding state: grid size");
    b.coordinates = state[4].cast<int>();
    b.restVertices = pointsFromArray(state[6], "Binding state: rest vertices", -1, false);
    b.minConditioning = state[7].cast<double>();
    const auto worst = state[8].cast<std::pair<float, float>>();
    b.worstNode = cv::Point2f(worst.first, worst.second);
    // The coefficients are copied into a Mat of their own: the Binding outlives the array.
    auto coefficients = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(state[5]);
    if (!coefficients || coefficients.ndim() != 2 || coefficients.shape(0) != b.coefficientCount() ||
        coefficients.shape(1) != b.gridSize.area() || b.gridStep < 1 ||
        b.gridSize != gridSizeFor(b.imageSize, b.gridStep))
        throw py::value_error("cannot unpickle a multicage.Binding: its coefficients, grid and vertices disagree");
    b.coefficients.create(static_cast<int>(coefficients.shape(0)), static_cast<int>(coefficients.shape(1)), CV_32F);
    std::copy(coefficients.data(), coefficients.data() + coefficients.size(), b.coefficients.ptr<float>());
    return b;
}

/** A Multicage argument, with a TypeError in Python's words for anything else. */
const Multicage& multicageArg(const py::handle& obj, const char* what) {
    if (!py::isinstance<Multicage>(obj))
        throw py::type_error(std::string(what) + ": expected a multicage.Multicage, got " + shortValue(obj));
    return obj.cast<const Multicage&>();
}

// --- the Deformer ---------------------------------------------------------------------------

/** A pose given in the coordinates of a multicage drawn for `from`, in those of an image of
size `to`. The user vertices go through Multicage::scaled itself, so that Python and the CLI
(which scales the cage file's poses with it) agree bit for bit. Frame corners, when the pose
has them (vertexCount + 4 points), are mapped in double: in float the rest frame would land a
rounding error off the new frame and move the border. */
std::vector<cv::Point2f> scalePose(std::vector<cv::Point2f> pose, int vertexCount, cv::Size from, cv::Size to) {
    if (from == to || pose.empty()) return pose;
    const int users = std::min<int>(vertexCount, static_cast<int>(pose.size()));
    if (users > 0) {
        Multicage m(from);
        m.addPolygon(std::vector<cv::Point2f>(pose.begin(), pose.begin() + users));
        const std::vector<cv::Point2f> scaled = m.scaled(to).polygon(0);
        std::copy(scaled.begin(), scaled.end(), pose.begin());
    }
    const double sx = static_cast<double>(to.width) / from.width, sy = static_cast<double>(to.height) / from.height;
    for (size_t i = static_cast<size_t>(users); i < pose.size(); ++i)
        pose[i] = cv::Point2f(static_cast<float>((pose[i].x + 0.5) * sx - 0.5),
                              static_cast<float>((pose[i].y + 0.5) * sy - 0.5));
    return pose;
}

/** The rest multicage for an image: the multicage itself, or scaled to the image as
`multicage deform` scales a cage file (edit small, render big). */
Multicage restForImage(const Multicage& cage, cv::Size imageSize) {
    if (cage.imageSize().area() <= 0)
        throw py::value_error("rest: the multicage has no image size; make it with Multicage((width, height)) "
                              "or Multicage.for_image(image)");
    return cage.imageSize() == imageSize ? cage : cage.scaled(imageSize);
}

std::string sizeString(cv::Size s) { return std::to_string(s.width) + "x" + std::to_string(s.height); }

/** A Deformer behind a mutex: the GIL is released while it works, and one instance holds
mutable state (CPU positions, a GL context), so Python threads sharing it take turns.
It also keeps what re-creates it in another process (pickling): a read-only copy of the
image and the parameters asked for; the binding comes from the deformer itself. */
struct PyDeformer {
    cv::Ptr<Deformer> deformer;
    std::mutex mutex;
    py::array image;      // read-only copy of the input image
    DeformParams params;  // as asked for: backend may be BACKEND_AUTO
    cv::Size cageSize;    // the size the rest multicage was drawn for: poses are in its coordinates
    cv::Size imageSize;
    int vertexCount = 0;  // user vertices (kept here: a GPU binding is read back only when asked for)

    /** The binding, under the mutex and without the GIL: a GPU deformer reads it back from its
    texture on first use, in its own GL context. */
    const Binding& binding() {
        py::gil_scoped_release release;
        std::lock_guard<std::mutex> lock(mutex);
        return deformer->binding();
    }

    std::vector<cv::Point2f> pose(const py::handle& obj) const {
        return scalePose(pointsFromArray(obj, "pose"), vertexCount, cageSize, imageSize);
    }
};

/** A read-only C-order copy of an image array (the Deformer's own), and its Mat. */
py::array ownImage(const py::handle& imageObj, cv::Mat& mat) {
    py::object keep;
    imageFromArray(imageObj, "image", keep);  // the checks, with their messages
    py::array copy = py::module_::import("numpy").attr("array")(imageObj, py::arg("order") = "C");
    copy.attr("setflags")(py::arg("write") = false);
    mat = imageFromArray(copy, "image", keep);
    return copy;
}

std::unique_ptr<PyDeformer> makeDeformer(const py::handle& imageObj, const py::handle& rest,
                                         const py::object& coordinates, const py::object& gridStep,
                                         const py::object& backend, const py::object& borderValue,
                                         const py::object& halfFloat, const py::object& gpuBinding,
                                         const py::object& memoryBudget) {
    auto d = std::make_unique<PyDeformer>();
    cv::Mat image;
    d->image = ownImage(imageObj, image);
    if (py::isinstance<Multicage>(rest)) {
        const Multicage& cage = rest.cast<const Multicage&>();
        d->params = deformParams(coordinates, gridStep, backend, borderValue, halfFloat, gpuBinding, memoryBudget,
                                 cage.coordinates());
        const Multicage scaled = restForImage(cage, image.size());
        d->cageSize = cage.imageSize();
        d->vertexCount = cage.vertexCount();
        d->imageSize = image.size();
        py::gil_scoped_release release;
        d->deformer = Deformer::create(image, scaled, d->params);
    } else if (py::isinstance<Binding>(rest)) {
        const Binding& binding = rest.cast<const Binding&>();
        d->params = deformParams(coordinates, gridStep, backend, borderValue, halfFloat, gpuBinding, memoryBudget,
                                 binding.coordinates);
        if (d->params.coordinates != binding.coordinates)
            throw py::value_error(std::string("coordinates: the binding holds ") + coordinatesName(binding.coordinates) +
                                  " coordinates, not " + coordinatesName(d->params.coordinates) +
                                  "; bind again with multicage.bind(cage, coordinates=...)");
        if (binding.imageSize != image.size())
            throw py::value_error("image: the image is " + sizeString(image.size()) + " but the binding was made for " +
                                  sizeString(binding.imageSize) + "; pass the Multicage instead (it is scaled to "
                                  "the image) or bind cage.scaled((" + std::to_string(image.cols) + ", " +
                                  std::to_string(image.rows) + "))");
        d->cageSize = binding.imageSize;
        d->vertexCount = binding.coefficientCount() - 4;
        d->imageSize = image.size();
        py::gil_scoped_release release;
        d->deformer = Deformer::create(image, binding, d->params);
    } else {
        throw py::type_error("rest: expected a multicage.Multicage or a multicage.Binding, got " + shortValue(rest));
    }
    return d;
}

const char* kDeformerDoc = R"doc(Binds an image to a multicage once, then deforms it for any number of poses.

Deformer(image, rest, *, coordinates=None, grid_step=1, backend='auto', border_value=None,
         half_float=False, gpu_binding=None, memory_budget=None)

image         numpy array as cv2 gives it: uint8, uint16 or float32; HxW, HxWx3 or HxWx4
rest          a Multicage, or a Binding made by multicage.bind() for an image of this size.
              A Multicage drawn for another image size is scaled to this image, as
              `multicage deform` scales a cage file (edit small, render big); poses are then
              given in the multicage's own coordinates and scaled the same way.
coordinates   'mvc' (mean value) or 'harmonic', or a CoordinateType; None (the default)
              follows the multicage's choice (Multicage.coordinates, a cage file's
              `coordinates:`), as `multicage deform` does without --coords    [--coords]
grid_step     a mesh node every grid_step pixels (1 is the paper's method)   [--grid-step]
backend       'auto', 'cpu' or 'gpu', or a Backend. 'auto' takes the GPU when a hardware
              OpenGL context can be made, else the CPU (multicage.auto_backend() says which);
              deformer.backend says which one this deformer uses        [--backend]
border_value  output pixels no deformed triangle covers: a number (every channel) or up to 4
                                                                             [--border]
half_float    GPU: store coefficients as 16-bit floats
gpu_binding   GPU: compute the mean value binding in a compute shader (None: where the GPU
              is a hardware one; True: always with the GPU backend; False: never)
memory_budget most bytes the coefficients may take (None: the library's 1 GiB; 0: no limit);
              above it the grid step is raised (deformer.grid_step says the step used)
[--name]: the `multicage deform` option that sets the same thing.

A pose is an Nx2 array of vertex_count points (or vertex_count + 4 with the frame corners
last). The GIL is released while binding and deforming.

A Deformer pickles (pickle, multiprocessing with 'spawn', Dask) as its image, its binding and
these parameters, and is re-created from them without binding again; it keeps a read-only
copy of the image for that. Unpickling raises multicage.Error where the deformer cannot be
made (backend='gpu' in a process without a GPU).)doc";

}  // namespace
}  // namespace multicage_py

PYBIND11_MODULE(_multicage, m) {
    using namespace multicage_py;
    m.doc() = "multicage: multicage image deformation (bindings over the C++ library)";
    m.attr("__version__") = MULTICAGE_VERSION;

    errorType = PyErr_NewExceptionWithDoc(
        "multicage.Error",
        "An error reported by the multicage library (a cv::Exception); the message is the "
        "library's own. Attributes: code (OpenCV error code), func (the C++ function).",
        PyExc_ValueError, nullptr);
    m.attr("Error") = py::handle(errorType);
    noObjectErrorType = PyErr_NewExceptionWithDoc(
        "multicage.NoObjectFoundError",
        "propose_multicage found no object in the image (the CLI's \"no object found\"); a "
        "multicage.Error, so a batch can skip such images with `except multicage.NoObjectFoundError`.",
        errorType, nullptr);
    m.attr("NoObjectFoundError") = py::handle(noObjectErrorType);
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const cv::Exception& e) {
            py::object exc = py::reinterpret_borrow<py::object>(errorType)(e.err);
            exc.attr("code") = e.code;
            exc.attr("func") = e.func;
            PyErr_SetObject(errorType, exc.ptr());
        }
    });

    py::enum_<Backend>(m, "Backend", "Where a Deformer runs.")
        .value("AUTO", BACKEND_AUTO)
        .value("CPU", BACKEND_CPU)
        .value("GPU", BACKEND_GPU);
    py::enum_<CoordinateType>(m, "CoordinateType", "Cage coordinates.")
        .value("MEAN_VALUE", MEAN_VALUE)
        .value("HARMONIC", HARMONIC);
    py::enum_<ProposeMethod>(m, "ProposeMethod", "How propose_multicage finds objects.")
        .value("AUTO", PROPOSE_AUTO)
        .value("THRESHOLD", PROPOSE_THRESHOLD)
        .value("ADAPTIVE", PROPOSE_ADAPTIVE)
        .value("GRABCUT", PROPOSE_GRABCUT)
        .value("SALIENCY", PROPOSE_SALIENCY)
        .value("SPECTRAL_RESIDUAL", PROPOSE_SPECTRAL_RESIDUAL)
        .value("MASK", PROPOSE_MASK)
        .value("LABELS", PROPOSE_LABELS);
    m.attr("CONDITIONING_WARNING") = kConditioningWarning;

    // --- Pose ---
    py::class_<Pose>(m, "Pose", "A named, timed position of every user vertex.")
        .def(py::init([](std::string name, const py::object& vertices, double time) {
                 Pose p;
                 p.name = std::move(name);
                 p.time = time;
                 p.vertices = pointsFromArray(vertices, "vertices");
                 return p;
             }),
             py::arg("name"), py::arg("vertices"), py::arg("time") = 0.0)
        .def_readwrite("name", &Pose::name)
        .def_readwrite("time", &Pose::time)
        .def_property(
            "vertices",
            [](const Pose& p) {
                // Read-only: a copy that silently ignored `pose.vertices[0] = ...` would lose the
                // edit; writing raises instead ("assignment destination is read-only").
                py::array a = arrayFromPoints(p.vertices);
                a.attr("setflags")(py::arg("write") = false);
                return a;
            },
            [](Pose& p, const py::object& v) { p.vertices = pointsFromArray(v, "vertices"); },
            "Nx2 float32 array, read-only: to change it, assign a whole array "
            "(v = pose.vertices.copy(); v[0] = ...; pose.vertices = v).")
        .def(py::pickle([](const Pose& p) { return py::make_tuple(kPickleVersion, p.name, arrayFromPoints(p.vertices), p.time); },
                        [](const py::tuple& state) {
                            checkState(state, 4, "Pose");
                            return poseFromState(state[1], state[2], state[3]);
                        }))
        .def("__eq__",
             [](const Pose& a, const py::object& other) {
                 if (!py::isinstance<Pose>(other)) return false;
                 const Pose& b = other.cast<const Pose&>();
                 return a.name == b.name && a.time == b.time && a.vertices == b.vertices;
             })
        .def("__repr__", [](const Pose& p) {
            return "<multicage.Pose '" + p.name + "' time=" + py::repr(py::float_(p.time)).cast<std::string>() +
                   ", " + std::to_string(p.vertices.size()) + " vertices>";
        });

    // --- Multicage ---
    py::class_<Multicage>(m, "Multicage", R"doc(Disjoint simple polygons over an image, plus the image frame.

Multicage(size=None): size is (width, height), as cv2 sizes are (not image.shape);
Multicage.for_image(image) takes it from an array. Points are (x, y) with pixel (x, y) at its
centre; the frame corners are (-0.5, -0.5) and (W-0.5, H-0.5). Vertices are numbered polygon
by polygon, then the 4 frame corners.)doc")
        .def(py::init([](const py::object& size) {
                 return size.is_none() ? Multicage() : Multicage(sizeFromObject(size, "size"));
             }),
             py::arg("size") = py::none())
        .def_static(
            "for_image",
            [](const py::object& image) {
                py::object keep;
                return Multicage(imageFromArray(image, "image", keep).size());
            },
            py::arg("image"), "An empty multicage of the image's size.")
        .def_property(
            "image_size", [](const Multicage& c) { return sizeTuple(c.imageSize()); },
            [](Multicage& c, const py::object& s) { c.setImageSize(sizeFromObject(s, "image_size")); },
            "(width, height)")
        .def_property_readonly("polygon_count", &Multicage::polygonCount)
        .def_property_readonly("vertex_count", &Multicage::vertexCount, "user vertices (frame excluded)")
        .def_property_readonly("pose_count", &Multicage::poseCount)
        .def(
            "add_polygon",
            [](Multicage& c, const py::object& points) { return c.addPolygon(pointsFromArray(points, "points")); },
            py::arg("points"),
            "Adds a polygon (Nx2 points, N >= 3) and returns its index. Geometry is checked by validate().")
        .def(
            "set_polygon",
            [](Multicage& c, int i, const py::object& points) {
                checkIndex(i, c.polygonCount(), "polygon");
                c.setPolygon(i, pointsFromArray(points, "points"));
            },
            py::arg("i"), py::arg("points"))
        .def(
            "remove_polygon",
            [](Multicage& c, int i) {
                checkIndex(i, c.polygonCount(), "polygon");
                c.removePolygon(i);
            },
            py::arg("i"))
        .def(
            "polygon",
            [](const Multicage& c, int i) {
                checkIndex(i, c.polygonCount(), "polygon");
                return arrayFromPoints(c.polygon(i));
            },
            py::arg("i"), "Rest positions of polygon i, Nx2 float32.")
        .def("polygons",
             [](const Multicage& c) {
                 py::list out;
                 for (int i = 0; i < c.polygonCount(); ++i) out.append(arrayFromPoints(c.polygon(i)));
                 return out;
             })
        .def(
            "polygon_offset",
            [](const Multicage& c, int i) {
                checkIndex(i, c.polygonCount(), "polygon");
                return c.polygonOffset(i);
            },
            py::arg("i"), "Index in vertices() of polygon i's first vertex.")
        .def(
            "depth",
            [](const Multicage& c, int i) {
                checkIndex(i, c.polygonCount(), "polygon");
                return c.depth(i);
            },
            py::arg("i"), "1 + the number of polygons containing polygon i (the frame is depth 0).")
        .def(
            "signed_area",
            [](const Multicage& c, int i) {
                checkIndex(i, c.polygonCount(), "polygon");
                return c.signedArea(i);
            },
            py::arg("i"), "> 0: clockwise on screen.")
        .def(
            "vertices", [](const Multicage& c) { return arrayFromPoints(c.vertices()); },
            "User vertices in order, then the 4 frame corners: (vertex_count + 4) x 2 float32.")
        .def(
            "rest_pose",
            [](const Multicage& c) {
                std::vector<cv::Point2f> v = c.vertices();
                v.resize(static_cast<size_t>(c.vertexCount()));
                return arrayFromPoints(v);
            },
            "The user vertices at rest, vertex_count x 2 float32: the identity pose, to move.")
        .def("frame", [](const Multicage& c) { return arrayFromPoints(c.frame()); })
        .def("orient", &Multicage::orient, "Applies the orientation rule (alternating with depth).")
        .def(
            "validate",
            [](const Multicage& c, bool raiseError) {
                std::string why;
                const bool ok = c.validate(&why);
                return validation(ok, why, raiseError);
            },
            py::arg("raise_error") = false,
            "Returns (ok, reason); with raise_error=True raises multicage.Error(reason) instead of "
            "returning False.")
        .def(
            "validate_geometry",
            [](const Multicage& c, bool raiseError) {
                std::string why;
                const bool ok = c.validateGeometry(&why);
                return validation(ok, why, raiseError);
            },
            py::arg("raise_error") = false, "As validate(), ignoring the orientation rule.")
        .def(
            "add_pose",
            [](Multicage& c, const std::string& name, const py::object& vertices, double time) {
                return c.addPose(name, pointsFromArray(vertices, "vertices"), time);
            },
            py::arg("name"), py::arg("vertices"), py::arg("time") = 0.0,
            "Adds a named pose (vertex_count points, or vertex_count + 4); returns its index.")
        .def(
            "pose",
            [](const Multicage& c, const py::object& key) {
                if (py::isinstance<py::str>(key)) {
                    const std::string name = key.cast<std::string>();
                    const int i = c.findPose(name);
                    if (i < 0) {
                        std::string names;
                        for (int j = 0; j < c.poseCount(); ++j) names += (j ? ", " : "") + c.pose(j).name;
                        throw py::key_error("no pose named '" + name + "' (the multicage has: " +
                                            (names.empty() ? "no poses" : names) + ")");
                    }
                    return c.pose(i);
                }
                const int i = key.cast<int>();
                checkIndex(i, c.poseCount(), "pose");
                return c.pose(i);
            },
            py::arg("key"), "A pose by index or by name (a copy).")
        .def_property_readonly(
            "poses",
            [](const Multicage& c) {
                std::vector<Pose> out;
                for (int i = 0; i < c.poseCount(); ++i) out.push_back(c.pose(i));
                return out;
            },
            "All poses (copies).")
        .def("find_pose", &Multicage::findPose, py::arg("name"), "Index of the pose called name, or -1.")
        .def(
            "set_pose",
            [](Multicage& c, int i, const Pose& p) {
                checkIndex(i, c.poseCount(), "pose");
                c.setPose(i, p);
            },
            py::arg("i"), py::arg("pose"))
        .def(
            "remove_pose",
            [](Multicage& c, int i) {
                checkIndex(i, c.poseCount(), "pose");
                c.removePose(i);
            },
            py::arg("i"))
        .def(
            "scaled", [](const Multicage& c, const py::object& s) { return c.scaled(sizeFromObject(s, "size")); },
            py::arg("size"), "The same multicage for an image of size (width, height).")
        .def_static("load", &Multicage::load, py::arg("path"), "Loads a YAML or JSON cage file.")
        .def("save", &Multicage::save, py::arg("path"), "Saves a YAML or JSON cage file (atomically).")
        .def(
            "draw",
            [](const Multicage& c, const py::object& image, int thickness, bool drawVertices) {
                py::object keep;
                cv::Mat canvas = imageFromArray(image, "image", keep).clone();
                c.draw(canvas, thickness, drawVertices);
                return arrayFromMat(canvas);
            },
            py::arg("image"), py::arg("thickness") = 1, py::arg("draw_vertices") = true,
            "A copy of image with the polygons drawn, coloured by depth.")
        .def_property(
            "coordinates", [](const Multicage& c) { return coordinatesName(c.coordinates()); },
            [](Multicage& c, const py::object& v) { c.setCoordinates(parseCoordinates(v)); },
            "'mvc' or 'harmonic': the coordinates this multicage is meant to be bound with (a cage file's "
            "`coordinates:`). Deformer, deform_image and bind follow it unless given coordinates=.")
        .def(py::pickle([](const Multicage& c) { return multicageState(c); },
                        [](const py::tuple& state) { return multicageFromState(state); }))
        .def("__copy__", [](const Multicage& c) { return Multicage(c); })
        .def("__deepcopy__", [](const Multicage& c, const py::object&) { return Multicage(c); }, py::arg("memo"))
        .def("__repr__", [](const Multicage& c) {
            return "<multicage.Multicage " + std::to_string(c.imageSize().width) + "x" +
                   std::to_string(c.imageSize().height) + ", " + std::to_string(c.polygonCount()) + " polygons, " +
                   std::to_string(c.vertexCount()) + " vertices, " + std::to_string(c.poseCount()) + " poses>";
        });

    // --- Binding ---
    py::class_<Binding>(m, "Binding", "Every grid node bound to every vertex of a multicage (Algorithm 1).")
        .def_property_readonly("image_size", [](const Binding& b) { return sizeTuple(b.imageSize); })
        .def_readonly("grid_step", &Binding::gridStep)
        .def_property_readonly("grid_size", [](const Binding& b) { return sizeTuple(b.gridSize); },
                               "(nodes in x, nodes in y)")
        .def_property_readonly("coordinates", [](const Binding& b) { return coordinatesName(b.coordinates); })
        .def_property_readonly(
            "coefficients", [](const Binding& b) { return arrayFromMat(b.coefficients, false); },
            "coefficient_count x node_count float32 (read-only view): row j is coefficient j of every "
            "node, node (gx, gy) at column gy * grid_size[0] + gx.")
        .def_property_readonly(
            "rest_vertices",
            [](const Binding& b) {
                py::array a = arrayFromPoints(b.restVertices);
                a.attr("setflags")(py::arg("write") = false);
                return a;
            },
            "(coefficient_count x 2) float32, read-only: user vertices, then the 4 frame corners.")
        .def(py::pickle([](const Binding& b) { return bindingState(b); },
                        [](const py::tuple& state) { return bindingFromState(state); }))
        .def_readonly("min_conditioning", &Binding::minConditioning)
        .def_property_readonly("worst_node", [](const Binding& b) { return py::make_tuple(b.worstNode.x, b.worstNode.y); })
        .def_property_readonly("coefficient_count", &Binding::coefficientCount)
        .def_property_readonly("node_count", &Binding::nodeCount)
        .def(
            "nodes", [](const Binding& b) { return arrayFromMat(b.nodes()); },
            "Rest positions of the nodes, grid height x grid width x 2 float32.")
        .def(
            "apply",
            [](const Binding& b, const py::object& pose) {
                const std::vector<cv::Point2f> p = pointsFromArray(pose, "pose");
                cv::Mat positions;
                {
                    py::gil_scoped_release release;
                    b.apply(p, positions);
                }
                return arrayFromMat(positions);
            },
            py::arg("pose"), "Deformed node positions for a pose, grid height x grid width x 2 float32.")
        .def("__repr__", [](const Binding& b) {
            return "<multicage.Binding " + std::string(coordinatesName(b.coordinates)) + ", " +
                   std::to_string(b.gridSize.width) + "x" + std::to_string(b.gridSize.height) + " nodes, " +
                   std::to_string(b.coefficientCount()) + " coefficients>";
        });

    m.def(
        "bind",
        [](const py::object& cageObj, const py::object& coordinates, const py::object& gridStepObj,
           const py::object& onGpuObj) {
            const Multicage& cage = multicageArg(cageObj, "multicage");
            const int coords = coordinates.is_none() ? cage.coordinates() : parseCoordinates(coordinates);
            const int gridStep = intArg(gridStepObj, "grid_step");
            if (gridStep < 1) throw py::value_error("grid_step: must be >= 1, got " + std::to_string(gridStep));
            const bool onGpu = boolArg(onGpuObj, "on_gpu");
            if (onGpu && coords != MEAN_VALUE)
                throw py::value_error("on_gpu: the GPU binds mean value coordinates only");
            py::gil_scoped_release release;
            return onGpu ? bindOnGpu(cage, gridStep) : bind(cage, coords, gridStep);
        },
        py::arg("multicage"), py::arg("coordinates") = py::none(), py::arg("grid_step") = 1,
        py::arg("on_gpu") = false,
        "Binds every grid node to every vertex (Algorithm 1); a Binding can feed several Deformers "
        "of images of the multicage's size. coordinates None follows multicage.coordinates. The GIL "
        "is released while it runs.");

    // --- Deformer ---
    // Every keyword is taken as an object and converted here, so that a wrong type gets a
    // TypeError naming the keyword (pybind11's own message would print every argument,
    // the whole image included).
    auto create = [](const py::object& image, const py::object& rest, const py::object& coordinates,
                     const py::object& gridStep, const py::object& backend, const py::object& borderValue,
                     const py::object& halfFloat, const py::object& gpuBinding, const py::object& memoryBudget) {
        return makeDeformer(image, rest, coordinates, gridStep, backend, borderValue, halfFloat, gpuBinding,
                            memoryBudget);
    };
    py::class_<PyDeformer>(m, "Deformer", kDeformerDoc)
        .def(py::init(create), py::arg("image"), py::arg("rest"), py::kw_only(), py::arg("coordinates") = py::none(),
             py::arg("grid_step") = 1, py::arg("backend") = "auto", py::arg("border_value") = py::none(),
             py::arg("half_float") = false, py::arg("gpu_binding") = py::none(), py::arg("memory_budget") = py::none())
        .def_static("create", create, py::arg("image"), py::arg("rest"), py::kw_only(),
                    py::arg("coordinates") = py::none(), py::arg("grid_step") = 1, py::arg("backend") = "auto",
                    py::arg("border_value") = py::none(), py::arg("half_float") = false,
                    py::arg("gpu_binding") = py::none(), py::arg("memory_budget") = py::none(), "Same as Deformer(...).")
        .def(
            "deform",
            [](PyDeformer& d, const py::object& pose) {
                const std::vector<cv::Point2f> p = d.pose(pose);
                cv::Mat out;
                {
                    py::gil_scoped_release release;
                    std::lock_guard<std::mutex> lock(d.mutex);
                    d.deformer->deform(p, out);
                }
                return arrayFromMat(out);
            },
            py::arg("pose"), "The image deformed to pose: same shape and dtype as the input.")
        .def(
            "compute_maps",
            [](PyDeformer& d, const py::object& pose) {
                const std::vector<cv::Point2f> p = d.pose(pose);
                cv::Mat mapx, mapy;
                {
                    py::gil_scoped_release release;
                    std::lock_guard<std::mutex> lock(d.mutex);
                    d.deformer->computeMaps(p, mapx, mapy);
                }
                return py::make_tuple(arrayFromMat(mapx), arrayFromMat(mapy));
            },
            py::arg("pose"),
            "Inverse maps (mapx, mapy) for cv2.remap, HxW float32: for each output pixel its source "
            "position; uncovered pixels get -1e4. Remap masks and labels with cv2.INTER_NEAREST.")
        .def(
            "folded_triangles",
            [](PyDeformer& d, const py::object& pose) {
                const std::vector<cv::Point2f> p = d.pose(pose);
                py::gil_scoped_release release;
                std::lock_guard<std::mutex> lock(d.mutex);
                return d.deformer->foldedTriangles(p);
            },
            py::arg("pose"), "Number of mesh triangles the pose turns over (0: no fold-over).")
        .def_property_readonly(
            "backend", [](const PyDeformer& d) { return backendName(d.deformer->backend()); },
            "'cpu' or 'gpu': the backend in use.")
        .def_property_readonly(
            "binding",
            [](PyDeformer& d) { return d.binding(); },
            "The Binding in use (for the image's size: a scaled multicage's).")
        .def_property_readonly("image_size", [](const PyDeformer& d) { return sizeTuple(d.imageSize); })
        .def_property_readonly(
            "cage_size", [](const PyDeformer& d) { return sizeTuple(d.cageSize); },
            "(width, height) the rest multicage was drawn for: poses are in its coordinates (equal to "
            "image_size unless the multicage was scaled to the image).")
        .def_property_readonly(
            "grid_step", [](PyDeformer& d) { return d.binding().gridStep; },
            "The grid step in use (raised above the one asked for when memory_budget requires it).")
        .def_property_readonly(
            "coordinates", [](PyDeformer& d) { return coordinatesName(d.binding().coordinates); },
            "'mvc' or 'harmonic': the coordinates in use.")
        .def_property_readonly(
            "vertex_count", [](const PyDeformer& d) { return d.vertexCount; },
            "user vertices: a pose has this many points (or 4 more).")
        .def(py::pickle(
            [](PyDeformer& d) {
                Binding binding = d.binding();
                const DeformParams& p = d.params;
                py::dict params;
                params["coordinates"] = coordinatesName(p.coordinates);
                params["grid_step"] = p.gridStep;
                params["backend"] = backendName(p.backend);
                params["border_value"] =
                    py::make_tuple(p.borderValue[0], p.borderValue[1], p.borderValue[2], p.borderValue[3]);
                params["half_float"] = p.halfFloat;
                params["gpu_binding"] =
                    p.gpuBinding < 0 ? py::object(py::none()) : py::object(py::bool_(p.gpuBinding > 0));
                params["memory_budget"] = p.memoryBudget;
                return py::make_tuple(kPickleVersion, d.image, py::cast(std::move(binding)), params,
                                      sizeTuple(d.cageSize));
            },
            [](const py::tuple& state) {
                checkState(state, 5, "Deformer");
                const py::dict params = state[3].cast<py::dict>();
                const py::object binding = state[2];
                std::unique_ptr<PyDeformer> d;
                try {
                    d = makeDeformer(state[1], binding, params["coordinates"], params["grid_step"], params["backend"],
                                     params["border_value"], params["half_float"], params["gpu_binding"],
                                     params["memory_budget"]);
                } catch (const cv::Exception& e) {
                    // Say what failed and why: the usual case is a GPU deformer sent to a process
                    // or machine without a GPU.
                    raise(errorType, "cannot re-create the pickled multicage.Deformer (backend='" +
                                         params["backend"].cast<std::string>() + "') here: " + e.err +
                                         (params["backend"].cast<std::string>() == "gpu"
                                              ? "; make deformers that travel with backend='auto' or 'cpu'"
                                              : ""));
                }
                d->cageSize = sizeFromObject(state[4], "Deformer state: cage size");
                return d;
            }))
        .def("__repr__", [](const py::handle& self) {
            // A failed __init__ leaves an instance that tracebacks (pytest's among them) still
            // show: its repr must not touch the PyDeformer it never got.
            auto* inst = reinterpret_cast<py::detail::instance*>(self.ptr());
            if (!inst->get_value_and_holder(py::detail::get_type_info(typeid(PyDeformer))).holder_constructed())
                return std::string("<multicage.Deformer (not initialised)>");
            PyDeformer& d = self.cast<PyDeformer&>();
            const Binding& b = d.binding();
            return "<multicage.Deformer " + std::string(backendName(d.deformer->backend())) + ", " +
                   std::to_string(b.imageSize.width) + "x" + std::to_string(b.imageSize.height) + ", " +
                   std::to_string(b.coefficientCount() - 4) + " vertices, grid step " +
                   std::to_string(b.gridStep) + ">";
        });

    m.def(
        "deform_image",
        [](const py::object& image, const py::object& restObj, const py::object& pose, const py::object& coordinates,
           const py::object& gridStep, const py::object& backend, const py::object& borderValue,
           const py::object& halfFloat, const py::object& gpuBinding, const py::object& memoryBudget) {
            const Multicage& rest = multicageArg(restObj, "rest");
            const DeformParams params = deformParams(coordinates, gridStep, backend, borderValue, halfFloat,
                                                     gpuBinding, memoryBudget, rest.coordinates());
            py::object keep;
            const cv::Mat src = imageFromArray(image, "image", keep);
            const Multicage scaled = restForImage(rest, src.size());
            const std::vector<cv::Point2f> p =
                scalePose(pointsFromArray(pose, "pose"), rest.vertexCount(), rest.imageSize(), src.size());
            cv::Mat out;
            {
                py::gil_scoped_release release;
                deformImage(src, scaled, p, out, params);
            }
            return arrayFromMat(out);
        },
        py::arg("image"), py::arg("rest"), py::arg("pose"), py::kw_only(), py::arg("coordinates") = py::none(),
        py::arg("grid_step") = 1, py::arg("backend") = "auto", py::arg("border_value") = py::none(),
        py::arg("half_float") = false, py::arg("gpu_binding") = py::none(), py::arg("memory_budget") = py::none(),
        "One shot: binds, deforms once, returns the image. Same keywords and scaling as Deformer; "
        "prefer a Deformer for several poses.");

    // --- coordinates, proposal, GPU ---
    m.def(
        "mean_value_coordinates",
        [](const py::object& polygon, const py::object& points, bool normalize) {
            const std::vector<cv::Point2f> poly = pointsFromArray(polygon, "polygon");
            const std::vector<cv::Point2f> pts = pointsFromArray(points, "points");
            cv::Mat weights;
            {
                py::gil_scoped_release release;
                meanValueCoordinates(poly, pts, weights, normalize);
            }
            return arrayFromMat(weights);
        },
        py::arg("polygon"), py::arg("points"), py::arg("normalize") = true,
        "Mean value coordinates (Hormann & Floater 2006) of N points for an n-gon: N x n float32. "
        "A point on a vertex or an edge gets the exact interpolating values.");

    // The keyword list with the library's defaults, so that the docs never drift from them.
    std::string proposeKeywordDoc;
    for (const auto& item : proposeDefaults())
        proposeKeywordDoc += "    " + item.first.cast<std::string>() + "=" + py::repr(item.second).cast<std::string>() + "\n";

    m.def(
        "propose_multicage",
        [](const py::object& image, const py::kwargs& kwargs) {
            const ProposeOptions options = proposeOptions(kwargs, "propose_multicage", true);
            const bool protectGiven = kwargs.contains("protect");
            py::object keep;
            const cv::Mat src = imageFromArray(image, "image", keep, true);
            Multicage cage;
            {
                py::gil_scoped_release release;
                cage = proposeProtected(src, options, protectGiven);
            }
            if (cage.polygonCount() == 0) {
                std::ostringstream s;
                s << "propose_multicage: no object found with method='" << proposeMethodName(options.params.method)
                  << "' (no region larger than min_region_area=" << options.params.minRegionArea
                  << " of the image); try another method, a smaller min_region_area, or a mask "
                     "(method='mask')";
                raise(noObjectErrorType, s.str());
            }
            return cage;
        },
        py::arg("image"),
        ("propose_multicage(image, **keywords) -> Multicage\n\n"
         "Proposes a valid, oriented multicage enclosing the objects of an image, as `multicage propose` "
         "does: the keywords are its options with '_' for '-' (--min-region-area: min_region_area; "
         "min_area is accepted too). Raises NoObjectFoundError (a multicage.Error) when it finds no "
         "object, where the CLI says \"no object found\".\n\n"
         "method: 'auto', 'threshold', 'adaptive', 'grabcut', 'saliency', 'spectral', 'mask', 'labels' "
         "or a ProposeMethod. protect=True adds inner polygons around the salient features inside "
         "every outer polygon (the multicage proper: what they enclose stays almost rigid when the "
         "outline moves); protect=False gives outlines only. margin < 0 and morphology_radius < 0 "
         "pick a size from the image. Defaults (the library's ProposeParams, also "
         "multicage.propose_defaults()):\n" + proposeKeywordDoc)
            .c_str());
    m.def("propose_defaults", &proposeDefaults,
          "The default of every propose_multicage keyword, from the library's ProposeParams().");
    m.def(
        "propose_segmentation",
        [](const py::object& image, const py::kwargs& kwargs) {
            const ProposeParams params = proposeOptions(kwargs, "propose_segmentation", true).params;
            py::object keep;
            const cv::Mat src = imageFromArray(image, "image", keep, true);
            cv::Mat mask;
            {
                py::gil_scoped_release release;
                proposeSegmentation(src, mask, params);
            }
            return arrayFromMat(mask);
        },
        py::arg("image"),
        "The cleaned segmentation propose_multicage encloses: HxW uint8, 255 on object pixels "
        "(all 0 where it finds no object). Same keywords as propose_multicage (protect changes nothing here).");
    m.def(
        "protect_features",
        [](const py::object& image, const py::object& cageObj, const py::object& polygonObj,
           const py::kwargs& kwargs) {
            const Multicage& cage = multicageArg(cageObj, "multicage");
            const int polygon = intArg(polygonObj, "polygon");
            const ProposeParams params = proposeOptions(kwargs, "protect_features", false).params;
            py::object keep;
            const cv::Mat src = imageFromArray(image, "image", keep);
            checkIndex(polygon, cage.polygonCount(), "polygon");
            py::gil_scoped_release release;
            return protectFeatures(src, cage, polygon, params);
        },
        py::arg("image"), py::arg("multicage"), py::arg("polygon"),
        "A copy of the multicage with protective polygons added around the salient features inside "
        "polygon `polygon` (unchanged when there is none). Same keywords as propose_multicage, "
        "except protect.");

    m.def(
        "gpu_available",
        [] {
            const GpuProbe& probe = gpuProbe();
            return py::make_tuple(probe.available, probe.description);
        },
        R"doc(gpu_available() -> (available, description)

Whether an OpenGL context (headless EGL, OpenGL 4.3+) can be made here, that is whether
backend='gpu' works, with the renderer's description or the reason there is none. A software
renderer (Mesa llvmpipe, on machines without a GPU) counts: backend='gpu' runs on it, but
backend='auto' does not take it, because there the CPU backend is faster. What 'auto' takes
is auto_backend(). Probed once per process.)doc");
    m.def(
        "auto_backend", [] { return backendName(autoBackend()); },
        R"doc(auto_backend() -> 'gpu' or 'cpu'

The backend that backend='auto' takes here: 'gpu' where a hardware OpenGL context can be made,
'cpu' where there is none or only a software renderer (gpu_available() says which). Found
once per process by asking the library itself, so it agrees with Deformer(..., backend='auto').)doc");
}

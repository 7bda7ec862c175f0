#include "common.hpp"

#include <algorithm>
#include <cctype>
#include <climits>
#include <cmath>

namespace multicage_py {

using namespace cv::multicage;

[[noreturn]] void raise(PyObject* type, const std::string& message) {
    PyErr_SetString(type, message.c_str());
    throw py::error_already_set();
}

// --- argument parsing -----------------------------------------------------------------------

namespace {

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}

}  // namespace

std::string shortValue(const py::handle& v) {
    if (py::isinstance<py::array>(v)) {
        const py::array a = py::reinterpret_borrow<py::array>(v);
        std::string shape = "(";
        for (py::ssize_t i = 0; i < a.ndim(); ++i)
            shape += (i ? ", " : "") + std::to_string(a.shape(i));
        shape += a.ndim() == 1 ? ",)" : ")";
        return "numpy.ndarray of shape " + shape + " and dtype " +
               py::str(a.dtype()).cast<std::string>();
    }
    std::string r = py::repr(v).cast<std::string>();
    if (r.size() > 40) r = r.substr(0, 37) + "...";
    return typeName(v) + " " + r;
}

int intArg(const py::handle& v, const std::string& name) {
    if (PyBool_Check(v.ptr()) || !PyIndex_Check(v.ptr()))
        throw py::type_error(name + ": expected an integer, got " + shortValue(v));
    const long long x =
        PyLong_AsLongLong(py::reinterpret_steal<py::object>(PyNumber_Index(v.ptr())).ptr());
    if (PyErr_Occurred() || x < INT_MIN || x > INT_MAX) {
        PyErr_Clear();
        throw py::value_error(name + ": " + py::repr(v).cast<std::string>() + " is out of range");
    }
    return static_cast<int>(x);
}

double numberArg(const py::handle& v, const std::string& name) {
    if (PyBool_Check(v.ptr()) || PyUnicode_Check(v.ptr()) || PyBytes_Check(v.ptr()) ||
        v.is_none() || PyComplex_Check(v.ptr()))
        throw py::type_error(name + ": expected a number, got " + shortValue(v));
    const double x = PyFloat_AsDouble(v.ptr());
    if (x == -1.0 && PyErr_Occurred()) {
        PyErr_Clear();
        throw py::type_error(name + ": expected a number, got " + shortValue(v));
    }
    return x;
}

bool boolArg(const py::handle& v, const std::string& name) {
    if (PyBool_Check(v.ptr())) return v.ptr() == Py_True;
    const py::object npBool = py::module_::import("numpy").attr("bool_");
    if (py::isinstance(v, npBool)) return v.cast<bool>();
    throw py::type_error(name + ": expected True or False, got " + shortValue(v));
}

int enumFromObject(const py::handle& obj, const char* what,
                   const std::vector<std::pair<std::string, int>>& names, int count) {
    if (py::isinstance<py::str>(obj)) {
        const std::string s = lower(obj.cast<std::string>());
        std::string known;
        for (const auto& n : names) {
            if (n.first == s) return n.second;
            known += (known.empty() ? "'" : ", '") + n.first + "'";
        }
        throw py::value_error(std::string(what) + ": '" + obj.cast<std::string>() +
                              "' is not one of " + known);
    }
    // pybind11 enums convert through int(); ints and numpy integers through __index__.
    const bool isEnum = py::hasattr(obj, "__members__") && py::hasattr(obj, "value");
    if (PyBool_Check(obj.ptr()) || !(isEnum || PyIndex_Check(obj.ptr())))
        throw py::type_error(std::string(what) + ": expected a name or an enum value, got " +
                             shortValue(obj));
    const int v = isEnum ? obj.attr("value").cast<int>() : intArg(obj, what);
    if (v < 0 || v >= count)
        throw py::value_error(std::string(what) + ": " + std::to_string(v) + " is out of range");
    return v;
}

int segmenterArg(const py::handle& obj) {
    std::vector<std::pair<std::string, int>> names;
    for (int s = SEGMENTER_AUTO; s <= SEGMENTER_CLASSIC; ++s)
        names.emplace_back(segmenterName(s), s);
    return enumFromObject(obj, "segmenter", names, SEGMENTER_CLASSIC + 1);
}

std::string pathArg(const py::handle& v, const std::string& name, const std::string& accepted) {
    if (!py::isinstance<py::str>(v) && !py::hasattr(v, "__fspath__"))
        throw py::type_error(name + ": expected " + accepted + ", got " + shortValue(v));
    const py::object path = py::module_::import("os").attr("fspath")(v);
    if (!py::isinstance<py::str>(path))
        throw py::type_error(name + ": expected a str path, got " + shortValue(path));
    return path.cast<std::string>();
}

std::string segmenterModelArg(const py::handle& obj) {
    if (obj.is_none()) return std::string();
    const std::string file = pathArg(obj, "segmenter_model", "a path (str or os.PathLike) or None");
    if (file.empty())
        throw py::value_error("segmenter_model: an empty path (None: the installed model)");
    return file;
}

void checkSegmenterPair(int segmenter, const std::string& model) {
    if (segmenter == SEGMENTER_CLASSIC && !model.empty())
        throw py::value_error("segmenter_model: '" + model +
                              "' given with segmenter='classic', which runs no model");
}

// The names are the library's (backendName, coordinateTypeName), as in the CLI.
int parseBackend(const py::handle& obj) {
    std::vector<std::pair<std::string, int>> names;
    for (int b : {BACKEND_AUTO, BACKEND_CPU, BACKEND_GPU})
        names.emplace_back(cv::multicage::backendName(b), b);
    return enumFromObject(obj, "backend", names, 3);
}

int parseCoordinates(const py::handle& obj) {
    return enumFromObject(obj, "coordinates",
                          {{coordinateTypeName(MEAN_VALUE), MEAN_VALUE},
                           {"mean_value", MEAN_VALUE},  // the cage file's spelling
                           {coordinateTypeName(HARMONIC), HARMONIC},
                           {coordinateTypeName(LOCAL_MEAN_VALUE), LOCAL_MEAN_VALUE},
                           {"local_mean_value", LOCAL_MEAN_VALUE}},
                          3);
}

const char* coordinatesName(int c) {
    // COORDINATES_FROM_CAGE reads as mvc, the cage's default, where a name must be given.
    return coordinateTypeName(c == COORDINATES_FROM_CAGE ? MEAN_VALUE : c);
}

DeformParams deformParams(const py::object& coordinates, const py::object& gridStep,
                          const py::object& backend, const py::object& borderValue,
                          const py::object& halfFloat, const py::object& gpuBinding,
                          const py::object& memoryBudget, const py::object& mapStep,
                          int cageCoordinates) {
    DeformParams p;
    p.coordinates = coordinates.is_none() ? cageCoordinates : parseCoordinates(coordinates);
    p.gridStep = intArg(gridStep, "grid_step");
    if (p.gridStep < 1)
        throw py::value_error("grid_step: must be >= 1, got " + std::to_string(p.gridStep));
    p.mapStep = intArg(mapStep, "map_step");
    if (p.mapStep < 1 || p.mapStep > DeformParams::kMaxMapStep)
        throw py::value_error("map_step: must be in [1, " +
                              std::to_string(DeformParams::kMaxMapStep) + "], got " +
                              std::to_string(p.mapStep));
    p.backend = parseBackend(backend);
    p.borderValue = scalarFromObject(borderValue, "border_value");
    p.halfFloat = boolArg(halfFloat, "half_float");
    // None: the library's default (on the GPU where it is a hardware one); True/False force it.
    p.gpuBinding = gpuBinding.is_none() ? -1 : boolArg(gpuBinding, "gpu_binding") ? 1 : 0;
    if (!memoryBudget.is_none()) {
        const double budget = numberArg(memoryBudget, "memory_budget");
        if (!(budget >= 0) || budget > 9.0e18 || budget != std::floor(budget))
            throw py::value_error(
                "memory_budget: expected a whole number of bytes >= 0 (0: no limit), got " +
                py::repr(memoryBudget).cast<std::string>());
        p.memoryBudget = static_cast<size_t>(budget);
    }
    return p;
}

const Multicage& multicageArg(const py::handle& obj, const char* what) {
    if (!py::isinstance<Multicage>(obj))
        throw py::type_error(std::string(what) + ": expected a multicage.Multicage, got " +
                             shortValue(obj));
    return obj.cast<const Multicage&>();
}

void checkIndex(int i, int count, const char* what) {
    if (i < 0 || i >= count)
        throw py::index_error(std::string(what) + " " + std::to_string(i) +
                              " does not exist (there " +
                              (count == 1 ? "is 1 " : "are " + std::to_string(count) + " ") + what +
                              (count == 1 ? ")" : "s)"));
}

py::tuple sizeTuple(cv::Size s) {
    return py::make_tuple(s.width, s.height);
}

std::string sizeString(cv::Size s) {
    return std::to_string(s.width) + "x" + std::to_string(s.height);
}

// --- points and images ----------------------------------------------------------------------

py::array transformPointsArray(
    const py::handle& points,
    const std::function<void(const std::vector<cv::Point2f>&, std::vector<cv::Point2f>&)>& run) {
    const py::module_ np = py::module_::import("numpy");
    py::array a;
    try {
        a = np.attr("asarray")(points);
    } catch (const py::error_already_set&) {
        throw py::type_error("points: expected an array of shape (..., 2) of (x, y), got " +
                             shortValue(points));
    }
    const char kind = a.dtype().kind();
    if (kind != 'f' && kind != 'i' && kind != 'u')
        throw py::type_error("points: expected real numbers (x, y), got " + shortValue(a));
    if (a.ndim() < 1 || a.shape(a.ndim() - 1) != 2)
        throw py::value_error("points: expected an array of shape (..., 2) of (x, y) points, got " +
                              shortValue(a));
    const py::object shape = a.attr("shape");
    const py::object flat = a.attr("reshape")(-1, 2);
    const std::vector<cv::Point2f> in = pointsFromArray(flat, "points");
    std::vector<cv::Point2f> out;
    run(in, out);
    py::array result = arrayFromPoints(out);
    return result.attr("reshape")(shape);
}

std::string matDescription(const cv::Mat& image) {
    static const char* names[] = {"uint8", "int8",    "uint16",  "int16",
                                  "int32", "float32", "float64", "float16"};
    std::string shape = "(" + std::to_string(image.rows) + ", " + std::to_string(image.cols);
    if (image.channels() > 1) shape += ", " + std::to_string(image.channels());
    return "shape " + shape + ") and dtype " + names[image.depth()];
}

// --- pickling -------------------------------------------------------------------------------

void checkState(const py::tuple& state, size_t size, const char* what) {
    if (state.size() != size || !py::isinstance<py::int_>(state[0]))
        throw py::value_error(std::string("cannot unpickle a multicage.") + what +
                              ": the state is not one this "
                              "module writes");
    const int version = state[0].cast<int>();
    if (version != kPickleVersion)
        throw py::value_error(std::string("cannot unpickle a multicage.") + what +
                              ": it was pickled in format " + std::to_string(version) +
                              ", this module (" MULTICAGE_VERSION ") reads format " +
                              std::to_string(kPickleVersion));
}

}  // namespace multicage_py

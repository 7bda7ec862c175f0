// What the binding files of the Python module share: the error types, the conversion of
// Python arguments (a wrong one is a TypeError or ValueError naming the keyword), the pickle
// state format, and the define functions PYBIND11_MODULE calls. Private to the module.
#ifndef MULTICAGE_PYTHON_COMMON_HPP
#define MULTICAGE_PYTHON_COMMON_HPP

#include <pybind11/stl.h>  // in every binding file, as pybind11 asks: one set of STL casters

#include <functional>
#include <opencv2/multicage.hpp>
#include <string>
#include <utility>
#include <vector>

#include "convert.hpp"

namespace multicage_py {

// --- errors ---------------------------------------------------------------------------------

extern PyObject* errorType;          // multicage.Error, alive as long as the interpreter
extern PyObject* noObjectErrorType;  // multicage.NoObjectFoundError, a multicage.Error

[[noreturn]] void raise(PyObject* type, const std::string& message);

// --- argument parsing -----------------------------------------------------------------------

/** A short description of a value for messages: its type, and its repr when that is short
(never a whole image array). */
std::string shortValue(const py::handle& v);

/** Python's int (or a numpy integer) as an int; bool, float and str are TypeErrors, as
Python itself treats them where an index is needed. */
int intArg(const py::handle& v, const std::string& name);

/** A str or os.PathLike as a str (os.fspath); anything else is a TypeError saying that `name`
expected `accepted`. */
std::string pathArg(const py::handle& v, const std::string& name,
                    const std::string& accepted = "a str or an os.PathLike");

/** A real number (int, float, numpy scalar); str, bytes, bool and None are TypeErrors. */
double numberArg(const py::handle& v, const std::string& name);

/** True or False (or a numpy bool); 1, 'yes' and None are TypeErrors: a flag is a flag. */
bool boolArg(const py::handle& v, const std::string& name);

/** A string name, one of the enum's members, or its integer value (not a float: 2.0 is
more likely a mistake than a method). */
int enumFromObject(const py::handle& obj, const char* what,
                   const std::vector<std::pair<std::string, int>>& names, int count);

/** The Python names of Backend and CoordinateType values, both ways ('auto', 'cpu', 'gpu';
'mvc' or 'mean_value', 'harmonic'). */
int parseBackend(const py::handle& obj);
int parseCoordinates(const py::handle& obj);
const char* coordinatesName(int c);  // backendName is the library's

/** The segmenter= keyword: 'auto', 'model', 'classic' (the library's segmenterName()) or
their integer values; anything else a ValueError (TypeError) naming the keyword. */
int segmenterArg(const py::handle& obj);
/** The segmenter_model= keyword: a path (str or os.PathLike); None gives "" (the library's
look-up). An empty path is a ValueError, anything else a TypeError, naming the keyword. */
std::string segmenterModelArg(const py::handle& obj);
/** Throws a ValueError for a model path given with segmenter='classic' (it would not run). */
void checkSegmenterPair(int segmenter, const std::string& model);

/** One keyword of ResizeParams into p (resize_py.cpp): coordinates, grid_step, backend, protect,
margin, segmenter, segmenter_model, max_scale, max_warp; None leaves the default. False for
another keyword. content_aware_resize, resize_pose and VideoReframer share it, so the names and
their values are the same everywhere. */
bool resizeParam(cv::multicage::ResizeParams& p, const std::string& key, const py::handle& v);
extern const char* const kResizeKeywords;  // the names resizeParam takes, for messages
/** One keyword of TrackParams into p (track_py.cpp): points_per_polygon, min_agreement,
min_points, agreement_px, max_round_trip_px, min_histogram_correlation, max_thumbnail_difference,
working_size. False for another keyword. CageTracker and VideoReframer share it. */
bool trackParam(cv::multicage::TrackParams& p, const std::string& key, const py::handle& v);
extern const char* const kTrackKeywords;  // the names trackParam takes, for messages

/** DeformParams from the Python keywords. coordinates None follows the multicage's own
choice (the cage file's `coordinates:`), as `multicage deform` does without --coords. */
cv::multicage::DeformParams deformParams(const py::object& coordinates, const py::object& gridStep,
                                         const py::object& backend, const py::object& borderValue,
                                         const py::object& halfFloat, const py::object& gpuBinding,
                                         const py::object& memoryBudget, const py::object& mapStep,
                                         int cageCoordinates);

/** A Multicage argument, with a TypeError in Python's words for anything else. */
const cv::multicage::Multicage& multicageArg(const py::handle& obj, const char* what);

void checkIndex(int i, int count, const char* what);

py::tuple sizeTuple(cv::Size s);
std::string sizeString(cv::Size s);

// --- points and images ----------------------------------------------------------------------

/** Deformer.transform_points and Binding.transform_points: points of shape (..., 2) (any real
dtype; a TypeError or ValueError naming `points` otherwise), run(points, landed) without the GIL
held by the caller's choice, the result in the same shape, float32. */
py::array transformPointsArray(
    const py::handle& points,
    const std::function<void(const std::vector<cv::Point2f>&, std::vector<cv::Point2f>&)>& run);

/** An image described for messages as numpy shows it: "shape (356, 493, 3) and dtype uint8". */
std::string matDescription(const cv::Mat& image);

// --- pickling -------------------------------------------------------------------------------
// States are tuples of Python numbers, strings and numpy arrays (no raw C++ memory), first
// a version number, so that a pickle travels between processes and machines (multiprocessing
// with 'spawn', Dask) and a later module can still read it or say why not.

constexpr int kPickleVersion = 1;

void checkState(const py::tuple& state, size_t size, const char* what);

// --- the parts of the module, in the order PYBIND11_MODULE defines them ---------------------
// A class is defined before the functions and classes that take or return it, so that their
// signatures name it (multicage._multicage.Pose, not the C++ type).

void definePose(py::module_& m);         // multicage_py.cpp
void defineMulticage(py::module_& m);    // multicage_py.cpp
void defineBinding(py::module_& m);      // binding_py.cpp: Binding and bind()
void defineDeformer(py::module_& m);     // deformer_py.cpp: Deformer and deform_image()
void defineCoordinates(py::module_& m);  // binding_py.cpp: mean_value_coordinates()
void defineProposal(py::module_& m);     // propose_py.cpp
void defineAugment(py::module_& m);      // augment_py.cpp: random_pose(), validate_pose()
void defineGpu(py::module_& m);          // gpu_py.cpp: gpu_available(), auto_backend()
void defineImageIo(py::module_& m);      // imageio_py.cpp: imread()
void defineResize(py::module_& m);       // resize_py.cpp: resize_pose(), content_aware_resize()
void defineTrack(py::module_& m);        // track_py.cpp: CageTracker
void defineReframe(py::module_& m);      // reframe_py.cpp: VideoReframer, reframe_window()

}  // namespace multicage_py

#endif

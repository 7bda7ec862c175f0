// The Python module `multicage._multicage`: bindings over the C++ library, nothing more.
// Conventions follow cv2: images are numpy arrays (HxW, HxWx3 BGR, HxWx4 BGRA; uint8, uint16,
// float32), points are Nx2 arrays of (x, y), sizes are (width, height). The GIL is released
// while the library binds, deforms, proposes or computes coordinates.
//
// One file per part of the module (multicage_py.cpp, binding_py.cpp, deformer_py.cpp,
// propose_py.cpp, gpu_py.cpp, imageio_py.cpp, resize_py.cpp, track_py.cpp, reframe_py.cpp), each
// with its define function; common.hpp holds what they share.
#include "common.hpp"

namespace multicage_py {

PyObject* errorType = nullptr;
PyObject* noObjectErrorType = nullptr;

namespace {

using namespace cv::multicage;

void defineErrors(py::module_& m) {
    errorType = PyErr_NewExceptionWithDoc(
        "multicage.Error",
        "An error reported by the multicage library (a cv::Exception); the message is the "
        "library's own. Attributes: code (OpenCV error code), func (the C++ function).",
        PyExc_ValueError, nullptr);
    m.attr("Error") = py::handle(errorType);
    noObjectErrorType = PyErr_NewExceptionWithDoc(
        "multicage.NoObjectFoundError",
        "propose_multicage found no object in the image (the CLI's \"no object found\"); a "
        "multicage.Error, so a batch can skip such images with `except "
        "multicage.NoObjectFoundError`.",
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
}

void defineEnums(py::module_& m) {
    py::enum_<Backend>(m, "Backend", "Where a Deformer runs.")
        .value("AUTO", BACKEND_AUTO)
        .value("CPU", BACKEND_CPU)
        .value("GPU", BACKEND_GPU);
    py::enum_<CoordinateType>(m, "CoordinateType", "Cage coordinates.")
        .value("MEAN_VALUE", MEAN_VALUE)
        .value("HARMONIC", HARMONIC)
        .value("LOCAL_MEAN_VALUE", LOCAL_MEAN_VALUE);
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
    m.attr("MAX_MAP_STEP") = DeformParams::kMaxMapStep;  // map_step's largest value
}

}  // namespace
}  // namespace multicage_py

PYBIND11_MODULE(_multicage, m) {
    using namespace multicage_py;
    m.doc() = "multicage: multicage image deformation (bindings over the C++ library)";
    m.attr("__version__") = MULTICAGE_VERSION;

    defineErrors(m);
    defineEnums(m);
    definePose(m);
    defineMulticage(m);
    defineBinding(m);
    defineDeformer(m);
    defineCoordinates(m);
    defineProposal(m);
    defineAugment(m);
    defineGpu(m);
    defineImageIo(m);
    defineResize(m);
    defineTrack(m);
    defineReframe(m);
}

#include "convert.hpp"

#include <climits>
#include <cmath>
#include <cstdint>
#include <sstream>

namespace multicage_py {

namespace {

std::string shapeString(const py::array& a) {
    std::ostringstream s;
    s << '(';
    for (py::ssize_t i = 0; i < a.ndim(); ++i) s << (i ? ", " : "") << a.shape(i);
    s << (a.ndim() == 1 ? ",)" : ")");
    return s.str();
}

std::string dtypeString(const py::array& a) {
    return py::str(a.dtype()).cast<std::string>();
}

py::module_ numpy() {
    return py::module_::import("numpy");
}

}  // namespace

std::string typeName(const py::handle& obj) {
    const py::handle type = reinterpret_cast<PyObject*>(Py_TYPE(obj.ptr()));
    const std::string module = py::str(type.attr("__module__")).cast<std::string>();
    const std::string name = py::str(type.attr("__qualname__")).cast<std::string>();
    return module == "builtins" ? name : module + "." + name;
}

cv::Mat imageFromArray(const py::handle& obj, const char* what, py::object& keep, bool allowInt32) {
    if (obj.is_none())
        throw py::type_error(std::string(what) +
                             ": expected a numpy array, got None (cv2.imread returns None "
                             "when it cannot read the file: check the path)");
    if (!py::isinstance<py::array>(obj))
        throw py::type_error(std::string(what) +
                             ": expected a numpy array (as cv2.imread returns), got " +
                             typeName(obj));
    py::array a = py::reinterpret_borrow<py::array>(obj);
    int depth;
    if (py::isinstance<py::array_t<std::uint8_t>>(a))
        depth = CV_8U;
    else if (py::isinstance<py::array_t<std::uint16_t>>(a))
        depth = CV_16U;
    else if (py::isinstance<py::array_t<float>>(a))
        depth = CV_32F;
    else if (allowInt32 && py::isinstance<py::array_t<std::int32_t>>(a))
        depth = CV_32S;
    else
        throw py::type_error(std::string(what) + ": dtype " + dtypeString(a) +
                             " is not supported; use uint8, uint16 or float32 as cv2 does "
                             "(for example " +
                             what + ".astype(numpy.float32))");
    if (a.ndim() != 2 && a.ndim() != 3)
        throw py::value_error(std::string(what) + ": shape " + shapeString(a) +
                              " is not an image; expected HxW, HxWx3 (BGR) or HxWx4 (BGRA)");
    const int cn = a.ndim() == 2 ? 1 : static_cast<int>(a.shape(2));
    if (cn != 1 && cn != 3 && cn != 4)
        throw py::value_error(std::string(what) + ": " + std::to_string(cn) + " channels (shape " +
                              shapeString(a) +
                              ") are not supported; use 1 (HxW), 3 (HxWx3, BGR) or "
                              "4 (HxWx4, BGRA)");
    if (a.shape(0) == 0 || a.shape(1) == 0)
        throw py::value_error(std::string(what) + ": the image is empty (shape " + shapeString(a) +
                              ")");
    if (a.shape(0) > INT_MAX / 4 || a.shape(1) > INT_MAX / 4)
        throw py::value_error(std::string(what) + ": shape " + shapeString(a) + " is too large");

    // OpenCV needs packed pixels and channels and rows at a positive step; a crop of a C-order
    // array has that and is shared as it is, anything else (transposed, strided) is copied.
    const py::ssize_t item = a.itemsize();
    const py::ssize_t pixel = item * cn;
    const bool aligned =
        (a.flags() & py::array::c_style) != 0 ||
        (reinterpret_cast<std::uintptr_t>(a.data()) % item == 0 && a.strides(0) % item == 0);
    bool packed = a.strides(1) == pixel && (a.ndim() == 2 || a.strides(2) == item) &&
                  a.strides(0) >= pixel * a.shape(1) && aligned;
    if (!packed) {
        a = numpy().attr("ascontiguousarray")(a);
        keep = a;
    }
    return cv::Mat(static_cast<int>(a.shape(0)), static_cast<int>(a.shape(1)),
                   CV_MAKETYPE(depth, cn), const_cast<void*>(a.data()),
                   static_cast<size_t>(a.strides(0)));
}

std::vector<cv::Point2f> pointsFromArray(const py::handle& obj, const char* what, int expected,
                                         bool finite) {
    py::array a = numpy().attr("asarray")(obj);
    const char kind = a.dtype().kind();
    if (kind != 'f' && kind != 'i' && kind != 'u')
        throw py::type_error(
            std::string(what) + ": dtype " + dtypeString(a) +
            " is not a real number type; use an Nx2 float32 array of (x, y) points");
    const bool nx2 = a.ndim() == 2 && a.shape(1) == 2;
    const bool nx1x2 = a.ndim() == 3 && a.shape(1) == 1 && a.shape(2) == 2;
    if (!nx2 && !nx1x2)
        throw py::value_error(
            std::string(what) + ": shape " + shapeString(a) +
            " is not a list of points; expected Nx2 (x, y) (or Nx1x2 as cv2.findContours gives)");
    const int n = static_cast<int>(a.shape(0));
    if (expected >= 0 && n != expected)
        throw py::value_error(std::string(what) + ": " + std::to_string(n) + " points, expected " +
                              std::to_string(expected));
    auto f = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
    if (!f) throw py::error_already_set();
    const float* p = f.data();
    std::vector<cv::Point2f> points(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) {
        points[i] = cv::Point2f(p[2 * i], p[2 * i + 1]);
        if (finite && !(std::isfinite(points[i].x) && std::isfinite(points[i].y))) {
            std::ostringstream s;
            s << what << ": point " << i << " is not finite (" << points[i].x << ", " << points[i].y
              << ")";
            throw py::value_error(s.str());
        }
    }
    return points;
}

py::array arrayFromMat(const cv::Mat& mat, bool writeable) {
    CV_Assert(mat.dims == 2);
    py::dtype dtype;
    switch (mat.depth()) {
        case CV_8U:
            dtype = py::dtype::of<std::uint8_t>();
            break;
        case CV_8S:
            dtype = py::dtype::of<std::int8_t>();
            break;
        case CV_16U:
            dtype = py::dtype::of<std::uint16_t>();
            break;
        case CV_16S:
            dtype = py::dtype::of<std::int16_t>();
            break;
        case CV_32S:
            dtype = py::dtype::of<std::int32_t>();
            break;
        case CV_32F:
            dtype = py::dtype::of<float>();
            break;
        case CV_64F:
            dtype = py::dtype::of<double>();
            break;
        default:
            throw std::runtime_error("multicage: no numpy dtype for " +
                                     cv::typeToString(mat.type()));
    }
    const int cn = mat.channels();
    const auto item = static_cast<py::ssize_t>(mat.elemSize1());
    std::vector<py::ssize_t> shape{mat.rows, mat.cols},
        strides{static_cast<py::ssize_t>(mat.step[0]), static_cast<py::ssize_t>(mat.elemSize())};
    if (cn > 1) {
        shape.push_back(cn);
        strides.push_back(item);
    }
    // The array keeps a reference to the Mat's buffer: no copy, freed with the last user.
    auto* owner = new cv::Mat(mat);
    py::capsule base(owner, [](void* p) { delete static_cast<cv::Mat*>(p); });
    py::array out(dtype, shape, strides, mat.data, base);
    if (!writeable) out.attr("setflags")(py::arg("write") = false);
    return out;
}

py::array arrayFromPoints(const std::vector<cv::Point2f>& points) {
    py::array_t<float> out({static_cast<py::ssize_t>(points.size()), py::ssize_t{2}});
    float* p = out.mutable_data();
    for (size_t i = 0; i < points.size(); ++i) {
        p[2 * i] = points[i].x;
        p[2 * i + 1] = points[i].y;
    }
    return out;
}

cv::Size sizeFromObject(const py::handle& obj, const char* what) {
    if (py::isinstance<py::str>(obj) || !py::isinstance<py::sequence>(obj) || py::len(obj) != 2)
        throw py::type_error(std::string(what) + ": expected (width, height), got " +
                             typeName(obj));
    const py::sequence s = py::reinterpret_borrow<py::sequence>(obj);
    int w, h;
    try {
        w = s[0].cast<int>();
        h = s[1].cast<int>();
    } catch (const py::cast_error&) {
        throw py::type_error(std::string(what) + ": expected (width, height) as two integers");
    }
    if (w <= 0 || h <= 0)
        throw py::value_error(std::string(what) + ": (" + std::to_string(w) + ", " +
                              std::to_string(h) + ") is not a positive (width, height)");
    return cv::Size(w, h);
}

cv::Scalar scalarFromObject(const py::handle& obj, const char* what) {
    if (obj.is_none()) return cv::Scalar();
    if (py::isinstance<py::float_>(obj) || py::isinstance<py::int_>(obj) ||
        (py::isinstance<py::array>(obj) && py::reinterpret_borrow<py::array>(obj).ndim() == 0))
        return cv::Scalar::all(obj.cast<double>());
    if (!py::isinstance<py::sequence>(obj) || py::isinstance<py::str>(obj))
        throw py::type_error(std::string(what) + ": expected a number or up to 4 numbers, got " +
                             typeName(obj));
    const py::sequence s = py::reinterpret_borrow<py::sequence>(obj);
    if (py::len(s) < 1 || py::len(s) > 4)
        throw py::value_error(std::string(what) + ": expected 1 to 4 values, got " +
                              std::to_string(py::len(s)));
    cv::Scalar v;
    for (size_t i = 0; i < py::len(s); ++i) v[static_cast<int>(i)] = s[i].cast<double>();
    return v;
}

}  // namespace multicage_py

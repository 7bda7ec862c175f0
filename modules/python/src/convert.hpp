// numpy <-> cv::Mat for the Python module, with the checks that make bad input fail early
// and clearly (the C++ library would reject it too, but with less Python-shaped words).
#ifndef MULTICAGE_PYTHON_CONVERT_HPP
#define MULTICAGE_PYTHON_CONVERT_HPP

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace multicage_py {

namespace py = pybind11;

/** An image as cv2 gives it: a numpy array of uint8, uint16 or float32, HxW, HxWx1, HxWx3 or
HxWx4. The Mat shares the array's memory when its rows are laid out as OpenCV needs (C order,
or a crop of such an array), else it is a contiguous copy; `keep` then holds the copy.
allowInt32 also takes int32 (label images for the proposal). Throws TypeError (not an array,
wrong dtype) or ValueError (shape), naming `what`. */
cv::Mat imageFromArray(const py::handle& obj, const char* what, py::object& keep,
                       bool allowInt32 = false);

/** Points as an Nx2 (or Nx1x2, as cv2.findContours gives) array-like of real numbers, as
float32. expected >= 0 also checks the count; finite checks for NaN and infinity. */
std::vector<cv::Point2f> pointsFromArray(const py::handle& obj, const char* what, int expected = -1,
                                         bool finite = true);

/** A Mat as a numpy array that owns a reference to the Mat's data (no copy): HxW for one
channel, HxWxC otherwise. writeable=false marks the array read-only. */
py::array arrayFromMat(const cv::Mat& mat, bool writeable = true);

/** Points as an Nx2 float32 array. */
py::array arrayFromPoints(const std::vector<cv::Point2f>& points);

/** (width, height) from a 2-sequence of integers. */
cv::Size sizeFromObject(const py::handle& obj, const char* what);

/** A number or a sequence of up to 4 numbers as a Scalar. */
cv::Scalar scalarFromObject(const py::handle& obj, const char* what);

/** Python's repr of an object's type, for messages ("numpy.ndarray", "list"). */
std::string typeName(const py::handle& obj);

}  // namespace multicage_py

#endif

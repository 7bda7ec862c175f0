// Conversion of the point arrays users pass (private).
#ifndef MULTICAGE_POINT_INPUT_HPP
#define MULTICAGE_POINT_INPUT_HPP

#include <opencv2/core.hpp>
#include <vector>

namespace cv {
namespace multicage {

/** Reads std::vector<Point2f>/<Point>/<Point2d> or an Nx2 / Nx1 two-channel (or 1xN) matrix of
CV_32F, CV_64F or CV_32S into points. `what` names the argument in the error message. */
std::vector<Point2f> toPoints(InputArray points, const char* what);

}  // namespace multicage
}  // namespace cv

#endif

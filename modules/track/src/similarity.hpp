// The least-squares similarity between two point sets, shared by the tracker and carryPose.
#ifndef MULTICAGE_TRACK_SIMILARITY_HPP
#define MULTICAGE_TRACK_SIMILARITY_HPP

#include <opencv2/core.hpp>
#include <vector>

namespace cv {
namespace multicage {

/** The similarity (turn, uniform scale, shift; no reflection) that carries the points `from`
closest to `to` in the least squares (Umeyama 1991), over the points whose `use` is set (all of
them when `use` is empty), as a 2x3 CV_64F matrix for cv::transform; the identity's turn and scale
where those points do not spread. */
Mat leastSquaresSimilarity(const std::vector<Point2f>& from, const std::vector<Point2f>& to,
                           const std::vector<uchar>& use = std::vector<uchar>());

}  // namespace multicage
}  // namespace cv

#endif

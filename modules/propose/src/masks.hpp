// Masks cleaned up (private): the pieces that hold something sure, openings, closings, and
// specks and holes removed.
#ifndef MULTICAGE_PROPOSE_MASKS_HPP
#define MULTICAGE_PROPOSE_MASKS_HPP

#include <opencv2/core.hpp>

namespace cv {
namespace multicage {
namespace propose_detail {

/** The pieces (8-connected components) of `mask` holding a non-zero pixel of `sure`: the
person is what holds a face, so a candle on the table or a lit patch of the wall that GrabCut
found apart from every face is not the subject. */
Mat piecesHolding(const Mat& mask, const Mat& sure);

/** Opening then closing with a disk of `radius`, then regions and holes smaller than
minArea pixels removed. */
Mat cleanMask(const Mat& mask, int radius, double minArea);

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv

#endif

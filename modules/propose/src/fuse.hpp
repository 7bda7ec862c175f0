// The learned subject map fused with the proposal's other cues (private): the person prior of
// the faces found, and the frame-inward GrabCut for a subject that goes on past the frame.
#ifndef MULTICAGE_PROPOSE_FUSE_HPP
#define MULTICAGE_PROPOSE_FUSE_HPP

#include <opencv2/multicage/propose.hpp>

namespace cv {
namespace multicage {
namespace propose_detail {

/** The subject of `img` (the 8-bit work copy, 1 or 3 channels) where the subject model ran:
`map` (CV_32FC1, any size, 0..1, subjectMapOf) fused with `person` (personSeed's work-size
labels; empty without faces), by the rule fuse.cpp opens with. Returns a work-size mask, 255
on the subject, before cleaning; empty when the map holds no subject, or only the whole
picture: then the classic cues decide. */
Mat fusedSubject(const Mat& img, const Mat& map, const Mat& person, const ProposeParams& params);

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv

#endif

// The learned subject cue (private): a salient-object network run through OpenCV's dnn module
// (U^2-Net-P by default, docs/models.md), found, checked and read once per process.
#ifndef MULTICAGE_PROPOSE_SEGMENTER_HPP
#define MULTICAGE_PROPOSE_SEGMENTER_HPP

#include <opencv2/multicage/propose.hpp>

namespace cv {
namespace multicage {
namespace propose_detail {

/** A subject model to run: its file, and whether it is the pinned default (found in the build
tree or the install prefix), whose size and sha256 are checked before it is read. */
struct SubjectModel {
    String file;
    bool pinned = false;
    bool empty() const { return file.empty(); }
};

/** The model a proposal runs for `params`: none for SEGMENTER_CLASSIC, and for
SEGMENTER_AUTO when none is found; SEGMENTER_MODEL without one throws StsObjectNotFound
saying how to get one. */
SubjectModel modelToRun(const ProposeParams& params);

/** The subject map of `img` (8-bit, 1 or 3 channels) by `model`: CV_32FC1 of the model's own
input size (256x256 for the pinned U^2-Net-P), 0..1. Reads the model on first use (see subjectMap in
propose.hpp for the errors); runs of one model from several threads take turns. */
Mat subjectMapOf(const Mat& img, const SubjectModel& model);

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv

#endif

// The subject of a photo with no face and no rectangle from the caller (private): GrabCut from
// the image frame inward, the frame reopened where the subject is cut by it.
#ifndef MULTICAGE_PROPOSE_SUBJECT_HPP
#define MULTICAGE_PROPOSE_SUBJECT_HPP

#include <opencv2/core.hpp>

#include "tasks.hpp"

namespace cv {
namespace multicage {
namespace propose_detail {

/** GrabCut labels (GC_BGD ... GC_PR_FGD) of the subject of `img` (CV_8UC3, GrabCut's working
size) after `iterations` iterations from the frame inward, then as many again with the frame
reopened where the subject is cut by it (subject.cpp says when). `salientStart`, when not empty,
holds GrabCut's start from a rectangle around the salient part: GrabCut runs from it too (beside
the frame-inward passes), and the frame-inward subject is returned only if it holds at least 80%
of that part's subject, else that part's labels are.

`beside`, when set, is work that decides whether the subject is wanted (the proposal's profile
and small face searches, tasks.hpp): its tasks run beside the frame-inward passes when there is
no salient part's GrabCut to run there, else before both; when the subject is not wanted then,
nothing else runs and the labels are empty. `reopened`, when set, tells whether the second
pass was kept (the subject goes on past the frame). */
Mat frameInwardSubject(const Mat& img, int iterations, const Mat& salientStart = Mat(),
                       const Beside& beside = {}, bool* reopened = nullptr);

/** True when some piece of the strip along the frame is as sharp as the picture's middle: the
frame may cut an in-focus subject, the condition of frameInwardSubject's second pass. */
bool frameInFocus(const Mat& img);

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv

#endif

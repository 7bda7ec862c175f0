// The subject of a photo with no face and no rectangle from the caller (private): GrabCut from
// the image frame inward, the frame reopened where the subject is cut by it.
#ifndef MULTICAGE_PROPOSE_SUBJECT_HPP
#define MULTICAGE_PROPOSE_SUBJECT_HPP

#include <opencv2/core.hpp>

namespace cv {
namespace multicage {
namespace propose_detail {

/** GrabCut labels (GC_BGD ... GC_PR_FGD) of the subject of `img` (CV_8UC3, GrabCut's working
size) after `iterations` iterations from the frame inward, then as many again with the frame
reopened where the subject is cut by it (subject.cpp says when). */
Mat frameInwardSubject(const Mat& img, int iterations);

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv

#endif

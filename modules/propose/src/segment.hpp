// The segmentation stage of the proposal (private): image -> binary mask of objects.
#ifndef MULTICAGE_PROPOSE_SEGMENT_HPP
#define MULTICAGE_PROPOSE_SEGMENT_HPP

#include <opencv2/multicage/propose.hpp>

#include "tasks.hpp"
#include "work.hpp"

namespace cv {
namespace multicage {
namespace propose_detail {

/** The input as 8-bit, 1 or 3 channels (alpha dropped; 16-bit and float rescaled). Throws
StsBadArg for an empty image or an unsupported channel count. */
Mat to8Bit(const Mat& image);
/** True when every pixel of an image holds the same bytes as the first (8-bit images here). */
bool isConstant(const Mat& image);

/** Otsu's threshold over the pixels where mask is non-zero (the whole image when mask is
empty); img is CV_8UC1. Returns the threshold t: pixels > t are the upper class. */
int otsuThreshold(const Mat& img, const Mat& mask = Mat());

/** Per pixel, the distance (Lab, 8-bit units, saturated to 255) from a background colour:
the median over the pixels where `backgroundMask` is non-zero. img: CV_8UC1 or CV_8UC3. */
Mat backgroundDistance(const Mat& img, const Mat& backgroundMask);
/** backgroundMask for backgroundDistance(): a strip along the image border. */
Mat borderStrip(Size size);
/** True when the background is plain: at most a quarter of the border strip (borderStrip)
differs from its median colour by more than 24 (backgroundDistance), what a threshold wants.
img: 8-bit, 1 or 3 channels. */
bool plainBackground(const Mat& img);

/** The saliency map (CV_8UC1 of img's size, 0..255) of opencv_contrib's fine grained or
spectral residual static saliency. */
Mat saliencyMap(const Mat& img, bool spectralResidual);

/** Raw segmentation (before cleaning) of an 8-bit work image: CV_8UC1, 255 on objects.
`method` is one of the image-based methods (threshold, adaptive, grabcut, saliency,
spectral); `region` (optional) restricts thresholds to the pixels inside it. */
Mat segmentImage(const Mat& img, int method, const ProposeParams& params, double scale,
                 const Mat& region = Mat());

/** What the outlines enclose. */
struct Segmentation {
    Mat objects;  // work size, 255 on objects (cleaned)
    Mat labels;   // work size CV_32S for PROPOSE_LABELS, else empty
};

/** The proposal's segmentation of an input (proposeMulticage's first stage): a mask or label
input as given (cleaned), a photo by params.method (PROPOSE_AUTO: threshold on a plain
background, else GrabCut from the frame inward, subject.hpp), cleaned. Throws StsBadArg for an empty
or constant image and a mask with more than one channel. `person`, when not empty, is a work-size
GrabCut seed from the person prior (person.hpp): GC_FGD / GC_PR_FGD where a face and the body below
it are, GC_PR_BGD elsewhere; with it PROPOSE_AUTO always runs GrabCut.

`beside`, when set, is work that decides whether the segmentation is wanted (tasks.hpp): the
proposal's profile and small face searches, which a face found makes the face-blind
segmentation moot (propose.cpp). Its tasks run beside the segmentation where that leaves a core
idle (the frame-inward GrabCut of a picture whose salient part is all of it: one chain of
GrabCuts), else before it; when it is not wanted then, the segmentation is skipped and empty.

`subject`, when not empty, is the subject model's map of the image (subjectMapOf): with
PROPOSE_AUTO and no rect it is fused with the person prior and the frame-inward GrabCut
(fuse.hpp), and the classic cues decide only where it holds no subject. */
Segmentation segmentForProposal(const Mat& image, const Work& w, const ProposeParams& params,
                                const Mat& person = Mat(), const Beside& beside = {},
                                const Mat& subject = Mat());

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv

#endif

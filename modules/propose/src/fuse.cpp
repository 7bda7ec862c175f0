// How the subject model's map joins what the proposal already knows (docs/propose/README.md,
// "The cues and how they are fused"). The map is a strong cue, not the answer: it is GrabCut's
// start. With faces the colour models then follow the person's own edges; without faces they
// may only trim the map, since what they added to it was background more often than subject.
//
//   faces found      the map is the start (as below), the face boxes sure subject, and the
//                    person prior's head and body (person.hpp) probable subject where the map
//                    sees something there (above kNear); where GrabCut's subject and the map's
//                    with the face boxes disagree (IoU under kAgreesWithFaces), those are kept;
//                    the map's subjects apart from every person stay as the map sees them; the
//                    pieces holding neither a face nor the map's sure subject are dropped (the
//                    candle beside the woman of the dinner scene).
//   no face          the map is the start: sure subject where it is above kSure, probable
//                    subject above kSubject, probable background near it, sure background
//                    elsewhere; GrabCut only trims the map (what it adds is dropped), and where
//                    its subject and the map's disagree (IoU under kAgrees) the map is kept.
//                    Where the map's subject stays inside the picture and the frame is in focus
//                    somewhere (frameInFocus), the frame-inward GrabCut runs beside it: when
//                    that one finds the subject going on past the frame, fills the frame
//                    (kFillsFrame) and holds the map's subject, it wins (a close-up whose fur
//                    fills the frame, which the network sees as a face in the middle). The
//                    map's subject is its check: the classic path's salient part and its
//                    GrabCut are not run.
//   nothing / all    no map value above kSubject, or above it nearly everywhere: the map says
//                    nothing, and the classic cues decide (segment.cpp).
#include "fuse.hpp"

#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include "grabcut.hpp"
#include "masks.hpp"
#include "subject.hpp"
#include "tasks.hpp"
#include "work.hpp"

namespace cv {
namespace multicage {
namespace propose_detail {

namespace {

constexpr double kSubject = 0.5;          // map value: probable subject
constexpr double kSure = 0.8;             // map value: sure subject
constexpr double kNear = 0.2;             // map value: something is there
constexpr double kNearReach = 0.08;       // of the longer side: probable background around it
constexpr double kMostOfAll = 0.97;       // the map's subject covering this much is the picture
constexpr double kCutByFrame = 0.05;      // share of the frame strip the map's subject covers
constexpr double kHolds = 0.9;            // share of the map's subject the frame-inward one holds
constexpr double kFillsFrame = 0.85;      // share of the picture a frame-filling subject covers
constexpr double kAgrees = 0.85;          // IoU of GrabCut's subject and the map's
constexpr double kAgreesWithFaces = 0.8;  // the same, the map's with the face boxes
constexpr int kSettleWithin = 5;          // GrabCut's iterations at most (seededGrabCut)

Mat subjectOf(const Mat& labels) {
    return (labels == GC_FGD) | (labels == GC_PR_FGD);
}

// GrabCut's start from the map alone.
Mat mapStart(const Mat& m) {
    Mat labels(m.size(), CV_8U, Scalar(GC_BGD));
    const int r = std::max(1, cvRound(kNearReach * std::max(m.cols, m.rows)));
    Mat near;
    dilate(m > kNear, near, getStructuringElement(MORPH_ELLIPSE, Size(2 * r + 1, 2 * r + 1)));
    labels.setTo(GC_PR_BGD, near);
    labels.setTo(GC_PR_FGD, m > kSubject);
    labels.setTo(GC_FGD, m > kSure);
    return labels;
}

// Whether GrabCut's subject still agrees with the map's (IoU at least `least`).
bool agrees(const Mat& grabCut, const Mat& map, double least) {
    return countNonZero(grabCut & map) >= least * countNonZero(grabCut | map);
}

// Share of a strip along the frame (3% of the longer side) that `mask` covers.
double frameShare(const Mat& mask) {
    const int b = std::max(1, cvRound(0.03 * std::max(mask.cols, mask.rows)));
    Mat strip(mask.size(), CV_8U, Scalar(255));
    if (mask.cols > 2 * b && mask.rows > 2 * b)
        strip(Rect(b, b, mask.cols - 2 * b, mask.rows - 2 * b)).setTo(0);
    return countNonZero(mask & strip) / std::max(1.0, static_cast<double>(countNonZero(strip)));
}

}  // namespace

Mat fusedSubject(const Mat& img, const Mat& map, const Mat& person, const ProposeParams& params) {
    CV_Assert(map.type() == CV_32FC1 && !map.empty());
    Mat color;
    if (img.channels() == 1)
        cvtColor(img, color, COLOR_GRAY2BGR);
    else
        color = img;
    Mat small, m;
    shrink(color, small, params.grabCutMaxSide / static_cast<double>(std::max(img.cols, img.rows)),
           INTER_AREA);
    resize(map, m, small.size(), 0, 0, INTER_LINEAR);
    const Mat subject = m > kSubject;
    const int n = countNonZero(subject);
    if (n == 0 || n > kMostOfAll * subject.total()) return Mat();
    Mat mask;
    if (!person.empty()) {
        Mat prior;
        resize(person, prior, small.size(), 0, 0, INTER_NEAREST);
        Mat labels = mapStart(m);
        labels.setTo(GC_PR_FGD, (prior == GC_PR_FGD) & (m > kNear));
        const Mat face = prior == GC_FGD;
        labels.setTo(GC_FGD, face);
        seededGrabCut(small, labels, params.grabCutIterations);
        // As without a face: where GrabCut parted from the map (the dark background beside
        // the dinner scene's dark hair), the map and the face boxes are kept.
        mask = subjectOf(labels);
        const Mat seen = subject | face;
        if (!agrees(mask, seen, kAgreesWithFaces)) mask = seen;
        // The person prior guides GrabCut around the persons only: a subject the map sees
        // apart from all of them stays as the map sees it (the man whose face is turned away
        // beside the basketball player: GrabCut gave his dark hair to the dark doorway).
        mask |= subject & ~piecesHolding(subject, (prior == GC_PR_FGD) | face);
        mask = piecesHolding(mask, face | (m > kSure));
    } else {
        Mat labels = mapStart(m), inward;
        bool reopened = false;
        const bool tryInward = frameShare(subject) <= kCutByFrame && frameInFocus(small);
        // Two GrabCut chains, one core each; each is seeded by itself (seededGrabCut).
        Tasks chains{
            [&] { seededGrabCut(small, labels, params.grabCutIterations, kSettleWithin); }};
        if (tryInward)  // the map's subject is the check the salient part's GrabCut was
            chains.push_back([&] {
                inward = frameInwardSubject(small, params.grabCutIterations, Mat(), {}, &reopened);
            });
        runTasks(chains);
        // GrabCut from the map only trims it: what GrabCut adds follows colours the background
        // shares with the subject (a kangaroo's fur and the sunlit path, a dog's and the dry
        // grass), and where it no longer agrees with the map, the map is kept.
        mask = subjectOf(labels);
        mask = agrees(mask, subject, kAgrees) ? Mat(mask & subject) : subject.clone();
        // A subject that fills the frame, seen by the network as its middle only (a close-up of
        // a baboon's face and fur): the frame-inward subject, where it holds the map's.
        if (reopened) {
            const Mat wide = subjectOf(inward);
            if (countNonZero(wide) >= kFillsFrame * wide.total() &&
                countNonZero(wide & subject) >= kHolds * n)
                mask = wide;
        }
    }
    if (mask.size() != img.size()) {
        resize(mask, mask, img.size(), 0, 0, INTER_LINEAR);
        threshold(mask, mask, 127, 255, THRESH_BINARY);
    }
    return mask;
}

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv

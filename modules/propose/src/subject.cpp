// The subject of a photo from the frame inward: what a person drawing a cage assumes (the
// subject is in the picture, the frame runs through the background), except where the subject
// is too big for the picture and the frame cuts it (a close-up of a cat or a baboon). The
// measurements behind each threshold are in docs/propose/history.md ("The frame-inward subject").
//
// First pass: a strip along the frame (3% of the longer side) is sure background, the rest
// probable subject; GrabCut keeps what does not look like the frame. It must hold what GrabCut
// from a rectangle around the spectral residual salient part found (that alone lights up an eye
// or a nose and leaves the rest of the animal out).
//
// Second pass, only where the first found the subject cut by the frame: the subject covers more
// than 30% of the band just inside the strip (per twelfth of a side) and the strip there is in
// focus (its mean Laplacian at least half the middle's: photographers let the background blur).
// Those runs of the strip become probable background and GrabCut runs again. The pass is kept
// only when what it adds goes on inward (at least half of it deeper than three strips, and at
// least 5% of the picture: not a table in focus along the bottom), and it is not run where
// every piece would be reopened (no sure background would be left to learn from).
//
// The salient part's GrabCut runs beside the frame-inward passes, or the proposal's profile
// face searches take the second core (`beside`). Each GrabCut is seeded by itself
// (seededGrabCut), so the result does not depend on which runs first or on the thread count.

#include "subject.hpp"

#include <algorithm>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include "grabcut.hpp"
#include "work.hpp"

namespace cv {
namespace multicage {
namespace propose_detail {

namespace {

constexpr double kStrip = 0.03;             // of the longer side
constexpr int kPiecesPerSide = 12;          // the strip is judged in twelfths of each side
constexpr double kReached = 0.3;            // share of the band inside a piece that is subject
constexpr double kSharpAsMiddle = 0.5;      // a piece's sharpness against the middle's
constexpr double kInward = 0.5;             // share of what the second pass adds that lies inside
constexpr double kInwardOfPicture = 0.05;   // and its share of the picture
constexpr double kSecondScale = 2.0 / 3.0;  // the second pass's copy
constexpr double kHoldsSalient = 0.8;       // share of the salient part the subject must hold
// Each GrabCut here goes on past ProposeParams::grabCutIterations, up to this many iterations,
// until one moves at most 1% of the pixels (seededGrabCut). Started from a whole strip or a
// rectangle, GrabCut is still carving the subject out after two iterations on some photos:
// on the benchmark's squirrel and robin the second moves 3-13% of the pixels and later ones up
// to 17%, and stopping after two left a rectangle of leaves or blurred background around
// them (most GrabCuts move under 1.5% in their second iteration: they stop there). Run
// until settled: squirrel outline IoU 0.36 -> 0.70, robin 0.46 -> 0.54, chelsea 0.49 -> 0.46,
// the mean of the 13 benchmark photos 0.671 -> 0.702 (0.664 -> 0.693 over the photos at 0.8,
// 0.9, 1.1 and 1.25x their sizes). Not for the person prior's GrabCut (segment.cpp): there
// the later iterations let the colour models drift from the prior and drop the body (the
// astronaut's suit at 1.1x: outline IoU 0.70 -> 0.15).
constexpr int kSettleWithin = 5;

// A piece of the strip along the frame and the band of the same size just inside it.
struct Piece {
    Rect strip, band;
};

// The strip's pieces in order around the frame (clockwise), so that neighbours are adjacent.
std::vector<Piece> piecesAround(Size size, int b) {
    const int w = size.width, h = size.height, k = kPiecesPerSide;
    std::vector<Piece> out;
    for (int i = 0; i < k; ++i) {  // top, left to right
        const int a = i * w / k, e = (i + 1) * w / k;
        out.push_back({Rect(a, 0, e - a, b), Rect(a, b, e - a, b)});
    }
    for (int i = 0; i < k; ++i) {  // right, top to bottom
        const int a = i * h / k, e = (i + 1) * h / k;
        out.push_back({Rect(w - b, a, b, e - a), Rect(w - 2 * b, a, b, e - a)});
    }
    for (int i = k - 1; i >= 0; --i) {  // bottom, right to left
        const int a = i * w / k, e = (i + 1) * w / k;
        out.push_back({Rect(a, h - b, e - a, b), Rect(a, h - 2 * b, e - a, b)});
    }
    for (int i = k - 1; i >= 0; --i) {  // left, bottom to top
        const int a = i * h / k, e = (i + 1) * h / k;
        out.push_back({Rect(0, a, b, e - a), Rect(b, a, b, e - a)});
    }
    return out;
}

// Local sharpness: the Laplacian's magnitude averaged over 2% of the longer side.
Mat sharpness(const Mat& img) {
    Mat gray, lap;
    cvtColor(img, gray, COLOR_BGR2GRAY);
    Laplacian(gray, lap, CV_32F, 3);
    lap = abs(lap);
    GaussianBlur(lap, lap, Size(), std::max(1.0, 0.02 * std::max(img.cols, img.rows)));
    return lap;
}

// Which pieces of the strip are as sharp as the picture's middle.
std::vector<char> sharpPieces(const std::vector<Piece>& pieces, const Mat& img) {
    const Mat sharp = sharpness(img);
    const Rect middle(img.cols / 4, img.rows / 4, img.cols / 2, img.rows / 2);
    const double least = kSharpAsMiddle * mean(sharp(middle))[0];
    std::vector<char> isSharp(pieces.size());
    for (size_t i = 0; i < pieces.size(); ++i)
        isSharp[i] = mean(sharp(pieces[i].strip))[0] >= least;
    return isSharp;
}

int stripWidth(Size size) {
    return std::max(2, cvRound(kStrip * std::max(size.width, size.height)));
}

// Which pieces the subject continues through: runs of sharp pieces holding a reached one.
std::vector<char> reopened(const std::vector<Piece>& pieces, const Mat& subject, const Mat& img) {
    const std::vector<char> isSharp = sharpPieces(pieces, img);
    const int n = static_cast<int>(pieces.size());
    std::vector<char> open(n, 0);
    for (int i = 0; i < n; ++i) {
        const Rect band = pieces[i].band;
        if (!isSharp[i] || countNonZero(subject(band)) <= kReached * band.area()) continue;
        for (int step : {1, -1})
            for (int j = i; isSharp[j] && (j == i || !open[j]); j = (j + step + n) % n) {
                open[j] = 1;
                if ((j + step + n) % n == i) break;  // all the way round
            }
    }
    return open;
}

// A subject cut by the frame goes on inward: the second pass must add subject inside the
// picture, not only a strip along the frame (the table an apple stands on).
bool goesInward(const Mat& first, const Mat& second, int b) {
    const Mat added =
        ((second == GC_FGD) | (second == GC_PR_FGD)) & (first != GC_FGD) & (first != GC_PR_FGD);
    const int deep = 3 * b;
    const Rect inside(deep, deep, first.cols - 2 * deep, first.rows - 2 * deep);
    const int all = countNonZero(added),
              within = inside.area() > 0 ? countNonZero(added(inside)) : 0;
    return within >= kInward * all && within >= kInwardOfPicture * first.total();
}

// GrabCut's start from the frame inward: the strip along the frame sure background, the rest
// probable subject; `b` is the strip's width. An image too small for a strip and a band gets a
// one-pixel frame.
Mat frameStart(Size size, int b) {
    if (size.width < 3 || size.height < 3)
        CV_Error_(Error::StsBadArg,
                  ("multicage: proposeMulticage: a %dx%d image is too small for GrabCut",
                   size.width, size.height));
    const int s = size.width <= 4 * b || size.height <= 4 * b ? 1 : b;
    Mat labels(size, CV_8U, Scalar(GC_BGD));
    labels(Rect(s, s, size.width - 2 * s, size.height - 2 * s)).setTo(GC_PR_FGD);
    return labels;
}

// The second pass (where the first found the subject cut by the frame) on the labels of the first:
// the second pass's labels when it goes inward, else an empty Mat (the first's stand). The second
// pass runs on a copy two thirds the size (kSecondScale), its labels scaled back. It was once only
// a trial there, deciding whether to run it again at full size from the first pass's flow, because
// it is refused more often than kept (refused on the apple, the orange, the robin, the coffee and
// the butterfly, kept on the baboon; on a copy half the size it refused the baboon too). The
// full-size run added 100 ms to the baboon's 350 and did not draw better outlines: the baboon's
// outline IoU is 0.934 from the copy's labels against 0.911 from the full size's (0.929 / 0.910 at
// 0.8x, 0.935 / 0.911 at 1.25x), and of opencv-doc's 91 example pictures the 4 that keep a second
// pass (the baboon, board.jpg, right02.jpg, right11.jpg) have alike outlines both ways but for
// right11.jpg, where the copy's goes around the chessboard and the full size's around the whole
// frame.
Mat reopenedPass(const Mat& img, int iterations, int b, const Mat& first, const Mat& labels) {
    const std::vector<Piece> pieces = piecesAround(img.size(), b);
    const std::vector<char> open =
        reopened(pieces, (labels == GC_FGD) | (labels == GC_PR_FGD), img);
    // None: the frame does not cut the subject. All: no sure background would be left.
    const auto opened = std::count(open.begin(), open.end(), 1);
    if (opened == 0 || opened == static_cast<long>(open.size())) return Mat();
    Mat second = first.clone();
    for (size_t i = 0; i < pieces.size(); ++i)
        if (open[i]) second(pieces[i].strip).setTo(GC_PR_BGD);
    Mat small, smallFirst, smallSecond;
    shrink(img, small, kSecondScale, INTER_AREA);
    resize(labels, smallFirst, small.size(), 0, 0, INTER_NEAREST);
    resize(second, smallSecond, small.size(), 0, 0, INTER_NEAREST);
    seededGrabCut(small, smallSecond, iterations, kSettleWithin);
    if (!goesInward(smallFirst, smallSecond, std::max(1, cvRound(kSecondScale * b)))) return Mat();
    resize(smallSecond, second, img.size(), 0, 0, INTER_NEAREST);
    return second;
}

}  // namespace

bool frameInFocus(const Mat& img) {
    const int b = stripWidth(img.size());
    if (img.cols <= 4 * b || img.rows <= 4 * b) return false;
    const std::vector<char> sharp = sharpPieces(piecesAround(img.size(), b), img);
    return std::find(sharp.begin(), sharp.end(), 1) != sharp.end();
}

Mat frameInwardSubject(const Mat& img, int iterations, const Mat& salientStart,
                       const Beside& beside, bool* reopenedKept) {
    CV_Assert(img.type() == CV_8UC3);
    if (reopenedKept) *reopenedKept = false;
    const int b = stripWidth(img.size());
    const Mat first = frameStart(img.size(), b);
    // Where the salient part's rectangle is the strip's inside (the saliency spreads over the
    // whole picture: the baboon, the apple) both GrabCuts start from the same labels and find
    // the same subject: the first pass's is the salient part's.
    const bool same = !salientStart.empty() && countNonZero(salientStart != first) == 0;
    Mat labels, salient = same ? Mat() : salientStart.clone();
    auto frameInward = [&] {
        labels = first.clone();
        seededGrabCut(img, labels, iterations, kSettleWithin);
        if (same) salient = labels.clone();
        if (img.cols > 4 * b && img.rows > 4 * b) {  // else no strip to reopen
            const Mat second = reopenedPass(img, iterations, b, first, labels);
            if (!second.empty()) {
                labels = second;
                if (reopenedKept) *reopenedKept = true;
            }
        }
    };
    if (salient.empty() && beside) {
        // One GrabCut chain, one core: `beside`'s tasks take the other, and this one when the
        // chain is done (the small faces' search and the two profile ones: 190-250 ms on one
        // core at 1024 px, against 70-170 ms for the chain).
        Tasks tasks{frameInward};
        tasks.insert(tasks.end(), beside.tasks.begin(), beside.tasks.end());
        runTasks(tasks);
    } else if (salient.empty()) {
        frameInward();
    } else {
        if (!beside.run()) return Mat();
        // The salient part's GrabCut is needed only for the check below: it runs beside the
        // frame-inward passes, on the second core. Nested parallel loops run serially in
        // OpenCV, so each GrabCut stays on its task's thread.
        runTasks({frameInward, [&] { seededGrabCut(img, salient, iterations, kSettleWithin); }});
    }
    if (salient.empty()) return labels;
    // The frame-inward subject may extend the salient part (a close-up's whole animal around
    // the nose saliency found), never replace it: where it holds less than 80% of it, GrabCut
    // took something else for the subject (the sky around a rocket, half a motorcycle and the
    // shelves behind it, two facets of a grey sculpture on grey).
    const Mat part = (salient == GC_FGD) | (salient == GC_PR_FGD);
    const Mat subject = (labels == GC_FGD) | (labels == GC_PR_FGD);
    if (countNonZero(part & subject) >= kHoldsSalient * countNonZero(part)) return labels;
    if (reopenedKept) *reopenedKept = false;
    return salient;
}

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv

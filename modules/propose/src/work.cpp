#include "work.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace cv {
namespace multicage {
namespace propose_detail {

void checkParams(const ProposeParams& p) {
    auto bad = [](const char* what, double value, const char* want) {
        CV_Error_(Error::StsOutOfRange,
                  ("multicage: ProposeParams::%s = %g is out of range (%s)", what, value, want));
    };
    if (p.method < PROPOSE_AUTO || p.method > PROPOSE_LABELS)
        bad("method", p.method, "a ProposeMethod");
    if (p.maxVertices < kMinPolygonVertices) bad("maxVertices", p.maxVertices, ">= 4");
    if (p.maxPolygonVertices < kMinPolygonVertices)
        bad("maxPolygonVertices", p.maxPolygonVertices, ">= 4");
    if (p.maxPolygons < 1) bad("maxPolygons", p.maxPolygons, ">= 1");
    if (p.maxDepth < 1) bad("maxDepth", p.maxDepth, ">= 1");
    if (!(p.margin < 1e6f)) bad("margin", p.margin, "a finite number of pixels");
    if (!(p.minRegionArea >= 0 && p.minRegionArea < 1))
        bad("minRegionArea", p.minRegionArea, "[0, 1)");
    if (p.workingSize != 0 && p.workingSize < 32) bad("workingSize", p.workingSize, "0 or >= 32");
    if (p.grabCutIterations < 1) bad("grabCutIterations", p.grabCutIterations, ">= 1");
    if (p.grabCutMaxSide < 32) bad("grabCutMaxSide", p.grabCutMaxSide, ">= 32");
    if (p.protect < PROTECT_SALIENCY || p.protect > PROTECT_ALL)
        bad("protect", p.protect, "a ProtectDetector");
    if (p.faceWorkingSize != 0 && p.faceWorkingSize < 48)
        bad("faceWorkingSize", p.faceWorkingSize, "0 or >= 48");
    if (p.segmenter < SEGMENTER_AUTO || p.segmenter > SEGMENTER_CLASSIC)
        bad("segmenter", p.segmenter, "a ProposeSegmenter");
}

Work resolve(Size full, const ProposeParams& p) {
    Work w;
    w.full = full;
    const int longer = std::max(full.width, full.height);
    w.scale = p.workingSize > 0 && longer > p.workingSize
                  ? longer / static_cast<double>(p.workingSize)
                  : 1.0;
    w.size = w.scale > 1.0 ? Size(std::max(1, cvRound(full.width / w.scale)),
                                  std::max(1, cvRound(full.height / w.scale)))
                           : full;
    // GrabCut and the frame strips need 3 pixels each way; a sliver has no room for a cage.
    if (w.size.width < 3 || w.size.height < 3)
        // StsBadSize: resizeCage's cue to scale such a strip plainly (a proposal's other
        // StsBadSize, protectFeatures' image and cage of different sizes, cannot reach it)
        CV_Error_(Error::StsBadSize,
                  ("multicage: proposeMulticage: a %dx%d image is too thin to propose a cage in "
                   "(its working copy is %dx%d; each side needs 3 pixels)",
                   full.width, full.height, w.size.width, w.size.height));
    const double diagonal = std::hypot(full.width, full.height);
    const double margin = p.margin >= 0 ? p.margin : std::max(3.0, 0.012 * diagonal);
    w.margin = static_cast<float>(std::max(1.0, margin / w.scale));
    w.gap = std::max(1.5f, 0.4f * w.margin);
    const int wlonger = std::max(w.size.width, w.size.height);
    w.radius = p.morphologyRadius >= 0 ? cvRound(p.morphologyRadius / w.scale)
                                       : std::max(1, cvRound(0.005 * wlonger));
    w.minArea = p.minRegionArea * w.size.area();
    return w;
}

Point2d shrink(const Mat& img, Mat& out, double s, int interpolation, int minSide) {
    if (!(s < 1.0)) {
        out = img;
        return {1.0, 1.0};
    }
    const Size plain(cvRound(img.cols * s), cvRound(img.rows * s));  // resize's own rounding
    const int minW = std::min(img.cols, minSide), minH = std::min(img.rows, minSide);
    if (plain.width >= minW && plain.height >= minH) {
        resize(img, out, Size(), s, s, interpolation);
        return {s, s};
    }
    const Size kept(std::max(plain.width, minW), std::max(plain.height, minH));
    resize(img, out, kept, 0, 0, interpolation);
    return {kept.width / static_cast<double>(img.cols),
            kept.height / static_cast<double>(img.rows)};
}

Mat toWork(const Mat& img, const Work& w, int interpolation) {
    if (img.size() == w.size) return img;
    Mat out;
    resize(img, out, w.size, 0, 0, interpolation);
    return out;
}

Mat fromWork(const Mat& mask, const Work& w) {
    if (mask.size() == w.full) return mask;
    Mat out;
    resize(mask, out, w.full, 0, 0, INTER_LINEAR);
    threshold(out, out, 127, 255, THRESH_BINARY);
    return out;
}

// Distance of every pixel to the nearest zero pixel of `src` (exact Euclidean).
Mat distanceTo(const Mat& src) {
    Mat d;
    distanceTransform(src, d, DIST_L2, DIST_MASK_PRECISE, CV_32F);
    return d;
}

void fillWork(Mat& mask, const Polygon& p, const Work& w, const Scalar& value) {
    const double sx = w.size.width / static_cast<double>(w.full.width);
    const double sy = w.size.height / static_cast<double>(w.full.height);
    std::vector<std::vector<Point>> q(1);
    for (Point2f v : p)
        q[0].emplace_back(cvRound(((v.x + 0.5) * sx - 0.5) * 16),
                          cvRound(((v.y + 0.5) * sy - 0.5) * 16));
    fillPoly(mask, q, value, LINE_8, 4);
}

// Room between a face's polygon and the outline around it, in input pixels. Mean value

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv

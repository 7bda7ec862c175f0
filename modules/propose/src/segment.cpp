#include "segment.hpp"

#include <algorithm>
#include <cfloat>
#include <cstring>
#include <opencv2/imgproc.hpp>
#include <opencv2/saliency.hpp>

#include "fuse.hpp"
#include "grabcut.hpp"
#include "masks.hpp"
#include "subject.hpp"

namespace cv {
namespace multicage {
namespace propose_detail {

Mat to8Bit(const Mat& image) {
    if (image.empty())
        CV_Error(Error::StsBadArg, "multicage: proposeMulticage: the image is empty");
    const int cn = image.channels();
    if (cn != 1 && cn != 3 && cn != 4)
        CV_Error_(
            Error::StsBadArg,
            ("multicage: proposeMulticage: the image has %d channels (1, 3 or 4 expected)", cn));
    Mat img;
    if (cn == 4)
        cvtColor(image, img, COLOR_BGRA2BGR);
    else
        img = image;
    if (img.depth() == CV_8U) return img;
    Mat out;
    if (img.depth() == CV_16U) {
        img.convertTo(out, CV_8U, 1.0 / 257.0);
    } else {
        // Floats and other integers have no fixed range: stretch what is there, its finite
        // values (an infinite pixel stretched the rest to one value: "the image is constant").
        const Mat values = img.reshape(1);
        Mat finite;
        if (values.depth() == CV_32F || values.depth() == CV_64F)
            compare(abs(values), values.depth() == CV_32F ? FLT_MAX : DBL_MAX, finite, CMP_LE);
        double lo = 0, hi = 0;
        minMaxLoc(values, &lo, &hi, nullptr, nullptr, finite);
        img.convertTo(out, CV_8U, hi > lo ? 255.0 / (hi - lo) : 0.0,
                      hi > lo ? -lo * 255.0 / (hi - lo) : 0.0);
    }
    return out;
}

bool isConstant(const Mat& image) {
    if (image.empty()) return true;
    // Pixel by pixel against the first, stopping at the first that differs: a photo stops in
    // its first row, where a whole-image comparison read every pixel twice.
    const size_t pixel = image.elemSize();
    const uchar* first = image.ptr(0);
    for (int y = 0; y < image.rows; ++y) {
        const uchar* row = image.ptr(y);
        for (int x = 0; x < image.cols; ++x)
            if (std::memcmp(row + x * pixel, first, pixel) != 0) return false;
    }
    return true;
}

int otsuThreshold(const Mat& img, const Mat& mask) {
    CV_Assert(img.type() == CV_8UC1);
    int histSize = 256;
    float range[] = {0, 256};
    const float* ranges[] = {range};
    Mat hist;
    calcHist(&img, 1, nullptr, mask, hist, 1, &histSize, ranges);
    double total = 0, sum = 0;
    for (int i = 0; i < 256; ++i) total += hist.at<float>(i), sum += i * hist.at<float>(i);
    if (total <= 0) return 255;
    // Otsu 1979: the threshold maximising the between-class variance.
    double w0 = 0, sum0 = 0, best = -1;
    int bestT = 0;
    for (int t = 0; t < 255; ++t) {
        w0 += hist.at<float>(t);
        sum0 += t * hist.at<float>(t);
        const double w1 = total - w0;
        if (w0 == 0 || w1 == 0) continue;
        const double m0 = sum0 / w0, m1 = (sum - sum0) / w1;
        const double between = w0 * w1 * (m0 - m1) * (m0 - m1);
        if (between > best) best = between, bestT = t;
    }
    return bestT;
}

Mat borderStrip(Size size) {
    Mat strip(size, CV_8U, Scalar(255));
    const int b = std::max(2, std::min(size.width, size.height) / 50);
    if (size.width > 2 * b && size.height > 2 * b)
        strip(Rect(b, b, size.width - 2 * b, size.height - 2 * b)).setTo(0);
    return strip;
}

Mat backgroundDistance(const Mat& img, const Mat& backgroundMask) {
    Mat lab;
    if (img.channels() == 3)
        cvtColor(img, lab, COLOR_BGR2Lab);
    else
        lab = img;
    const int cn = lab.channels();
    // The median ignores the objects that reach into the background sample.
    std::vector<std::vector<uchar>> samples(cn);
    for (int y = 0; y < lab.rows; ++y) {
        const uchar* p = lab.ptr<uchar>(y);
        const uchar* m = backgroundMask.ptr<uchar>(y);
        for (int x = 0; x < lab.cols; ++x)
            if (m[x])
                for (int c = 0; c < cn; ++c) samples[c].push_back(p[x * cn + c]);
    }
    Scalar background;
    for (int c = 0; c < cn; ++c) {
        std::vector<uchar>& s = samples[c];
        if (s.empty()) continue;
        std::nth_element(s.begin(), s.begin() + s.size() / 2, s.end());
        background[c] = s[s.size() / 2];
    }
    Mat diff;
    lab.convertTo(diff, CV_32F);
    subtract(diff, background, diff);
    diff = diff.reshape(1, static_cast<int>(diff.total()));
    multiply(diff, diff, diff);
    Mat sq;
    reduce(diff, sq, 1, REDUCE_SUM);
    sqrt(sq, sq);
    Mat out;
    sq.reshape(1, img.rows).convertTo(out, CV_8U);
    return out;
}

bool plainBackground(const Mat& img) {
    // Only the strip's pixels, in a row of their own: the whole picture's distances (its
    // conversion to Lab) took 5% of a proposal's CPU time at 1024 px for a strip of 8% of it.
    std::vector<Point> where;
    findNonZero(borderStrip(img.size()), where);
    Mat strip(1, static_cast<int>(where.size()), img.type());
    for (int i = 0; i < strip.cols; ++i)
        if (img.channels() == 3)
            strip.at<Vec3b>(0, i) = img.at<Vec3b>(where[i]);
        else
            strip.at<uchar>(0, i) = img.at<uchar>(where[i]);
    const Mat all(strip.size(), CV_8U, Scalar(255));
    return countNonZero(backgroundDistance(strip, all) > 24) < 0.25 * strip.cols;
}

Mat saliencyMap(const Mat& img, bool spectralResidual) {
    Ptr<saliency::StaticSaliency> algorithm;
    if (spectralResidual)
        algorithm = saliency::StaticSaliencySpectralResidual::create();
    else
        algorithm = saliency::StaticSaliencyFineGrained::create();
    Mat map;
    if (!algorithm->computeSaliency(img, map) || map.empty())
        CV_Error(Error::StsError, "multicage: proposeMulticage: the saliency algorithm failed");
    Mat f, out;
    map.convertTo(f, CV_32F);
    normalize(f, f, 0, 255, NORM_MINMAX);
    f.convertTo(out, CV_8U);
    if (out.size() != img.size()) resize(out, out, img.size(), 0, 0, INTER_LINEAR);
    return out;
}

namespace {
Mat thresholdAbove(const Mat& feature, int t, const Mat& region) {
    Mat mask;
    threshold(feature, mask, t, 255, THRESH_BINARY);
    if (!region.empty()) mask &= region;
    return mask;
}

// Objects differ from the background by at least this much (Lab units) or there are none:
// Otsu splits pure noise in two as readily as a real object.
constexpr int kMinContrast = 12;

Mat segmentThreshold(const Mat& img, const Mat& region, bool adaptive) {
    Mat background = region.empty() ? borderStrip(img.size()) : Mat();
    if (!region.empty()) {
        // Inside a polygon the background is the band along its edge.
        Mat inner;
        erode(region, inner, getStructuringElement(MORPH_ELLIPSE, Size(7, 7)));
        background = region & ~inner;
    }
    Mat dist = backgroundDistance(img, background);
    GaussianBlur(dist, dist, Size(5, 5), 0);
    double hi;
    minMaxLoc(dist, nullptr, &hi, nullptr, nullptr, region);
    if (hi < kMinContrast) return Mat::zeros(img.size(), CV_8U);
    if (!adaptive)
        return thresholdAbove(dist, std::max(otsuThreshold(dist, region), kMinContrast / 2),
                              region);
    // Local mean threshold: the block spans about a sixth of the image, so an object smaller
    // than that stands out from its surroundings even when the lighting changes.
    const int block = std::max(3, std::max(img.cols, img.rows) / 6) | 1;
    Mat mask;
    adaptiveThreshold(dist, mask, 255, ADAPTIVE_THRESH_MEAN_C, THRESH_BINARY, block,
                      -kMinContrast / 2.0);
    if (!region.empty()) mask &= region;
    return mask;
}

Mat segmentSaliency(const Mat& img, const Mat& region, bool spectral) {
    // The map is blurred to blobs below, so a copy of at most 320 pixels loses nothing and
    // costs the fine grained centre-surround a third of the time.
    Mat small;
    shrink(img, small, 320.0 / std::max(img.cols, img.rows), INTER_AREA);
    Mat map = saliencyMap(small, spectral);
    if (map.size() != img.size()) resize(map, map, img.size(), 0, 0, INTER_LINEAR);
    // Saliency responds to edges and texture; a blur of ~2% of the size turns the response
    // into blobs that follow whole objects instead of their outlines.
    const double sigma = std::max(1.0, 0.02 * std::max(img.cols, img.rows));
    GaussianBlur(map, map, Size(), sigma);
    double lo, hi;
    minMaxLoc(map, &lo, &hi, nullptr, nullptr, region);
    if (hi - lo < kMinContrast) return Mat::zeros(img.size(), CV_8U);
    return thresholdAbove(map, otsuThreshold(map, region), region);
}

// A rectangle around the spectral residual salient part, grown to take in its edges.
Rect automaticGrabCutRect(const Mat& img) {
    Mat mask = segmentSaliency(img, Mat(), true);
    Rect r = countNonZero(mask) > 0 ? boundingRect(mask) : Rect();
    const int mx = std::max(2, img.cols * 3 / 100), my = std::max(2, img.rows * 3 / 100);
    if (r.area() == 0) r = Rect(img.cols / 10, img.rows / 10, img.cols * 8 / 10, img.rows * 8 / 10);
    // Grow by 5% of the image so the object's edges are inside, but leave a strip of
    // background all round: GrabCut learns the background model from outside the rect.
    r.x -= img.cols / 20, r.y -= img.rows / 20, r.width += img.cols / 10, r.height += img.rows / 10;
    return r & Rect(mx, my, img.cols - 2 * mx, img.rows - 2 * my);
}

// GrabCut's labels of the subject of `small` (GrabCut's working size) from the frame inward,
// checked against the salient part's (frameInwardSubject in subject.hpp, with its `beside`).
Mat frameInwardLabels(const Mat& small, const ProposeParams& params, const Beside& beside) {
    // The salient part and the subject from the frame inward, which must hold it (subject.hpp).
    Mat salient(small.size(), CV_8U, Scalar(GC_BGD));
    const Rect r = automaticGrabCutRect(small) & Rect(1, 1, small.cols - 2, small.rows - 2);
    if (r.width >= 2 && r.height >= 2)
        salient(r).setTo(GC_PR_FGD);
    else
        salient.release();
    return frameInwardSubject(small, params.grabCutIterations, salient, beside);
}

Mat segmentGrabCut(const Mat& img, const ProposeParams& params, double scale, const Mat& region,
                   const Mat& seed = Mat(), const Beside& beside = {}) {
    Mat color;
    if (img.channels() == 1)
        cvtColor(img, color, COLOR_GRAY2BGR);
    else
        color = img;
    // GrabCut's cost is per pixel and per iteration: run it small, upscale the mask.
    Mat small;
    const double longer = std::max(img.cols, img.rows);
    const Point2d s = shrink(color, small, params.grabCutMaxSide / longer, INTER_AREA);
    Rect rect;
    if (!region.empty()) {
        Mat r;
        resize(region, r, small.size(), 0, 0, INTER_NEAREST);
        rect = boundingRect(r);
    } else if (params.rect.area() > 0) {
        const double kx = s.x / scale, ky = s.y / scale;  // input pixels -> small pixels
        rect = Rect(cvFloor(params.rect.x * kx), cvFloor(params.rect.y * ky),
                    cvCeil(params.rect.width * kx), cvCeil(params.rect.height * ky));
    } else {
        rect = Rect(0, 0, small.cols, small.rows);  // unused: the seed or the frame is the start
    }
    rect &= Rect(1, 1, small.cols - 2, small.rows - 2);
    // Without a region, a rectangle or a seed, the frame is GrabCut's start (subject.hpp).
    const bool fromFrame = region.empty() && params.rect.area() == 0 && seed.empty();
    if (!fromFrame && seed.empty() && (rect.width < 2 || rect.height < 2))
        CV_Error_(Error::StsBadArg,
                  ("multicage: proposeMulticage: the GrabCut rectangle (%d, %d, %d, %d) "
                   "is empty inside the image",
                   params.rect.x, params.rect.y, params.rect.width, params.rect.height));
    Mat labels(small.size(), CV_8U, Scalar(GC_BGD));
    if (fromFrame) {
        labels = frameInwardLabels(small, params, beside);
        if (labels.empty()) return Mat();  // `beside` made it moot
    } else {
        labels(rect).setTo(GC_PR_FGD);
        // The person prior (person.hpp) replaces the rectangle: its labels are GrabCut's start.
        if (!seed.empty()) resize(seed, labels, small.size(), 0, 0, INTER_NEAREST);
        seededGrabCut(small, labels, params.grabCutIterations);
    }
    Mat mask = (labels == GC_FGD) | (labels == GC_PR_FGD);
    if (!seed.empty()) {
        Mat s;
        resize(seed, s, small.size(), 0, 0, INTER_NEAREST);
        mask = piecesHolding(mask, s == GC_FGD);
    }
    if (mask.size() != img.size()) {
        resize(mask, mask, img.size(), 0, 0, INTER_LINEAR);
        threshold(mask, mask, 127, 255, THRESH_BINARY);
    }
    if (!region.empty()) mask &= region;
    return mask;
}
}  // namespace

Mat segmentImage(const Mat& img, int method, const ProposeParams& params, double scale,
                 const Mat& region) {
    switch (method) {
        case PROPOSE_THRESHOLD:
            return segmentThreshold(img, region, false);
        case PROPOSE_ADAPTIVE:
            return segmentThreshold(img, region, true);
        case PROPOSE_GRABCUT:
            return segmentGrabCut(img, params, scale, region);
        case PROPOSE_SALIENCY:
            return segmentSaliency(img, region, false);
        case PROPOSE_SPECTRAL_RESIDUAL:
            return segmentSaliency(img, region, true);
        default:
            CV_Error_(Error::StsBadArg,
                      ("multicage: proposeMulticage: method %d is not an image method", method));
    }
}

Segmentation segmentForProposal(const Mat& image, const Work& w, const ProposeParams& params,
                                const Mat& person, const Beside& beside, const Mat& subject) {
    Segmentation s;
    if (params.method == PROPOSE_MASK || params.method == PROPOSE_LABELS) {
        if (!beside.run()) return s;
        if (image.empty())
            CV_Error(Error::StsBadArg, "multicage: proposeMulticage: the mask is empty");
        if (image.channels() != 1)
            CV_Error_(Error::StsBadArg,
                      ("multicage: proposeMulticage: a %s must have one channel (it has %d)",
                       params.method == PROPOSE_MASK ? "mask" : "label image", image.channels()));
        if (params.method == PROPOSE_MASK) {
            s.objects = toWork(image != 0, w, INTER_NEAREST);
            s.objects = cleanMask(s.objects, w.radius, w.minArea);
        } else {
            if (image.depth() != CV_8U && image.depth() != CV_16U && image.depth() != CV_32S)
                CV_Error(
                    Error::StsBadArg,
                    "multicage: proposeMulticage: a label image must be CV_8U, CV_16U or CV_32S");
            Mat l;
            image.convertTo(l, CV_32S);
            s.labels = toWork(l, w, INTER_NEAREST);
            // Labels are the user's word: only regions below the minimum area go.
            s.objects = cleanMask(s.labels != 0, 0, w.minArea);
            s.labels.setTo(0, s.objects == 0);
        }
        return s;
    }
    const Mat img8 = to8Bit(image);
    if (isConstant(img8))
        CV_Error(Error::StsBadArg,
                 "multicage: proposeMulticage: the image is constant (every pixel has the "
                 "same value): there is nothing to segment");
    const Mat work = toWork(img8, w, INTER_AREA);
    if (!subject.empty() && params.method == PROPOSE_AUTO && params.rect.area() == 0) {
        if (!beside.run()) return s;
        // A map with no subject, or whose subject is all specks, leaves it to the classic cues.
        const Mat fused = fusedSubject(work, subject, person, params);
        if (!fused.empty()) s.objects = cleanMask(fused, w.radius, w.minArea);
        if (!s.objects.empty() && countNonZero(s.objects) > 0) return s;
    }
    int method = params.method;
    if (method == PROPOSE_AUTO && person.empty()) {
        // A plain background (most of the border strip near its median colour) is what a
        // threshold wants; on anything else GrabCut, seeded by saliency, finds whole objects
        // where saliency alone lights up texture.
        method = plainBackground(work) ? PROPOSE_THRESHOLD : PROPOSE_GRABCUT;
    }
    const bool grabCut = method == PROPOSE_AUTO || method == PROPOSE_GRABCUT;
    if (grabCut && person.empty() && params.rect.area() == 0 && beside) {
        // From the frame inward, which takes `beside` along (subject.hpp).
        const Mat mask = segmentGrabCut(work, params, w.scale, Mat(), Mat(), beside);
        if (!mask.empty()) s.objects = cleanMask(mask, w.radius, w.minArea);
        return s;
    }
    if (!beside.run()) return s;
    if (!person.empty() && grabCut && params.rect.area() == 0) {
        // A face was found: the person prior seeds GrabCut, whatever the background.
        s.objects =
            cleanMask(segmentGrabCut(work, params, w.scale, Mat(), person), w.radius, w.minArea);
        return s;
    }
    s.objects = cleanMask(segmentImage(work, method, params, w.scale), w.radius, w.minArea);
    return s;
}

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv

// CageTracker: each polygon of a multicage follows what it encloses, from frame to frame.
#include <algorithm>
#include <numeric>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/multicage/internal/geometry.hpp>
#include <opencv2/multicage/track.hpp>
#include <opencv2/video/tracking.hpp>

#include "similarity.hpp"

namespace cv {
namespace multicage {

namespace {

constexpr int kWindow = 21;              // the optical flow's window, pixels
constexpr double kRekeyAgreement = 0.9;  // fewer agreeing points than this: a new key frame

// The frame as 8-bit grey; anything but 8-bit 1, 3 or 4 channels is refused.
Mat greyOf(InputArray frameIn) {
    const Mat frame = frameIn.getMat();
    if (frame.empty()) CV_Error(Error::StsBadArg, "CageTracker: the frame is empty");
    if (frame.depth() != CV_8U ||
        (frame.channels() != 1 && frame.channels() != 3 && frame.channels() != 4))
        CV_Error(Error::StsUnsupportedFormat,
                 "CageTracker: frames must be 8-bit with 1, 3 or 4 channels");
    Mat grey;
    if (frame.channels() == 1)
        grey = frame.clone();
    else
        cvtColor(frame, grey, frame.channels() == 3 ? COLOR_BGR2GRAY : COLOR_BGRA2GRAY);
    return grey;
}

// Polygon i's own region: inside it and outside its children (parent: geometry::parents).
Mat ownRegion(const std::vector<geometry::Polygon>& polygons, const std::vector<int>& parent, int i,
              Size size) {
    Mat mask = Mat::zeros(size, CV_8U);
    std::vector<std::vector<Point>> shape(1);
    auto fill = [&](int k, uchar value) {
        shape[0].assign(polygons[k].begin(), polygons[k].end());
        fillPoly(mask, shape, Scalar(value), LINE_8);
    };
    fill(i, 255);
    for (size_t k = 0; k < polygons.size(); ++k)
        if (parent[k] == i) fill(int(k), 0);
    return mask;
}

// Points of the region to follow: its corners, and a grid of it where corners are few (a
// plain region still moves with its border).
std::vector<Point2f> pointsToFollow(const Mat& grey, const Mat& region, bool outline,
                                    const TrackParams& p) {
    // An outline's corners whose flow window (21 x 21) lies inside it: a window over its border
    // sees the background, which moves otherwise, and biases the flow towards it. (Around an
    // inner polygon lies the subject, which mostly moves with it: all of its region serves.)
    Mat inner;
    if (outline) erode(region, inner, getStructuringElement(MORPH_RECT, Size(kWindow, kWindow)));
    std::vector<Point2f> points;
    goodFeaturesToTrack(grey, points, p.pointsPerPolygon, 0.01, 3,
                        outline && countNonZero(inner) > 0 ? inner : region);
    if (int(points.size()) >= 2 * p.minPoints) return points;
    const Rect box = boundingRect(region);
    const double area = std::max(1, countNonZero(region));
    const int step = std::max(1, int(std::sqrt(area / std::max(1, p.pointsPerPolygon))));
    for (int y = box.y + step / 2; y < box.br().y; y += step)
        for (int x = box.x + step / 2; x < box.br().x; x += step)
            if (region.at<uchar>(y, x)) points.emplace_back(float(x), float(y));
    return points;
}

// Correlation of the frames' 32-bin grey-level histograms.
double histogramCorrelation(const Mat& a, const Mat& b) {
    const int bins = 32, channel = 0;
    const float range[] = {0, 256};
    const float* ranges[] = {range};
    Mat ha, hb;
    calcHist(&a, 1, &channel, Mat(), ha, 1, &bins, ranges);
    calcHist(&b, 1, &channel, Mat(), hb, 1, &bins, ranges);
    return compareHist(ha, hb, HISTCMP_CORREL);
}

// The mean absolute grey difference of the frames' 16 x 12 thumbnails: where the picture's
// layout changes at once. Shots of one palette (a dialogue's two faces) correlate in their
// histograms, not in their layouts.
double thumbnailDifference(const Mat& a, const Mat& b) {
    Mat ta, tb;
    resize(a, ta, Size(16, 12), 0, 0, INTER_AREA);
    resize(b, tb, Size(16, 12), 0, 0, INTER_AREA);
    return norm(ta, tb, NORM_L1) / double(ta.total());
}

// The points' flow from `from` to `to`, each starting at its guess, kept where the flow back
// returns within maxRoundTrip.
void followPoints(const Mat& from, const Mat& to, const std::vector<Point2f>& points,
                  std::vector<Point2f>& moved, double maxRoundTrip, std::vector<uchar>& kept) {
    std::vector<Point2f> back = points;
    std::vector<uchar> status, statusBack;
    std::vector<float> error;
    const Size window(kWindow, kWindow);
    const TermCriteria stop(TermCriteria::COUNT | TermCriteria::EPS, 30, 0.01);
    calcOpticalFlowPyrLK(from, to, points, moved, status, error, window, 3, stop,
                         OPTFLOW_USE_INITIAL_FLOW);
    calcOpticalFlowPyrLK(to, from, moved, back, statusBack, error, window, 3, stop,
                         OPTFLOW_USE_INITIAL_FLOW);
    kept.assign(points.size(), 0);
    for (size_t k = 0; k < points.size(); ++k)
        kept[k] = status[k] && statusBack[k] && norm(back[k] - points[k]) <= maxRoundTrip;
}

// The similarity most of a polygon's followed points agree on, and the part of the `sought`
// points (all those of the key frame, followed or not) that agrees; empty when too few do.
// (Counting the points the flow lost too: a region whose content changed, or was covered, keeps
// few, and those few may agree on anything.)
Mat agreedMotion(const std::vector<Point2f>& from, const std::vector<Point2f>& to, size_t sought,
                 const TrackParams& p, double& agreement) {
    agreement = 0;
    if (int(from.size()) < p.minPoints) return Mat();
    std::vector<uchar> agree;
    const Mat m = estimateAffinePartial2D(from, to, agree, RANSAC, p.agreementPx, 2000, 0.995);
    const int agreeing = countNonZero(agree);
    agreement = double(agreeing) / double(std::max(sought, from.size()));
    if (m.empty() || agreeing < p.minPoints || agreement < p.minAgreement) return Mat();
    // Refitted on the agreeing points: RANSAC's own fit stops at its sample's consensus, and its
    // random sample shows as jitter from frame to frame.
    return leastSquaresSimilarity(from, to, agree);
}

// The part of the points that motion m carries to within tolerance of where they went.
double agreementWith(const Mat& m, const std::vector<Point2f>& from, const std::vector<Point2f>& to,
                     double tolerance) {
    if (from.empty()) return 0;
    std::vector<Point2f> carried;
    transform(from, carried, m);
    int agreeing = 0;
    for (size_t k = 0; k < from.size(); ++k) agreeing += norm(carried[k] - to[k]) <= tolerance;
    return double(agreeing) / double(from.size());
}

Mat identityMotion() {
    return Mat::eye(2, 3, CV_64F);
}

// Whether a similarity turns by more than 5 degrees or scales by more than 5%: then the corners
// of the flow's 21 x 21 window are a pixel off what it sees, the flow degrades, and a new key
// frame is due. (A key frame moved on adds the error of its frame, so not on every frame.)
bool farFromKey(const Mat& m) {
    const double a = m.at<double>(0, 0), b = m.at<double>(1, 0);
    const double scale = std::sqrt(a * a + b * b), turn = std::abs(std::atan2(b, a));
    return turn > 5.0 * CV_PI / 180.0 || std::abs(scale - 1.0) > 0.05;
}

}  // namespace

// The key frame the polygons are measured from, and where they moved since.
struct CageTracker::Impl {
    TrackParams params;
    Multicage cage;     // on the last frame, in the frames' pixels (what multicage() gives)
    Multicage keyCage;  // on the key frame, at the working size (as everything below)
    Size frameSize, workingSize;
    Mat keyGrey, lastGrey;
    int type = -1;
    std::vector<std::vector<Point2f>> keyPoints;  // per polygon, on the key frame
    std::vector<Mat> motion;                      // per polygon: key frame -> last frame
    std::vector<int> parent, outermostFirst;      // the nesting, and the polygons by depth

    // The frame in grey at the working size: flow windows and tolerances are in its pixels.
    Mat working(InputArray frame) const {
        Mat grey = greyOf(frame);
        if (grey.size() != frameSize || frame.type() != type)
            CV_Error(Error::StsBadArg,
                     "CageTracker: the frame's size or type differs from the first");
        if (workingSize != frameSize) resize(grey, grey, workingSize, 0, 0, INTER_AREA);
        return grey;
    }

    void setKey(const Multicage& c, const Mat& grey) {
        keyCage = c, keyGrey = grey, lastGrey = grey;
        cage = c.imageSize() == frameSize ? c : c.scaled(frameSize);
        const int P = c.polygonCount();
        std::vector<geometry::Polygon> polygons;
        for (int i = 0; i < P; ++i) polygons.push_back(c.polygon(i));
        // The nesting once (Multicage::depth() tests every polygon against every other per call).
        const std::vector<int> depth = geometry::depths(polygons);
        parent = geometry::parents(polygons, depth);
        outermostFirst.resize(P);
        std::iota(outermostFirst.begin(), outermostFirst.end(), 0);
        std::stable_sort(outermostFirst.begin(), outermostFirst.end(),
                         [&](int a, int b) { return depth[a] < depth[b]; });
        motion.assign(P, identityMotion());
        keyPoints.assign(P, {});
        for (int i = 0; i < P; ++i)
            keyPoints[i] = pointsToFollow(grey, ownRegion(polygons, parent, i, grey.size()),
                                          parent[i] < 0, params);
    }

    // Polygon i's motion from the key frame to grey; empty when lost. An inner polygon whose
    // points its parent's motion (`parentMotion`, empty for an outline) carries as well as
    // minAgreement asks moves with its parent: the parent's many points fix a turn or a
    // scale better than a small region's few, and a rigid subject stays rigid. One whose own
    // points agree on nothing (an eye that blinks, a face that talks) moves with its parent too:
    // only an outline is lost.
    Mat follow(int i, const Mat& grey, const Mat& parentMotion, double& agreement) const {
        const std::vector<Point2f>& key = keyPoints[i];
        if (key.empty()) return parentMotion.empty() ? Mat() : parentMotion;
        std::vector<Point2f> guess, from, to;
        transform(key, guess, motion[i]);
        std::vector<uchar> kept;
        followPoints(keyGrey, grey, key, guess, params.maxRoundTripPx, kept);
        for (size_t k = 0; k < key.size(); ++k)
            if (kept[k]) from.push_back(key[k]), to.push_back(guess[k]);
        if (!parentMotion.empty()) {
            agreement = agreementWith(parentMotion, from, to, params.agreementPx);
            if (agreement >= params.minAgreement) return parentMotion;
        }
        const Mat own = agreedMotion(from, to, key.size(), params, agreement);
        return own.empty() && !parentMotion.empty() ? parentMotion : own;
    }
};

CageTracker::CageTracker(const Multicage& cage, InputArray frame, const TrackParams& params)
    : impl_(makePtr<Impl>()) {
    impl_->params = params;
    reset(cage, frame);
}

const Multicage& CageTracker::multicage() const {
    return impl_->cage;
}

void CageTracker::reset(const Multicage& cage, InputArray frame) {
    Impl& s = *impl_;
    s.frameSize = greyOf(frame).size();
    const Multicage fitted = cage.imageSize() == s.frameSize ? cage : cage.scaled(s.frameSize);
    std::string why;
    if (!fitted.validateGeometry(&why))
        CV_Error(Error::StsBadArg, "CageTracker: invalid multicage: " + why);
    const int side = std::max(s.frameSize.width, s.frameSize.height);
    const double f = s.params.workingSize > 0 && side > s.params.workingSize
                         ? double(s.params.workingSize) / side
                         : 1.0;
    s.workingSize = Size(std::max(1, cvRound(s.frameSize.width * f)),
                         std::max(1, cvRound(s.frameSize.height * f)));
    s.type = frame.type();
    s.setKey(f < 1 ? fitted.scaled(s.workingSize) : fitted, s.working(frame));
}

TrackReport CageTracker::track(InputArray frame) {
    Impl& s = *impl_;
    const Mat grey = s.working(frame);
    TrackReport report;
    report.histogramCorrelation = histogramCorrelation(s.lastGrey, grey);
    report.thumbnailDifference = thumbnailDifference(s.lastGrey, grey);
    s.lastGrey = grey;
    if (report.histogramCorrelation < s.params.minHistogramCorrelation) {
        report.state = TRACK_CUT;
        report.why = format("a cut: the grey-level histograms correlate %.2f (below %.2f)",
                            report.histogramCorrelation, s.params.minHistogramCorrelation);
        return report;
    }
    if (report.thumbnailDifference > s.params.maxThumbnailDifference) {
        report.state = TRACK_CUT;
        report.why = format("a cut: the frames' thumbnails differ by %.1f grey levels (above %.1f)",
                            report.thumbnailDifference, s.params.maxThumbnailDifference);
        return report;
    }
    Multicage next = s.keyCage;
    std::vector<Mat> motion(s.keyCage.polygonCount());
    bool rekey = false;
    for (int i : s.outermostFirst) {
        double agreement = 0;
        const int parent = s.parent[i];
        motion[i] = s.follow(i, grey, parent < 0 ? Mat() : motion[parent], agreement);
        if (motion[i].empty()) {
            report.lost.push_back(i);
            continue;
        }
        std::vector<Point2f> vertices;
        transform(s.keyCage.polygon(i), vertices, motion[i]);
        // An outline along the frame (a subject the frame cuts) stays on it, strictly inside
        // the frame as validate() has it, (-0.5, -0.5)-(W-0.5, H-0.5): a vertex that did not
        // move stays where it was (a proposal puts those on the frame at -0.3 and W-0.7).
        const float lo = -0.49f, right = grey.cols - 0.51f, bottom = grey.rows - 0.51f;
        for (Point2f& v : vertices)
            v = Point2f(std::min(std::max(v.x, lo), right), std::min(std::max(v.y, lo), bottom));
        next.setPolygon(i, vertices);
        rekey = rekey || farFromKey(motion[i]) || agreement < kRekeyAgreement;
    }
    if (!report.lost.empty()) {
        report.state = TRACK_LOST;
        report.why = format("polygon %d: too few points agree on its motion", report.lost[0]);
        return report;
    }
    if (!next.validateGeometry(&report.why)) {
        report.state = TRACK_LOST;
        report.why = "the moved multicage is invalid: " + report.why;
        return report;
    }
    report.why.clear();
    s.motion = motion;
    if (rekey)
        s.setKey(next, grey);
    else
        s.cage = s.workingSize == s.frameSize ? next : next.scaled(s.frameSize);
    return report;
}

}  // namespace multicage
}  // namespace cv

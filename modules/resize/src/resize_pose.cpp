// The resize pose (docs/resize/README.md): the frame to the new frame, each outline and what it
// holds by one similarity, the background absorbing the aspect change.
#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/multicage/internal/geometry.hpp>
#include <opencv2/multicage/resize.hpp>

#include "fold_free_blend.hpp"
#include "outline_similarity.hpp"

namespace cv {
namespace multicage {

namespace {

/** Frame coordinates u = x + 0.5 run from 0 to W over the frame (-0.5 .. W - 0.5). */
struct Axis {
    double lo, hi;  // the outline's bounding box, frame coordinates
    double size;    // W (or H)
    double newSize;
    double scale() const { return newSize / size; }
    double extent() const { return hi - lo; }
    double gapLow() const { return lo; }
    double gapHigh() const { return size - hi; }
};

// A subject "cut by the border": its outline runs within this distance of a side of the frame
// (proposals keep polygons a margin inside the frame; 1% of the shorter side covers them).
double touchTolerance(Size image) {
    return std::max(2.0, 0.01 * std::min(image.width, image.height));
}

// The least gap an outline keeps to a side: the background between them may be squeezed to 4%
// of the new side (what the frame's own scaling leaves, where that is less), no further: a
// thinner band of background folds under mean value coordinates.
double keptGap(double gap, const Axis& a) {
    return std::min(gap * std::min(a.scale(), 1.0), 0.04 * a.newSize);
}

// The largest uniform scale at which the outline fits between the kept gaps on this axis.
double fitScale(const Axis& a) {
    const double room = a.newSize - keptGap(a.gapLow(), a) - keptGap(a.gapHigh(), a);
    return a.extent() > 0 ? room / a.extent() : INFINITY;
}

// Where the outline's low side goes on this axis at uniform scale s.
double placeLow(const Axis& a, double s, double tol) {
    const double length = s * a.extent();
    const bool low = a.gapLow() <= tol, high = a.gapHigh() <= tol;
    double start;
    if (low && !high)
        start = a.gapLow() * a.scale();  // stays on the low border
    else if (high && !low)
        start = a.newSize - a.gapHigh() * a.scale() - length;
    else
        start =
            0.5 * (a.lo + a.hi) * a.scale() - 0.5 * length;  // the frame's scaling of the centre
    // Inside the new frame with the kept gaps (fitScale() made room for them).
    const double first = keptGap(a.gapLow(), a),
                 last = a.newSize - keptGap(a.gapHigh(), a) - length;
    return std::min(std::max(start, first), std::max(first, last));
}

}  // namespace

Similarity outlineSimilarity(const std::vector<Point2f>& outline, Size image, Size target) {
    Rect2f box(outline[0], Size2f());
    for (const Point2f& p : outline) {
        const float r = std::max(box.x + box.width, p.x), b = std::max(box.y + box.height, p.y);
        box.x = std::min(box.x, p.x), box.y = std::min(box.y, p.y);
        box.width = r - box.x, box.height = b - box.y;
    }
    // Frame coordinates: the box of the polygon's vertices, from the frame's corner.
    Axis x{box.x + 0.5, box.x + box.width + 0.5, double(image.width), double(target.width)};
    Axis y{box.y + 0.5, box.y + box.height + 0.5, double(image.height), double(target.height)};
    const double sMin = std::min(x.scale(), y.scale()), sMax = std::max(x.scale(), y.scale());
    // The subject keeps its size in pixels where the new frame allows (1 between the frame's two
    // scales); otherwise the frame's scale nearer 1; never more than fits.
    double s = std::min(std::max(1.0, sMin), sMax);
    s = std::min({s, fitScale(x), fitScale(y)});
    s = std::max(s, 1e-3);
    const double tol = touchTolerance(image);
    Similarity sim;
    sim.s = s;
    sim.from = Point2d(box.x, box.y);  // the box's corner in pixel coordinates
    sim.to = Point2d(placeLow(x, s, tol) - 0.5, placeLow(y, s, tol) - 0.5);
    return sim;
}

namespace {

// Each polygon's depth, and the polygons of depth 1 and 2 holding it (itself at that depth or
// above), computed once: Multicage::depth() tests every polygon against every other.
struct Nesting {
    std::vector<int> depth, outline, group;
    explicit Nesting(const Multicage& cage) {
        const int P = cage.polygonCount();
        std::vector<geometry::Polygon> polygons;
        for (int i = 0; i < P; ++i) polygons.push_back(cage.polygon(i));
        depth = geometry::depths(polygons);
        const std::vector<int> parent = geometry::parents(polygons, depth);
        auto ancestor = [&](int i, int d) {  // up the parents to depth d
            while (depth[i] > d && parent[i] >= 0) i = parent[i];
            return i;
        };
        for (int i = 0; i < P; ++i)
            outline.push_back(ancestor(i, 1)), group.push_back(ancestor(i, 2));
    }
};

// The frame's own scaling: the cv::resize pose (valid and fold-free for any multicage).
Point2f frameScaling(Point2f p, Size image, Size target) {
    return Point2f(float((p.x + 0.5) * target.width / image.width - 0.5),
                   float((p.y + 0.5) * target.height / image.height - 0.5));
}

bool validGeometry(const Multicage& cage, const std::vector<Point2f>& pose, Size target) {
    Multicage moved = cage.posed(pose);
    moved.setImageSize(target);
    return moved.validateGeometry();
}

}  // namespace

void checkResizeSize(Size imageSize, Size newSize, double maxScale) {
    if (imageSize.width < 1 || imageSize.height < 1)
        CV_Error(Error::StsBadSize, "multicage: resize: the image is empty");
    if (newSize.width < 1 || newSize.height < 1)
        CV_Error_(Error::StsOutOfRange,
                  ("multicage: resize: the size %dx%d is not a size (both sides must be at "
                   "least 1 pixel)",
                   newSize.width, newSize.height));
    // Far smaller, the mesh's cells shrink below float rounding of pixel coordinates and even
    // the frame's own scaling folds them: 1/64 of a side keeps them 200 times above it.
    constexpr int kMaxShrink = 64;
    if (newSize.width * kMaxShrink < imageSize.width ||
        newSize.height * kMaxShrink < imageSize.height)
        CV_Error_(Error::StsOutOfRange,
                  ("multicage: resize: %dx%d is more than %dx smaller than the image's %dx%d (at "
                   "least %dx%d)",
                   newSize.width, newSize.height, kMaxShrink, imageSize.width, imageSize.height,
                   (imageSize.width + kMaxShrink - 1) / kMaxShrink,
                   (imageSize.height + kMaxShrink - 1) / kMaxShrink));
    const double limitW = maxScale * imageSize.width, limitH = maxScale * imageSize.height;
    if (newSize.width > limitW || newSize.height > limitH)
        CV_Error_(Error::StsOutOfRange,
                  ("multicage: resize: %dx%d is more than %gx the image's %dx%d (at most %dx%d; "
                   "ResizeParams::maxScale sets the limit)",
                   newSize.width, newSize.height, maxScale, imageSize.width, imageSize.height,
                   int(std::floor(limitW)), int(std::floor(limitH))));
}

namespace {

void checkResizeInputs(const Multicage& cage, const Binding& binding, Size newSize,
                       const ResizeParams& params) {
    const Size image = cage.imageSize();
    checkResizeSize(image, newSize, params.maxScale);
    std::string why;
    if (!cage.validate(&why))
        CV_Error_(Error::StsBadArg,
                  ("multicage: resize: the multicage is not valid: %s", why.c_str()));
    if (binding.imageSize != image || binding.coefficientCount() != cage.vertexCount() + 4)
        CV_Error(Error::StsBadArg, "multicage: resize: the binding is not of this multicage");
}

// The two poses a resize blends between, the similarity pose and the frame-scaling pose (vertex
// for vertex), and what keeps inner polygons similarities while their outline blends.
struct ResizeBlend {
    Size image, newSize;
    Nesting nesting;
    std::vector<Similarity> outlines;  // per polygon: its similarity, at depth 1
    std::vector<Point2f> rest, similar, scaled;
    std::vector<int> owner;       // per vertex: the depth-2 polygon it moves with, -1: none
    std::vector<Point2f> centre;  // per polygon: its centre, at depth 2
    double startScale;            // stage 1's start scale of the inner polygons

    ResizeBlend(const Multicage& cage, Size target);
    std::vector<Point2f> operator()(double t, bool whole) const;
    bool validStart(const Multicage& cage, bool whole, std::vector<Point2f>& start);

  private:
    void poseSimilarities(const Multicage& cage);
    void moveFrameCorners();
    void groupInnerPolygons(const Multicage& cage);
};

ResizeBlend::ResizeBlend(const Multicage& cage, Size target)
    : image(cage.imageSize()), newSize(target), nesting(cage) {
    outlines.resize(cage.polygonCount());
    for (int i = 0; i < cage.polygonCount(); ++i)
        if (nesting.depth[i] == 1) outlines[i] = outlineSimilarity(cage.polygon(i), image, newSize);
    poseSimilarities(cage);
    moveFrameCorners();
    groupInnerPolygons(cage);
    startScale =
        std::min(double(newSize.width) / image.width, double(newSize.height) / image.height);
}

void ResizeBlend::poseSimilarities(const Multicage& cage) {
    rest = cage.vertices();
    similar.resize(rest.size()), scaled.resize(rest.size());
    for (size_t k = 0; k < rest.size(); ++k) scaled[k] = frameScaling(rest[k], image, newSize);
    const double tol = touchTolerance(image);
    for (int i = 0; i < cage.polygonCount(); ++i) {
        const Similarity& sim = outlines[nesting.outline[i]];
        const int begin = cage.polygonOffset(i), n = static_cast<int>(cage.polygon(i).size());
        for (int k = begin; k < begin + n; ++k) {
            similar[k] = sim(rest[k]);
            if (nesting.depth[i] != 1) continue;
            // An outline vertex on a side of the frame (a subject cut by the border) slides along
            // that side as the frame does: mean value coordinates are global, and a frame edge
            // stretching a pixel or two from an outline edge that does not would fold the mesh
            // between them and leak into the subject.
            const double u = rest[k].x + 0.5, v = rest[k].y + 0.5;
            if (u <= tol || image.width - u <= tol) similar[k].y = scaled[k].y;
            if (v <= tol || image.height - v <= tol) similar[k].x = scaled[k].x;
        }
    }
}

// Both poses put the frame's corners on the new frame's.
void ResizeBlend::moveFrameCorners() {
    const std::array<Point2f, 4> frame = {{{-0.5f, -0.5f},
                                           {newSize.width - 0.5f, -0.5f},
                                           {newSize.width - 0.5f, newSize.height - 0.5f},
                                           {-0.5f, newSize.height - 0.5f}}};
    const size_t users = rest.size() - 4;
    for (int k = 0; k < 4; ++k) similar[users + k] = scaled[users + k] = frame[k];
}

// Inner polygons' centres, for keeping them similarities while their outline blends: a depth-2
// polygon and everything nested in it move as one (the eyes with their face).
void ResizeBlend::groupInnerPolygons(const Multicage& cage) {
    owner.assign(rest.size(), -1);
    centre.resize(cage.polygonCount());
    for (int i = 0; i < cage.polygonCount(); ++i) {
        if (nesting.depth[i] != 2) continue;
        const std::vector<Point2f> poly = cage.polygon(i);
        Point2f c;
        for (const Point2f& p : poly) c += p;
        centre[i] = c * (1.f / poly.size());
    }
    for (int i = 0; i < cage.polygonCount(); ++i) {
        if (nesting.depth[i] < 2) continue;
        for (int k = 0; k < static_cast<int>(cage.polygon(i).size()); ++k)
            owner[cage.polygonOffset(i) + k] = nesting.group[i];
    }
}

// Stage 1 (t in [0, 1]): outlines go t of the way from the frame's scaling to their similarity;
// inner polygons stay similarities all the way, their centre carried from the frame's scaling of
// it to the outline's similarity of it, their scale from a start scale to the outline's. The
// start scale is the frame's smaller scale (a uniform copy at that scale fits inside the frame's
// scaling of a roughly convex, upright polygon, so inside the outline at t = 0), halved up to
// twice while the start still crosses something (a slanted polygon; smaller still, its inside
// would be too thin for the fold margin of foldFreeBlend()). With local coordinates what they
// hold then keeps its shape exactly, whatever t the fold check allows. Stage 2 (whole = true):
// every vertex blends, inner ones included.
std::vector<Point2f> ResizeBlend::operator()(double t, bool whole) const {
    std::vector<Point2f> pose(rest.size());
    for (size_t k = 0; k < rest.size(); ++k) {
        pose[k] = scaled[k] + float(t) * (similar[k] - scaled[k]);
        const int i = owner[k];
        if (i < 0 || whole) continue;
        const Similarity& sim = outlines[nesting.outline[i]];
        const Point2f c = frameScaling(centre[i], image, newSize), cs = sim(centre[i]);
        const double s0 = std::min(sim.s, startScale), s = s0 + t * (sim.s - s0);
        pose[k] = c + float(t) * (cs - c) + float(s) * (rest[k] - centre[i]);
    }
    return pose;
}

// The stage's pose at t = 0 in start, and whether it is valid (stage 1 halves its start scale up
// to twice until it is; stage 2's is the frame's scaling itself: always valid).
bool ResizeBlend::validStart(const Multicage& cage, bool whole, std::vector<Point2f>& start) {
    start = (*this)(0, whole);
    bool startValid = whole || validGeometry(cage, start, newSize);
    for (int halve = 0; !startValid && halve < 2; ++halve) {
        startScale *= 0.5, start = (*this)(0, whole);
        startValid = validGeometry(cage, start, newSize);
    }
    return startValid;
}

// Up to where the first triangle of the interpolated mesh p0 + t (p1 - p0) shrinks to a
// twentieth of its area under the frame's scaling (0 when the start is already that thin):
// deform() applies the pose itself, and its positions differ from the interpolated ones by float
// rounding (thousandths of a pixel: sums of up to a hundred products of pixel coordinates), far
// less than that margin can take, so the pose folds nothing without a confirming apply.
double foldFreeBlend(const Binding& binding, const Mat& p0, const Mat& p1, Size image,
                     Size newSize) {
    const double thin = 0.05 * binding.gridStep * binding.gridStep *
                        std::min(1.0, double(newSize.area()) / image.area());
    return std::min(1.0, firstFold(p0, p1, thin));
}

// Polygons crossing at t = good: bisection to 1/256 below it (no mesh needed).
double crossFreeBlend(const Multicage& cage, const ResizeBlend& blend, bool whole, double good) {
    if (validGeometry(cage, blend(good, whole), blend.newSize)) return good;
    double bad = good;
    good = 0;
    for (int it = 0; it < 8; ++it) {
        const double t = 0.5 * (good + bad);
        (validGeometry(cage, blend(t, whole), blend.newSize) ? good : bad) = t;
    }
    return good;
}

}  // namespace

std::vector<Point2f> resizePose(const Multicage& cage, const Binding& binding, Size newSize,
                                const ResizeParams& params) {
    checkResizeInputs(cage, binding, newSize, params);
    ResizeBlend blend(cage, newSize);
    // The mesh of the similarities (t = 1 of both stages). Node positions are linear in the
    // pose (Binding::apply), and the poses of a stage are affine in t, so the mesh at t is
    // P0 + t (P1 - P0): firstFold() finds where its first triangle folds in one pass. The
    // meshes are kept per thread: fresh ones cost page faults on every size of a slider (up to
    // 64 MB each: a bigger binding gives them back at the end).
    thread_local Mat p1, p0;
    struct ReleaseBig {
        ~ReleaseBig() {
            for (Mat* m : {&p0, &p1})
                if (m->total() * m->elemSize() > (size_t(64) << 20)) m->release();
        }
    } releaseBig;
    binding.apply(blend.similar, p1);
    const bool similarValid = validGeometry(cage, blend.similar, newSize);
    if (similarValid && foldedTriangles(p1) == 0) return blend.similar;
    // Subjects that would cross, or a fold: the least blend towards the frame's scaling that is
    // valid, outlines first (what they protect keeps its shape), then everything (t = 0 of
    // stage 2 is the frame's scaling itself: always valid).
    for (bool whole : {false, true}) {
        std::vector<Point2f> start;
        if (!blend.validStart(cage, whole, start)) continue;
        binding.apply(start, p0);
        double good = foldFreeBlend(binding, p0, p1, blend.image, newSize);
        if (!whole && good == 0) continue;
        good = crossFreeBlend(cage, blend, whole, good);
        CV_LOG_INFO(nullptr, "multicage: resize: subjects would cross or the mesh fold; "
                                 << (whole ? "the pose" : "the outlines") << " go " << good
                                 << " of the way from the frame's scaling to the similarities");
        return blend(good, whole);
    }
    return blend.scaled;  // not reached: stage 2 at t = 0 is the frame's scaling
}

std::vector<Point2f> resizePose(const Multicage& cage, Size newSize, const ResizeParams& params) {
    checkResizeSize(cage.imageSize(), newSize, params.maxScale);
    std::string why;
    if (!cage.validate(&why))
        CV_Error_(Error::StsBadArg,
                  ("multicage: resize: the multicage is not valid: %s", why.c_str()));
    return resizePose(cage, bind(cage, params.coordinates, params.gridStep), newSize, params);
}

}  // namespace multicage
}  // namespace cv

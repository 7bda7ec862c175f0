// Crop and warp (docs/resize/README.md): the window of the image an output shows when the aspect
// change is more than a warp should take, and the multicage and pose on that window.
#include <algorithm>
#include <cmath>
#include <opencv2/multicage/internal/geometry.hpp>
#include <opencv2/multicage/resize.hpp>

#include "outline_similarity.hpp"

namespace cv {
namespace multicage {

namespace {

// An extent along one axis (x, or y for a wider target): a polygon's, or what must stay whole.
struct Extent {
    double lo = HUGE_VAL, hi = -HUGE_VAL;
    void add(const Extent& e) { lo = std::min(lo, e.lo), hi = std::max(hi, e.hi); }
    bool empty() const { return lo > hi; }
    double size() const { return hi - lo; }
    double centre() const { return 0.5 * (lo + hi); }
};

Extent extent(const std::vector<Point2f>& polygon, bool alongX) {
    Extent e;
    for (const Point2f& p : polygon) {
        const double v = alongX ? p.x : p.y;
        e.lo = std::min(e.lo, v), e.hi = std::max(e.hi, v);
    }
    return e;
}

// The cage's polygons seen along the cut axis and across it.
struct Layout {
    std::vector<geometry::Polygon> polygons;
    std::vector<Extent> along, across;
    std::vector<int> depth, parent;
    bool alongX = true;  // the cut axis is x (a narrower target), else y
    Size image, target;
    double crop = 0;    // the plain crop's length along the cut axis, in image pixels
    double length = 0;  // the image's length along it
    double out = 0;     // the target's length along it

    bool inside(int i, double lo, double hi) const {
        return along[size_t(i)].lo >= lo && along[size_t(i)].hi <= hi;
    }

    // The window holding `keep`: its start and length. A margin on each side of what is kept,
    // so nothing kept touches the window's side: 4% of the plain crop, and 6% of the window where
    // subjects far apart widen it past the crop (the warp squeezes the window into the output,
    // and the resize pose leaves an outline at least 4% of the output to the frame, so a thinner
    // margin would squeeze the outline itself). Never narrower than the plain crop (what is kept
    // then centred in it), nor wider than the image; with nothing kept, centred on the outlines.
    std::pair<double, double> window(const Extent& keep, const Extent& outlines) const {
        double width = crop, centre = length / 2;
        if (!keep.empty()) {
            const double span = keep.size();
            width = std::clamp(std::max(span + 0.08 * crop, span / 0.88), crop, length);
            centre = keep.centre();
        } else if (!outlines.empty()) {
            centre = outlines.centre();
        }
        return {std::clamp(centre - width / 2, 0.0, length - width), width};
    }

    // Where the resize pose puts a polygon moving on its own (an outline, or a polygon whose
    // outline the window cuts) along the cut axis, the window [lo, lo + width] cropped and
    // resized to the target: as an outline of the crop (outlineSimilarity()).
    Extent placed(int i, double lo, double width) const {
        geometry::Polygon p = polygons[size_t(i)];
        for (Point2f& v : p) (alongX ? v.x : v.y) -= float(lo);
        const int side = std::max(1, cvRound(width));
        const Similarity sim = outlineSimilarity(
            p, alongX ? Size(side, image.height) : Size(image.width, side), target);
        for (Point2f& v : p) v = sim(v);
        return extent(p, alongX);
    }

    // Whether the resize pose can move what the window holds by similarities without two of
    // them coming too near: each polygon keeps its scale while the window is squeezed (scale a),
    // so two that overlap across come closer, and those near the window's sides are pushed
    // inwards. Two must keep between them what a uniform squeeze leaves, or 2% of the output.
    bool feasible(double lo, double width) const {
        const double a = out / width;
        std::vector<int> movers;
        for (int i = 0; i < int(along.size()); ++i)
            if (inside(i, lo, lo + width) && (depth[size_t(i)] == 1 || parent[size_t(i)] < 0 ||
                                              !inside(parent[size_t(i)], lo, lo + width)))
                movers.push_back(i);
        std::vector<Extent> at;
        for (int i : movers) at.push_back(placed(i, lo, width));
        for (size_t m = 0; m < movers.size(); ++m)
            for (size_t n = m + 1; n < movers.size(); ++n) {
                const Extent &p = along[size_t(movers[m])], &q = along[size_t(movers[n])];
                const Extent &pa = across[size_t(movers[m])], &qa = across[size_t(movers[n])];
                if (pa.hi < qa.lo || qa.hi < pa.lo) continue;  // side by side: they cannot meet
                const bool before = p.centre() <= q.centre();
                const double rest = before ? q.lo - p.hi : p.lo - q.hi,
                             now = before ? at[n].lo - at[m].hi : at[m].lo - at[n].hi;
                if (now < std::min(a * rest, 0.02 * out) - 1e-6) return false;  // (rounding)
            }
        return true;
    }
};

}  // namespace

Rect2d reframeWindow(const Multicage& cage, Size newSize, const ResizeParams& params) {
    const Size image = cage.imageSize();
    CV_Assert(!image.empty() && !newSize.empty());
    const Rect2d whole(0, 0, image.width, image.height);
    const double sx = double(newSize.width) / image.width,
                 sy = double(newSize.height) / image.height;
    if (!(params.maxWarp >= 1) || std::max(sx, sy) <= params.maxWarp * std::min(sx, sy))
        return whole;
    // The axis that is cut: x for a narrower target (the height is all kept), y for a wider one.
    const bool alongX = sx < sy;
    Layout l;
    l.alongX = alongX;
    l.image = image, l.target = newSize;
    l.length = alongX ? image.width : image.height;
    l.out = alongX ? newSize.width : newSize.height;
    // A plain crop's window: the target's aspect at the full other side.
    l.crop = alongX ? image.height * double(newSize.width) / newSize.height
                    : image.width * double(newSize.height) / newSize.width;
    std::vector<geometry::Polygon>& polygons = l.polygons;
    for (int i = 0; i < cage.polygonCount(); ++i) polygons.push_back(cage.polygon(i));
    l.depth = geometry::depths(polygons);
    l.parent = geometry::parents(polygons, l.depth);
    for (const geometry::Polygon& p : polygons)
        l.along.push_back(extent(p, alongX)), l.across.push_back(extent(p, !alongX));
    // What the window keeps whole: each outline the plain crop could hold; of a wider one, the
    // polygons it protects (faces, features) that the plain crop could hold. A polygon wider
    // than that could only be kept by shrinking it and stretching what is around it, so the
    // window cuts it, as a plain crop would, and shows it at its size. Outlines come first, then
    // inner polygons, each in the cage's order (a proposal lists each outline's faces before
    // its features); one is left out when keeping it too would leave the pose no room to move
    // what the window holds by similarities (feasible()): the window then holds what came before.
    Extent outlines;
    std::vector<int> candidates;
    for (int d : {1, 2})
        for (size_t i = 0; i < polygons.size(); ++i) {
            const Extent& e = l.along[i];
            if (l.depth[i] == 1 && d == 1) outlines.add(e);
            if (l.depth[i] != d || e.size() > l.crop) continue;
            if (d == 2 && l.along[size_t(l.parent[i])].size() <= l.crop) continue;
            candidates.push_back(int(i));
        }
    Extent keep;
    for (int i : candidates) {
        Extent trial = keep;
        trial.add(l.along[size_t(i)]);
        const auto [lo, width] = l.window(trial, outlines);
        if (keep.empty() || l.feasible(lo, width)) keep = trial;  // the first alone always fits
    }
    const auto [lo, width] = l.window(keep, outlines);
    return alongX ? Rect2d(lo, 0, width, image.height) : Rect2d(0, lo, image.width, width);
}

Rect windowCrop(const Rect2d& window, Size image) {
    const Rect crop(
        Point(int(std::floor(window.x + 1e-6)), int(std::floor(window.y + 1e-6))),
        Point(int(std::ceil(window.br().x - 1e-6)), int(std::ceil(window.br().y - 1e-6))));
    return crop & Rect(Point(), image);
}

Rect reframeCrop(const Multicage& cage, Size newSize, const ResizeParams& params) {
    const Rect2d w = reframeWindow(cage, newSize, params);
    return windowCrop(Rect2d(cvRound(w.x), cvRound(w.y), cvRound(w.width), cvRound(w.height)),
                      cage.imageSize());
}

Multicage cropMulticage(const Multicage& cage, const Rect& crop, std::vector<int>* kept) {
    CV_Assert(!crop.empty());
    if (kept) kept->clear();
    Multicage out(crop.size());
    out.setCoordinates(cage.coordinates());
    // A polygon is kept when it lies strictly inside the crop's frame (half a pixel outside its
    // outer pixel centres), as validate() wants of any multicage: on the whole image, all are.
    constexpr float eps = 1e-3f;
    const float left = crop.x - 0.5f + eps, top = crop.y - 0.5f + eps,
                right = crop.x + crop.width - 0.5f - eps,
                bottom = crop.y + crop.height - 0.5f - eps;
    for (int i = 0; i < cage.polygonCount(); ++i) {
        std::vector<Point2f> p = cage.polygon(i);
        const bool in = std::all_of(p.begin(), p.end(), [&](const Point2f& v) {
            return v.x >= left && v.y >= top && v.x <= right && v.y <= bottom;
        });
        if (!in) continue;
        if (kept) kept->push_back(i);
        for (Point2f& v : p) v -= Point2f(float(crop.x), float(crop.y));
        out.addPolygon(p);
    }
    out.orient();
    return out;
}

std::vector<Point2f> windowPose(const std::vector<Point2f>& cropPose, Size newSize,
                                const Rect& crop, const Rect2d& window) {
    CV_Assert(!crop.empty() && window.width > 0 && window.height > 0 && cropPose.size() >= 4);
    // Back to the crop's pixels by the crop's own scaling, then onto newSize by the window's.
    const double kx = double(crop.width) / newSize.width, ky = double(crop.height) / newSize.height;
    const double wx = newSize.width / window.width, wy = newSize.height / window.height;
    std::vector<Point2f> pose = cropPose;
    for (size_t i = 0; i + 4 < cropPose.size(); ++i) {
        const double x = (cropPose[i].x + 0.5) * kx + crop.x - window.x,
                     y = (cropPose[i].y + 0.5) * ky + crop.y - window.y;
        pose[i] = Point2f(float(x * wx - 0.5), float(y * wy - 0.5));
    }
    return pose;
}

}  // namespace multicage
}  // namespace cv

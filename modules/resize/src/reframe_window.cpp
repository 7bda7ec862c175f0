// Crop and warp (docs/resize/README.md): the window of the image an output shows when the aspect
// change is more than a warp should take, and the multicage and pose on that window.
#include <algorithm>
#include <cmath>
#include <opencv2/multicage/internal/geometry.hpp>
#include <opencv2/multicage/resize.hpp>

namespace cv {
namespace multicage {

namespace {

// Extents of what must stay whole along one axis (x, or y for a wider target).
struct Keep {
    double lo = HUGE_VAL, hi = -HUGE_VAL;
    void add(double a, double b) { lo = std::min(lo, a), hi = std::max(hi, b); }
    bool empty() const { return lo > hi; }
};

std::pair<double, double> extent(const std::vector<Point2f>& polygon, bool alongX) {
    double lo = HUGE_VAL, hi = -HUGE_VAL;
    for (const Point2f& p : polygon) {
        const double v = alongX ? p.x : p.y;
        lo = std::min(lo, v), hi = std::max(hi, v);
    }
    return {lo, hi};
}

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
    const double length = alongX ? image.width : image.height;
    // A plain crop's window: the target's aspect at the full other side.
    const double crop = alongX ? image.height * double(newSize.width) / newSize.height
                               : image.width * double(newSize.height) / newSize.width;
    std::vector<geometry::Polygon> polygons(size_t(cage.polygonCount()));
    for (int i = 0; i < cage.polygonCount(); ++i) polygons[size_t(i)] = cage.polygon(i);
    const std::vector<int> depth = geometry::depths(polygons);
    const std::vector<int> parent = geometry::parents(polygons, depth);
    // What the window keeps whole: each outline the plain crop could hold; of a wider one, the
    // polygons it protects (faces, features) that the plain crop could hold. A polygon wider
    // than that could only be kept by shrinking it and stretching what is around it, so the
    // window cuts it, as a plain crop would, and shows it at its size.
    Keep keep, outlines;
    for (size_t i = 0; i < polygons.size(); ++i) {
        const auto [lo, hi] = extent(polygons[i], alongX);
        if (depth[i] == 1) outlines.add(lo, hi);
        if (hi - lo > crop) continue;
        if (depth[i] == 1) {
            keep.add(lo, hi);
        } else if (depth[i] == 2) {
            const auto [plo, phi] = extent(polygons[size_t(parent[i])], alongX);
            if (phi - plo > crop) keep.add(lo, hi);
        }
    }
    // A margin on each side of what is kept, so nothing kept touches the window's side: 4% of
    // the plain crop, and 6% of the window where subjects far apart widen it past the crop (the
    // warp squeezes the window into the output, and the resize pose leaves an outline at least 4%
    // of the output to the frame, so a thinner margin would squeeze the outline itself). Never
    // narrower than the plain crop (what is kept then centred in it), nor wider than the image.
    double width = crop, centre = length / 2;
    if (!keep.empty()) {
        const double span = keep.hi - keep.lo;
        width = std::clamp(std::max(span + 0.08 * crop, span / 0.88), crop, length);
        centre = (keep.lo + keep.hi) / 2;
    } else if (!outlines.empty()) {
        centre = (outlines.lo + outlines.hi) / 2;
    }
    const double lo = std::clamp(centre - width / 2, 0.0, length - width);
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

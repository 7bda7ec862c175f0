// Random poses for data augmentation (augment.hpp): per-polygon similarities composed along
// the nesting, jitter, scaling to the amplitude, checks, retries and scale-downs.
#include <opencv2/multicage/augment.hpp>
#include <opencv2/multicage/internal/geometry.hpp>
#include <opencv2/multicage/internal/point_input.hpp>

#include <algorithm>
#include <cmath>
#include <memory>

namespace cv {
namespace multicage {

namespace {

using geometry::Polygon;

std::vector<Polygon> polygonsOf(const Multicage& cage) {
    std::vector<Polygon> out(cage.polygonCount());
    for (int i = 0; i < cage.polygonCount(); ++i) out[i] = cage.polygon(i);
    return out;
}

/** For each polygon, the innermost other polygon containing it, or -1. */
std::vector<int> parentsOf(const std::vector<Polygon>& polygons) {
    const std::vector<int> depth = geometry::depths(polygons);
    std::vector<int> parent(polygons.size(), -1);
    for (size_t i = 0; i < polygons.size(); ++i)
        for (size_t k = 0; k < polygons.size(); ++k)
            if (k != i && geometry::contains(polygons[k], Point2d(polygons[i][0])) &&
                (parent[i] < 0 || depth[k] > depth[parent[i]]))
                parent[i] = static_cast<int>(k);
    return parent;
}

double segmentDistance(Point2d p, Point2d a, Point2d b) {
    const Point2d ab = b - a;
    const double len2 = ab.dot(ab);
    const double t = len2 > 0 ? std::min(1.0, std::max(0.0, (p - a).dot(ab) / len2)) : 0.0;
    const Point2d d = p - (a + t * ab);
    return std::sqrt(d.dot(d));
}

/** Per user vertex, the largest jitter that cannot cross anything: a fifth of the shorter
adjacent edge and of the distance to every edge not incident to it (frame included). */
std::vector<double> jitterLimits(const Multicage& cage, const std::vector<Polygon>& polygons) {
    std::vector<std::pair<Point2d, Point2d>> edges;
    std::vector<std::pair<int, int>> owner;  // (polygon, edge index); frame: polygon -1
    for (size_t p = 0; p < polygons.size(); ++p)
        for (size_t e = 0; e < polygons[p].size(); ++e)
            edges.emplace_back(Point2d(polygons[p][e]), Point2d(polygons[p][(e + 1) % polygons[p].size()])),
                owner.emplace_back(static_cast<int>(p), static_cast<int>(e));
    const std::vector<Point2f> frame = cage.frame();
    for (int e = 0; e < 4; ++e) edges.emplace_back(Point2d(frame[e]), Point2d(frame[(e + 1) % 4])), owner.emplace_back(-1, e);
    std::vector<double> limit;
    for (size_t p = 0; p < polygons.size(); ++p) {
        const int n = static_cast<int>(polygons[p].size());
        for (int v = 0; v < n; ++v) {
            const Point2d x(polygons[p][v]);
            double d = std::min(cv::norm(x - Point2d(polygons[p][(v + 1) % n])),
                                cv::norm(x - Point2d(polygons[p][(v + n - 1) % n])));
            for (size_t k = 0; k < edges.size(); ++k) {
                const bool incident = owner[k].first == static_cast<int>(p) &&
                                      (owner[k].second == v || owner[k].second == (v + n - 1) % n);
                if (!incident) d = std::min(d, segmentDistance(x, edges[k].first, edges[k].second));
            }
            limit.push_back(0.2 * d);
        }
    }
    return limit;
}

/** The fold-over check mesh of the overload without a binding: bound once per thread for the
last multicage seen (augmentation draws many poses of one multicage). */
const Binding& checkBinding(const Multicage& cage, int step) {
    struct Cached {
        Size size;
        std::vector<Point2f> vertices;
        std::vector<int> sizes;
        int coordinates = -2, step = 0;
        Binding binding;
    };
    thread_local std::unique_ptr<Cached> cache;
    std::vector<int> sizes(cage.polygonCount());
    for (int i = 0; i < cage.polygonCount(); ++i) sizes[i] = static_cast<int>(cage.polygon(i).size());
    const int coordinates = resolveCoordinates(cage, COORDINATES_FROM_CAGE);
    if (!cache || cache->size != cage.imageSize() || cache->vertices != cage.vertices() ||
        cache->sizes != sizes || cache->coordinates != coordinates || cache->step != step) {
        std::unique_ptr<Cached> fresh(new Cached);
        fresh->binding = bind(cage, coordinates, step);
        fresh->size = cage.imageSize(), fresh->vertices = cage.vertices(), fresh->sizes = sizes;
        fresh->coordinates = coordinates, fresh->step = step;
        cache = std::move(fresh);
    }
    return cache->binding;
}

class PoseDrawer {
public:
    PoseDrawer(const Multicage& cage, const RandomPoseParams& params)
        : cage_(cage), params_(params), polygons_(polygonsOf(cage)), parents_(parentsOf(polygons_)),
          jitter_(jitterLimits(cage, polygons_)) {}

    std::vector<Point2f> draw(double amplitude, RNG& rng) const {
        const size_t count = polygons_.size();
        // Each polygon's own similarity x -> c + s R (x - c) + t, as a 2x3 affine matrix; a
        // polygon's motion is its own displacement plus its parent's motion at the point.
        std::vector<Matx23d> own(count);
        for (size_t i = 0; i < count; ++i) {
            const Polygon& poly = polygons_[i];
            Point2d c(0, 0);
            for (const Point2f& v : poly) c += Point2d(v);
            c *= 1.0 / poly.size();
            double r = 1e-9;
            for (const Point2f& v : poly) r = std::max(r, cv::norm(Point2d(v) - c));
            const double maxAngle = std::min(params_.maxRotation * CV_PI / 180.0, amplitude / r);
            const double angle = rng.uniform(-1.0, 1.0) * maxAngle;
            const double scale = 1.0 + rng.uniform(-1.0, 1.0) * std::min(params_.maxScale, amplitude / r);
            const Point2d t(rng.uniform(-amplitude, amplitude), rng.uniform(-amplitude, amplitude));
            const double a = scale * std::cos(angle), b = scale * std::sin(angle);
            own[i] = Matx23d(a, -b, c.x - a * c.x + b * c.y + t.x, b, a, c.y - b * c.x - a * c.y + t.y);
        }
        std::vector<Point2d> displacement;
        for (size_t i = 0; i < count; ++i)
            for (const Point2f& v : polygons_[i]) displacement.push_back(motion(static_cast<int>(i), Point2d(v), own));
        for (size_t k = 0; k < displacement.size(); ++k) {
            const double j = std::min(params_.jitter * amplitude, jitter_[k]);
            displacement[k] += Point2d(rng.uniform(-j, j), rng.uniform(-j, j));
        }
        double longest = 0;
        for (const Point2d& d : displacement) longest = std::max(longest, cv::norm(d));
        const double fit = longest > amplitude ? amplitude / longest : 1.0;
        // Away from the border: not closer than the margin, or than the vertex was at rest.
        const double margin = params_.frameMargin >= 0 ? params_.frameMargin : amplitude;
        const Size size = cage_.imageSize();
        std::vector<Point2f> pose;
        size_t k = 0;
        for (const Polygon& poly : polygons_)
            for (const Point2f& v : poly) {
                const Point2d p = Point2d(v) + fit * displacement[k++];
                const double x = std::min(std::max(p.x, std::min<double>(v.x, margin)),
                                          std::max<double>(v.x, size.width - 1.0 - margin));
                const double y = std::min(std::max(p.y, std::min<double>(v.y, margin)),
                                          std::max<double>(v.y, size.height - 1.0 - margin));
                pose.emplace_back(static_cast<float>(x), static_cast<float>(y));
            }
        return pose;
    }

private:
    Point2d motion(int i, Point2d x, const std::vector<Matx23d>& own) const {
        Point2d d(0, 0);
        for (int p = i; p >= 0; p = parents_[p]) {
            const Matx23d& m = own[p];
            d += Point2d(m(0, 0) * x.x + m(0, 1) * x.y + m(0, 2), m(1, 0) * x.x + m(1, 1) * x.y + m(1, 2)) - x;
        }
        return d;
    }

    const Multicage& cage_;
    RandomPoseParams params_;
    std::vector<Polygon> polygons_;
    std::vector<int> parents_;
    std::vector<double> jitter_;
};

void checkArguments(const Multicage& cage, double amplitude, const RandomPoseParams& params) {
    std::string why;
    if (!cage.validateGeometry(&why)) CV_Error(Error::StsBadArg, "multicage: randomPose: " + why);
    if (!std::isfinite(amplitude) || amplitude < 0)
        CV_Error_(Error::StsBadArg, ("multicage: randomPose: the amplitude must be a finite number "
                                     ">= 0 (pixels), got %g", amplitude));
    if (params.attempts < 1 || params.scaleDowns < 0 || params.checkGridStep < 0 ||
        !(params.maxRotation >= 0) || !(params.maxScale >= 0 && params.maxScale < 1) || !(params.jitter >= 0))
        CV_Error(Error::StsBadArg, "multicage: randomPose: RandomPoseParams out of range (attempts >= 1, "
                                   "scaleDowns >= 0, checkGridStep >= 0, maxRotation >= 0, 0 <= maxScale < 1, "
                                   "jitter >= 0)");
}

std::vector<Point2f> drawPose(const Multicage& cage, const Binding& binding, double amplitude, RNG& rng,
                              const RandomPoseParams& params) {
    std::vector<Point2f> rest = cage.vertices();
    rest.resize(cage.vertexCount());
    if (amplitude == 0 || cage.polygonCount() == 0) return rest;
    const PoseDrawer drawer(cage, params);
    const Mat restNodes = binding.nodes();
    Mat positions;
    for (int level = 0; level <= params.scaleDowns; ++level, amplitude *= 0.5) {
        for (int attempt = 0; attempt < params.attempts; ++attempt) {
            std::vector<Point2f> pose = drawer.draw(amplitude, rng);
            if (!validatePose(cage, pose)) continue;
            binding.apply(pose, positions);
            if (countFoldedTriangles(positions, restNodes) == 0) return pose;
        }
    }
    return rest;
}

}  // namespace

bool validatePose(const Multicage& cage, InputArray poseIn, std::string* why) {
    std::vector<Point2f> pose = toPoints(poseIn, "pose");
    const int n = cage.vertexCount();
    auto fail = [&](const std::string& text) {
        if (why) *why = text;
        return false;
    };
    if (static_cast<int>(pose.size()) == n + 4) {
        const std::vector<Point2f> frame = cage.frame();
        if (!std::equal(frame.begin(), frame.end(), pose.begin() + n))
            return fail("the pose moves the frame corners (vertices " + std::to_string(n) + "-" +
                        std::to_string(n + 3) + "); only poses with the rest frame are checked here");
        pose.resize(n);
    }
    if (static_cast<int>(pose.size()) != n)
        return fail(format("the pose has %d vertices, the multicage has %d", static_cast<int>(pose.size()), n));
    const Multicage posed = cage.posed(pose);
    std::string reason;
    if (!posed.validateGeometry(&reason)) return fail("posed: " + reason);
    const std::vector<int> before = parentsOf(polygonsOf(cage)), after = parentsOf(polygonsOf(posed));
    for (size_t i = 0; i < before.size(); ++i)
        if (before[i] != after[i]) {
            auto name = [](int p) { return p < 0 ? std::string("no polygon") : "polygon " + std::to_string(p); };
            return fail("posed: polygon " + std::to_string(i) + " lies inside " + name(after[i]) +
                        ", at rest inside " + name(before[i]));
        }
    if (why) why->clear();
    return true;
}

std::vector<Point2f> randomPose(const Multicage& cage, double amplitude, RNG& rng, const RandomPoseParams& params) {
    checkArguments(cage, amplitude, params);
    const Size size = cage.imageSize();
    const int step = params.checkGridStep > 0 ? params.checkGridStep
                                              : std::max(1, (std::max(size.width, size.height) + 159) / 160);
    return drawPose(cage, checkBinding(cage, step), amplitude, rng, params);
}

std::vector<Point2f> randomPose(const Multicage& cage, const Binding& binding, double amplitude, RNG& rng,
                                const RandomPoseParams& params) {
    checkArguments(cage, amplitude, params);
    if (binding.empty() || binding.imageSize != cage.imageSize() || binding.restVertices != cage.vertices())
        CV_Error(Error::StsBadArg, "multicage: randomPose: the binding was not made for this multicage (its "
                                   "image size or rest vertices differ); bind the multicage itself");
    return drawPose(cage, binding, amplitude, rng, params);
}

}  // namespace multicage
}  // namespace cv

// Random poses for data augmentation (augment.hpp): per-polygon similarities composed along
// the nesting, jitter, scaling to the amplitude, checks, retries and scale-downs.
#include <algorithm>
#include <cmath>
#include <memory>
#include <opencv2/multicage/augment.hpp>
#include <opencv2/multicage/coordinates.hpp>
#include <opencv2/multicage/internal/geometry.hpp>
#include <opencv2/multicage/internal/point_input.hpp>

#include "fan_sums.hpp"

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
    const Point2d d = p - geometry::nearestOnSegment(p, a, b);
    return std::sqrt(d.dot(d));
}

/** Per user vertex, the distance to the nearest edge not incident to it (frame included), and
the length of its shorter adjacent edge. */
struct VertexRoom {
    std::vector<double> clearance, shortestEdge;
};

VertexRoom vertexRoom(const Multicage& cage, const std::vector<Polygon>& polygons) {
    std::vector<std::pair<Point2d, Point2d>> edges;
    std::vector<std::pair<int, int>> owner;  // (polygon, edge index); frame: polygon -1
    for (size_t p = 0; p < polygons.size(); ++p)
        for (size_t e = 0; e < polygons[p].size(); ++e)
            edges.emplace_back(Point2d(polygons[p][e]),
                               Point2d(polygons[p][(e + 1) % polygons[p].size()])),
                owner.emplace_back(static_cast<int>(p), static_cast<int>(e));
    const std::vector<Point2f> frame = cage.frame();
    for (int e = 0; e < 4; ++e)
        edges.emplace_back(Point2d(frame[e]), Point2d(frame[(e + 1) % 4])),
            owner.emplace_back(-1, e);
    VertexRoom room;
    for (size_t p = 0; p < polygons.size(); ++p) {
        const int n = static_cast<int>(polygons[p].size());
        for (int v = 0; v < n; ++v) {
            const Point2d x(polygons[p][v]);
            room.shortestEdge.push_back(
                std::min(cv::norm(x - Point2d(polygons[p][(v + 1) % n])),
                         cv::norm(x - Point2d(polygons[p][(v + n - 1) % n]))));
            double d = INFINITY;
            for (size_t k = 0; k < edges.size(); ++k) {
                const bool incident = owner[k].first == static_cast<int>(p) &&
                                      (owner[k].second == v || owner[k].second == (v + n - 1) % n);
                if (!incident) d = std::min(d, segmentDistance(x, edges[k].first, edges[k].second));
            }
            room.clearance.push_back(d);
        }
    }
    return room;
}

/** Per user vertex, the largest jitter that cannot cross anything: a fifth of the shorter
adjacent edge and of the distance to every edge not incident to it (frame included). */
std::vector<double> jitterLimits(const Multicage& cage, const std::vector<Polygon>& polygons) {
    const VertexRoom room = vertexRoom(cage, polygons);
    std::vector<double> limit(room.clearance.size());
    for (size_t j = 0; j < limit.size(); ++j)
        limit[j] = 0.2 * std::min(room.clearance[j], room.shortestEdge[j]);
    return limit;
}

/** Fold-over near the cage vertices, where mean value coordinates bend most (the map is a cone
around a vertex, the same at every scale, so a grid can miss a fold there): a small polar mesh
around every user vertex (rings of radius 0.3, 1.5, 3 and 6 px, 16 directions: sectors of 22.5
degrees, and of 112.5 degrees within half the distance to the nearest other edge), its points'
coordinates computed once (Algorithm 1 at arbitrary points, or its local variant: each point sums
the polygons bounding its region only), then moved by each pose and checked for reversed
triangles. Empty for harmonic coordinates (they exist only on the grid). */
class VertexFans {
  public:
    VertexFans() = default;
    VertexFans(const Multicage& cage, bool local) {
        const VertexRoom room = vertexRoom(cage, polygonsOf(cage));
        const std::vector<Point2f> vertices = cage.vertices();
        for (int j = 0; j < cage.vertexCount(); ++j)
            addFan(Point2d(vertices[j]), room.clearance[j], cage.imageSize());
        const Mat total = rawWeights(cage, local);
        normalise(total, cage.vertexCount());
        restPoints_.assign(points_.begin(), points_.end());
        for (const Vec3i& t : triangles_) {
            const Point2d ra(points_[t[0]]), rb(points_[t[1]]), rc(points_[t[2]]);
            positiveAtRest_.push_back((rb - ra).cross(rc - ra) > 0);
        }
    }

    /** Whether pose (user vertices) reverses a triangle of a fan. */
    bool folds(const std::vector<Point2f>& pose, const std::vector<Point2f>& rest) const {
        if (points_.empty()) return false;
        const int users = static_cast<int>(pose.size()), count = byVertex_.cols;
        // Scratch kept by the thread (the fans are cached per thread too): a draw allocates
        // nothing here.
        thread_local FoldScratch s;
        s.rows.clear(), s.dx.clear(), s.dy.clear();
        for (int j = 0; j < users; ++j)
            if (pose[j].x != rest[j].x || pose[j].y != rest[j].y)
                s.rows.push_back(byVertex_.ptr<double>(j)), s.dx.push_back(pose[j].x - rest[j].x),
                    s.dy.push_back(pose[j].y - rest[j].y);
        const int moved = static_cast<int>(s.rows.size());
        s.offset.resize(moved);
        // Fan by fan (a fan's triangles use only its own samples), so that a draw that folds
        // stops at the first fan that does. Each sample: sample + sum_j CC_j (v'_j - v_j), the
        // sum over j in order as one point at a time would add it (vertices at rest add
        // nothing), a vertex at a time across the fan's samples (contiguous in byVertex_ rows).
        for (size_t f = 0; f < centres_.size(); ++f) {
            const int begin = centres_[f];
            const int end = f + 1 < centres_.size() ? centres_[f + 1] : count;
            s.sx.assign(end - begin, 0.0), s.sy.assign(end - begin, 0.0);
            for (int q = 0; q < moved; ++q) s.offset[q] = s.rows[q] + begin;
            accumulateFanSums(s.offset.data(), s.dx.data(), s.dy.data(), moved, end - begin,
                              s.sx.data(), s.sy.data());
            const Point2d* rest2 = restPoints_.data() + begin;
            auto at = [&](int i) {
                return rest2[i - begin] + Point2d(s.sx[i - begin], s.sy[i - begin]);
            };
            const int tEnd = f + 1 < centres_.size() ? triangleStart_[f + 1]
                                                     : static_cast<int>(triangles_.size());
            for (int k = triangleStart_[f]; k < tEnd; ++k) {
                const Vec3i& t = triangles_[k];
                const Point2d a = at(t[0]), b = at(t[1]), c = at(t[2]);
                if (positiveAtRest_[k] != ((b - a).cross(c - a) > 0)) return true;
            }
        }
        return false;
    }

  private:
    static constexpr int kDirections = 16, kRings = 4;

    void addTriangle(int a, int b, int c) {  // -1: a sample outside the frame
        if (a >= 0 && b >= 0 && c >= 0) triangles_.emplace_back(a, b, c);
    }

    /** The fan of the user vertex v: its centre, the ring samples inside the frame, and the
    triangles between them; clearance: v's distance to the nearest edge not incident to it. */
    void addFan(Point2d v, double clearance, Size size) {
        static const double radii[] = {0.3, 1.5, 3.0, 6.0};
        auto inside = [&](Point2d p) {
            return p.x > -0.5 && p.y > -0.5 && p.x < size.width - 0.5 && p.y < size.height - 0.5;
        };
        const int centre = static_cast<int>(points_.size());
        points_.push_back(Point2f(v));
        centres_.push_back(centre);
        triangleStart_.push_back(static_cast<int>(triangles_.size()));
        std::vector<int> index(kRings * kDirections, -1);
        for (int r = 0; r < kRings; ++r)
            for (int k = 0; k < kDirections; ++k) {
                // 22.5-degree steps; the irrational offset keeps the samples off the polygon
                // edges (where the exact-edge policy would apply).
                const double a = 2 * CV_PI * (k + 0.3183098861837907) / kDirections;
                const Point2d p = v + radii[r] * Point2d(std::cos(a), std::sin(a));
                if (!inside(p)) continue;
                index[r * kDirections + k] = static_cast<int>(points_.size());
                points_.push_back(Point2f(p));
            }
        for (int k = 0; k < kDirections; ++k) {
            const int k1 = (k + 1) % kDirections;
            addTriangle(centre, index[k], index[k1]);
            for (int r = 0; r + 1 < kRings; ++r) {  // the quads between rings
                const int a = index[r * kDirections + k], b = index[r * kDirections + k1];
                const int c = index[(r + 1) * kDirections + k],
                          d = index[(r + 1) * kDirections + k1];
                addTriangle(a, c, b), addTriangle(b, c, d);
            }
            // Wide sectors too: a mesh triangle with a corner on the vertex spans up to 90
            // degrees there, and flips when the pose opens that sector past 180 degrees, though
            // every narrow sector stays positive. Every 90-degree sector lies in one of these
            // 112.5-degree ones, which must stay under 180 degrees. Only within half the
            // distance to any other edge: beyond, a wide sector may reach across another
            // polygon's edge, into a region that moves apart, and turn over with no fold.
            for (int r = 0; r < kRings; ++r)
                if (radii[r] <= 0.5 * clearance)
                    addTriangle(centre, index[r * kDirections + k],
                                index[r * kDirections + (k + 5) % kDirections]);
        }
    }

    /** Local coordinates: the region of each sample (the deepest polygon holding it, the
    frame's = polygonCount()) and each polygon's parent (the frame's = polygonCount()). */
    void sampleRegions(const Multicage& cage, std::vector<int>& region,
                       std::vector<int>& parent) const {
        const int frameIndex = cage.polygonCount(), count = static_cast<int>(points_.size());
        const std::vector<geometry::Polygon> all = polygonsOf(cage);
        const std::vector<int> depthOf = geometry::depths(all),
                               up = geometry::parents(all, depthOf);
        for (int p = 0; p < frameIndex; ++p)
            if (up[p] >= 0) parent[p] = up[p];
        for (int i = 0; i < count; ++i)
            for (int p = 0; p < frameIndex; ++p)
                if ((region[i] == frameIndex || depthOf[p] > depthOf[region[i]]) &&
                    geometry::contains(cage.polygon(p), points_[i]))
                    region[i] = p;
    }

    /** Algorithm 1 at the sample points, before the division by the total: every polygon's raw
    weights (signed as if oriented by the orientation rule) and the frame's, samples x (users +
    4). With local coordinates polygon p is summed at a sample only where it bounds the sample's
    region (p is the region, or one of its children). */
    Mat rawWeights(const Multicage& cage, bool local) const {
        const int users = cage.vertexCount();
        const int count = static_cast<int>(points_.size()), c = users + 4;
        Mat total(count, c, CV_64F, Scalar(0));
        std::vector<std::pair<std::vector<Point2f>, int>> polygons;
        for (int p = 0; p < cage.polygonCount(); ++p)
            polygons.emplace_back(cage.polygon(p), cage.polygonOffset(p));
        polygons.emplace_back(cage.frame(), users);
        const int frameIndex = cage.polygonCount();
        std::vector<int> region(count, frameIndex), parent(frameIndex, frameIndex);
        if (local) sampleRegions(cage, region, parent);
        for (size_t p = 0; p < polygons.size(); ++p) {
            double sign = 1;
            if (static_cast<int>(p) < cage.polygonCount())
                sign = (cage.signedArea(static_cast<int>(p)) > 0) ==
                               (cage.depth(static_cast<int>(p)) % 2 == 0)
                           ? 1
                           : -1;
            Mat w;
            meanValueCoordinates(polygons[p].first, points_, w, false);
            const int pi = static_cast<int>(p);
            for (int i = 0; i < count; ++i) {
                const bool bounds =
                    !local || pi == region[i] || (pi != frameIndex && parent[pi] == region[i]);
                if (!bounds) continue;
                for (int k = 0; k < w.cols; ++k)
                    total.at<double>(i, polygons[p].second + k) = sign * w.at<float>(i, k);
            }
        }
        return total;
    }

    /** The cage coordinates of the samples: the raw weights divided by their total, each fan's
    centre exactly its vertex. */
    void normalise(const Mat& total, int users) {
        const int count = total.rows;
        coefficients_.create(count, total.cols, CV_64F);
        for (int i = 0; i < count; ++i) {
            const double sum = cv::sum(total.row(i))[0];
            coefficients_.row(i) = total.row(i) * (1.0 / sum);
        }
        // The centre of each fan is the vertex itself: exactly its pose position.
        for (int j = 0; j < users; ++j) {
            coefficients_.row(centres_[j]).setTo(0);
            coefficients_.at<double>(centres_[j], j) = 1;
        }
        byVertex_ = coefficients_.colRange(0, users).t();
    }

    struct FoldScratch {
        std::vector<const double*> rows, offset;
        std::vector<double> dx, dy, sx, sy;
    };

    std::vector<Point2f> points_;       // fan centres (the vertices) and ring samples
    std::vector<Point2d> restPoints_;   // points_ in double
    std::vector<char> positiveAtRest_;  // per triangle: its orientation at rest is positive
    std::vector<int> centres_;  // index of each user vertex's centre in points_ (its fan's first)
    std::vector<int> triangleStart_;  // index of each fan's first triangle in triangles_
    std::vector<Vec3i> triangles_;
    Mat coefficients_;  // samples x (users + 4), CV_64F
    Mat byVertex_;      // users x samples, CV_64F: the user vertices' columns, transposed
};

/** Per polygon, the distance to the nearest other polygon (the frame not counted; infinity when
alone): the room its own motion has relative to its neighbours. */
std::vector<double> polygonRoom(const std::vector<Polygon>& polygons) {
    std::vector<double> room(polygons.size(), INFINITY);
    for (size_t i = 0; i < polygons.size(); ++i)
        for (size_t k = 0; k < polygons.size(); ++k) {
            if (k == i) continue;
            // Disjoint polygons are nearest at a vertex of one of them: vertices of i to the
            // edges of k (the loop over pairs also does k's vertices to i's edges).
            const Polygon& e = polygons[k];
            for (const Point2f& v : polygons[i])
                for (size_t a = 0; a < e.size(); ++a) {
                    const double d =
                        segmentDistance(Point2d(v), Point2d(e[a]), Point2d(e[(a + 1) % e.size()]));
                    room[i] = std::min(room[i], d), room[k] = std::min(room[k], d);
                }
        }
    return room;
}

class PoseDrawer {
  public:
    explicit PoseDrawer(const Multicage& cage)
        : size_(cage.imageSize()),
          polygons_(polygonsOf(cage)),
          parents_(parentsOf(polygons_)),
          jitter_(jitterLimits(cage, polygons_)),
          room_(polygonRoom(polygons_)) {}

    /** A pose at this amplitude; margin: RandomPoseParams::frameMargin resolved (the asked-for
    amplitude when negative, kept when the amplitude is scaled down). */
    std::vector<Point2f> draw(double amplitude, double margin, RNG& rng,
                              const RandomPoseParams& params) const {
        const size_t count = polygons_.size();
        // Each polygon's own similarity x -> c + s R (x - c) + t, kept as its displacement
        // x -> (s R - I) x + b, an affine map; a polygon's motion is its own displacement plus
        // its parent's motion at the point, so nested polygons move together. The own part is
        // limited to a quarter of the distance to the nearest other polygon, so that polygons
        // close together (siblings a few pixels apart) move nearly as one: the displacement
        // stays smooth where the multicage is tight.
        std::vector<Matx23d> own(count);
        for (size_t i = 0; i < count; ++i) {
            const Polygon& poly = polygons_[i];
            Point2d c(0, 0);
            for (const Point2f& v : poly) c += Point2d(v);
            c *= 1.0 / poly.size();
            double r = 1e-9;
            for (const Point2f& v : poly) r = std::max(r, cv::norm(Point2d(v) - c));
            const double maxAngle = std::min(params.maxRotation * CV_PI / 180.0, amplitude / r);
            const double angle = rng.uniform(-1.0, 1.0) * maxAngle;
            const double scale =
                1.0 + rng.uniform(-1.0, 1.0) * std::min(params.maxScale, amplitude / r);
            // Two draws in one expression would come in the compiler's order of evaluating
            // arguments (GCC: right to left, clang: left to right), and a seed would replay
            // differently by compiler: drawn one statement at a time, y first (the GCC order
            // the recorded draws were made with).
            const double ty = rng.uniform(-amplitude, amplitude);
            const Point2d t(rng.uniform(-amplitude, amplitude), ty);
            const double a = scale * std::cos(angle) - 1, b = scale * std::sin(angle);
            Matx23d d(a, -b, -a * c.x + b * c.y + t.x, b, a, -b * c.x - a * c.y + t.y);
            double largest = 0;
            for (const Point2f& v : poly)
                largest = std::max(largest, cv::norm(apply(d, Point2d(v))));
            const double limit = 0.25 * room_[i];
            own[i] = largest > limit ? d * (limit / largest) : d;
        }
        std::vector<Point2d> displacement;
        for (size_t i = 0; i < count; ++i)
            for (const Point2f& v : polygons_[i])
                displacement.push_back(motion(static_cast<int>(i), Point2d(v), own));
        size_t k = 0;
        for (; k < displacement.size(); ++k) {
            const double j = std::min(params.jitter * amplitude, jitter_[k]);
            const double jy = rng.uniform(-j, j);  // y first, as t above
            displacement[k] += Point2d(rng.uniform(-j, j), jy);
        }
        double longest = 0;
        for (const Point2d& d : displacement) longest = std::max(longest, cv::norm(d));
        const double fit = longest > amplitude ? amplitude / longest : 1.0;
        // The frame stays fixed: a vertex near it moves less (linearly less from twice the
        // margin down to 0 at the frame), so the narrow band between it and the frame is not
        // sheared over; and it never gets closer than the margin, or than it was at rest.
        const Size size = size_;
        k = 0;
        for (const Polygon& poly : polygons_)
            for (const Point2f& v : poly) {
                const double gap = std::min(std::min(v.x + 0.5, size.width - 0.5 - v.x),
                                            std::min(v.y + 0.5, size.height - 0.5 - v.y));
                if (margin > 0 && gap < 2 * margin) displacement[k] *= gap / (2 * margin);
                ++k;
            }
        std::vector<Point2f> pose;
        k = 0;
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
    static Point2d apply(const Matx23d& m, Point2d x) {
        return Point2d(m(0, 0) * x.x + m(0, 1) * x.y + m(0, 2),
                       m(1, 0) * x.x + m(1, 1) * x.y + m(1, 2));
    }
    Point2d motion(int i, Point2d x, const std::vector<Matx23d>& own) const {
        Point2d d(0, 0);
        for (int p = i; p >= 0; p = parents_[p]) d += apply(own[p], x);
        return d;
    }

    Size size_;
    std::vector<Polygon> polygons_;
    std::vector<int> parents_;
    std::vector<double> jitter_;
    std::vector<double> room_;
};

/** What the checks of one multicage need, made once per thread for the last multicage seen
(augmentation draws many poses of one multicage): the coarse binding of the overload without
a binding, the vertex fans and the pose drawer's tables. */
struct CageChecks {
    Size size;
    std::vector<Point2f> vertices;
    std::vector<int> sizes;
    int coordinates = -2, step = -1;
    Binding binding;  // step > 0 only
    VertexFans fans;
    std::unique_ptr<PoseDrawer> drawer;  // its per-polygon tables (rooms, jitter limits, nesting)
};

const CageChecks& cageChecks(const Multicage& cage, int step) {
    thread_local std::unique_ptr<CageChecks> cache;
    std::vector<int> sizes(cage.polygonCount());
    for (int i = 0; i < cage.polygonCount(); ++i)
        sizes[i] = static_cast<int>(cage.polygon(i).size());
    const int coordinates = resolveCoordinates(cage, COORDINATES_FROM_CAGE);
    if (!cache || cache->size != cage.imageSize() || cache->vertices != cage.vertices() ||
        cache->sizes != sizes || cache->coordinates != coordinates) {
        std::unique_ptr<CageChecks> fresh(new CageChecks);
        fresh->size = cage.imageSize(), fresh->vertices = cage.vertices(), fresh->sizes = sizes;
        fresh->coordinates = coordinates;
        if (coordinates == MEAN_VALUE || coordinates == LOCAL_MEAN_VALUE)
            fresh->fans = VertexFans(cage, coordinates == LOCAL_MEAN_VALUE);
        fresh->drawer.reset(new PoseDrawer(cage));
        cache = std::move(fresh);
    }
    if (step > 0 && cache->step != step) {
        cache->binding = bind(cage, coordinates, step);
        cache->step = step;
    }
    return *cache;
}

void checkArguments(const Multicage& cage, double amplitude, const RandomPoseParams& params) {
    std::string why;
    if (!cage.validateGeometry(&why)) CV_Error(Error::StsBadArg, "multicage: randomPose: " + why);
    if (!std::isfinite(amplitude) || amplitude < 0)
        CV_Error_(Error::StsBadArg, ("multicage: randomPose: the amplitude must be a finite number "
                                     ">= 0 (pixels), got %g",
                                     amplitude));
    if (params.attempts < 1 || params.scaleDowns < 0 || params.checkGridStep < 0 ||
        !(params.maxRotation >= 0) || !(params.maxScale >= 0 && params.maxScale < 1) ||
        !(params.jitter >= 0))
        CV_Error(Error::StsBadArg,
                 "multicage: randomPose: RandomPoseParams out of range (attempts >= 1, "
                 "scaleDowns >= 0, checkGridStep >= 0, maxRotation >= 0, 0 <= maxScale < 1, "
                 "jitter >= 0)");
}

/** binding.nodes(), kept by the thread for the last grid seen (they depend on the image size
and grid step only). */
const Mat& restNodesOf(const Binding& binding) {
    thread_local Mat nodes;
    thread_local Size image(-1, -1);
    thread_local int step = -1;
    if (binding.imageSize != image || binding.gridStep != step || nodes.size() != binding.gridSize)
        nodes = binding.nodes(), image = binding.imageSize, step = binding.gridStep;
    return nodes;
}

std::vector<Point2f> drawPose(const Multicage& cage, const Binding& binding,
                              const CageChecks& checks, double amplitude, RNG& rng,
                              const RandomPoseParams& params) {
    std::vector<Point2f> rest = cage.vertices();
    rest.resize(cage.vertexCount());
    if (amplitude == 0 || cage.polygonCount() == 0) return rest;
    const PoseDrawer& drawer = *checks.drawer;
    const VertexFans& fans = checks.fans;
    const Mat& restNodes = restNodesOf(binding);
    const double margin = params.frameMargin >= 0 ? params.frameMargin : amplitude;
    thread_local Mat positions;  // reused: a fresh one would be mapped and faulted in per draw
    for (int level = 0; level <= params.scaleDowns; ++level, amplitude *= 0.5) {
        for (int attempt = 0; attempt < params.attempts; ++attempt) {
            std::vector<Point2f> pose = drawer.draw(amplitude, margin, rng, params);
            if (!validatePose(cage, pose) || fans.folds(pose, rest)) continue;
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
                        std::to_string(n + 3) +
                        "); only poses with the rest frame are checked here");
        pose.resize(n);
    }
    if (static_cast<int>(pose.size()) != n)
        return fail(format("the pose has %d vertices, the multicage has %d",
                           static_cast<int>(pose.size()), n));
    const Multicage posed = cage.posed(pose);
    std::string reason;
    if (!posed.validateGeometry(&reason)) return fail("posed: " + reason);
    const std::vector<int> before = parentsOf(polygonsOf(cage)),
                           after = parentsOf(polygonsOf(posed));
    for (size_t i = 0; i < before.size(); ++i)
        if (before[i] != after[i]) {
            auto name = [](int p) {
                return p < 0 ? std::string("no polygon") : "polygon " + std::to_string(p);
            };
            return fail("posed: polygon " + std::to_string(i) + " lies inside " + name(after[i]) +
                        ", at rest inside " + name(before[i]));
        }
    if (why) why->clear();
    return true;
}

std::vector<Point2f> randomPose(const Multicage& cage, double amplitude, RNG& rng,
                                const RandomPoseParams& params) {
    checkArguments(cage, amplitude, params);
    const Size size = cage.imageSize();
    const int step = params.checkGridStep > 0
                         ? params.checkGridStep
                         : std::max(1, (std::max(size.width, size.height) + 159) / 160);
    const CageChecks& checks = cageChecks(cage, step);
    return drawPose(cage, checks.binding, checks, amplitude, rng, params);
}

std::vector<Point2f> randomPose(const Multicage& cage, const Binding& binding, double amplitude,
                                RNG& rng, const RandomPoseParams& params) {
    checkArguments(cage, amplitude, params);
    if (binding.empty() || binding.imageSize != cage.imageSize() ||
        binding.restVertices != cage.vertices())
        CV_Error(Error::StsBadArg,
                 "multicage: randomPose: the binding was not made for this multicage (its "
                 "image size or rest vertices differ); bind the multicage itself");
    return drawPose(cage, binding, cageChecks(cage, 0), amplitude, rng, params);
}

}  // namespace multicage
}  // namespace cv

#include <algorithm>
#include <numeric>
#include <opencv2/multicage/internal/geometry.hpp>

namespace cv {
namespace multicage {
namespace geometry {

double signedArea(const Polygon& polygon) {
    double twice = 0.0;
    const size_t n = polygon.size();
    for (size_t i = 0; i < n; ++i) {
        const Point2d a = polygon[i], b = polygon[(i + 1) % n];
        twice += a.x * b.y - b.x * a.y;
    }
    return 0.5 * twice;
}

int orientation(Point2d a, Point2d b, Point2d c) {
    const double d = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    return (d > 0) - (d < 0);
}

static bool onSegment(Point2d a, Point2d b, Point2d p) {
    return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
           p.y <= std::max(a.y, b.y);
}

bool segmentsIntersect(Point2d p1, Point2d p2, Point2d q1, Point2d q2) {
    const int o1 = orientation(p1, p2, q1), o2 = orientation(p1, p2, q2);
    const int o3 = orientation(q1, q2, p1), o4 = orientation(q1, q2, p2);
    if (o1 != o2 && o3 != o4) return true;
    return (o1 == 0 && onSegment(p1, p2, q1)) || (o2 == 0 && onSegment(p1, p2, q2)) ||
           (o3 == 0 && onSegment(q1, q2, p1)) || (o4 == 0 && onSegment(q1, q2, p2));
}

bool contains(const Polygon& polygon, Point2d p) {
    bool inside = false;
    const size_t n = polygon.size();
    for (size_t i = 0, j = n - 1; i < n; j = i++) {
        const Point2d a = polygon[i], b = polygon[j];
        if ((a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x)
            inside = !inside;
    }
    return inside;
}

namespace {
struct Edge {
    int polygon, index;
    Point2d a, b;
    double minX, maxX, minY, maxY;
};

// Two edges of one polygon meeting at vertex v = end of `first`: they are a crossing only
// when collinear and folding back (a spike), since meeting at v is the polygon's own corner.
bool foldsBack(const Edge& first, const Edge& second) {
    const Point2d u = first.a - first.b, w = second.b - second.a;
    return orientation(first.a, first.b, second.b) == 0 && u.dot(w) > 0;
}
}  // namespace

bool findCrossing(const std::vector<Polygon>& polygons, Crossing* crossing) {
    std::vector<Edge> edges;
    for (int p = 0; p < static_cast<int>(polygons.size()); ++p) {
        const int n = static_cast<int>(polygons[p].size());
        for (int i = 0; i < n; ++i) {
            Edge e{p, i, polygons[p][i], polygons[p][(i + 1) % n], 0, 0, 0, 0};
            e.minX = std::min(e.a.x, e.b.x), e.maxX = std::max(e.a.x, e.b.x);
            e.minY = std::min(e.a.y, e.b.y), e.maxY = std::max(e.a.y, e.b.y);
            edges.push_back(e);
        }
    }
    std::sort(edges.begin(), edges.end(),
              [](const Edge& l, const Edge& r) { return l.minX < r.minX; });
    bool found = false;
    Crossing best;
    auto better = [&](const Crossing& c) {  // deterministic: lowest (A, edge, B, edge)
        return !found || std::tie(c.polygonA, c.edgeA, c.polygonB, c.edgeB) <
                             std::tie(best.polygonA, best.edgeA, best.polygonB, best.edgeB);
    };
    for (size_t i = 0; i < edges.size(); ++i) {
        const Edge& e = edges[i];
        for (size_t j = i + 1; j < edges.size() && edges[j].minX <= e.maxX; ++j) {
            const Edge& f = edges[j];
            if (f.minY > e.maxY || f.maxY < e.minY) continue;
            bool hit;
            if (e.polygon == f.polygon) {
                const int n = static_cast<int>(polygons[e.polygon].size());
                if ((e.index + 1) % n == f.index)
                    hit = foldsBack(e, f);
                else if ((f.index + 1) % n == e.index)
                    hit = foldsBack(f, e);
                else
                    hit = segmentsIntersect(e.a, e.b, f.a, f.b);
            } else {
                hit = segmentsIntersect(e.a, e.b, f.a, f.b);
            }
            if (!hit) continue;
            Crossing c;
            const Edge& hi =
                (e.polygon > f.polygon || (e.polygon == f.polygon && e.index < f.index)) ? e : f;
            const Edge& lo = (&hi == &e) ? f : e;
            c.polygonA = hi.polygon, c.edgeA = hi.index, c.polygonB = lo.polygon,
            c.edgeB = lo.index;
            if (better(c)) best = c, found = true;
        }
    }
    if (found && crossing) *crossing = best;
    return found;
}

std::vector<int> depths(const std::vector<Polygon>& polygons) {
    std::vector<int> depth(polygons.size(), 1);
    for (size_t i = 0; i < polygons.size(); ++i) {
        if (polygons[i].empty()) continue;
        for (size_t j = 0; j < polygons.size(); ++j)
            if (j != i && polygons[j].size() >= 3 && contains(polygons[j], polygons[i][0]))
                ++depth[i];
    }
    return depth;
}

std::vector<int> parents(const std::vector<Polygon>& polygons, const std::vector<int>& depth) {
    std::vector<int> parent(polygons.size(), -1);
    for (size_t i = 0; i < polygons.size(); ++i) {
        if (polygons[i].empty()) continue;
        for (size_t j = 0; j < polygons.size(); ++j)
            if (depth[j] == depth[i] - 1 && polygons[j].size() >= 3 &&
                contains(polygons[j], polygons[i][0]))
                parent[i] = static_cast<int>(j);
    }
    return parent;
}

}  // namespace geometry
}  // namespace multicage
}  // namespace cv

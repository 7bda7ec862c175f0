// Planar predicates shared by the modules (private). All arithmetic in double.
#ifndef MULTICAGE_GEOMETRY_HPP
#define MULTICAGE_GEOMETRY_HPP

#include <algorithm>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace cv {
namespace multicage {
namespace geometry {

using Polygon = std::vector<Point2f>;

/** A = 1/2 sum(x_i y_{i+1} - x_{i+1} y_i); > 0 is clockwise on screen (y down). */
double signedArea(const Polygon& polygon);
inline bool isFinite(Point2f p) {
    return std::isfinite(p.x) && std::isfinite(p.y);
}
/** Sign of det(b - a, c - a): +1, 0 or -1. */
int orientation(Point2d a, Point2d b, Point2d c);
/** True when the closed segments share at least one point. */
bool segmentsIntersect(Point2d p1, Point2d p2, Point2d q1, Point2d q2);
/** Crossing-number test; points on the boundary may go either way. */
bool contains(const Polygon& polygon, Point2d p);
/** The point of the closed segment ab nearest to p (a itself where a == b). */
inline Point2d nearestOnSegment(Point2d p, Point2d a, Point2d b) {
    const Point2d ab = b - a;
    const double len2 = ab.dot(ab);
    const double t = len2 > 0 ? std::min(1.0, std::max(0.0, (p - a).dot(ab) / len2)) : 0.0;
    return a + t * ab;
}

/** A pair of edges that touch or cross. Edge e of a polygon runs from vertex e to e+1. */
struct Crossing {
    int polygonA = -1, edgeA = -1;  // polygonA >= polygonB
    int polygonB = -1, edgeB = -1;
};
/** Finds a touching or crossing pair of edges among polygons (a polygon's two edges at a
shared vertex count only when they fold back onto each other). Sweep over x: O((E + K) log E)
for E edges and K bounding-box overlaps. Returns false when there is none. */
bool findCrossing(const std::vector<Polygon>& polygons, Crossing* crossing);

/** For each polygon, 1 + the number of other polygons containing its first vertex. */
std::vector<int> depths(const std::vector<Polygon>& polygons);

/** For each polygon, the polygon one level up (depths() of them given) holding its first vertex,
or -1 for an outline: in a valid multicage polygons are nested or disjoint, so that one vertex
decides. */
std::vector<int> parents(const std::vector<Polygon>& polygons, const std::vector<int>& depth);

}  // namespace geometry
}  // namespace multicage
}  // namespace cv

#endif

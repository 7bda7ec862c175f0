// Regions to polygons (private): the cage mask around the objects, its nested regions, and
// their simplification within the vertex budgets, repaired until every polygon is simple and
// all are pairwise disjoint.
//
// Where polygons come from: the objects are dilated by the margin and closed by a small gap
// (objects nearer than two gaps share a polygon), and every outer contour of that "cage
// mask" (findContours, RETR_TREE) is one polygon; an object inside another object's hole is
// one level deeper. Distinct contours of the cage mask are at least two gaps apart, so
// simplifying each within a tolerance below the gap cannot make them cross; a tolerance
// forced higher by the vertex budget is checked and repaired.
#ifndef MULTICAGE_PROPOSE_POLYGONS_HPP
#define MULTICAGE_PROPOSE_POLYGONS_HPP

#include <functional>

#include "work.hpp"

namespace cv {
namespace multicage {
namespace propose_detail {

/** dilate(objects, margin), closed by gap. The image is padded first so that an object cut by
the image edge is dilated and closed as if it went on: its polygon then follows the edge. */
Mat cageMaskFromObjects(const Mat& objects, const Work& w);

/** For a label image: each label component dilated by the margin into the pixels nearer to
it than to any other label, less a band of `gap` along the split, so that touching labels get
separate polygons and a label inside another one is nested in it. */
Mat cageMaskFromLabels(const Mat& labels, const Work& w);

// One polygon to make: an outer contour of the cage mask.
struct Region {
    std::vector<Point> contour;
    int depth = 1;
    double area = 0;
    Mat distance;  // from the filled contour, within `roi`; made when first needed
    Rect roi;
    Mat limit;  // work-size mask the grown region must stay in (empty: the image)
};

/** Outer contours at even levels of the contour tree, as regions with their depth, largest
first. */
std::vector<Region> nestedRegions(const Mat& cageMask, int maxDepth, double minArea);

// What new polygons may take: polygon slots, vertices in all, and vertices of one polygon.
struct Budget {
    int polygons, vertices, polygonVertices;
};

// How a proposal's result is checked: proposeMulticage promises a valid multicage (validate()),
// protectFeatures the geometry its input had to have (validateGeometry()).
enum class Check { VALID, GEOMETRY };

// The tail both proposals share: the regions that fit the budget (in priority order) become
// polygons, simplified within the budget and repaired against the polygons `cage` already
// has; those that survive (and that `accept`, when given, accepts) are added to it, and the
// result is oriented and checked. `depth`:
// of the polygon the regions sit in (0 for a whole image); `who` names the public function in
// the error an invalid result raises.
Multicage addPolygons(Multicage cage, std::vector<Region> found, const Work& w,
                      const Budget& budget, int depth, const char* who, Check check,
                      const std::function<bool(const Polygon&)>& accept = nullptr);

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv

#endif

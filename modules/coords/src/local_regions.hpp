// Which polygons bound each node's region, for local mean value coordinates (private).
#ifndef MULTICAGE_LOCAL_REGIONS_HPP
#define MULTICAGE_LOCAL_REGIONS_HPP

#include <opencv2/multicage/multicage.hpp>
#include <vector>

namespace cv {
namespace multicage {

/** The regions of a multicage and the polygons bounding each.

Region r (0 <= r < polygonCount()) is the inside of user polygon r minus its children; region
polygonCount() is the frame's: inside the frame, outside every outline. Polygon index
polygonCount() stands for the frame. The polygons bounding region r are r itself and its
children (depth one more, inside it): exactly those local mean value coordinates sum over. */
class LocalRegions {
  public:
    explicit LocalRegions(const Multicage& multicage);

    int frame() const { return static_cast<int>(parent_.size()); }
    /** True when polygon p (frame() for the frame) bounds region r. */
    bool bounds(int p, int r) const { return p == r || (p != frame() && parent_[p] == r); }

    /** The region of every node (xs[k], y), k < m: the deepest polygon whose inside holds it
    (crossing numbers along the row, in double), frame() for none. A node on an edge may go to
    either side: mean value coordinates there are the edge's, whichever side names it. */
    void regionsOfRow(const float* xs, int m, double y, int* region) const;

  private:
    std::vector<std::vector<Point2d>> polygons_;
    std::vector<int> parent_;   // per polygon: its parent polygon, frame() for outlines
    std::vector<int> byDepth_;  // polygon indices, shallowest first
};

}  // namespace multicage
}  // namespace cv

#endif

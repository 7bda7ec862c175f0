// How the resize pose moves an outline (private): the one similarity resizePose() gives each
// depth-1 polygon, shared with reframeWindow(), which places what a window holds the same way.
#ifndef MULTICAGE_OUTLINE_SIMILARITY_HPP
#define MULTICAGE_OUTLINE_SIMILARITY_HPP

#include <opencv2/core.hpp>
#include <vector>

namespace cv {
namespace multicage {

/** p' = to + s (p - from). */
struct Similarity {
    double s = 1;
    Point2d from, to;
    Point2f operator()(Point2f p) const { return Point2f(to + s * (Point2d(p) - from)); }
};

/** The similarity resizePose() moves `outline` (a depth-1 polygon, pixel coordinates of an
image of `image`) by into a frame of `target`: s = 1 between the frame's two scales, else the
scale nearer 1, never more than fits with the gaps the outline keeps to the sides; its box's
centre follows the frame's scaling, kept inside those gaps (an outline on a side stays on it). */
Similarity outlineSimilarity(const std::vector<Point2f>& outline, Size image, Size target);

}  // namespace multicage
}  // namespace cv

#endif

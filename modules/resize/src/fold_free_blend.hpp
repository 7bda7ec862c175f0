// How far a mesh can blend towards another before a triangle folds (private).
#ifndef MULTICAGE_FOLD_FREE_BLEND_HPP
#define MULTICAGE_FOLD_FREE_BLEND_HPP

#include <opencv2/core.hpp>

namespace cv {
namespace multicage {

/** The first t > 0 at which a triangle of the mesh p0 + t (p1 - p0) reaches zero area, infinity
when none ever does, 0 when p0 itself has a flat or folded triangle (gridSize CV_32FC2 meshes
of a Binding, the triangles of kCellTriangles). Each corner moves linearly in t, so each
triangle's signed area is a quadratic in t and its first positive root is exact: one pass over
the mesh replaces a bisection of fold counts. */
double firstFold(const Mat& p0, const Mat& p1);

/** countFoldedTriangles(positions, binding.nodes()) without the rest mesh, on all threads: every
triangle of a node grid is positively oriented at rest, so a fold is an area <= 0 (the same
double arithmetic). */
int foldedTriangles(const Mat& positions);

}  // namespace multicage
}  // namespace cv

#endif

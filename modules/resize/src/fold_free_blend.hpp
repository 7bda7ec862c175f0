// How far a mesh can blend towards another before a triangle folds (private).
#ifndef MULTICAGE_FOLD_FREE_BLEND_HPP
#define MULTICAGE_FOLD_FREE_BLEND_HPP

#include <opencv2/core.hpp>

namespace cv {
namespace multicage {

/** The first t > 0 at which a triangle of the mesh p0 + t (p1 - p0) shrinks to `area` (its cross
product (b - a) x (c - a): 1 px^2 at rest at grid step 1; 0 means a fold), infinity when none
ever does, 0 when one of p0 already is that small (gridSize CV_32FC2 meshes of a Binding, the
triangles of kCellTriangles). Each corner moves linearly in t, so each triangle's area is a
quadratic in t and its first root is exact: one pass over the mesh replaces a bisection of fold
counts. */
double firstFold(const Mat& p0, const Mat& p1, double area = 0);

/** countFoldedTriangles(positions, binding.nodes()) without the rest mesh, on all threads: every
triangle of a node grid is positively oriented at rest, so a fold is an area <= 0 (the same
double arithmetic). */
int foldedTriangles(const Mat& positions);

}  // namespace multicage
}  // namespace cv

#endif

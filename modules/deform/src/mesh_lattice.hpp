// Inverse maps found on a lattice and interpolated (private): DeformParams::mapStep.
//
// Where the mesh folds nowhere, its inverse is a continuous piecewise linear map, so the maps
// can be found exactly on a lattice of output points every mapStep pixels or less (the pull
// kernel, mesh_pull.hpp, walking to the lattice's points instead of pixels) and interpolated
// bilinearly in between: exact wherever a lattice cell lies inside one triangle, off by the
// bend of the map across the triangles' edges elsewhere. That is the same kind of error a grid
// step makes, on the other side of the map, and of about its size (docs/performance.md, "Maps on
// a lattice", has the figures).
#ifndef MULTICAGE_MESH_LATTICE_HPP
#define MULTICAGE_MESH_LATTICE_HPP

#include <opencv2/core.hpp>
#include <vector>

#include "mesh_pull.hpp"

namespace cv {
namespace multicage {
namespace raster {

/** The lattice of an output of `size` for mapStep `step` (>= 2): (cols x rows) points at
x = i * spacing.x, y = j * spacing.y, the first and last on the border pixels' centres,
spacing.x = (width - 1) / (cols - 1) <= step (and likewise in y). */
struct Lattice {
    Size points;
    Point2d spacing;
    static Lattice of(Size size, int step);
};

/** Whether a lattice can be used for an output of `size`: both sides at least 2 pixels, and
the mesh's frame (its ring's outer boundary, convex: frameConvex) holding every output pixel
centre with room to spare, so that every lattice point and every pixel between them is covered
(a frame moved inwards leaves pixels no triangle covers, which interpolation would blur). */
bool latticeFits(const PullMesh& mesh, Size size, int step);

/** The inverse maps at the lattice's points (lx, ly: lattice.points CV_32F, made here unless
they are already) for a pullable mesh (raster::pullable), in parallel: the pull kernel with the
lattice's spacing (PullMesh::spacing). False where a point's walk did not settle (the caller then
draws the maps whole). */
bool pullLattice(const PullMesh& mesh, const Lattice& lattice, Mat& lx, Mat& ly);

/** Each output column's place in a lattice: its interval (left) and weight in it, and, for 8
columns at a time, each one's interval less the first's (local). They depend on the output's
width and the lattice alone: made once, with the lattice's maps, not per pose. */
struct LatticeColumns {
    std::vector<int> left, local;
    std::vector<float> weight;
    static LatticeColumns of(const Lattice& lattice, int width);
};

/** Rows [y0, y1) of the maps (CV_32F, the output's size, columns.left.size() wide) interpolated
bilinearly from the lattice's (pullLattice). */
void interpolateRows(const Lattice& lattice, const LatticeColumns& columns, const Mat& lx,
                     const Mat& ly, int y0, int y1, Mat& mapx, Mat& mapy);

}  // namespace raster
}  // namespace multicage
}  // namespace cv

#endif

// The pull kernel (private): inverse maps of a mesh that folds nowhere, found pixel by pixel.
#ifndef MULTICAGE_MESH_PULL_HPP
#define MULTICAGE_MESH_PULL_HPP

#include <opencv2/core.hpp>

namespace cv {
namespace multicage {
namespace raster {

/** A binding's node grid with its ring (RasterMesh's layout): deformed nodes ((n+2) x (m+2)
CV_32FC2, continuous) around grid nodes that rest at (min(gx step, hi.x), min(gy step, hi.y)), the
ring's nodes at rest on their nearest grid node. */
struct PullMesh {
    const Point2f* nodes;
    int cols, rows;  // nodes per row (m + 2), node rows (n + 2)
    Size gridSize;   // m, n
    float step;
    Point2f lo, hi;  // the rest nodes' extent, the maps' clamp (as the raster's)
    /** Where pixel (i, j) of the maps pulled lies: (i spacing.x, j spacing.y). 1 for the maps of
    the output itself; a lattice's spacing for maps found only at its points (mesh_lattice.hpp). */
    Point2f spacing{1.f, 1.f};
};

/** Whether every triangle of the mesh (kCellTriangles of each cell, ring included) keeps the rest
grid's orientation by a clear margin (no fold, no sliver, every node finite), and the ring's outer
boundary is a convex quadrilateral of that orientation. Then every pixel centre inside the frame
lies in exactly one triangle (the boundary winds once around it, and each triangle counts +1),
except on shared edges, where the triangles' affine maps agree: a pixel's value does not depend on
the order triangles are drawn in, and it can be found from the pixel. */
bool pullable(const PullMesh& mesh);

/** The two halves of pullable: the ring's outer boundary is a convex quadrilateral of the rest
grid's orientation; every triangle of the cells between node rows ey and ey + 1, for ey in
[ey0, ey1) (rows of the mesh, ring included), is clearly positive. False without the kernel. */
bool frameConvex(const PullMesh& mesh);
bool positiveRows(const PullMesh& mesh, int ey0, int ey1);

/** The rows of a pull's guesses: each run of kPullRun rows from a multiple of it starts afresh,
the rows after extrapolating from the rows above. So a pixel's walk, and where a tie between
triangles sharing an edge is settled, depends on the pixel alone, not on how the rows were split
between threads: the same bits on 1 thread or 16. */
constexpr int kPullRun = 16;

/** Rows [y0, y1) of the inverse maps of a pullable mesh, each pixel found by walking from a guess
to the triangle that holds it: the rest point (clamped to [lo, hi]) of that triangle, or kUncovered
outside the frame. False when some pixel's walk did not settle (a frame edge through a pixel
centre, or a mesh distorted beyond the walk's reach): the caller then draws the rows with the
raster kernel. Float arithmetic: the values are the raster's within a few float roundings.
y0 is a multiple of kPullRun. */
bool pullRows(const PullMesh& mesh, int y0, int y1, Mat& mapx, Mat& mapy);

/** Whether this build and CPU have a pull kernel (AVX-512, or AVX2: the same walk 8 pixels at a
time). */
bool havePullKernel();
/** The pull kernel pullRows runs: "AVX-512", "AVX2" or "none". */
const char* pullKernelName();
/** Makes pullRows and positiveRows use the AVX2 kernel even where AVX-512 is there (true), or
choose again (false): for tests that compare the kernels. */
void preferAvx2Pull(bool avx2);

}  // namespace raster
}  // namespace multicage
}  // namespace cv

#endif

/** @file
@brief Cage coordinates and binding (paper §3.2, Algorithm 1).
@ingroup multicage_coords
*/
#ifndef OPENCV2_MULTICAGE_COORDINATES_HPP
#define OPENCV2_MULTICAGE_COORDINATES_HPP

#include <functional>
#include <opencv2/multicage/multicage.hpp>

namespace cv {
namespace multicage {

//! @addtogroup multicage_coords
//! @{

/** @brief The coordinates a binding uses: coordinates, or the multicage's own choice when it is
COORDINATES_FROM_CAGE.
@param multicage the multicage to be bound.
@param coordinates a CoordinateType.
@return coordinates, or multicage.coordinates() when it is COORDINATES_FROM_CAGE.
*/
CV_EXPORTS int resolveCoordinates(const Multicage& multicage, int coordinates);

/** @brief Mean value coordinates of points with respect to one polygon (Floater 2003; Hormann &
Floater 2006), valid inside and outside the polygon.

The raw weight of vertex i is `w_i = (tan(a_{i-1}/2) + tan(a_i/2)) / r_i` (Hormann & Floater
2006, Eq. 7), with r_i the distance to vertex i and a_i the signed angle the edge (i, i+1)
subtends at the point.
Edge cases are a policy, not an accident: a point on a vertex gets 1 for that vertex; a point
on an edge gets the linear interpolation between the edge's two vertices; both are returned
as these exact values even when normalize is false (the raw weights are infinite there).
Raw weights sum to a positive number inside a polygon with signed area > 0 and a negative one
outside it. Computed in double precision.

@param polygon n points (std::vector<Point2f> or Nx2), n >= 3, the vertices in order; fewer
throws a cv::Exception (StsBadArg).
@param points N points, in the same forms.
@param[out] weights N x n CV_32F, row k the coordinates of point k.
@param normalize divide by the sum (true) or return the raw weights w_i (false).
@sa bind
*/
CV_EXPORTS_W void meanValueCoordinates(InputArray polygon, InputArray points, OutputArray weights,
                                       bool normalize = true);

/** @brief Below this Binding::minConditioning the tools (`multicage deform`, the editor) warn
of a likely spring-up singularity: the raw weights of all polygons nearly cancel there, and
small pose changes move the node a lot. */
constexpr double kConditioningWarning = 1e-3;

/** @brief Every node of a grid over the image bound to all vertices of a multicage.

Nodes sit every gridStep pixels, `x_k = min(k*gridStep, W-1)` and likewise in y, so the last
row and column lie on the image border. Node (gx, gy) has index `gy*gridSize.width + gx`.

The coefficients are stored planar: row j of `coefficients` holds coefficient j of every
node, so each coefficient is one image-sized plane (this is also what packing wants).
@sa bind, packCoefficients, Deformer::create
*/
struct CV_EXPORTS Binding {
    Size imageSize;                     //!< the multicage's image size, in pixels
    int gridStep = 1;                   //!< pixels between nodes; 1: a node per pixel (the paper's)
    Size gridSize;                      //!< nodes in x and y
    int coordinates = MEAN_VALUE;       //!< CoordinateType
    Mat coefficients;                   //!< coefficientCount() x nodeCount(), CV_32F
    std::vector<Point2f> restVertices;  //!< user vertices, then the 4 frame corners
    /** Minimum over nodes of `|sum_j w_j| / sum_j |w_j|` over raw weights; 1 for harmonic.
    @sa kConditioningWarning */
    double minConditioning = 1.0;
    Point2f worstNode;  //!< where minConditioning occurs (pixel coordinates)

    /** @brief Coefficients per node: the user vertices and the 4 frame corners.
    @return restVertices.size(). */
    int coefficientCount() const { return static_cast<int>(restVertices.size()); }
    /** @brief Number of grid nodes.
    @return gridSize.area(). */
    int nodeCount() const { return gridSize.area(); }
    /** @brief Whether nothing is bound (a default-constructed Binding).
    @return true when coefficients is empty. */
    bool empty() const { return coefficients.empty(); }
    /** @brief Rest position of node (gx, gy).
    @param gx node column, 0 <= gx < gridSize.width.
    @param gy node row, 0 <= gy < gridSize.height.
    @return `(min(gx*gridStep, W-1), min(gy*gridStep, H-1))`. */
    Point2f node(int gx, int gy) const;
    /** @brief Rest positions of all nodes.
    @return a gridSize CV_32FC2 matrix, element (gy, gx) = node(gx, gy). */
    Mat nodes() const;
    /** @brief Deformed node positions for a pose.

    `p' = x + sum_j CC_j (v'_j - v_j)`: the displacement form of `sum_j CC_j v'_j` (exact for
    the rest pose; vertices that did not move cost nothing).
    @param pose vertexCount() points, or coefficientCount() with the frame last
    (completePose() checks it).
    @param[out] positions gridSize CV_32FC2.
    @sa transformPoints */
    void apply(InputArray pose, OutputArray positions) const;
    /** @brief The pose as coefficientCount() points: checks count and finiteness, appends the
    frame corners when they are omitted.
    @param pose vertexCount() or coefficientCount() points.
    @return coefficientCount() points, the frame corners last.
    @throws cv::Exception naming the bad vertex, or the count when it is neither. */
    std::vector<Point2f> completePose(InputArray pose) const;
};

/** @brief Node grid size for an image and a grid step: `ceil((W-1)/s)+1` by `ceil((H-1)/s)+1`.
@param imageSize a non-empty image size.
@param gridStep s >= 1; less throws a cv::Exception (StsOutOfRange).
@return the number of nodes in x and y.
*/
CV_EXPORTS Size gridSizeFor(Size imageSize, int gridStep);

/** @brief Binds every grid node to every vertex of the multicage.

MEAN_VALUE (the paper's Algorithm 1): the raw weights of each polygon (frame included, each
signed as if oriented by the orientation rule) are concatenated and divided by their total. A
node on a polygon's vertex or edge gets that polygon's exact values and zero elsewhere. The
float kernel's rounding is removed by projecting each node's coefficients onto partition of
unity and linear precision. minConditioning and worstNode report the worst cancellation.

HARMONIC (Joshi et al. 2007; DeRose & Meyer 2006): a discrete Laplace solve per region on
the node grid with every polygon edge and the frame as Dirichlet boundaries (Eigen sparse
LDL^T); coefficients are in [0, 1] and a region's nodes see only the polygons bounding it.
minConditioning is 1 and worstNode (0, 0): there is no cancellation. Details:
docs/harmonic/README.md.

LOCAL_MEAN_VALUE: Algorithm 1 summed, node by node, over the polygons bounding the node's
region only (the region's own polygon and its children; the frame and the outlines outside
every outline), then projected like MEAN_VALUE onto those polygons' vertices; every other
coefficient is exactly 0 (docs/coordinates.md).

COORDINATES_FROM_CAGE (the default) binds with multicage.coordinates().

Runs on all cores (cv::parallel_for_).
@param multicage the multicage; it must pass validateGeometry() (the orientation rule is
not needed).
@param coordinates a CoordinateType; another value throws a cv::Exception (StsOutOfRange).
@param gridStep pixels between nodes, >= 1.
@return the binding: coefficientCount() = vertexCount() + 4 coefficients per node.
@throws cv::Exception (StsBadArg) when the multicage does not pass validateGeometry().
@sa bindOnGpu, Deformer::create
*/
CV_EXPORTS Binding bind(const Multicage& multicage, int coordinates = COORDINATES_FROM_CAGE,
                        int gridStep = 1);

/** @brief Progress of a long binding.

Called with the fraction done, from 0 to 1 and never decreasing, one call at a time but from
any of the binding's threads. Return false to cancel: bind() then stops at the next step and
throws a cv::Exception (code Error::StsError) whose message ends in kBindCancelled, leaving
nothing behind. */
typedef std::function<bool(double)> BindProgress;
/** @brief The end of the message of the exception a cancelled bind() throws. */
constexpr const char* kBindCancelled = "binding cancelled";

/** @brief bind() reporting progress, and cancellable.

Harmonic coordinates report after the boundary, the system assembly, each region's
factorisation and each block of solves, and stop at the next of these points when cancelled;
the one step that cannot be interrupted is the factorisation of the largest region, which
takes most of the time: until it ends, reports pause and a cancel waits (shares measured in
docs/harmonic/README.md). Mean value and local mean value coordinates, bound in one pass,
report 0 and 1 only.
@param multicage as bind().
@param coordinates as bind().
@param gridStep as bind().
@param progress the callback; empty: no reports, as bind().
@return the binding, as bind() gives it.
@throws cv::Exception as bind(), and (StsError, message ending in kBindCancelled) when
progress returned false.
@sa DeformParams::progress
*/
CV_EXPORTS Binding bind(const Multicage& multicage, int coordinates, int gridStep,
                        const BindProgress& progress);

//! @} multicage_coords

}  // namespace multicage
}  // namespace cv

#endif

// Cage coordinates and binding (paper §3.2, Algorithm 1).
#ifndef OPENCV2_MULTICAGE_COORDINATES_HPP
#define OPENCV2_MULTICAGE_COORDINATES_HPP

#include <functional>
#include <opencv2/multicage/multicage.hpp>

namespace cv {
namespace multicage {

/** coordinates, or multicage.coordinates() when it is COORDINATES_FROM_CAGE. */
CV_EXPORTS int resolveCoordinates(const Multicage& multicage, int coordinates);

/** Mean value coordinates of points with respect to one polygon (Hormann & Floater 2006),
valid inside and outside the polygon.

Inputs:
  polygon  n points (std::vector<Point2f> or Nx2), n >= 3, the vertices in order
  points   N points
  normalize  divide by the sum (true) or return the raw weights w_i (false)
Outputs:
  weights  N x n CV_32F, row k the coordinates of point k

Edge cases are a policy, not an accident: a point on a vertex gets 1 for that vertex; a point
on an edge gets the linear interpolation between the edge's two vertices; both are returned
as these exact values even when normalize is false (the raw weights are infinite there).
Raw weights sum to a positive number inside a polygon with signed area > 0 and a negative one
outside it. Computed in double precision. */
CV_EXPORTS_W void meanValueCoordinates(InputArray polygon, InputArray points,
                                       OutputArray weights, bool normalize = true);

/** Below this conditioning minimum bind() reports a likely spring-up singularity: the raw
weights of all polygons nearly cancel there, and small pose changes move the node a lot. */
constexpr double kConditioningWarning = 1e-3;

/** Every node of a grid over the image bound to all vertices of a multicage.

Nodes sit every gridStep pixels, x_k = min(k*gridStep, W-1) and likewise in y, so the last
row and column lie on the image border. Node (gx, gy) has index gy*gridSize.width + gx.

The coefficients are stored planar: row j of `coefficients` holds coefficient j of every
node, so each coefficient is one image-sized plane (this is also what packing wants). */
struct CV_EXPORTS Binding {
    Size imageSize;
    int gridStep = 1;
    Size gridSize;                     //!< nodes in x and y
    int coordinates = MEAN_VALUE;      //!< CoordinateType
    Mat coefficients;                  //!< coefficientCount() x nodeCount(), CV_32F
    std::vector<Point2f> restVertices; //!< user vertices, then the 4 frame corners
    /** Minimum over nodes of |sum_j w_j| / sum_j |w_j| over raw weights; 1 for harmonic. */
    double minConditioning = 1.0;
    Point2f worstNode;                 //!< where minConditioning occurs (pixel coordinates)

    int coefficientCount() const { return static_cast<int>(restVertices.size()); }
    int nodeCount() const { return gridSize.area(); }
    bool empty() const { return coefficients.empty(); }
    /** Rest position of node (gx, gy). */
    Point2f node(int gx, int gy) const;
    /** Rest positions of all nodes, gridSize CV_32FC2. */
    Mat nodes() const;
    /** Deformed node positions for a pose: p' = x + sum_j CC_j (v'_j - v_j) (the displacement
    form of sum_j CC_j v'_j; exact for the rest pose). pose: vertexCount() points, or
    coefficientCount() with the frame last. positions: gridSize CV_32FC2. */
    void apply(InputArray pose, OutputArray positions) const;
    /** The pose as coefficientCount() points: checks count and finiteness, appends the frame
    corners when they are omitted. Throws a cv::Exception naming the bad vertex. */
    std::vector<Point2f> completePose(InputArray pose) const;
};

/** Node grid size for an image and a grid step: ceil((W-1)/s)+1 by ceil((H-1)/s)+1. */
CV_EXPORTS Size gridSizeFor(Size imageSize, int gridStep);

/** Binds every grid node to every vertex of the multicage.

MEAN_VALUE (Algorithm 1): the raw weights of each polygon (frame included, each signed as if
oriented by the orientation rule) are concatenated and divided by their total. A node on a
polygon's vertex or edge gets that polygon's exact values and zero elsewhere. The float
kernel's rounding is removed by projecting each node's coefficients onto partition of unity
and linear precision. minConditioning and worstNode report the worst cancellation.

HARMONIC (DeRose & Meyer 2006): a discrete Laplace solve per region on the node grid with
every polygon edge and the frame as Dirichlet boundaries (Eigen sparse LDL^T); coefficients are
in [0, 1] and a region's nodes see only the polygons bounding it. minConditioning is 1 and
worstNode (0, 0): there is no cancellation.

LOCAL_MEAN_VALUE: Algorithm 1 summed, node by node, over the polygons bounding the node's
region only (the region's own polygon and its children; the frame and the outlines outside
every outline), then projected like MEAN_VALUE onto those polygons' vertices; every other
coefficient is exactly 0 (docs/coordinates.md).

COORDINATES_FROM_CAGE (the default) binds with multicage.coordinates().

Runs on all cores (cv::parallel_for_). Throws a cv::Exception when the multicage does not pass
validateGeometry(). */
CV_EXPORTS Binding bind(const Multicage& multicage, int coordinates = COORDINATES_FROM_CAGE,
                        int gridStep = 1);

/** Progress of a long binding: called with the fraction done, from 0 to 1 and never
decreasing, one call at a time but from any of the binding's threads. Return false to cancel: bind() then stops at the
next step and throws a cv::Exception (code Error::StsError) whose message ends in
kBindCancelled, leaving nothing behind. */
typedef std::function<bool(double)> BindProgress;
/** The end of the message of the exception a cancelled bind() throws. */
constexpr const char* kBindCancelled = "binding cancelled";

/** bind() reporting progress, and cancellable. Harmonic coordinates report after the
boundary, the system assembly, each region's factorisation and each block of solves, and stop
at the next of these points when cancelled; the one step that cannot be
interrupted is the factorisation of the largest region, most of the time (80 % on the butterfly
multicage): until it ends, reports pause and a cancel waits. Mean value coordinates (fast: tens of milliseconds per megapixel) report 0
and 1 only. */
CV_EXPORTS Binding bind(const Multicage& multicage, int coordinates, int gridStep,
                        const BindProgress& progress);

}  // namespace multicage
}  // namespace cv

#endif

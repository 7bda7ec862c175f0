/** @file
@brief Random poses for data augmentation: smooth, valid, reproducible from a seed.

A pose drawn here keeps every polygon simple, polygons nested as at rest and disjoint, every
vertex inside the image, and folds no triangle of the mesh over, so a batch of augmented
images never holds a torn or mirrored patch. Points and masks follow the image through
Deformer::transformPoints and Deformer::computeMaps.
@ingroup multicage_animate
*/
#ifndef OPENCV2_MULTICAGE_AUGMENT_HPP
#define OPENCV2_MULTICAGE_AUGMENT_HPP

#include <opencv2/multicage/deformer.hpp>
#include <opencv2/multicage/multicage.hpp>
#include <string>
#include <vector>

namespace cv {
namespace multicage {

//! @addtogroup multicage_animate
//! @{

/** @brief Limits of randomPose()'s draws. Out of range (attempts < 1, scaleDowns < 0,
checkGridStep < 0, maxRotation < 0, maxScale outside [0, 1), jitter < 0) randomPose() throws. */
struct CV_EXPORTS RandomPoseParams {
    /** Largest rotation of a polygon about its centre, in degrees (and never more than moves
    its farthest vertex by the amplitude). */
    double maxRotation = 8.0;
    /** Largest relative change of a polygon's size: scale in [1 - maxScale, 1 + maxScale]
    (and never more than moves its farthest vertex by the amplitude). */
    double maxScale = 0.08;
    /** Per-vertex jitter as a fraction of the amplitude, further limited at each vertex to a
    fifth of its adjacent edges and of its distance to any other edge (so jitter never crosses
    a thin gap). */
    double jitter = 0.25;
    /** No vertex gets closer to the image border than this many pixels, or than it was at rest
    (squeezing the band between a polygon and the frame would pull border pixels inwards);
    negative: the amplitude. */
    double frameMargin = -1;
    /** Draws at one amplitude before the amplitude is halved. */
    int attempts = 8;
    /** Times the amplitude is halved before giving up: then the rest pose (always valid) is
    returned. */
    int scaleDowns = 6;
    /** The grid step of the mesh the overload without a binding checks fold-overs on; 0: the
    step giving about 160 nodes along the longer side of the image (bound once per thread and
    multicage, then reused, as are the vertex fans). */
    int checkGridStep = 0;
};

/** @brief A smooth random pose of cage, every user vertex at most `amplitude` pixels from rest.

The displacement: each polygon moves by its own small similarity (rotation, scale, shift drawn
uniformly within RandomPoseParams and the amplitude), added to the motion of the polygon that
contains it, so nested polygons move together; a polygon's own part is limited to a quarter of
its distance to the nearest other polygon, so polygons close together move nearly as one and
the field stays smooth where the multicage is tight. Then a small per-vertex jitter, a uniform
scaling that brings the largest displacement within `amplitude`, and, since the frame stays
fixed, less motion near the image border (linearly less within twice
RandomPoseParams::frameMargin of it, and never closer than the margin or than at rest).

A draw is accepted when validatePose() holds and nothing folds over: (1) around every cage
vertex (mean value coordinates), a small polar mesh of sample points at 0.3 to 6 px, whose
coordinates are computed once, must keep the orientation of its 22.5-degree sectors and of its
112.5-degree ones (any 90-degree corner of a mesh triangle at the vertex lies in one), since a
grid can miss a fold at a vertex; (2) the mesh of a binding (the one given, or one with about 160
nodes along the longer side, bound once per thread and multicage) must have no reversed
triangle (countFoldedTriangles). A rejected draw is drawn again (RandomPoseParams::attempts
times), then the amplitude is halved (RandomPoseParams::scaleDowns times), and at last the rest
pose is returned. tests/animate/random_pose_test.cpp draws 1,000 poses of each sample cage and
finds none invalid and none folded at grid step 2 (the first 100 also at step 1).

The same rng state gives the same pose: seed a cv::RNG for reproducible augmentation.
@param cage a multicage that passes validateGeometry().
@param amplitude the largest vertex move in pixels, finite and >= 0 (0 gives the rest pose).
@param rng the random source; advanced by the draws.
@param params limits of the draws.
@return vertexCount() points (no frame corners: the frame stays fixed).
@throws cv::Exception (StsBadArg) when the multicage does not pass validateGeometry(), the
amplitude is not finite and >= 0, or params are out of range.
@sa validatePose, Deformer::deformBatch, docs/python.md
*/
CV_EXPORTS std::vector<Point2f> randomPose(const Multicage& cage, double amplitude, RNG& rng,
                                           const RandomPoseParams& params = RandomPoseParams());

/** @brief The same, checking fold-overs on `binding` (the binding the poses will deform with,
e.g. a Deformer's, at its grid step) instead of a coarse one.
@param cage as the other overload.
@param binding made for this multicage (same image size and rest vertices), else
cv::Exception (StsBadArg).
@param amplitude as the other overload.
@param rng as the other overload.
@param params as the other overload; checkGridStep is not used.
@return vertexCount() points.
*/
CV_EXPORTS std::vector<Point2f> randomPose(const Multicage& cage, const Binding& binding,
                                           double amplitude, RNG& rng,
                                           const RandomPoseParams& params = RandomPoseParams());

/** @brief Whether pose keeps the multicage valid: every posed polygon simple and strictly
inside the image frame, no two polygons touching or crossing, and every polygon nested in the
same polygon as at rest.

Fold-over is a property of the mesh, not of the polygons: see Deformer::foldedTriangles.
@param cage the multicage at rest.
@param pose vertexCount() points, or +4 with the frame corners, which must then be the rest
frame.
@param[out] why when not null, receives on failure one sentence saying what is wrong.
@return true when the posed multicage is valid.
*/
CV_EXPORTS bool validatePose(const Multicage& cage, InputArray pose, std::string* why = nullptr);

//! @} multicage_animate

}  // namespace multicage
}  // namespace cv

#endif

// Faces in the proposal (private): the protective polygon a face gets, and which faces share
// one. Detection itself is public (detectFaces in propose.hpp).
#ifndef MULTICAGE_PROPOSE_FACES_HPP
#define MULTICAGE_PROPOSE_FACES_HPP

#include <functional>
#include <memory>
#include <opencv2/multicage/propose.hpp>

#include "tasks.hpp"

namespace cv {
namespace multicage {
namespace propose_detail {

/** Vertices of a face's polygon when the budget allows (it depends on the polygon's shape,
not on how finely the shape is cut: see facePolygon). */
constexpr int kFaceVertices = 12;

/** A face's size: the mean of its box's sides. */
inline double faceSize(const Rect& face) {
    return 0.5 * (face.width + face.height);
}

/** Distance in input pixels from a face's box corners to its polygon: 2% of the box's longer
side, at least 2 px. Along the sides the polygon bulges further out (9% of the half side). */
double faceMargin(const Rect& face);

/** How far above a detected face's box its forehead goes, and below it its chin, in box
heights (facePolygon). */
constexpr double kFaceForehead = 0.05;
constexpr double kFaceChin = 0.10;

/** Exponent of the superellipse a face's polygon follows: a rounded box. */
constexpr double kFaceExponent = 8.0;

/** A face's protective polygon: `vertices` (a multiple of 4, at least 4) points on the
superellipse |x/a|^8 + |y/b|^8 = 1 centred on the box grown up to the forehead
and down to the chin (kFaceForehead, kFaceChin), through that box's corners when
margin = 0 and `margin` pixels further out otherwise, one vertex on each diagonal so that the
corners are inside. Input pixels; signed area > 0.

Why this shape (measured, docs/faces/README.md): with mean value coordinates the outline's
motion leaks through the polygon into the face, and the leak grows with the polygon's size
relative to the face: the tighter the polygon hugs the box, the less leaks (a rounded box
leaks less than the ellipse through the corners, which leaks less than one with a margin of
10%). The vertex count hardly matters: a polygon's total mean value weight at a point depends
on the polygon's shape, not on collinear subdivisions of its edges. */
std::vector<Point2f> facePolygon(const Rect2d& box, double margin, int vertices);

/** facePolygon with a margin of its own on each side (left, top, right, bottom). The quarters
meet on the axes, so the polygon stays a rounded box through the box's corners. */
std::vector<Point2f> facePolygon(const Rect2d& box, const Vec4d& margins, int vertices);

/** facePolygon at `margin` with the sides whose vertices come nearer than `band` to the
boundary of `outline` pulled in, a quarter of the margin at a time, until `fits` accepts it;
empty where even the polygon through the box's corners (margin 0) is refused. Input pixels. */
std::vector<Point2f> faceInOutline(const Rect2d& box, double margin, int vertices,
                                   const std::vector<Point2f>& outline, double band,
                                   const std::function<bool(const std::vector<Point2f>&)>& fits);

/** Anchors a face's polygon holds (faceAnchors). */
constexpr int kFaceAnchors = 4;

/** Four small diamonds (4 vertices each) inside a face's box, about where the eyes and the
corners of the mouth are: fixed polygons nested in the face's polygon.

Why: with mean value coordinates the leak through the face's polygon is zero on the polygon
and largest far from it, in the middle of the face; four anchors spread over the face leave
no point of it far from a fixed boundary. Measured (docs/faces/README.md): the face's
residual falls by a quarter to a third (astronaut.png 1.01 -> 0.77 px); one central anchor
gains 5%, a large one loses (it and the face's polygon have opposite orientations, and their
weights cancel inside it, as with any ring of two nested polygons). Input pixels. */
std::vector<std::vector<Point2f>> faceAnchors(const Rect2d& box);

/** detectFaces in steps, for the proposal's order of work (propose.cpp): the searches run
when asked, and faces() answers what detectFaces would once all have run. The constructor
loads the cascades (throwing as detectFaces does) and makes the working copy. */
class FaceSearch {
  public:
    FaceSearch(InputArray image, const ProposeParams& params);
    ~FaceSearch();
    /** The frontal search, on every core; true when it found a face. */
    bool frontal();
    /** The searches left after frontal(), each a task to run on any thread (tasks.hpp),
    longest first: the frontal search for the faces too small for the working copy, on a copy
    twice as large; then, with `profiles`, the profile cascade's two (as the image is and
    mirrored; none without the cascade). */
    Tasks remaining(bool profiles);
    /** The faces of the searches run so far, merged, in input pixels, largest first. */
    std::vector<Rect> faces() const;

  private:
    struct State;
    std::unique_ptr<State> state_;
};

/** Faces whose polygons, grown by `gap` pixels, would overlap are one face: merged into their
bounding box until none overlap. Largest first. */
std::vector<Rect> mergeNearFaces(std::vector<Rect> faces, double gap);

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv

#endif

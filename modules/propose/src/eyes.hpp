// Eyes in a face (private): where a face is large enough, its two eyes found by OpenCV's eye
// cascades, and the polygon each gets inside the face's polygon (features.cpp places them).
#ifndef MULTICAGE_PROPOSE_EYES_HPP
#define MULTICAGE_PROPOSE_EYES_HPP

#include "work.hpp"

namespace cv {
namespace multicage {
namespace propose_detail {

/** The least face width, in input pixels, searched for eyes. Measured on 117 faces found by
the face cascade in opencv-doc's pictures and frames of Megamind.avi (docs/faces/README.md,
"Eyes"): from 59 px the cascades found both eyes of 21 of 24 sharp faces up to 99 px wide,
and no eye pair anywhere but on eyes; on messi5.jpg's 50 px face they find one eye at most,
even on a copy enlarged 4 times. */
constexpr int kEyeFaceMin = 60;

/** Vertices of an eye's polygon: two eyes take the 16 vertices the four anchors they replace
took (the proposal's budget for a face does not change). */
constexpr int kEyeVertices = 8;

/** The two eyes of `face` in `gray` (8-bit grey, input pixels), left one first, as boxes
from the eye cascades (haarcascade_eye.xml, and haarcascade_eye_tree_eyeglasses.xml for
glasses) in the cascade folder of `params`. Empty when the face is narrower than
kEyeFaceMin, a cascade is missing, or no two detections look like a pair of eyes: one in
each half of the face, in its upper 15-60%, a quarter to 0.7 of the face's width apart, at
most a quarter of that apart vertically, of sizes within 1.6 times. One eye alone (a
profile, a wink, a reflection on glasses) is not trusted. */
std::vector<Rect> findEyes(const Mat& gray, const Rect& face, const ProposeParams& params);

/** An eye's polygon: kEyeVertices points on the ellipse inscribed in the eye's box, half as
high as wide plus `margin` pixels (the cascade's box is square and holds brow and cheek
too), input pixels, signed area > 0. */
Polygon eyePolygon(const Rect2d& eye, double margin);

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv

#endif

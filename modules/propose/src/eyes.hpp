// Eyes in a face (private): where a face is large enough, its two eyes found by OpenCV's eye
// cascades, and the polygon each gets inside the face's polygon (features.cpp places them).
#ifndef MULTICAGE_PROPOSE_EYES_HPP
#define MULTICAGE_PROPOSE_EYES_HPP

#include "work.hpp"

namespace cv {
namespace multicage {
namespace propose_detail {

/** The least face width, in input pixels, searched for eyes. Measured on 117 faces that the
frontal cascade finds in opencv-doc's pictures and in frames of Megamind.avi, with a model of
findEyes (docs/faces/README.md, "Eyes"): 74 got a pair, every one on the two eyes; of the 20
sharp faces 59-99 px wide, 19 (the 20th has landmarks drawn over it); on messi5.jpg's 50 px
face the cascades find one eye at most, even on a copy enlarged 4 times. */
constexpr int kEyeFaceMin = 60;

/** Vertices of an eye's polygon: two eyes take the 16 vertices the four anchors they replace
took (the proposal's budget for a face does not change). */
constexpr int kEyeVertices = 8;

/** The two eyes of `face` in `gray` (8-bit grey, input pixels), left one first, as boxes
from the eye cascades (haarcascade_eye.xml, and haarcascade_eye_tree_eyeglasses.xml for
glasses) in the cascade folder of `params`. Empty when the face is narrower than
kEyeFaceMin, a cascade is missing, or no two detections look like a pair of eyes: one in
each half of the face, in its upper 15-60%, a quarter to 0.55 of the face's width apart (the
75 pairs found in the 117 faces: 0.28-0.53; an ear and an eye of a profile face were 0.66),
at most a quarter of that apart vertically, of sizes within 1.4 times (the temple and the
eye of camera.png's profile face: 1.55). It was 1.3 (74 of the 75 pairs of the 117 faces
within 1.26), which lost the turned faces of the cartoon dinner scene at 1.1-1.5 times its
size (1.31-1.34: the far eye is smaller). On opencv-doc's pictures and every tenth frame of
Megamind.avi at 0.85, 1, 1.15 and 1.3 times their size (117-149 faces of 60 px or more), 1.4
pairs 11 more faces than 1.3, every pair on the two eyes (looked at); 1.5 would pair 11 more
still, two of them on no face at all (picture frames, a pixelated drawing) and two with a box
on the brow and temple. One eye alone (a profile, a wink, a reflection on glasses) is not
trusted. */
std::vector<Rect> findEyes(const Mat& gray, const Rect& face, const ProposeParams& params);

/** An eye's polygon: kEyeVertices points around the ellipse 0.84 of the eye's box wide and
0.6 of it high, grown by `margin` pixels (negative: shrunk), centred on the box; its edges
stay about outside that ellipse. The cascade's box is square and holds brow and cheek too; this
ellipse holds the eye with its lids (looked at on the benchmark's three faces with eyes, where
it holds the hand-drawn eye boxes' inscribed ellipses: 0.76 x 0.5 missed two of six). Input
pixels, signed area > 0. */
Polygon eyePolygon(const Rect2d& eye, double margin);

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv

#endif

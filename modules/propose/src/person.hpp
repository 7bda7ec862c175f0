// The person prior (private): where a face is found, a person is there. The face seeds the
// head as sure foreground, and a face-anchored body region below it seeds probable foreground,
// so that GrabCut's outline follows the person (hair, shoulders, an arm holding a glass)
// instead of whatever saliency lit up.
#ifndef MULTICAGE_PROPOSE_PERSON_HPP
#define MULTICAGE_PROPOSE_PERSON_HPP

#include "work.hpp"

namespace cv {
namespace multicage {
namespace propose_detail {

/** A GrabCut seed (work size, CV_8UC1 of GC_* labels) for the people whose faces (input
pixels) are given, empty when `faces` is:
  GC_FGD     the face box's inner 80% (surely the person; the box's edges may hold background
             beside the cheeks),
  GC_PR_FGD  the head around it (hair: half a face size above, a third to the sides) and the
             body below: a trapezoid from a neck 1.2 face widths wide at the chin to shoulders
             3.6 face widths wide one face height lower, down to 5 face heights below the chin
             or the image bottom (a face-anchored torso: people in photos stand or sit upright
             more often than not),
  GC_BGD     a strip along the image border (3% of the longer side) outside the person,
  GC_PR_BGD  everywhere else.
The body prior only proposes: GrabCut's colour models decide where the person ends. */
Mat personSeed(const std::vector<Rect>& faces, const Work& w);

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv

#endif

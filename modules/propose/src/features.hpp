// The feature finders (private): what protectFeatures() protects inside a polygon. Faces
// first (a rounded box hugging each, with anchors), then the salient regions that pass the
// texture rule, each grown into a protective polygon nested in the polygon.
#ifndef MULTICAGE_PROPOSE_FEATURES_HPP
#define MULTICAGE_PROPOSE_FEATURES_HPP

#include "work.hpp"

namespace cv {
namespace multicage {
namespace propose_detail {

/** True when the face search runs for these parameters: a photo (not a mask or label input),
protect is not PROTECT_SALIENCY, and a cascade is installed (PROTECT_ALL goes on without one,
salient features only; PROTECT_FACES says why not). */
bool wantsFaces(const ProposeParams& params);

/** Faces already found in the image, and what findEyes() found in each (eyes[i] for
boxes[i]; a face past the end of `eyes` is searched when its polygon is placed). */
struct KnownFaces {
    std::vector<Rect> boxes;
    std::vector<std::vector<Rect>> eyes;
};

/** The input as 8-bit grey, input pixels: where eyes are searched. */
Mat grayOf(const Mat& img);

/** protectFeatures(): protective polygons for the features inside polygon `polygon` of
`cage`. `known`: the faces (and eyes) already found (nullptr: detect here). */
Multicage protectInPolygon(InputArray image, const Multicage& cage, int polygon,
                           const ProposeParams& params, const KnownFaces* known);

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv

#endif

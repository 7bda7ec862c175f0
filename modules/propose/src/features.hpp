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

/** protectFeatures(): protective polygons for the features inside polygon `polygon` of
`cage`. `knownFaces`: faces already detected in the image (nullptr: detect here). */
Multicage protectInPolygon(InputArray image, const Multicage& cage, int polygon,
                           const ProposeParams& params, const std::vector<Rect>* knownFaces);

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv

#endif

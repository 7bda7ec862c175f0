// The texture rule (private): which salient regions are features worth an inner polygon.
#ifndef MULTICAGE_PROPOSE_TEXTURE_HPP
#define MULTICAGE_PROPOSE_TEXTURE_HPP

#include "work.hpp"

namespace cv {
namespace multicage {
namespace propose_detail {

/** A feature's edge density against its object's and its surroundings', and its largest
share of the object (docs/propose/README.md, "The texture rule"). */
constexpr double kTextureRatio = 1.3;
constexpr double kFeatureShare = 0.1;

/** 1 on the Canny edges of the grey work copy of `img` (blurred by a pixel: JPEG noise and
film grain are not structure), 0 elsewhere, CV_32F: what texturedOnly measures. */
Mat textureEdges(const Mat& img, const Work& w);

/** `objects` (work pixels, 255 on salient regions) less the connected regions that are not
features of the polygon `inside` (work pixels, 255 where protection may go) of the image
whose textureEdges are `edges`:
a region stays when its edge density is at least kTextureRatio times the density of the
whole of `inside` (the object's own texture) and of a ring around the region (its
surroundings), and it covers at most kFeatureShare of `inside`. With plainSurroundings, the
ring must also be no denser than `inside` (a badge sits on plain cloth; a colour-distinct
region in a busy pattern is part of it). MULTICAGE_DEBUG_TEXTURE=1 prints each region's
measures. */
Mat texturedOnly(const Mat& objects, const Mat& edges, const Mat& inside,
                 bool plainSurroundings = false);

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv

#endif

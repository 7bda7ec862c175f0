// Colour-distinct regions (private): feature candidates saliency misses on a garment.
#ifndef MULTICAGE_PROPOSE_DISTINCT_HPP
#define MULTICAGE_PROPOSE_DISTINCT_HPP

#include "work.hpp"

namespace cv {
namespace multicage {
namespace propose_detail {

/** The least Lab distance (8-bit Lab) from the local median that makes a pixel distinct. */
constexpr double kDistinctFloor = 18.0;

/** Regions of `inside` (work pixels, 255 where protection may go) of the 8-bit image img8 that
differ in colour from their neighbourhood much more than is typical inside, of a feature's
shape, and alone of their kind (distinct.cpp): a badge, a name tag, a patch on cloth. Work
pixels, 255 on the regions. */
Mat distinctRegions(const Mat& img8, const Mat& inside, const Work& w);

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv

#endif

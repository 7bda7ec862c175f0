// Harmonic coordinates on the node grid (DeRose & Meyer 2006), private to the coords module.
#ifndef MULTICAGE_HARMONIC_HPP
#define MULTICAGE_HARMONIC_HPP

#include <opencv2/multicage/coordinates.hpp>

namespace cv {
namespace multicage {

/** bind() for coordinates == HARMONIC; the multicage has passed validateGeometry(). */
Binding bindHarmonic(const Multicage& multicage, int gridStep);

}  // namespace multicage
}  // namespace cv

#endif

// Keyframed poses over time (the paper's animation by moving multicage vertices).
#ifndef OPENCV2_MULTICAGE_ANIMATE_HPP
#define OPENCV2_MULTICAGE_ANIMATE_HPP

#include <opencv2/multicage/multicage.hpp>

namespace cv {
namespace multicage {

enum PoseInterpolation { INTERPOLATE_LINEAR = 0, INTERPOLATE_CATMULL_ROM = 1 };

}  // namespace multicage
}  // namespace cv

#endif

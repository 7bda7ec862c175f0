// Automatic multicage proposal from an image (the paper's §6 future work).
#ifndef OPENCV2_MULTICAGE_PROPOSE_HPP
#define OPENCV2_MULTICAGE_PROPOSE_HPP

#include <opencv2/multicage/multicage.hpp>

namespace cv {
namespace multicage {

struct CV_EXPORTS ProposeParams {
    int maxVertices = 80;  //!< total vertex budget over all polygons
};

/** Proposes a valid, oriented multicage enclosing the image's objects. */
CV_EXPORTS Multicage proposeMulticage(InputArray image, const ProposeParams& params = ProposeParams());

}  // namespace multicage
}  // namespace cv

#endif

#include <opencv2/multicage/propose.hpp>

namespace cv {
namespace multicage {

Multicage proposeMulticage(InputArray, const ProposeParams&) {
    CV_Error(Error::StsNotImplemented, "multicage: proposeMulticage is not implemented yet");
}

}  // namespace multicage
}  // namespace cv

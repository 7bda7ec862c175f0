#include "harmonic.hpp"

namespace cv {
namespace multicage {

Binding bindHarmonic(const Multicage&, int) {
    CV_Error(Error::StsNotImplemented, "multicage: harmonic coordinates are not available in this build yet");
}

}  // namespace multicage
}  // namespace cv

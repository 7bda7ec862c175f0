// bind() with a progress callback, and the "from the cage" coordinate rule.
#include "harmonic.hpp"

namespace cv {
namespace multicage {

int resolveCoordinates(const Multicage& multicage, int coordinates) {
    return coordinates == COORDINATES_FROM_CAGE ? multicage.coordinates() : coordinates;
}

Binding bind(const Multicage& multicage, int coordinates, int gridStep,
             const BindProgress& progress) {
    coordinates = resolveCoordinates(multicage, coordinates);
    if (!progress) return bind(multicage, coordinates, gridStep);
    if (coordinates == HARMONIC) {
        std::string why;  // as bind() checks it
        if (!multicage.validateGeometry(&why))
            CV_Error(Error::StsBadArg, "multicage: cannot bind: " + why);
        return bindHarmonic(multicage, gridStep, nullptr, progress);
    }
    // Mean value coordinates take tens of milliseconds per megapixel: start and end only.
    if (!progress(0.0))
        CV_Error(Error::StsError,
                 std::string("multicage: mean value coordinates: ") + kBindCancelled);
    Binding b = bind(multicage, coordinates, gridStep);
    progress(1.0);
    return b;
}

}  // namespace multicage
}  // namespace cv

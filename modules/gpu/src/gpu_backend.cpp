#include "gpu_backend.hpp"

namespace cv {
namespace multicage {
namespace gpu {

Ptr<Deformer> createDeformer(const Mat&, const Binding&, const DeformParams&, std::string* why) {
    if (why) *why = "this build of multicage has no GPU backend";
    return Ptr<Deformer>();
}

}  // namespace gpu
}  // namespace multicage
}  // namespace cv

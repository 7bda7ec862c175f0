// Mean value binding in a compute shader (private to the gpu module).
#ifndef MULTICAGE_GL_BINDING_HPP
#define MULTICAGE_GL_BINDING_HPP

#include <opencv2/multicage/packing.hpp>

#include "gl_util.hpp"

namespace cv {
namespace multicage {
namespace gpu {

/** Binds every node of binding->gridSize to multicage (Algorithm 1) into `texture`, an
immutable GL_TEXTURE_2D (or GL_TEXTURE_2D_ARRAY when layout.layers > 1) of layout's size
in RGBA32F or RGBA16F (half). Fills binding->minConditioning and worstNode; the
coefficients themselves stay on the GPU. Needs a current GL 4.3 context. */
void bindMeanValue(const Multicage& multicage, const PackLayout& layout, GLuint texture, bool half,
                   Binding* binding, double* shaderBuildMs = nullptr);

}  // namespace gpu
}  // namespace multicage
}  // namespace cv

#endif

// The input size an ONNX graph declares, read and rewritten in its protobuf bytes (private).
// OpenCV's importer folds every shape computation of the graph (U^2-Net-P's upsampling sizes)
// from the declared input, so a graph declared at another size runs at that size.
#ifndef MULTICAGE_PROPOSE_ONNX_INPUT_HPP
#define MULTICAGE_PROPOSE_ONNX_INPUT_HPP

#include <opencv2/core.hpp>
#include <vector>

namespace cv {
namespace multicage {
namespace propose_detail {

/** Width and height the first four-dimensional input of an ONNX model (NCHW) declares; an
empty Size where there is none, or where either is not a fixed number. */
Size onnxInputSize(const std::vector<uchar>& model);

/** Declares that input `size` instead, in place. Only where the new numbers take as many bytes
as the old (any of 128-16383 for the other), so that no length around them changes; returns
whether it did. */
bool setOnnxInputSize(std::vector<uchar>& model, Size size);

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv

#endif

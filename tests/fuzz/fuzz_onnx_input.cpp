// libFuzzer target: the walk over an ONNX file's protobuf bytes that reads and rewrites the
// declared input size (modules/propose/src/onnx_input.cpp), on bytes a user's model file may
// hold. Contract: never a crash or a read past the bytes; a rewrite changes no length, and the
// rewritten bytes declare the new size; bytes it refuses to rewrite stay as they were.
#include <cstdint>
#include <vector>

#include "fuzz_common.hpp"
#include "onnx_input.hpp"

using cv::multicage::propose_detail::onnxInputSize;
using cv::multicage::propose_detail::setOnnxInputSize;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::vector<uchar> bytes(data, data + size);
    (void)onnxInputSize(bytes);
    std::vector<uchar> copy = bytes;
    const cv::Size wanted(256, 200);
    if (setOnnxInputSize(copy, wanted)) {
        if (copy.size() != bytes.size())
            multicage_fuzz::finding("fuzz_onnx_input", "length changed");
        if (onnxInputSize(copy) != wanted)
            multicage_fuzz::finding("fuzz_onnx_input", "the rewritten bytes declare another size");
    } else if (copy != bytes) {
        multicage_fuzz::finding("fuzz_onnx_input", "refused, yet the bytes changed");
    }
    return 0;
}

// A walk over the protobuf wire format, just deep enough to reach the graph's input shapes:
// ModelProto.graph (7) -> GraphProto.input (11) -> ValueInfoProto.type (2) ->
// TypeProto.tensor_type (1) -> shape (2) -> dim (1) -> dim_value (1).
#include "onnx_input.hpp"

#include <cstdint>

namespace cv {
namespace multicage {
namespace propose_detail {

namespace {

struct Span {
    const uchar* begin = nullptr;
    const uchar* end = nullptr;
};

bool varint(const uchar*& p, const uchar* end, uint64_t& value) {
    value = 0;
    for (int shift = 0; shift < 64 && p < end; shift += 7) {
        const uchar b = *p++;
        value |= static_cast<uint64_t>(b & 0x7f) << shift;
        if (!(b & 0x80)) return true;
    }
    return false;
}

// The fields numbered `field` of the message in `in`, in order: their values' bytes (for a
// varint its encoding, for a length-delimited field its content). Empty on malformed bytes.
std::vector<Span> fields(Span in, int field, int wireType) {
    std::vector<Span> out;
    const uchar* p = in.begin;
    while (p < in.end) {
        uint64_t key = 0, n = 0;
        if (!varint(p, in.end, key)) return {};
        const uchar* value = p;
        switch (key & 7) {
            case 0:
                if (!varint(p, in.end, n)) return {};
                break;
            case 1:
                if (in.end - p < 8) return {};
                p += 8;
                break;
            case 2:
                if (!varint(p, in.end, n) || n > static_cast<uint64_t>(in.end - p)) return {};
                value = p;
                p += n;
                break;
            case 5:
                if (in.end - p < 4) return {};
                p += 4;
                break;
            default:
                return {};
        }
        if (static_cast<int>(key >> 3) == field && static_cast<int>(key & 7) == wireType)
            out.push_back({value, p});
    }
    return out;
}

// The dim_value encodings of the first input with four dimensions, all fixed.
std::vector<Span> inputDims(const std::vector<uchar>& model) {
    const Span whole{model.data(), model.data() + model.size()};
    for (const Span& graph : fields(whole, 7, 2))
        for (const Span& input : fields(graph, 11, 2))
            for (const Span& type : fields(input, 2, 2))
                for (const Span& tensor : fields(type, 1, 2))
                    for (const Span& shape : fields(tensor, 2, 2)) {
                        const std::vector<Span> all = fields(shape, 1, 2);
                        if (all.size() != 4) continue;
                        std::vector<Span> dims;
                        for (const Span& dim : all) {
                            const std::vector<Span> v = fields(dim, 1, 0);
                            if (v.size() == 1) dims.push_back(v[0]);
                        }
                        return dims.size() == 4 ? dims : std::vector<Span>();
                    }
    return {};
}

int valueOf(Span s) {
    uint64_t v = 0;
    const uchar* p = s.begin;
    return varint(p, s.end, v) && v > 0 && v < (1u << 20) ? static_cast<int>(v) : 0;
}

}  // namespace

Size onnxInputSize(const std::vector<uchar>& model) {
    const std::vector<Span> dims = inputDims(model);
    if (dims.empty()) return Size();
    const Size size(valueOf(dims[3]), valueOf(dims[2]));
    return size.width > 0 && size.height > 0 ? size : Size();
}

bool setOnnxInputSize(std::vector<uchar>& model, Size size) {
    const std::vector<Span> dims = inputDims(model);
    if (dims.empty() || size.width < 128 || size.height < 128 || size.width >= 16384 ||
        size.height >= 16384)
        return false;
    const Span h = dims[2], w = dims[3];
    if (h.end - h.begin != 2 || w.end - w.begin != 2) return false;  // values 128-16383
    for (const auto& [span, value] :
         {std::make_pair(h, size.height), std::make_pair(w, size.width)}) {
        uchar* p = model.data() + (span.begin - model.data());
        p[0] = static_cast<uchar>(0x80 | (value & 0x7f));
        p[1] = static_cast<uchar>(value >> 7);
    }
    return true;
}

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv

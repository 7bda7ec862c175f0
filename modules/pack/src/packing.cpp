// Paper §4, Eq. 6-7: the block layout of the packed coefficient texture, and packing itself.
#include <cmath>
#include <opencv2/core/utility.hpp>
#include <opencv2/multicage/packing.hpp>

namespace cv {
namespace multicage {

Point PackLayout::texel(int b, int x, int y, int* layer) const {
    const int perLayer = blocksPerLayer(), slot = b % perLayer;
    if (layer) *layer = b / perLayer;
    return Point(x + (slot % cols) * blockSize.width, y + (slot / cols) * blockSize.height);
}

PackLayout paperPackLayout(Size gridSize, int coefficientCount) {
    CV_Assert(gridSize.width > 0 && gridSize.height > 0 && coefficientCount > 0);
    const bool portrait = gridSize.width < gridSize.height;
    const int m = portrait ? gridSize.height : gridSize.width;  // the long side
    const int n = portrait ? gridSize.width : gridSize.height;
    PackLayout layout;
    layout.blockSize = gridSize;
    layout.blocks = (coefficientCount + 3) / 4;
    // Eq. 6; Eq. 7 as printed reads ceil(B / sqrt(...)), but only ceil(B / cols) matches Fig. 6.
    const int along = static_cast<int>(std::ceil(std::sqrt(double(layout.blocks) * (m / n))));
    const int across = (layout.blocks + along - 1) / along;
    // Blocks run along the long side; a portrait grid gets the transposed block grid.
    layout.cols = portrait ? across : along;
    layout.rows = portrait ? along : across;
    layout.textureSize = Size(layout.cols * gridSize.width, layout.rows * gridSize.height);
    return layout;
}

PackLayout choosePackLayout(Size gridSize, int coefficientCount, int maxTextureSize,
                            int maxLayers) {
    PackLayout paper = paperPackLayout(gridSize, coefficientCount);
    if (paper.textureSize.width <= maxTextureSize && paper.textureSize.height <= maxTextureSize)
        return paper;
    if (gridSize.width > maxTextureSize || gridSize.height > maxTextureSize)
        CV_Error_(Error::StsOutOfRange,
                  ("multicage: the node grid %dx%d is larger than the texture limit %d; use a "
                   "larger gridStep",
                   gridSize.width, gridSize.height, maxTextureSize));
    if (paper.blocks > maxLayers)
        CV_Error_(Error::StsOutOfRange,
                  ("multicage: %d coefficient blocks need more than the %d texture array layers",
                   paper.blocks, maxLayers));
    // One block per layer: no empty blocks, and each layer is only as large as the node grid.
    PackLayout layered = paper;
    layered.cols = layered.rows = 1;
    layered.textureSize = gridSize;
    layered.layers = paper.blocks;
    return layered;
}

static void checkLayout(const PackLayout& layout, Size gridSize, int c) {
    if (layout.blockSize != gridSize || layout.blocks != (c + 3) / 4 || layout.layers < 1 ||
        layout.blocksPerLayer() * layout.layers < layout.blocks)
        CV_Error_(Error::StsBadArg,
                  ("multicage: pack layout (%d blocks of %dx%d) does not fit a %dx%d grid with %d "
                   "coefficients",
                   layout.blocks, layout.blockSize.width, layout.blockSize.height, gridSize.width,
                   gridSize.height, c));
}

void packCoefficients(const Binding& binding, const PackLayout& layout, OutputArray packedOut,
                      int depth) {
    CV_Assert(!binding.empty() && binding.coefficients.type() == CV_32F);
    CV_Assert(depth == CV_32F || depth == CV_16F);
    const int c = binding.coefficientCount(), m = binding.gridSize.width,
              n = binding.gridSize.height;
    checkLayout(layout, binding.gridSize, c);
    const Size full(layout.textureSize.width, layout.textureSize.height * layout.layers);
    // A caller's buffer of the right size and type (a mapped pixel buffer) is written in place.
    packedOut.create(full, CV_MAKETYPE(depth, 4));
    Mat packed = packedOut.getMat();
    // Every texel row is written once, in parallel, so nothing is cleared first: empty blocks
    // and the channels past coefficient c get zeros on the way. Half floats are converted a
    // row at a time from a float row (OpenCV's vectorised conversion).
    const int blockRows = layout.rows * layout.layers;
    parallel_for_(Range(0, blockRows * n), [&](const Range& r) {
        std::vector<Vec4f> row(depth == CV_16F ? m : 0);
        for (int i = r.start; i < r.end; ++i) {
            const int blockRow = i / n, y = i % n;
            const int layer = blockRow / layout.rows, texY = (blockRow % layout.rows) * n + y;
            uchar* line = packed.ptr(texY + layer * layout.textureSize.height);
            for (int col = 0; col < layout.cols; ++col) {
                const int b =
                    layer * layout.blocksPerLayer() + (blockRow % layout.rows) * layout.cols + col;
                Vec4f* dst =
                    depth == CV_32F ? reinterpret_cast<Vec4f*>(line) + col * m : row.data();
                const int channels = b < layout.blocks ? std::min(4, c - 4 * b) : 0;
                const float* src[4] = {};
                for (int ch = 0; ch < channels; ++ch)
                    src[ch] = binding.coefficients.ptr<float>(4 * b + ch) + size_t(y) * m;
                switch (channels) {  // one loop per channel count keeps each one vectorisable
                    case 4:
                        for (int x = 0; x < m; ++x)
                            dst[x] = Vec4f(src[0][x], src[1][x], src[2][x], src[3][x]);
                        break;
                    case 3:
                        for (int x = 0; x < m; ++x)
                            dst[x] = Vec4f(src[0][x], src[1][x], src[2][x], 0.f);
                        break;
                    case 2:
                        for (int x = 0; x < m; ++x) dst[x] = Vec4f(src[0][x], src[1][x], 0.f, 0.f);
                        break;
                    case 1:
                        for (int x = 0; x < m; ++x) dst[x] = Vec4f(src[0][x], 0.f, 0.f, 0.f);
                        break;
                    default:
                        std::fill(dst, dst + m, Vec4f::all(0.f));
                }
                if (depth == CV_16F) {
                    Mat halfRow(1, 4 * m, CV_16F, line + size_t(col) * m * 4 * sizeof(float16_t));
                    Mat(1, 4 * m, CV_32F, row.data()).convertTo(halfRow, CV_16F);
                }
            }
        }
    });
}

void unpackCoefficients(InputArray packedIn, const PackLayout& layout, int c, OutputArray out) {
    Mat packed = packedIn.getMat();
    CV_Assert(packed.channels() == 4 && (packed.depth() == CV_32F || packed.depth() == CV_16F));
    if (packed.depth() == CV_16F) packed.convertTo(packed, CV_32F);
    checkLayout(layout, layout.blockSize, c);
    CV_Assert(packed.cols == layout.textureSize.width &&
              packed.rows == layout.textureSize.height * layout.layers);
    const int m = layout.blockSize.width, n = layout.blockSize.height;
    out.create(c, m * n, CV_32F);
    Mat coefficients = out.getMat();
    for (int b = 0; b < layout.blocks; ++b)
        for (int y = 0; y < n; ++y) {
            int layer;
            const Point t0 = layout.texel(b, 0, y, &layer);
            const Vec4f* src = packed.ptr<Vec4f>(t0.y + layer * layout.textureSize.height) + t0.x;
            for (int ch = 0; ch < std::min(4, c - 4 * b); ++ch) {
                float* dst = coefficients.ptr<float>(4 * b + ch) + size_t(y) * m;
                for (int x = 0; x < m; ++x) dst[x] = src[x][ch];
            }
        }
}

}  // namespace multicage
}  // namespace cv

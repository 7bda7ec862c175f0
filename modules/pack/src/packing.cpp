// Paper §4, Eq. 6-7: the block layout of the packed coefficient texture.
#include <opencv2/multicage/packing.hpp>

#include <cmath>

namespace cv {
namespace multicage {

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

}  // namespace multicage
}  // namespace cv

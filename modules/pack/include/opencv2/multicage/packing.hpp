/** @file
@brief Packing cage coordinates into one RGBA texture (paper §4, Eq. 6-7, Fig. 6).
@ingroup multicage_pack
*/
#ifndef OPENCV2_MULTICAGE_PACKING_HPP
#define OPENCV2_MULTICAGE_PACKING_HPP

#include <opencv2/multicage/coordinates.hpp>

namespace cv {
namespace multicage {

//! @addtogroup multicage_pack
//! @{

/** @brief Where each coefficient of each node lives in the packed texture.

B = ceil(c/4) blocks, each the size of the node grid (blockSize), on a cols x rows block
grid; coefficients 4b..4b+3 of node (x, y) are the R, G, B, A of texel
(x + (b mod cols)*m, y + (b div cols)*n). Unused channels and blocks are 0.

When layers > 1 the texture is a 2D texture array of `layers` layers of textureSize each
(the fallback for layouts larger than GL_MAX_TEXTURE_SIZE): block b sits in layer
b div (cols*rows), at block position (b mod (cols*rows)) within it, as above.
@sa paperPackLayout, choosePackLayout, packCoefficients
*/
struct CV_EXPORTS PackLayout {
    Size blockSize;    //!< the node grid, m x n
    int blocks = 0;    //!< B = ceil(c / 4)
    int cols = 0;      //!< blocks per texture row
    int rows = 0;      //!< block rows
    Size textureSize;  //!< cols*m x rows*n (of one layer)
    int layers = 1;    //!< 1: the paper's single texture; > 1: a texture array

    /** @brief Blocks in one layer.
    @return cols * rows. */
    int blocksPerLayer() const { return cols * rows; }
    /** @brief Texel of block b's node (x, y).
    @param b block index, 0 <= b < blocks (coefficients 4b..4b+3).
    @param x node column, 0 <= x < blockSize.width.
    @param y node row, 0 <= y < blockSize.height.
    @param[out] layer when not null, receives the layer of the texture array.
    @return the texel within that layer. */
    Point texel(int b, int x, int y, int* layer) const;
};

/** @brief The paper's layout (Eq. 6-7).

With m >= n, `cols = ceil(sqrt(B * floor(m/n)))` (Eq. 6) and `rows = ceil(B / cols)` (Eq. 7
as printed reads ceil(B / sqrt(...)); only ceil(B / cols) matches the paper's Fig. 6); a
portrait grid (m < n) swaps the roles of m and n and then of the texture's width and height.
@param gridSize the node grid (Binding::gridSize), not empty.
@param coefficientCount coefficients per node, > 0, the 4 frame corners included.
@return a single-texture layout (layers = 1).
*/
CV_EXPORTS PackLayout paperPackLayout(Size gridSize, int coefficientCount);

/** @brief The paper's layout when its texture fits in maxTextureSize x maxTextureSize, else one
block per layer of a 2D texture array (so the vertex count is limited only by maxLayers and
memory).
@param gridSize the node grid (Binding::gridSize).
@param coefficientCount coefficients per node, the 4 frame corners included.
@param maxTextureSize the largest texture side (GL_MAX_TEXTURE_SIZE).
@param maxLayers the most layers of a texture array (GL_MAX_ARRAY_TEXTURE_LAYERS).
@return paperPackLayout() or the layered fallback.
@throws cv::Exception (StsOutOfRange) when even one block (the node grid) is larger than
maxTextureSize or more than maxLayers layers would be needed: use a larger grid step.
*/
CV_EXPORTS PackLayout choosePackLayout(Size gridSize, int coefficientCount, int maxTextureSize,
                                       int maxLayers = 2048);

/** @brief Packs a binding's planar coefficients into the texture described by layout.
@param binding a non-empty binding; its gridSize must equal layout.blockSize and
ceil(c/4) == layout.blocks (else cv::Exception, StsBadArg).
@param layout from paperPackLayout() or choosePackLayout().
@param[out] packed textureSize.width x (textureSize.height * layers), 4 channels of depth:
the layers stacked top to bottom, exactly the memory glTexImage2D/3D wants.
@param depth CV_32F (RGBA32F, bit-exact) or CV_16F (RGBA16F, rounded to nearest).
@sa unpackCoefficients
*/
CV_EXPORTS void packCoefficients(const Binding& binding, const PackLayout& layout,
                                 OutputArray packed, int depth = CV_32F);

/** @brief The inverse of packCoefficients. For CV_32F input the round trip is bit for bit.
@param packed what packCoefficients() writes: 4 channels, CV_32F or CV_16F.
@param layout the layout it was packed with.
@param coefficientCount c, coefficients per node.
@param[out] coefficients c x nodeCount CV_32F (planar, as in Binding::coefficients).
*/
CV_EXPORTS void unpackCoefficients(InputArray packed, const PackLayout& layout,
                                   int coefficientCount, OutputArray coefficients);

//! @} multicage_pack

}  // namespace multicage
}  // namespace cv

#endif

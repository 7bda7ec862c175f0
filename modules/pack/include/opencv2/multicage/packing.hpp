// Packing cage coordinates into one RGBA texture (paper §4, Eq. 6-7, Fig. 6).
#ifndef OPENCV2_MULTICAGE_PACKING_HPP
#define OPENCV2_MULTICAGE_PACKING_HPP

#include <opencv2/multicage/coordinates.hpp>

namespace cv {
namespace multicage {

/** Where each coefficient of each node lives in the packed texture.

B = ceil(c/4) blocks, each the size of the node grid (blockSize), on a cols x rows block
grid; coefficients 4b..4b+3 of node (x, y) are the R, G, B, A of texel
(x + (b mod cols)*m, y + (b div cols)*n). Unused channels and blocks are 0.

When layers > 1 the texture is a 2D texture array of `layers` layers of textureSize each
(the fallback for layouts larger than GL_MAX_TEXTURE_SIZE): block b sits in layer
b div (cols*rows), at block position (b mod (cols*rows)) within it, as above. */
struct CV_EXPORTS PackLayout {
    Size blockSize;    //!< the node grid, m x n
    int blocks = 0;    //!< B = ceil(c / 4)
    int cols = 0;      //!< blocks per texture row
    int rows = 0;      //!< block rows
    Size textureSize;  //!< cols*m x rows*n (of one layer)
    int layers = 1;    //!< 1: the paper's single texture; > 1: a texture array

    int blocksPerLayer() const { return cols * rows; }
    /** Texel of block b's node (x, y) in layer *layer. */
    Point texel(int b, int x, int y, int* layer) const;
};

/** The paper's layout (Eq. 6-7): with m >= n, cols = ceil(sqrt(B * floor(m/n))),
rows = ceil(B / cols); a portrait grid (m < n) swaps the roles of m and n and then of the
texture's width and height. coefficientCount includes the 4 frame corners. */
CV_EXPORTS PackLayout paperPackLayout(Size gridSize, int coefficientCount);

/** The paper's layout when its texture fits in maxTextureSize x maxTextureSize, else one
block per layer of a 2D texture array (so the vertex count is limited only by maxLayers
and memory). Throws a cv::Exception when even one block (the node grid) is larger than
maxTextureSize or more than maxLayers layers would be needed: use a larger grid step. */
CV_EXPORTS PackLayout choosePackLayout(Size gridSize, int coefficientCount, int maxTextureSize,
                                       int maxLayers = 2048);

/** Packs a binding's planar coefficients into the texture described by layout.

Inputs:
  binding  its gridSize must equal layout.blockSize and ceil(c/4) == layout.blocks
  depth    CV_32F (RGBA32F, bit-exact) or CV_16F (RGBA16F, rounded to nearest)
Outputs:
  packed   textureSize.width x (textureSize.height * layers), 4 channels of depth: the
           layers stacked top to bottom, exactly the memory glTexImage2D/3D wants. */
CV_EXPORTS void packCoefficients(const Binding& binding, const PackLayout& layout,
                                 OutputArray packed, int depth = CV_32F);

/** The inverse of packCoefficients: coefficients as c x nodeCount CV_32F (planar, as in
Binding::coefficients). For CV_32F input the round trip is bit for bit. */
CV_EXPORTS void unpackCoefficients(InputArray packed, const PackLayout& layout,
                                   int coefficientCount, OutputArray coefficients);

}  // namespace multicage
}  // namespace cv

#endif

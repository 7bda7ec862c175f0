// Packing cage coordinates into one RGBA texture (paper §4, Eq. 6-7, Fig. 6).
#ifndef OPENCV2_MULTICAGE_PACKING_HPP
#define OPENCV2_MULTICAGE_PACKING_HPP

#include <opencv2/multicage/coordinates.hpp>

namespace cv {
namespace multicage {

/** Where each coefficient of each node lives in the packed texture.

B = ceil(c/4) blocks, each the size of the node grid (blockSize), on a cols x rows block
grid; coefficients 4b..4b+3 of node (x, y) are the R, G, B, A of texel
(x + (b mod cols)*m, y + (b div cols)*n). Unused channels and blocks are 0. */
struct CV_EXPORTS PackLayout {
    Size blockSize;    //!< the node grid, m x n
    int blocks = 0;    //!< B = ceil(c / 4)
    int cols = 0;      //!< blocks per texture row
    int rows = 0;      //!< block rows
    Size textureSize;  //!< cols*m x rows*n
};

/** The paper's layout (Eq. 6-7): with m >= n, cols = ceil(sqrt(B * floor(m/n))),
rows = ceil(B / cols); a portrait grid (m < n) swaps the roles of m and n and then of the
texture's width and height. coefficientCount includes the 4 frame corners. */
CV_EXPORTS PackLayout paperPackLayout(Size gridSize, int coefficientCount);

}  // namespace multicage
}  // namespace cv

#endif

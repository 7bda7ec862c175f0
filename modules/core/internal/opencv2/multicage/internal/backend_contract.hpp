// What the CPU backend (modules/deform) and the GPU backend and binding (modules/gpu) must
// agree on to draw the same pictures from the same binding. One definition each, here; the
// shaders restate the mesh rules in GLSL (mesh_grid.glsl, mesh_positions.glsl), and the
// GpuCompute tests check that both backends give bit-identical maps.
#ifndef MULTICAGE_INTERNAL_BACKEND_CONTRACT_HPP
#define MULTICAGE_INTERNAL_BACKEND_CONTRACT_HPP

#include <array>
#include <cmath>
#include <opencv2/multicage/multicage.hpp>

namespace cv {
namespace multicage {

/** The inverse-map value of an output pixel no deformed triangle covers: far outside any
image, so cv::remap (and the GPU gather) gives the border value there. */
constexpr float kUncovered = -1e4f;

/** The image frame of a size, corners in the order the frame's 4 coefficients use: TL, TR,
BR, BL. Pixel centres are integers, so the frame runs half a pixel outside them. */
inline std::array<Point2f, 4> frameCorners(Size imageSize) {
    const float r = imageSize.width - 0.5f, b = imageSize.height - 0.5f;
    return {{{-0.5f, -0.5f}, {r, -0.5f}, {r, b}, {-0.5f, b}}};
}

/** The size of the image a pose renders into: the size whose frame the pose's 4 frame corners
(TL, TR, BR, BL, as frameCorners) lie on, within 1e-3 px, when they lie on one (content-aware
resizing: a pose with its frame on another size's frame renders an image of that size);
otherwise imageSize (a frame moved any other way is deformed into the input's size, as always).
One rule for the CPU and GPU backends and for transformPoints. */
inline Size frameOutputSize(const Point2f* corners, Size imageSize) {
    constexpr float tol = 1e-3f;
    auto near = [](float a, float b) { return std::abs(a - b) <= tol; };
    const float right = corners[1].x + 0.5f, bottom = corners[3].y + 0.5f;
    const int w = cvRound(right), h = cvRound(bottom);
    const bool onFrame = near(corners[0].x, -0.5f) && near(corners[0].y, -0.5f) &&
                         near(corners[1].y, -0.5f) && near(corners[3].x, -0.5f) &&
                         near(corners[2].x, corners[1].x) && near(corners[2].y, corners[3].y) &&
                         near(right, float(w)) && near(bottom, float(h));
    return onFrame && w >= 1 && h >= 1 ? Size(w, h) : imageSize;
}

/** The mesh's triangles. A cell's corners are a = (x, y), b = (x+1, y), c = (x, y+1),
d = (x+1, y+1) of the node grid ringed by the frame; each cell is (a, b, c) then (b, d, c),
cells in row-major order, and where triangles overlap (a fold-over) the later one wins. As
(dx, dy) offsets from a. */
constexpr int kCellTriangles[2][3][2] = {{{0, 0}, {1, 0}, {0, 1}}, {{1, 0}, {1, 1}, {0, 1}}};

/** The orientation rule (paper §3.1): a polygon at even depth runs counter-clockwise in the
y-down image (positive signed area), one at odd depth clockwise. */
inline bool wantsPositiveArea(int depth) {
    return depth % 2 == 0;
}

/** +1 when polygon p of the multicage obeys the orientation rule, -1 when it runs the other
way: the sign its raw mean value weights are multiplied by, on the CPU and the GPU. */
inline int orientationSign(const Multicage& multicage, int p) {
    return (multicage.signedArea(p) > 0) == wantsPositiveArea(multicage.depth(p)) ? 1 : -1;
}

/** Throws a cv::Exception unless type is CV_8U, CV_16U or CV_32F with 1, 3 or 4 channels: the
images both backends deform. */
void checkImageType(int type);
/** The same, and that the image is non-empty and 2-dimensional. */
void checkImage(InputArray image);

}  // namespace multicage
}  // namespace cv

#endif

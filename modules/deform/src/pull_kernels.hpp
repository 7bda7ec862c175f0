// The pull's kernels (private): pullRows and positiveRows of mesh_pull.hpp in AVX-512
// (pull_avx512.cpp, 16 pixels per vector) and AVX2 (pull_avx2.cpp, 8), and what they share:
// the walk's tolerances, the frame, the guesses of the next row. mesh_pull.cpp picks one by the
// CPU's level (internal/cpu_dispatch.hpp).
#ifndef MULTICAGE_PULL_KERNELS_HPP
#define MULTICAGE_PULL_KERNELS_HPP

// A file that includes this includes raster_options.hpp first, before any other header.
#include <cmath>
#include <utility>
#include <vector>

#include "mesh_pull.hpp"

namespace cv {
namespace multicage {
namespace raster {

// A triangle is pullable when cross(e1, e2) exceeds this part of |e1.x e2.y| + |e1.y e2.x|: its
// angles are not within 1e-4 rad of 0 or pi, so the float barycentrics of the walk hold 3 digits
// more than the edge tolerance needs.
constexpr float kSliver = 1e-4f;
constexpr int kMaxSteps = 12;          // then the band is drawn by the raster kernel
constexpr float kEdge = 1e-6f;         // barycentric tolerance: shared edges leave no crack
constexpr float kFrameMargin = 2e-3f;  // px: nearer the frame than this, the raster decides

/** The frame's edges as lines n.p + c (n a unit normal pointing inside): signed distances. */
struct FrameLines {
    float nx[4], ny[4], c[4];
};
/** The frame (the ring's outer boundary) of a mesh as lines (mesh_pull.cpp). */
FrameLines frameLines(const PullMesh& m);

/** Where each pixel of the two rows above ended, in cell coordinates (cell + barycentric): the
guesses of the next row. Each row is padded by `pad` floats, since a row's last vectors read and
write whole vectors. One buffer per thread, kept between calls. */
struct Estimates {
    float *e1x, *e1y;  // the row above
    float *e2x, *e2y;  // the row above that; this row's estimates overwrite it
    Estimates(int width, int pad) {
        thread_local std::vector<float> store;
        const size_t row = size_t(width) + size_t(pad);
        store.resize(4 * row);
        e1x = store.data(), e1y = e1x + row, e2x = e1y + row, e2y = e2x + row;
    }
    /** This row's estimates become the row above. */
    void nextRow() { std::swap(e1x, e2x), std::swap(e1y, e2y); }
};

/** The first guess of rows that start a run (kPullRun): nodes 1..cols-2 rest on pixels 0..W-1 of
a frame at rest, so pixel x of row y guesses cell coordinates (1 + x sx, 1 + y sy). */
struct FirstGuess {
    float sx, sy;
    FirstGuess(const PullMesh& m, Size maps)
        : sx(maps.width > 1 ? float(m.cols - 3) / float(maps.width - 1) : 0.f),
          sy(maps.height > 1 ? float(m.rows - 3) / float(maps.height - 1) : 0.f) {}
};

// Internal linkage on purpose, as raster_kernels.hpp's helpers: each kernel's file compiles and
// inlines its own copy.
namespace {

// Whether cross(e1, e2) is clearly positive (kSliver): the float operations of the kernels' lanes.
inline bool clearlyPositive(float e1x, float e1y, float e2x, float e2y) {
    const float l = e1x * e2y, r = e1y * e2x;
    return l - r > kSliver * (std::abs(l) + std::abs(r));
}

// Whether both triangles of cells [k0, k1) of node rows p0, p1 (kCellTriangles: (a,b,c) and
// (b,d,c)) are clearly positive.
inline bool cellsPositive(const Point2f* p0, const Point2f* p1, int k0, int k1) {
    bool good = true;
    for (int k = k0; k < k1; ++k) {
        const Point2f a = p0[k], b = p0[k + 1], c = p1[k], d = p1[k + 1];
        good &= clearlyPositive(b.x - a.x, b.y - a.y, c.x - a.x, c.y - a.y);
        good &= clearlyPositive(d.x - b.x, d.y - b.y, c.x - b.x, c.y - b.y);
    }
    return good;
}

}  // namespace

/** Whether this build has the kernel (GCC or clang on x86-64); the caller asks the CPU. */
bool haveAvx512Pull();
bool haveAvx2Pull();
/** pullRows and positiveRows, 16 pixels (AVX-512) or 8 (AVX2) per vector. */
bool pullRowsAvx512(const PullMesh& m, int y0, int y1, Mat& mapx, Mat& mapy);
bool positiveRowsAvx512(const PullMesh& m, int ey0, int ey1);
bool pullRowsAvx2(const PullMesh& m, int y0, int y1, Mat& mapx, Mat& mapy);
bool positiveRowsAvx2(const PullMesh& m, int ey0, int ey1);

}  // namespace raster
}  // namespace multicage
}  // namespace cv

#endif

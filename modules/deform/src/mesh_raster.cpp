// Rasterising the deformed node mesh into inverse maps (the CPU backend's "draw call").

// First, before any other header (clang-format would sort it among them): the rasteriser's
// floating-point options.
// clang-format off
#include "raster_options.hpp"
// clang-format on

#include <algorithm>
#include <atomic>
#include <climits>
#include <cmath>
#include <memory>
#include <mutex>
#include <opencv2/core/utility.hpp>
#include <opencv2/multicage/deformer.hpp>
#include <opencv2/multicage/internal/apply_rows.hpp>
#include <opencv2/multicage/internal/cpu_dispatch.hpp>

#include "cpu_deformer.hpp"
#include "mesh_lattice.hpp"
#include "mesh_pull.hpp"
#include "raster_kernels.hpp"
#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace cv {
namespace multicage {

template <typename RestNode>
void RasterMesh::resetWith(Size grid, Size outputSize, bool separable, RestNode&& rest) {
    CV_Assert(grid.width >= 2 && grid.height >= 2 && outputSize.area() > 0);
    const int m = grid.width, n = grid.height;
    rest_ = out_ = outputSize;
    gridStep_ = 0;
    pullable_ = Pullable::unknown;
    lo_ = rest(0, 0), hi_ = rest(m - 1, n - 1);
    owners_.clear();
    P_ = hugePageMat(Size(m + 2, n + 2), CV_32FC2, owners_);
    // Touched here, once: a first pose does not pay for the page faults of a fresh buffer.
    P_.setTo(Scalar::all(0));
    // Rest mesh: interior the rest nodes, ring the nearest one. A regular grid needs only its
    // column x and row y (the rows are made when drawn); any other rest mesh is stored whole.
    restX_.assign(m + 2, 0.f), restY_.assign(n + 2, 0.f);
    R_.release();
    if (separable) {
        for (int ex = 0; ex < m + 2; ++ex)
            restX_[ex] = rest(std::min(std::max(ex - 1, 0), m - 1), 0).x;
        for (int ey = 0; ey < n + 2; ++ey)
            restY_[ey] = rest(0, std::min(std::max(ey - 1, 0), n - 1)).y;
    } else {
        R_ = hugePageMat(Size(m + 2, n + 2), CV_32FC2, owners_);
        for (int ey = 0; ey < n + 2; ++ey) {
            Point2f* row = R_.ptr<Point2f>(ey);
            const int gy = std::min(std::max(ey - 1, 0), n - 1);
            for (int ex = 0; ex < m + 2; ++ex)
                row[ex] = rest(std::min(std::max(ex - 1, 0), m - 1), gy);
        }
    }
    rowMin_.resize(n + 1), rowMax_.resize(n + 1);
}

const Point2f* RasterMesh::restRow(int ey, std::vector<Point2f>& buffer) const {
    if (!R_.empty()) return R_.ptr<Point2f>(ey);
    buffer.resize(restX_.size());
    const float y = restY_[ey];
    for (size_t ex = 0; ex < restX_.size(); ++ex) buffer[ex] = Point2f(restX_[ex], y);
    return buffer.data();
}

void RasterMesh::reset(const Mat& rest, Size outputSize) {
    CV_Assert(rest.type() == CV_32FC2 && rest.rows >= 2 && rest.cols >= 2);
    resetWith(rest.size(), outputSize, false,
              [&](int gx, int gy) { return rest.at<Point2f>(gy, gx); });
}

void RasterMesh::reset(const Binding& binding) {
    // Node (gx, gy) rests at (x of column gx, y of row gy): two short tables instead of the
    // whole node grid.
    std::vector<float> xs(binding.gridSize.width), ys(binding.gridSize.height);
    for (int gx = 0; gx < binding.gridSize.width; ++gx) xs[gx] = binding.node(gx, 0).x;
    for (int gy = 0; gy < binding.gridSize.height; ++gy) ys[gy] = binding.node(0, gy).y;
    resetWith(binding.gridSize, binding.imageSize, true,
              [&](int gx, int gy) { return Point2f(xs[gx], ys[gy]); });
    gridStep_ = binding.gridStep;
}

template <typename F>
void RasterMesh::forEachRingNode(F&& f) const {
    const int m = P_.cols - 2, n = P_.rows - 2;
    for (int ex = 0; ex < m + 2; ++ex) f(ex, 0);
    for (int ey = 1; ey < n + 1; ++ey) f(0, ey), f(m + 1, ey);
    for (int ex = 0; ex < m + 2; ++ex) f(ex, n + 1);
}

void RasterMesh::setFrame(const Point2f* frame) {
    pullable_ = Pullable::unknown;
    // The mesh gets a ring of nodes on the image frame, around the node grid (whose outer nodes
    // sit on the border pixel centres, half a pixel inside the frame). A ring node follows the
    // frame as mean value coordinates do on a polygon edge (the frame corners interpolated
    // linearly) and samples the border pixel next to it. So the half-pixel band between the
    // frame and the border nodes is always covered: when border nodes move inwards the border
    // pixels stretch instead of leaving a line of border colour. deform.vert builds the same ring.
    const float W = static_cast<float>(rest_.width), H = static_cast<float>(rest_.height);
    std::array<Point2f, 4> corners = frameCorners(rest_);
    if (frame) std::copy(frame, frame + 4, corners.begin());
    const int m = P_.cols - 2, n = P_.rows - 2;
    forEachRingNode([&](int ex, int ey) {
        const Point2f source =
            R_.empty() ? Point2f(restX_[ex], restY_[ey]) : R_.at<Point2f>(ey, ex);
        const float rx = ex == 0 ? -0.5f : ex == m + 1 ? W - 0.5f : source.x;
        const float ry = ey == 0 ? -0.5f : ey == n + 1 ? H - 0.5f : source.y;
        const float u = (rx + 0.5f) / W, v = (ry + 0.5f) / H;
        P_.at<Point2f>(ey, ex) = (1 - u) * (1 - v) * corners[0] + u * (1 - v) * corners[1] +
                                 u * v * corners[2] + (1 - u) * v * corners[3];
    });
}

void RasterMesh::setOutputSize(Size outputSize) {
    CV_Assert(outputSize.area() > 0);
    out_ = outputSize;
}

// Vertical extent of each row of cells, so that a band of output rows skips whole cell rows:
// each node row's extent first (in parallel), then pairs of rows.
void RasterMesh::findRowExtents() {
    const Mat& P = P_;
    std::vector<float> nodeMin(P.rows), nodeMax(P.rows);
    parallel_for_(
        Range(0, P.rows),
        [&](const Range& r) {
            for (int gy = r.start; gy < r.end; ++gy) {
                const Point2f* p = P.ptr<Point2f>(gy);
                float lo = INFINITY, hi = -INFINITY;
                for (int gx = 0; gx < P.cols; ++gx)
                    lo = std::min(lo, p[gx].y), hi = std::max(hi, p[gx].y);
                nodeMin[gy] = lo, nodeMax[gy] = hi;
            }
        },
        std::max(1.0, P.rows / 64.0));
    for (int gy = 0; gy + 1 < P.rows; ++gy)
        rowMin_[gy] = std::min(nodeMin[gy], nodeMin[gy + 1]),
        rowMax_[gy] = std::max(nodeMax[gy], nodeMax[gy + 1]);
}

raster::PullMesh RasterMesh::pullMesh() const {
    const Size grid(P_.cols - 2, P_.rows - 2);  // within the ring
    return {P_.ptr<Point2f>(), P_.cols, P_.rows, grid, float(gridStep_), lo_, hi_};
}

namespace {
// Bands of output rows drawn in parallel: 4 per thread, or of 64 rows (two maps of 512 px: 256 KB,
// in cache while drawn) where there are more. The cell rows across a band's edge are set up by
// both bands, so narrower ones repeat more work.
int bandCount(int rows) {
    return std::max(1, std::min(rows, std::max(getNumThreads() * 4, rows / 64)));
}
}  // namespace

bool RasterMesh::mayPull() const {
    return gridStep_ > 0 && (gridStep_ <= kMaxPullStep || mapStep_ > 1) && pullPreferred_ &&
           raster::havePullKernel() && P_.isContinuous();
}

bool RasterMesh::foldsNowhere() const {
    if (!mayPull()) return false;
    if (pullable_ != Pullable::unknown) return pullable_ == Pullable::yes;
    return raster::pullable(pullMesh());
}

bool RasterMesh::pulls() const {
    return gridStep_ <= kMaxPullStep && foldsNowhere();
}

void RasterMesh::reserveLattice() {
    latticeOwners_.clear();
    latticeX_.release(), latticeY_.release();
    latticeColumns_ = raster::LatticeColumns();
    latticeFor_ = out_;
    if (mapStep_ < 2 || out_.width < 2 || out_.height < 2) return;
    // Allocated and touched here (for a Deformer: at its creation), in 2 MB pages where the
    // kernel offers them: a first deform does not pay the page faults of fresh maps.
    lattice_ = raster::Lattice::of(out_, mapStep_);
    latticeX_ = hugePageMat(lattice_.points, CV_32F, latticeOwners_);
    latticeY_ = hugePageMat(lattice_.points, CV_32F, latticeOwners_);
    latticeX_.setTo(Scalar::all(0)), latticeY_.setTo(Scalar::all(0));
    latticeColumns_ = raster::LatticeColumns::of(lattice_, out_.width);
}

bool RasterMesh::interpolates() const {
    return mapStep_ > 1 && mayPull() && raster::latticeFits(pullMesh(), out_, mapStep_) &&
           foldsNowhere();
}

bool RasterMesh::drawInterpolated(Mat& mapx, Mat& mapy,
                                  const std::function<void(int, int)>& bandDone) {
    if (latticeFor_ != out_) reserveLattice();  // a pose of another output size
    if (!raster::pullLattice(pullMesh(), lattice_, latticeX_, latticeY_)) return false;
    // Bands of output rows as draw()'s, each sampled (bandDone) while its maps are in cache.
    const int bands = bandCount(out_.height);
    parallel_for_(Range(0, bands), [&](const Range& range) {
        for (int band = range.start; band < range.end; ++band) {
            const int y0 = out_.height * band / bands, y1 = out_.height * (band + 1) / bands;
            raster::interpolateRows(lattice_, latticeColumns_, latticeX_, latticeY_, y0, y1, mapx,
                                    mapy);
            if (bandDone) bandDone(y0, y1);
        }
    });
    return true;
}

void RasterMesh::pose(const Binding& binding, const std::vector<Point2f>& vertices) {
    CV_Assert(binding.gridSize == Size(P_.cols - 2, P_.rows - 2) &&
              vertices.size() == size_t(binding.coefficientCount()));
    const Point2f* frame = &vertices[vertices.size() - 4];
    // The ring follows the frame alone (not the nodes): placed first, so that the check below
    // finds it in place.
    setFrame(frame);
    setOutputSize(frameOutputSize(frame, binding.imageSize));
    Mat nodes = this->nodes();
    if (!mayPull()) {
        applyRows(binding, vertices, nodes, {});
        return;
    }
    // Cell row ey lies between mesh rows ey and ey + 1; node row gy is mesh row gy + 1. A block
    // of node rows [gy0, gy1) holds the cell rows [gy0 + 1, gy1) whole; the rest (the ring's, and
    // those across blocks: 1 in 16 at 1024 px) are checked after, reading 2 rows each.
    const raster::PullMesh mesh = pullMesh();
    std::vector<uchar> checked(P_.rows - 1, 0);
    std::atomic<bool> positive{raster::frameConvex(mesh)};
    applyRows(binding, vertices, nodes, [&](int gy0, int gy1) {
        if (!positive.load(std::memory_order_relaxed)) return;
        if (!raster::positiveRows(mesh, gy0 + 1, gy1)) positive = false;
        std::fill(checked.begin() + gy0 + 1, checked.begin() + std::max(gy0 + 1, gy1), uchar(1));
    });
    for (int ey = 0; positive && ey + 1 < P_.rows; ++ey)
        if (!checked[ey] && !raster::positiveRows(mesh, ey, ey + 1)) positive = false;
    pullable_ = positive ? Pullable::yes : Pullable::no;
}

void RasterMesh::draw(Mat& mapx, Mat& mapy, const std::function<void(int, int)>& bandDone) {
    CV_Assert(mapx.type() == CV_32F && mapy.type() == CV_32F && mapx.size() == out_ &&
              mapy.size() == out_);
    if (interpolates() && drawInterpolated(mapx, mapy, bandDone)) return;
    const Mat& P = P_;
    const Point2f lo = lo_, hi = hi_;
    const Size outputSize = out_;
    // Bands of output rows in parallel (bandCount); each clears its rows, then walks the cells in
    // the same order, so where the mesh folds over, the later triangle wins exactly as in a GPU
    // draw call.
    const int bands = bandCount(outputSize.height);
    const raster::DrawCellRowFn kernel = raster::cellRowKernel();
    // A regular grid of small cells that folds nowhere is pulled pixel by pixel (mesh_pull.cpp),
    // band by band, where this CPU can: per pixel it costs about what a raster costs per
    // triangle, so it pays where cells cover a few pixels (at 1024x768, one thread, the pull took
    // 0.27x the raster's time at grid step 1, 0.6x at step 2 and 1.5x at step 4). A band whose
    // pixels did not all settle is drawn as any other mesh is.
    const raster::PullMesh pullMesh = this->pullMesh();
    const bool pull = pulls();
    // The raster's row extents: found before the bands (in parallel) when every band is drawn,
    // else by the first band that is.
    std::once_flag extentsFound;
    auto findExtents = [&] { std::call_once(extentsFound, [this] { findRowExtents(); }); };
    if (!pull) findExtents();
    parallel_for_(Range(0, bands), [&](const Range& range) {
        std::unique_ptr<raster::TriangleSetup> setup(new raster::TriangleSetup);
        std::vector<Point2f> rest0, rest1;  // rest rows of a regular grid
        for (int band = range.start; band < range.end; ++band) {
            int y0 = outputSize.height * band / bands, y1 = outputSize.height * (band + 1) / bands;
            if (pull) {  // bands of whole runs of the pull's guesses (raster::kPullRun)
                auto runStart = [](int y) { return y / raster::kPullRun * raster::kPullRun; };
                y0 = runStart(y0), y1 = band + 1 == bands ? outputSize.height : runStart(y1);
                if (y0 == y1) continue;
                if (raster::pullRows(pullMesh, y0, y1, mapx, mapy)) {
                    if (bandDone) bandDone(y0, y1);
                    continue;
                }
            }
            findExtents();
            for (int y = y0; y < y1; ++y) {
                std::fill_n(mapx.ptr<float>(y), outputSize.width, kUncovered);
                std::fill_n(mapy.ptr<float>(y), outputSize.width, kUncovered);
            }
            for (int gy = 0; gy + 1 < P.rows; ++gy) {
                if (rowMax_[gy] < y0 - 1 || rowMin_[gy] > y1 + 1) continue;
                const Point2f* p0 = P.ptr<Point2f>(gy);
                const Point2f* p1 = P.ptr<Point2f>(gy + 1);
                const Point2f* r0 = restRow(gy, rest0);
                const Point2f* r1 = restRow(gy + 1, rest1);
                kernel(p0, p1, r0, r1, P.cols - 1, y0, y1, lo, hi, mapx, mapy, *setup);
            }
            if (bandDone) bandDone(y0, y1);
        }
    });
}

void rasterizeMaps(InputArray positionsIn, InputArray restIn, Size outputSize, OutputArray mapxOut,
                   OutputArray mapyOut, InputArray frameIn) {
    Mat P = positionsIn.getMat(), R = restIn.getMat();
    CV_Assert(P.type() == CV_32FC2 && R.type() == CV_32FC2 && P.size() == R.size());
    CV_Assert(P.rows >= 2 && P.cols >= 2 && outputSize.area() > 0);
    Point2f corners[4];
    if (!frameIn.empty()) {
        Mat f = frameIn.getMat();
        CV_Assert(f.total() == 4 && f.type() == CV_32FC2);
        if (!f.isContinuous()) f = f.clone();
        std::copy(f.ptr<Point2f>(), f.ptr<Point2f>() + 4, corners);
    }
    RasterMesh mesh;
    mesh.reset(R, outputSize);
    P.copyTo(mesh.nodes());
    mesh.setFrame(frameIn.empty() ? nullptr : corners);
    mapxOut.create(outputSize, CV_32F);
    mapyOut.create(outputSize, CV_32F);
    Mat mapx = mapxOut.getMat(), mapy = mapyOut.getMat();
    mesh.draw(mapx, mapy);
}

namespace {

// The triangles of one row of cells (node rows p0/p1 deformed, r0/r1 rest) whose orientation
// differs between the two meshes. The sign of cross(b - a, c - a): differences in float,
// products and their difference in double (products of floats are exact in double, so the sign
// is exact for those differences, fused or not). Each leg is a difference of two nodes of the
// row pair (kCellTriangles: triangle 0 from (0,0) to (1,0) and (0,1); triangle 1 from (1,0) to
// (1,1) and (0,1)); they are formed in blocks of cells as planes of floats, so that the loop
// over cells vectorises: a random pose is checked on every node of a mesh, once per drawn pose.
// A copy per CPU level (AVX-512: eight doubles per instruction); no fused multiply-add in this
// file, and the products of floats are exact anyway: the same count from every copy.
MULTICAGE_ALWAYS_INLINE int foldedInRowKernel(const Point2f* p0, const Point2f* p1,
                                              const Point2f* r0, const Point2f* r1, int cells) {
    static_assert(kCellTriangles[0][0][0] == 0 && kCellTriangles[0][0][1] == 0 &&
                      kCellTriangles[0][1][0] == 1 && kCellTriangles[0][1][1] == 0 &&
                      kCellTriangles[0][2][0] == 0 && kCellTriangles[0][2][1] == 1 &&
                      kCellTriangles[1][0][0] == 1 && kCellTriangles[1][0][1] == 0 &&
                      kCellTriangles[1][1][0] == 1 && kCellTriangles[1][1][1] == 1 &&
                      kCellTriangles[1][2][0] == 0 && kCellTriangles[1][2][1] == 1,
                  "the legs below follow kCellTriangles");
    constexpr int kBlock = 64;
    auto cross = [](float ux, float uy, float vx, float vy) {
        return double(ux) * vy - double(uy) * vx;
    };
    // Orientations differ: one positive and the other not, or one negative and the other not.
    auto differ = [](double p, double r) { return ((p > 0) != (r > 0)) | ((p < 0) != (r < 0)); };
    int folded = 0;
    for (int g0 = 0; g0 < cells; g0 += kBlock) {
        const int n = std::min(kBlock, cells - g0);
        const float *a = reinterpret_cast<const float*>(p0 + g0),
                    *b = reinterpret_cast<const float*>(p1 + g0),
                    *ra = reinterpret_cast<const float*>(r0 + g0),
                    *rb = reinterpret_cast<const float*>(r1 + g0);
        for (int k = 0; k < n; ++k) {
            const int x = 2 * k, y = 2 * k + 1, x1 = 2 * k + 2, y1 = 2 * k + 3;
            // Triangle 0: legs top (a[k] -> a[k+1]) and left (a[k] -> b[k]); triangle 1: legs
            // right (a[k+1] -> b[k+1]) and diagonal (a[k+1] -> b[k]).
            const double posed0 = cross(a[x1] - a[x], a[y1] - a[y], b[x] - a[x], b[y] - a[y]);
            const double rest0 =
                cross(ra[x1] - ra[x], ra[y1] - ra[y], rb[x] - ra[x], rb[y] - ra[y]);
            const double posed1 = cross(b[x1] - a[x1], b[y1] - a[y1], b[x] - a[x1], b[y] - a[y1]);
            const double rest1 =
                cross(rb[x1] - ra[x1], rb[y1] - ra[y1], rb[x] - ra[x1], rb[y] - ra[y1]);
            folded += differ(posed0, rest0) + differ(posed1, rest1);
        }
    }
    return folded;
}

MULTICAGE_CPU_CLONES(int, foldedInRow,
                     (const Point2f* p0, const Point2f* p1, const Point2f* r0, const Point2f* r1,
                      int cells),
                     (p0, p1, r0, r1, cells))

}  // namespace

int countFoldedTriangles(InputArray positionsIn, InputArray restIn) {
    const Mat P = positionsIn.getMat(), R = restIn.getMat();
    CV_Assert(P.type() == CV_32FC2 && R.type() == CV_32FC2 && P.size() == R.size());
    int folded = 0;
    for (int gy = 0; gy + 1 < P.rows; ++gy)
        folded += foldedInRow(P.ptr<Point2f>(gy), P.ptr<Point2f>(gy + 1), R.ptr<Point2f>(gy),
                              R.ptr<Point2f>(gy + 1), P.cols - 1);
    return folded;
}

}  // namespace multicage
}  // namespace cv

// Rasterising the deformed node mesh into inverse maps (the CPU backend's "draw call").
#include <opencv2/core/utility.hpp>
#include <opencv2/multicage/deformer.hpp>

#include "cpu_deformer.hpp"

#include <cmath>

namespace cv {
namespace multicage {

namespace {

constexpr float kUncovered = -1e4f;  // far outside any image: cv::remap gives the border value

inline double cross(Point2d a, Point2d b) { return a.x * b.y - a.y * b.x; }

// Writes, for every pixel centre of rows [y0, y1) inside triangle q (deformed), the matching
// point of triangle p (rest). Inside a triangle the inverse map is affine, so each row is a
// span [xl, xr] found from the three barycentric edge functions, filled by a straight loop.
// Edges are inclusive with a small tolerance so that neighbouring triangles leave no crack;
// on a shared edge both write almost the same value.
void drawTriangle(const Point2f q[3], const Point2f p[3], int y0, int y1, Point2f lo, Point2f hi,
                  Mat& mapx, Mat& mapy) {
    const Point2d q0 = q[0], q1 = q[1], q2 = q[2];
    // Bounds are clamped in double before they become ints: a pose may put nodes 1e30 px
    // away or at infinity, and converting such a value to int is undefined (fuzz_deform).
    // The negated tests also drop NaN coordinates.
    const double minY = std::min({q0.y, q1.y, q2.y}), maxY = std::max({q0.y, q1.y, q2.y});
    if (!(maxY >= y0 && minY <= y1 - 1)) return;
    const int ya = static_cast<int>(std::ceil(std::max(minY, double(y0))));
    const int yb = static_cast<int>(std::floor(std::min(maxY, double(y1 - 1))));
    if (ya > yb) return;
    const double minX = std::min({q0.x, q1.x, q2.x}), maxX = std::max({q0.x, q1.x, q2.x});
    if (!(maxX >= 0 && minX <= mapx.cols - 1)) return;
    const int xa = static_cast<int>(std::ceil(std::max(minX, 0.0)));
    const int xb = static_cast<int>(std::floor(std::min(maxX, double(mapx.cols - 1))));
    if (xa > xb) return;
    const double area = cross(q1 - q0, q2 - q0);
    // Degenerate, NaN, or infinite (a node at infinity: the affine map would be NaN).
    if (!(std::abs(area) > 1e-12) || !std::isfinite(area)) return;
    const double inv = 1.0 / area;
    // Barycentric l_i(x, y) = (cross(a, b) + x (a.y - b.y) + y (b.x - a.x)) / area for the
    // edge (a, b) opposite vertex i.
    const Point2d e[3][2] = {{q1, q2}, {q2, q0}, {q0, q1}};
    double ax[3], ay[3], a0[3];
    for (int i = 0; i < 3; ++i) {
        const Point2d a = e[i][0], b = e[i][1];
        ax[i] = (a.y - b.y) * inv, ay[i] = (b.x - a.x) * inv, a0[i] = cross(a, b) * inv;
    }
    // The rest position as an affine function of the output pixel: r = p2 + l0 (p0-p2) + l1 (p1-p2).
    const Point2d d0 = Point2d(p[0]) - Point2d(p[2]), d1 = Point2d(p[1]) - Point2d(p[2]);
    const double mxx = ax[0] * d0.x + ax[1] * d1.x, mxy = ay[0] * d0.x + ay[1] * d1.x;
    const double mx0 = p[2].x + a0[0] * d0.x + a0[1] * d1.x;
    const double myx = ax[0] * d0.y + ax[1] * d1.y, myy = ay[0] * d0.y + ay[1] * d1.y;
    const double my0 = p[2].y + a0[0] * d0.y + a0[1] * d1.y;
    constexpr double eps = -1e-7;
    double invAx[3];  // once per triangle, not per row
    for (int i = 0; i < 3; ++i) invAx[i] = ax[i] != 0 ? 1.0 / ax[i] : 0.0;
    for (int y = ya; y <= yb; ++y) {
        double left = xa, right = xb;
        for (int i = 0; i < 3; ++i) {  // l_i(x) = ax x + c >= eps
            const double c = a0[i] + ay[i] * y;
            if (ax[i] > 0) left = std::max(left, (eps - c) * invAx[i]);
            else if (ax[i] < 0) right = std::min(right, (eps - c) * invAx[i]);
            else if (c < eps) right = -1;
        }
        if (!(left <= right)) continue;  // empty span (or NaN) before converting to int
        const int xl = static_cast<int>(std::ceil(left)), xr = static_cast<int>(std::floor(right));
        if (xl > xr) continue;
        float* mx = mapx.ptr<float>(y);
        float* my = mapy.ptr<float>(y);
        const double bx = mxy * y + mx0, by = myy * y + my0;
        for (int x = xl; x <= xr; ++x) {
            mx[x] = std::min(std::max(static_cast<float>(mxx * x + bx), lo.x), hi.x);
            my[x] = std::min(std::max(static_cast<float>(myx * x + by), lo.y), hi.y);
        }
    }
}

}  // namespace

void RasterMesh::reset(const Mat& rest, Size outputSize) {
    CV_Assert(rest.type() == CV_32FC2 && rest.rows >= 2 && rest.cols >= 2 && outputSize.area() > 0);
    const int m = rest.cols, n = rest.rows;
    out_ = outputSize;
    lo_ = rest.at<Point2f>(0, 0), hi_ = rest.at<Point2f>(n - 1, m - 1);
    P_.create(n + 2, m + 2, CV_32FC2);
    R_.create(n + 2, m + 2, CV_32FC2);
    // Touched here, once: a first pose does not pay for the page faults of a fresh buffer.
    P_.setTo(Scalar::all(0));
    rest.copyTo(R_(Rect(1, 1, m, n)));
    forEachRingNode([&](int ex, int ey) {
        R_.at<Point2f>(ey, ex) = rest.at<Point2f>(std::min(std::max(ey - 1, 0), n - 1),
                                                  std::min(std::max(ex - 1, 0), m - 1));
    });
    rowMin_.resize(n + 1), rowMax_.resize(n + 1);
}

template <typename F>
void RasterMesh::forEachRingNode(F&& f) const {
    const int m = R_.cols - 2, n = R_.rows - 2;
    for (int ex = 0; ex < m + 2; ++ex) f(ex, 0);
    for (int ey = 1; ey < n + 1; ++ey) f(0, ey), f(m + 1, ey);
    for (int ex = 0; ex < m + 2; ++ex) f(ex, n + 1);
}

void RasterMesh::setFrame(const Point2f* frame) {
    // The mesh gets a ring of nodes on the image frame, around the node grid (whose outer nodes
    // sit on the border pixel centres, half a pixel inside the frame). A ring node follows the
    // frame as mean value coordinates do on a polygon edge (the frame corners interpolated
    // linearly) and samples the border pixel next to it. So the half-pixel band between the
    // frame and the border nodes is always covered: when border nodes move inwards the border
    // pixels stretch instead of leaving a line of border colour. deform.vert builds the same ring.
    const float W = static_cast<float>(out_.width), H = static_cast<float>(out_.height);
    Point2f corners[4] = {{-0.5f, -0.5f}, {W - 0.5f, -0.5f}, {W - 0.5f, H - 0.5f}, {-0.5f, H - 0.5f}};
    if (frame) std::copy(frame, frame + 4, corners);
    const int m = R_.cols - 2, n = R_.rows - 2;
    forEachRingNode([&](int ex, int ey) {
        const Point2f source = R_.at<Point2f>(ey, ex);
        const float rx = ex == 0 ? -0.5f : ex == m + 1 ? W - 0.5f : source.x;
        const float ry = ey == 0 ? -0.5f : ey == n + 1 ? H - 0.5f : source.y;
        const float u = (rx + 0.5f) / W, v = (ry + 0.5f) / H;
        P_.at<Point2f>(ey, ex) = (1 - u) * (1 - v) * corners[0] + u * (1 - v) * corners[1] +
                                 u * v * corners[2] + (1 - u) * v * corners[3];
    });
}

void RasterMesh::draw(Mat& mapx, Mat& mapy) {
    CV_Assert(mapx.type() == CV_32F && mapy.type() == CV_32F && mapx.size() == out_ && mapy.size() == out_);
    const Mat& P = P_;
    const Mat& R = R_;
    // Vertical extent of each row of cells, so that a band of output rows skips whole cell
    // rows: each node row's extent first (in parallel), then pairs of rows.
    std::vector<float> nodeMin(P.rows), nodeMax(P.rows);
    parallel_for_(Range(0, P.rows), [&](const Range& r) {
        for (int gy = r.start; gy < r.end; ++gy) {
            const Point2f* p = P.ptr<Point2f>(gy);
            float lo = INFINITY, hi = -INFINITY;
            for (int gx = 0; gx < P.cols; ++gx) lo = std::min(lo, p[gx].y), hi = std::max(hi, p[gx].y);
            nodeMin[gy] = lo, nodeMax[gy] = hi;
        }
    }, std::max(1.0, P.rows / 64.0));
    for (int gy = 0; gy + 1 < P.rows; ++gy)
        rowMin_[gy] = std::min(nodeMin[gy], nodeMin[gy + 1]), rowMax_[gy] = std::max(nodeMax[gy], nodeMax[gy + 1]);
    const std::vector<float>& rowMin = rowMin_;
    const std::vector<float>& rowMax = rowMax_;
    const Point2f lo = lo_, hi = hi_;
    const Size outputSize = out_;
    // Bands of output rows in parallel; each clears its rows, then walks the cells in the same
    // order, so where the mesh folds over, the later triangle wins exactly as in a GPU draw call.
    const int bands = std::max(1, std::min(outputSize.height, getNumThreads() * 4));
    parallel_for_(Range(0, bands), [&](const Range& range) {
        for (int band = range.start; band < range.end; ++band) {
            const int y0 = outputSize.height * band / bands, y1 = outputSize.height * (band + 1) / bands;
            for (int y = y0; y < y1; ++y) {
                std::fill_n(mapx.ptr<float>(y), outputSize.width, kUncovered);
                std::fill_n(mapy.ptr<float>(y), outputSize.width, kUncovered);
            }
            for (int gy = 0; gy + 1 < P.rows; ++gy) {
                if (rowMax[gy] < y0 - 1 || rowMin[gy] > y1 + 1) continue;
                const Point2f* p0 = P.ptr<Point2f>(gy);
                const Point2f* p1 = P.ptr<Point2f>(gy + 1);
                const Point2f* r0 = R.ptr<Point2f>(gy);
                const Point2f* r1 = R.ptr<Point2f>(gy + 1);
                for (int gx = 0; gx + 1 < P.cols; ++gx) {
                    const Point2f qa[3] = {p0[gx], p0[gx + 1], p1[gx]};
                    const Point2f ra[3] = {r0[gx], r0[gx + 1], r1[gx]};
                    drawTriangle(qa, ra, y0, y1, lo, hi, mapx, mapy);
                    const Point2f qb[3] = {p0[gx + 1], p1[gx + 1], p1[gx]};
                    const Point2f rb[3] = {r0[gx + 1], r1[gx + 1], r1[gx]};
                    drawTriangle(qb, rb, y0, y1, lo, hi, mapx, mapy);
                }
            }
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

int countFoldedTriangles(InputArray positionsIn, InputArray restIn) {
    const Mat P = positionsIn.getMat(), R = restIn.getMat();
    CV_Assert(P.type() == CV_32FC2 && R.type() == CV_32FC2 && P.size() == R.size());
    auto orientationOf = [](Point2f a, Point2f b, Point2f c) {
        const double d = cross(Point2d(b - a), Point2d(c - a));
        return (d > 0) - (d < 0);
    };
    int folded = 0;
    for (int gy = 0; gy + 1 < P.rows; ++gy)
        for (int gx = 0; gx + 1 < P.cols; ++gx) {
            const Point2f a = P.at<Point2f>(gy, gx), b = P.at<Point2f>(gy, gx + 1);
            const Point2f c = P.at<Point2f>(gy + 1, gx), d = P.at<Point2f>(gy + 1, gx + 1);
            const Point2f ra = R.at<Point2f>(gy, gx), rb = R.at<Point2f>(gy, gx + 1);
            const Point2f rc = R.at<Point2f>(gy + 1, gx), rd = R.at<Point2f>(gy + 1, gx + 1);
            folded += orientationOf(a, b, c) != orientationOf(ra, rb, rc);
            folded += orientationOf(b, d, c) != orientationOf(rb, rd, rc);
        }
    return folded;
}

}  // namespace multicage
}  // namespace cv

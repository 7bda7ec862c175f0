// countFoldedTriangles, which randomPose calls once per draw, against a plain count: its kernel
// forms the legs in planes and runs on AVX-512, and must count exactly as before (replayed
// poses depend on every accept or reject).
#include <opencv2/multicage/deformer.hpp>

#include "testing.hpp"

using namespace cv;
using namespace cv::multicage;

namespace {

// The two triangles of a mesh cell, corners as (dx, dy) from its top-left node (the backends'
// contract, docs/ARCHITECTURE.md).
constexpr int kTriangles[2][3][2] = {{{0, 0}, {1, 0}, {0, 1}}, {{1, 0}, {1, 1}, {0, 1}}};

int orientation(Point2f a, Point2f b, Point2f c) {
    const double ux = b.x - a.x, uy = b.y - a.y, vx = c.x - a.x, vy = c.y - a.y;
    const double d = ux * vy - uy * vx;
    return (d > 0) - (d < 0);
}

/** flat: incremented per triangle of zero area in P. */
int plainCount(const Mat& P, const Mat& R, int& flat) {
    int folded = 0;
    for (int gy = 0; gy + 1 < P.rows; ++gy)
        for (int gx = 0; gx + 1 < P.cols; ++gx)
            for (const auto& t : kTriangles) {
                auto at = [&](const Mat& M, int v) {
                    return M.at<Point2f>(gy + t[v][1], gx + t[v][0]);
                };
                const int posed = orientation(at(P, 0), at(P, 1), at(P, 2));
                folded += posed != orientation(at(R, 0), at(R, 1), at(R, 2));
                flat += posed == 0;
            }
    return folded;
}

}  // namespace

// Grids of several widths (blocks of cells and their remainders), perturbed from slightly to
// enough to fold, some nodes snapped onto a neighbour or onto a line through two (triangles of
// zero area: orientation 0 must differ from +-1), and rest meshes that are not grids.
TEST(FoldCount, CountsAsThePlainLoop) {
    RNG rng(23);
    int withFolds = 0, withFlat = 0;
    for (int trial = 0; trial < 60; ++trial) {
        const Size grid(2 + rng.uniform(0, 150), 2 + rng.uniform(0, 12));
        const float step = static_cast<float>(rng.uniform(1, 6));
        const double noise = rng.uniform(0.0, 1.2) * step;
        Mat R(grid, CV_32FC2), P(grid, CV_32FC2);
        for (int y = 0; y < grid.height; ++y)
            for (int x = 0; x < grid.width; ++x) {
                const Point2f r(x * step, y * step);
                R.at<Point2f>(y, x) = trial % 3 == 0 ? r + Point2f(rng.uniform(-0.4f, 0.4f) * step,
                                                                   rng.uniform(-0.4f, 0.4f) * step)
                                                     : r;
                P.at<Point2f>(y, x) = r + Point2f(static_cast<float>(rng.gaussian(noise)),
                                                  static_cast<float>(rng.gaussian(noise)));
            }
        for (int k = 0; k < grid.area() / 10; ++k) {  // flat triangles
            const int x = rng.uniform(0, grid.width - 1), y = rng.uniform(0, grid.height - 1);
            if (k % 2)
                P.at<Point2f>(y, x) = P.at<Point2f>(y, x + 1);
            else if (y + 1 < grid.height)
                P.at<Point2f>(y + 1, x) =
                    P.at<Point2f>(y, x) + 2.f * (P.at<Point2f>(y, x + 1) - P.at<Point2f>(y, x));
        }
        int flat = 0;
        const int expected = plainCount(P, R, flat);
        EXPECT_EQ(countFoldedTriangles(P, R), expected) << "trial " << trial << " grid " << grid;
        withFolds += expected > 0;
        withFlat += flat > 0;
    }
    EXPECT_GT(withFolds, 20);
    EXPECT_GT(withFlat, 20);
}

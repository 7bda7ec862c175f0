// How far a mesh can blend towards another before a triangle folds.
#include "fold_free_blend.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>
#include <opencv2/core/utility.hpp>
#include <opencv2/multicage/internal/backend_contract.hpp>

namespace cv {
namespace multicage {

namespace {

// The first root in (0, inf) of a + b t + c t^2 with a > 0 (the area at t = 0), or inf.
double firstPositiveRoot(double a, double b, double c) {
    if (!(a > 0)) return 0;  // already flat or folded (or NaN): no blend at all
    const double scale = std::abs(a) + std::abs(b) + std::abs(c);
    if (std::abs(c) <= 1e-12 * scale) return b < 0 ? -a / b : INFINITY;
    const double disc = b * b - 4 * a * c;
    if (disc < 0) return INFINITY;  // the area never reaches 0
    // The two roots, computed without cancellation: q = -(b + sign(b) sqrt(disc)) / 2.
    const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
    const double r1 = q / c, r2 = q != 0 ? a / q : INFINITY;
    double first = INFINITY;
    for (double r : {r1, r2})
        if (r > 0) first = std::min(first, r);
    return first;
}

}  // namespace

double firstFold(const Mat& p0, const Mat& p1, double area) {
    CV_Assert(p0.type() == CV_32FC2 && p1.type() == CV_32FC2 && p0.size() == p1.size());
    std::mutex lock;
    double first = INFINITY;
    parallel_for_(Range(0, std::max(0, p0.rows - 1)), [&](const Range& rows) {
        double local = INFINITY;
        for (int gy = rows.start; gy < rows.end; ++gy) {
            const Point2f* a[2] = {p0.ptr<Point2f>(gy), p0.ptr<Point2f>(gy + 1)};
            const Point2f* b[2] = {p1.ptr<Point2f>(gy), p1.ptr<Point2f>(gy + 1)};
            for (int gx = 0; gx + 1 < p0.cols; ++gx)
                for (const auto& t : kCellTriangles) {
                    // Corners q_i(t) = a_i + t d_i; the area of (q0, q1, q2) is
                    // cross(A1 + t D1, A2 + t D2) with A_i = a_i - a_0, D_i = d_i - d_0.
                    Point2d A[3], D[3];
                    for (int i = 0; i < 3; ++i) {
                        const Point2f s = a[t[i][1]][gx + t[i][0]], e = b[t[i][1]][gx + t[i][0]];
                        A[i] = Point2d(s), D[i] = Point2d(e) - Point2d(s);
                    }
                    const Point2d A1 = A[1] - A[0], A2 = A[2] - A[0], D1 = D[1] - D[0],
                                  D2 = D[2] - D[0];
                    const double c0 = A1.cross(A2), c1 = A1.cross(D2) + D1.cross(A2),
                                 c2 = D1.cross(D2);
                    local = std::min(local, firstPositiveRoot(c0 - area, c1, c2));
                }
        }
        std::lock_guard<std::mutex> guard(lock);
        first = std::min(first, local);
    });
    return first;
}

int foldedTriangles(const Mat& p) {
    CV_Assert(p.type() == CV_32FC2);
    std::atomic<int> folded(0);
    parallel_for_(Range(0, std::max(0, p.rows - 1)), [&](const Range& rows) {
        int local = 0;
        for (int gy = rows.start; gy < rows.end; ++gy) {
            const Point2f* q[2] = {p.ptr<Point2f>(gy), p.ptr<Point2f>(gy + 1)};
            for (int gx = 0; gx + 1 < p.cols; ++gx)
                for (const auto& t : kCellTriangles) {
                    const Point2d a(q[t[0][1]][gx + t[0][0]]), b(q[t[1][1]][gx + t[1][0]]),
                        c(q[t[2][1]][gx + t[2][0]]);
                    local += !((b - a).cross(c - a) > 0);
                }
        }
        folded += local;
    });
    return folded;
}

}  // namespace multicage
}  // namespace cv

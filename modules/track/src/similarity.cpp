// leastSquaresSimilarity (similarity.hpp).
#include "similarity.hpp"

namespace cv {
namespace multicage {

Mat leastSquaresSimilarity(const std::vector<Point2f>& from, const std::vector<Point2f>& to,
                           const std::vector<uchar>& use) {
    auto used = [&](size_t k) { return use.empty() || use[k]; };
    Point2d mf(0, 0), mt(0, 0);
    int n = 0;
    for (size_t k = 0; k < from.size(); ++k)
        if (used(k)) mf += Point2d(from[k]), mt += Point2d(to[k]), ++n;
    if (n > 0) mf /= n, mt /= n;
    double sxx = 0, sxy = 0, var = 0;  // sum of (f . t) and (f x t) over centred points
    for (size_t k = 0; k < from.size(); ++k) {
        if (!used(k)) continue;
        const Point2d f = Point2d(from[k]) - mf, t = Point2d(to[k]) - mt;
        sxx += f.x * t.x + f.y * t.y, sxy += f.x * t.y - f.y * t.x, var += f.dot(f);
    }
    const double a = var > 0 ? sxx / var : 1.0, b = var > 0 ? sxy / var : 0.0;  // s cos, s sin
    Mat m = (Mat_<double>(2, 3) << a, -b, 0, b, a, 0);
    m.at<double>(0, 2) = mt.x - (a * mf.x - b * mf.y);
    m.at<double>(1, 2) = mt.y - (b * mf.x + a * mf.y);
    return m;
}

}  // namespace multicage
}  // namespace cv

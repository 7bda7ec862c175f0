#include "mean_value.hpp"

#include <opencv2/multicage/coordinates.hpp>
#include <opencv2/multicage/internal/point_input.hpp>
#include <vector>

namespace cv {
namespace multicage {

MeanValueCase meanValueWeights(const Point2d* v, int n, Point2d x, double* w) {
    // Lengths below this (in pixels) are "on": far below any meaningful pixel position, far
    // above double rounding of coordinates up to 1e6.
    constexpr double kOn = 1e-9;
    std::vector<double> r(n), t(n);
    for (int i = 0; i < n; ++i) {
        const Point2d s = v[i] - x;
        r[i] = std::sqrt(s.dot(s));
        if (r[i] <= kOn) {
            std::fill(w, w + n, 0.0);
            w[i] = 1.0;
            return MeanValueCase::OnVertex;
        }
    }
    for (int i = 0; i < n; ++i) {
        const int j = (i + 1) % n;
        const Point2d si = v[i] - x, sj = v[j] - x;
        const double A = si.x * sj.y - si.y * sj.x;  // det(s_i, s_{i+1})
        const double D = si.dot(sj);
        if (D < 0 && std::abs(A) <= kOn * (r[i] + r[j])) {  // x on edge (v_i, v_{i+1})
            std::fill(w, w + n, 0.0);
            w[i] = r[j] / (r[i] + r[j]);
            w[j] = r[i] / (r[i] + r[j]);
            return MeanValueCase::OnEdge;
        }
        t[i] = D > 0 ? A / (r[i] * r[j] + D) : (r[i] * r[j] - D) / A;
    }
    for (int i = 0; i < n; ++i) w[i] = (t[(i + n - 1) % n] + t[i]) / r[i];
    return MeanValueCase::General;
}

void meanValueCoordinates(InputArray polygonIn, InputArray pointsIn, OutputArray weightsOut,
                          bool normalize) {
    const std::vector<Point2f> polygon = toPoints(polygonIn, "polygon");
    const std::vector<Point2f> points = toPoints(pointsIn, "points");
    const int n = static_cast<int>(polygon.size());
    if (n < 3)
        CV_Error_(Error::StsBadArg, ("meanValueCoordinates: the polygon has %d vertices, it needs "
                                     "at least 3",
                                     n));
    const std::vector<Point2d> v(polygon.begin(), polygon.end());
    weightsOut.create(static_cast<int>(points.size()), n, CV_32F);
    Mat weights = weightsOut.getMat();
    std::vector<double> w(n);
    for (int k = 0; k < static_cast<int>(points.size()); ++k) {
        const MeanValueCase c = meanValueWeights(v.data(), n, points[k], w.data());
        double sum = 1.0;
        if (c == MeanValueCase::General && normalize) {
            sum = 0.0;
            for (double x : w) sum += x;
        }
        float* row = weights.ptr<float>(k);
        for (int i = 0; i < n; ++i) row[i] = static_cast<float>(w[i] / sum);
    }
}

}  // namespace multicage
}  // namespace cv

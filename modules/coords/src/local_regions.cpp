// Which polygons bound each node's region, for local mean value coordinates.
#include "local_regions.hpp"

#include <algorithm>
#include <numeric>
#include <opencv2/multicage/internal/geometry.hpp>

namespace cv {
namespace multicage {

namespace {

// Where the edges of a polygon cross the line y (an edge counts when exactly one of its ends is
// at or above y: each crossing is counted once, also through a vertex), sorted.
void rowCrossings(const std::vector<Point2d>& v, double y, std::vector<double>& out) {
    out.clear();
    const size_t n = v.size();
    for (size_t i = 0, j = n - 1; i < n; j = i++) {
        const Point2d a = v[j], b = v[i];
        if ((a.y <= y) == (b.y <= y)) continue;
        out.push_back(a.x + (y - a.y) * (b.x - a.x) / (b.y - a.y));
    }
    std::sort(out.begin(), out.end());
}

}  // namespace

LocalRegions::LocalRegions(const Multicage& multicage) {
    const int P = multicage.polygonCount();
    polygons_.resize(P);
    for (int p = 0; p < P; ++p) {
        const std::vector<Point2f> poly = multicage.polygon(p);
        polygons_[p].assign(poly.begin(), poly.end());
    }
    parent_.assign(P, P);
    byDepth_.resize(P);
    std::iota(byDepth_.begin(), byDepth_.end(), 0);
    std::vector<geometry::Polygon> all;
    for (int p = 0; p < P; ++p) all.push_back(multicage.polygon(p));
    const std::vector<int> depth = geometry::depths(all);  // once: depth(p) finds them all
    std::stable_sort(byDepth_.begin(), byDepth_.end(),
                     [&](int a, int b) { return depth[a] < depth[b]; });
    const std::vector<int> parent = geometry::parents(all, depth);
    for (int p = 0; p < P; ++p)
        if (parent[p] >= 0) parent_[p] = parent[p];  // outlines keep frame()
}

void LocalRegions::regionsOfRow(const float* xs, int m, double y, int* region) const {
    std::fill(region, region + m, frame());
    std::vector<double> crossings;
    // Shallowest first: a deeper polygon's inside overwrites its parent's.
    for (int p : byDepth_) {
        rowCrossings(polygons_[p], y, crossings);
        // xs rises along the row: walk the crossings and the nodes together.
        size_t c = 0;
        for (int k = 0; k < m; ++k) {
            while (c < crossings.size() && crossings[c] < xs[k]) ++c;
            if (c % 2 == 1) region[k] = p;
        }
    }
}

}  // namespace multicage
}  // namespace cv

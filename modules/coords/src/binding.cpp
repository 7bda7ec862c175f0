// Binding a node grid to a multicage (paper Algorithm 1) and applying poses to it.
#include <opencv2/core/utility.hpp>
#include <opencv2/multicage/coordinates.hpp>

#include <atomic>
#include <mutex>

#include "geometry.hpp"
#include "harmonic.hpp"
#include "mean_value.hpp"
#include "point_input.hpp"

// The row kernel is compiled twice, for AVX2+FMA and for the baseline, and the loader picks
// the one this CPU runs (GCC function multiversioning): 8 nodes per instruction where possible.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(__SANITIZE_ADDRESS__)
#define MULTICAGE_TARGET_CLONES __attribute__((target_clones("arch=haswell", "default")))
#else
#define MULTICAGE_TARGET_CLONES
#endif

namespace cv {
namespace multicage {

Size gridSizeFor(Size imageSize, int gridStep) {
    CV_Assert(imageSize.width > 0 && imageSize.height > 0);
    if (gridStep < 1)
        CV_Error_(Error::StsOutOfRange, ("multicage: gridStep must be >= 1, got %d", gridStep));
    return Size((imageSize.width - 1 + gridStep - 1) / gridStep + 1,
                (imageSize.height - 1 + gridStep - 1) / gridStep + 1);
}

static inline float nodeCoordinate(int k, int step, int size) {
    return static_cast<float>(std::min(k * step, size - 1));
}

Point2f Binding::node(int gx, int gy) const {
    return Point2f(nodeCoordinate(gx, gridStep, imageSize.width),
                   nodeCoordinate(gy, gridStep, imageSize.height));
}

Mat Binding::nodes() const {
    Mat out(gridSize, CV_32FC2);
    for (int gy = 0; gy < gridSize.height; ++gy)
        for (int gx = 0; gx < gridSize.width; ++gx) out.at<Point2f>(gy, gx) = node(gx, gy);
    return out;
}

std::vector<Point2f> Binding::completePose(InputArray poseIn) const {
    std::vector<Point2f> pose = toPoints(poseIn, "pose");
    const int c = coefficientCount(), user = c - 4;
    if (static_cast<int>(pose.size()) == user)
        pose.insert(pose.end(), restVertices.end() - 4, restVertices.end());
    if (static_cast<int>(pose.size()) != c)
        CV_Error_(Error::StsBadSize, ("multicage: the pose has %d vertices; the multicage has %d "
                                      "(or %d with the frame corners)",
                                      static_cast<int>(pose.size()), user, c));
    for (int j = 0; j < c; ++j)
        if (!geometry::isFinite(pose[j]))
            CV_Error_(Error::StsBadArg, ("multicage: pose vertex %d is not a finite number", j));
    return pose;
}

void Binding::apply(InputArray poseIn, OutputArray positionsOut) const {
    CV_Assert(!empty());
    const std::vector<Point2f> pose = completePose(poseIn);
    // Displacement form p' = x + sum_j CC_j (v'_j - v_j): exact for the rest pose, and vertices
    // that did not move cost nothing.
    std::vector<int> moved;
    std::vector<Point2f> delta;
    for (int j = 0; j < coefficientCount(); ++j) {
        const Point2f d = pose[j] - restVertices[j];
        if (d.x != 0.f || d.y != 0.f) moved.push_back(j), delta.push_back(d);
    }
    positionsOut.create(gridSize, CV_32FC2);
    Mat positions = positionsOut.getMat();
    const int N = nodeCount(), m = gridSize.width;
    constexpr int kChunk = 4096;
    parallel_for_(Range(0, (N + kChunk - 1) / kChunk), [&](const Range& r) {
        std::vector<float> px(kChunk), py(kChunk);
        for (int chunk = r.start; chunk < r.end; ++chunk) {
            const int begin = chunk * kChunk, count = std::min(kChunk, N - begin);
            for (int k = 0; k < count; ++k) {
                const Point2f x = node((begin + k) % m, (begin + k) / m);
                px[k] = x.x, py[k] = x.y;
            }
            for (size_t q = 0; q < moved.size(); ++q) {
                const float* cc = coefficients.ptr<float>(moved[q]) + begin;
                const float dx = delta[q].x, dy = delta[q].y;
                for (int k = 0; k < count; ++k) px[k] += cc[k] * dx, py[k] += cc[k] * dy;
            }
            Point2f* out = positions.ptr<Point2f>() + begin;
            for (int k = 0; k < count; ++k) out[k] = Point2f(px[k], py[k]);
        }
    });
}

namespace {

struct BoundPolygon {
    std::vector<Point2f> v;
    int first;    // coefficient index of vertex 0
    float sign;   // +1 or -1: the raw weights as if the polygon obeyed the orientation rule
};

// Raw mean value weights, times `sign`, of polygon v[0..n) for the nodes (xs[k], y), k < m.
// Hormann & Floater 2006: t_i = tan(alpha_i / 2), w_i = (t_{i-1} + t_i) / r_i. The float
// kernel flags nodes on or near a vertex or an edge; those are redone in double by the caller.
// out[i] receives vertex i's row; tbuf is n*m scratch.
MULTICAGE_TARGET_CLONES
void rawWeightsRow(const Point2f* v, int n, float sign, const float* xs, int m, float y,
                   float* const* out, float* tbuf, uchar* nearSingular) {
    for (int i = 0; i < n; ++i) {  // r_i, kept in the output row until pass 3
        const float vx = v[i].x, dy = v[i].y - y;
        float* r = out[i];
        for (int k = 0; k < m; ++k) {
            const float dx = vx - xs[k];
            r[k] = std::sqrt(dx * dx + dy * dy);
        }
    }
    for (int i = 0; i < n; ++i) {  // t_i for edge (v_i, v_{i+1})
        const int j = i + 1 == n ? 0 : i + 1;
        const float vix = v[i].x, diy = v[i].y - y, vjx = v[j].x, djy = v[j].y - y;
        const float* ri = out[i];
        const float* rj = out[j];
        float* t = tbuf + static_cast<size_t>(i) * m;
        for (int k = 0; k < m; ++k) {
            const float dix = vix - xs[k], djx = vjx - xs[k];
            const float A = dix * djy - diy * djx;
            const float D = dix * djx + diy * djy;
            const float rr = ri[k] * rj[k];
            const float tk = D > 0.f ? A / (rr + D) : (rr - D) / A;
            t[k] = sign * tk;
            // near a vertex (r small) or an edge (A small while the edge is seen at > 90 deg)
            const bool bad = ri[k] < 1e-3f || (D <= 0.f && std::abs(A) < 1e-4f * rr);
            nearSingular[k] |= static_cast<uchar>(bad);
        }
    }
    for (int i = 0; i < n; ++i) {
        const float* tprev = tbuf + static_cast<size_t>(i == 0 ? n - 1 : i - 1) * m;
        const float* t = tbuf + static_cast<size_t>(i) * m;
        float* w = out[i];
        for (int k = 0; k < m; ++k) w[k] = (tprev[k] + t[k]) / w[k];
    }
}

// Algorithm 1 for one node in double precision, with the exact vertex/edge policy.
// Writes the c coefficients to cc and returns the conditioning |sum w| / sum |w|.
double bindNodeExact(const std::vector<BoundPolygon>& polygons, Point2d x, double* cc, int c) {
    std::fill(cc, cc + c, 0.0);
    std::vector<Point2d> v;
    for (const BoundPolygon& p : polygons) {
        v.assign(p.v.begin(), p.v.end());
        const MeanValueCase where = meanValueWeights(v.data(), static_cast<int>(v.size()), x, cc + p.first);
        if (where != MeanValueCase::General) {  // the node follows this polygon alone
            std::vector<double> own(cc + p.first, cc + p.first + v.size());
            std::fill(cc, cc + c, 0.0);
            std::copy(own.begin(), own.end(), cc + p.first);
            return 1.0;
        }
        for (size_t i = 0; i < v.size(); ++i) cc[p.first + i] *= p.sign;
    }
    double sum = 0.0, absSum = 0.0;
    for (int j = 0; j < c; ++j) sum += cc[j], absSum += std::abs(cc[j]);
    if (sum == 0.0) {  // exact cancellation: leave the node at rest rather than divide by 0
        std::fill(cc, cc + c, 0.0);
        return 0.0;
    }
    for (int j = 0; j < c; ++j) cc[j] /= sum;
    return std::abs(sum) / absSum;
}

}  // namespace

Binding bind(const Multicage& multicage, int coordinates, int gridStep) {
    std::string why;
    if (!multicage.validateGeometry(&why)) CV_Error(Error::StsBadArg, "multicage: cannot bind: " + why);
    if (coordinates == HARMONIC) return bindHarmonic(multicage, gridStep);
    if (coordinates != MEAN_VALUE)
        CV_Error_(Error::StsOutOfRange, ("multicage: unknown coordinate type %d", coordinates));
    Binding b;
    b.imageSize = multicage.imageSize();
    b.gridStep = gridStep;
    b.gridSize = gridSizeFor(b.imageSize, gridStep);
    b.coordinates = coordinates;
    b.restVertices = multicage.vertices();
    const int c = b.coefficientCount(), m = b.gridSize.width, N = b.nodeCount();

    // The frame is a polygon like the others (depth 0, A > 0), its corners the last 4 slots.
    std::vector<BoundPolygon> polygons;
    int maxN = 4;
    for (int p = 0; p < multicage.polygonCount(); ++p) {
        BoundPolygon bp{multicage.polygon(p), multicage.polygonOffset(p), 1.f};
        const bool wantPositive = multicage.depth(p) % 2 == 0;
        bp.sign = (multicage.signedArea(p) > 0) == wantPositive ? 1.f : -1.f;
        maxN = std::max(maxN, static_cast<int>(bp.v.size()));
        polygons.push_back(std::move(bp));
    }
    polygons.push_back(BoundPolygon{multicage.frame(), c - 4, 1.f});

    b.coefficients.create(c, N, CV_32F);
    std::mutex worstLock;
    double worst = 2.0;
    Point2f worstAt;
    parallel_for_(Range(0, b.gridSize.height), [&](const Range& rows) {
        std::vector<float> xs(m), tbuf(static_cast<size_t>(maxN) * m), sum(m), absSum(m);
        std::vector<uchar> nearSingular(m);
        std::vector<float*> out(c);
        std::vector<double> exact(c);
        double localWorst = 2.0;
        Point2f localAt;
        for (int gx = 0; gx < m; ++gx) xs[gx] = b.node(gx, 0).x;
        for (int gy = rows.start; gy < rows.end; ++gy) {
            const float y = b.node(0, gy).y;
            for (int j = 0; j < c; ++j) out[j] = b.coefficients.ptr<float>(j) + static_cast<size_t>(gy) * m;
            std::fill(nearSingular.begin(), nearSingular.end(), 0);
            for (const BoundPolygon& p : polygons)
                rawWeightsRow(p.v.data(), static_cast<int>(p.v.size()), p.sign, xs.data(), m, y,
                              out.data() + p.first, tbuf.data(), nearSingular.data());
            std::fill(sum.begin(), sum.end(), 0.f);
            std::fill(absSum.begin(), absSum.end(), 0.f);
            for (int j = 0; j < c; ++j)
                for (int k = 0; k < m; ++k) sum[k] += out[j][k], absSum[k] += std::abs(out[j][k]);
            for (int k = 0; k < m; ++k) {
                // Sums of non-finite or cancelling weights are redone in double as well.
                if (!std::isfinite(absSum[k]) || std::abs(sum[k]) < 1e-4f * absSum[k]) nearSingular[k] = 1;
                sum[k] = 1.f / sum[k];
            }
            for (int j = 0; j < c; ++j)
                for (int k = 0; k < m; ++k) out[j][k] *= sum[k];
            for (int k = 0; k < m; ++k) {
                double kappa;
                if (nearSingular[k]) {
                    kappa = bindNodeExact(polygons, Point2d(xs[k], y), exact.data(), c);
                    for (int j = 0; j < c; ++j) out[j][k] = static_cast<float>(exact[j]);
                } else {
                    kappa = 1.0 / (std::abs(sum[k]) * absSum[k]);
                }
                if (kappa < localWorst) localWorst = kappa, localAt = Point2f(xs[k], y);
            }
        }
        std::lock_guard<std::mutex> lock(worstLock);
        if (localWorst < worst || (localWorst == worst && (localAt.y < worstAt.y))) worst = localWorst, worstAt = localAt;
    });
    b.minConditioning = std::min(worst, 1.0);
    b.worstNode = worstAt;
    return b;
}

}  // namespace multicage
}  // namespace cv

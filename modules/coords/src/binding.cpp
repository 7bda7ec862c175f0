// Binding a node grid to a multicage (paper Algorithm 1) and applying poses to it.
#include <cstring>
#include <memory>
#include <mutex>
#include <opencv2/core/utility.hpp>
#include <opencv2/multicage/coordinates.hpp>
#if defined(__linux__)
#include <sys/mman.h>
#endif

#include <opencv2/multicage/internal/apply_rows.hpp>
#include <opencv2/multicage/internal/backend_contract.hpp>
#include <opencv2/multicage/internal/geometry.hpp>
#include <opencv2/multicage/internal/point_input.hpp>

#include "harmonic.hpp"
#include "local_regions.hpp"
#include "mean_value.hpp"

// The row kernels are compiled for AVX-512, AVX2 and the baseline, and the CPU's level picks one
// (MULTICAGE_CPU_CLONES): 8 or 16 nodes per instruction where possible.
#include <opencv2/multicage/internal/cpu_dispatch.hpp>

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
    for (int gy = 0; gy < gridSize.height; ++gy) {  // node(gx, gy), a row at a time
        Point2f* row = out.ptr<Point2f>(gy);
        const float y = nodeCoordinate(gy, gridStep, imageSize.height);
        for (int gx = 0; gx < gridSize.width; ++gx)
            row[gx] = Point2f(nodeCoordinate(gx, gridStep, imageSize.width), y);
    }
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

namespace {

// px[k] += CC_q[k] dx_q, py[k] += CC_q[k] dy_q for the moved vertices q in order, nodes
// [begin, begin + count). Four planes per pass over px, py (each sum still adds the terms one
// by one in vertex order, so the result does not depend on the grouping); a product and a sum
// are two roundings, never contracted to one fused multiply-add, so every instruction set
// gives the same bits.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC push_options
#pragma GCC optimize("fp-contract=off")
#elif defined(__clang__)
#pragma clang fp contract(off)
#endif
MULTICAGE_ALWAYS_INLINE void accumulateDisplacementsKernel(const Mat& coefficients,
                                                           const int* moved, const Point2f* delta,
                                                           int count_q, size_t begin, int count,
                                                           float* __restrict px,
                                                           float* __restrict py) {
    int q = 0;
    for (; q + 4 <= count_q; q += 4) {
        const float* __restrict c0 = coefficients.ptr<float>(moved[q]) + begin;
        const float* __restrict c1 = coefficients.ptr<float>(moved[q + 1]) + begin;
        const float* __restrict c2 = coefficients.ptr<float>(moved[q + 2]) + begin;
        const float* __restrict c3 = coefficients.ptr<float>(moved[q + 3]) + begin;
        const float x0 = delta[q].x, x1 = delta[q + 1].x, x2 = delta[q + 2].x, x3 = delta[q + 3].x;
        const float y0 = delta[q].y, y1 = delta[q + 1].y, y2 = delta[q + 2].y, y3 = delta[q + 3].y;
        for (int k = 0; k < count; ++k) {
            float x = px[k], y = py[k];
            x += c0[k] * x0, y += c0[k] * y0;
            x += c1[k] * x1, y += c1[k] * y1;
            x += c2[k] * x2, y += c2[k] * y2;
            x += c3[k] * x3, y += c3[k] * y3;
            px[k] = x, py[k] = y;
        }
    }
    for (; q < count_q; ++q) {
        const float* __restrict c = coefficients.ptr<float>(moved[q]) + begin;
        const float dx = delta[q].x, dy = delta[q].y;
        for (int k = 0; k < count; ++k) px[k] += c[k] * dx, py[k] += c[k] * dy;
    }
}

MULTICAGE_CPU_CLONES(void, accumulateDisplacements,
                     (const Mat& coefficients, const int* moved, const Point2f* delta, int count_q,
                      size_t begin, int count, float* __restrict px, float* __restrict py),
                     (coefficients, moved, delta, count_q, begin, count, px, py))
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC pop_options
#elif defined(__clang__)
#pragma clang fp contract(on)
#endif

}  // namespace

void Binding::apply(InputArray poseIn, OutputArray positionsOut) const {
    applyRows(*this, poseIn, positionsOut, {});
}

void applyRows(const Binding& b, InputArray poseIn, OutputArray positionsOut,
               const std::function<void(int, int)>& rowsDone) {
    CV_Assert(!b.empty());
    const std::vector<Point2f> pose = b.completePose(poseIn);
    // Displacement form p' = x + sum_j CC_j (v'_j - v_j): exact for the rest pose, and vertices
    // that did not move cost nothing.
    std::vector<int> moved;
    std::vector<Point2f> delta;
    for (int j = 0; j < b.coefficientCount(); ++j) {
        const Point2f d = pose[j] - b.restVertices[j];
        if (d.x != 0.f || d.y != 0.f) moved.push_back(j), delta.push_back(d);
    }
    positionsOut.create(b.gridSize, CV_32FC2);
    Mat positions = positionsOut.getMat();  // may be a view into a larger mesh (not continuous)
    const int m = b.gridSize.width, n = b.gridSize.height;
    // Blocks of whole rows, about 16384 nodes each (128 KB of running sums, in L2), at least two
    // per thread: each pass streams 4 coefficient planes 64 KB long, long enough for the hardware
    // prefetcher. (Blocks of 2048 nodes, sums in L1, streamed 8 KB per plane: at 1024x768 the sum
    // took 1.2-1.5x the time of one plain read of the coefficients, 16384 about 1.0x.)
    const int rowsPerBlock = std::max(1, std::min(16384 / m, n / (2 * getNumThreads())));
    const int blocks = (n + rowsPerBlock - 1) / rowsPerBlock;
    parallel_for_(Range(0, blocks), [&](const Range& r) {
        const int cap = rowsPerBlock * m;
        std::vector<float> px(cap), py(cap);
        for (int block = r.start; block < r.end; ++block) {
            const int gy0 = block * rowsPerBlock, gy1 = std::min(n, gy0 + rowsPerBlock);
            const size_t begin = static_cast<size_t>(gy0) * m;
            const int count = (gy1 - gy0) * m;
            for (int gy = gy0; gy < gy1; ++gy) {  // the rest positions, as node(gx, gy) gives them
                const float y = nodeCoordinate(gy, b.gridStep, b.imageSize.height);
                float* qx = px.data() + (gy - gy0) * m;
                float* qy = py.data() + (gy - gy0) * m;
                for (int gx = 0; gx < m; ++gx)
                    qx[gx] = nodeCoordinate(gx, b.gridStep, b.imageSize.width), qy[gx] = y;
            }
            accumulateDisplacements(b.coefficients, moved.data(), delta.data(),
                                    static_cast<int>(moved.size()), begin, count, px.data(),
                                    py.data());
            for (int gy = gy0; gy < gy1; ++gy) {
                Point2f* out = positions.ptr<Point2f>(gy);
                const float* qx = px.data() + (gy - gy0) * m;
                const float* qy = py.data() + (gy - gy0) * m;
                for (int gx = 0; gx < m; ++gx) out[gx] = Point2f(qx[gx], qy[gx]);
            }
            if (rowsDone) rowsDone(gy0, gy1);
        }
    });
}

namespace {

// A binding is hundreds of MB written once: backing it with 2 MB pages (where the kernel
// offers them on request) saves most of the page faults of the first touch.
void adviseHugePages(Mat& m) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    constexpr uintptr_t kHuge = 2u << 20;
    const uintptr_t begin = (reinterpret_cast<uintptr_t>(m.data) + kHuge - 1) & ~(kHuge - 1);
    const uintptr_t end =
        (reinterpret_cast<uintptr_t>(m.data) + m.total() * m.elemSize()) & ~(kHuge - 1);
    if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#endif
}

// 8 doubles / 8 floats as GCC vector types (unaligned loads and stores through memcpy). Only
// used inside this file's inlined code, so GCC's note that passing AVX-sized types without AVX
// changes the ABI does not concern us (-Wpsabi is off for this file).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif
typedef double v8d __attribute__((vector_size(64)));
typedef float v8f __attribute__((vector_size(32)));
typedef long long v8i __attribute__((vector_size(64)));
inline v8d load8d(const double* p) {
    v8d r;
    std::memcpy(&r, p, sizeof r);
    return r;
}
inline v8f load8f(const float* p) {
    v8f r;
    std::memcpy(&r, p, sizeof r);
    return r;
}
inline void store8d(double* p, v8d v) {
    std::memcpy(p, &v, sizeof v);
}
inline v8d absd(v8d v) {  // std::abs: the sign bit cleared
    return reinterpret_cast<v8d>(reinterpret_cast<v8i>(v) & (v8i{} + 0x7fffffffffffffffLL));
}

struct BoundPolygon {
    std::vector<Point2f> v;
    int first;   // coefficient index of vertex 0
    float sign;  // +1 or -1: the raw weights as if the polygon obeyed the orientation rule
};

// Per node of a row, in double: the total W = sum_j w_j, sum_j |w_j|, and the first moments
// sum_j w_j (v_j - x) that measure the linear-precision residual.
struct RowSums {
    std::vector<double> xs, W, absW, sx, sy;
    explicit RowSums(int m) : xs(m), W(m), absW(m), sx(m), sy(m) {}
    void clear() {
        for (auto* a : {&W, &absW, &sx, &sy}) std::fill(a->begin(), a->end(), 0.0);
    }
};

// The sums of nodes [k0, k0 + K) of a row.
struct SumsAt {
    double *xs, *W, *absW, *sx, *sy;
    SumsAt(RowSums& s, int k0)
        : xs(s.xs.data() + k0),
          W(s.W.data() + k0),
          absW(s.absW.data() + k0),
          sx(s.sx.data() + k0),
          sy(s.sy.data() + k0) {}
};

// Raw mean value weights, times `sign`, of polygon v[0..n) for the nodes (xs[k], y), k < m.
// Hormann & Floater 2006: t_i = tan(alpha_i / 2), w_i = (t_{i-1} + t_i) / r_i. The float
// kernel flags nodes on or near a vertex or an edge; those are redone in double by the caller.
// out[i] receives vertex i's row; tbuf is n*m scratch.
// keep (local mean value coordinates; nullptr: every node) is 0 at nodes whose region this
// polygon does not bound: their weights are 0, and nothing of this polygon flags them.
MULTICAGE_ALWAYS_INLINE void rawWeightsRowKernel(const Point2f* v, int n, float sign,
                                                 const float* xs, int m, float y, float* const* out,
                                                 float* tbuf, int* nearSingular, const SumsAt& sums,
                                                 const int* keep) {
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
        // det(s_i, s_{i+1}) = det(s_i, e_i) with the edge e_i = v_{i+1} - v_i: products of
        // size r*|e| instead of r^2, so far less cancellation in float near long edges.
        const float ex = v[j].x - v[i].x, ey = v[j].y - v[i].y;
        const float* ri = out[i];
        const float* rj = out[j];
        float* t = tbuf + static_cast<size_t>(i) * m;
        for (int k = 0; k < m; ++k) {
            const float dix = vix - xs[k], djx = vjx - xs[k];
            const float A = dix * ey - diy * ex;
            const float D = dix * djx + diy * djy;
            const float rr = ri[k] * rj[k];
            // One division: select numerator and denominator first.
            const float num = D > 0.f ? A : rr - D, den = D > 0.f ? rr + D : A;
            t[k] = sign * num / den;
            // near a vertex (r small) or an edge (A small while the edge is seen at > 90 deg)
            const bool bad = ri[k] < 1e-3f || (D <= 0.f && std::abs(A) < 1e-4f * rr);
            nearSingular[k] |= static_cast<int>(bad) & (keep ? keep[k] : 1);
        }
    }
    for (int i = 0; i < n; ++i) {  // w_i
        const float* __restrict tprev = tbuf + static_cast<size_t>(i == 0 ? n - 1 : i - 1) * m;
        const float* __restrict t = tbuf + static_cast<size_t>(i) * m;
        float* __restrict w = out[i];
        if (keep) {
            for (int k = 0; k < m; ++k) {
                const float wk = (tprev[k] + t[k]) / w[k];
                w[k] = keep[k] ? wk : 0.f;  // a select: NaN or inf of a far polygon is dropped
            }
        } else {
            for (int k = 0; k < m; ++k) w[k] = (tprev[k] + t[k]) / w[k];
        }
    }
    // The sums Algorithm 1 and the projection need, in double: for 8 nodes at a time, all n
    // vertices in order with the 8 nodes' sums kept in registers (GCC vector extensions: one
    // AVX-512 register per sum in that clone, two AVX ones in the AVX2 clone, four SSE ones in
    // the default one). Each node adds its terms in the same order as a vertex-by-vertex loop.
    double* W = sums.W;
    double* absW = sums.absW;
    double* sx = sums.sx;
    double* sy = sums.sy;
    const double* xd = sums.xs;
    int k = 0;
    for (; k + 8 <= m; k += 8) {
        v8d Ws = load8d(W + k), As = load8d(absW + k), Xs = load8d(sx + k), Ys = load8d(sy + k);
        const v8d xk = load8d(xd + k);
        for (int i = 0; i < n; ++i) {
            const double vx = v[i].x, dy = v[i].y - y;
            const v8d wd = __builtin_convertvector(load8f(out[i] + k), v8d);
            Ws += wd;
            As += absd(wd);
            Xs += wd * (vx - xk);
            Ys += wd * dy;
        }
        store8d(W + k, Ws), store8d(absW + k, As), store8d(sx + k, Xs), store8d(sy + k, Ys);
    }
    for (; k < m; ++k)
        for (int i = 0; i < n; ++i) {
            const double vx = v[i].x, dy = v[i].y - y;
            const double wd = out[i][k];
            W[k] += wd, absW[k] += std::abs(wd);
            sx[k] += wd * (vx - xd[k]), sy[k] += wd * dy;
        }
}

MULTICAGE_CPU_CLONES(void, rawWeightsRow,
                     (const Point2f* v, int n, float sign, const float* xs, int m, float y,
                      float* const* out, float* tbuf, int* nearSingular, const SumsAt& sums,
                      const int* keep),
                     (v, n, sign, xs, m, y, out, tbuf, nearSingular, sums, keep))

// Sums of the rest vertices' coordinates, for the Gram matrix of the linear-precision projection.
struct VertexMoments {
    double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
    VertexMoments() = default;
    explicit VertexMoments(const std::vector<Point2f>& v) {
        for (const Point2f& p : v) add(p);
    }
    void add(Point2f p) {
        n += 1, sx += p.x, sy += p.y;
        sxx += double(p.x) * p.x, sxy += double(p.x) * p.y, syy += double(p.y) * p.y;
    }
};

// Per node: 1 / W, the conditioning, and the projection's (l0, l1, l2) (see below). The moments
// by value and __restrict arrays: otherwise GCC must assume a store may change them, and leaves
// the loop scalar.
inline void projectionTerms(const VertexMoments mo, double y, int m, const double* __restrict xs,
                            const double* __restrict Ws, const double* __restrict absW,
                            const double* __restrict sx, const double* __restrict sy,
                            int* __restrict flags, double* __restrict kap, float* __restrict invOut,
                            float* __restrict l0Out, float* __restrict l1Out,
                            float* __restrict l2Out) {
    for (int k = 0; k < m; ++k) {
        const double x = xs[k], invW = 1.0 / Ws[k];
        const double kk = std::abs(Ws[k]) / absW[k];
        kap[k] = kk;
        flags[k] |= static_cast<int>(!(kk >= 1e-6));  // also catches NaN; no branch: vectorises
        const double a = mo.n, b = mo.sx - mo.n * x, cc = mo.sy - mo.n * y;
        const double d = mo.sxx - 2 * x * mo.sx + mo.n * x * x;
        const double e = mo.sxy - x * mo.sy - y * mo.sx + mo.n * x * y;
        const double f = mo.syy - 2 * y * mo.sy + mo.n * y * y;
        const double r1 = -sx[k] * invW, r2 = -sy[k] * invW;  // the sum is 1 by construction
        // Cramer's rule on the symmetric positive definite [[a b c] [b d e] [c e f]] (the frame
        // alone spans the plane), right-hand side (0, r1, r2).
        const double A = d * f - e * e, B = cc * e - b * f, C = b * e - cc * d;
        const double invDet = 1.0 / (a * A + b * B + cc * C);
        l0Out[k] = static_cast<float>((B * r1 + C * r2) * invDet);
        l1Out[k] = static_cast<float>(((a * f - cc * cc) * r1 + (b * cc - a * e) * r2) * invDet);
        l2Out[k] = static_cast<float>(((b * cc - a * e) * r1 + (a * d - b * b) * r2) * invDet);
        invOut[k] = static_cast<float>(invW);
    }
}

// Algorithm 1's division by the total, fused with a correction of the float kernel's rounding.
// That rounding leaves ~1e-7 relative noise in each raw weight, which at image coordinates of
// ~1000 px is up to 1e-3 px of linear-precision error. True mean value coordinates satisfy
// sum_j CC_j = 1 and sum_j CC_j (v_j - x) = 0 exactly, so projecting the computed ones
// orthogonally onto that affine set can only bring them closer to the truth:
// CC_j = w_j / W + l0 + l1 dx_j + l2 dy_j, (l0, l1, l2) from the 3x3 Gram system (in double).
// Writes each node's conditioning |W| / sum |w_j| to kappa and flags non-finite or cancelling
// totals in nearSingular (the caller redoes those nodes exactly).
// active (local mean value coordinates; nullptr: all) flags the vertices of the polygons that
// bound the nodes' region: the projection spreads over those alone (M holds their moments), and
// the others stay exactly 0.
MULTICAGE_ALWAYS_INLINE void normalizeAndProjectKernel(float* const* out, int c, const Point2f* v,
                                                       const VertexMoments& M, double y, int m,
                                                       const SumsAt& s, int* nearSingular,
                                                       double* kappa, float* inv, float* l0,
                                                       float* l1, float* l2,
                                                       const unsigned char* active) {
    projectionTerms(M, y, m, s.xs, s.W, s.absW, s.sx, s.sy, nearSingular, kappa, inv, l0, l1, l2);
    for (int j = 0; j < c; ++j) {
        const float vx = v[j].x, dy = static_cast<float>(v[j].y - y);
        float* w = out[j];
        if (active && !active[j]) {
            std::fill(w, w + m, 0.f);
            continue;
        }
        for (int k = 0; k < m; ++k) {
            const float dx = vx - static_cast<float>(s.xs[k]);
            w[k] = w[k] * inv[k] + (l0[k] + l1[k] * dx + l2[k] * dy);
        }
    }
}

MULTICAGE_CPU_CLONES(void, normalizeAndProject,
                     (float* const* out, int c, const Point2f* v, const VertexMoments& M, double y,
                      int m, const SumsAt& s, int* nearSingular, double* kappa, float* inv,
                      float* l0, float* l1, float* l2, const unsigned char* active),
                     (out, c, v, M, y, m, s, nearSingular, kappa, inv, l0, l1, l2, active))

// Algorithm 1 for one node in double precision, with the exact vertex/edge policy.
// Writes the c coefficients to cc and returns the conditioning |sum w| / sum |w|.
// keep (local mean value coordinates; empty: all): the polygons bounding x's region.
double bindNodeExact(const std::vector<BoundPolygon>& polygons, Point2d x, double* cc, int c,
                     const std::vector<bool>& keep = {}) {
    std::fill(cc, cc + c, 0.0);
    std::vector<Point2d> v;
    for (size_t q = 0; q < polygons.size(); ++q) {
        if (!keep.empty() && !keep[q]) continue;
        const BoundPolygon& p = polygons[q];
        v.assign(p.v.begin(), p.v.end());
        const MeanValueCase where =
            meanValueWeights(v.data(), static_cast<int>(v.size()), x, cc + p.first);
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

Binding emptyBinding(const Multicage& multicage, int coordinates, int gridStep) {
    Binding b;
    b.imageSize = multicage.imageSize();
    b.gridStep = gridStep;
    b.gridSize = gridSizeFor(b.imageSize, gridStep);
    b.coordinates = coordinates;
    b.restVertices = multicage.vertices();
    return b;
}

namespace {

// The frame is a polygon like the others (depth 0, A > 0), its corners the last 4 slots (c is
// the coefficient count); *maxN: the most vertices of one polygon, at least 4.
std::vector<BoundPolygon> boundPolygons(const Multicage& multicage, int c, int* maxN) {
    std::vector<BoundPolygon> polygons;
    for (int p = 0; p < multicage.polygonCount(); ++p) {
        BoundPolygon bp{multicage.polygon(p), multicage.polygonOffset(p), 1.f};
        bp.sign = static_cast<float>(orientationSign(multicage, p));
        *maxN = std::max(*maxN, static_cast<int>(bp.v.size()));
        polygons.push_back(std::move(bp));
    }
    polygons.push_back(BoundPolygon{multicage.frame(), c - 4, 1.f});
    return polygons;
}

// Local mean value coordinates: per region, the polygons bounding it (their raw weights are the
// only ones summed there), their vertices, and those vertices' moments.
struct LocalBinding {
    std::unique_ptr<LocalRegions> regions;
    std::vector<std::vector<bool>> boundingPolygons;
    std::vector<std::vector<unsigned char>> activeVertices;
    std::vector<VertexMoments> regionMoments;

    LocalBinding(const Multicage& multicage, const std::vector<BoundPolygon>& polygons, int c)
        : regions(new LocalRegions(multicage)) {
        const int R = regions->frame() + 1;
        boundingPolygons.assign(R, std::vector<bool>(polygons.size()));
        activeVertices.assign(R, std::vector<unsigned char>(c));
        regionMoments.resize(R);
        for (int r = 0; r < R; ++r)
            for (size_t q = 0; q < polygons.size(); ++q) {
                if (!regions->bounds(static_cast<int>(q), r)) continue;
                boundingPolygons[r][q] = true;
                for (size_t i = 0; i < polygons[q].v.size(); ++i) {
                    activeVertices[r][polygons[q].first + i] = 1;
                    regionMoments[r].add(polygons[q].v[i]);
                }
            }
    }
};

// Binds rows of nodes with mean value coordinates (Algorithm 1 a row at a time, the linear-
// precision projection, the exact redo of near-singular nodes), with one thread's scratch; it
// keeps the worst-conditioned node it bound.
class RowBinder {
  public:
    // The row in chunks of nodes small enough that every pass over a chunk (distances,
    // half-angle tangents, weights and sums, normalisation) stays in the L1/L2 cache. Each
    // node's arithmetic is the same whatever the chunk.
    static constexpr int kChunk = 256;

    double worst = 2.0;  // the least conditioning |W| / sum |w_j| bound so far, and where
    Point2f worstAt;

    // local: nullptr for (global) mean value coordinates; maxN: the most vertices of a polygon.
    RowBinder(Binding& b, const std::vector<BoundPolygon>& polygons, const VertexMoments& moments,
              const LocalBinding* local, int maxN)
        : b_(b),
          polygons_(polygons),
          moments_(moments),
          local_(local),
          c_(b.coefficientCount()),
          m_(b.gridSize.width),
          xs_(m_),
          tbuf_(static_cast<size_t>(maxN) * kChunk),
          inv_(kChunk),
          l0_(kChunk),
          l1_(kChunk),
          l2_(kChunk),
          kappa_(m_),
          sums_(m_),
          nearSingular_(m_),
          region_(local ? m_ : 0),
          keep_(local ? kChunk : 0),
          runOut_(local ? c_ : 0),
          out_(c_),
          chunkOut_(c_),
          exact_(c_) {
        for (int gx = 0; gx < m_; ++gx) xs_[gx] = b.node(gx, 0).x, sums_.xs[gx] = xs_[gx];
    }

    void bindRow(int gy) {
        const double y = b_.node(0, gy).y;
        for (int j = 0; j < c_; ++j)
            out_[j] = b_.coefficients.ptr<float>(j) + static_cast<size_t>(gy) * m_;
        std::fill(nearSingular_.begin(), nearSingular_.end(), 0);
        sums_.clear();
        if (local_) local_->regions->regionsOfRow(xs_.data(), m_, y, region_.data());
        for (int k0 = 0; k0 < m_; k0 += kChunk) {
            const int K = std::min(kChunk, m_ - k0);
            for (int j = 0; j < c_; ++j) chunkOut_[j] = out_[j] + k0;
            const SumsAt at(sums_, k0);
            rawWeights(k0, K, y, at);
            if (local_)
                projectRegionRuns(k0, K, y);
            else
                normalizeAndProject(chunkOut_.data(), c_, b_.restVertices.data(), moments_, y, K,
                                    at, nearSingular_.data() + k0, kappa_.data() + k0, inv_.data(),
                                    l0_.data(), l1_.data(), l2_.data(), nullptr);
        }
        redoNearSingular(y);
    }

  private:
    // Every polygon's raw weights at nodes [k0, k0 + K), into chunkOut_ and the row's sums.
    void rawWeights(int k0, int K, double y, const SumsAt& at) {
        for (size_t q = 0; q < polygons_.size(); ++q) {
            const BoundPolygon& p = polygons_[q];
            if (local_) {  // a polygon bounding no region of this chunk adds nothing
                int any = 0;
                for (int k = 0; k < K; ++k)
                    any |= keep_[k] = local_->regions->bounds(static_cast<int>(q), region_[k0 + k]);
                if (!any) continue;  // its weights here: zeroed by the projection
            }
            rawWeightsRow(p.v.data(), static_cast<int>(p.v.size()), p.sign, xs_.data() + k0, K,
                          float(y), chunkOut_.data() + p.first, tbuf_.data(),
                          nearSingular_.data() + k0, at, local_ ? keep_.data() : nullptr);
        }
    }

    // Local coordinates: each run of nodes of one region is projected onto that region's
    // vertices.
    void projectRegionRuns(int k0, int K, double y) {
        for (int a = 0; a < K;) {
            const int r = region_[k0 + a];
            int e = a + 1;
            while (e < K && region_[k0 + e] == r) ++e;
            for (int j = 0; j < c_; ++j) runOut_[j] = chunkOut_[j] + a;
            normalizeAndProject(
                runOut_.data(), c_, b_.restVertices.data(), local_->regionMoments[r], y, e - a,
                SumsAt(sums_, k0 + a), nearSingular_.data() + k0 + a, kappa_.data() + k0 + a,
                inv_.data(), l0_.data(), l1_.data(), l2_.data(), local_->activeVertices[r].data());
            a = e;
        }
    }

    // The row's near-singular nodes again, exactly (bindNodeExact); the worst conditioning.
    void redoNearSingular(double y) {
        for (int k = 0; k < m_; ++k) {
            if (nearSingular_[k]) {
                kappa_[k] = bindNodeExact(
                    polygons_, Point2d(xs_[k], y), exact_.data(), c_,
                    local_ ? local_->boundingPolygons[region_[k]] : std::vector<bool>());
                for (int j = 0; j < c_; ++j) out_[j][k] = static_cast<float>(exact_[j]);
            }
            if (kappa_[k] < worst) worst = kappa_[k], worstAt = Point2f(xs_[k], float(y));
        }
    }

    Binding& b_;
    const std::vector<BoundPolygon>& polygons_;
    const VertexMoments& moments_;
    const LocalBinding* local_;
    const int c_, m_;  // coefficients, nodes of a row
    std::vector<float> xs_, tbuf_, inv_, l0_, l1_, l2_;
    std::vector<double> kappa_;
    RowSums sums_;
    std::vector<int> nearSingular_;  // int, not uchar: the AVX2 kernel needs no packing
    std::vector<int> region_, keep_;
    std::vector<float*> runOut_, out_, chunkOut_;
    std::vector<double> exact_;
};

}  // namespace

Binding bind(const Multicage& multicage, int coordinates, int gridStep) {
    std::string why;
    if (!multicage.validateGeometry(&why))
        CV_Error(Error::StsBadArg, "multicage: cannot bind: " + why);
    coordinates = resolveCoordinates(multicage, coordinates);
    if (coordinates == HARMONIC) return bindHarmonic(multicage, gridStep);
    if (coordinates != MEAN_VALUE && coordinates != LOCAL_MEAN_VALUE)
        CV_Error_(Error::StsOutOfRange, ("multicage: unknown coordinate type %d", coordinates));
    const bool local = coordinates == LOCAL_MEAN_VALUE;
    Binding b = emptyBinding(multicage, coordinates, gridStep);
    const int c = b.coefficientCount(), N = b.nodeCount();

    int maxN = 4;
    const std::vector<BoundPolygon> polygons = boundPolygons(multicage, c, &maxN);
    const VertexMoments moments(b.restVertices);
    std::unique_ptr<LocalBinding> localBinding;
    if (local) localBinding.reset(new LocalBinding(multicage, polygons, c));
    b.coefficients.create(c, N, CV_32F);
    adviseHugePages(b.coefficients);
    std::mutex worstLock;
    double worst = 2.0;
    Point2f worstAt;
    parallel_for_(Range(0, b.gridSize.height), [&](const Range& rows) {
        RowBinder binder(b, polygons, moments, localBinding.get(), maxN);
        for (int gy = rows.start; gy < rows.end; ++gy) binder.bindRow(gy);
        std::lock_guard<std::mutex> lock(worstLock);
        if (binder.worst < worst || (binder.worst == worst && (binder.worstAt.y < worstAt.y)))
            worst = binder.worst, worstAt = binder.worstAt;
    });
    b.minConditioning = std::min(worst, 1.0);
    b.worstNode = worstAt;
    return b;
}

}  // namespace multicage
}  // namespace cv

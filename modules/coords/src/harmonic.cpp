// Harmonic coordinates of a multicage on the node grid (DeRose & Meyer 2006).
//
// Discretisation. The unknowns are the grid nodes; the Dirichlet boundary is the union of all
// closed polygon edges and the image frame, carrying the hat function of each vertex (1 at the
// vertex, linear along its two edges, 0 elsewhere). Each node talks to its 4 neighbours along
// grid links. A link that meets the boundary is cut at the first point where it does, and
// the node sees the boundary value there at the shortened distance (Shortley & Weller 1938).
// We weight each link by conductance w/h (w: the width of the node's dual cell across the
// link, h: the link's length, shortened or not) and drop Shortley-Weller's 2/(h_E + h_W)
// row scaling; the rows are then a symmetric finite-volume stencil:
//     sum_links w_l / h_l (u_i - u_l) = 0.
// Why this form:
//   - the matrix is symmetric positive definite (an M-matrix): one sparse LDL^T per region,
//     reused for every vertex, and a discrete maximum principle, so coefficients lie in [0, 1];
//   - opposite links of a node have equal w, so any linear function with linear boundary data
//     solves the system exactly: linear precision holds to solver precision on any grid step,
//     including the shorter last row and column and the half-pixel links to the frame;
//   - a link crossing a polygon is always cut, so regions on two sides of a polygon share no
//     equation: they are separate systems, and coefficients are exactly 0 across polygons.
// A node within kHarmonicOnEdgeTolerance of an edge is itself a Dirichlet node carrying the
// edge's values, so nodes on an edge interpolate it exactly (docs/harmonic/README.md,
// Discretisation).
#include "harmonic.hpp"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <opencv2/core/utility.hpp>
#include <vector>

namespace cv {
namespace multicage {

namespace {

// Progress reports from any thread, one at a time; once the callback says stop, every later
// step is skipped and the binding throws at the next checkpoint.
class ProgressReporter {
  public:
    explicit ProgressReporter(const BindProgress& callback) : callback_(callback) {}
    void report(double fraction) {
        if (!callback_ || cancelled_) return;
        std::lock_guard<std::mutex> lock(lock_);
        // Threads compute their fractions before taking the lock: never report a step back.
        last_ = std::min(1.0, std::max(last_, fraction));
        if (!cancelled_ && !callback_(last_)) cancelled_ = true;
    }
    bool cancelled() const { return cancelled_; }
    void throwIfCancelled() const {
        if (cancelled_)
            CV_Error(Error::StsError,
                     std::string("multicage: harmonic coordinates: ") + kBindCancelled);
    }

  private:
    const BindProgress& callback_;
    std::mutex lock_;
    double last_ = 0.0;
    std::atomic<bool> cancelled_{false};
};

// Share of the whole binding each stage takes (measured on the butterfly multicage at 1.6
// megapixels, grid step 1: boundary, regions and stencils 8 %, factorisations 80 %, solves
// 12 %). The factorisation of one region reports only when it ends.
constexpr double kAssemblyShare = 0.08, kFactorShare = 0.80;

// Link directions; kOpposite[d] is the reverse of d.
enum Direction { kEast = 0, kWest = 1, kSouth = 2, kNorth = 3 };
constexpr int kOpposite[4] = {kWest, kEast, kNorth, kSouth};

// A boundary value: the hat functions of the edge (a, b) at a point wa of the way from b to a,
// i.e. coefficient a gets wa and b gets 1 - wa. On a vertex a == b or wa is 0 or 1.
struct HatValue {
    int a = -1, b = -1;
    double wa = 0.0;
};

// Where a link from a node first meets the boundary, or a node on the boundary (dist 0).
struct Hit {
    double dist;
    HatValue value;
};

// Node positions along one grid axis, with the frame half a pixel beyond either end:
// position(-1) = -0.5, position(k) = min(k*step, size-1), position(count) = size - 0.5.
struct Axis {
    int count, step, size;
    double position(int k) const {
        if (k < 0) return -0.5;
        if (k >= count) return size - 0.5;
        return std::min(k * step, size - 1);
    }
    // Largest k in [-1, count - 1] with position(k) <= p: the link (k, k+1) holds p.
    int below(double p) const {
        int k = p < 0 ? -1 : std::min(static_cast<int>(std::floor(p / step)), count - 1);
        while (k + 1 < count && position(k + 1) <= p) ++k;
        while (k >= 0 && position(k) > p) --k;
        return k;
    }
};

// The boundary seen from the grid: per node, its Dirichlet value if it lies on the boundary,
// and per node and direction the nearest boundary point along that link.
class BoundaryMap {
  public:
    BoundaryMap(const Axis& xs, const Axis& ys) : xs_(xs), ys_(ys) {
        const size_t N = static_cast<size_t>(xs.count) * ys.count;
        onBoundary_.assign(N, -1);
        for (std::vector<int>& h : linkHit_) h.assign(N, -1);
    }

    // Every point where the closed edge p -> q (vertices a -> b) meets a grid line.
    void addEdge(Point2d p, Point2d q, int a, int b) {
        scanLines(p, q, a, b, /*rows=*/true);
        scanLines(p, q, a, b, /*rows=*/false);
    }

    int nodeIndex(int gx, int gy) const { return gy * xs_.count + gx; }
    const Hit* dirichlet(int node) const {
        return onBoundary_[node] < 0 ? nullptr : &hits_[onBoundary_[node]];
    }
    const Hit* linkHit(int node, int d) const {
        const int h = linkHit_[d][node];
        return h < 0 ? nullptr : &hits_[h];
    }

  private:
    // Intersections with the rows (y = const, rows == true) or the columns. Everything is
    // written for rows; for columns the roles of x and y swap.
    void scanLines(Point2d p, Point2d q, int a, int b, bool rows) {
        const Axis& across = rows ? ys_ : xs_;                      // the lines' fixed coordinate
        const double pu = rows ? p.y : p.x, qu = rows ? q.y : q.x;  // across the lines
        const double pv = rows ? p.x : p.y, qv = rows ? q.x : q.y;  // along the lines
        const double lo = std::min(pu, qu), hi = std::max(pu, qu);
        for (int k = std::max(0, across.below(lo)); k < across.count; ++k) {
            const double line = across.position(k);
            if (line > hi) break;
            if (line < lo) continue;
            if (pu == qu) {  // the edge lies on this line: its endpoints and every node between
                const Axis& along = rows ? xs_ : ys_;
                addPoint(rows, k, pv, HatValue{a, b, 1.0});
                addPoint(rows, k, qv, HatValue{a, b, 0.0});
                const double vlo = std::min(pv, qv), vhi = std::max(pv, qv);
                for (int j = std::max(0, along.below(vlo)); j < along.count; ++j) {
                    const double v = along.position(j);
                    if (v > vhi) break;
                    if (v > vlo) addPoint(rows, k, v, HatValue{a, b, 1.0 - (v - pv) / (qv - pv)});
                }
                continue;
            }
            // Exact at the endpoints, so that a vertex on a node lands on it.
            const double t = line == pu ? 0.0 : line == qu ? 1.0 : (line - pu) / (qu - pu);
            const double v = t == 0.0 ? pv : t == 1.0 ? qv : pv + t * (qv - pv);
            addPoint(rows, k, v, HatValue{a, b, 1.0 - t});
        }
    }

    // A boundary point at coordinate v along grid line `line` (a row when rows is true).
    void addPoint(bool rows, int line, double v, const HatValue& value) {
        const Axis& along = rows ? xs_ : ys_;
        const int k = along.below(v);
        const auto node = [&](int j) { return rows ? nodeIndex(j, line) : nodeIndex(line, j); };
        for (int j : {k, k + 1}) {
            if (j >= 0 && j < along.count &&
                std::abs(along.position(j) - v) <= kHarmonicOnEdgeTolerance) {
                int& slot = onBoundary_[node(j)];
                if (slot < 0) slot = push(Hit{0.0, value});
                return;
            }
        }
        // Strictly inside the link from node k to node k+1 (either may be the frame beyond
        // the last node): each end keeps the nearest boundary point.
        const int forward = rows ? kEast : kSouth;
        if (k >= 0 && k < along.count) keepNearest(node(k), forward, v - along.position(k), value);
        if (k + 1 < along.count)
            keepNearest(node(k + 1), kOpposite[forward], along.position(k + 1) - v, value);
    }

    void keepNearest(int node, int d, double dist, const HatValue& value) {
        int& slot = linkHit_[d][node];
        if (slot < 0)
            slot = push(Hit{dist, value});
        else if (dist < hits_[slot].dist)
            hits_[slot] = Hit{dist, value};
    }

    int push(const Hit& h) {
        hits_.push_back(h);
        return static_cast<int>(hits_.size()) - 1;
    }

    Axis xs_, ys_;
    std::vector<Hit> hits_;
    std::vector<int> onBoundary_;  // index into hits_ or -1
    std::vector<int> linkHit_[4];  // per direction: index into hits_ or -1
};

using SparseMatrixD = Eigen::SparseMatrix<double>;
using Factor = Eigen::SimplicialLDLT<SparseMatrixD, Eigen::Lower, Eigen::AMDOrdering<int>>;

// Right-hand sides solved together: the factor is read once per block, not once per column.
constexpr int kBlock = 8;

// Solves A X = B for one block of right-hand sides with the factor P A P^T = L D L^T.
// Y holds P B row-major (n x kBlock) on entry and P X on exit. Eigen's sparse triangular
// solves take one column at a time; with 70-odd columns sharing one factor the solve is
// bound by reading L, so a block of columns per pass is several times faster.
void solveBlock(const Factor& factor, double* Y) {
    const SparseMatrixD& L = factor.matrixL().nestedExpression();  // unit lower, diagonal unused
    const Eigen::VectorXd& D = factor.vectorD();
    const int n = static_cast<int>(L.cols());
    for (int j = 0; j < n; ++j) {  // L Z = Y, by columns of L
        const double* yj = Y + static_cast<size_t>(j) * kBlock;
        for (SparseMatrixD::InnerIterator it(L, j); it; ++it) {
            if (it.index() <= j) continue;
            double* yi = Y + static_cast<size_t>(it.index()) * kBlock;
            const double l = it.value();
            for (int q = 0; q < kBlock; ++q) yi[q] -= l * yj[q];
        }
    }
    for (int j = 0; j < n; ++j) {  // D W = Z
        const double inv = 1.0 / D[j];
        double* yj = Y + static_cast<size_t>(j) * kBlock;
        for (int q = 0; q < kBlock; ++q) yj[q] *= inv;
    }
    for (int j = n - 1; j >= 0; --j) {  // L^T X = W, by rows of L^T
        double* yj = Y + static_cast<size_t>(j) * kBlock;
        for (SparseMatrixD::InnerIterator it(L, j); it; ++it) {
            if (it.index() <= j) continue;
            const double* yi = Y + static_cast<size_t>(it.index()) * kBlock;
            const double l = it.value();
            for (int q = 0; q < kBlock; ++q) yj[q] -= l * yi[q];
        }
    }
}

// One region of the grid: the unknown nodes that talk to each other, its Laplace matrix and,
// per vertex its boundary touches, the right-hand side of that vertex's hat function.
struct Region {
    std::vector<int> nodes;  // global node indices; local index = position here
    std::vector<Eigen::Triplet<double>> entries;
    std::vector<int> vertices;                             // columns to solve for
    std::vector<std::vector<std::pair<int, double>>> rhs;  // per column: (local row, value)
    std::unique_ptr<Factor> factor;
};

// A coefficient of the binding. The exact solution lies in [0, 1] (discrete maximum principle);
// what falls outside by rounding is clamped, anything larger is left for the tests to see.
void writeCoefficient(Mat& coefficients, int vertex, int node, double value) {
    if (value < 0.0 && value > -1e-9) value = 0.0;
    if (value > 1.0 && value < 1.0 + 1e-9) value = 1.0;
    coefficients.at<float>(vertex, node) = static_cast<float>(value);
}

void writeHat(Mat& coefficients, int node, const HatValue& h) {
    writeCoefficient(coefficients, h.a, node, h.wa);
    if (h.b != h.a) writeCoefficient(coefficients, h.b, node, 1.0 - h.wa);
}

// Step 1. The Dirichlet boundary on the grid: user polygons and the frame (its vertices
// numbered from firstFrameVertex), every edge closed.
BoundaryMap boundaryOnGrid(const Multicage& multicage, const Axis& xs, const Axis& ys,
                           int firstFrameVertex) {
    BoundaryMap boundary(xs, ys);
    const auto addPolygon = [&](const std::vector<Point2f>& v, int first) {
        const int n = static_cast<int>(v.size());
        for (int i = 0; i < n; ++i) {
            const int j = (i + 1) % n;
            boundary.addEdge(Point2d(v[i]), Point2d(v[j]), first + i, first + j);
        }
    };
    for (int p = 0; p < multicage.polygonCount(); ++p)
        addPolygon(multicage.polygon(p), multicage.polygonOffset(p));
    addPolygon(multicage.frame(), firstFrameVertex);
    return boundary;
}

// Step 2. Regions: unknown nodes joined by uncut links (flood fill). Nodes on the boundary
// get their Dirichlet values in `coefficients` and are counted in *dirichletNodes.
std::vector<Region> findRegions(const BoundaryMap& boundary, const Axis& xs, const Axis& ys,
                                Mat& coefficients, int* dirichletNodes) {
    const int N = xs.count * ys.count;
    std::vector<int> label(N, -1);
    std::vector<Region> regions;
    *dirichletNodes = 0;
    std::vector<int> stack;
    for (int start = 0; start < N; ++start) {
        if (const Hit* h = boundary.dirichlet(start)) {
            writeHat(coefficients, start, h->value);
            ++*dirichletNodes;
            continue;
        }
        if (label[start] >= 0) continue;
        const int r = static_cast<int>(regions.size());
        regions.emplace_back();
        std::vector<int>& nodes = regions.back().nodes;
        label[start] = r;
        stack.assign(1, start);
        while (!stack.empty()) {
            const int i = stack.back();
            stack.pop_back();
            nodes.push_back(i);
            const int gx = i % xs.count, gy = i / xs.count;
            const int next[4] = {gx + 1 < xs.count ? i + 1 : -1, gx > 0 ? i - 1 : -1,
                                 gy + 1 < ys.count ? i + xs.count : -1, gy > 0 ? i - xs.count : -1};
            for (int d = 0; d < 4; ++d) {
                const int j = next[d];
                if (j < 0 || boundary.linkHit(i, d) || boundary.dirichlet(j) || label[j] >= 0)
                    continue;
                label[j] = r;
                stack.push_back(j);
            }
        }
    }
    return regions;
}

// What the stencil rows of every region read: the boundary, the grid, the dual cell widths
// and each unknown node's local index in its region.
struct StencilGrid {
    const BoundaryMap& boundary;
    const Axis &xs, &ys;
    // Dual cell widths (finite-volume weights): half the distance between the neighbouring
    // grid lines, the frame counting as a line. Equal for a node's two opposite links.
    std::vector<double> dualX, dualY;
    std::vector<int> local;  // per node: its index in its region, -1 on the boundary
};

// The stencil rows of one region. `column` maps a vertex to its right-hand side's column in
// this region (-1: none yet); it comes back all -1.
void assembleRegion(Region& region, const StencilGrid& g, std::vector<int>& column) {
    const Axis &xs = g.xs, &ys = g.ys;
    const auto addRhs = [&](int row, int vertex, double value) {
        if (value == 0.0) return;
        if (column[vertex] < 0) {
            column[vertex] = static_cast<int>(region.vertices.size());
            region.vertices.push_back(vertex);
            region.rhs.emplace_back();
        }
        region.rhs[column[vertex]].emplace_back(row, value);
    };
    region.entries.reserve(region.nodes.size() * 3);
    for (size_t row = 0; row < region.nodes.size(); ++row) {
        const int i = region.nodes[row];
        const int gx = i % xs.count, gy = i / xs.count;
        const double spacing[4] = {
            xs.position(gx + 1) - xs.position(gx), xs.position(gx) - xs.position(gx - 1),
            ys.position(gy + 1) - ys.position(gy), ys.position(gy) - ys.position(gy - 1)};
        const double width[4] = {g.dualY[gy], g.dualY[gy], g.dualX[gx], g.dualX[gx]};
        const int next[4] = {i + 1, i - 1, i + xs.count, i - xs.count};
        double diagonal = 0.0;
        for (int d = 0; d < 4; ++d) {
            const Hit* cut = g.boundary.linkHit(i, d);
            // No cut and no neighbour only happens beyond the last node, and the frame
            // always cuts there; a cut link ends on the boundary.
            CV_DbgAssert(cut || (d == kEast    ? gx + 1 < xs.count
                                 : d == kWest  ? gx > 0
                                 : d == kSouth ? gy + 1 < ys.count
                                               : gy > 0));
            const Hit* end = cut ? cut : g.boundary.dirichlet(next[d]);
            const double conductance = width[d] / (cut ? cut->dist : spacing[d]);
            diagonal += conductance;
            if (end) {
                addRhs(static_cast<int>(row), end->value.a, conductance * end->value.wa);
                if (end->value.b != end->value.a)
                    addRhs(static_cast<int>(row), end->value.b,
                           conductance * (1.0 - end->value.wa));
            } else if (next[d] < i) {  // the lower triangle is all LDL^T reads
                region.entries.emplace_back(static_cast<int>(row), g.local[next[d]], -conductance);
            }
        }
        region.entries.emplace_back(static_cast<int>(row), static_cast<int>(row), diagonal);
    }
    for (int v : region.vertices) column[v] = -1;
}

// Step 3. Per region: the stencil rows. Cut links and links to Dirichlet nodes go to the
// right-hand side, one column per vertex (of `vertexCount`) whose hat function is non-zero
// there.
void assembleStencils(std::vector<Region>& regions, const BoundaryMap& boundary, const Axis& xs,
                      const Axis& ys, int vertexCount) {
    StencilGrid g{boundary, xs, ys, {}, {}, {}};
    g.dualX.resize(xs.count);
    g.dualY.resize(ys.count);
    for (int k = 0; k < xs.count; ++k) g.dualX[k] = 0.5 * (xs.position(k + 1) - xs.position(k - 1));
    for (int k = 0; k < ys.count; ++k) g.dualY[k] = 0.5 * (ys.position(k + 1) - ys.position(k - 1));
    // Local indices in node order, so that local[j] < local[i] exactly when j < i.
    g.local.assign(static_cast<size_t>(xs.count) * ys.count, -1);
    for (Region& region : regions) {
        std::sort(region.nodes.begin(), region.nodes.end());
        for (size_t k = 0; k < region.nodes.size(); ++k)
            g.local[region.nodes[k]] = static_cast<int>(k);
    }
    parallel_for_(Range(0, static_cast<int>(regions.size())), [&](const Range& range) {
        std::vector<int> column(vertexCount, -1);
        for (int r = range.start; r < range.end; ++r) assembleRegion(regions[r], g, column);
    });
}

// Step 4. One factorisation per region (largest first, so the long one starts at once).
// Returns the regions in that order; adds the sizes of the systems to *stats.
std::vector<int> factorise(std::vector<Region>& regions, ProgressReporter& progress,
                           HarmonicStats* stats) {
    std::vector<int> order(regions.size());
    for (size_t r = 0; r < regions.size(); ++r) order[r] = static_cast<int>(r);
    std::sort(order.begin(), order.end(),
              [&](int a, int b) { return regions[a].nodes.size() > regions[b].nodes.size(); });
    std::mutex statsLock;
    std::atomic<bool> failed{false};
    // Progress by nodes factorised (the cost grows faster than that, so the large region's
    // share is if anything understated and the bar never runs backwards).
    size_t unknownNodes = 0;
    for (const Region& region : regions) unknownNodes += region.nodes.size();
    std::atomic<size_t> factorised{0};
    parallel_for_(
        Range(0, static_cast<int>(order.size())),
        [&](const Range& range) {
            for (int k = range.start; k < range.end; ++k) {
                Region& region = regions[order[k]];
                if (progress.cancelled()) return;
                if (region.vertices.empty()) continue;  // enclosed by nothing resolvable: stays 0
                const int n = static_cast<int>(region.nodes.size());
                SparseMatrixD A(n, n);
                A.setFromTriplets(region.entries.begin(), region.entries.end());
                std::vector<Eigen::Triplet<double>>().swap(region.entries);
                region.factor.reset(new Factor(A));
                if (region.factor->info() != Eigen::Success) failed = true;
                std::lock_guard<std::mutex> lock(statsLock);
                stats->matrixNonZeros += static_cast<size_t>(A.nonZeros());
                stats->factorNonZeros +=
                    static_cast<size_t>(region.factor->matrixL().nestedExpression().nonZeros());
                factorised += region.nodes.size();
                progress.report(kAssemblyShare + kFactorShare * double(factorised) /
                                                     double(std::max<size_t>(1, unknownNodes)));
            }
        },
        static_cast<double>(order.size()));
    progress.throwIfCancelled();
    if (failed)
        CV_Error(Error::StsInternal,
                 "multicage: harmonic coordinates: a Laplace system could not be factorised");
    progress.report(kAssemblyShare + kFactorShare);
    return order;
}

// Solves one block of up to kBlock vertices of `region` (its columns from `first`) and writes
// their coefficients. Y and identity are the calling thread's scratch space.
void solveColumns(const Region& region, int first, Mat& coefficients, std::vector<double>& Y,
                  std::vector<int>& identity) {
    const int n = static_cast<int>(region.nodes.size());
    const int width = std::min(kBlock, static_cast<int>(region.vertices.size()) - first);
    // Row r of the system is row P[r] of the factor (no permutation: identity).
    const auto& perm = region.factor->permutationP().indices();
    if (perm.size() == 0 && static_cast<int>(identity.size()) < n)
        for (int r = static_cast<int>(identity.size()); r < n; ++r) identity.push_back(r);
    const int* P = perm.size() ? perm.data() : identity.data();
    Y.assign(static_cast<size_t>(n) * kBlock, 0.0);
    for (int q = 0; q < width; ++q)
        for (const auto& e : region.rhs[first + q])
            Y[static_cast<size_t>(P[e.first]) * kBlock + q] += e.second;
    solveBlock(*region.factor, Y.data());
    for (int q = 0; q < width; ++q)
        for (int row = 0; row < n; ++row)
            writeCoefficient(coefficients, region.vertices[first + q], region.nodes[row],
                             Y[static_cast<size_t>(P[row]) * kBlock + q]);
}

// Step 5. Solves in blocks of kBlock vertices per region, all sharing their region's factor,
// regions in `order`. Returns the number of (region, vertex) right-hand sides solved.
int solveAll(const std::vector<Region>& regions, const std::vector<int>& order,
             ProgressReporter& progress, Mat& coefficients) {
    std::vector<std::pair<int, int>> jobs;  // (region, first column)
    int solves = 0;
    for (int r : order) {
        solves += static_cast<int>(regions[r].vertices.size());
        for (size_t col = 0; col < regions[r].vertices.size(); col += kBlock)
            jobs.emplace_back(r, static_cast<int>(col));
    }
    std::atomic<size_t> solvedJobs{0};
    parallel_for_(
        Range(0, static_cast<int>(jobs.size())),
        [&](const Range& range) {
            std::vector<double> Y;
            std::vector<int> identity;
            for (int k = range.start; k < range.end; ++k) {
                if (progress.cancelled()) return;
                solveColumns(regions[jobs[k].first], jobs[k].second, coefficients, Y, identity);
                const size_t done = ++solvedJobs;
                progress.report(kAssemblyShare + kFactorShare +
                                (1.0 - kAssemblyShare - kFactorShare) * double(done) /
                                    double(jobs.size()));
            }
        },
        static_cast<double>(jobs.size()));
    progress.throwIfCancelled();
    return solves;
}

}  // namespace

Binding bindHarmonic(const Multicage& multicage, int gridStep, HarmonicStats* stats,
                     const BindProgress& progressCallback) {
    ProgressReporter progress(progressCallback);
    progress.report(0.0);
    Binding out = emptyBinding(multicage, HARMONIC, gridStep);
    out.minConditioning = 1.0;  // no cancellation: all weights are non-negative
    out.worstNode = Point2f(0, 0);
    const int c = out.coefficientCount(), N = out.nodeCount();
    const Axis xs{out.gridSize.width, gridStep, out.imageSize.width};
    const Axis ys{out.gridSize.height, gridStep, out.imageSize.height};
    out.coefficients = Mat::zeros(c, N, CV_32F);

    const BoundaryMap boundary = boundaryOnGrid(multicage, xs, ys, c - 4);  // 1.
    int dirichletNodes = 0;
    std::vector<Region> regions =  // 2.
        findRegions(boundary, xs, ys, out.coefficients, &dirichletNodes);
    progress.report(0.5 * kAssemblyShare);
    progress.throwIfCancelled();
    assembleStencils(regions, boundary, xs, ys, c);  // 3.
    progress.report(kAssemblyShare);
    progress.throwIfCancelled();
    HarmonicStats s;
    const std::vector<int> order = factorise(regions, progress, &s);  // 4.
    s.solves = solveAll(regions, order, progress, out.coefficients);  // 5.

    if (stats) {
        s.unknowns = N - dirichletNodes;
        s.dirichletNodes = dirichletNodes;
        s.components = static_cast<int>(regions.size());
        *stats = s;
    }
    return out;
}

}  // namespace multicage
}  // namespace cv

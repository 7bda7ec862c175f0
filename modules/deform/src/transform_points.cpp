// Points follow the image: the forward map of the deformed node mesh, exact at cage vertices
// (the rule is documented at transformPoints() in deformer.hpp).
#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>
#include <opencv2/multicage/deformer.hpp>
#include <opencv2/multicage/internal/point_input.hpp>
#include <unordered_map>
#include <vector>

namespace cv {
namespace multicage {

namespace {

/** The mesh the CPU rasteriser draws, seen from the rest side: node columns X and rows Y with
the frame ring included (X = -0.5, node x..., W - 0.5), and the deformed position of any of its
nodes, computed on demand (in double) and kept. */
class ForwardMesh {
  public:
    ForwardMesh(const Binding& b, const std::vector<Point2f>& pose) : b_(b) {
        const int m = b.gridSize.width, n = b.gridSize.height;
        W_ = b.imageSize.width, H_ = b.imageSize.height;
        X_.push_back(-0.5);
        for (int gx = 0; gx < m; ++gx) X_.push_back(b.node(gx, 0).x);
        X_.push_back(W_ - 0.5);
        Y_.push_back(-0.5);
        for (int gy = 0; gy < n; ++gy) Y_.push_back(b.node(0, gy).y);
        Y_.push_back(H_ - 0.5);
        const int c = b.coefficientCount();
        for (int j = 0; j < c; ++j) {
            const Point2d d = Point2d(pose[j]) - Point2d(b.restVertices[j]);
            if (d.x != 0 || d.y != 0) moved_.push_back(j), delta_.push_back(d);
        }
        for (int k = 0; k < 4; ++k) frame_[k] = Point2d(pose[c - 4 + k]);
    }

    const std::vector<double>& X() const { return X_; }
    const std::vector<double>& Y() const { return Y_; }

    /** The bilinear map of the frame corners (TL, TR, BR, BL) at p: where the ring puts its
    nodes (RasterMesh::setFrame), continued outside the frame. Written as the first corner plus
    the two sides plus the twist (zero for a frame that stays a parallelogram), not as the four
    corners' weights: far outside the frame those weights are huge and of both signs, and their
    sum cancelled to nothing (a point 1e20 px away lost its 3 px translation). */
    Point2d frameMap(Point2d p) const {
        const double u = (p.x + 0.5) / W_, v = (p.y + 0.5) / H_;
        const Point2d side1 = frame_[1] - frame_[0], side3 = frame_[3] - frame_[0];
        const Point2d twist = frame_[0] - frame_[1] + frame_[2] - frame_[3];
        return frame_[0] + u * side1 + v * side3 + (u * v) * twist;
    }

    /** Cell (ex, ey) of the ringed mesh holding p (inside the frame), and p's place in it. */
    void locate(Point2d p, int& ex, int& ey, double& u, double& v) const {
        ex = cellOf(X_, p.x), ey = cellOf(Y_, p.y);
        u = (p.x - X_[ex]) / (X_[ex + 1] - X_[ex]);
        v = (p.y - Y_[ey]) / (Y_[ey + 1] - Y_[ey]);
    }

    /** The piecewise linear map of the deformed mesh at p (inside the frame): triangles
    (a,b,c) and (b,d,c) of each cell, as the rasteriser draws them. */
    Point2d map(Point2d p) {
        int ex, ey;
        double u, v;
        locate(p, ex, ey, u, v);
        if (u + v <= 1) {
            const Point2d a = node(ex, ey), b = node(ex + 1, ey), c = node(ex, ey + 1);
            return a + u * (b - a) + v * (c - a);
        }
        const Point2d b = node(ex + 1, ey), c = node(ex, ey + 1), d = node(ex + 1, ey + 1);
        return d + (1 - u) * (c - d) + (1 - v) * (b - d);
    }

    bool insideFrame(Point2d p) const {
        return p.x >= -0.5 && p.x <= W_ - 0.5 && p.y >= -0.5 && p.y <= H_ - 0.5;
    }

  private:
    static int cellOf(const std::vector<double>& edges, double x) {
        const int k =
            static_cast<int>(std::upper_bound(edges.begin(), edges.end(), x) - edges.begin()) - 1;
        return std::min(std::max(k, 0), static_cast<int>(edges.size()) - 2);
    }

    // Deformed position of node (ex, ey) of the ringed mesh.
    Point2d node(int ex, int ey) {
        const int m = b_.gridSize.width, n = b_.gridSize.height;
        if (ex == 0 || ey == 0 || ex == m + 1 || ey == n + 1)
            return frameMap(Point2d(X_[ex], Y_[ey]));
        const long long key = static_cast<long long>(ey) * (m + 2) + ex;
        auto it = cache_.find(key);
        if (it != cache_.end()) return it->second;
        const int index = (ey - 1) * m + (ex - 1);
        Point2d p(X_[ex], Y_[ey]);
        for (size_t k = 0; k < moved_.size(); ++k)
            p += double(b_.coefficients.at<float>(moved_[k], index)) * delta_[k];
        cache_.emplace(key, p);
        return p;
    }

    const Binding& b_;
    double W_ = 0, H_ = 0;
    std::vector<double> X_, Y_;
    std::vector<int> moved_;
    std::vector<Point2d> delta_;
    Point2d frame_[4];
    std::unordered_map<long long, Point2d> cache_;
};

/** A tent in one axis: 0 at lo and hi, 1 at peak, linear between, 0 outside. */
struct Tent {
    double lo, peak, hi;
    double operator()(double x) const {
        if (x <= lo || x >= hi) return x == peak ? 1.0 : 0.0;
        return x <= peak ? (x - lo) / (peak - lo) : (hi - x) / (hi - peak);
    }
};

/** The tent of a cage vertex coordinate along the mesh lines `edges`: over the cell holding
it, or over the two cells either side when it lies on a mesh line. */
Tent tentAround(const std::vector<double>& edges, double x) {
    const int last = static_cast<int>(edges.size()) - 1;
    int k = static_cast<int>(std::upper_bound(edges.begin(), edges.end(), x) - edges.begin()) - 1;
    k = std::min(std::max(k, 0), last);
    if (edges[k] == x)  // on a line: both cells around it (the frame lines are never reached)
        return Tent{edges[std::max(k - 1, 0)], x, edges[std::min(k + 1, last)]};
    return Tent{edges[k], x, edges[std::min(k + 1, last)]};
}

struct VertexCorrection {
    Tent tx, ty;
    Point2d weight;  // solved so that every cage vertex lands on its pose position
    double at(Point2d p) const { return tx(p.x) * ty(p.y); }
};

/** The corrections of the user vertices: tents weighted so that map + sum of corrections is
exact at every cage vertex. Vertices whose tents overlap are solved together. */
std::vector<VertexCorrection> vertexCorrections(const Binding& b, const std::vector<Point2f>& pose,
                                                ForwardMesh& mesh) {
    const int users = b.coefficientCount() - 4;
    std::vector<VertexCorrection> out(users);
    std::vector<Point2d> residual(users);
    for (int j = 0; j < users; ++j) {
        const Point2d rest(b.restVertices[j]);
        out[j].tx = tentAround(mesh.X(), rest.x);
        out[j].ty = tentAround(mesh.Y(), rest.y);
        const Point2d landed = mesh.insideFrame(rest) ? mesh.map(rest) : mesh.frameMap(rest);
        residual[j] = Point2d(pose[j]) - landed;
    }
    // Clusters of vertices whose tents reach each other (union-find over pairs in range).
    std::vector<int> parent(users);
    std::iota(parent.begin(), parent.end(), 0);
    std::function<int(int)> root = [&](int i) {
        return parent[i] == i ? i : parent[i] = root(parent[i]);
    };
    std::vector<int> order(users);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(),
              [&](int a, int c) { return out[a].tx.lo < out[c].tx.lo; });
    for (size_t a = 0; a < order.size(); ++a)
        for (size_t c = a + 1; c < order.size() && out[order[c]].tx.lo < out[order[a]].tx.hi; ++c) {
            const int i = order[a], k = order[c];
            const Point2d vi(b.restVertices[i]), vk(b.restVertices[k]);
            if (out[i].at(vk) != 0 || out[k].at(vi) != 0) parent[root(i)] = root(k);
        }
    std::unordered_map<int, std::vector<int>> clusters;
    for (int j = 0; j < users; ++j) clusters[root(j)].push_back(j);
    for (const auto& entry : clusters) {
        const std::vector<int>& ids = entry.second;
        if (ids.size() == 1) {
            out[ids[0]].weight = residual[ids[0]];
            continue;
        }
        const int k = static_cast<int>(ids.size());
        Mat H(k, k, CV_64F), E(k, 2, CV_64F), C;
        for (int r = 0; r < k; ++r) {
            const Point2d vr(b.restVertices[ids[r]]);
            for (int c = 0; c < k; ++c) H.at<double>(r, c) = out[ids[c]].at(vr);
            E.at<double>(r, 0) = residual[ids[r]].x, E.at<double>(r, 1) = residual[ids[r]].y;
        }
        if (!solve(H, E, C, DECOMP_LU)) solve(H, E, C, DECOMP_SVD);  // least squares if singular
        for (int r = 0; r < k; ++r)
            out[ids[r]].weight = Point2d(C.at<double>(r, 0), C.at<double>(r, 1));
    }
    return out;
}

}  // namespace

void transformPoints(const Binding& binding, InputArray poseIn, InputArray pointsIn,
                     OutputArray dst) {
    if (binding.empty())
        CV_Error(Error::StsBadArg, "multicage: transformPoints: the binding is empty");
    const std::vector<Point2f> pose = binding.completePose(poseIn);
    const std::vector<Point2f> points =
        pointsIn.empty() ? std::vector<Point2f>() : toPoints(pointsIn, "points");
    for (size_t i = 0; i < points.size(); ++i)
        if (!std::isfinite(points[i].x) || !std::isfinite(points[i].y))
            CV_Error_(Error::StsBadArg,
                      ("multicage: transformPoints: point %d (%g, %g) is not finite",
                       static_cast<int>(i), points[i].x, points[i].y));
    ForwardMesh mesh(binding, pose);
    const std::vector<VertexCorrection> corrections = vertexCorrections(binding, pose, mesh);
    // Corrections by mesh cell, so that a point looks only at the vertices near it.
    const int cols = static_cast<int>(mesh.X().size()) - 1;
    std::unordered_map<long long, std::vector<int>> byCell;
    for (size_t j = 0; j < corrections.size(); ++j) {
        const VertexCorrection& v = corrections[j];
        if (v.weight.x == 0 && v.weight.y == 0) continue;
        int ex0, ey0, ex1, ey1;
        double u, w;
        mesh.locate(Point2d(v.tx.lo, v.ty.lo), ex0, ey0, u, w);
        mesh.locate(Point2d(v.tx.hi, v.ty.hi), ex1, ey1, u, w);
        for (int ey = ey0; ey <= ey1; ++ey)
            for (int ex = ex0; ex <= ex1; ++ex)
                byCell[static_cast<long long>(ey) * cols + ex].push_back(static_cast<int>(j));
    }
    dst.create(static_cast<int>(points.size()), 1, CV_32FC2);
    if (points.empty()) return;
    Mat out = dst.getMat();
    for (size_t i = 0; i < points.size(); ++i) {
        const Point2d p(points[i]);
        Point2d q;
        if (!mesh.insideFrame(p)) {
            q = mesh.frameMap(p);
        } else {
            q = mesh.map(p);
            int ex, ey;
            double u, w;
            mesh.locate(p, ex, ey, u, w);
            auto it = byCell.find(static_cast<long long>(ey) * cols + ex);
            if (it != byCell.end())
                for (int j : it->second) q += corrections[j].at(p) * corrections[j].weight;
        }
        out.at<Point2f>(static_cast<int>(i)) =
            Point2f(static_cast<float>(q.x), static_cast<float>(q.y));
    }
}

void Deformer::transformPoints(InputArray pose, InputArray points, OutputArray dst) const {
    multicage::transformPoints(binding(), pose, points, dst);
}

}  // namespace multicage
}  // namespace cv

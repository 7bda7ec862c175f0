// The Boykov-Kolmogorov max-flow on a pixel grid (grid_cut.hpp). The search trees grow from the
// terminals along edges with residual capacity (growth), an edge joining the two trees closes
// a path from the source to the sink, which is saturated (augmentation), and the nodes cut off
// from their tree by a saturated edge look for a new parent in the same tree or leave it
// (adoption). Distances to the terminal and the time they were checked steer adoption to short
// paths, as in the paper and GCGraph.
#include "grid_cut.hpp"

#include <algorithm>
#include <climits>

namespace cv {
namespace multicage {
namespace propose_detail {

const Point GridCut::kStep[GridCut::kDirections] = {{1, 0},  {1, 1},   {0, 1},  {-1, 1},
                                                    {-1, 0}, {-1, -1}, {0, -1}, {1, -1}};

namespace {
constexpr int opposite(int d) {
    return (d + 4) & 7;
}
}  // namespace

GridCut::GridCut(Size size) : size_(size), stride_(size.width + 2) {
    CV_Assert(size.width > 0 && size.height > 0);
    const size_t n = static_cast<size_t>(stride_) * (size.height + 2);
    for (int d = 0; d < kDirections; ++d) offset_[d] = kStep[d].y * stride_ + kStep[d].x;
    cap_.assign(n * kDirections, 0.0);
    tr_.assign(n, 0.0);
    net_.assign(n, 0.0);
    parent_.assign(n, kNone);
    tree_.assign(n, kSourceTree);
    dist_.assign(n, 0);
    ts_.assign(n, 0);
    queued_.assign(n, 0);
}

void GridCut::setEdge(Point p, int d, double capacity) {
    CV_DbgAssert(d >= 0 && d < 4 && capacity >= 0);
    const Point q = p + kStep[d];
    CV_DbgAssert(Rect(Point(), size_).contains(p) && Rect(Point(), size_).contains(q));
    const int v = index(p), u = index(q);
    cap(v, d) = capacity;
    cap(u, opposite(d)) = capacity;
}

void GridCut::setTerminal(Point p, double source, double sink) {
    CV_DbgAssert(source >= 0 && sink >= 0);
    const int v = index(p);
    const double net = source - sink;
    tr_[v] += net - net_[v];
    net_[v] = net;
}

void GridCut::activate(int v) {
    if (queued_[v]) return;
    queued_[v] = 1;
    active_.push_back(v);
}

int GridCut::nextActive() {
    if (head_ == active_.size()) return -1;
    if (head_ > 4096 && head_ * 2 > active_.size()) {  // drop what was taken off the front
        active_.erase(active_.begin(), active_.begin() + static_cast<long>(head_));
        head_ = 0;
    }
    return active_[head_];
}

bool GridCut::grow(int& from, int& direction) {
    for (int v; (v = nextActive()) >= 0;) {
        if (parent_[v] != kNone) {
            const uint8_t t = tree_[v];
            for (int d = 0; d < kDirections; ++d) {
                const int u = v + offset_[d];
                // The source tree grows along edges out of it, the sink tree along edges into it.
                if ((t == kSourceTree ? cap(v, d) : cap(u, opposite(d))) == 0) continue;
                if (parent_[u] == kNone) {
                    tree_[u] = t;
                    parent_[u] = static_cast<int8_t>(opposite(d));
                    ts_[u] = ts_[v];
                    dist_[u] = dist_[v] + 1;
                    activate(u);
                } else if (tree_[u] != t) {
                    // The trees meet: v stays active, it may have more to give.
                    from = t == kSourceTree ? v : u;
                    direction = t == kSourceTree ? d : opposite(d);
                    return true;
                } else if (dist_[u] > dist_[v] + 1 && ts_[u] <= ts_[v]) {
                    parent_[u] = static_cast<int8_t>(opposite(d));  // a shorter way to the root
                    ts_[u] = ts_[v];
                    dist_[u] = dist_[v] + 1;
                }
            }
        }
        queued_[v] = 0;
        ++head_;
    }
    return false;
}

double GridCut::augment(int from, int direction) {
    const int to = from + offset_[direction];
    // The bottleneck: the joining edge, each tree's edges to its root, and the roots' terminals.
    double m = cap(from, direction);
    int v = from;
    for (int p; (p = parent_[v]) != kTerminal; v += offset_[p])
        m = std::min(m, cap(v + offset_[p], opposite(p)));
    m = std::min(m, tr_[v]);
    v = to;
    for (int p; (p = parent_[v]) != kTerminal; v += offset_[p]) m = std::min(m, cap(v, p));
    m = std::min(m, -tr_[v]);

    cap(from, direction) -= m;
    cap(to, opposite(direction)) += m;
    auto orphan = [this](int o) {
        parent_[o] = kOrphan;
        orphans_.push_back(o);
    };
    for (v = from;;) {  // source tree: flow goes from the parent to the child
        const int p = parent_[v];
        if (p == kTerminal) {
            if ((tr_[v] -= m) == 0) orphan(v);
            break;
        }
        const int u = v + offset_[p];
        cap(v, p) += m;
        if ((cap(u, opposite(p)) -= m) == 0) orphan(v);
        v = u;
    }
    for (v = to;;) {  // sink tree: from the child to the parent
        const int p = parent_[v];
        if (p == kTerminal) {
            if ((tr_[v] += m) == 0) orphan(v);
            break;
        }
        const int u = v + offset_[p];
        cap(u, opposite(p)) += m;
        if ((cap(v, p) -= m) == 0) orphan(v);
        v = u;
    }
    return m;
}

// Whether u's way up its tree ends at a terminal (not at an orphan); `distance` is then u's
// distance to it, counted in nodes. Nodes checked in this adoption round keep their distance
// (ts_ == time_), so a walk stops where an earlier one passed.
bool GridCut::reachesTerminal(int u, int& distance) {
    int d = 0;
    for (;;) {
        if (ts_[u] == time_) {
            distance = d + dist_[u];
            return true;
        }
        const int p = parent_[u];
        ++d;
        if (p == kTerminal) {
            ts_[u] = time_;
            dist_[u] = 1;
            distance = d;
            return true;
        }
        if (p == kOrphan) return false;
        u += offset_[p];
    }
}

void GridCut::adopt() {
    ++time_;
    while (!orphans_.empty()) {
        const int v = orphans_.back();
        orphans_.pop_back();
        const uint8_t t = tree_[v];
        int best = -1, bestDistance = INT_MAX;
        for (int d = 0; d < kDirections; ++d) {
            const int u = v + offset_[d];
            if (tree_[u] != t || parent_[u] == kNone) continue;
            // A parent must still reach v (source tree) or be reached from it (sink tree).
            if ((t == kSourceTree ? cap(u, opposite(d)) : cap(v, d)) == 0) continue;
            int du;
            if (!reachesTerminal(u, du)) continue;
            const int dv = du + 1;
            if (dv < bestDistance) {
                bestDistance = dv;
                best = d;
            }
            // Remember the distances along u's way up for the next walks of this round.
            int k = dv;
            for (int w = u; ts_[w] != time_; w += offset_[parent_[w]]) {
                ts_[w] = time_;
                dist_[w] = --k;
            }
        }
        if (best >= 0) {
            parent_[v] = static_cast<int8_t>(best);
            ts_[v] = time_;
            dist_[v] = bestDistance;
            continue;
        }
        // No parent: v leaves its tree (keeping its side, as GCGraph's vertices do). Its
        // neighbours that could grow into it become active again, and its children orphans.
        parent_[v] = kNone;
        ts_[v] = 0;
        for (int d = 0; d < kDirections; ++d) {
            const int u = v + offset_[d];
            const int p = parent_[u];
            if (tree_[u] != t || p == kNone) continue;
            if ((t == kSourceTree ? cap(u, opposite(d)) : cap(v, d)) != 0) activate(u);
            if (p == opposite(d)) {
                parent_[u] = kOrphan;
                orphans_.push_back(u);
            }
        }
    }
}

// The first solve's head start. Augmenting paths carry a GrabCut's first flow across the
// picture one path at a time: 95,000 augmentations along paths of about 100 nodes on the
// benchmark's squirrel at 240 px, where each path takes one pixel's excess (its terminal
// residual: pairwise capacities are up to 50, terminals a few units). Push-relabel moves the
// excess in bulk instead: it flows downhill, gathering as it goes. Each round here is one
// global relabel and one sweep: the distance of every node to the nearest node that lacks
// (tr_ < 0) along edges with residual capacity, by breadth-first search, then the nodes from
// the farthest inwards, each pushing its excess to neighbours one step nearer and, what is
// left, to neighbours at its own distance not swept yet (around an edge that filled up). Any
// flow within the edges' capacities is a start from which the minimum cut is still found
// exactly: what a node holds or lacks afterwards is its terminal residual, which changes
// every cut by the same constant (Kohli & Torr's argument), so the augmenting paths finish
// the work and the labels are those of the paths alone. Returns the flow it brought to nodes
// that lacked it.
//
// 30 rounds: the 13 benchmark photos' GrabCuts from the frame inward (4 iterations at 240 px,
// one thread) took 1781 ms together with no rounds, 1252 with 20 rounds pushing downhill only,
// 1185 with 40, 1158 with 20 and the sideways pushes, 1143 with 30 and 1170 with 40 (each
// photo's 4 iterations: the squirrel 233 -> 118 ms, the baboon 163 -> 103, the apple, whose
// paths were short, 70 -> 80). Stopping when a round delivered under 2-20% of the first
// round's flow was no better; rounds before the later solves, which start from the flow kept,
// were slower (30 each) or within the noise (1-3 each).
double GridCut::pushDownhill() {
    constexpr int kRounds = 30;
    const int n = static_cast<int>(tr_.size());
    std::vector<int> distance(n), order, place(n);  // place: a node's position in `order`
    order.reserve(n);
    double delivered = 0;
    auto push = [&](int u, int d, int v) {
        const double f = std::min(tr_[u], cap(u, d));
        if (f <= 0) return false;
        if (tr_[v] < 0) delivered += std::min(f, -tr_[v]);
        cap(u, d) -= f;
        cap(v, opposite(d)) += f;
        tr_[u] -= f;
        tr_[v] += f;
        return true;
    };
    for (int round = 0; round < kRounds; ++round) {
        std::fill(distance.begin(), distance.end(), -1);
        order.clear();
        for (int v = 0; v < n; ++v)
            if (tr_[v] < 0)
                distance[v] = 0, place[v] = static_cast<int>(order.size()), order.push_back(v);
        for (size_t head = 0; head < order.size(); ++head) {
            const int v = order[head];
            for (int d = 0; d < kDirections; ++d) {
                const int u = v + offset_[d];
                if (distance[u] >= 0 || cap(u, opposite(d)) == 0) continue;
                distance[u] = distance[v] + 1;
                place[u] = static_cast<int>(order.size());
                order.push_back(u);
            }
        }
        bool moved = false;
        for (int i = static_cast<int>(order.size()); i-- > 0;) {
            const int u = order[i];
            if (distance[u] == 0) break;  // the rest lack: nothing to push
            for (int d = 0; d < kDirections && tr_[u] > 0; ++d) {
                const int v = u + offset_[d];
                if (distance[v] == distance[u] - 1) moved |= push(u, d, v);
            }
            for (int d = 0; d < kDirections && tr_[u] > 0; ++d) {
                const int v = u + offset_[d];
                if (distance[v] == distance[u] && place[v] < i) moved |= push(u, d, v);
            }
        }
        if (!moved) break;
    }
    return delivered;
}

double GridCut::maxFlow() {
    double flow = 0;
    if (!solved_) flow = pushDownhill();
    solved_ = true;
    // Every solve starts its trees afresh from the nodes with terminal residual; the residual
    // capacities carry over.
    active_.clear();
    head_ = 0;
    std::fill(queued_.begin(), queued_.end(), 0);
    std::fill(ts_.begin(), ts_.end(), 0);
    time_ = 0;
    for (size_t v = 0; v < tr_.size(); ++v) {
        tree_[v] = kSourceTree;
        if (tr_[v] != 0) {
            parent_[v] = kTerminal;
            tree_[v] = tr_[v] < 0 ? kSinkTree : kSourceTree;
            dist_[v] = 1;
            activate(static_cast<int>(v));
        } else {
            parent_[v] = kNone;
        }
    }
    for (int from, direction; grow(from, direction);) {
        flow += augment(from, direction);
        adopt();
    }
    return flow;
}

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv

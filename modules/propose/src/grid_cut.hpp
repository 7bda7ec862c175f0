// Minimum s-t cut of an 8-connected pixel grid (private), for GrabCut (grabcut.hpp).
//
// The Boykov-Kolmogorov augmenting-path algorithm (Boykov & Kolmogorov 2004, "An experimental
// comparison of min-cut/max-flow algorithms for energy minimization in vision"), as OpenCV's
// GCGraph runs it for cv::grabCut, with two differences that decide its speed:
//
// - The graph is a grid, not an edge list: a node's eight residual capacities lie next to
//   each other and its neighbours are found by offsets, so no edge is allocated or followed by
//   pointer (a 240 px GrabCut graph is 58k nodes and 460k edges; GCGraph builds it again for
//   every iteration).
// - The flow is kept between solves. GrabCut's iterations change only the terminal capacities
//   (the colour models); the pairwise ones depend on the image alone. Kohli & Torr (2005,
//   "Efficiently solving dynamic Markov random fields using graph cuts") show that adding the
//   change of a node's terminal capacities to its residual keeps the residual graph that of a
//   valid flow, so the next solve only pushes what changed instead of the whole flow again.
// - The first solve starts with rounds of pushes downhill (pushDownhill): the excess of every
//   pixel moves in bulk towards the nearest pixel that lacks, as push-relabel moves it, where
//   augmenting paths would carry it one path at a time.
#ifndef MULTICAGE_PROPOSE_GRID_CUT_HPP
#define MULTICAGE_PROPOSE_GRID_CUT_HPP

#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

namespace cv {
namespace multicage {
namespace propose_detail {

class GridCut {
  public:
    /** Directions to the eight neighbours: right, down-right, down, down-left, left, up-left,
    up, up-right (x right, y down). (d + 4) % 8 is the opposite direction. */
    static constexpr int kDirections = 8;
    static const Point kStep[kDirections];

    /** A size.width x size.height grid, every capacity zero. */
    explicit GridCut(Size size);

    Size size() const { return size_; }
    /** Sets the capacity of the edge from pixel p to its neighbour in direction d and of the
    edge back to the same value (an undirected pairwise term); d in 0..3, the neighbour
    inside the grid. Before the first maxFlow() only. */
    void setEdge(Point p, int d, double capacity);
    /** Sets pixel p's terminal capacities: the edge from the source and the edge to the sink
    (both >= 0 and finite). Between solves only the change is added to the residual, which
    keeps the flow found so far valid (Kohli & Torr). */
    void setTerminal(Point p, double source, double sink);
    /** Pushes as much flow as the residual graph allows; returns the flow pushed in this call
    (through the terminals' residuals: a constant per node is left out, as in GCGraph). The
    first call starts with pushDownhill. */
    double maxFlow();
    /** After maxFlow(): true when pixel p is on the source side of the minimum cut. A pixel
    that neither side reaches is on the side it was last in (the source side if never in
    either), as in GCGraph. */
    bool inSource(Point p) const { return tree_[index(p)] == kSourceTree; }

  private:
    static constexpr uint8_t kSourceTree = 0, kSinkTree = 1;
    static constexpr int8_t kNone = -1, kTerminal = 8, kOrphan = 9;

    int index(Point p) const { return (p.y + 1) * stride_ + p.x + 1; }  // past the padding
    // The residual capacity of the edge from node v in direction d.
    double& cap(int v, int d) { return cap_[static_cast<size_t>(v) * kDirections + d]; }
    void activate(int v);
    int nextActive();
    bool grow(int& from, int& direction);
    double augment(int from, int direction);
    void adopt();
    double pushDownhill();
    bool reachesTerminal(int u, int& distance);

    Size size_;
    int stride_;               // padded row length: a ring of dead nodes avoids bounds checks
    int offset_[kDirections];  // index steps to the neighbours
    std::vector<double> cap_;  // residual capacities, kDirections per node
    std::vector<double> tr_;   // residual terminal capacity: > 0 from the source, < 0 to the sink
    std::vector<double> net_;  // source minus sink capacity as last set
    std::vector<int8_t> parent_;  // direction to the parent, kNone, kTerminal or kOrphan
    std::vector<uint8_t> tree_;   // kSourceTree or kSinkTree
    std::vector<int> dist_, ts_;  // distance to the terminal and when it was last checked
    std::vector<uint8_t> queued_;
    std::vector<int> active_;  // FIFO of active nodes (head_ onwards)
    size_t head_ = 0;
    std::vector<int> orphans_;
    int time_ = 0;
    bool solved_ = false;  // whether maxFlow() has run (pushDownhill before the first)
};

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv

#endif

// The CPU backend (private): node positions, mesh rasterised into inverse maps, cv::remap.
#ifndef MULTICAGE_CPU_DEFORMER_HPP
#define MULTICAGE_CPU_DEFORMER_HPP

#include <algorithm>
#include <functional>
#include <opencv2/multicage/deformer.hpp>
#include <opencv2/multicage/internal/backend_contract.hpp>
#include <vector>

#include "batch.hpp"
#include "mesh_lattice.hpp"
#include "mesh_pull.hpp"

namespace cv {
namespace multicage {

Ptr<Deformer> createCpuDeformer(const Mat& image, const Binding& binding,
                                const DeformParams& params);

/** The node mesh the CPU backend rasterises (mesh_raster.cpp): the node grid with a ring of
nodes on the image frame around it, (n+2) x (m+2). It is made once per Deformer and reused by
every pose, so a pose allocates nothing and touches no fresh memory. */
class RasterMesh {
  public:
    /** Allocates (and touches) the mesh for these rest nodes (gridSize CV_32FC2) and output size.
     */
    void reset(const Mat& restNodes, Size outputSize);
    /** The same for a binding's node grid and image size, without making its node matrix. */
    void reset(const Binding& binding);
    /** The deformed grid nodes: a gridSize CV_32FC2 view inside the mesh, to write a pose into
    (whether the mesh folds is then found again when drawn). */
    Mat nodes() {
        pullable_ = Pullable::unknown;
        return P_(Rect(1, 1, P_.cols - 2, P_.rows - 2));
    }
    /** Places the ring on the frame with these 4 corners (TL, TR, BR, BL); null: the rest frame. */
    void setFrame(const Point2f* frame);
    /** A pose of the binding reset() was given: its nodes (Binding::apply of vertices, as
    completePose gives them, frame last), the ring on its frame, and the output size that frame
    asks for (frameOutputSize). Where draw() may pull, whether the mesh folds is checked while
    apply writes the nodes, each block of rows while it is in cache: raster::pullable's answer
    in about half its time (0.14 ms against 0.25 at 1024x768, grid step 1, 2 threads). */
    void pose(const Binding& binding, const std::vector<Point2f>& vertices);
    /** The size draw() writes; reset() sets it to the rest frame's size. A pose whose frame lies
    on another size's frame (frameOutputSize) draws into that size. */
    void setOutputSize(Size outputSize);
    Size outputSize() const { return out_; }
    /** Inverse maps (outputSize CV_32F, every pixel written) for the current nodes and frame.
    Drawn in bands of rows, in parallel; bandDone(y0, y1), if given, is called on the band's
    thread as soon as rows [y0, y1) are final (to sample them while they are in cache). */
    void draw(Mat& mapx, Mat& mapy, const std::function<void(int, int)>& bandDone = {});
    /** Whether draw() may pull the maps of a mesh that folds nowhere pixel by pixel (the default)
    instead of drawing every triangle: within a few float roundings of the raster's values. */
    void setPullPreferred(bool pull) { pullPreferred_ = pull; }
    /** Whether draw() pulls the current nodes and frame: a binding's grid of step 1 or 2 that
    folds nowhere (raster::pullable), pulling preferred, on a CPU with the pull kernel. */
    bool pulls() const;
    /** DeformParams::mapStep: from 2 up, draw() finds the maps of a mesh that folds nowhere on a
    lattice of points at most this many pixels apart and interpolates them (mesh_lattice.hpp),
    where it may pull (setPullPreferred, the pull kernel); 1 (the default): every pixel. */
    void setMapStep(int step) {
        mapStep_ = std::max(step, 1);
        pullable_ = Pullable::unknown;
        reserveLattice();
    }
    /** Whether draw() interpolates the current nodes and frame from a lattice (setMapStep). */
    bool interpolates() const;

  private:
    template <typename F>
    void forEachRingNode(F&& f) const;
    template <typename RestNode>
    void resetWith(Size grid, Size outputSize, bool separable, RestNode&& rest);
    raster::PullMesh pullMesh() const;
    // Whether the current nodes and frame may be pulled but for the fold check: a binding's grid
    // of a small step (or any step, onto a lattice: setMapStep), pulling preferred, a CPU with
    // the kernel.
    bool mayPull() const;
    // raster::pullable of the current nodes and frame (pose() may have found it), where mayPull.
    bool foldsNowhere() const;
    // The lattice for the output size and map step: its maps allocated and touched, its columns.
    void reserveLattice();
    // draw() through a lattice (setMapStep); false, nothing written, where a walk did not settle.
    bool drawInterpolated(Mat& mapx, Mat& mapy, const std::function<void(int, int)>& bandDone);
    // rowMin_ and rowMax_ for the current nodes.
    void findRowExtents();
    // The largest grid step whose meshes are pulled (draw()).
    static constexpr int kMaxPullStep = 2;
    // Row ey of the rest mesh: R_'s, or made in `buffer` from restX_ and restY_.
    const Point2f* restRow(int ey, std::vector<Point2f>& buffer) const;
    std::vector<Mat> owners_;  // the memory of P_ and R_
    Mat P_, R_;  // deformed and rest nodes, ring included; R_ empty for a regular grid
    std::vector<float> restX_, restY_;  // a regular grid's rest x per column, y per row
    Point2f lo_, hi_;
    Size rest_, out_;  // the rest frame's size (the ring's parameter), the size drawn
    std::vector<float> rowMin_, rowMax_;
    int gridStep_ = 0;  // a binding's grid step (its nodes rest at multiples of it), else 0
    bool pullPreferred_ = true;
    int mapStep_ = 1;
    std::vector<Mat> latticeOwners_;  // the memory of latticeX_, latticeY_
    // drawInterpolated's, kept between poses: the output size they were made for (reserveLattice),
    // the lattice, its maps and its columns.
    Size latticeFor_;
    raster::Lattice lattice_;
    Mat latticeX_, latticeY_;
    raster::LatticeColumns latticeColumns_;
    // raster::pullable of the current nodes and frame, when pose() found it.
    enum class Pullable { unknown, yes, no } pullable_ = Pullable::unknown;
};

}  // namespace multicage
}  // namespace cv

#endif

// GrabCut (Rother, Kolmogorov & Blake 2004) from a label mask (private): cv::grabCut's model,
// step for step, on a graph that is built once and keeps its flow between iterations.
//
// The proposal runs GrabCut up to five iterations at a time and several times per photo
// (subject.cpp); with cv::grabCut, 55-85% of that time went to max-flow and most of the rest
// to building the graph again for every iteration (measured on the benchmark's baboon, orange,
// squirrel and coffee at GrabCut's 240 px). Here the pairwise capacities are computed once and
// each iteration only changes the terminal ones (grid_cut.hpp), so later iterations push only
// what the new colour models changed.
//
// The colour models are cv::grabCut's to the bit: two Gaussian mixtures of 5 components with
// full covariance, started by k-means++ (10 iterations, cv::theRNG()) on the background and
// subject pixels, and learnt again from the pixels' components in every iteration; the
// energy's weights are cv::grabCut's (gamma 50, lambda 450, beta from the mean contrast,
// 8-connected). A minimum cut can differ from cv::grabCut's only in pixels that neither
// terminal reaches (ties, which the two max-flows break in their own order): tests compare the
// two (GrabCut.*).
#ifndef MULTICAGE_PROPOSE_GRABCUT_HPP
#define MULTICAGE_PROPOSE_GRABCUT_HPP

#include <memory>
#include <opencv2/core.hpp>

#include "grid_cut.hpp"

namespace cv {
namespace multicage {
namespace propose_detail {

class GrabCut {
  public:
    /** Starts the colour models from `labels` (CV_8UC1, GC_BGD ... GC_PR_FGD, img's size;
    both sides must have pixels) with k-means++ seeded by cv::theRNG(). img: CV_8UC3. */
    GrabCut(const Mat& img, const Mat& labels);
    ~GrabCut();
    /** One iteration, as cv::grabCut's: each pixel takes its side's most likely component,
    the models are learnt again, and the minimum cut relabels the probable pixels
    (GC_PR_BGD / GC_PR_FGD); sure ones stay. */
    void iterate(Mat& labels);

  private:
    struct Mixture;
    const Mat img_;
    std::unique_ptr<Mixture> background_, subject_;
    std::unique_ptr<GridCut> graph_;
};

/** GrabCut (the class above: cv::grabCut's labels, in less time) from `labels`, its k-means
seeded with a fixed number so that the result is a function of the image alone; `labels` is
updated in place. It runs `iterations` iterations, then, when `settleWithin` is more, goes on
until one moves at most 1% of the pixels between subject and background (the `iterations`-th
included), `settleWithin` in all at most. */
void seededGrabCut(const Mat& img, Mat& labels, int iterations, int settleWithin = 0);

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv

#endif

// The proposal's own GrabCut (modules/propose/src/grabcut.hpp) and its grid max-flow
// (grid_cut.hpp): cv::grabCut's labels, iteration for iteration, and minimum cuts checked
// against every cut of small grids, before and after the terminals change between solves.
#include "grabcut.hpp"

#include <cfloat>
#include <opencv2/imgproc.hpp>
#include <opencv2/imgproc/detail/gcgraph.hpp>

#include "grid_cut.hpp"
#include "testing.hpp"

using namespace cv;
using namespace cv::multicage::propose_detail;

namespace {

// A random grid problem: the pairwise capacities of the four forward directions and the
// terminals of every pixel, some of them zero (ties and dead ends are where max-flows differ).
struct Problem {
    Size size;
    std::vector<double> edge;  // 4 per pixel, row-major; directions as GridCut's 0..3
    std::vector<double> source, sink;
};

Problem randomProblem(RNG& rng, Size size) {
    Problem p{size, {}, {}, {}};
    auto capacity = [&rng](double most) {
        return rng.uniform(0, 4) == 0 ? 0.0 : rng.uniform(0.0, most);
    };
    for (int i = 0; i < size.area(); ++i) {
        for (int d = 0; d < 4; ++d) p.edge.push_back(capacity(3.0));
        p.source.push_back(capacity(5.0));
        p.sink.push_back(capacity(5.0));
    }
    return p;
}

// New terminals for the same pairwise capacities (what a GrabCut iteration changes).
void redrawTerminals(RNG& rng, Problem& p) {
    const Problem q = randomProblem(rng, p.size);
    p.source = q.source;
    p.sink = q.sink;
}

void setTerminals(GridCut& g, const Problem& p);

// Solve `solve` of a sequence on one graph: the first with p's terminals, each later one
// after they are drawn again. Returns the flow the solve pushed.
double solveAgain(GridCut& g, Problem& p, RNG& rng, int solve) {
    if (solve > 0) redrawTerminals(rng, p);
    setTerminals(g, p);
    return g.maxFlow();
}

bool inside(Size s, Point q) {
    return q.x >= 0 && q.y >= 0 && q.x < s.width && q.y < s.height;
}

void setEdges(GridCut& g, const Problem& p) {
    for (int y = 0; y < p.size.height; ++y)
        for (int x = 0; x < p.size.width; ++x)
            for (int d = 0; d < 4; ++d)
                if (inside(p.size, Point(x, y) + GridCut::kStep[d]))
                    g.setEdge(Point(x, y), d, p.edge[(y * p.size.width + x) * 4 + d]);
}

void setTerminals(GridCut& g, const Problem& p) {
    for (int y = 0; y < p.size.height; ++y)
        for (int x = 0; x < p.size.width; ++x) {
            const int i = y * p.size.width + x;
            g.setTerminal(Point(x, y), p.source[i], p.sink[i]);
        }
}

// The capacity of the cut that puts the pixels marked in `source` on the source side.
double cutCapacity(const Problem& p, const std::vector<char>& source) {
    double c = 0;
    for (int y = 0; y < p.size.height; ++y)
        for (int x = 0; x < p.size.width; ++x) {
            const int i = y * p.size.width + x;
            c += source[i] ? p.sink[i] : p.source[i];
            for (int d = 0; d < 4; ++d) {
                const Point q = Point(x, y) + GridCut::kStep[d];
                if (!inside(p.size, q)) continue;
                const int j = q.y * p.size.width + q.x;
                if (source[i] != source[j]) c += p.edge[i * 4 + d];  // undirected: both ways
            }
        }
    return c;
}

double leastCut(const Problem& p) {
    const int n = p.size.area();
    double least = DBL_MAX;
    std::vector<char> side(n);
    for (int bits = 0; bits < (1 << n); ++bits) {
        for (int i = 0; i < n; ++i) side[i] = (bits >> i) & 1;
        least = std::min(least, cutCapacity(p, side));
    }
    return least;
}

// A benchmark photo at GrabCut's working size (240 px on the longer side).
Mat photo240(const char* name) {
    const Mat photo = multicage_testing::readSample(std::string("propose_bench/") + name + ".jpg");
    Mat img;
    const double s = 240.0 / std::max(photo.cols, photo.rows);
    resize(photo, img, Size(), s, s, INTER_AREA);
    return img;
}

// subject.cpp's start: a strip along the frame sure background, the rest probable subject.
constexpr int kStrip = 7;  // 3% of 240
Mat frameStart(Size size) {
    Mat labels(size, CV_8U, Scalar(GC_BGD));
    labels(Rect(kStrip, kStrip, size.width - 2 * kStrip, size.height - 2 * kStrip))
        .setTo(GC_PR_FGD);
    return labels;
}

std::vector<char> sidesOf(const GridCut& g) {
    std::vector<char> side;
    for (int y = 0; y < g.size().height; ++y)
        for (int x = 0; x < g.size().width; ++x) side.push_back(g.inSource(Point(x, y)));
    return side;
}

}  // namespace

// Max-flow = min-cut: the cut GridCut returns is the least of all 2^n cuts of the grid.
TEST(GridCut, FindsTheLeastCutOfSmallGrids) {
    RNG rng(7);
    for (int trial = 0; trial < 60; ++trial) {
        const Size size(trial % 3 + 2, (trial / 3) % 3 + 2);  // up to 4x4: 2^16 cuts
        const Problem p = randomProblem(rng, size);
        GridCut g(size);
        setEdges(g, p);
        setTerminals(g, p);
        const double flow = g.maxFlow();
        double constant = 0;  // what each pixel's two terminals carry straight through it
        for (int i = 0; i < size.area(); ++i) constant += std::min(p.source[i], p.sink[i]);
        const double least = leastCut(p);
        EXPECT_NEAR(cutCapacity(p, sidesOf(g)), least, 1e-9) << "trial " << trial;
        EXPECT_NEAR(flow + constant, least, 1e-9) << "trial " << trial;
    }
}

// Between solves only the terminals change (GrabCut's iterations): the flow kept from the
// first solve must still lead to the least cut of the new capacities, however they moved.
TEST(GridCut, AfterTheTerminalsChangeTheCutIsTheLeastOfTheNewCapacities) {
    RNG rng(11);
    for (int trial = 0; trial < 40; ++trial) {
        const Size size(trial % 3 + 2, (trial / 3) % 2 + 3);
        Problem p = randomProblem(rng, size);
        GridCut g(size);
        setEdges(g, p);
        for (int solve = 0; solve < 3; ++solve) {
            solveAgain(g, p, rng, solve);
            EXPECT_NEAR(cutCapacity(p, sidesOf(g)), leastCut(p), 1e-9)
                << "trial " << trial << ", solve " << solve;
        }
    }
}

// On a photo-sized grid, where no brute force reaches: the same least cut as OpenCV's GCGraph
// built afresh with the new capacities, after several changes of the terminals; and the first
// solve, which starts by pushing downhill, pushes GCGraph's flow.
TEST(GridCut, MatchesGcGraphOnALargeGridAcrossChanges) {
    RNG rng(3);
    const Size size(61, 47);
    Problem p = randomProblem(rng, size);
    GridCut g(size);
    setEdges(g, p);
    for (int solve = 0; solve < 4; ++solve) {
        const double flow = solveAgain(g, p, rng, solve);
        detail::GCGraph<double> reference;
        reference.create(size.area(), 8 * size.area());
        for (int i = 0; i < size.area(); ++i) {
            reference.addVtx();
            reference.addTermWeights(i, p.source[i], p.sink[i]);
        }
        for (int y = 0; y < size.height; ++y)
            for (int x = 0; x < size.width; ++x)
                for (int d = 0; d < 4; ++d) {
                    const Point q = Point(x, y) + GridCut::kStep[d];
                    if (!inside(size, q)) continue;
                    const double c = p.edge[(y * size.width + x) * 4 + d];
                    reference.addEdges(y * size.width + x, q.y * size.width + q.x, c, c);
                }
        const double least = reference.maxFlow();  // (GCGraph counts each pixel's constant)
        EXPECT_NEAR(cutCapacity(p, sidesOf(g)), least, 1e-7 * least) << "solve " << solve;
        if (solve == 0) {
            double constant = 0;
            for (int i = 0; i < size.area(); ++i) constant += std::min(p.source[i], p.sink[i]);
            EXPECT_NEAR(flow + constant, least, 1e-7 * least);
        }
    }
}

// The proposal's GrabCut gives cv::grabCut's labels to the pixel, after each of five
// iterations, from the frame inward (subject.cpp's start) and from a rectangle, on photos at
// GrabCut's working size.
TEST(GrabCut, SameLabelsAsCvGrabCutIterationForIteration) {
    for (const char* name : {"baboon", "squirrel", "messi5"}) {
        const Mat img = photo240(name);
        const Mat fromFrame = frameStart(img.size());
        Mat fromRect(img.size(), CV_8U, Scalar(GC_BGD));
        fromRect(Rect(img.cols / 5, img.rows / 6, img.cols / 2, img.rows * 2 / 3)).setTo(GC_PR_FGD);
        for (const Mat& start : {fromFrame, fromRect}) {
            Mat theirs = start.clone(), ours = start.clone(), bgd, fgd;
            theRNG() = RNG(5);
            grabCut(img, theirs, Rect(), bgd, fgd, 1, GC_INIT_WITH_MASK);
            theRNG() = RNG(5);
            GrabCut grabCut(img, ours);
            grabCut.iterate(ours);
            for (int i = 1; i <= 5; ++i) {
                if (i > 1) {
                    cv::grabCut(img, theirs, Rect(), bgd, fgd, 1, GC_EVAL);
                    grabCut.iterate(ours);
                }
                EXPECT_EQ(countNonZero(ours != theirs), 0)
                    << name
                    << (start.data == fromFrame.data ? ", from the frame" : ", from a rectangle")
                    << ", iteration " << i;
            }
        }
    }
}

// A side with fewer pixels than the mixture has components (a sliver of an image, one
// pixel of background) gets one component per pixel, and the labels are still cv::grabCut's.
TEST(GrabCut, SidesSmallerThanTheMixtureAsCvGrabCut) {
    RNG rng(21);
    for (Size size : {Size(3, 3), Size(7, 2), Size(9, 6)}) {
        Mat img(size, CV_8UC3);
        rng.fill(img, RNG::UNIFORM, 0, 256);
        Mat start(size, CV_8U, Scalar(GC_PR_FGD));
        start.at<uchar>(0, 0) = GC_BGD;
        start.at<uchar>(size.height - 1, size.width - 1) = GC_PR_BGD;
        Mat theirs = start.clone(), ours = start.clone(), bgd, fgd;
        theRNG() = RNG(5);
        grabCut(img, theirs, Rect(), bgd, fgd, 3, GC_INIT_WITH_MASK);
        theRNG() = RNG(5);
        GrabCut grabCut(img, ours);
        for (int i = 0; i < 3; ++i) grabCut.iterate(ours);
        EXPECT_EQ(countNonZero(ours != theirs), 0) << size;
    }
}

TEST(GrabCut, NeedsBothSidesToStart) {
    const Mat img(20, 20, CV_8UC3, Scalar(10, 20, 30));
    EXPECT_THROW(GrabCut(img, Mat(img.size(), CV_8U, Scalar(GC_PR_FGD))), cv::Exception);
    EXPECT_THROW(GrabCut(img, Mat(img.size(), CV_8U, Scalar(GC_BGD))), cv::Exception);
}

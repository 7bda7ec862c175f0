// GrabCut's colour models and energy (grabcut.hpp); the minimum cut is grid_cut.cpp's.
#include "grabcut.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "grid_cut.hpp"

namespace cv {
namespace multicage {
namespace propose_detail {

namespace {

constexpr int kComponents = 5;
constexpr double kGamma = 50;            // weight of the smoothness term
constexpr double kLambda = 9 * kGamma;   // terminal capacity of a sure pixel
constexpr double kVarianceFloor = 0.01;  // added to a singular covariance's diagonal
constexpr int kKMeansIterations = 10;
// -log of a likelihood that underflows to zero: far above any pixel's pairwise capacities
// (8 neighbours of at most gamma), so the pixel is as sure as cv::grabCut's infinite weight
// makes it, but finite, so that a change of the terminals stays a number.
constexpr double kMostUnlikely = 1e6;

bool isBackground(uchar label) {
    return label == GC_BGD || label == GC_PR_BGD;
}

}  // namespace

// A Gaussian mixture of colours, as cv::grabCut's GMM: the same sums in the same order.
struct GrabCut::Mixture {
    double weight[kComponents], mean[kComponents][3], inverse[kComponents][9];
    double scale[kComponents];  // 1 / sqrt(det(covariance))
    double sums[kComponents][3], products[kComponents][9];
    int count[kComponents], total;

    void startLearning() {
        for (int k = 0; k < kComponents; ++k) {
            std::fill(sums[k], sums[k] + 3, 0.0);
            std::fill(products[k], products[k] + 9, 0.0);
            count[k] = 0;
        }
        total = 0;
    }

    void add(int k, const Vec3d& c) {
        for (int i = 0; i < 3; ++i) {
            sums[k][i] += c[i];
            for (int j = 0; j < 3; ++j) products[k][i * 3 + j] += c[i] * c[j];
        }
        ++count[k];
        ++total;
    }

    void endLearning() {
        for (int k = 0; k < kComponents; ++k) {
            const int n = count[k];
            weight[k] = n == 0 ? 0.0 : static_cast<double>(n) / total;
            if (n == 0) continue;
            double* m = mean[k];
            for (int i = 0; i < 3; ++i) m[i] = sums[k][i] / n;
            double c[9];
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j) c[i * 3 + j] = products[k][i * 3 + j] / n - m[i] * m[j];
            auto determinant = [&c] {
                return c[0] * (c[4] * c[8] - c[5] * c[7]) - c[1] * (c[3] * c[8] - c[5] * c[6]) +
                       c[2] * (c[3] * c[7] - c[4] * c[6]);
            };
            double det = determinant();
            // A component of one colour (or of colours on a line) has no volume: a little
            // variance makes it invertible. cv::grabCut adds it once and asserts; a component
            // still singular after that gets it again until it is not.
            while (det <= DBL_EPSILON) {
                c[0] += kVarianceFloor, c[4] += kVarianceFloor, c[8] += kVarianceFloor;
                det = determinant();
            }
            double* v = inverse[k];
            v[0] = (c[4] * c[8] - c[5] * c[7]) / det;
            v[3] = -(c[3] * c[8] - c[5] * c[6]) / det;
            v[6] = (c[3] * c[7] - c[4] * c[6]) / det;
            v[1] = -(c[1] * c[8] - c[2] * c[7]) / det;
            v[4] = (c[0] * c[8] - c[2] * c[6]) / det;
            v[7] = -(c[0] * c[7] - c[1] * c[6]) / det;
            v[2] = (c[1] * c[5] - c[2] * c[4]) / det;
            v[5] = -(c[0] * c[5] - c[2] * c[3]) / det;
            v[8] = (c[0] * c[4] - c[1] * c[3]) / det;
            scale[k] = 1.0 / std::sqrt(det);
        }
    }

    // Component k's density at c (without its weight).
    double density(int k, const Vec3d& c) const {
        if (weight[k] <= 0) return 0.0;
        const double d0 = c[0] - mean[k][0], d1 = c[1] - mean[k][1], d2 = c[2] - mean[k][2];
        const double* v = inverse[k];
        const double q = d0 * (d0 * v[0] + d1 * v[3] + d2 * v[6]) +
                         d1 * (d0 * v[1] + d1 * v[4] + d2 * v[7]) +
                         d2 * (d0 * v[2] + d1 * v[5] + d2 * v[8]);
        return scale[k] * std::exp(-0.5 * q);
    }

    double likelihood(const Vec3d& c) const {
        double p = 0;
        for (int k = 0; k < kComponents; ++k) p += weight[k] * density(k, c);
        return p;
    }

    int mostLikely(const Vec3d& c) const {
        int best = 0;
        double most = 0;
        for (int k = 0; k < kComponents; ++k) {
            const double p = density(k, c);
            if (p > most) most = p, best = k;
        }
        return best;
    }
};

GrabCut::GrabCut(const Mat& img, const Mat& labels)
    : img_(img), background_(std::make_unique<Mixture>()), subject_(std::make_unique<Mixture>()) {
    CV_Assert(img.type() == CV_8UC3 && labels.type() == CV_8UC1 && labels.size() == img.size());
    // The colour models start from k-means++ on each side's colours.
    std::vector<Vec3f> colours[2];
    for (int y = 0; y < img.rows; ++y)
        for (int x = 0; x < img.cols; ++x)
            colours[isBackground(labels.at<uchar>(y, x)) ? 0 : 1].push_back(
                Vec3f(img.at<Vec3b>(y, x)));
    if (colours[0].empty() || colours[1].empty())
        CV_Error(Error::StsBadArg,
                 "multicage: GrabCut needs pixels on both sides of its start (background and "
                 "subject)");
    Mixture* models[2] = {background_.get(), subject_.get()};
    for (int s = 0; s < 2; ++s) {
        Mat samples(static_cast<int>(colours[s].size()), 3, CV_32F, &colours[s][0][0]), ids;
        // A side of fewer pixels than components gets a component per pixel (so does
        // cv::grabCut's; the others stay empty).
        const int clusters = std::min(kComponents, samples.rows);
        kmeans(samples, clusters, ids, TermCriteria(TermCriteria::MAX_ITER, kKMeansIterations, 0),
               0, KMEANS_PP_CENTERS);
        models[s]->startLearning();
        for (size_t i = 0; i < colours[s].size(); ++i)
            models[s]->add(ids.at<int>(static_cast<int>(i)), Vec3d(colours[s][i]));
        models[s]->endLearning();
    }
    // The pairwise capacities: gamma exp(-beta |colour difference|^2) to each of the eight
    // neighbours (divided by sqrt 2 on the diagonals), beta from the mean squared difference.
    // Each pixel looks back at its left, up-left, up and up-right neighbours (cv::grabCut's
    // order, which its sum keeps): the neighbour reaches the pixel in GridCut's direction
    // 0..3 (right, down-right, down, down-left).
    auto behind = [&img](int x, int y, int i, Point& n) {
        n = Point(x, y) - GridCut::kStep[i];
        return n.x >= 0 && n.y >= 0 && n.x < img.cols;
    };
    double sum = 0;
    Point n;
    for (int y = 0; y < img.rows; ++y)
        for (int x = 0; x < img.cols; ++x)
            for (int i = 0; i < 4; ++i)
                if (behind(x, y, i, n)) {
                    const Vec3d d = Vec3d(img.at<Vec3b>(y, x)) - Vec3d(img.at<Vec3b>(n));
                    sum += d.dot(d);
                }
    const double pairs = 4.0 * img.cols * img.rows - 3.0 * img.cols - 3.0 * img.rows + 2.0;
    const double beta = sum <= DBL_EPSILON ? 0.0 : 1.0 / (2 * sum / pairs);
    graph_ = std::make_unique<GridCut>(img.size());
    for (int y = 0; y < img.rows; ++y)
        for (int x = 0; x < img.cols; ++x)
            for (int i = 0; i < 4; ++i)
                if (behind(x, y, i, n)) {
                    const Vec3d d = Vec3d(img.at<Vec3b>(y, x)) - Vec3d(img.at<Vec3b>(n));
                    // (cv::grabCut divides by the float square root of 2.)
                    const double gamma = i % 2 == 0 ? kGamma : kGamma / std::sqrt(2.0f);
                    graph_->setEdge(n, i, gamma * std::exp(-beta * d.dot(d)));
                }
}

GrabCut::~GrabCut() = default;

void GrabCut::iterate(Mat& labels) {
    CV_Assert(labels.type() == CV_8UC1 && labels.size() == img_.size());
    // Each pixel's component in its side's model, then both models learnt from them.
    Mat component(img_.size(), CV_8U);
    for (int y = 0; y < img_.rows; ++y)
        for (int x = 0; x < img_.cols; ++x) {
            const Vec3d c = img_.at<Vec3b>(y, x);
            const bool bg = isBackground(labels.at<uchar>(y, x));
            component.at<uchar>(y, x) =
                static_cast<uchar>((bg ? background_ : subject_)->mostLikely(c));
        }
    background_->startLearning();
    subject_->startLearning();
    for (int y = 0; y < img_.rows; ++y)
        for (int x = 0; x < img_.cols; ++x)
            (isBackground(labels.at<uchar>(y, x)) ? background_ : subject_)
                ->add(component.at<uchar>(y, x), Vec3d(img_.at<Vec3b>(y, x)));
    background_->endLearning();
    subject_->endLearning();
    // Terminals: a probable pixel pays -log of the other side's likelihood to be cut from
    // it; a sure one is tied to its side by lambda.
    auto cost = [](double likelihood) { return std::min(-std::log(likelihood), kMostUnlikely); };
    for (int y = 0; y < img_.rows; ++y)
        for (int x = 0; x < img_.cols; ++x) {
            const uchar l = labels.at<uchar>(y, x);
            double fromSource, toSink;
            if (l == GC_PR_BGD || l == GC_PR_FGD) {
                const Vec3d c = img_.at<Vec3b>(y, x);
                fromSource = cost(background_->likelihood(c));
                toSink = cost(subject_->likelihood(c));
            } else {
                fromSource = l == GC_BGD ? 0.0 : kLambda;
                toSink = l == GC_BGD ? kLambda : 0.0;
            }
            graph_->setTerminal(Point(x, y), fromSource, toSink);
        }
    graph_->maxFlow();
    for (int y = 0; y < img_.rows; ++y)
        for (int x = 0; x < img_.cols; ++x) {
            uchar& l = labels.at<uchar>(y, x);
            if (l == GC_PR_BGD || l == GC_PR_FGD)
                l = graph_->inSource(Point(x, y)) ? GC_PR_FGD : GC_PR_BGD;
        }
}

void seededGrabCut(const Mat& img, Mat& labels, int iterations, int settleWithin) {
    // GrabCut seeds its colour models with k-means++ from cv::theRNG(): a fixed seed makes
    // the proposal a function of the image (not of what ran before on this thread), and the
    // caller's generator is put back as it was.
    struct SeededRng {
        RNG saved = theRNG();
        SeededRng() { theRNG() = RNG(0x6d756c7469636167ULL); }
        ~SeededRng() { theRNG() = saved; }
    } seeded;
    GrabCut grabCut(img, labels);
    // When settling, the `iterations`-th iteration and those after it are each compared with
    // the labels before them.
    constexpr double kSettled = 0.01;  // of the pixels changing side in an iteration
    const bool settle = settleWithin > iterations;
    Mat before;
    for (int done = 1; done <= std::max(iterations, settleWithin); ++done) {
        const bool check = settle && done >= iterations;
        if (check) labels.copyTo(before);
        grabCut.iterate(labels);
        // GC_FGD (1) and GC_PR_FGD (3) have bit 0 set, GC_BGD (0) and GC_PR_BGD (2) do not.
        if (check && countNonZero((before ^ labels) & Scalar(1)) <= kSettled * labels.total())
            break;
    }
}

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv

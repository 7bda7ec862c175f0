// Colour-distinct regions.
//
// Saliency looks at the whole picture: on a uniform it lights up the face and the shirt front
// and merges a name tag or a patch into them, so the texture rule never sees them alone. A
// person sees a badge as a small thing of another colour on the cloth: here each work pixel is
// compared with the median colour of a window around it (0.3 times the polygon's size, more
// than a badge, less than a garment), and what differs much more than is typical inside the
// polygon becomes a candidate. Three shape tests then keep what a person would call one thing:
// compact (a strap or a flag's stripe is long and thin), not tiny (the work copy's minimum
// area), and alone of its kind (a butterfly's spots, a row of buttons, five red tunics repeat;
// a badge is one).
#include "distinct.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "texture.hpp"

namespace cv {
namespace multicage {
namespace propose_detail {

namespace {

constexpr double kWindow = 0.3;    // median window, of the polygon's longer side
constexpr double kTypical = 2.0;   // distinct: this many times the typical distance
constexpr double kMinFill = 0.45;  // of the region's bounding box
constexpr double kMaxElongation = 4.0;
constexpr double kSameColour = 20.0;  // Lab distance of two regions of one kind
constexpr int kMaxSiblings = 1;       // others of its kind a feature may have
constexpr int kMedianCopy = 4;        // the window's median on a copy this many times smaller

// Lab distance of every pixel of `lab` from the median of a k x k window (CV_32F).
Mat distanceFromMedian(const Mat& lab, int k) {
    // The median of a window this wide changes slowly: it is taken on a copy a quarter the size
    // (a 151-pixel median of a 512x400 channel takes 4.9 ms, a 37-pixel one of 128x100 0.4 ms;
    // on the benchmark the features and the polygons on nothing are the same at three scales).
    Mat small;
    resize(lab, small,
           Size(std::max(1, lab.cols / kMedianCopy), std::max(1, lab.rows / kMedianCopy)), 0, 0,
           INTER_AREA);
    std::vector<Mat> channels;
    split(small, channels);
    for (Mat& c : channels) medianBlur(c, c, std::max(3, k / kMedianCopy) | 1);
    Mat median;
    merge(channels, median);
    resize(median, median, lab.size(), 0, 0, INTER_LINEAR);
    Mat diff;
    absdiff(lab, median, diff);
    diff.convertTo(diff, CV_32F);
    diff = diff.mul(diff);
    Mat sum = diff.reshape(1, diff.rows * diff.cols);
    reduce(sum, sum, 1, REDUCE_SUM);
    sqrt(sum, sum);
    return sum.reshape(1, lab.rows);
}

// The median of `values` (CV_32F, >= 0) over `mask`, to the unit.
double medianOver(const Mat& values, const Mat& mask) {
    std::vector<int> histogram(512, 0);
    int count = 0;
    for (int y = 0; y < values.rows; ++y)
        for (int x = 0; x < values.cols; ++x)
            if (mask.at<uchar>(y, x)) {
                ++histogram[std::min(511, cvRound(values.at<float>(y, x)))];
                ++count;
            }
    for (int v = 0, seen = 0; v < 512; ++v)
        if ((seen += histogram[v]) * 2 >= count) return v;
    return 0.0;
}

}  // namespace

Mat distinctRegions(const Mat& img8, const Mat& inside, const Work& w) {
    Mat out = Mat::zeros(w.size, CV_8U);
    const Rect roi = boundingRect(inside);
    if (roi.area() == 0) return out;
    Mat bgr = img8;
    if (img8.channels() == 1) cvtColor(img8, bgr, COLOR_GRAY2BGR);
    if (img8.channels() == 4) cvtColor(img8, bgr, COLOR_BGRA2BGR);
    Mat lab;
    cvtColor(toWork(bgr, w, INTER_AREA)(roi), lab, COLOR_BGR2Lab);
    const int k = std::max(15, cvRound(kWindow * std::max(roi.width, roi.height))) | 1;
    const Mat distance = distanceFromMedian(lab, k);
    const Mat in = inside(roi);
    const double threshold = std::max(kDistinctFloor, kTypical * medianOver(distance, in));
    Mat candidates = (distance > threshold) & in;
    const int r = std::max(1, cvRound(0.005 * std::max(roi.width, roi.height)));
    morphologyEx(candidates, candidates, MORPH_CLOSE,
                 getStructuringElement(MORPH_ELLIPSE, Size(2 * r + 1, 2 * r + 1)));
    morphologyEx(candidates, candidates, MORPH_OPEN, getStructuringElement(MORPH_RECT, Size(3, 3)));

    Mat ids, stats, centroids;
    const int n = connectedComponentsWithStats(candidates, ids, stats, centroids, 8, CV_32S);
    std::vector<Vec3d> colour(n, Vec3d());
    for (int y = 0; y < ids.rows; ++y)
        for (int x = 0; x < ids.cols; ++x) {
            const Vec3b& c = lab.at<Vec3b>(y, x);
            colour[ids.at<int>(y, x)] += Vec3d(c[0], c[1], c[2]);
        }
    const double insideArea = countNonZero(in);
    std::vector<int> shaped;  // regions of a feature's size and shape
    for (int i = 1; i < n; ++i) {
        const int area = stats.at<int>(i, CC_STAT_AREA);
        const int bw = stats.at<int>(i, CC_STAT_WIDTH), bh = stats.at<int>(i, CC_STAT_HEIGHT);
        colour[i] /= area;
        if (area >= w.minArea && area <= kFeatureShare * insideArea && area >= kMinFill * bw * bh &&
            std::max(bw, bh) <= kMaxElongation * std::min(bw, bh))
            shaped.push_back(i);
    }
    std::vector<char> keep(n, 0);
    for (int i : shaped) {
        int siblings = 0;
        for (int j : shaped) {
            const double ratio =
                double(stats.at<int>(j, CC_STAT_AREA)) / stats.at<int>(i, CC_STAT_AREA);
            siblings +=
                j != i && norm(colour[i] - colour[j]) < kSameColour && ratio >= 0.5 && ratio <= 2.0;
        }
        keep[i] = siblings <= kMaxSiblings;
    }
    Mat kept = out(roi);
    for (int y = 0; y < ids.rows; ++y)
        for (int x = 0; x < ids.cols; ++x)
            if (keep[ids.at<int>(y, x)]) kept.at<uchar>(y, x) = 255;
    return out;
}

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv

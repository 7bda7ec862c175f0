#include "masks.hpp"

#include <opencv2/imgproc.hpp>
#include <vector>

namespace cv {
namespace multicage {
namespace propose_detail {

Mat piecesHolding(const Mat& mask, const Mat& sure) {
    Mat ids;
    const int n = connectedComponents(mask, ids, 8, CV_32S);
    std::vector<char> keep(n, 0);
    for (int y = 0; y < ids.rows; ++y)
        for (int x = 0; x < ids.cols; ++x)
            if (sure.at<uchar>(y, x)) keep[ids.at<int>(y, x)] = 1;
    keep[0] = 0;
    Mat out = mask.clone();
    for (int y = 0; y < ids.rows; ++y)
        for (int x = 0; x < ids.cols; ++x)
            if (!keep[ids.at<int>(y, x)]) out.at<uchar>(y, x) = 0;
    return out;
}

Mat cleanMask(const Mat& mask, int radius, double minArea) {
    Mat out = mask.clone();
    if (radius > 0) {
        const Mat disk = getStructuringElement(MORPH_ELLIPSE, Size(2 * radius + 1, 2 * radius + 1));
        morphologyEx(out, out, MORPH_OPEN, disk);
        // Close with a zero border of the kernel's size so objects cut by the image edge are
        // not glued to it (the default border of morphologyEx would count as object).
        Mat padded;
        copyMakeBorder(out, padded, radius + 1, radius + 1, radius + 1, radius + 1, BORDER_CONSTANT,
                       0);
        morphologyEx(padded, padded, MORPH_CLOSE, disk, Point(-1, -1), 1, BORDER_CONSTANT, 0);
        out = padded(Rect(radius + 1, radius + 1, mask.cols, mask.rows)).clone();
    }
    // Drop small regions, then fill small holes (a hole is a region of the background).
    for (int pass = 0; pass < 2; ++pass) {
        Mat subject = pass == 0 ? out : ~out;
        Mat labels, stats, centroids;
        const int n = connectedComponentsWithStats(subject, labels, stats, centroids, 8, CV_32S);
        std::vector<uchar> small(n, 0);
        bool any = false;
        for (int i = 1; i < n; ++i)
            if (stats.at<int>(i, CC_STAT_AREA) < minArea) small[i] = 1, any = true;
        if (!any) continue;
        for (int y = 0; y < out.rows; ++y) {
            const int* l = labels.ptr<int>(y);
            uchar* o = out.ptr<uchar>(y);
            for (int x = 0; x < out.cols; ++x)
                if (small[l[x]]) o[x] = pass == 0 ? 0 : 255;
        }
    }
    return out;
}

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv

// The proposal's working copy (private): ProposeParams checked and resolved into pixels of a
// downscaled copy of the image, and the moves between the copy and the input.
#ifndef MULTICAGE_PROPOSE_WORK_HPP
#define MULTICAGE_PROPOSE_WORK_HPP

#include <opencv2/multicage/internal/geometry.hpp>
#include <opencv2/multicage/propose.hpp>

namespace cv {
namespace multicage {
namespace propose_detail {

using geometry::Polygon;

constexpr int kMinPolygonVertices = 4;  // the bounding-box fallback needs 4

/** Throws StsOutOfRange naming the first field of `p` out of its range. */
void checkParams(const ProposeParams& p);

// The parameters in pixels of the working copy.
struct Work {
    Size full, size;
    double scale = 1.0;    // full pixels per work pixel
    float margin = 0.f;    // distance from object to polygon
    float gap = 0.f;       // half the least distance between two polygons
    int radius = 0;        // cleaning
    double minArea = 0.0;  // pixels
};

/** The working copy for an input of size `full`. */
Work resolve(Size full, const ProposeParams& p);
/** img scaled by s into out, exactly as resize(img, out, Size(), s, s, interpolation) does,
except that each side keeps at least minSide pixels (or all it has, where fewer): a thin
image's smaller copies (GrabCut's, the saliency map's) keep the rows a frame strip and a band
need instead of rounding to none. s >= 1: out is img. Returns the scale applied per axis. */
Point2d shrink(const Mat& img, Mat& out, double s, int interpolation, int minSide = 8);
/** An input-size image resized to the work size (itself when the sizes agree). */
Mat toWork(const Mat& img, const Work& w, int interpolation);
/** A work-size mask resized to the input size, thresholded at 127. */
Mat fromWork(const Mat& mask, const Work& w);
/** Distance of every pixel to the nearest zero pixel of `src` (exact Euclidean). */
Mat distanceTo(const Mat& src);
/** Fills a polygon given in input pixels into a work-size mask. */
void fillWork(Mat& mask, const Polygon& p, const Work& w, const Scalar& value);

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv

#endif

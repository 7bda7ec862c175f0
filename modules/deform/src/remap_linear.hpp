// The CPU backend's bilinear sampling (private): cv::remap's arithmetic, faster on 8-bit colour.
#ifndef MULTICAGE_REMAP_LINEAR_HPP
#define MULTICAGE_REMAP_LINEAR_HPP

#include <opencv2/core.hpp>

namespace cv {
namespace multicage {

/** cv::remap(src, dst, mapx, mapy, INTER_LINEAR, BORDER_CONSTANT, border), bit for bit (the
same fixed-point maps, weights and rounding), src not dst. 8-bit 3-channel images on CPUs with
AVX-512 or AVX2 take a path of their own, faster than OpenCV's (whose build here dispatches remap
to SSE2 only); any other image is cv::remap's. */
void remapLinear(const Mat& src, OutputArray dst, const Mat& mapx, const Mat& mapy,
                 const Scalar& border);

/** Rows [y0, y1) of what remapLinear writes, into dst already made (mapx's size, src's type),
on this thread: for a caller that samples a band of rows while its maps are still in cache. */
void remapLinearRows(const Mat& src, Mat& dst, const Mat& mapx, const Mat& mapy,
                     const Scalar& border, int y0, int y1);

/** Whether remapLinear takes its own path for images of this type on this CPU (for tests). */
bool remapLinearOwnPath(int type);

/** The paths, for tests that compare them: `best` is this CPU's own (AVX-512, else AVX2). */
enum class RemapPath { best, avx2 };

/** Makes remapLinear take `path` (RemapPath::best: choose again); false, changing nothing, where
this CPU or build cannot run it. */
bool preferRemapPath(RemapPath path);

}  // namespace multicage
}  // namespace cv

#endif

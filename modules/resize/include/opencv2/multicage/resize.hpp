/** @file
@brief Content-aware resizing (the paper's §6: "multicage deformation as constraints in image
resizing"): bind once, then every target size is one pose.
@ingroup multicage_resize
*/
#ifndef OPENCV2_MULTICAGE_RESIZE_HPP
#define OPENCV2_MULTICAGE_RESIZE_HPP

#include <opencv2/multicage/deformer.hpp>
#include <opencv2/multicage/propose.hpp>

namespace cv {
namespace multicage {

//! @addtogroup multicage_resize
//! @{

/** @brief Parameters of resizePose() and contentAwareResize(). */
struct CV_EXPORTS ResizeParams {
    /** CoordinateType of the binding contentAwareResize() makes (COORDINATES_FROM_CAGE: the
    cage's). Local mean value coordinates by default: what an outline holds then follows the
    outline's similarity exactly, where Algorithm 1's global sums leak the frame's stretch
    into it (docs/resize). */
    int coordinates = LOCAL_MEAN_VALUE;
    int gridStep = 1;            //!< its grid step (DeformParams::gridStep)
    int backend = BACKEND_AUTO;  //!< its Backend
    /** ProtectDetector of the default proposal (an empty cage in contentAwareResize()):
    faces first, then salient features (no face cascade installed: features only); -1:
    ProposeParams' own default. */
    int protect = PROTECT_ALL;
    /** ProposeParams::margin of the default proposal (< 0: its automatic margin). */
    float margin = -1.f;
    /** ProposeParams::segmenter of the default proposal (ProposeSegmenter; SEGMENTER_AUTO: the
    learned subject model when one is found, else the classic cues). */
    int segmenter = SEGMENTER_AUTO;
    /** ProposeParams::segmenterModel of the default proposal (empty: the usual look-up,
    segmenterModelFile()). */
    String segmenterModel;
    /** The largest factor a side may grow by (the target's side <= maxScale x the image's):
    an output 8x wider holds 64x the pixels, and the maps 8 bytes per output pixel. */
    double maxScale = 8.0;
    /** The largest aspect change the warp takes alone (the ratio of the frame's two scales):
    beyond it the output shows a window of the image, chosen by reframeWindow(), and the warp
    takes the rest. 1.5 lets 4:3 become 16:9 by the warp alone; 16:9 to 9:16 (3.2) crops. A
    value below 1 never crops. */
    double maxWarp = 1.5;
};

/** @brief The pose that resizes an image bound to `cage` into an image of newSize
(docs/resize).

Rule (with sx = W'/W, sy = H'/H the frame's scales):
  - the frame corners go to the new frame (-0.5,-0.5)-(W'-0.5,H'-0.5);
  - each outline (a depth-1 polygon) moves by a similarity `p' = c' + s (p - c)` of its
    bounding box's centre c: s = 1 when 1 lies between min(sx, sy) and max(sx, sy) (the
    subject keeps its size in pixels: the background absorbs the aspect change), else the one
    of the two nearer 1; s shrinks further (uniformly, never squashed) when the outline would
    not fit in the new frame with its gaps to the frame scaled as the frame is;
  - c' is where the frame's own scaling puts c, so subjects keep their places and their
    distances scale with the frame; an outline within 1% of a side of the frame (a subject cut
    by the image border) keeps its gap to that side instead, so it stays on that border;
  - every inner polygon (depth >= 2: faces, features, what a person nested to protect) moves
    by the similarity of the outline around it, so what an outline holds keeps its shape;
  - the background between the frame and the outlines absorbs the rest.

Where outlines of two subjects would cross, or the pose would fold a triangle of the mesh,
the outlines are blended towards the frame's own scaling (the cv::resize pose, always valid and
fold-free by linear precision) by the least amount that makes it valid, while every inner
polygon stays a similarity (so with local mean value coordinates what it holds keeps its shape
exactly); only where that cannot start does everything blend. The returned pose always
validates and folds no triangle of `binding`'s mesh.

This form checks folds on a binding of cage with params.coordinates (local mean value by
default) at params.gridStep: the pose is fold-free for a Deformer bound the same way (it binds
each call: use the form with a Binding, the Deformer's own, to resize many times).
@param cage a multicage that passes validate() (else cv::Exception, StsBadArg).
@param newSize each side at least 1 and 1/64 of the image's, and at most params.maxScale x the
image's (else cv::Exception StsOutOfRange naming the limit; checkResizeSize()).
@param params coordinates, gridStep and maxScale are read.
@return vertexCount()+4 points, frame corners last: Deformer::deform renders it into a newSize
image.
*/
CV_EXPORTS std::vector<Point2f> resizePose(const Multicage& cage, Size newSize,
                                           const ResizeParams& params = ResizeParams());
/** @brief resizePose() checking folds on this binding (Deformer::binding()): no binding made.
@param cage as the other form.
@param binding a binding of cage (its image size and coefficient count; else cv::Exception,
StsBadArg).
@param newSize as the other form.
@param params maxScale is read.
@return as the other form.
*/
CV_EXPORTS std::vector<Point2f> resizePose(const Multicage& cage, const Binding& binding,
                                           Size newSize,
                                           const ResizeParams& params = ResizeParams());

/** @brief Resizes image to newSize keeping what the multicage protects: binds image to cage,
then deforms it to resizePose().

For several sizes of one image, make a Deformer once and deform it to
resizePose(cage, deformer->binding(), size) per size.
@param image the image, as Deformer::create takes it; not empty (else cv::Exception,
StsBadArg).
@param newSize as resizePose().
@param[out] dst newSize, the image's type.
@param cage the multicage; an empty one (default-constructed): resizeCage(); one drawn on
another size is scaled to the image (Multicage::scaled()).
@param params the binding's coordinates, grid step and backend, and the default proposal's
options.
*/
CV_EXPORTS void contentAwareResize(InputArray image, Size newSize, OutputArray dst,
                                   const Multicage& cage = Multicage(),
                                   const ResizeParams& params = ResizeParams());

/** @brief The multicage contentAwareResize() uses for image when given none.

proposeProtectedMulticage() with params.protect, params.margin, params.segmenter and
params.segmenterModel; for an image too thin to propose in (a strip under 3 pixels each way in
the proposal's working copy), no polygon: it scales plainly.
@param image the image.
@param params protect, margin, segmenter and segmenterModel are read.
@return the multicage, of the image's size.
*/
CV_EXPORTS Multicage resizeCage(InputArray image, const ResizeParams& params = ResizeParams());

/** @brief Checks that newSize is a size resizePose() accepts for an image of imageSize: each
side >= 1, >= 1/64 and <= maxScale x the image's.
@param imageSize the image's size, not empty (else StsBadSize).
@param newSize the target size.
@param maxScale the largest factor a side may grow by (ResizeParams::maxScale).
@throws cv::Exception (StsOutOfRange) naming the limit newSize breaks.
*/
CV_EXPORTS void checkResizeSize(Size imageSize, Size newSize, double maxScale = 8.0);

/** @brief The part of an image bound to `cage` that an output of newSize shows (crop and warp,
docs/resize).
When the frame's scales sx = W'/W and sy = H'/H differ by at most params.maxWarp, the whole
image. Otherwise the side with the larger scale is kept whole and the other is cut to a window:
  - the window holds every outline that the plain crop (the target's aspect at the full other
    side) could hold, and of a wider outline the polygons it protects (faces, features) that the
    plain crop could hold; a polygon wider than the plain crop is cut, as a crop would cut it, and
    keeps its size (shrinking it would stretch what is around it);
  - outlines first, then inner polygons, each in the cage's order (a proposal lists faces before
    features): one is left out when holding it too would leave the resize pose no room to keep
    what the window holds apart at its scale (two polygons overlapping across the cut axis
    placed as resizePose() places them, under 2% of the output apart, or nearer than a uniform
    squeeze would bring them); the window may then cut it;
  - with 4% of the plain crop to spare on each side (6% of the window where subjects far apart
    widen it past the plain crop); never narrower than the plain crop, nor wider than the
    image;
  - centred on what it holds, moved inside the image; with nothing held, centred on the
    outlines, or on the image.
The warp then takes the window's aspect to the target's: where the window is a plain crop it is a
uniform scale, where it holds subjects far apart the background between them absorbs the rest.
@param cage a multicage (its image size is the image's; polygons need not be oriented).
@param newSize the target size, not empty.
@param params maxWarp is read.
@return the window in pixel edges (pixel (i, j) covers [i, i+1) x [j, j+1), the whole image is
(0, 0, W, H)); fractional where a caller smooths it over time.
*/
CV_EXPORTS Rect2d reframeWindow(const Multicage& cage, Size newSize,
                                const ResizeParams& params = ResizeParams());
/** @brief The whole pixels that cover window (reframeWindow()), inside an image of imageSize.
@param window a window in pixel edges, as reframeWindow() gives it.
@param imageSize the image's size.
@return the smallest rectangle of whole pixels holding window, clipped to the image. */
CV_EXPORTS Rect windowCrop(const Rect2d& window, Size imageSize);
/** @brief A photo's window: reframeWindow() rounded to whole pixels, so that the crop is resized
to newSize exactly (the whole image where the warp alone takes the change). contentAwareResize()
and `multicage resize` use it.
@param cage as reframeWindow().
@param newSize as reframeWindow().
@param params as reframeWindow().
@return the crop, inside the image. */
CV_EXPORTS Rect reframeCrop(const Multicage& cage, Size newSize,
                            const ResizeParams& params = ResizeParams());
/** @brief The multicage on a crop of its image: each polygon that lies inside the crop's frame
(its pixels' outer edges; on the whole image, every polygon of a valid multicage), moved to the
crop's pixels; a polygon the crop cuts is dropped, so what it held
becomes an outline of its own. Oriented, with the cage's coordinate type.
@param cage the multicage.
@param crop the crop, not empty.
@param[out] kept if given, the indices in cage of the polygons kept, in order.
@return a multicage of crop.size(), valid when cage is. */
CV_EXPORTS Multicage cropMulticage(const Multicage& cage, const Rect& crop,
                                   std::vector<int>* kept = nullptr);
/** @brief Moves the polygons of a pose of the crop (resizePose() of cropMulticage() to newSize)
to where showing window, which the crop covers, puts them; the frame corners stay on newSize's
frame. For a window smoothed over time: its subjects follow it to a fraction of a pixel, while
the frame shows whole pixels of the image, the background between taking up the difference
(under a pixel). The result may cross or fold where the crop's pose is tight: check it.
@param cropPose the pose on the crop, frame corners last.
@param newSize the output size.
@param crop windowCrop() of window.
@param window the window.
@return the pose, as many points as cropPose. */
CV_EXPORTS std::vector<Point2f> windowPose(const std::vector<Point2f>& cropPose, Size newSize,
                                           const Rect& crop, const Rect2d& window);
//! @} multicage_resize

}  // namespace multicage
}  // namespace cv

#endif

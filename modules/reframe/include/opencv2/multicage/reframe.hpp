/** @file
@brief Reframing clips: a clip to another aspect ratio, frame by frame, with its subjects
tracked and kept in shape, and nothing jumping from one frame to the next.
@ingroup multicage_reframe
*/
#ifndef OPENCV2_MULTICAGE_REFRAME_HPP
#define OPENCV2_MULTICAGE_REFRAME_HPP

#include <opencv2/multicage/resize.hpp>
#include <opencv2/multicage/track.hpp>
#include <string>
#include <vector>

namespace cv {
namespace multicage {

//! @addtogroup multicage_reframe
//! @{

/** @brief Options of VideoReframer. */
struct CV_EXPORTS ReframeParams {
    /** The resize of each frame: coordinates, backend, the proposal's options, maxWarp (crop
    and warp, reframeWindow()). The grid step is 2 for clips: a binding per frame is the
    largest cost, and a step of 2 keeps faces within a pixel of a similarity (docs/video). */
    ResizeParams resize = [] {
        ResizeParams p;
        p.gridStep = 2;
        return p;
    }();
    /** How polygons follow their subjects (CageTracker). */
    TrackParams track;
    /** Frames on each side of a frame that its window and pose are averaged over (a Gaussian of
    standard deviation smoothing / 2, within one shot and one multicage): subjects glide
    instead of jumping. The output runs 2 x smoothing frames behind the input (lag()); 0: no
    smoothing, no lag. */
    int smoothing = 6;
    /** With no polygon on the frames (nothing proposed), a proposal is tried again after this
    many frames (and at every cut): a subject that walks in is picked up. After a frame with
    nothing to segment (a black frame), the next frame is tried. */
    int retryEmptyEvery = 30;
};

/** @brief One output frame of VideoReframer, with how it was made. */
struct CV_EXPORTS ReframedFrame {
    Mat image;       //!< the output frame, of the reframer's size and the input's type
    int index = -1;  //!< its input frame's index (0 first)
    int shot = 0;    //!< the shot it belongs to (a cut starts the next)
    /** The window of the input frame it shows (reframeWindow(), smoothed over time), and the
    whole pixels covering it (windowCrop()). */
    Rect2d window;
    Rect crop;          //!< windowCrop() of window: the part of the input frame that was bound
    Multicage cage;     //!< the tracked multicage on the crop (cropMulticage()), at rest
    Multicage tracked;  //!< the tracked multicage on the whole input frame
    /** The pose the crop was deformed to (smoothed over time), frame corners last: cage's
    vertices onto the output frame. */
    std::vector<Point2f> pose;
    bool smoothed = false;  //!< false where the averaged pose was invalid and its own was used
};

/** @brief What a VideoReframer did so far, and where its time went (milliseconds, summed). */
struct CV_EXPORTS ReframeStats {
    int framesIn = 0;      //!< frames pushed
    int framesOut = 0;     //!< frames ready or popped
    int proposals = 0;     //!< multicages proposed (the first frame, cuts, lost subjects)
    int cuts = 0;          //!< cuts found (CageTracker's TRACK_CUT)
    int lost = 0;          //!< frames where a subject was lost (TRACK_LOST)
    int unsmoothed = 0;    //!< frames whose averaged pose was invalid or folded (own pose used)
    double proposeMs = 0;  //!< proposing multicages (resizeCage())
    double trackMs = 0;    //!< CageTracker::track()
    double bindMs = 0;     //!< binding each frame's crop (Deformer::create())
    double poseMs = 0;     //!< resizePose() and windowPose()
    double deformMs = 0;   //!< Deformer::deform()
    std::string lastWhy;   //!< why the last proposal was made, in words
};

/** @brief Reframes a clip to another size or aspect ratio, frame by frame: the tracked
multicage of each frame is resized (resizePose(), with a crop where the aspect change is more
than the warp takes: reframeWindow()), and the windows and poses are averaged over nearby frames,
so that subjects glide instead of jumping.

Frames go in with push() and come out with pop(), ReframeParams::smoothing x 2 frames later
(the averages look that far ahead); finish() lets the last ones out. On the first frame, at
every cut and where a subject is lost, the multicage is proposed afresh (resizeCage());
otherwise CageTracker moves it, and each polygon keeps its shape. Works on frames from any reader
(cv::VideoCapture, PyAV, numpy arrays).
@code
VideoReframer reframer(Size(405, 720));
ReframedFrame out;
while (capture.read(frame)) {
    reframer.push(frame);
    while (reframer.pop(out)) writer.write(out.image);
}
reframer.finish();
while (reframer.pop(out)) writer.write(out.image);
@endcode
@sa docs/video/README.md
*/
class CV_EXPORTS VideoReframer {
  public:
    /** @brief A reframer to frames of newSize.
    @param newSize the output size; with the first frame, checkResizeSize() applies.
    @param params the options.
    @param cage the multicage of the first frame (empty: proposed); later ones are proposed. */
    explicit VideoReframer(Size newSize, const ReframeParams& params = ReframeParams(),
                           const Multicage& cage = Multicage());
    ~VideoReframer();
    /** @brief Adds the next frame of the clip.
    @param frame 8-bit, 1, 3 or 4 channels; every frame of the first's size and type (else
    cv::Exception, StsBadArg). */
    void push(InputArray frame);
    /** @brief Takes the next output frame, when one is ready.
    @param[out] out the frame and how it was made.
    @return false when no frame is ready yet (push more, or finish()). */
    bool pop(ReframedFrame& out);
    /** @brief Marks the end of the clip: every frame pushed becomes ready to pop(). */
    void finish();
    /** @brief How many frames the output runs behind the input.
    @return 2 x ReframeParams::smoothing. */
    int lag() const;
    /** @brief The output size.
    @return the size given to the constructor. */
    Size size() const;
    /** @brief What was done so far, and where the time went.
    @return the counts and times, summed since the first frame. */
    const ReframeStats& stats() const;

    struct Impl;  //!< the frames in flight (reframer.cpp)

  private:
    Ptr<Impl> impl_;
};

//! @}

}  // namespace multicage
}  // namespace cv

#endif

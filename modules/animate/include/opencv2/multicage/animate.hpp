/** @file
@brief Keyframed poses over time (the paper's animation by moving multicage vertices).

A multicage's poses are the keyframes: Pose::time says when each is reached (seconds).
samplePose() interpolates between them; renderAnimation() binds once and writes one
deformed frame per time step to a video, a GIF or a folder of PNG frames.
@ingroup multicage_animate
*/
#ifndef OPENCV2_MULTICAGE_ANIMATE_HPP
#define OPENCV2_MULTICAGE_ANIMATE_HPP

#include <functional>
#include <opencv2/multicage/deformer.hpp>
#include <opencv2/multicage/multicage.hpp>
#include <string>
#include <vector>

namespace cv {
namespace multicage {

//! @addtogroup multicage_animate
//! @{

/** @brief How samplePose() moves between keyframes (AnimationParams::interpolation). */
enum PoseInterpolation {
    /** Straight lines between consecutive keyframes: exact at keyframes, velocity jumps there. */
    INTERPOLATE_LINEAR = 0,
    /** Cubic Hermite segments whose tangent at keyframe i is the finite difference
    `(p[i+1] - p[i-1]) / (t[i+1] - t[i-1])`: Catmull & Rom 1974 for non-uniform times. It
    passes through every keyframe with continuous velocity. Ends of a clamped animation use the
    one-sided difference; a looped one wraps its neighbours. */
    INTERPOLATE_CATMULL_ROM = 1
};

/** @brief Checks that the poses can drive an animation: at least two poses, every time finite,
no two poses at the same time. Poses need not be stored in time order.
@param cage the multicage whose poses are the keyframes.
@param[out] why when not null, receives on failure one sentence that says what is needed ("an
animation needs at least two timed poses; the cage has one ('flap')").
@return true when the keyframes can drive an animation.
*/
CV_EXPORTS bool validateKeyframes(const Multicage& cage, std::string* why = nullptr);

/** @brief Pose indices ordered by time (ties keep their stored order).
@param cage the multicage whose poses are the keyframes.
@return poseCount() indices.
*/
CV_EXPORTS std::vector<int> keyframeOrder(const Multicage& cage);

/** @brief Time of the earliest pose.
@param cage the multicage whose poses are the keyframes.
@return seconds (0 without poses).
*/
CV_EXPORTS double animationStart(const Multicage& cage);
/** @brief Time of the latest pose.
@param cage the multicage whose poses are the keyframes.
@return seconds (0 without poses).
*/
CV_EXPORTS double animationEnd(const Multicage& cage);

/** @brief Length of one play-through in seconds.

Clamped: animationEnd - animationStart. Looped: that plus a closing segment from the last
keyframe back to the first, as long as the mean keyframe spacing, i.e. `span * n / (n - 1)`
for n keyframes.
@param cage the multicage whose poses are the keyframes.
@param loop whether the animation loops.
@return seconds.
*/
CV_EXPORTS double animationDuration(const Multicage& cage, bool loop = false);

/** @brief The pose at time t (seconds, on the keyframes' clock).
@param cage with at least two poses at distinct finite times (validateKeyframes()).
@param t the time; finite.
@param interpolation a PoseInterpolation.
@param loop false: t before the first keyframe gives the first pose, after the last the last
pose; true: t wraps with period animationDuration(cage, true), and the closing segment leads
smoothly from the last keyframe to the first.
@return vertexCount() points (no frame corners), the keyframe's vertices exactly when t is a
keyframe time.
@throws cv::Exception (StsBadArg) with validateKeyframes()'s sentence when the keyframes
cannot drive an animation, and for an unknown interpolation or a time that is not finite.
*/
CV_EXPORTS std::vector<Point2f> samplePose(const Multicage& cage, double t,
                                           int interpolation = INTERPOLATE_CATMULL_ROM,
                                           bool loop = false);

/** @brief Adds a keyframe: pose `vertices` reached at `time`. Meant for an editor's "add
keyframe" button.

A pose already at that time (within 1 microsecond) is replaced, keeping its name unless
`name` is given; otherwise the pose is appended, named `name` or "key_" and the time in
milliseconds (with a suffix _2, _3, ... when that name is taken).
@param cage the multicage to add to.
@param vertices vertexCount() points, or +4 with the frame corners last.
@param time seconds; finite (else cv::Exception, StsBadArg).
@param name the pose's name; empty: the one above.
@return the pose's index.
*/
CV_EXPORTS int addKeyframe(Multicage& cage, InputArray vertices, double time,
                           const std::string& name = std::string());

/** @brief Options of an animation: frame rate, length, looping and interpolation. */
struct CV_EXPORTS AnimationParams {
    double fps = 25.0;  //!< frames per second of the output
    /** Seconds of output; <= 0 means one play-through (animationDuration(cage, loop)).
    Longer than that holds the last pose (clamped) or repeats the cycle (loop). */
    double duration = 0.0;
    bool loop = false;                            //!< see samplePose()
    int interpolation = INTERPOLATE_CATMULL_ROM;  //!< PoseInterpolation
};

/** @brief Keyframe-clock time of every output frame.

Clamped: n = round(duration * fps) + 1 frames evenly spaced from animationStart to
animationStart + duration, so the first and last frames are exactly the first and last
keyframes. Looped: n = round(duration * fps) frames evenly spaced over [start, start +
duration), so that playing the output on repeat is seamless. At least 2 frames.
@param cage the multicage whose poses are the keyframes.
@param params fps finite and positive; duration finite (<= 0, the default: one play-through).
@return the times in seconds.
@throws cv::Exception (StsBadArg) like samplePose() on bad keyframes, on an fps that is not
finite and positive or a duration that is not finite, and past a million frames.
*/
CV_EXPORTS std::vector<double> animationFrameTimes(const Multicage& cage,
                                                   const AnimationParams& params);

/** @brief Where the frames go, picked from the path: a folder of PNG frames (a path ending in
'/', or an existing folder), ".mp4" (H.264, else MPEG-4 part 2), ".avi" (Motion JPEG),
".gif". */
enum AnimationFormat {
    ANIMATION_FRAMES = 0,  //!< a folder of frame_NNNN.png files
    ANIMATION_MP4 = 1,     //!< .mp4: H.264, else MPEG-4 part 2
    ANIMATION_AVI = 2,     //!< .avi: Motion JPEG
    ANIMATION_GIF = 3      //!< .gif: one palette, looping forever
};

/** @brief The format for `path`, checking that it can be written.
@param path the output: a folder (ending in '/', or existing), or a .mp4, .avi or .gif file.
@return an AnimationFormat.
@throws cv::Exception (StsBadArg) with one sentence: an unknown extension ("use .mp4, .avi,
.gif or a folder ending in /"), or an output that cannot be written (no such parent folder,
not writable, a folder that holds files other than frames).
*/
CV_EXPORTS int checkAnimationOutput(const String& path);

/** @brief Writes frames to a video, a GIF or a folder of PNG frames, all or nothing.

Frames go to a temporary file (or folder) beside `path`, finish() renames it into place, and
a writer destroyed before finish() removes it, so `path` never holds a partial animation. An
existing frames folder is replaced only if it holds nothing but frame_NNNN.png files.

Frames: all the same size, CV_8UC1, CV_8UC3 (BGR) or CV_8UC4 (BGRA; alpha dropped for video
and GIF); 16-bit and float frames are scaled to 8 bits for video and GIF (x1/257; floats x255
when the first frame's values are in [0, 1], a maximum up to 2 included, else x1); PNG frames
keep 8 and 16 bits and store floats as 16 bits (x65535, or x257 for 0-255 floats). note()
says which. Video frames of odd width or height are padded by one pixel (the edge repeated),
since 4:2:0 chroma needs even sizes. GIF: one palette of 255 colours found by k-means on the
first frame (deformed frames reuse the image's colours), unchanged pixels written as
transparent and each frame cropped to what changed, repeats forever. Delays are in 1/100 s,
at least 2.
@sa renderAnimation, checkAnimationOutput
*/
class CV_EXPORTS AnimationWriter {
  public:
    /** @brief A writer for path.
    @param path as checkAnimationOutput().
    @param fps frames per second; finite and positive.
    @return the writer.
    @throws cv::Exception (StsBadArg) as checkAnimationOutput(), and for a bad fps. */
    static Ptr<AnimationWriter> create(const String& path, double fps);
    /** @brief Removes the temporary output when finish() was not called. */
    virtual ~AnimationWriter();
    /** @brief Appends a frame.
    @param frame as the class description says; not empty, the first frame's size and type. */
    virtual void write(InputArray frame) = 0;
    /** @brief Closes the file and moves it to the path.
    @throws cv::Exception when no frames were written, or the output cannot be written. */
    virtual void finish() = 0;
    /** @brief Frames written so far.
    @return the count. */
    virtual int frameCount() const = 0;
    /** @brief The output's format.
    @return an AnimationFormat. */
    virtual int format() const = 0;
    /** @brief What the writer changed to store the frames, in one sentence, or "".

    A depth scaled ("the float frames (values 0-1) were scaled by 255 to 8 bits"), a size
    padded ("padded from 493x356 to 494x356: the codec needs even sizes"). Known after the first
    frame.
    @return the sentence, or "". */
    virtual String note() const = 0;
};

/** @brief What renderAnimation() did and where its time went. */
struct CV_EXPORTS AnimationStats {
    int frames = 0;              //!< frames written
    int backend = BACKEND_AUTO;  //!< the Deformer's backend
    double bindMs = 0;           //!< Deformer::create (0 for the overload that takes one)
    double sampleMs = 0;         //!< samplePose, all frames
    double deformMs = 0;         //!< Deformer::deform, all frames (GPU: includes readback)
    double writeMs = 0;          //!< encoding and writing, all frames, and finish()
    double totalMs = 0;          //!< the whole render, binding included
    String note;                 //!< AnimationWriter::note(): a depth or size change, or ""
    /** @brief Frames per second of the whole render.
    @return frames / totalMs, per second; 0 when totalMs is 0. */
    double fps() const { return totalMs > 0 ? 1000.0 * frames / totalMs : 0.0; }
};

/** @brief Called after each frame with (frames done, frames in all); for progress bars. */
typedef std::function<void(int, int)> AnimationProgress;

/** @brief Renders the animation: binds `image` to `cage` once, then for every time of
animationFrameTimes() deforms to samplePose() and writes the frame through an
AnimationWriter. `path` is written completely or not at all.
@param image the image the cage was drawn on.
@param cage the rest polygons and the keyframes (validateKeyframes()).
@param path as checkAnimationOutput().
@param params frame rate, length, looping and interpolation.
@param deformParams picks the backend and grid step (Deformer::create).
@param progress called after each frame; empty: no reports.
@return what was done and the time it took.
@throws cv::Exception as animationFrameTimes(), Deformer::create and AnimationWriter.
*/
CV_EXPORTS AnimationStats renderAnimation(InputArray image, const Multicage& cage,
                                          const String& path, const AnimationParams& params,
                                          const DeformParams& deformParams = DeformParams(),
                                          const AnimationProgress& progress = AnimationProgress());
/** @brief The same with an existing Deformer (bound to `cage`'s rest polygons), e.g. an
editor's.
@param deformer the Deformer; its image is the one animated.
@param cage the rest polygons the deformer was bound to, and the keyframes.
@param path as checkAnimationOutput().
@param params frame rate, length, looping and interpolation.
@param progress called after each frame; empty: no reports.
@return what was done and the time it took (bindMs 0).
*/
CV_EXPORTS AnimationStats renderAnimation(Deformer& deformer, const Multicage& cage,
                                          const String& path, const AnimationParams& params,
                                          const AnimationProgress& progress = AnimationProgress());

//! @} multicage_animate

}  // namespace multicage
}  // namespace cv

#endif

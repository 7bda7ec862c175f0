// Keyframed poses over time (the paper's animation by moving multicage vertices).
//
// A multicage's poses are the keyframes: Pose::time says when each is reached (seconds).
// samplePose() interpolates between them; renderAnimation() binds once and writes one
// deformed frame per time step to a video, a GIF or a folder of PNG frames.
#ifndef OPENCV2_MULTICAGE_ANIMATE_HPP
#define OPENCV2_MULTICAGE_ANIMATE_HPP

#include <opencv2/multicage/deformer.hpp>
#include <opencv2/multicage/multicage.hpp>

#include <functional>
#include <string>
#include <vector>

namespace cv {
namespace multicage {

enum PoseInterpolation {
    /** Straight lines between consecutive keyframes: exact at keyframes, velocity jumps there. */
    INTERPOLATE_LINEAR = 0,
    /** Cubic Hermite segments whose tangent at keyframe i is the finite difference
    (p[i+1] - p[i-1]) / (t[i+1] - t[i-1]): Catmull & Rom 1974 for non-uniform times. It passes
    through every keyframe with continuous velocity. Ends of a clamped animation use the
    one-sided difference; a looped one wraps its neighbours. */
    INTERPOLATE_CATMULL_ROM = 1
};

/** Checks that the poses can drive an animation: at least two poses, every time finite, no
two poses at the same time. On failure returns false and, if why is given, one sentence that
says what is needed ("an animation needs at least two timed poses; the cage has one ('flap')").
Poses need not be stored in time order. */
CV_EXPORTS bool validateKeyframes(const Multicage& cage, std::string* why = nullptr);

/** Pose indices ordered by time (ties keep their stored order). */
CV_EXPORTS std::vector<int> keyframeOrder(const Multicage& cage);

/** Time of the earliest and of the latest pose (0 without poses). */
CV_EXPORTS double animationStart(const Multicage& cage);
CV_EXPORTS double animationEnd(const Multicage& cage);

/** Length of one play-through in seconds. Clamped: animationEnd - animationStart. Looped:
that plus a closing segment from the last keyframe back to the first, as long as the mean
keyframe spacing, i.e. span * n / (n - 1) for n keyframes. */
CV_EXPORTS double animationDuration(const Multicage& cage, bool loop = false);

/** The pose at time t (seconds, on the keyframes' clock).

Inputs: cage with at least two poses at distinct finite times (validateKeyframes());
interpolation a PoseInterpolation; loop false: t before the first keyframe gives the first
pose, after the last the last pose; loop true: t wraps with period animationDuration(cage,
true), and the closing segment leads smoothly from the last keyframe to the first.
Output: vertexCount() points (no frame corners), the keyframe's vertices exactly when t is a
keyframe time. Throws cv::Exception (StsBadArg) with validateKeyframes()'s sentence otherwise. */
CV_EXPORTS std::vector<Point2f> samplePose(const Multicage& cage, double t,
                                           int interpolation = INTERPOLATE_CATMULL_ROM,
                                           bool loop = false);

/** Adds a keyframe: pose `vertices` (vertexCount() points, or +4 with the frame corners
last) reached at `time`. A pose already at that time (within 1 microsecond) is replaced,
keeping its name unless `name` is given; otherwise the pose is appended, named `name` or
"key_<time in ms>". Returns the pose's index. Meant for an editor's "add keyframe" button. */
CV_EXPORTS int addKeyframe(Multicage& cage, InputArray vertices, double time,
                           const std::string& name = std::string());

struct CV_EXPORTS AnimationParams {
    double fps = 25.0;                            //!< frames per second of the output
    /** Seconds of output; <= 0 means one play-through (animationDuration(cage, loop)).
    Longer than that holds the last pose (clamped) or repeats the cycle (loop). */
    double duration = 0.0;
    bool loop = false;                            //!< see samplePose()
    int interpolation = INTERPOLATE_CATMULL_ROM;  //!< PoseInterpolation
};

/** Keyframe-clock time of every output frame. Clamped: n = round(duration * fps) + 1 frames
evenly spaced from animationStart to animationStart + duration, so the first and last frames
are exactly the first and last keyframes. Looped: n = round(duration * fps) frames evenly
spaced over [start, start + duration), so that playing the output on repeat is seamless.
At least 2 frames. Throws like samplePose() on bad keyframes, and on fps or duration that is
not finite and positive (duration may be <= 0: the default). */
CV_EXPORTS std::vector<double> animationFrameTimes(const Multicage& cage,
                                                   const AnimationParams& params);

/** Where the frames go, picked from the path: a folder of PNG frames (a path ending in '/',
or an existing folder), ".mp4" (H.264, else MPEG-4 part 2), ".avi" (Motion JPEG), ".gif". */
enum AnimationFormat {
    ANIMATION_FRAMES = 0,
    ANIMATION_MP4 = 1,
    ANIMATION_AVI = 2,
    ANIMATION_GIF = 3
};

/** The format for `path`, or throws cv::Exception (StsBadArg) with one sentence: an unknown
extension ("use .mp4, .avi, .gif or a folder ending in /"), or an output that cannot be written
(no such parent folder, not writable, a folder that holds files other than frames). */
CV_EXPORTS int checkAnimationOutput(const String& path);

/** Writes frames to a video, a GIF or a folder of PNG frames, all or nothing: frames go to a
temporary file (or folder) beside `path`, finish() renames it into place, and a writer
destroyed before finish() removes it, so `path` never holds a partial animation. An existing
frames folder is replaced only if it holds nothing but frame_NNNN.png files.

Frames: all the same size, CV_8UC1, CV_8UC3 (BGR) or CV_8UC4 (BGRA; alpha dropped for
video and GIF); 16-bit and float frames are scaled to 8 bits for video and GIF (x1/257; floats x255 when the
first frame's values are in [0, 1], a maximum up to 2 included, else x1); PNG frames keep 8 and
16 bits and store floats as 16 bits (x65535, or x257 for 0-255 floats). note() says which. Video frames of odd width or height are padded by one pixel (the edge
repeated), since 4:2:0 chroma needs even sizes. GIF: one palette of 255 colours found by k-means on the first frame
(deformed frames reuse the image's colours), unchanged pixels written as transparent and
each frame cropped to what changed, repeats forever. Delays are in 1/100 s, at least 2. */
class CV_EXPORTS AnimationWriter {
public:
    static Ptr<AnimationWriter> create(const String& path, double fps);
    virtual ~AnimationWriter();
    virtual void write(InputArray frame) = 0;
    /** Closes the file and moves it to the path. No frames written throws. */
    virtual void finish() = 0;
    virtual int frameCount() const = 0;
    virtual int format() const = 0;  //!< AnimationFormat
    /** What the writer changed to store the frames, in one sentence, or "": a depth scaled
    ("the float frames (values 0-1) were scaled by 255 to 8 bits"), a size padded ("padded from
    493x356 to 494x356: the codec needs even sizes"). Known after the first frame. */
    virtual String note() const = 0;
};

struct CV_EXPORTS AnimationStats {
    int frames = 0;
    int backend = BACKEND_AUTO;  //!< the Deformer's backend
    double bindMs = 0;           //!< Deformer::create (0 for the overload that takes one)
    double sampleMs = 0;         //!< samplePose, all frames
    double deformMs = 0;         //!< Deformer::deform, all frames (GPU: includes readback)
    double writeMs = 0;          //!< encoding and writing, all frames, and finish()
    double totalMs = 0;          //!< the whole render, binding included
    String note;                 //!< AnimationWriter::note(): a depth or size change, or ""
    /** Frames per second of the whole render (frames / totalMs). */
    double fps() const { return totalMs > 0 ? 1000.0 * frames / totalMs : 0.0; }
};

/** Called after each frame with (frames done, frames in all); for progress bars. */
typedef std::function<void(int, int)> AnimationProgress;

/** Renders the animation: binds `image` to `cage` once (DeformParams picks the backend and
grid step), then for every time of animationFrameTimes() deforms to samplePose() and writes
the frame through an AnimationWriter. `path` is written completely or not at all. */
CV_EXPORTS AnimationStats renderAnimation(InputArray image, const Multicage& cage,
                                          const String& path, const AnimationParams& params,
                                          const DeformParams& deformParams = DeformParams(),
                                          const AnimationProgress& progress = AnimationProgress());
/** The same with an existing Deformer (bound to `cage`'s rest polygons), e.g. an editor's. */
CV_EXPORTS AnimationStats renderAnimation(Deformer& deformer, const Multicage& cage,
                                          const String& path, const AnimationParams& params,
                                          const AnimationProgress& progress = AnimationProgress());

}  // namespace multicage
}  // namespace cv

#endif

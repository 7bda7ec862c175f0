#ifndef OPENCV_MULTICAGE_TRACK_HPP
#define OPENCV_MULTICAGE_TRACK_HPP

#include <opencv2/core.hpp>
#include <opencv2/multicage/multicage.hpp>
#include <string>
#include <vector>

namespace cv {
namespace multicage {

//! @addtogroup multicage_track
//! @{

/** @brief Options of CageTracker. */
struct CV_EXPORTS TrackParams {
    /** Corners sought in each polygon's own region (inside it, outside its inner polygons) on
    the frame tracked from; where too few are found, a grid of the region fills in. */
    int pointsPerPolygon = 80;
    /** A polygon whose motion fewer points agree on than this part of those sought on the key
    frame (followed or not), or fewer than minPoints, is lost (an inner polygon then moves with
    its parent). */
    double minAgreement = 0.5;
    /** The fewest points that must agree on a polygon's motion. */
    int minPoints = 8;
    /** Distance in pixels from the similarity within which a point agrees with it (RANSAC). */
    double agreementPx = 1.0;
    /** A point's forward-backward optical flow error in pixels above which it is not used. */
    double maxRoundTripPx = 1.0;
    /** Correlation of the two frames' grey-level histograms below which the frame is a cut. */
    double minHistogramCorrelation = 0.5;
    /** Mean absolute grey difference of the two frames' 16 x 12 thumbnails above which the frame
    is a cut: the layout changed at once (on Megamind.avi, cuts between two faces in one palette
    measure 38-40 grey levels, the frames between them at most 3). */
    double maxThumbnailDifference = 20.0;
    /** Frames whose longer side is above this many pixels are tracked on a copy scaled down to
    it (0: always the frames themselves): the flow's window and the pixel tolerances above then
    mean the same on a 1080p clip as on a small one, and the flow costs the same. */
    int workingSize = 640;
};

/** @brief What CageTracker::track found. */
enum TrackState {
    TRACK_OK = 0,   //!< every polygon moved with what it encloses; the multicage is valid
    TRACK_CUT = 1,  //!< the frame does not follow the last one (a cut): nothing moved
    TRACK_LOST = 2  //!< some polygon could not be followed, or the moved multicage is invalid
};

/** @brief The result of one CageTracker::track call. */
struct CV_EXPORTS TrackReport {
    /** What was found: TRACK_OK, TRACK_CUT or TRACK_LOST. */
    TrackState state = TRACK_OK;
    /** The polygons that could not be followed (TRACK_LOST), by index. */
    std::vector<int> lost;
    /** Correlation of the grey-level histograms of the frame and the one before (1: alike). */
    double histogramCorrelation = 1.0;
    /** Mean absolute grey difference of the two frames' 16 x 12 thumbnails (0: alike). */
    double thumbnailDifference = 0.0;
    /** Why the state is not TRACK_OK, in words; empty when it is. */
    std::string why;
};

/** @brief A multicage that follows its subject from frame to frame of a clip.

Each polygon moves with what it encloses: points of its own region (inside it, outside its
inner polygons) on a key frame are followed into the frame by pyramidal Lucas-Kanade optical
flow (starting from where the polygon's last motion puts them), kept where the flow back returns
them within TrackParams::maxRoundTripPx, and the similarity (rotation, uniform scale,
translation) most of them agree on (RANSAC) moves the polygon's key frame vertices. Measuring
every frame from the key frame, not from the frame before, keeps small errors from adding up; the
key frame moves on when the subject has turned or scaled too far from it for the flow. A polygon
with too few agreeing points is lost; a frame whose grey-level histogram differs from the last one's
is a cut. In either case, or when the moved multicage would be invalid (crossing polygons, a vertex
outside the frame), nothing moves and track() says why: the caller proposes a multicage again
and calls reset(). Only the polygons' rest positions are tracked; poses are not carried.

@code
CageTracker tracker(cage, firstFrame);
while (video.read(frame)) {
    const TrackReport r = tracker.track(frame);
    if (r.state != TRACK_OK) tracker.reset(proposeMulticage(frame), frame);
    use(frame, tracker.multicage());
}
@endcode
@sa docs/video/README.md
*/
class CV_EXPORTS CageTracker {
  public:
    /** @brief Starts tracking cage, which lies on frame.
    @param cage a valid multicage of frame's size (a cage of another size is scaled to it).
    @param frame the frame the cage lies on: 8-bit, 1, 3 or 4 channels.
    @param params the options.
    @throws cv::Exception for an empty or unsupported frame, or an invalid cage. */
    CageTracker(const Multicage& cage, InputArray frame, const TrackParams& params = TrackParams());

    /** @brief Moves the multicage from the last frame to frame.
    @param frame the next frame of the clip, of the first frame's size and type.
    @return TRACK_OK with the multicage moved, or TRACK_CUT or TRACK_LOST with it where it was.
    @throws cv::Exception for an empty frame or one of another size or type. */
    TrackReport track(InputArray frame);

    /** @brief Starts again from cage on frame (after a cut, or a lost polygon).
    @param cage a valid multicage of frame's size (a cage of another size is scaled to it).
    @param frame the frame the cage lies on, which becomes the key frame.
    @throws cv::Exception as the constructor. */
    void reset(const Multicage& cage, InputArray frame);

    /** @brief The multicage as it lies on the last frame given.
    @return the multicage, valid, of the frames' size. */
    const Multicage& multicage() const;

    struct Impl;  //!< the key frame and the polygons' motions (cage_tracker.cpp)

  private:
    Ptr<Impl> impl_;
};

/** @brief A pose drawn on one frame, carried to where the multicage lies on another: each
polygon's posed vertices move by the similarity that takes the polygon from `from` to `to` (the
least-squares fit of its vertices: CageTracker moves a polygon by a similarity), plus what that
similarity leaves of the vertex's own move (where the tracker kept a vertex within the frame), so
an edit moves, turns and scales with its subject and the rest pose lands on `to` exactly. Frame
corners, when given, stay.
@param from the multicage on the frame the pose was drawn on.
@param pose a pose of from: vertexCount() points, or +4 with the frame corners.
@param to the same multicage on another frame (CageTracker::multicage()): the same polygons and
vertex counts (else cv::Exception, StsBadArg).
@return the pose of to, as many points as pose. */
CV_EXPORTS std::vector<Point2f> carryPose(const Multicage& from, InputArray pose,
                                          const Multicage& to);

//! @}

}  // namespace multicage
}  // namespace cv

#endif

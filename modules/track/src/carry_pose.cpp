// carryPose: an edit drawn on one frame moves with each polygon's similarity to another frame.
#include <opencv2/multicage/internal/point_input.hpp>
#include <opencv2/multicage/track.hpp>

#include "similarity.hpp"

namespace cv {
namespace multicage {

std::vector<Point2f> carryPose(const Multicage& from, InputArray poseIn, const Multicage& to) {
    const int n = from.vertexCount();
    bool same = to.polygonCount() == from.polygonCount();
    for (int i = 0; same && i < from.polygonCount(); ++i)
        same = from.polygon(i).size() == to.polygon(i).size();
    if (!same)
        CV_Error(Error::StsBadArg,
                 "multicage: carryPose: the two multicages differ in polygons or vertex counts");
    std::vector<Point2f> pose = toPoints(poseIn, "carryPose: pose");
    if (int(pose.size()) != n && int(pose.size()) != n + 4)
        CV_Error(Error::StsBadSize,
                 format("multicage: carryPose: the pose has %d points; the multicage has %d "
                        "vertices (+4 frame corners)",
                        int(pose.size()), n));
    for (int i = 0; i < from.polygonCount(); ++i) {
        const std::vector<Point2f> a = from.polygon(i), b = to.polygon(i);
        const size_t offset = size_t(from.polygonOffset(i));
        const std::vector<Point2f> drawn(pose.begin() + long(offset),
                                         pose.begin() + long(offset + a.size()));
        std::vector<Point2f> posed, rest;
        const Mat s = leastSquaresSimilarity(a, b);
        transform(drawn, posed, s);
        transform(a, rest, s);
        // Plus what the similarity leaves of each vertex's own move (a vertex the tracker kept
        // within the frame), so the rest pose is carried onto `to` exactly.
        for (size_t k = 0; k < a.size(); ++k) pose[offset + k] = posed[k] + (b[k] - rest[k]);
    }
    return pose;
}

}  // namespace multicage
}  // namespace cv

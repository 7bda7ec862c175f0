// carryPose: an edit drawn on one frame moves with each polygon's similarity to another frame.
#include <opencv2/multicage/internal/point_input.hpp>
#include <opencv2/multicage/track.hpp>

namespace cv {
namespace multicage {

namespace {

// The similarity p -> c + (a -b; b a)(p - c0) that best takes `from` onto `to` (least squares).
struct Similarity {
    Point2d c0, c;
    double a = 1, b = 0;
    Point2f operator()(Point2f p) const {
        const Point2d d = Point2d(p) - c0;
        return Point2f(c + Point2d(a * d.x - b * d.y, b * d.x + a * d.y));
    }
};

Similarity fit(const std::vector<Point2f>& from, const std::vector<Point2f>& to) {
    Similarity s;
    for (size_t k = 0; k < from.size(); ++k) s.c0 += Point2d(from[k]), s.c += Point2d(to[k]);
    s.c0 /= double(from.size()), s.c /= double(from.size());
    double dot = 0, cross = 0, norm = 0;
    for (size_t k = 0; k < from.size(); ++k) {
        const Point2d p = Point2d(from[k]) - s.c0, q = Point2d(to[k]) - s.c;
        dot += p.x * q.x + p.y * q.y, cross += p.x * q.y - p.y * q.x, norm += p.dot(p);
    }
    if (norm > 0) s.a = dot / norm, s.b = cross / norm;
    return s;
}

}  // namespace

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
        const Similarity s = fit(a, b);
        // Plus what the similarity leaves of each vertex's own move (a vertex the tracker kept
        // within the frame), so the rest pose is carried onto `to` exactly.
        const size_t offset = size_t(from.polygonOffset(i));
        for (size_t k = 0; k < a.size(); ++k)
            pose[offset + k] = s(pose[offset + k]) + (b[k] - s(a[k]));
    }
    return pose;
}

}  // namespace multicage
}  // namespace cv

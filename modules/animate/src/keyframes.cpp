// Keyframes: poses at times, and the poses between them.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <opencv2/multicage/animate.hpp>
#include <sstream>

namespace cv {
namespace multicage {

namespace {
std::string quoted(const std::string& name) {
    return "'" + name + "'";
}

std::string formatTime(double t) {
    std::ostringstream s;
    s << t;
    return s.str();
}

// Keyframes in time order, with the loop's closing time.
struct Keys {
    std::vector<double> t;
    std::vector<const std::vector<Point2f>*> p;
    double period = 0;  // looped: span * n / (n - 1)

    int size() const { return static_cast<int>(t.size()); }
    // Time of key j for any j: looped keys repeat every period.
    double time(int j) const {
        const int n = size();
        const int wraps = j >= 0 ? j / n : -((n - 1 - j) / n);
        return t[j - wraps * n] + wraps * period;
    }
    const std::vector<Point2f>& pose(int j) const {
        const int n = size();
        return *p[((j % n) + n) % n];
    }
};

Keys keys(const Multicage& cage) {
    std::string why;
    if (!validateKeyframes(cage, &why)) CV_Error(Error::StsBadArg, why);
    Keys k;
    for (int i : keyframeOrder(cage)) {
        k.t.push_back(cage.pose(i).time);
        k.p.push_back(&cage.pose(i).vertices);
    }
    const int n = k.size();
    k.period = (k.t.back() - k.t.front()) * n / (n - 1);
    return k;
}

std::vector<Point2f> toPoints(InputArray a, int vertexCount) {
    Mat m = a.getMat();
    if (m.empty()) CV_Error(Error::StsBadArg, "addKeyframe: the pose is empty");
    if (m.channels() == 1 && m.cols == 2) m = m.reshape(2, m.rows);
    if (m.channels() != 2)
        CV_Error(Error::StsBadArg, "addKeyframe: a pose is a list of 2D points (Nx2)");
    m = m.reshape(2, static_cast<int>(m.total()));
    Mat f;
    m.convertTo(f, CV_32FC2);
    std::vector<Point2f> pts(f.begin<Point2f>(), f.end<Point2f>());
    if (static_cast<int>(pts.size()) == vertexCount + 4) pts.resize(vertexCount);
    if (static_cast<int>(pts.size()) != vertexCount)
        CV_Error(Error::StsBadArg, "addKeyframe: the pose has " + std::to_string(pts.size()) +
                                       " points; the multicage has " + std::to_string(vertexCount) +
                                       " vertices");
    return pts;
}
}  // namespace

bool validateKeyframes(const Multicage& cage, std::string* why) {
    auto fail = [why](const std::string& message) {
        if (why) *why = message;
        return false;
    };
    const int n = cage.poseCount();
    if (n == 0)
        return fail(
            "an animation needs at least two timed poses (keyframes); the cage has no poses: "
            "add them under `poses:` with a `time:` each");
    if (n == 1)
        return fail("an animation needs at least two timed poses (keyframes); the cage has one (" +
                    quoted(cage.pose(0).name) + " at time " + formatTime(cage.pose(0).time) +
                    "): add another under `poses:` with a different `time:`");
    for (int i = 0; i < n; ++i)
        if (!std::isfinite(cage.pose(i).time))
            return fail("pose " + std::to_string(i) + " (" + quoted(cage.pose(i).name) +
                        ") has no finite time; give every pose a `time:` in seconds");
    const std::vector<int> order = keyframeOrder(cage);
    for (int k = 1; k < n; ++k) {
        const Pose &a = cage.pose(order[k - 1]), &b = cage.pose(order[k]);
        if (b.time - a.time < 1e-6)
            return fail("poses " + quoted(a.name) + " and " + quoted(b.name) +
                        " are both at time " + formatTime(a.time) +
                        "; each pose needs its own `time:` (seconds)");
    }
    for (int i = 0; i < n; ++i)
        if (static_cast<int>(cage.pose(i).vertices.size()) != cage.vertexCount())
            return fail("pose " + quoted(cage.pose(i).name) + " has " +
                        std::to_string(cage.pose(i).vertices.size()) +
                        " vertices; the multicage has " + std::to_string(cage.vertexCount()));
    return true;
}

std::vector<int> keyframeOrder(const Multicage& cage) {
    std::vector<int> order(cage.poseCount());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(),
                     [&](int a, int b) { return cage.pose(a).time < cage.pose(b).time; });
    return order;
}

double animationStart(const Multicage& cage) {
    if (cage.poseCount() == 0) return 0;
    return cage.pose(keyframeOrder(cage).front()).time;
}

double animationEnd(const Multicage& cage) {
    if (cage.poseCount() == 0) return 0;
    return cage.pose(keyframeOrder(cage).back()).time;
}

double animationDuration(const Multicage& cage, bool loop) {
    const int n = cage.poseCount();
    const double span = animationEnd(cage) - animationStart(cage);
    return loop && n > 1 ? span * n / (n - 1) : span;
}

std::vector<Point2f> samplePose(const Multicage& cage, double t, int interpolation, bool loop) {
    if (interpolation != INTERPOLATE_LINEAR && interpolation != INTERPOLATE_CATMULL_ROM)
        CV_Error(Error::StsBadArg,
                 "samplePose: unknown interpolation " + std::to_string(interpolation));
    if (!std::isfinite(t)) CV_Error(Error::StsBadArg, "samplePose: the time is not finite");
    const Keys k = keys(cage);
    const int n = k.size();
    double u = t;
    int i;  // segment: from key i to key i + 1
    if (loop) {
        u = std::fmod(t - k.t.front(), k.period);
        if (u < 0) u += k.period;
        u += k.t.front();
        i = static_cast<int>(std::upper_bound(k.t.begin(), k.t.end(), u) - k.t.begin()) - 1;
        i = std::max(i, 0);  // u rounded below the first key
    } else {
        if (u <= k.t.front()) return *k.p.front();
        if (u >= k.t.back()) return *k.p.back();
        i = static_cast<int>(std::upper_bound(k.t.begin(), k.t.end(), u) - k.t.begin()) - 1;
    }
    const double t0 = k.time(i), t1 = k.time(i + 1), h = t1 - t0;
    const double s = std::min(std::max((u - t0) / h, 0.0), 1.0);
    const std::vector<Point2f>&p0 = k.pose(i), &p1 = k.pose(i + 1);
    if (s == 0) return p0;
    std::vector<Point2f> out(p0.size());
    if (interpolation == INTERPOLATE_LINEAR) {
        for (size_t v = 0; v < out.size(); ++v)
            out[v] = Point2f(static_cast<float>((1 - s) * p0[v].x + s * p1[v].x),
                             static_cast<float>((1 - s) * p0[v].y + s * p1[v].y));
        return out;
    }
    // Tangents (velocity, pixels per second) by central differences in time; a clamped
    // animation's end keys use the one-sided difference.
    auto tangent = [&](int j, size_t v) -> Point2d {
        int a = j - 1, b = j + 1;
        if (!loop) {
            a = std::max(a, 0);
            b = std::min(b, n - 1);
        }
        const Point2f d = k.pose(b)[v] - k.pose(a)[v];
        return Point2d(d.x, d.y) / (k.time(b) - k.time(a));
    };
    // Cubic Hermite basis (Catmull & Rom 1974, with the tangents above).
    const double s2 = s * s, s3 = s2 * s;
    const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2,
                 h11 = s3 - s2;
    for (size_t v = 0; v < out.size(); ++v) {
        const Point2d m0 = tangent(i, v), m1 = tangent(i + 1, v);
        const double x = h00 * p0[v].x + h10 * h * m0.x + h01 * p1[v].x + h11 * h * m1.x;
        const double y = h00 * p0[v].y + h10 * h * m0.y + h01 * p1[v].y + h11 * h * m1.y;
        out[v] = Point2f(static_cast<float>(x), static_cast<float>(y));
    }
    return out;
}

int addKeyframe(Multicage& cage, InputArray vertices, double time, const std::string& name) {
    if (!std::isfinite(time)) CV_Error(Error::StsBadArg, "addKeyframe: the time is not finite");
    const std::vector<Point2f> pts = toPoints(vertices, cage.vertexCount());
    for (int i = 0; i < cage.poseCount(); ++i)
        if (std::abs(cage.pose(i).time - time) < 1e-6) {
            Pose p = cage.pose(i);
            if (!name.empty()) p.name = name;
            p.vertices = pts;
            cage.setPose(i, p);
            return i;
        }
    std::string chosen = name;
    if (chosen.empty()) {
        chosen = "key_" + std::to_string(static_cast<long long>(std::llround(time * 1000)));
        for (int suffix = 2; cage.findPose(chosen) >= 0; ++suffix)
            chosen = "key_" + std::to_string(static_cast<long long>(std::llround(time * 1000))) +
                     "_" + std::to_string(suffix);
    }
    return cage.addPose(chosen, pts, time);
}

std::vector<double> animationFrameTimes(const Multicage& cage, const AnimationParams& params) {
    if (!(std::isfinite(params.fps) && params.fps > 0))
        CV_Error(Error::StsBadArg,
                 "the frame rate must be a positive number (got " + formatTime(params.fps) + ")");
    if (!std::isfinite(params.duration))
        CV_Error(Error::StsBadArg, "the duration must be a finite number of seconds");
    std::string why;
    if (!validateKeyframes(cage, &why)) CV_Error(Error::StsBadArg, why);
    const double start = animationStart(cage);
    const double duration =
        params.duration > 0 ? params.duration : animationDuration(cage, params.loop);
    const double steps = std::round(duration * params.fps);
    if (steps > 1e6)
        CV_Error(Error::StsBadArg, "the animation would have more than a million frames (" +
                                       formatTime(duration) + " s at " + formatTime(params.fps) +
                                       " fps)");
    std::vector<double> times;
    if (params.loop) {
        const int n = std::max(2, static_cast<int>(steps));
        for (int f = 0; f < n; ++f) times.push_back(start + duration * f / n);
    } else {
        const int n = std::max(2, static_cast<int>(steps) + 1);
        for (int f = 0; f < n; ++f)
            times.push_back(f == n - 1 ? start + duration : start + duration * f / (n - 1));
    }
    return times;
}

}  // namespace multicage
}  // namespace cv

// Keyframes: interpolation exact at keyframes, smooth between them, clamped or looped ends.
#include <cmath>
#include <opencv2/multicage/animate.hpp>

#include "testing.hpp"

using namespace cv::multicage;

namespace {
// A triangle with three keyframes stored out of time order: times 0, 0.5 and 2.
Multicage threeKeys() {
    Multicage cage(cv::Size(200, 200));
    cage.addPolygon(std::vector<cv::Point2f>{{50, 50}, {150, 50}, {100, 150}});
    cage.addPose("late", std::vector<cv::Point2f>{{60, 40}, {160, 60}, {90, 170}}, 2.0);
    cage.addPose("first", std::vector<cv::Point2f>{{50, 50}, {150, 50}, {100, 150}}, 0.0);
    cage.addPose("middle", std::vector<cv::Point2f>{{40, 55}, {140, 40}, {110, 140}}, 0.5);
    return cage;
}

double distance(const std::vector<cv::Point2f>& a, const std::vector<cv::Point2f>& b) {
    double d = 0;
    for (size_t i = 0; i < a.size(); ++i)
        d = std::max(d, static_cast<double>(cv::norm(a[i] - b[i])));
    return d;
}

// Velocity of vertex 0 by a one-sided difference just left (-1) or right (+1) of t.
cv::Point2d velocity(const Multicage& cage, double t, int side, int interpolation, bool loop) {
    const double h = 1e-4;
    const auto a = samplePose(cage, side < 0 ? t - h : t, interpolation, loop);
    const auto b = samplePose(cage, side < 0 ? t : t + h, interpolation, loop);
    return cv::Point2d(b[0].x - a[0].x, b[0].y - a[0].y) / h;
}
}  // namespace

TEST(Keyframes, OrderAndDurationFollowTimes) {
    const Multicage cage = threeKeys();
    EXPECT_EQ(keyframeOrder(cage), (std::vector<int>{1, 2, 0}));
    EXPECT_DOUBLE_EQ(animationStart(cage), 0.0);
    EXPECT_DOUBLE_EQ(animationEnd(cage), 2.0);
    EXPECT_DOUBLE_EQ(animationDuration(cage, false), 2.0);
    EXPECT_DOUBLE_EQ(animationDuration(cage, true), 3.0);  // closing segment = mean spacing (1 s)
}

TEST(Keyframes, BothInterpolationsAreExactAtKeyframes) {
    const Multicage cage = threeKeys();
    for (int interpolation : {INTERPOLATE_LINEAR, INTERPOLATE_CATMULL_ROM})
        for (bool loop : {false, true})
            for (int i = 0; i < cage.poseCount(); ++i)
                EXPECT_EQ(samplePose(cage, cage.pose(i).time, interpolation, loop),
                          cage.pose(i).vertices)
                    << "pose " << cage.pose(i).name << " interpolation " << interpolation
                    << " loop " << loop;
}

TEST(Keyframes, LinearIsTheStraightLineBetweenKeys) {
    const Multicage cage = threeKeys();
    const auto mid = samplePose(cage, 0.25, INTERPOLATE_LINEAR, false);
    const auto& a = cage.pose(1).vertices;
    const auto& b = cage.pose(2).vertices;
    for (size_t v = 0; v < mid.size(); ++v) {
        EXPECT_NEAR(mid[v].x, 0.5 * (a[v].x + b[v].x), 1e-4);
        EXPECT_NEAR(mid[v].y, 0.5 * (a[v].y + b[v].y), 1e-4);
    }
    // Three quarters of the way from 0.5 to 2.
    const auto q = samplePose(cage, 1.625, INTERPOLATE_LINEAR, false);
    const auto& c = cage.pose(0).vertices;
    EXPECT_NEAR(q[1].x, 0.25 * b[1].x + 0.75 * c[1].x, 1e-4);
}

TEST(Keyframes, CatmullRomHasContinuousVelocityWhereLinearHasAKink) {
    const Multicage cage = threeKeys();
    const double t = 0.5;  // the interior keyframe
    const cv::Point2d lin = velocity(cage, t, -1, INTERPOLATE_LINEAR, false) -
                            velocity(cage, t, +1, INTERPOLATE_LINEAR, false);
    const cv::Point2d cr = velocity(cage, t, -1, INTERPOLATE_CATMULL_ROM, false) -
                           velocity(cage, t, +1, INTERPOLATE_CATMULL_ROM, false);
    EXPECT_GT(cv::norm(lin), 10.0);  // linear: the velocity jumps at a keyframe
    EXPECT_LT(cv::norm(cr), 0.1);    // Catmull-Rom: it does not
    // The tangent at the interior key is the central difference (p2 - p0) / (t2 - t0).
    const cv::Point2d v = velocity(cage, t, +1, INTERPOLATE_CATMULL_ROM, false);
    const cv::Point2f d = cage.pose(0).vertices[0] - cage.pose(1).vertices[0];
    EXPECT_NEAR(v.x, d.x / 2.0, 0.05);
    EXPECT_NEAR(v.y, d.y / 2.0, 0.05);
}

TEST(Keyframes, ClampedHoldsTheEndPoses) {
    const Multicage cage = threeKeys();
    for (int interpolation : {INTERPOLATE_LINEAR, INTERPOLATE_CATMULL_ROM}) {
        EXPECT_EQ(samplePose(cage, -3.0, interpolation, false), cage.pose(1).vertices);
        EXPECT_EQ(samplePose(cage, 2.5, interpolation, false), cage.pose(0).vertices);
        EXPECT_EQ(samplePose(cage, 1e9, interpolation, false), cage.pose(0).vertices);
    }
}

TEST(Keyframes, LoopWrapsBackToTheFirstKeySmoothly) {
    const Multicage cage = threeKeys();
    const double period = animationDuration(cage, true);  // 3 s
    for (int interpolation : {INTERPOLATE_LINEAR, INTERPOLATE_CATMULL_ROM}) {
        // Periodic, forwards and backwards.
        for (double t : {0.1, 0.7, 1.9, 2.4, 2.99}) {
            EXPECT_LT(distance(samplePose(cage, t, interpolation, true),
                               samplePose(cage, t + 2 * period, interpolation, true)),
                      1e-3)
                << t;
            EXPECT_LT(distance(samplePose(cage, t, interpolation, true),
                               samplePose(cage, t - period, interpolation, true)),
                      1e-3)
                << t;
        }
        // After the last key (t = 2) the loop moves back to the first, reached at t = 3.
        EXPECT_EQ(samplePose(cage, period, interpolation, true), cage.pose(1).vertices);
        EXPECT_LT(
            distance(samplePose(cage, period - 1e-6, interpolation, true), cage.pose(1).vertices),
            1e-3);
        EXPECT_GT(distance(samplePose(cage, 2.5, interpolation, true), cage.pose(0).vertices), 1.0);
        // A clamped animation would still hold the last pose there.
        EXPECT_EQ(samplePose(cage, 2.5, interpolation, false), cage.pose(0).vertices);
    }
    // Catmull-Rom's velocity is continuous across the wrap too.
    const cv::Point2d jump = velocity(cage, period, -1, INTERPOLATE_CATMULL_ROM, true) -
                             velocity(cage, period, +1, INTERPOLATE_CATMULL_ROM, true);
    EXPECT_LT(cv::norm(jump), 0.1);
}

TEST(Keyframes, BadKeyframesSayWhatIsNeeded) {
    Multicage cage(cv::Size(200, 200));
    cage.addPolygon(std::vector<cv::Point2f>{{50, 50}, {150, 50}, {100, 150}});
    std::string why;
    EXPECT_FALSE(validateKeyframes(cage, &why));
    EXPECT_NE(why.find("at least two timed poses"), std::string::npos) << why;
    EXPECT_NE(why.find("no poses"), std::string::npos) << why;
    cage.addPose("only", cage.polygon(0), 1.0);
    EXPECT_FALSE(validateKeyframes(cage, &why));
    EXPECT_NE(why.find("has one ('only' at time 1)"), std::string::npos) << why;
    EXPECT_THROW(samplePose(cage, 0.5), cv::Exception);
    cage.addPose("again", cage.polygon(0), 1.0);
    EXPECT_FALSE(validateKeyframes(cage, &why));
    EXPECT_NE(why.find("'only' and 'again' are both at time 1"), std::string::npos) << why;
    Pose p = cage.pose(1);
    p.time = std::nan("");
    cage.setPose(1, p);
    EXPECT_FALSE(validateKeyframes(cage, &why));
    EXPECT_NE(why.find("no finite time"), std::string::npos) << why;
    p.time = 2.0;
    cage.setPose(1, p);
    EXPECT_TRUE(validateKeyframes(cage, &why)) << why;
}

TEST(Keyframes, AddKeyframeAppendsOrReplacesAtTheSameTime) {
    Multicage cage = threeKeys();
    std::vector<cv::Point2f> pose = {{55, 45}, {150, 52}, {101, 149}};
    const int added = addKeyframe(cage, pose, 1.0);
    EXPECT_EQ(cage.poseCount(), 4);
    EXPECT_EQ(cage.pose(added).name, "key_1000");
    EXPECT_EQ(samplePose(cage, 1.0), pose);
    // The frame corners may come along (an editor's full vertex list): they are dropped.
    std::vector<cv::Point2f> withFrame = pose;
    withFrame[0].x = 70;
    for (const cv::Point2f& c : cage.frame()) withFrame.push_back(c);
    const int replaced = addKeyframe(cage, withFrame, 0.5 + 1e-9);
    EXPECT_EQ(replaced, cage.findPose("middle"));
    EXPECT_EQ(cage.poseCount(), 4);
    EXPECT_EQ(cage.pose(replaced).vertices[0].x, 70.f);
    EXPECT_THROW(addKeyframe(cage, std::vector<cv::Point2f>{{1, 2}}, 3.0), cv::Exception);
}

TEST(Keyframes, FrameTimesHitBothEndsOrLoopSeamlessly) {
    const Multicage cage = threeKeys();
    AnimationParams params;
    params.fps = 5.5;  // 2 s * 5.5 = 11 steps
    std::vector<double> t = animationFrameTimes(cage, params);
    ASSERT_EQ(t.size(), 12u);
    EXPECT_EQ(t.front(), 0.0);
    EXPECT_EQ(t.back(), 2.0);
    params.loop = true;  // 3 s * 5.5 = 16.5 -> 17 frames over [0, 3)
    t = animationFrameTimes(cage, params);
    ASSERT_EQ(t.size(), 17u);
    EXPECT_EQ(t.front(), 0.0);
    EXPECT_NEAR(t.back() + 3.0 / 17, 3.0, 1e-12);
    params.loop = false;
    params.duration = 4;  // longer than the keys: the last 2 s hold the last pose
    t = animationFrameTimes(cage, params);
    EXPECT_EQ(t.size(), 23u);
    EXPECT_EQ(t.back(), 4.0);
    params.fps = 0;
    EXPECT_THROW(animationFrameTimes(cage, params), cv::Exception);
}

// VideoReframer and the crop-and-warp rule (issue 42): a clip reframed to another aspect ratio
// comes out whole and in order, its faces keep their shape, its subjects glide and stay tracked,
// a still clip stays still, cuts start a shot, and bad frames are refused.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <opencv2/imgproc.hpp>
#include <opencv2/multicage/reframe.hpp>

#include "testing.hpp"

using namespace cv;
using namespace cv::multicage;
using multicage_testing::readSample;

namespace {

// The least-squares similarity (turn, uniform scale, shift) of rest onto moved, and the largest
// distance from it of a moved point: 0 when moved is a similarity of rest.
double maxSimilarityResidual(const std::vector<Point2f>& rest, const std::vector<Point2f>& moved) {
    const size_t n = std::min(rest.size(), moved.size());
    if (n < 2) return INFINITY;
    Point2d cp(0, 0), cq(0, 0);
    for (size_t i = 0; i < n; ++i) cp += Point2d(rest[i]), cq += Point2d(moved[i]);
    cp *= 1.0 / n, cq *= 1.0 / n;
    double a = 0, b = 0, norm2 = 0;
    for (size_t i = 0; i < n; ++i) {
        const Point2d p = Point2d(rest[i]) - cp, q = Point2d(moved[i]) - cq;
        a += p.x * q.x + p.y * q.y, b += p.x * q.y - p.y * q.x, norm2 += p.dot(p);
    }
    if (!(norm2 > 0)) return INFINITY;
    a /= norm2, b /= norm2;
    double worst = 0;
    for (size_t i = 0; i < n; ++i) {
        const Point2d p = Point2d(rest[i]) - cp;
        worst = std::max(
            worst, norm(cq + Point2d(a * p.x - b * p.y, b * p.x + a * p.y) - Point2d(moved[i])));
    }
    return worst;
}

// Width over height of the points' bounds.
double aspectOf(const std::vector<Point2f>& points) {
    Point2f lo = points[0], hi = points[0];
    for (const Point2f& p : points)
        lo = Point2f(std::min(lo.x, p.x), std::min(lo.y, p.y)),
        hi = Point2f(std::max(hi.x, p.x), std::max(hi.y, p.y));
    return double(hi.x - lo.x) / (hi.y - lo.y);
}

Point2d centreOf(const std::vector<Point2f>& points) {
    Point2d c(0, 0);
    for (const Point2f& p : points) c += Point2d(p);
    return c * (1.0 / points.size());
}

// Polygon i of cage where pose (vertexCount()+4 points, frame corners last) puts it.
std::vector<Point2f> posedPolygon(const Multicage& cage, const std::vector<Point2f>& pose, int i) {
    const int first = cage.polygonOffset(i), count = cage.polygonOffset(i + 1) - first;
    return std::vector<Point2f>(pose.begin() + first, pose.begin() + first + count);
}

// The polygons a multicage protects inside its outlines (depth 2 or more: faces, features).
std::vector<int> innerPolygons(const Multicage& cage) {
    std::vector<int> inner;
    for (int i = 0; i < cage.polygonCount(); ++i)
        if (cage.depth(i) >= 2) inner.push_back(i);
    return inner;
}
// The inner polygons holding the centre of one of faces.
std::vector<int> facePolygons(const Multicage& cage, const std::vector<Rect>& faces) {
    std::vector<int> out;
    for (int i : innerPolygons(cage))
        for (const Rect& f : faces)
            if (pointPolygonTest(cage.polygon(i),
                                 Point2f(f.x + 0.5f * f.width, f.y + 0.5f * f.height), false) > 0) {
                out.push_back(i);
                break;
            }
    return out;
}
std::vector<int> outlines(const Multicage& cage) {
    std::vector<int> out;
    for (int i = 0; i < cage.polygonCount(); ++i)
        if (cage.depth(i) == 1) out.push_back(i);
    return out;
}

// The root mean square of a path's second difference (its acceleration, px per frame^2).
double rmsAcceleration(const std::vector<Point2d>& path) {
    double sum = 0;
    int n = 0;
    for (size_t t = 1; t + 1 < path.size(); ++t, ++n) {
        const Point2d a = path[t + 1] - 2 * path[t] + path[t - 1];
        sum += a.dot(a);
    }
    return n ? std::sqrt(sum / n) : 0.0;
}

// An ellipse-like polygon of n vertices around centre, clockwise on screen.
std::vector<Point2f> ellipsePolygon(Point2f centre, Size2f semiAxes, int n) {
    std::vector<Point2f> p;
    for (int k = 0; k < n; ++k) {
        const double a = 2 * CV_PI * k / n;
        p.emplace_back(centre.x + semiAxes.width * float(std::cos(a)),
                       centre.y + semiAxes.height * float(std::sin(a)));
    }
    return p;
}
// The polygon of a box: an octagon inscribed in `fraction` of it (an ellipse, as a face is).
std::vector<Point2f> boxPolygon(const Rect2f& box, float fraction) {
    return ellipsePolygon(Point2f(box.x + box.width / 2, box.y + box.height / 2),
                          Size2f(fraction * box.width / 2, fraction * box.height / 2), 8);
}

Mat photo(const std::string& name, Size size) {
    Mat image = readSample(name);
    resize(image, image, size, 0, 0, INTER_AREA);
    return image;
}

// The reference cages of samples/data/propose_bench (NAME.ref.json, a person's judgement): an
// outline and the face and features inside it, on the photo's own size.
Multicage messiCage() {  // messi5.jpg, 548x342: the player's box, face, lettering, badge
    Multicage cage(Size(548, 342));
    cage.addPolygon(std::vector<Point2f>{{60, 55}, {460, 55}, {460, 335}, {60, 335}});
    cage.addPolygon(boxPolygon(Rect2f(226, 90, 40, 44), 0.75f));
    cage.addPolygon(boxPolygon(Rect2f(205, 138, 70, 22), 0.8f));
    cage.addPolygon(boxPolygon(Rect2f(262, 120, 20, 25), 0.8f));
    cage.orient();
    return cage;
}
Multicage astronautCage() {  // astronaut.jpg, 512x512: the astronaut, face, patch, name tag
    Multicage cage(Size(512, 512));
    cage.addPolygon(std::vector<Point2f>{{200, 18},  {255, 12},  {295, 40},  {300, 100}, {290, 140},
                                         {300, 180}, {340, 215}, {350, 260}, {360, 330}, {420, 345},
                                         {470, 370}, {500, 420}, {511, 470}, {511, 511}, {20, 511},
                                         {25, 420},  {30, 300},  {45, 250},  {85, 225},  {120, 200},
                                         {150, 180}, {180, 150}, {180, 100}, {185, 50}});
    cage.addPolygon(boxPolygon(Rect2f(170, 50, 110, 110), 0.7f));
    cage.addPolygon(boxPolygon(Rect2f(135, 345, 75, 75), 0.8f));
    cage.addPolygon(boxPolygon(Rect2f(278, 338, 52, 40), 0.8f));
    cage.orient();
    return cage;
}

// A clip through a reframer: every frame out, and how many came out before finish().
struct Reframed {
    std::vector<ReframedFrame> frames;
    int beforeFinish = 0;
    int lag = 0;
    ReframeStats stats;
};
Reframed reframeClip(const std::vector<Mat>& clip, Size newSize, const Multicage& cage = {},
                     const ReframeParams& params = ReframeParams()) {
    VideoReframer reframer(newSize, params, cage);
    Reframed r;
    r.lag = reframer.lag();
    ReframedFrame out;
    for (const Mat& frame : clip) {
        reframer.push(frame);
        while (reframer.pop(out)) r.frames.push_back(out);
    }
    r.beforeFinish = int(r.frames.size());
    reframer.finish();
    while (reframer.pop(out)) r.frames.push_back(out);
    r.stats = reframer.stats();
    return r;
}

// Every frame out, in order, of the asked size and the input's type.
void expectWholeClip(const Reframed& r, int frames, Size newSize, int type) {
    ASSERT_EQ(int(r.frames.size()), frames);
    EXPECT_EQ(r.stats.framesIn, frames);
    EXPECT_EQ(r.stats.framesOut, frames);
    for (int k = 0; k < frames; ++k) {
        const ReframedFrame& f = r.frames[size_t(k)];
        EXPECT_EQ(f.index, k);
        EXPECT_EQ(f.image.size(), newSize) << "frame " << k;
        EXPECT_EQ(f.image.type(), type) << "frame " << k;
        EXPECT_EQ(f.pose.size(), size_t(f.cage.vertexCount() + 4)) << "frame " << k;
    }
}

// A person crossing a still scene: a textured cut-out (the baboon's face, an ellipse of 72 x 92)
// moving 6 px a frame to the right and bobbing 4 px up and down over coffee.jpg at 384x216.
struct Crossing {
    static constexpr int kFrames = 36;
    const Size size{384, 216};
    const Size patch{80, 100};          // the cut-out's square, its centre at (39.5, 49.5)
    const Size2f semiAxes{36.f, 46.f};  // the subject's ellipse
    const Point2f faceOffset{0.f, -8.f};
    Mat background, subject, alpha;

    Crossing() {
        Mat scene = readSample("propose_bench/coffee.jpg");  // 600x400: its middle at 16:9
        resize(scene(Rect(0, 31, 600, 338)), background, size, 0, 0, INTER_AREA);
        Mat face = readSample("propose_bench/baboon.jpg")(Rect(96, 40, 320, 400));
        resize(face, subject, patch, 0, 0, INTER_AREA);
        Mat mask = Mat::zeros(patch, CV_8U);
        ellipse(mask, Point(cvRound(39.5 * 16), cvRound(49.5 * 16)),
                Size(cvRound(semiAxes.width * 16), cvRound(semiAxes.height * 16)), 0, 0, 360,
                Scalar(255), FILLED, LINE_AA, 4);
        mask.convertTo(alpha, CV_32F, 1 / 255.0);
    }
    static Point2d centre(int t) {
        return {90.0 + 6.0 * t, 108.0 + 4.0 * std::sin(2 * CV_PI * t / 24.0)};
    }
    Point2d faceCentre(int t) const { return centre(t) + Point2d(faceOffset); }
    Mat frame(int t) const {
        const Point2d c = centre(t);
        const Mat m = (Mat_<double>(2, 3) << 1, 0, c.x - 39.5, 0, 1, c.y - 49.5);
        Mat moved, a;
        warpAffine(subject, moved, m, size, INTER_LINEAR, BORDER_CONSTANT);
        warpAffine(alpha, a, m, size, INTER_LINEAR, BORDER_CONSTANT);
        Mat a3, bg, fg, out;
        cvtColor(a, a3, COLOR_GRAY2BGR);
        background.convertTo(bg, CV_32FC3);
        moved.convertTo(fg, CV_32FC3);
        out = bg.mul(Scalar::all(1.0) - a3) + fg.mul(a3);
        out.convertTo(out, CV_8UC3);
        return out;
    }
    Mat trueMask(int t) const {
        const Point2d c = centre(t);
        Mat mask = Mat::zeros(size, CV_8U);
        ellipse(mask, Point(cvRound(c.x * 16), cvRound(c.y * 16)),
                Size(cvRound(semiAxes.width * 16), cvRound(semiAxes.height * 16)), 0, 0, 360,
                Scalar(255), FILLED, LINE_8, 4);
        return mask;
    }
    // An outline on the subject's border and a polygon inside it standing for the face.
    Multicage cage() const {
        Multicage c(size);
        const Point2f o(centre(0));
        c.addPolygon(ellipsePolygon(o, semiAxes, 20));
        c.addPolygon(ellipsePolygon(o + faceOffset, Size2f(16.f, 20.f), 8));
        c.orient();
        return c;
    }
};

double iou(const Mat& a, const Mat& b) {
    const double both = countNonZero(a & b), either = countNonZero(a | b);
    return either > 0 ? both / either : 0.0;
}

}  // namespace

// Item 1: the crossing reframed to 9:16 at the same height.
TEST(VideoReframer, APersonCrossingAStillSceneComesOutWholeSmoothAndInShape) {
    const Crossing clip;
    const Multicage start = clip.cage();
    ASSERT_TRUE(start.validate());
    std::vector<Mat> frames;
    for (int t = 0; t < Crossing::kFrames; ++t) frames.push_back(clip.frame(t));
    const Size newSize(122, 216);
    const Reframed r = reframeClip(frames, newSize, start);

    // a. Every frame, in order, of the asked size; the output runs lag() frames behind.
    expectWholeClip(r, Crossing::kFrames, newSize, CV_8UC3);
    if (HasFatalFailure()) return;
    EXPECT_EQ(r.beforeFinish, Crossing::kFrames - r.lag);
    EXPECT_EQ(r.stats.cuts, 0);
    EXPECT_EQ(r.stats.lost, 0);
    EXPECT_EQ(r.stats.proposals, 0);

    double worstResidual = 0, worstAspect = 0, worstIou = 1, worstCentre = 0;
    std::vector<Point2d> faceIn, faceOut;
    for (const ReframedFrame& f : r.frames) {
        const int t = f.index;
        // The outline and the face are both kept on the crop.
        const std::vector<int> faces = innerPolygons(f.cage), outline = outlines(f.cage);
        ASSERT_EQ(faces.size(), 1u) << "frame " << t;
        ASSERT_EQ(outline.size(), 1u) << "frame " << t;
        // b. The face keeps its shape: a similarity of its rest polygon, its aspect kept.
        const std::vector<Point2f> rest = f.cage.polygon(faces[0]),
                                   posed = posedPolygon(f.cage, f.pose, faces[0]);
        const double residual = maxSimilarityResidual(rest, posed),
                     aspect = std::abs(aspectOf(posed) / aspectOf(rest) - 1);
        EXPECT_LE(residual, 1.0) << "frame " << t;
        EXPECT_LE(aspect, 0.05) << "frame " << t;
        worstResidual = std::max(worstResidual, residual);
        worstAspect = std::max(worstAspect, aspect);
        faceIn.push_back(clip.faceCentre(t));
        faceOut.push_back(centreOf(posed));
        // d. The tracked outline stays on the subject.
        std::vector<Point2f> onFrame = f.cage.polygon(outline[0]);
        for (Point2f& p : onFrame) p += Point2f(f.crop.tl());
        const double overlap =
            iou(multicage_fixtures::polygonMask(onFrame, clip.size), clip.trueMask(t));
        const double centreError = norm(centreOf(onFrame) - clip.centre(t));
        EXPECT_GE(overlap, 0.8) << "frame " << t;
        EXPECT_LE(centreError, 2.0) << "frame " << t;
        worstIou = std::min(worstIou, overlap);
        worstCentre = std::max(worstCentre, centreError);
        // The face is on the output frame.
        EXPECT_TRUE(Rect2d(0, 0, newSize.width, newSize.height).contains(centreOf(posed)))
            << "frame " << t << ": " << centreOf(posed);
    }
    // c. Smoothness: the face glides no less smoothly than it moves in the input.
    const double accelIn = rmsAcceleration(faceIn), accelOut = rmsAcceleration(faceOut);
    EXPECT_LE(accelOut, accelIn + 0.5);
    std::cout << "[ crossing ] face residual max " << worstResidual << " px, aspect change max "
              << 100 * worstAspect << " %; outline IoU min " << worstIou << ", centre error max "
              << worstCentre << " px; RMS acceleration of the face centre: input " << accelIn
              << ", output " << accelOut << " px/frame^2; unsmoothed " << r.stats.unsmoothed
              << std::endl;
    std::cout << "[ crossing ] posed face centre x:";
    for (const Point2d& p : faceOut) std::cout << ' ' << cvRound(p.x * 10) / 10.0;
    std::cout << std::endl;
}

namespace {

// Item 2: a frame held with mild noise; the outputs, lightly blurred, all within a grey level
// (mean absolute difference) of the first.
void expectStill(const Mat& still, Size newSize, const Multicage& cage, const char* what) {
    const int kFrames = 30;
    RNG rng(20261130);
    std::vector<Mat> clip;
    for (int t = 0; t < kFrames; ++t) {
        Mat noise(still.size(), CV_32FC3), frame;
        rng.fill(noise, RNG::NORMAL, Scalar::all(0), Scalar::all(2));
        still.convertTo(frame, CV_32FC3);
        frame += noise;
        frame.convertTo(frame, CV_8UC3);
        clip.push_back(frame);
    }
    const Reframed r = reframeClip(clip, newSize, cage);
    expectWholeClip(r, kFrames, newSize, CV_8UC3);
    if (int(r.frames.size()) != kFrames) return;
    Mat first;
    GaussianBlur(r.frames[0].image, first, Size(5, 5), 1.5);
    double worst = 0, windowSpread = 0, poseSpread = 0;
    int otherCages = 0;
    for (const ReframedFrame& f : r.frames) {
        Mat blurred;
        GaussianBlur(f.image, blurred, Size(5, 5), 1.5);
        const double mad = norm(blurred, first, NORM_L1) / double(first.total() * 3);
        EXPECT_LE(mad, 1.0) << what << ": frame " << f.index;
        worst = std::max(worst, mad);
        windowSpread = std::max(windowSpread, std::abs(f.window.x - r.frames[0].window.x));
        // The pose stands still too, where the crop keeps the same polygons as on the last
        // frame (not on the first: VideoReframer.TheFirstFrameKeepsThePolygonsTheNextOnesKeep).
        const std::vector<Point2f>& last = r.frames.back().pose;
        if (f.pose.size() != last.size()) {
            ++otherCages;
            continue;
        }
        for (size_t v = 0; v < f.pose.size(); ++v)
            poseSpread = std::max(poseSpread, double(norm(f.pose[v] - last[v])));
    }
    EXPECT_LE(poseSpread, 0.5) << what;
    std::cout << "[ still, " << what << " ] largest mean |difference| from the first frame "
              << worst << " grey levels; window x moved at most " << windowSpread
              << " px, pose vertices at most " << poseSpread << " px; polygons on the crop "
              << r.frames[0].cage.polygonCount() << " (frame 0), "
              << r.frames.back().cage.polygonCount() << " (last), " << otherCages
              << " frames unlike the last; proposals " << r.stats.proposals << ", lost "
              << r.stats.lost << ", cuts " << r.stats.cuts << std::endl;
}

}  // namespace

TEST(VideoReframer, AStillShotWithNoiseStaysStillWithAGivenCage) {
    const Size size(384, 240);
    const Mat still = photo("propose_bench/messi5.jpg", size);
    const Multicage cage = messiCage().scaled(size);
    ASSERT_TRUE(cage.validate());
    expectStill(still, Size(136, 240), cage, "messi5, given cage");
}

TEST(VideoReframer, AStillShotWithNoiseStaysStillWithTheProposal) {
    const Size size(384, 240);
    const Mat still = photo("propose_bench/messi5.jpg", size);
    expectStill(still, Size(136, 240), Multicage(), "messi5, proposed cage");
}

// The same with a ratio the warp takes alone (1.6 to 4:3: the window is the whole frame).
TEST(VideoReframer, AStillShotWithNoiseStaysStillWhenOnlyWarped) {
    const Size size(384, 240);
    const Mat still = photo("propose_bench/messi5.jpg", size);
    expectStill(still, Size(320, 240), Multicage(), "messi5, proposed cage, 4:3");
}

namespace {

// Item 3: contentAwareResize to newSize with cage, its pose computed as it does (window, crop,
// cropped multicage, binding, resize pose): the polygons in `mustKeep` (faces) whole, and every
// inner polygon the window holds within a pixel of a similarity.
void expectFacesKept(const Mat& image, const Multicage& rest, Size newSize, bool whole,
                     const std::string& what, std::vector<int> mustKeep = {}) {
    if (mustKeep.empty()) mustKeep = innerPolygons(rest);
    SCOPED_TRACE(what + " to " + std::to_string(newSize.width) + "x" +
                 std::to_string(newSize.height));
    ResizeParams params;
    params.gridStep = 2;
    // A photo is cropped to the window rounded to whole pixels (reframeCrop).
    const Rect2d window = reframeWindow(rest, newSize, params);
    const Rect crop = reframeCrop(rest, newSize, params);
    EXPECT_LE(std::abs(crop.x - window.x) + std::abs(crop.width - window.width), 1.0);
    if (whole) {
        EXPECT_EQ(window, Rect2d(0, 0, image.cols, image.rows));
        EXPECT_EQ(crop, Rect(0, 0, image.cols, image.rows));
    } else {
        EXPECT_LT(crop.area(), image.size().area());
    }
    std::vector<int> kept;
    const Multicage cropped = cropMulticage(rest, crop, &kept);
    ASSERT_TRUE(cropped.validate());
    // Every face lies whole in the window (a feature may be left out: reframeWindow()).
    for (int i : mustKeep)
        EXPECT_NE(std::find(kept.begin(), kept.end(), i), kept.end())
            << "polygon " << i << " (depth " << rest.depth(i) << ") is cut by window " << window;
    DeformParams deform;
    deform.coordinates = params.coordinates;
    deform.gridStep = params.gridStep;
    const Ptr<Deformer> deformer = Deformer::create(image(crop), cropped, deform);
    const std::vector<Point2f> pose = resizePose(cropped, deformer->binding(), newSize, params);
    Mat positions;
    deformer->binding().apply(pose, positions);
    double worstVertex = 0, worstNode = 0, worstAspect = 0;
    // The faces and features of rest, on the crop (an outline the window cuts is dropped, and
    // what it held becomes an outline of its own: still moved by a similarity).
    int faces = 0;
    for (int r : innerPolygons(rest)) {
        const auto at = std::find(kept.begin(), kept.end(), r);
        if (at == kept.end()) continue;
        const int i = int(at - kept.begin());
        ++faces;
        const std::vector<Point2f> polygon = cropped.polygon(i),
                                   posed = posedPolygon(cropped, pose, i);
        const double residual = maxSimilarityResidual(polygon, posed),
                     aspect = std::abs(aspectOf(posed) / aspectOf(polygon) - 1);
        EXPECT_LE(residual, 1.0) << "polygon " << r;
        EXPECT_LE(aspect, 0.05) << "polygon " << r;
        // What the polygon holds: the binding's nodes inside it, where the pose moves them.
        std::vector<Point2f> restNodes, movedNodes;
        const Binding& b = deformer->binding();
        for (int gy = 0; gy < b.gridSize.height; ++gy)
            for (int gx = 0; gx < b.gridSize.width; ++gx) {
                const Point2f p = b.node(gx, gy);
                if (pointPolygonTest(polygon, p, true) < 0.5) continue;
                restNodes.push_back(p);
                movedNodes.push_back(positions.at<Point2f>(gy, gx));
            }
        if (restNodes.size() >= 3) {
            const double nodes = maxSimilarityResidual(restNodes, movedNodes);
            EXPECT_LE(nodes, 1.0) << "polygon " << r << ": its content";
            worstNode = std::max(worstNode, nodes);
        }
        worstVertex = std::max(worstVertex, residual), worstAspect = std::max(worstAspect, aspect);
    }
    Mat mine, dst;
    deformer->deform(pose, mine);
    contentAwareResize(image, newSize, dst, rest, params);
    EXPECT_EQ(dst.size(), newSize);
    EXPECT_EQ(dst.type(), image.type());
    // contentAwareResize binds the same crop the same way (on the whole image, the whole
    // multicage: cropMulticage() keeps every polygon there).
    EXPECT_GE(multicage_testing::psnr(mine, dst), 40.0);
    std::cout << "[ ratios ] " << what << " to " << newSize << ": window " << window << ", "
              << faces << " faces and features, residual max " << worstVertex << " px (content "
              << worstNode << " px), aspect change max " << 100 * worstAspect << " %" << std::endl;
}

}  // namespace

TEST(ReframeRatios, FacesStayWholeAndInShapeWithGivenCages) {
    const Size messiSize(384, 240), astronautSize(320, 320);
    const Mat messi = photo("propose_bench/messi5.jpg", messiSize),
              astronaut = photo("propose_bench/astronaut.jpg", astronautSize);
    const Multicage messiRest = messiCage().scaled(messiSize),
                    astronautRest = astronautCage().scaled(astronautSize);
    ASSERT_TRUE(messiRest.validate());
    ASSERT_TRUE(astronautRest.validate());
    expectFacesKept(messi, messiRest, Size(136, 240), false, "messi5 9:16");
    expectFacesKept(messi, messiRest, Size(240, 240), false, "messi5 1:1");
    expectFacesKept(messi, messiRest, Size(384, 164), true, "messi5 21:9");  // 1.46: warp only
    expectFacesKept(messi, messiRest, Size(320, 240), true, "messi5 4:3");
    expectFacesKept(astronaut, astronautRest, Size(180, 320), false, "astronaut 9:16");
    expectFacesKept(astronaut, astronautRest, Size(320, 136), false, "astronaut 21:9");
    expectFacesKept(astronaut, astronautRest, Size(320, 240), true, "astronaut 4:3");
}

TEST(ReframeRatios, FacesStayWholeAndInShapeWithProposedCages) {
    const Size messiSize(384, 240), astronautSize(320, 320);
    const Mat messi = photo("propose_bench/messi5.jpg", messiSize),
              astronaut = photo("propose_bench/astronaut.jpg", astronautSize);
    ResizeParams params;
    params.gridStep = 2;
    const Multicage messiRest = resizeCage(messi, params),
                    astronautRest = resizeCage(astronaut, params);
    std::cout << "[ ratios ] proposed: messi5 " << messiRest.polygonCount() << " polygons ("
              << innerPolygons(messiRest).size() << " inner), astronaut "
              << astronautRest.polygonCount() << " (" << innerPolygons(astronautRest).size()
              << " inner); face cascade: "
              << (faceCascadeFile().empty() ? "none" : faceCascadeFile()) << std::endl;
    // The faces: the inner polygons holding a face the cascade finds (a feature may be left out).
    // Without the cascades (opencv-data) there are none, and every inner polygon must be whole.
    const bool cascades = !faceCascadeFile().empty();
    const std::vector<int> messiFaces = cascades ? facePolygons(messiRest, detectFaces(messi))
                                                 : innerPolygons(messiRest),
                           astronautFaces =
                               cascades ? facePolygons(astronautRest, detectFaces(astronaut))
                                        : innerPolygons(astronautRest);
    if (cascades) {
        ASSERT_FALSE(messiFaces.empty());
        ASSERT_FALSE(astronautFaces.empty());
    }
    expectFacesKept(messi, messiRest, Size(136, 240), false, "messi5 (proposed) 9:16", messiFaces);
    expectFacesKept(messi, messiRest, Size(240, 240), false, "messi5 (proposed) 1:1", messiFaces);
    expectFacesKept(messi, messiRest, Size(384, 164), true, "messi5 (proposed) 21:9", messiFaces);
    expectFacesKept(messi, messiRest, Size(320, 240), true, "messi5 (proposed) 4:3", messiFaces);
    expectFacesKept(astronaut, astronautRest, Size(180, 320), false, "astronaut (proposed) 9:16",
                    astronautFaces);
    expectFacesKept(astronaut, astronautRest, Size(320, 136), false, "astronaut (proposed) 21:9",
                    astronautFaces);
    expectFacesKept(astronaut, astronautRest, Size(320, 240), true, "astronaut (proposed) 4:3",
                    astronautFaces);
}

// Item 4: the window rule (reframeWindow), on a 640x360 image reframed to 9:16 (180x320): the
// plain crop is 202.5 wide, with 8.1 px (4%) to spare on each side of what it holds.
namespace {
const Size kImage(640, 360), kPortrait(180, 320);
const double kPlainCrop = 360.0 * 180 / 320;

std::vector<Point2f> box(float x0, float y0, float x1, float y1) {
    return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}
Multicage cageOf(Size size, const std::vector<std::vector<Point2f>>& polygons) {
    Multicage cage(size);
    for (const auto& p : polygons) cage.addPolygon(p);
    cage.orient();
    return cage;
}
bool holds(const Rect2d& window, const std::vector<Point2f>& polygon) {
    for (const Point2f& p : polygon)
        if (p.x < window.x || p.y < window.y || p.x > window.br().x || p.y > window.br().y)
            return false;
    return true;
}
}  // namespace

TEST(ReframeWindow, WithinMaxWarpTheWholeImage) {
    const Multicage cage = cageOf(Size(640, 480), {box(100, 100, 200, 200)});
    // 4:3 to 16:9 is 1.33, under the default 1.5.
    EXPECT_EQ(reframeWindow(cage, Size(640, 360)), Rect2d(0, 0, 640, 480));
    EXPECT_EQ(reframeWindow(cage, Size(320, 240)), Rect2d(0, 0, 640, 480));
    EXPECT_EQ(reframeWindow(cage, Size(1280, 960)), Rect2d(0, 0, 640, 480));
    // Past it, a crop; maxWarp below 1 never crops, even at 9:16.
    EXPECT_NE(reframeWindow(cage, Size(180, 480)), Rect2d(0, 0, 640, 480));
    ResizeParams never;
    never.maxWarp = 0.5;
    EXPECT_EQ(reframeWindow(cage, Size(180, 480), never), Rect2d(0, 0, 640, 480));
    never.maxWarp = 0;
    EXPECT_EQ(reframeWindow(cage, Size(180, 480), never), Rect2d(0, 0, 640, 480));
    // Nothing in the cage: a plain crop in the middle.
    const Rect2d middle = reframeWindow(Multicage(kImage), kPortrait);
    EXPECT_NEAR(middle.width, kPlainCrop, 1e-9);
    EXPECT_NEAR(middle.x + middle.width / 2, 320.0, 1e-9);
    EXPECT_EQ(middle.y, 0.0);
    EXPECT_EQ(middle.height, 360.0);
}

TEST(ReframeWindow, ASmallOutlineGetsAPlainCropCentredOnIt) {
    const std::vector<Point2f> subject = box(400, 100, 440, 200);
    const Rect2d w = reframeWindow(cageOf(kImage, {subject}), kPortrait);
    EXPECT_NEAR(w.width, kPlainCrop, 1e-6);
    EXPECT_NEAR(w.x + w.width / 2, 420.0, 1e-6);
    EXPECT_EQ(w.y, 0.0);
    EXPECT_EQ(w.height, 360.0);
    EXPECT_TRUE(holds(w, subject));
    // Near the border: moved inside the image, still holding it.
    const std::vector<Point2f> edge = box(5, 100, 45, 200);
    const Rect2d e = reframeWindow(cageOf(kImage, {edge}), kPortrait);
    EXPECT_NEAR(e.x, 0.0, 1e-9);
    EXPECT_NEAR(e.width, kPlainCrop, 1e-6);
    const Rect2d r = reframeWindow(cageOf(kImage, {box(600, 100, 639, 200)}), kPortrait);
    EXPECT_NEAR(r.br().x, 640.0, 1e-6);
    // The window's crop covers it with whole pixels.
    const Rect crop = windowCrop(w, kImage);
    EXPECT_LE(crop.x, w.x);
    EXPECT_GE(crop.br().x, w.br().x);
    EXPECT_LT(crop.width, w.width + 2);
}

TEST(ReframeWindow, OutlinesFarApartWidenItWithinTheImage) {
    const std::vector<Point2f> left = box(50, 100, 90, 200), right = box(500, 120, 540, 220);
    const Rect2d w = reframeWindow(cageOf(kImage, {left, right}), kPortrait);
    EXPECT_TRUE(holds(w, left));
    EXPECT_TRUE(holds(w, right));
    EXPECT_GT(w.width, kPlainCrop);
    EXPECT_LE(w.width, 640.0);
    // 6% of the window to spare on each side (more than 4% of the plain crop here).
    EXPECT_NEAR(w.width, 490 / 0.88, 1e-6);
    EXPECT_NEAR(w.x + w.width / 2, 295.0, 1e-6);
    // The warp brings them in: both on the output, the outlines and what they protect (a face
    // each) moved by similarities: the margin leaves the resize pose room to keep them whole.
    const std::vector<Point2f> leftFace = box(58, 110, 82, 140),
                               rightFace = box(508, 130, 532, 160);
    const Multicage withFaces = cageOf(kImage, {left, right, leftFace, rightFace});
    EXPECT_EQ(reframeWindow(withFaces, kPortrait), w);
    const Rect crop = windowCrop(w, kImage);
    std::vector<int> kept;
    const Multicage cropped = cropMulticage(withFaces, crop, &kept);
    ASSERT_EQ(kept, (std::vector<int>{0, 1, 2, 3}));
    ResizeParams params;
    params.gridStep = 2;
    const std::vector<Point2f> pose =
        resizePose(cropped, bind(cropped, params.coordinates, params.gridStep), kPortrait, params);
    const Rect2d output(-0.5, -0.5, kPortrait.width, kPortrait.height);
    for (int i = 0; i < 4; ++i) {
        const std::vector<Point2f> posed = posedPolygon(cropped, pose, i);
        const double residual = maxSimilarityResidual(cropped.polygon(i), posed),
                     aspect = aspectOf(posed) / aspectOf(cropped.polygon(i));
        EXPECT_TRUE(holds(output, posed)) << "polygon " << i;
        EXPECT_LE(residual, 1.0) << "polygon " << i;
        EXPECT_NEAR(aspect, 1.0, 0.05) << "polygon " << i;
        std::cout << "[ far apart ] window " << w << ", polygon " << i << " (depth "
                  << cropped.depth(i) << "): similarity residual " << residual << " px, aspect x "
                  << aspect << std::endl;
    }
    // Spanning the image: never wider than it.
    const Rect2d all =
        reframeWindow(cageOf(kImage, {box(2, 100, 40, 200), box(600, 100, 637, 200)}), kPortrait);
    EXPECT_EQ(all, Rect2d(0, 0, 640, 360));
    // Close together: never narrower than the plain crop.
    const Rect2d close = reframeWindow(
        cageOf(kImage, {box(300, 100, 320, 200), box(330, 100, 350, 200)}), kPortrait);
    EXPECT_NEAR(close.width, kPlainCrop, 1e-6);
    EXPECT_NEAR(close.x + close.width / 2, 325.0, 1e-6);
}

TEST(ReframeWindow, AnOutlineWiderThanTheCropIsCutAroundWhatItProtects) {
    // No inner polygon: a plain crop centred on the outline.
    const std::vector<Point2f> wide = box(100, 50, 500, 300);
    const Rect2d w = reframeWindow(cageOf(kImage, {wide}), kPortrait);
    EXPECT_NEAR(w.width, kPlainCrop, 1e-6);
    EXPECT_NEAR(w.x + w.width / 2, 300.0, 1e-6);
    // A face inside it: a plain crop centred on the face, which it holds.
    const std::vector<Point2f> face = box(380, 80, 440, 150);
    const Rect2d f = reframeWindow(cageOf(kImage, {wide, face}), kPortrait);
    EXPECT_NEAR(f.width, kPlainCrop, 1e-6);
    EXPECT_NEAR(f.x + f.width / 2, 410.0, 1e-6);
    EXPECT_TRUE(holds(f, face));
    std::vector<int> kept;
    const Multicage cropped =
        cropMulticage(cageOf(kImage, {wide, face}), windowCrop(f, kImage), &kept);
    EXPECT_EQ(kept, std::vector<int>{1});  // the outline is cut, the face kept
    EXPECT_EQ(cropped.polygonCount(), 1);
    EXPECT_TRUE(cropped.validate());
}

// Inner polygons that cannot stay in shape together in a window squeezed into the output: the
// window holds the one that comes first in the cage (a proposal lists faces first) and cuts the
// other. Each keeps its scale while the window is squeezed: a patch beside the face comes too
// near it; one further off is pushed inwards from the window's side onto it. Held together,
// the blend that stops them crossing flattens them. A small patch that fits the plain crop
// beside the face is held with it.
TEST(ReframeWindow, WhatCannotStayInShapeTogetherTheFirstInTheCageWins) {
    const std::vector<Point2f> wide = box(20, 20, 620, 340), face = box(100, 60, 220, 180);
    ResizeParams params;
    params.gridStep = 2;
    // The worst residual from a similarity of the polygons the window's crop keeps.
    auto worstResidual = [&](const Multicage& cage, const Rect2d& window) {
        const Multicage cropped = cropMulticage(cage, windowCrop(window, kImage));
        const std::vector<Point2f> pose = resizePose(cropped, kPortrait, params);
        double worst = 0;
        for (int i = 0; i < cropped.polygonCount(); ++i)
            worst = std::max(
                worst, maxSimilarityResidual(cropped.polygon(i), posedPolygon(cropped, pose, i)));
        return worst;
    };
    for (const auto& [patch, where] : {std::pair(box(230, 100, 300, 170), "beside"),
                                       std::pair(box(300, 100, 370, 170), "further off")}) {
        SCOPED_TRACE(where);
        const Multicage faceFirst = cageOf(kImage, {wide, face, patch});
        const Rect2d w = reframeWindow(faceFirst, kPortrait, params);
        EXPECT_TRUE(holds(w, face));
        EXPECT_FALSE(holds(w, patch));
        EXPECT_NEAR(w.width, kPlainCrop, 1e-6);
        EXPECT_NEAR(w.x + w.width / 2, 160.0, 1e-6);
        // The patch listed first: the patch is held, the face cut.
        const Rect2d p = reframeWindow(cageOf(kImage, {wide, patch, face}), kPortrait, params);
        EXPECT_TRUE(holds(p, patch));
        EXPECT_FALSE(holds(p, face));
        // Both held (what the window did before it checked): the pose cannot keep their shape.
        const double lo = 100, hi = patch[1].x, span = hi - lo,
                     both = std::max(span + 0.08 * kPlainCrop, span / 0.88);
        const Rect2d holdingBoth((lo + hi - both) / 2, 0, both, kImage.height);
        ASSERT_TRUE(holds(holdingBoth, face) && holds(holdingBoth, patch));
        const double kept = worstResidual(faceFirst, w),
                     squeezed = worstResidual(faceFirst, holdingBoth);
        EXPECT_LE(kept, 1.0);
        EXPECT_GT(squeezed, 1.0);
        std::cout << "[ first wins ] patch " << where << ": residual " << kept
                  << " px with the face alone, " << squeezed << " px holding both" << std::endl;
    }
    const std::vector<Point2f> small = box(230, 100, 260, 130);
    const Multicage withSmall = cageOf(kImage, {wide, face, small});
    const Rect2d s = reframeWindow(withSmall, kPortrait, params);
    EXPECT_TRUE(holds(s, face) && holds(s, small));
    EXPECT_LE(worstResidual(withSmall, s), 1.0);
}

TEST(ReframeWindow, WiderTargetsCropVertically) {
    // A portrait 360x640 to 16:9 (320x180): the whole width, a window of rows 202.5 high.
    const std::vector<Point2f> subject = box(100, 400, 200, 460);
    const Rect2d w = reframeWindow(cageOf(Size(360, 640), {subject}), Size(320, 180));
    EXPECT_EQ(w.x, 0.0);
    EXPECT_EQ(w.width, 360.0);
    EXPECT_NEAR(w.height, 360.0 * 180 / 320, 1e-6);
    EXPECT_NEAR(w.y + w.height / 2, 430.0, 1e-6);
    EXPECT_TRUE(holds(w, subject));
}

// Item 5: a cut from one photo to another starts a shot.
TEST(VideoReframer, ACutStartsAShotAndEveryFrameComesOut) {
    const Size size(384, 216), newSize(122, 216);
    const Mat a = photo("fruits.jpg", size), b = photo("building.jpg", size);
    std::vector<Mat> clip;
    for (int t = 0; t < 30; ++t) clip.push_back(t < 15 ? a : b);
    const Multicage cage = cageOf(
        size, {box(200, 40, 300, 180), ellipsePolygon(Point2f(250, 100), Size2f(20, 25), 8)});
    ASSERT_TRUE(cage.validate());
    const Reframed r = reframeClip(clip, newSize, cage);
    expectWholeClip(r, 30, newSize, CV_8UC3);
    if (HasFatalFailure()) return;
    EXPECT_EQ(r.stats.cuts, 1);
    EXPECT_EQ(r.stats.proposals, 1);  // on the new shot
    for (const ReframedFrame& f : r.frames) {
        EXPECT_EQ(f.shot, f.index < 15 ? 0 : 1) << "frame " << f.index;
        // Each shot's window is its own, not averaged across the cut.
        const ReframedFrame& first = r.frames[f.index < 15 ? 0 : 15];
        EXPECT_NEAR(f.window.x, first.window.x, 0.05) << "frame " << f.index;
        EXPECT_NEAR(f.window.width, first.window.width, 0.05) << "frame " << f.index;
    }
    // The first shot's window holds the given outline, centred on it.
    EXPECT_NEAR(r.frames[0].window.x + r.frames[0].window.width / 2, 250.0, 0.05);
    std::cout << "[ cut ] windows: shot 0 " << r.frames[0].window << ", shot 1 "
              << r.frames[15].window << "; " << r.frames[15].cage.polygonCount()
              << " polygons proposed on the second shot (" << r.stats.lastWhy << ")" << std::endl;
}

// Item 6: frames it cannot take are refused with a cv::Exception, never a crash.
TEST(VideoReframer, BadFramesAreRefused) {
    const Size size(320, 180), newSize(100, 180);
    const Mat good = photo("fruits.jpg", size);
    {
        VideoReframer r(newSize);
        EXPECT_THROW(r.push(Mat()), cv::Exception);
        EXPECT_THROW(r.push(Mat(size, CV_16UC3, Scalar::all(0))), cv::Exception);
        EXPECT_THROW(r.push(Mat(size, CV_8UC2, Scalar::all(0))), cv::Exception);
        EXPECT_THROW(r.push(Mat(size, CV_32FC3, Scalar::all(0))), cv::Exception);
        EXPECT_THROW(r.push(Mat(size, CV_8UC(5), Scalar::all(0))), cv::Exception);
        // None of those counted: the first good frame is frame 0.
        r.push(good);
        EXPECT_EQ(r.stats().framesIn, 1);
        EXPECT_THROW(r.push(photo("fruits.jpg", Size(322, 180))), cv::Exception);
        Mat grey;
        cvtColor(good, grey, COLOR_BGR2GRAY);
        EXPECT_THROW(r.push(grey), cv::Exception);  // another type after the first
        r.push(good);
        r.finish();
        EXPECT_THROW(r.push(good), cv::Exception);
        ReframedFrame out;
        int n = 0;
        while (r.pop(out)) ++n;
        EXPECT_EQ(n, 2);
    }
    EXPECT_THROW(VideoReframer(Size(0, 180)), cv::Exception);
    {
        VideoReframer tooLarge(Size(320 * 9, 180));  // past maxScale: refused on the first frame
        EXPECT_THROW(tooLarge.push(good), cv::Exception);
    }
}

TEST(VideoReframer, ABlackClipWithNoCageStillComesOut) {
    const Size size(320, 180), newSize(100, 180);
    std::vector<Mat> clip(10, Mat(size, CV_8UC3, Scalar::all(0)));
    const Reframed r = reframeClip(clip, newSize);
    expectWholeClip(r, 10, newSize, CV_8UC3);
    for (const ReframedFrame& f : r.frames) {
        EXPECT_EQ(f.cage.polygonCount(), 0) << "frame " << f.index;
        EXPECT_EQ(countNonZero(f.image.reshape(1)), 0) << "frame " << f.index;
    }
    // Grey (1-channel) and BGRA clips too.
    const Reframed g = reframeClip(std::vector<Mat>(6, Mat(size, CV_8UC1, Scalar(0))), newSize);
    expectWholeClip(g, 6, newSize, CV_8UC1);
    const Reframed a =
        reframeClip(std::vector<Mat>(3, Mat(size, CV_8UC4, Scalar::all(0))), newSize);
    expectWholeClip(a, 3, newSize, CV_8UC4);
}

// Outlines along the image's frame: the default proposal ends the outline of a subject the frame
// cuts 0.2 px inside the frame (x = -0.3, y = H - 0.7: resizeCage() on messi5 and astronaut at
// 384x240 and 320x320), and a cage drawn on the last pixel and scaled to a smaller frame lands
// past the last pixel centre too (511 of 512 becomes 319.19 of 320). cropMulticage() keeps them
// where the crop's frame holds them (they were dropped while it asked for [x, x + width - 1]).
TEST(ReframeCrop, CropMulticageKeepsOutlinesAlongTheImageFrame) {
    const Size size(320, 240);
    const std::vector<Point2f> person = box(100, 60, 180, 239.3f), side = box(-0.3f, 50, 40, 120);
    const Multicage cage = cageOf(size, {person, side});
    ASSERT_TRUE(cage.validate());
    std::vector<int> kept;
    cropMulticage(cage, Rect(Point(), size), &kept);
    EXPECT_EQ(kept, (std::vector<int>{0, 1})) << "the whole image";
    cropMulticage(cage, Rect(0, 0, 200, 240), &kept);
    EXPECT_EQ(kept, (std::vector<int>{0, 1})) << "a crop on the image's left, top and bottom";
}

// Within maxWarp the window is the whole frame: contentAwareResize() binds the whole multicage,
// VideoReframer cropMulticage()'s of the whole frame, which must be the same (the proposal's
// outline of the player, cut by the bottom border, included): the clip's frames are the photo's.
TEST(VideoReframer, AWholeWindowShowsWhatContentAwareResizeShows) {
    const Size size(384, 240), newSize(320, 240);  // 1.6 to 4:3: within maxWarp, no crop
    const Mat frame = photo("propose_bench/messi5.jpg", size);
    const ReframeParams params;
    const Multicage rest = resizeCage(frame, params.resize);
    Mat expected;
    contentAwareResize(frame, newSize, expected, rest, params.resize);
    const Reframed r = reframeClip({frame, frame, frame}, newSize, Multicage(), params);
    expectWholeClip(r, 3, newSize, CV_8UC3);
    for (const ReframedFrame& f : r.frames) {
        // (averaged over frames: the whole frame to a rounding)
        EXPECT_NEAR(f.window.x, 0, 1e-9) << "frame " << f.index;
        EXPECT_NEAR(f.window.width, size.width, 1e-9) << "frame " << f.index;
        EXPECT_EQ(f.crop, Rect(Point(), size)) << "frame " << f.index;
        EXPECT_EQ(f.cage.polygonCount(), rest.polygonCount()) << "frame " << f.index;
        const double db = multicage_testing::psnr(f.image, expected);
        EXPECT_GE(db, 40.0) << "frame " << f.index;
        if (f.index == 0)
            std::cout << "[ whole window ] proposed " << rest.polygonCount() << " polygons, "
                      << f.cage.polygonCount() << " on the reframer's crop; PSNR against "
                      << "contentAwareResize " << db << " dB" << std::endl;
    }
}

// Past maxWarp: two subjects far apart, both cut by the bottom border as the proposal cuts them,
// each with a face, reframed to 9:16. The window widens to hold both, the crop keeps both
// outlines, and the faces come out as similarities. (The outlines themselves are blended towards
// the frame's scaling where a similarity would fold the mesh, as resizePose() documents: their
// squash is printed, not asserted.)
TEST(ReframeRatios, SubjectsCutByTheFrameAreKeptInAWidenedWindow) {
    const std::vector<std::vector<Point2f>> polygons = {
        box(40, 150, 120, 359.3f), box(520, 150, 600, 359.3f), box(62, 170, 98, 215),
        box(542, 170, 578, 215)};
    const Multicage rest = cageOf(kImage, polygons);
    ASSERT_TRUE(rest.validate());
    ResizeParams params;
    params.gridStep = 2;
    const Rect2d window = reframeWindow(rest, kPortrait, params);
    for (const auto& p : polygons) EXPECT_TRUE(holds(window, p));
    EXPECT_GT(window.width, kPlainCrop);
    const Rect crop = windowCrop(window, kImage);
    std::vector<int> kept;
    const Multicage cropped = cropMulticage(rest, crop, &kept);
    ASSERT_EQ(kept, (std::vector<int>{0, 1, 2, 3}));
    const std::vector<Point2f> pose =
        resizePose(cropped, bind(cropped, params.coordinates, params.gridStep), kPortrait, params);
    const Rect2d output(-0.5, -0.5, kPortrait.width, kPortrait.height);
    for (int i = 0; i < cropped.polygonCount(); ++i) {
        const std::vector<Point2f> posed = posedPolygon(cropped, pose, i);
        const double residual = maxSimilarityResidual(cropped.polygon(i), posed),
                     aspect = aspectOf(posed) / aspectOf(cropped.polygon(i));
        EXPECT_TRUE(holds(output, posed)) << "polygon " << i;
        if (cropped.depth(i) >= 2) {
            EXPECT_LE(residual, 1.0) << "face " << i;
            EXPECT_NEAR(aspect, 1.0, 0.05) << "face " << i;
        }
        std::cout << "[ cut by the frame ] window " << window << ", polygon " << i << " (depth "
                  << cropped.depth(i) << "): similarity residual " << residual << " px, aspect x "
                  << aspect << std::endl;
    }
}

// A proposed outline along the frame lies past the last pixel centre (y = H - 0.7); CageTracker
// moves it within [0, H-1]. The crop must keep it on both, or a still shot's first frame (and any
// re-proposed one: a cut, a lost subject) carries other polygons than the next, a key of its own
// (not averaged with its neighbours) and, where the window is the whole frame, another picture
// (it was 21.7 dB from the second frame at 4:3 while cropMulticage() dropped it).
TEST(VideoReframer, TheFirstFrameKeepsThePolygonsTheNextOnesKeep) {
    const Size size(384, 240);
    const Mat frame = photo("propose_bench/messi5.jpg", size);
    for (const Size newSize : {Size(136, 240), Size(320, 240)}) {
        const Reframed r = reframeClip({frame, frame, frame}, newSize);
        expectWholeClip(r, 3, newSize, CV_8UC3);
        if (r.frames.size() != 3) continue;
        const ReframedFrame &first = r.frames[0], &second = r.frames[1];
        EXPECT_EQ(first.cage.polygonCount(), second.cage.polygonCount()) << newSize;
        const double db = multicage_testing::psnr(first.image, second.image);
        EXPECT_GE(db, 40.0) << newSize;
        std::cout << "[ first frame ] to " << newSize << ": polygons on the crop "
                  << first.cage.polygonCount() << " (frame 0), " << second.cage.polygonCount()
                  << " (frame 1); frames 0 and 1 " << db << " dB apart" << std::endl;
    }
}

// Item 8: a subject that walks out of the frame. The outline is held on the frame's side while
// the tracker can follow it, then lost and proposed again: every frame still comes out, every
// multicage it shows is valid, and what stays protected is still moved by a similarity.
TEST(VideoReframer, ASubjectLeavingTheFrameIsLetGo) {
    const Crossing clip;
    const int frames = 60;  // the subject's centre runs to x = 444, its ellipse out past 420
    std::vector<Mat> video;
    for (int t = 0; t < frames; ++t) video.push_back(clip.frame(t));
    const Size newSize(122, 216);
    const Reframed r = reframeClip(video, newSize, clip.cage());
    expectWholeClip(r, frames, newSize, CV_8UC3);
    EXPECT_GE(r.stats.proposals + r.stats.lost, 1) << "the subject left without notice";
    for (const ReframedFrame& f : r.frames) {
        std::string why;
        EXPECT_TRUE(f.cage.validateGeometry(&why)) << "frame " << f.index << ": " << why;
        EXPECT_TRUE(f.tracked.validateGeometry(&why)) << "frame " << f.index << ": " << why;
        for (int i : innerPolygons(f.cage))
            EXPECT_LE(maxSimilarityResidual(f.cage.polygon(i), posedPolygon(f.cage, f.pose, i)),
                      1.0)
                << "frame " << f.index << ", polygon " << i;
    }
    std::cout << "[ leaving ] proposals " << r.stats.proposals << ", lost " << r.stats.lost
              << ", last frame's polygons " << r.frames.back().tracked.polygonCount() << std::endl;
}

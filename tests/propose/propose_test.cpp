// Automatic multicage proposal: validity, coverage, budgets, nesting, feature protection.
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "propose_bench.hpp"
#include "testing.hpp"

using namespace cv::multicage;
using multicage_testing::readSample;
using propose_bench::maskIoU;

namespace {

// Pixels inside a polygon (centres inside or on it), as a mask of the image's size.
cv::Mat fill(const std::vector<cv::Point2f>& polygon, cv::Size size) {
    cv::Mat m(size, CV_8U, cv::Scalar(0));
    std::vector<std::vector<cv::Point>> pts(1);
    for (const cv::Point2f& p : polygon) pts[0].emplace_back(cvRound(p.x * 16), cvRound(p.y * 16));
    cv::fillPoly(m, pts, cv::Scalar(255), cv::LINE_8, 4);
    return m;
}

cv::Mat fillAll(const Multicage& cage) {
    cv::Mat m(cage.imageSize(), CV_8U, cv::Scalar(0));
    for (int p = 0; p < cage.polygonCount(); ++p) m |= fill(cage.polygon(p), cage.imageSize());
    return m;
}

// A mask dilated by a Euclidean radius (what "the dilated shape" means below).
cv::Mat dilated(const cv::Mat& mask, float radius) {
    cv::Mat d;
    cv::distanceTransform(~mask, d, cv::DIST_L2, cv::DIST_MASK_PRECISE);
    return d <= radius;
}

int polygonAt(const Multicage& cage, cv::Point2f p) {
    int best = -1;
    for (int i = 0; i < cage.polygonCount(); ++i)
        if (cv::pointPolygonTest(cage.polygon(i), p, false) > 0 &&
            (best < 0 || cage.depth(i) > cage.depth(best)))
            best = i;
    return best;
}

// Random shapes: blobs, rings (some with a disk inside), stars, touching pairs, and shapes
// whose centre is near or beyond the image border.
cv::Mat randomShapes(cv::RNG& rng, cv::Size size) {
    cv::Mat mask(size, CV_8U, cv::Scalar(0));
    const int n = rng.uniform(1, 5);
    const float s = static_cast<float>(std::min(size.width, size.height));
    for (int k = 0; k < n; ++k) {
        cv::Point2f c(rng.uniform(0.f, 1.f) * size.width, rng.uniform(0.f, 1.f) * size.height);
        const float r = rng.uniform(0.08f, 0.3f) * s;
        switch (rng.uniform(0, 6)) {
            case 0:  // blob
                cv::ellipse(mask,
                            cv::RotatedRect(c, cv::Size2f(2 * r, rng.uniform(0.6f, 2.f) * r),
                                            rng.uniform(0.f, 180.f)),
                            cv::Scalar(255), cv::FILLED);
                break;
            case 1: {  // ring, maybe with a disk inside
                const float t = rng.uniform(0.15f, 0.4f) * r;
                cv::circle(mask, c, cvRound(r - t / 2), cv::Scalar(255), std::max(2, cvRound(t)));
                if (rng.uniform(0, 2))
                    cv::circle(mask, c, cvRound(rng.uniform(0.15f, 0.4f) * r), cv::Scalar(255),
                               cv::FILLED);
                break;
            }
            case 2: {  // star
                std::vector<float> radii;
                const int m = rng.uniform(5, 14);
                for (int i = 0; i < m; ++i) radii.push_back(r * rng.uniform(0.35f, 1.f));
                std::vector<std::vector<cv::Point>> pts(1);
                for (cv::Point2f p :
                     multicage_fixtures::starPolygon(c, radii, rng.uniform(0.f, 6.f)))
                    pts[0].emplace_back(p);
                cv::fillPoly(mask, pts, cv::Scalar(255));
                break;
            }
            case 3: {  // touching pair
                const float r2 = r * rng.uniform(0.5f, 1.f);
                const float a = rng.uniform(0.f, 6.3f);
                cv::circle(mask, c, cvRound(r), cv::Scalar(255), cv::FILLED);
                cv::circle(mask, c + (r + r2) * cv::Point2f(std::cos(a), std::sin(a)), cvRound(r2),
                           cv::Scalar(255), cv::FILLED);
                break;
            }
            case 4: {  // cut by the border
                c.x = rng.uniform(0, 2) ? rng.uniform(-0.5f, 0.3f) * r
                                        : size.width - rng.uniform(-0.5f, 0.3f) * r;
                cv::rectangle(
                    mask,
                    cv::Rect(cvRound(c.x - r), cvRound(c.y - r / 2), cvRound(2 * r), cvRound(r)),
                    cv::Scalar(255), cv::FILLED);
                break;
            }
            default: {  // thin bar (simplification stress)
                const cv::Point2f d = r * cv::Point2f(std::cos(k * 1.3f), std::sin(k * 1.3f));
                cv::line(mask, c - d, c + d, cv::Scalar(255), rng.uniform(3, 8));
                break;
            }
        }
    }
    return mask;
}

// The mask as a photograph: dark shapes of one colour on a light noisy background.
cv::Mat render(cv::RNG& rng, const cv::Mat& mask) {
    const cv::Scalar bg(rng.uniform(190, 255), rng.uniform(190, 255), rng.uniform(190, 255));
    const cv::Scalar fg(rng.uniform(0, 120), rng.uniform(0, 120), rng.uniform(0, 120));
    cv::Mat img(mask.size(), CV_8UC3, bg), noise(mask.size(), CV_16SC3), out;
    img.setTo(fg, mask);
    cv::randn(noise, cv::Scalar::all(0), cv::Scalar::all(6));
    img.convertTo(img, CV_16SC3);
    cv::Mat(img + noise).convertTo(out, CV_8UC3);
    return out;
}

}  // namespace

// Item 2: every proposal is valid, encloses what was segmented, and holds its budgets.
TEST(Propose, AlwaysValidCoveringAndWithinBudgetOnRandomImages) {
    cv::RNG rng(20240611);
    int invalid = 0, overBudget = 0, images = 0, withPolygons = 0;
    double segmented = 0, covered = 0, marginPixels = 0, marginCovered = 0;
    std::string firstProblem;
    for (int i = 0; i < 520; ++i) {
        const cv::Size size(rng.uniform(96, 224), rng.uniform(96, 224));
        const cv::Mat mask = randomShapes(rng, size);
        ProposeParams params;
        params.method = i % 2 ? PROPOSE_THRESHOLD : PROPOSE_MASK;
        params.margin = static_cast<float>(rng.uniform(2, 9));
        params.maxVertices = std::vector<int>{24, 40, 80}[rng.uniform(0, 3)];
        params.maxPolygonVertices = std::vector<int>{8, 16, 32}[rng.uniform(0, 3)];
        params.maxDepth = rng.uniform(1, 4);
        params.minRegionArea = 0.002;
        const cv::Mat input = params.method == PROPOSE_MASK ? mask : render(rng, mask);
        Multicage cage;
        try {
            cage = proposeMulticage(input, params);
        } catch (const cv::Exception& e) {
            if (cv::countNonZero(mask) == 0) continue;  // a constant photograph: an error by design
            ++invalid;
            if (firstProblem.empty())
                firstProblem = "image " + std::to_string(i) + " threw: " + e.err;
            continue;
        }
        ++images;
        std::string why;
        if (!cage.validate(&why)) {
            ++invalid;
            if (firstProblem.empty()) firstProblem = "image " + std::to_string(i) + ": " + why;
        }
        bool within =
            cage.vertexCount() <= params.maxVertices && cage.polygonCount() <= params.maxPolygons;
        for (int p = 0; p < cage.polygonCount(); ++p)
            within = within &&
                     static_cast<int>(cage.polygon(p).size()) <= params.maxPolygonVertices &&
                     cage.depth(p) <= params.maxDepth;
        overBudget += !within;
        if (cage.polygonCount() == 0) continue;
        ++withPolygons;
        cv::Mat seg;
        proposeSegmentation(input, seg, params);
        const cv::Mat inside = fillAll(cage);
        segmented += cv::countNonZero(seg);
        covered += cv::countNonZero(seg & inside);
        // The margin: the segmentation grown by half the margin is still inside.
        const cv::Mat grown = dilated(seg, 0.5f * params.margin);
        marginPixels += cv::countNonZero(grown);
        marginCovered += cv::countNonZero(grown & inside);
    }
    const double coverage = covered / segmented, marginCoverage = marginCovered / marginPixels;
    std::cout << "[ propose  ] " << images << " random images, " << withPolygons
              << " with polygons, " << invalid << " invalid, " << overBudget
              << " over budget, coverage " << 100 * coverage << "%, half-margin coverage "
              << 100 * marginCoverage << "%" << std::endl;
    EXPECT_GE(images, 500);
    EXPECT_EQ(invalid, 0) << firstProblem;
    EXPECT_EQ(overBudget, 0);
    EXPECT_GE(coverage, 0.995);
    EXPECT_GE(marginCoverage, 0.99);
}

// Item 3: known nesting.
TEST(Propose, DiskInsideRingGivesNestedPolygonsMatchingTheDilatedShapes) {
    const cv::Size size(260, 220);
    const cv::Point c(130, 110);
    cv::Mat ring(size, CV_8U, cv::Scalar(0)), disk = ring.clone(), ringFilled = ring.clone();
    cv::circle(ring, c, 80, cv::Scalar(255), cv::FILLED);
    cv::circle(ring, c, 55, cv::Scalar(0), cv::FILLED);
    cv::circle(ringFilled, c, 80, cv::Scalar(255), cv::FILLED);
    cv::circle(disk, c, 25, cv::Scalar(255), cv::FILLED);
    for (int method : {PROPOSE_MASK, PROPOSE_THRESHOLD}) {
        ProposeParams params;
        params.method = method;
        params.margin = 6;
        cv::RNG rng(7);
        const cv::Mat input =
            method == PROPOSE_MASK ? cv::Mat(ring | disk) : render(rng, ring | disk);
        const Multicage cage = proposeMulticage(input, params);
        ASSERT_TRUE(cage.validate());
        ASSERT_EQ(cage.polygonCount(), 2) << proposeMethodName(method);
        const int outer = cage.depth(0) == 1 ? 0 : 1, inner = 1 - outer;
        EXPECT_EQ(cage.depth(outer), 1);
        EXPECT_EQ(cage.depth(inner), 2);
        const double iouRing = maskIoU(fill(cage.polygon(outer), size), dilated(ringFilled, 6));
        const double iouDisk = maskIoU(fill(cage.polygon(inner), size), dilated(disk, 6));
        std::cout << "[ propose  ] " << proposeMethodName(method) << ": IoU ring " << iouRing
                  << ", disk " << iouDisk << std::endl;
        EXPECT_GE(iouRing, 0.9);
        EXPECT_GE(iouDisk, 0.9);
    }
}

TEST(Propose, SeparateObjectsGetSeparatePolygons) {
    const cv::Size size(300, 180);
    cv::Mat a(size, CV_8U, cv::Scalar(0)), b = a.clone();
    cv::circle(a, cv::Point(70, 90), 45, cv::Scalar(255), cv::FILLED);
    cv::rectangle(b, cv::Rect(170, 40, 90, 100), cv::Scalar(255), cv::FILLED);
    ProposeParams params;
    params.method = PROPOSE_MASK;
    params.margin = 8;
    const Multicage cage = proposeMulticage(a | b, params);
    ASSERT_TRUE(cage.validate());
    ASSERT_EQ(cage.polygonCount(), 2);
    for (const cv::Mat& shape : {a, b}) {
        const cv::Mat target = dilated(shape, 8);
        const int p =
            polygonAt(cage, cv::Point2f(cv::boundingRect(shape).tl() + cv::Point(20, 20)));
        ASSERT_GE(p, 0);
        EXPECT_EQ(cage.depth(p), 1);
        const double v = maskIoU(fill(cage.polygon(p), size), target);
        std::cout << "[ propose  ] separate object IoU " << v << std::endl;
        EXPECT_GE(v, 0.9);
    }
}

TEST(Propose, ObjectTouchingTheBorderIsEnclosedAlongTheEdge) {
    const cv::Size size(240, 200);
    cv::Mat shape(size, CV_8U, cv::Scalar(0));
    cv::ellipse(shape, cv::Point(0, 100), cv::Size(90, 60), 0, 0, 360, cv::Scalar(255), cv::FILLED);
    cv::rectangle(shape, cv::Rect(150, 150, 60, 50), cv::Scalar(255),
                  cv::FILLED);  // on the bottom edge
    ProposeParams params;
    params.method = PROPOSE_MASK;
    params.margin = 6;
    const Multicage cage = proposeMulticage(shape, params);
    std::string why;
    ASSERT_TRUE(cage.validate(&why)) << why;
    ASSERT_EQ(cage.polygonCount(), 2);
    const cv::Mat inside = fillAll(cage);
    // Every object pixel, those on the image edge included, is inside.
    EXPECT_EQ(cv::countNonZero(shape & ~inside), 0);
    const double v = maskIoU(inside, dilated(shape, 6));
    std::cout << "[ propose  ] border object IoU " << v << std::endl;
    EXPECT_GE(v, 0.9);
}

TEST(Propose, TouchingLabelsGetSeparatePolygonsAndNestedLabelsNest) {
    cv::Mat labels(200, 300, CV_32S, cv::Scalar(0));
    labels(cv::Rect(30, 40, 100, 120)).setTo(1);
    labels(cv::Rect(130, 40, 100, 120)).setTo(2);  // touches label 1
    labels(cv::Rect(160, 80, 40, 40)).setTo(3);    // inside label 2
    ProposeParams params;
    params.method = PROPOSE_LABELS;
    params.margin = 5;
    const Multicage cage = proposeMulticage(labels, params);
    std::string why;
    ASSERT_TRUE(cage.validate(&why)) << why;
    ASSERT_EQ(cage.polygonCount(), 3);
    const int p1 = polygonAt(cage, {60, 100}), p2 = polygonAt(cage, {215, 60}),
              p3 = polygonAt(cage, {180, 100});
    EXPECT_EQ(cage.depth(p1), 1);
    EXPECT_EQ(cage.depth(p2), 1);
    EXPECT_EQ(cage.depth(p3), 2);
    EXPECT_NE(p1, p2);
}

TEST(Propose, BudgetsHoldOnComplexShapes) {
    // A comb: many teeth want many vertices.
    cv::Mat comb(200, 300, CV_8U, cv::Scalar(0));
    comb(cv::Rect(20, 20, 260, 30)).setTo(255);
    for (int x = 20; x < 280; x += 20) comb(cv::Rect(x, 50, 8, 120)).setTo(255);
    for (int budget : {4, 8, 12, 20, 40}) {
        ProposeParams params;
        params.method = PROPOSE_MASK;
        params.margin = 3;
        params.maxVertices = budget;
        params.maxPolygonVertices = budget;
        const Multicage cage = proposeMulticage(comb, params);
        ASSERT_TRUE(cage.validate());
        ASSERT_EQ(cage.polygonCount(), 1);
        EXPECT_LE(cage.vertexCount(), budget);
    }
}

// A polygon short of vertices follows the shape grown by the margin, as far inside it as
// outside, instead of running around it (Douglas-Peucker alone: IoU 0.71 here), and still
// keeps half the margin from the shape.
TEST(Propose, APolygonShortOfVerticesFollowsTheMarginNotOutsideIt) {
    const cv::Size size(260, 260);
    std::vector<cv::Point> star;
    for (int i = 0; i < 14; ++i) {
        const double a = CV_PI * i / 7, r = i % 2 == 0 ? 110 : 45;
        star.emplace_back(cvRound(130 + r * std::cos(a)), cvRound(130 + r * std::sin(a)));
    }
    cv::Mat shape(size, CV_8U, cv::Scalar(0));
    cv::fillPoly(shape, std::vector<std::vector<cv::Point>>{star}, cv::Scalar(255));
    ProposeParams params;
    params.method = PROPOSE_MASK;
    params.margin = 6;
    params.maxVertices = params.maxPolygonVertices = 14;  // one a corner, no more
    const Multicage cage = proposeMulticage(shape, params);
    ASSERT_TRUE(cage.validate());
    ASSERT_EQ(cage.polygonCount(), 1);
    const cv::Mat inside = fill(cage.polygon(0), size);
    EXPECT_EQ(cv::countNonZero(shape & ~inside), 0);
    const double iou = maskIoU(inside, dilated(shape, 6));
    std::cout << "[ propose  ] IoU with the star grown by the margin: " << iou << std::endl;
    EXPECT_GE(iou, 0.85);
    cv::Mat distance;
    cv::distanceTransform(~shape, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE);
    const std::vector<cv::Point2f> p = cage.polygon(0);
    for (size_t i = 0; i < p.size(); ++i)
        for (int k = 0; k <= 100; ++k) {
            const cv::Point2f q = p[i] + (p[(i + 1) % p.size()] - p[i]) * (k / 100.f);
            EXPECT_GE(distance.at<float>(cvRound(q.y), cvRound(q.x)), 6 / 2 - 1.0)
                << "edge " << i << " at " << q;
        }
}

TEST(Propose, ConstantImageIsAnErrorAndEmptyMaskGivesNoPolygon) {
    EXPECT_THROW(proposeMulticage(cv::Mat(100, 120, CV_8UC3, cv::Scalar(40, 50, 60))),
                 cv::Exception);
    EXPECT_THROW(proposeMulticage(cv::Mat()), cv::Exception);
    ProposeParams params;
    params.method = PROPOSE_MASK;
    EXPECT_EQ(proposeMulticage(cv::Mat::zeros(100, 120, CV_8U), params).polygonCount(), 0);
    params.maxVertices = 2;
    EXPECT_THROW(proposeMulticage(cv::Mat::zeros(100, 120, CV_8U), params), cv::Exception);
}

TEST(Propose, EveryMethodGivesAValidCage) {
    const cv::Mat image = readSample("butterfly.jpg");
    for (int method : {PROPOSE_AUTO, PROPOSE_THRESHOLD, PROPOSE_ADAPTIVE, PROPOSE_GRABCUT,
                       PROPOSE_SALIENCY, PROPOSE_SPECTRAL_RESIDUAL}) {
        ProposeParams params;
        params.method = method;
        const Multicage cage = proposeMulticage(image, params);
        std::string why;
        EXPECT_TRUE(cage.validate(&why)) << proposeMethodName(method) << ": " << why;
        EXPECT_GE(cage.polygonCount(), 1) << proposeMethodName(method);
        EXPECT_LE(cage.vertexCount(), params.maxVertices);
        EXPECT_EQ(parseProposeMethod(proposeMethodName(method)), method);
    }
    ProposeParams params;
    params.method = PROPOSE_GRABCUT;
    params.rect = cv::Rect(10, 20, 470, 300);
    EXPECT_TRUE(proposeMulticage(image, params).validate());
}

// GrabCut from the frame inward needs a frame and an inside: a tiny image still gets a valid
// cage (or none), and one without an inside is refused with a clear error, not an assertion
// deep in cv::grabCut.
TEST(Propose, GrabCutFromTheFrameOnTinyImages) {
    ProposeParams params;
    params.method = PROPOSE_GRABCUT;
    cv::Mat tiny(9, 9, CV_8UC3, cv::Scalar(20, 20, 20));
    cv::rectangle(tiny, cv::Rect(3, 3, 3, 3), cv::Scalar(200, 220, 240), cv::FILLED);
    EXPECT_TRUE(proposeMulticage(tiny, params).validate());
    cv::Mat line(2, 40, CV_8UC3, cv::Scalar(20, 20, 20));
    line(cv::Rect(10, 0, 10, 2)).setTo(cv::Scalar(200, 220, 240));
    try {
        proposeMulticage(line, params);
        ADD_FAILURE() << "a 40x2 image went through GrabCut";
    } catch (const cv::Exception& e) {
        // Refused before any segmentation, whatever the method: a 40x2 sliver holds no cage.
        EXPECT_EQ(e.code, cv::Error::StsBadSize) << e.what();
        EXPECT_NE(std::string(e.what()).find("a 40x2 image is too thin to propose a cage in"),
                  std::string::npos)
            << e.what();
    }
}

// Item 4: the sample photographs, default parameters.
TEST(Propose, SamplePhotosGiveValidCagesWithinTheDefaultBudget) {
    for (const char* name : {"butterfly.jpg", "fruits.jpg", "messi5.jpg", "HappyFish.jpg",
                             "building.jpg", "smarties.png"}) {
        const Multicage cage = proposeMulticage(readSample(name));
        std::string why;
        EXPECT_TRUE(cage.validate(&why)) << name << ": " << why;
        EXPECT_GE(cage.polygonCount(), 1) << name;
        EXPECT_LE(cage.vertexCount(), 80) << name;
    }
    // "Follows the object": the butterfly's body and wings are in, the leaves around are out.
    const Multicage butterfly = proposeMulticage(readSample("butterfly.jpg"));
    for (cv::Point2f in : {cv::Point2f(235, 180), cv::Point2f(80, 200), cv::Point2f(420, 190),
                           cv::Point2f(300, 250)})
        EXPECT_GE(polygonAt(butterfly, in), 0) << "butterfly point " << in << " is outside";
    for (cv::Point2f out :
         {cv::Point2f(40, 40), cv::Point2f(60, 330), cv::Point2f(450, 335), cv::Point2f(246, 25)})
        EXPECT_LT(polygonAt(butterfly, out), 0) << "background point " << out << " is inside";
}

// Item 5: protective polygons make the features inside a moved polygon nearly rigid.
TEST(Propose, ProtectedFeaturesDistortFiveTimesLess) {
    const cv::Size size(320, 240);
    cv::Mat image(size, CV_8UC3);
    cv::RNG rng(3);
    cv::randu(image, cv::Scalar::all(150), cv::Scalar::all(190));  // textured background
    cv::GaussianBlur(image, image, cv::Size(5, 5), 0);
    cv::Mat feature(size, CV_8U, cv::Scalar(0));
    cv::ellipse(feature, cv::Point(175, 115), cv::Size(34, 24), 20, 0, 360, cv::Scalar(255),
                cv::FILLED);
    image.setTo(cv::Scalar(40, 30, 160), feature);
    cv::line(image, cv::Point(150, 105), cv::Point(200, 125), cv::Scalar(240, 240, 240), 3);
    Multicage cage(size);
    cage.addPolygon(std::vector<cv::Point2f>{
        {40, 30}, {280, 25}, {295, 120}, {270, 215}, {50, 210}, {25, 120}});
    cage.orient();
    ProposeParams params;
    params.method = PROPOSE_THRESHOLD;
    params.margin = 8;
    const Multicage protectedCage = protectFeatures(image, cage, 0, params);
    std::string why;
    ASSERT_TRUE(protectedCage.validate(&why)) << why;
    ASSERT_EQ(protectedCage.polygonCount(), 2);
    EXPECT_EQ(protectedCage.depth(1), 2);
    EXPECT_EQ(cv::countNonZero(feature & ~fill(protectedCage.polygon(1), size)), 0)
        << "the feature is enclosed";

    // The user stretches the outer polygon (not a similarity); the inner one stays at rest.
    const int step = 2;
    auto residual = [&](const Multicage& c) {
        const Binding binding = bind(c, MEAN_VALUE, step);
        const std::vector<cv::Point2f> pose =
            multicage_fixtures::stretchPolygon(c, 0, 1.35f, 0.8f, {10, -5});
        cv::Mat moved;
        binding.apply(pose, moved);
        std::vector<cv::Point2f> rest, after;
        for (int gy = 0; gy < binding.gridSize.height; ++gy)
            for (int gx = 0; gx < binding.gridSize.width; ++gx) {
                const cv::Point2f p = binding.node(gx, gy);
                if (!feature.at<uchar>(cvRound(p.y), cvRound(p.x))) continue;
                rest.push_back(p);
                after.push_back(moved.at<cv::Point2f>(gy, gx));
            }
        EXPECT_GT(rest.size(), 100u);
        return multicage_testing::similarityResidual(rest, after);
    };
    const double without = residual(cage), with = residual(protectedCage);
    std::cout << "[ propose  ] feature residual without protection " << without << " px, with "
              << with << " px, ratio " << without / with << std::endl;
    EXPECT_GE(without, 5 * with);
}

// HappyFish.jpg: the fish's eye is more textured than the fish (the texture rule keeps it).
// Issue 21 changed this from butterfly.jpg: its salient blobs are whole wings, no more
// textured than the butterfly itself, and the texture rule now leaves them out
// (ProposeFeatures.ARegionNoMoreTexturedThanItsObjectGetsNoPolygon).
TEST(Propose, ProtectFeaturesOnAPhotoAddsValidInnerPolygons) {
    const cv::Mat image = readSample("HappyFish.jpg");
    const Multicage cage = proposeMulticage(image);
    ASSERT_GE(cage.polygonCount(), 1);
    const Multicage out = protectFeatures(image, cage, 0);
    std::string why;
    ASSERT_TRUE(out.validate(&why)) << why;
    EXPECT_GT(out.polygonCount(), cage.polygonCount());
    EXPECT_LE(out.vertexCount(), ProposeParams().maxVertices);
    for (int p = cage.polygonCount(); p < out.polygonCount(); ++p) EXPECT_EQ(out.depth(p), 2);
    for (int p = 0; p < cage.polygonCount(); ++p) EXPECT_EQ(out.polygon(p), cage.polygon(p));
}

// ---- Issue 16: faces. Photos: messi5.jpg (samples), astronaut.png, camera.png and coins.png
// (scikit-image's data, Debian package python3-skimage; public domain / CC0 / no known copyright
// restrictions), in tests/propose/data (its README.md).
namespace {
cv::Mat readFacePhoto(const std::string& name) {
    if (name == "messi5.jpg") return readSample(name);
    const cv::Mat m =
        cv::imread(std::string(MULTICAGE_FACE_DATA_DIR) + "/" + name, cv::IMREAD_COLOR);
    EXPECT_FALSE(m.empty()) << name;
    return m;
}
const char* const kFacePhotos[] = {"messi5.jpg", "astronaut.png", "camera.png"};

using propose_bench::haveCascades;

ProposeParams facesParams(int detector = PROTECT_ALL) {
    ProposeParams p;
    p.protect = detector;
    return p;
}

bool rectInside(const cv::Rect& r, const std::vector<cv::Point2f>& polygon) {
    for (cv::Point2f c : {cv::Point2f(r.x, r.y), cv::Point2f(r.br().x - 1, r.y),
                          cv::Point2f(r.br().x - 1, r.br().y - 1), cv::Point2f(r.x, r.br().y - 1)})
        if (cv::pointPolygonTest(polygon, c, false) <= 0) return false;
    return true;
}
}  // namespace

TEST(ProposeFaces, FrontalCascadeFindsMessisFace) {
    if (!haveCascades()) GTEST_SKIP() << "opencv-data is not installed";
    const cv::Mat image = readSample("messi5.jpg");
    const auto t0 = std::chrono::steady_clock::now();
    const std::vector<cv::Rect> faces = detectFaces(image);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    ASSERT_FALSE(faces.empty());
    for (const cv::Rect& f : faces) std::cout << "[ faces    ] messi5.jpg face " << f << "\n";
    std::cout << "[ faces    ] detectFaces(messi5.jpg) " << ms
              << " ms (first call: loads the cascades)\n";
    bool near = false;
    for (const cv::Rect& f : faces)
        near |= cv::norm(cv::Point2f(f.x, f.y) - cv::Point2f(227, 94)) < 25 ||
                f.contains(cv::Point(227 + 10, 94 + 10));
    EXPECT_TRUE(near);
}

// A photo without colour has no skin to refuse what the frontal cascade finds on a pattern: a
// coin's portrait (3-4 windows, no eye) was taken for a face, and the person prior then caged
// that one coin and nothing else. There a frontal face needs 5 windows that agree or an eye;
// the faces of grey copies of people photos, and the camera man's profile, still stand.
TEST(ProposeFaces, AFrontalFaceInAGreyPhotoNeedsAgreeingWindowsOrAnEye) {
    if (!haveCascades()) GTEST_SKIP() << "opencv-data is not installed";
    const cv::Mat coins = readFacePhoto("coins.png");
    EXPECT_TRUE(detectFaces(coins).empty());
    const Multicage cage = proposeProtectedMulticage(coins);
    int outlines = 0;
    for (int p = 0; p < cage.polygonCount(); ++p) outlines += cage.depth(p) == 1;
    std::cout << "[ faces    ] coins.png: " << outlines << " outlines\n";
    EXPECT_GE(outlines, 5);  // the coins (neighbours may share one), not one of them
    for (const char* name : kFacePhotos) {
        SCOPED_TRACE(name);
        cv::Mat grey;
        cv::cvtColor(readFacePhoto(name), grey, cv::COLOR_BGR2GRAY);
        cv::cvtColor(grey, grey, cv::COLOR_GRAY2BGR);  // grey in three channels, as files often are
        const std::vector<cv::Rect> inColour = detectFaces(readFacePhoto(name)),
                                    inGrey = detectFaces(grey);
        ASSERT_FALSE(inColour.empty());
        ASSERT_FALSE(inGrey.empty());
        EXPECT_GT((inGrey[0] & inColour[0]).area(), 0.5 * inColour[0].area());
    }
}

// The profile search finds the camera man's face in the benchmark's copy (camera.jpg) twice: a
// box on his face (4 windows) and one 1.9 times as wide around his head and camera (3 windows).
// Merged, the face was the larger box, 3.2 times the face the reference boxes: the face is the
// smaller box, the surer one. The outline then followed him closer (outline IoU 0.753 -> 0.808).
TEST(ProposeFaces, ABoxAroundAHeadAndWhatItHoldsGivesWayToTheFaceInIt) {
    if (!haveCascades()) GTEST_SKIP() << "opencv-data is not installed";
    const std::vector<cv::Rect> reference = propose_bench::referenceBoxes("camera", "faces");
    ASSERT_EQ(reference.size(), 1u);
    const std::vector<cv::Rect> faces = detectFaces(propose_bench::benchPhoto("camera"));
    ASSERT_EQ(faces.size(), 1u);
    std::cout << "[ faces    ] camera.jpg face " << faces[0] << ", reference " << reference[0]
              << "\n";
    EXPECT_LE(faces[0].area(), 1.5 * reference[0].area());
    EXPECT_GE((faces[0] & reference[0]).area(), 0.6 * faces[0].area());
}

// A full figure's face is under the working copy's least face: the basketball player's, 29 px
// wide in a 640 px photo, is 14 px at 320. The copy twice as large finds it, at any size of the
// photo, and the proposal hugs it with a polygon of its own.
TEST(ProposeFaces, AFullFiguresSmallFaceIsFoundOnTheLargerCopy) {
    if (!haveCascades()) GTEST_SKIP() << "opencv-data is not installed";
    const std::vector<cv::Rect> reference = propose_bench::referenceBoxes("basketball", "faces");
    ASSERT_EQ(reference.size(), 1u);
    const cv::Mat photo = propose_bench::benchPhoto("basketball");
    std::vector<cv::Rect> faces;
    const Multicage cage = proposeProtectedMulticage(photo, facesParams(), &faces);
    ASSERT_EQ(faces.size(), 1u);
    std::cout << "[ faces    ] basketball.jpg face " << faces[0] << ", reference " << reference[0]
              << "\n";
    EXPECT_GE((faces[0] & reference[0]).area(), 0.5 * reference[0].area());
    EXPECT_LE(faces[0].area(), 3 * reference[0].area());
    int holders = 0;
    for (int p = 0; p < cage.polygonCount(); ++p)
        holders += cage.depth(p) == 2 && rectInside(faces[0], cage.polygon(p));
    EXPECT_EQ(holders, 1);
    // What is found does not depend on the photo's size: at 0.8 the face is 23 px, under the
    // working copy's least face even without shrinking; the larger copy is then enlarged.
    cv::Mat smaller;
    cv::resize(photo, smaller, cv::Size(), 0.8, 0.8, cv::INTER_AREA);
    const std::vector<cv::Rect> found = detectFaces(smaller);
    const cv::Rect scaled(cvRound(0.8 * reference[0].x), cvRound(0.8 * reference[0].y),
                          cvRound(0.8 * reference[0].width), cvRound(0.8 * reference[0].height));
    ASSERT_EQ(found.size(), 1u);
    EXPECT_GE((found[0] & scaled).area(), 0.5 * scaled.area());
}

TEST(ProposeFaces, EveryDetectedFaceIsInsideExactlyOneInnerPolygon) {
    if (!haveCascades()) GTEST_SKIP() << "opencv-data is not installed";
    for (const char* name : kFacePhotos) {
        SCOPED_TRACE(name);
        const cv::Mat image = readFacePhoto(name);
        std::vector<cv::Rect> faces;
        const Multicage cage = proposeProtectedMulticage(image, facesParams(), &faces);
        std::string why;
        ASSERT_TRUE(cage.validate(&why)) << why;
        EXPECT_LE(cage.vertexCount(), ProposeParams().maxVertices);
        ASSERT_FALSE(faces.empty()) << "no face found";
        for (const cv::Rect& f : faces) {
            int inner = 0, outer = 0;
            for (int p = 0; p < cage.polygonCount(); ++p) {
                if (!rectInside(f, cage.polygon(p))) continue;
                (cage.depth(p) >= 2 ? inner : outer) += 1;
            }
            std::cout << "[ faces    ] " << name << " face " << f << ": in " << inner
                      << " inner polygon(s), " << outer << " outline(s); cage "
                      << cage.polygonCount() << " polygons " << cage.vertexCount() << " vertices\n";
            EXPECT_EQ(inner, 1) << f;
            EXPECT_EQ(outer, 1) << f;
        }
    }
}

TEST(ProposeFaces, StretchingTheOutlineLeavesEachFaceASimilarity) {
    if (!haveCascades()) GTEST_SKIP() << "opencv-data is not installed";
    for (const char* name : kFacePhotos) {
        SCOPED_TRACE(name);
        const cv::Mat image = readFacePhoto(name);
        std::vector<cv::Rect> faces;
        const Multicage cage = proposeProtectedMulticage(image, facesParams(), &faces);
        ASSERT_FALSE(faces.empty());
        ASSERT_EQ(cage.coordinates(), LOCAL_MEAN_VALUE);
        // The same outlines without their inner polygons: the cage without protection.
        Multicage outlines(cage.imageSize());
        for (int p = 0; p < cage.polygonCount(); ++p)
            if (cage.depth(p) == 1) outlines.addPolygon(cage.polygon(p));
        outlines.orient();
        // The proposal asks for local mean value coordinates (its faces' polygons hold the
        // eyes); a cage bound with the paper's mean value coordinates is protected for them
        // by protectFeatures (its faces' polygons hold the four anchors).
        Multicage forMeanValue = outlines;
        for (int p = 0; p < outlines.polygonCount(); ++p)
            forMeanValue = protectFeatures(image, forMeanValue, p, facesParams());
        for (const cv::Rect& f : faces) {
            int outline = -1;
            for (int p = 0; p < outlines.polygonCount(); ++p)
                if (rectInside(f, outlines.polygon(p))) outline = p;
            ASSERT_GE(outline, 0);
            // The outline's index is the same in both cages (outlines come first).
            ASSERT_EQ(cage.polygon(outline), outlines.polygon(outline));
            auto residual = [&](const Multicage& c, int coordinates) {
                const int step = 2;
                const Binding binding = bind(c, coordinates, step);
                // Stretched 20% horizontally about its centroid: not a similarity.
                const std::vector<cv::Point2f> pose =
                    multicage_fixtures::stretchPolygon(c, outline, 1.2f, 1.0f);
                EXPECT_GT(multicage_testing::boxNodes(binding, f).size(), 50u);
                return multicage_testing::boxResidual(binding, pose, f);
            };
            const double mvcWithout = residual(outlines, MEAN_VALUE);
            const double mvcWith = residual(forMeanValue, MEAN_VALUE);
            const double harmWithout = residual(outlines, HARMONIC);
            const double harmWith = residual(cage, HARMONIC);
            const double localWith = residual(cage, COORDINATES_FROM_CAGE);
            std::cout << "[ faces    ] " << name << " face " << f
                      << " similarity residual, outline stretched 20%: mean value " << mvcWithout
                      << " px without protection, " << mvcWith << " px with; harmonic "
                      << harmWithout << " px without, " << harmWith
                      << " px with; the proposal's local mean value " << localWith << " px\n";
            // Mean value coordinates are global: the outline's motion leaks through the face's
            // polygon; a polygon hugging the face with room to the outline keeps the leak
            // about a pixel (measured 0.26-1.01 px with the subject model's outlines, which
            // leave the head less room than the classic ones did: 0.5-0.9 px). Harmonic
            // coordinates and the proposal's local mean value coordinates are local: exact.
            EXPECT_LE(mvcWith, 1.1);
            // Protection cuts the mean value leak 2.9-15 times on these photos (3-20 times with
            // the classic outlines' wider room).
            EXPECT_LE(2.5 * mvcWith, mvcWithout);
            EXPECT_LE(harmWith, 0.05);
            EXPECT_LE(localWith, 0.05);
        }
    }
}

namespace {
// The inner polygon around face f (the deepest one holding the whole box), or -1.
int deepestPolygonAround(const Multicage& cage, const cv::Rect& f) {
    int best = -1;
    for (int p = 0; p < cage.polygonCount(); ++p)
        if (cage.depth(p) >= 2 && rectInside(f, cage.polygon(p)) &&
            (best < 0 || cage.depth(p) > cage.depth(best)))
            best = p;
    return best;
}

// Least distance between two polygons' boundaries (vertex to edge, both ways).
double boundaryDistance(const std::vector<cv::Point2f>& a, const std::vector<cv::Point2f>& b) {
    double best = HUGE_VAL;
    for (int pass = 0; pass < 2; ++pass) {
        const auto& p = pass == 0 ? a : b;
        const auto& q = pass == 0 ? b : a;
        for (const cv::Point2f& v : p)
            for (size_t i = 0; i < q.size(); ++i) {
                const cv::Point2f e0 = q[i], e1 = q[(i + 1) % q.size()], d = e1 - e0;
                const float t =
                    std::max(0.f, std::min(1.f, (v - e0).dot(d) / std::max(1e-6f, d.dot(d))));
                best = std::min(best, static_cast<double>(cv::norm(v - (e0 + t * d))));
            }
    }
    return best;
}
}  // namespace

// Item 2: a face's polygon hugs the face (a rounded box a small margin around the detected box),
// holds nothing but the face's eyes (issue 21: the proposal's local coordinates need no
// anchors), and no salient polygon comes near it or goes around it.
TEST(ProposeFaces, FacePolygonHugsTheFaceHoldsOnlyItsEyesAndKeepsSalientPolygonsAway) {
    if (!haveCascades()) GTEST_SKIP() << "opencv-data is not installed";
    for (const char* name : kFacePhotos) {
        SCOPED_TRACE(name);
        const cv::Mat image = readFacePhoto(name);
        std::vector<cv::Rect> faces;
        const Multicage cage = proposeProtectedMulticage(image, facesParams(), &faces);
        ASSERT_TRUE(cage.validate());
        ASSERT_FALSE(faces.empty());
        for (const cv::Rect& f : faces) {
            const int face = deepestPolygonAround(cage, f);
            ASSERT_GE(face, 0);
            EXPECT_EQ(cage.depth(face), 2) << "only the outline is around the face's polygon";
            const double area = std::abs(cv::contourArea(cage.polygon(face)));
            std::cout << "[ faces    ] " << name << " face " << f << ": polygon " << area / f.area()
                      << " x the box's area\n";
            // The polygon takes in the forehead and the chin past the cascade's box (15% of its
            // height): 1.41-1.50 times the box's area on these three photos.
            EXPECT_LE(area, 1.6 * f.area()) << "the polygon hugs the face";
            int eyes = 0;
            for (int p = 0; p < cage.polygonCount(); ++p) {
                if (p == face) continue;
                const std::vector<cv::Point2f>& q = cage.polygon(p);
                if (cv::pointPolygonTest(cage.polygon(face), q[0], false) > 0) {
                    ++eyes;  // inside the face's polygon: an eye, in the box's upper 60%
                    EXPECT_EQ(cage.depth(p), 3);
                    for (const cv::Point2f& v : q)
                        EXPECT_TRUE(
                            cv::Rect(f.x, f.y, f.width, f.height * 6 / 10).contains(cv::Point(v)));
                } else if (cage.depth(p) == 2) {  // a salient polygon beside the face
                    EXPECT_GE(boundaryDistance(q, cage.polygon(face)), 0.25 * (f.width + f.height))
                        << p;
                }
            }
            EXPECT_TRUE(eyes == 0 || eyes == 2) << eyes;  // a pair or none
        }
    }
}

// Item 2: faces close together get polygons that never cross: either one each, or one around
// both (merged), and every face is inside exactly one.
TEST(ProposeFaces, CloseFacesNeverGetCrossingPolygons) {
    if (!haveCascades()) GTEST_SKIP() << "opencv-data is not installed";
    const cv::Mat astronaut = readFacePhoto("astronaut.png");
    const cv::Rect crop(150, 30, 150, 170);  // the face and hair
    cv::Mat image(320, 480, CV_8UC3, cv::Scalar(200, 200, 205));
    // The second face overlaps the first one's hair at -40 (their polygons' margins meet:
    // one polygon around both), is 40 px apart at 40 (one each).
    for (int gap : {-40, 0, 40}) {
        SCOPED_TRACE(gap);
        image.setTo(cv::Scalar(200, 200, 205));
        astronaut(crop).copyTo(image(cv::Rect(60, 70, crop.width, crop.height)));
        astronaut(crop).copyTo(
            image(cv::Rect(60 + crop.width + gap, 70 + gap / 2, crop.width, crop.height)));
        std::vector<cv::Rect> faces;
        const Multicage cage = proposeProtectedMulticage(image, facesParams(PROTECT_FACES), &faces);
        std::string why;
        ASSERT_TRUE(cage.validate(&why)) << why;
        const std::vector<cv::Rect> found = detectFaces(image);
        std::cout << "[ faces    ] two faces " << gap << " px apart: " << found.size()
                  << " detected, " << faces.size() << " protected\n";
        // detectFaces merges only detections of one face (sharing a quarter of the smaller
        // box): at -40 the two boxes share 4% and stay two faces (two heads for the person
        // prior); their polygons would overlap, so they share one.
        EXPECT_EQ(found.size(), 2u);
        if (found.size() == 2u) EXPECT_LT((found[0] & found[1]).area(), found[1].area() / 4);
        EXPECT_EQ(faces.size(), gap < 0 ? 1u : 2u) << "close faces share one polygon";
        for (const cv::Rect& f : found) {
            int inner = 0;
            for (int p = 0; p < cage.polygonCount(); ++p)
                inner += cage.depth(p) >= 2 && rectInside(f, cage.polygon(p));
            EXPECT_EQ(inner, 1) << f;
        }
    }
}

// protectFeatures on a user's cage: a face with room gets its polygon and anchors; a face
// its polygon cannot fit around (the user's polygon hugs the face) still gets a valid inner
// polygon, clipped to where one may go, and never one crossing the user's.
TEST(ProposeFaces, ProtectFeaturesFitsTheFaceInTheUsersPolygon) {
    if (!haveCascades()) GTEST_SKIP() << "opencv-data is not installed";
    const cv::Mat image = readFacePhoto("astronaut.png");
    const std::vector<cv::Rect> faces = detectFaces(image);
    ASSERT_EQ(faces.size(), 1u);
    const cv::Rect f = faces[0];
    for (int room : {80, 6}) {
        SCOPED_TRACE(room);
        const cv::Rect r =
            cv::Rect(f.x - room, f.y - room, f.width + 2 * room, f.height + 2 * room) &
            cv::Rect(2, 2, image.cols - 4, image.rows - 4);
        Multicage cage(image.size());
        cage.addPolygon(std::vector<cv::Point2f>{cv::Point2f(r.x, r.y), cv::Point2f(r.br().x, r.y),
                                                 cv::Point2f(r.br().x, r.br().y),
                                                 cv::Point2f(r.x, r.br().y)});
        cage.orient();
        const Multicage out = protectFeatures(image, cage, 0, facesParams(PROTECT_FACES));
        std::cout << "[ faces    ] user polygon " << room
                  << " px around the face: " << out.polygonCount() - 1 << " inner polygon(s)\n";
        std::string why;
        ASSERT_TRUE(out.validate(&why)) << why;
        EXPECT_EQ(out.polygon(0), cage.polygon(0));
        ASSERT_GE(out.polygonCount(), 2);
        for (int p = 1; p < out.polygonCount(); ++p) EXPECT_GE(out.depth(p), 2);
        if (room == 80) {
            EXPECT_EQ(out.polygonCount(), 1 + 1 + 4) << "the face's polygon and its anchors";
            EXPECT_TRUE(rectInside(f, out.polygon(1)));
        }
    }
}

TEST(ProposeFaces, MissingCascadeIsAnExceptionNamingThePackage) {
    ProposeParams params = facesParams(PROTECT_FACES);
    params.cascadeDir = "/nonexistent/cascades";
    EXPECT_TRUE(faceCascadeFile(params).empty());
    const cv::Mat image = readSample("messi5.jpg");
    try {
        detectFaces(image, params);
        ADD_FAILURE() << "no exception";
    } catch (const cv::Exception& e) {
        EXPECT_EQ(e.code, cv::Error::StsObjectNotFound);
        EXPECT_NE(e.err.find("opencv-data"), std::string::npos) << e.err;
    }
    EXPECT_THROW(proposeProtectedMulticage(image, params), cv::Exception);
    // `all` without cascades: salient features only, no error.
    params.protect = PROTECT_ALL;
    std::vector<cv::Rect> faces;
    const Multicage cage = proposeProtectedMulticage(image, params, &faces);
    EXPECT_TRUE(faces.empty());
    EXPECT_TRUE(cage.validate());
}

TEST(ProposeFaces, NoFaceFoundAddsNoFacePolygonAndIsNoError) {
    if (!haveCascades()) GTEST_SKIP() << "opencv-data is not installed";
    cv::Mat image(240, 320, CV_8UC3);
    cv::randu(image, cv::Scalar::all(0), cv::Scalar::all(255));
    cv::GaussianBlur(image, image, cv::Size(9, 9), 0);
    cv::circle(image, cv::Point(160, 120), 60, cv::Scalar(20, 200, 30), cv::FILLED);
    Multicage cage(image.size());
    cage.addPolygon(std::vector<cv::Point2f>{{20, 20}, {300, 20}, {300, 220}, {20, 220}});
    cage.orient();
    EXPECT_TRUE(detectFaces(image).empty());
    const Multicage out = protectFeatures(image, cage, 0, facesParams(PROTECT_FACES));
    EXPECT_EQ(out.polygonCount(), 1);
    EXPECT_TRUE(out.validate());
    EXPECT_EQ(protectFeatures(image, cage, 0, facesParams(PROTECT_ALL)).vertices(),
              protectFeatures(image, cage, 0, facesParams(PROTECT_SALIENCY)).vertices());
}

TEST(ProposeFaces, DetectorNames) {
    for (int d = PROTECT_SALIENCY; d <= PROTECT_ALL; ++d)
        EXPECT_EQ(parseProtectDetector(protectDetectorName(d)), d);
    EXPECT_EQ(parseProtectDetector("nose"), -1);
    ProposeParams bad;
    bad.protect = 7;
    EXPECT_THROW(proposeProtectedMulticage(readSample("messi5.jpg"), bad), cv::Exception);
}

#ifdef MULTICAGE_CLI_PATH
// Item 7: the command line writes a cage only when it has a valid one.
TEST(ProposeCli, WritesAValidCageAndRefusesBlankImages) {
    namespace fs = std::filesystem;
    const std::string dir = multicage_testing::tempDir("propose_cli");
    const std::string cli = MULTICAGE_CLI_PATH;
    auto run = [&](const std::string& args) {
        return std::system(
            (cli + " propose " + args + " > " + dir + "/out.txt 2> " + dir + "/err.txt").c_str());
    };
    auto stderrLines = [&] {
        std::ifstream f(dir + "/err.txt");
        std::string line;
        int n = 0;
        while (std::getline(f, line)) ++n;
        return n;
    };
    ASSERT_EQ(run(multicage_testing::samplePath("HappyFish.jpg") + " -o " + dir +
                  "/fish.yml --overlay " + dir + "/fish.png"),
              0);
    EXPECT_TRUE(Multicage::load(dir + "/fish.yml").validate());
    EXPECT_TRUE(fs::exists(dir + "/fish.png"));

    cv::imwrite(dir + "/blank.png", cv::Mat(60, 80, CV_8UC3, cv::Scalar(255, 255, 255)));
    EXPECT_NE(run(dir + "/blank.png -o " + dir + "/blank.yml"), 0);
    EXPECT_FALSE(fs::exists(dir + "/blank.yml"));
    EXPECT_EQ(stderrLines(), 1);

    cv::imwrite(dir + "/black.png", cv::Mat(60, 80, CV_8UC1, cv::Scalar(0)));
    EXPECT_NE(run(dir + "/black.png -o " + dir + "/black.yml --method mask"), 0);
    EXPECT_FALSE(fs::exists(dir + "/black.yml"));
    EXPECT_EQ(stderrLines(), 1);

    std::ofstream(dir + "/junk.png") << "not an image";
    EXPECT_NE(run(dir + "/junk.png -o " + dir + "/junk.yml"), 0);
    EXPECT_FALSE(fs::exists(dir + "/junk.yml"));
    EXPECT_EQ(stderrLines(), 1);
    fs::remove_all(dir);
}
#endif

#ifdef MULTICAGE_CLI_PATH
namespace {
using multicage_testing::CliRun;

// Runs `multicage ARGS` with stdout and stderr caught in files of `dir`.
CliRun runCli(const std::string& dir, const std::string& args) {
    return multicage_testing::runCli(MULTICAGE_CLI_PATH, dir, args);
}

int countOf(const std::string& text, const std::string& what) {
    int n = 0;
    for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
}

int lineCount(const std::string& text) {
    return static_cast<int>(std::count(text.begin(), text.end(), '\n'));
}
}  // namespace

// Issue 16, item 4: `multicage demo --faces` writes the demo's outputs for astronaut.jpg, and its
// pose stretches the body while the face only moves by a similarity.
TEST(ProposeCli, DemoFacesStretchesTheBodyAndTheFaceStaysAFace) {
    if (!haveCascades()) GTEST_SKIP() << "opencv-data is not installed";
    namespace fs = std::filesystem;
    const std::string dir = multicage_testing::tempDir("demo_faces");
    const CliRun r = runCli(dir, "demo --faces --backend cpu -o " + dir + "/out");
    ASSERT_EQ(r.status, 0) << r.err;
    for (const char* name : {"input.png", "overlay.png", "deformed.png", "deformed_overlay.png",
                             "side_by_side.png", "cage.yml"})
        EXPECT_TRUE(fs::exists(dir + "/out/" + name)) << name;
    EXPECT_EQ(countOf(r.out, "stays a face"), 1) << r.out;
    const cv::Mat input = cv::imread(dir + "/out/input.png", cv::IMREAD_COLOR);
    const cv::Mat deformed = cv::imread(dir + "/out/deformed.png", cv::IMREAD_COLOR);
    const Multicage cage = Multicage::load(dir + "/out/cage.yml");
    ASSERT_EQ(input.size(), cage.imageSize());
    ASSERT_EQ(deformed.size(), input.size());
    ASSERT_GE(cage.findPose("stretch"), 0);
    const std::vector<cv::Point2f> pose = cage.pose(cage.findPose("stretch")).vertices;
    const std::vector<cv::Rect> faces = detectFaces(input);
    ASSERT_FALSE(faces.empty());
    const cv::Rect f = faces[0];

    // The body stretched: outline vertices moved by up to 8% of the image width (a 20%
    // stretch of an outline about as wide as the image, about its centre).
    double most = 0;
    for (int p = 0; p < cage.polygonCount(); ++p)
        if (cage.depth(p) == 1)
            for (int i = 0; i < static_cast<int>(cage.polygon(p).size()); ++i)
                most = std::max(most, cv::norm(pose[cage.polygonOffset(p) + i] -
                                               cage.vertices()[cage.polygonOffset(p) + i]));
    EXPECT_GE(most, 0.06 * input.cols);

    // The face moved by a similarity (mesh nodes inside its box, the coordinates the demo
    // deforms with: the cage's own).
    const Binding binding = bind(cage, COORDINATES_FROM_CAGE, 2);
    cv::Mat moved;
    binding.apply(pose, moved);
    std::vector<cv::Point2f> rest, after;
    for (int gy = 0; gy < binding.gridSize.height; ++gy)
        for (int gx = 0; gx < binding.gridSize.width; ++gx) {
            const cv::Point2f p = binding.node(gx, gy);
            if (!f.contains(cv::Point(cvRound(p.x), cvRound(p.y)))) continue;
            rest.push_back(p);
            after.push_back(moved.at<cv::Point2f>(gy, gx));
        }
    ASSERT_GT(rest.size(), 50u);
    const double residual = multicage_testing::similarityResidual(rest, after);
    cv::Point2f shift(0, 0);
    for (size_t i = 0; i < rest.size(); ++i) shift += (after[i] - rest[i]) * (1.f / rest.size());
    std::cout << "[ faces    ] demo --faces: face " << f << " moved by " << shift << ", "
              << residual << " px from a similarity\n";
    EXPECT_LE(residual, 1.0);

    // In the pictures: the face in deformed.png is the input's face moved by `shift`, while
    // the body around it changed.
    // The input moved by the face's similarity (issue 21: with the outline 0.15 face sizes
    // from the face, not 2, the face moves by a fraction of a pixel and scales a little;
    // comparing with the input shifted by whole pixels compared pixels half a pixel apart).
    cv::Mat shifted;
    const cv::Mat move =
        cv::estimateAffinePartial2D(rest, after, cv::noArray(), cv::RANSAC, 1e9, 2000, 0.99, 50);
    ASSERT_FALSE(move.empty());
    cv::warpAffine(input, shifted, move, input.size(), cv::INTER_LINEAR, cv::BORDER_REPLICATE);
    const double faceDiff = cv::norm(shifted(f), deformed(f), cv::NORM_L1) / (3.0 * f.area());
    const cv::Rect body(f.x - f.width, f.br().y + f.height / 2, 3 * f.width, f.height);
    const double bodyDiff =
        cv::norm(input(body), deformed(body), cv::NORM_L1) / (3.0 * body.area());
    std::cout << "[ faces    ] demo --faces: mean |difference| on the face " << faceDiff
              << " (moved), on the body below it " << bodyDiff << "\n";
    // Issue 21 moved the outline to 0.3, then 0.15 face sizes from the face (it was 2): the face is
    // still within a pixel of a similarity (above), but that sub-pixel residual on a 50-pixel
    // face with sharp hair edges is 9 grey levels of mean difference (it was under 8); the
    // body changes over three times as much.
    EXPECT_GE(bodyDiff, 3 * faceDiff);
    fs::remove_all(dir);
}

// Issue 16, item 5: no cascade installed: --protect faces fails with one line naming the
// package and writes nothing; --protect all goes on with salient features and says why once.
TEST(ProposeCli, NoCascadeIsOneLineNamingThePackage) {
    namespace fs = std::filesystem;
    const std::string dir = multicage_testing::tempDir("propose_no_cascade");
    const std::string messi = multicage_testing::samplePath("messi5.jpg");
    CliRun r = runCli(dir, "propose " + messi + " -o " + dir + "/faces.yml --overlay " + dir +
                               "/faces.png --protect faces --cascade-dir " + dir + "/none");
    EXPECT_NE(r.status, 0);
    EXPECT_EQ(lineCount(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("opencv-data"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir + "/faces.yml"));
    EXPECT_FALSE(fs::exists(dir + "/faces.png"));

    r = runCli(dir, "propose " + messi + " -o " + dir + "/all.yml --protect all --cascade-dir " +
                        dir + "/none");
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(Multicage::load(dir + "/all.yml").validate());
    EXPECT_EQ(countOf(r.out + r.err, "opencv-data"), 1) << r.out << r.err;
    fs::remove_all(dir);
}

// Issue 16, item 5: a photo with no face: --protect all protects the salient features and says
// "no face found" once; --protect faces says so too and keeps the outlines.
TEST(ProposeCli, NoFaceFoundIsSaidOnce) {
    if (!haveCascades()) GTEST_SKIP() << "opencv-data is not installed";
    const std::string dir = multicage_testing::tempDir("propose_no_face");
    const std::string smarties = multicage_testing::samplePath("smarties.png");
    ASSERT_TRUE(detectFaces(readSample("smarties.png")).empty());
    for (const char* detector : {"all", "faces"}) {
        SCOPED_TRACE(detector);
        const std::string cage = dir + "/" + detector + ".yml";
        const CliRun r =
            runCli(dir, "propose " + smarties + " -o " + cage + " --protect " + detector);
        EXPECT_EQ(r.status, 0) << r.err;
        EXPECT_EQ(countOf(r.out + r.err, "no face found"), 1) << r.out << r.err;
        const Multicage m = Multicage::load(cage);
        EXPECT_TRUE(m.validate());
        EXPECT_GE(m.polygonCount(), 1);
    }
    std::filesystem::remove_all(dir);
}
#endif

// A float photo with a few infinite pixels (a division by zero upstream) was stretched by its
// infinite maximum to one grey: "the image is constant". The stretch now takes the finite values.
TEST(Propose, FloatPhotoWithInfinitePixelsIsStretchedByItsFiniteValues) {
    cv::Mat photo;
    readSample("butterfly.jpg").convertTo(photo, CV_32FC3, 1.0 / 255);
    const Multicage clean = proposeMulticage(photo);
    cv::RNG rng(9);
    for (int k = 0; k < 200; ++k) {  // one draw per statement: the same pixels from any compiler
        const int y = rng.uniform(0, photo.rows);
        const int x = rng.uniform(0, photo.cols);
        const int c = rng.uniform(0, 3);
        photo.at<cv::Vec3f>(y, x)[c] = k % 2 ? INFINITY : -INFINITY;
    }
    const Multicage spotted = proposeMulticage(photo);
    std::string why;
    ASSERT_TRUE(spotted.validate(&why)) << why;
    ASSERT_EQ(spotted.polygonCount(), clean.polygonCount());
    // The same butterfly: the outlines cover each other's area almost entirely.
    cv::Mat a = cv::Mat::zeros(photo.size(), CV_8U), b = a.clone();
    std::vector<std::vector<cv::Point>> pa, pb;
    for (int p = 0; p < clean.polygonCount(); ++p) {
        std::vector<cv::Point> q, r;
        for (const cv::Point2f& v : clean.polygon(p)) q.emplace_back(cvRound(v.x), cvRound(v.y));
        for (const cv::Point2f& v : spotted.polygon(p)) r.emplace_back(cvRound(v.x), cvRound(v.y));
        pa.push_back(q), pb.push_back(r);
    }
    cv::fillPoly(a, pa, 255), cv::fillPoly(b, pb, 255);
    const double iou = cv::countNonZero(a & b) / static_cast<double>(cv::countNonZero(a | b));
    EXPECT_GT(iou, 0.9) << iou;
}

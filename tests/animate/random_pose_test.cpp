// randomPose (issue 15, item 2): smooth random poses that keep the multicage valid and fold no
// triangle over, reproducible from a seed.
#include <cstdio>
#include <opencv2/multicage/augment.hpp>
#include <opencv2/multicage/propose.hpp>

#include "testing.hpp"

using namespace cv;
using namespace cv::multicage;

namespace {

/** The sample cages: samples/butterfly.yml, and the multicages proposed for the sample photos
(outlines with the inner polygons that protect features: nested, the harder case). */
std::vector<std::pair<std::string, Multicage>> sampleCages() {
    std::vector<std::pair<std::string, Multicage>> out;
    out.emplace_back("butterfly.yml",
                     Multicage::load(std::string(MULTICAGE_SAMPLE_CAGES) + "/butterfly.yml"));
    for (const char* photo : {"HappyFish.jpg", "fruits.jpg", "messi5.jpg"}) {
        const Mat image = multicage_testing::readSample(photo);
        out.emplace_back(photo,
                         proposeProtectedMulticage(image));  // what `multicage propose` writes
    }
    return out;
}

double largestMove(const std::vector<Point2f>& pose, const std::vector<Point2f>& rest) {
    double d = 0;
    for (size_t j = 0; j < pose.size(); ++j) d = std::max(d, double(norm(pose[j] - rest[j])));
    return d;
}

}  // namespace

// 1,000 draws per sample cage (amplitude 2.5 % of the longer image side: 12 px at 493x356),
// checked on a mesh at grid step 2 (what augment.py deforms with) and, for the first 100, at the
// paper's grid step 1: none invalid, none folded, each vertex within the amplitude, and the
// draws at a good fraction of it on average (not the rest pose).
// Local mean value coordinates (a cage that asks for them): 300 draws, checked on local meshes.
TEST(RandomPose, ThousandDrawsAreValidAndFoldFree) {
    for (auto [name, cage] : sampleCages())
        for (int coordinates : {MEAN_VALUE, LOCAL_MEAN_VALUE}) {
            cage.setCoordinates(coordinates);
            // A fifth of the rounds under a sanitizer (the same paths, 430 s there otherwise).
            const int draws =
                (coordinates == MEAN_VALUE ? 1000 : 300) / (multicage_testing::kSanitized ? 5 : 1);
            const int finestDraws = multicage_testing::kSanitized ? 20 : 100;
            const double amplitude =
                0.025 * std::max(cage.imageSize().width, cage.imageSize().height);
            ASSERT_TRUE(cage.validateGeometry()) << name;
            std::vector<Point2f> rest = cage.vertices();
            rest.resize(cage.vertexCount());
            const Binding fine = bind(cage, coordinates, 2), finest = bind(cage, coordinates, 1);
            const Mat fineNodes = fine.nodes(), finestNodes = finest.nodes();
            RNG rng(2024);
            int invalid = 0, folded = 0, restPoses = 0, outOfBound = 0;
            double sumMove = 0, drawMs = 0;
            Mat positions;
            for (int k = 0; k < draws; ++k) {
                const int64 start = getTickCount();
                const std::vector<Point2f> pose = randomPose(cage, amplitude, rng);
                drawMs += (getTickCount() - start) * 1000.0 / getTickFrequency();
                ASSERT_EQ(pose.size(), rest.size());
                std::string why;
                if (!validatePose(cage, pose, &why)) {
                    ++invalid;
                    ADD_FAILURE() << name << " draw " << k << ": " << why;
                }
                fine.apply(pose, positions);
                folded += countFoldedTriangles(positions, fineNodes) > 0;
                if (k < finestDraws) {
                    finest.apply(pose, positions);
                    folded += countFoldedTriangles(positions, finestNodes) > 0;
                }
                const double move = largestMove(pose, rest);
                outOfBound += move > amplitude + 1e-3;
                restPoses += move == 0;
                sumMove += move;
            }
            std::printf(
                "%s (%d polygons, %d vertices, %s coordinates): %d draws, %d invalid, %d folded, "
                "%d rest poses, largest vertex move %.2f px on average (amplitude %.1f), %.2f ms "
                "per draw\n",
                name.c_str(), cage.polygonCount(), cage.vertexCount(),
                coordinateTypeDescription(coordinates), draws, invalid, folded, restPoses,
                sumMove / draws, amplitude, drawMs / draws);
            EXPECT_EQ(invalid, 0) << name;
            EXPECT_EQ(folded, 0) << name << " " << coordinateTypeName(coordinates);
            EXPECT_EQ(outOfBound, 0) << name;
            EXPECT_LE(restPoses, draws / 100) << name;
            // 0.38-0.92 of the amplitude on these cages; the least is messi5's, whose proposal
            // (with the subject model) gives the ball its own polygon a thin gap from the foot,
            // and the gap bounds the draws of both.
            EXPECT_GT(sumMove / draws, 0.35 * amplitude) << name << ": the draws hardly move";
        }
}

TEST(RandomPose, TheSameSeedGivesTheSamePose) {
    const Multicage cage = multicage_testing::butterflyCage(true);
    RNG a(7), b(7), c(8);
    for (int k = 0; k < 20; ++k) {
        const std::vector<Point2f> pa = randomPose(cage, 10, a), pb = randomPose(cage, 10, b);
        EXPECT_EQ(pa, pb) << k;
        EXPECT_NE(pa, randomPose(cage, 10, c)) << k;
    }
}

TEST(RandomPose, KeepsVerticesAwayFromTheBorder) {
    const Multicage cage = multicage_testing::butterflyCage(true);
    const Size size = cage.imageSize();
    RNG rng(1);
    const double amplitude = 15;
    std::vector<Point2f> rest = cage.vertices();
    for (int k = 0; k < 200; ++k) {
        const std::vector<Point2f> pose = randomPose(cage, amplitude, rng);
        for (size_t j = 0; j < pose.size(); ++j) {
            const double restGap = std::min(std::min(rest[j].x, size.width - 1 - rest[j].x),
                                            std::min(rest[j].y, size.height - 1 - rest[j].y));
            const double gap = std::min(std::min(pose[j].x, size.width - 1 - pose[j].x),
                                        std::min(pose[j].y, size.height - 1 - pose[j].y));
            ASSERT_GE(gap, std::min(restGap, amplitude) - 1e-3)
                << "draw " << k << ", vertex " << j << " " << rest[j] << " -> " << pose[j];
        }
    }
}

// A binding at the Deformer's grid step checks fold-over on exactly the mesh that deforms.
TEST(RandomPose, ChecksFoldOverOnAGivenBinding) {
    const Multicage cage = multicage_testing::butterflyCage(true);
    const Binding binding = bind(cage, MEAN_VALUE, 1);
    RNG rng(5);
    Mat positions;
    for (int k = 0; k < 50; ++k) {
        const std::vector<Point2f> pose = randomPose(cage, binding, 20, rng);
        binding.apply(pose, positions);
        ASSERT_EQ(countFoldedTriangles(positions, binding.nodes()), 0);
        ASSERT_TRUE(validatePose(cage, pose));
    }
    EXPECT_THROW(randomPose(cage, bind(cage.scaled(Size(200, 150)), MEAN_VALUE, 4), 5, rng),
                 cv::Exception);
}

// Large amplitudes on a cage with a narrow gap are scaled down until valid, never invalid.
TEST(RandomPose, ScalesDownWhereTheAmplitudeCannotFit) {
    Multicage cage(Size(200, 200));
    cage.addPolygon(std::vector<Point2f>{{40, 40}, {160, 40}, {160, 160}, {40, 160}});
    cage.addPolygon(
        std::vector<Point2f>{{44, 44}, {156, 44}, {156, 156}, {44, 156}});  // a 4 px band
    cage.orient();
    RNG rng(9);
    std::vector<Point2f> rest = cage.vertices();
    rest.resize(cage.vertexCount());
    double sum = 0;
    for (int k = 0; k < 200; ++k) {
        const std::vector<Point2f> pose = randomPose(cage, 40, rng);
        std::string why;
        ASSERT_TRUE(validatePose(cage, pose, &why)) << why;
        sum += largestMove(pose, rest);
    }
    EXPECT_GT(sum / 200, 0.5);  // still moving
}

TEST(RandomPose, ValidatePoseSaysWhatIsWrong) {
    const Multicage cage = multicage_testing::butterflyCage(true);
    std::vector<Point2f> pose = cage.vertices();
    pose.resize(cage.vertexCount());
    EXPECT_TRUE(validatePose(cage, pose));
    std::vector<Point2f> crossing = pose;
    const int body = cage.polygonOffset(1);
    for (int j = body; j < cage.vertexCount(); ++j)
        crossing[j] += Point2f(-200, 0);  // into the wings' edge
    std::string why;
    EXPECT_FALSE(validatePose(cage, crossing, &why));
    EXPECT_NE(why.find("posed:"), std::string::npos) << why;
    std::vector<Point2f> out = pose;
    out[0] = Point2f(-5, 10);
    EXPECT_FALSE(validatePose(cage, out, &why));
    EXPECT_FALSE(validatePose(cage, std::vector<Point2f>(3), &why));
    EXPECT_NE(why.find("the pose has 3 vertices"), std::string::npos) << why;
}

TEST(RandomPose, BadInputThrows) {
    const Multicage cage = multicage_testing::butterflyCage(true);
    RNG rng;
    EXPECT_THROW(randomPose(cage, -1, rng), cv::Exception);
    EXPECT_THROW(randomPose(cage, NAN, rng), cv::Exception);
    Multicage bad(Size(100, 100));
    bad.addPolygon(std::vector<Point2f>{{10, 10}, {90, 90}, {90, 10}, {10, 90}});  // a bow tie
    try {
        randomPose(bad, 5, rng);
        FAIL();
    } catch (const cv::Exception& e) {
        EXPECT_NE(e.err.find("randomPose"), std::string::npos) << e.err;
    }
    std::vector<Point2f> rest = cage.vertices();
    rest.resize(cage.vertexCount());
    EXPECT_EQ(randomPose(cage, 0, rng), rest);
}

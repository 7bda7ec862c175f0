// randomPose replays by seed (issue 23, item 6): the draws must stay bit for bit what they
// were before the pose draw was made faster, since users keep seeds to replay augmentations.
// Each case draws a sequence from one seeded RNG and hashes every coordinate's bits and the
// RNG's final state; the expected hashes were recorded with the implementation before the
// speed-up (commit 9a64bd1) by GCC. CI runs this test in a clang build too (the sanitizers):
// the draws must not depend on the compiler either (they did once: two draws in one argument
// list came in each compiler's order of evaluating arguments).
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <opencv2/multicage/augment.hpp>

#include "testing.hpp"

using namespace cv;
using namespace cv::multicage;

namespace {

struct Fnv {
    uint64_t h = 1469598103934665603ull;
    void add(const void* data, size_t bytes) {
        const unsigned char* p = static_cast<const unsigned char*>(data);
        for (size_t i = 0; i < bytes; ++i) h = (h ^ p[i]) * 1099511628211ull;
    }
};

/** The hash of `draws` poses of cage from RNG(seed) (with binding when given), and the RNG's
final state (retries and scale-downs consume numbers: a change there shows too). */
uint64_t drawHash(const Multicage& cage, double amplitude, int draws, uint64_t seed,
                  const Binding* binding = nullptr) {
    RNG rng(seed);
    Fnv f;
    for (int k = 0; k < draws; ++k) {
        const std::vector<Point2f> pose =
            binding ? randomPose(cage, *binding, amplitude, rng) : randomPose(cage, amplitude, rng);
        f.add(pose.data(), pose.size() * sizeof(Point2f));
    }
    f.add(&rng.state, sizeof rng.state);
    return f.h;
}

Multicage withCoordinates(Multicage cage, int coordinates) {
    cage.setCoordinates(coordinates);
    return cage;
}

/** Two nested squares 4 px apart: large amplitudes need retries and scale-downs. */
Multicage narrowBand() {
    Multicage cage(Size(200, 200));
    cage.addPolygon(std::vector<Point2f>{{40, 40}, {160, 40}, {160, 160}, {40, 160}});
    cage.addPolygon(std::vector<Point2f>{{44, 44}, {156, 44}, {156, 156}, {44, 156}});
    cage.orient();
    return cage;
}

void expectHash(const char* what, uint64_t got, uint64_t expected) {
    std::printf("%s: 0x%016llx\n", what, static_cast<unsigned long long>(got));
    EXPECT_EQ(got, expected) << what << ": the draws differ from the recorded ones";
}

}  // namespace

TEST(RandomPoseReplay, MeanValueAndLocalCoordinatesDrawAsRecorded) {
    const Multicage butterfly = multicage_testing::butterflyCage(true);
    expectHash("butterfly, mean value", drawHash(butterfly, 12, 1000, 11), 0x6f2fb4c65e41522full);
    expectHash("butterfly, local",
               drawHash(withCoordinates(butterfly, LOCAL_MEAN_VALUE), 12, 300, 12),
               0xdbca498d515c5ae1ull);
    expectHash("butterfly, wings only",
               drawHash(multicage_testing::butterflyCage(false), 20, 300, 13),
               0x458f70405f4e56c6ull);
    // What proposeProtectedMulticage made of two sample photos (saved, so that changes to the
    // proposal do not change these draws): an outline with inner polygons, six at messi5.
    struct Recorded {
        const char* cage;
        uint64_t meanValue, local;
    };
    for (const Recorded& r :
         {Recorded{"replay_happyfish.yml", 0x902c4dfc8b02e12eull, 0xe9087847148b5060ull},
          Recorded{"replay_messi5.yml", 0x5770b40963bbee25ull, 0xf0ea53954fb6076eull}}) {
        const Multicage cage = Multicage::load(std::string(MULTICAGE_REPLAY_CAGES) + "/" + r.cage);
        const std::string name = r.cage;
        expectHash((name + ", mean value").c_str(),
                   drawHash(withCoordinates(cage, MEAN_VALUE), 12, 300, 14), r.meanValue);
        expectHash((name + ", local").c_str(),
                   drawHash(withCoordinates(cage, LOCAL_MEAN_VALUE), 12, 200, 15), r.local);
    }
}

TEST(RandomPoseReplay, RetriesScaleDownsAndGivenBindingsDrawAsRecorded) {
    const Multicage band = narrowBand();
    expectHash("narrow band, amplitude 40", drawHash(band, 40, 300, 16), 0x070a9fa0605c560dull);
    const Multicage butterfly = multicage_testing::butterflyCage(true);
    const Binding fine = bind(butterfly, MEAN_VALUE, 2);
    expectHash("butterfly, its grid-step-2 binding", drawHash(butterfly, 20, 200, 17, &fine),
               0xb4d7d0a958647c85ull);
    RandomPoseParams params;
    params.checkGridStep = 3, params.jitter = 0.5, params.attempts = 2;
    RNG rng(18);
    Fnv f;
    for (int k = 0; k < 200; ++k) {
        const std::vector<Point2f> pose = randomPose(butterfly, 25, rng, params);
        f.add(pose.data(), pose.size() * sizeof(Point2f));
    }
    f.add(&rng.state, sizeof rng.state);
    expectHash("butterfly, grid step 3, jitter 0.5, 2 attempts", f.h, 0xf3bc67bac1071600ull);
}

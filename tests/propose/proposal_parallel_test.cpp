// Issue 21, item 7: parts of a proposal run side by side (docs/propose/README.md, "Speed").
// What runs in parallel must not change what is proposed: the same photo gives the same cage
// every time, on one thread or several, and the caller's random generator is left as it was.
#include <opencv2/core/utility.hpp>

#include "faces.hpp"
#include "testing.hpp"
#include "work.hpp"

namespace {

using namespace cv::multicage;

// Restores OpenCV's thread count when a test ends, failed or not.
struct ThreadCount {
    int saved = cv::getNumThreads();
    ~ThreadCount() { cv::setNumThreads(saved); }
};

// Exact equality: the polygons, their order and every vertex bit for bit.
void expectSameCage(const Multicage& a, const Multicage& b, const std::string& what) {
    ASSERT_EQ(a.polygonCount(), b.polygonCount()) << what;
    for (int p = 0; p < a.polygonCount(); ++p) {
        ASSERT_EQ(a.polygon(p).size(), b.polygon(p).size()) << what << ", polygon " << p;
        for (size_t i = 0; i < a.polygon(p).size(); ++i) {
            EXPECT_EQ(a.polygon(p)[i].x, b.polygon(p)[i].x) << what << ", polygon " << p;
            EXPECT_EQ(a.polygon(p)[i].y, b.polygon(p)[i].y) << what << ", polygon " << p;
        }
    }
}

}  // namespace

// The baboon's salient part and frame-inward pass start from the same labels (one GrabCut
// serves both) and its frame is reopened; the orange's salient part runs beside the
// frame-inward passes and its reopened frame is refused; messi5 has a face (the person prior,
// the face search's three cascades side by side); the Megamind close-up's face is large
// enough for eyes (the two eye cascades side by side).
TEST(ProposeParallel, AProposalIsTheSameEveryTimeOnOneThreadOrMore) {
    ThreadCount restore;
    for (const char* name : {"baboon", "orange", "messi5", "megamind_closeup"}) {
        const cv::Mat image =
            multicage_testing::readSample(std::string("propose_bench/") + name + ".jpg");
        const Multicage first = proposeProtectedMulticage(image);
        ASSERT_GT(first.polygonCount(), 0) << name;
        expectSameCage(first, proposeProtectedMulticage(image), std::string(name) + " run twice");
        cv::setNumThreads(1);
        expectSameCage(first, proposeProtectedMulticage(image),
                       std::string(name) + " on one thread");
        cv::setNumThreads(restore.saved);
    }
}

// GrabCut seeds its colour models from cv::theRNG(); the proposal seeds its own and puts the
// caller's back, on whichever thread each GrabCut ran.
TEST(ProposeParallel, TheCallersRandomGeneratorIsLeftAsItWas) {
    const cv::Mat image = multicage_testing::readSample("propose_bench/orange.jpg");
    cv::theRNG() = cv::RNG(12345);
    proposeProtectedMulticage(image);
    EXPECT_EQ(cv::theRNG().state, cv::RNG(12345).state);
}

// Without a frontal face the profile searches run beside the face-blind segmentation or before
// it (propose.cpp): the faces a proposal finds are still detectFaces' own. The camera man's
// face is found in profile only (the segmentation it spares), the baboon's proposal runs the
// searches beside its one chain of GrabCuts, the orange's before its two, the astronaut's face
// is frontal.
TEST(ProposeParallel, TheFacesFoundAreDetectFacesOwnWhereverTheProfileSearchesRan) {
    using namespace cv::multicage::propose_detail;
    for (const char* name : {"camera", "baboon", "orange", "astronaut"}) {
        const cv::Mat image =
            multicage_testing::readSample(std::string("propose_bench/") + name + ".jpg");
        const ProposeParams params;
        const Work w = resolve(image.size(), params);
        const std::vector<cv::Rect> expected =
            mergeNearFaces(detectFaces(image, params), w.margin * w.scale);
        std::vector<cv::Rect> found;
        proposeProtectedMulticage(image, params, &found);
        EXPECT_EQ(found, expected) << name;
        if (std::string(name) == "camera" || std::string(name) == "astronaut")
            EXPECT_EQ(found.size(), 1u) << name;
    }
}

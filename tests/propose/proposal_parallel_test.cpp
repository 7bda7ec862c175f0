// Issue 21, item 7: parts of a proposal run side by side (docs/propose/README.md, "Speed").
// What runs in parallel must not change what is proposed: the same photo gives the same cage
// every time, on one thread or several, and the caller's random generator is left as it was.
#include <atomic>
#include <opencv2/core/utility.hpp>
#include <thread>

#include "faces.hpp"
#include "tasks.hpp"
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

// Without a frontal face the small faces' and the profile searches run beside the face-blind
// segmentation or before it (propose.cpp, tasks.hpp): the faces a proposal finds are still
// detectFaces' own, with the subject model and without. The camera man's face is found in
// profile only (the segmentation it spares), the basketball player's on the larger copy only;
// without the model the baboon's proposal queues the searches behind its one chain of GrabCuts,
// the orange's runs them before its two; the astronaut's face is frontal.
TEST(ProposeParallel, TheFacesFoundAreDetectFacesOwnWhereverTheSearchesRan) {
    using namespace cv::multicage::propose_detail;
    for (int segmenter : {SEGMENTER_AUTO, SEGMENTER_CLASSIC})
        for (const char* name : {"camera", "basketball", "baboon", "orange", "astronaut"}) {
            const cv::Mat image =
                multicage_testing::readSample(std::string("propose_bench/") + name + ".jpg");
            ProposeParams params;
            params.segmenter = segmenter;
            const Work w = resolve(image.size(), params);
            const std::vector<cv::Rect> expected =
                mergeNearFaces(detectFaces(image, params), w.margin * w.scale);
            std::vector<cv::Rect> found;
            proposeProtectedMulticage(image, params, &found);
            const std::string what = std::string(name) + ", " + segmenterName(segmenter);
            EXPECT_EQ(found, expected) << what;
            const bool person = std::string(name) == "camera" ||
                                std::string(name) == "basketball" ||
                                std::string(name) == "astronaut";
            EXPECT_EQ(found.size(), person ? 1u : 0u) << what;
        }
}

// The queue of tasks: each runs once, however many workers take them, and a task's exception
// reaches the caller; a single task runs on the caller's thread (its own parallel loops then
// use every core: inside another parallel loop OpenCV runs them serially).
TEST(ProposeParallel, EveryTaskRunsOnceOnOneThreadOrMore) {
    using namespace cv::multicage::propose_detail;
    ThreadCount restore;
    for (int threads : {1, 2}) {
        cv::setNumThreads(threads);
        std::vector<std::atomic<int>> runs(7);
        Tasks tasks;
        for (auto& r : runs) tasks.push_back([&r] { ++r; });
        runTasks(tasks);
        for (size_t i = 0; i < runs.size(); ++i)
            EXPECT_EQ(runs[i].load(), 1) << "task " << i << ", " << threads << " threads";
        tasks.push_back([] { CV_Error(cv::Error::StsError, "a task failed"); });
        EXPECT_THROW(runTasks(tasks), cv::Exception) << threads << " threads";
    }
    cv::setNumThreads(restore.saved);
    std::thread::id ranOn;
    runTasks({[&ranOn] { ranOn = std::this_thread::get_id(); }});  // one: on this thread
    EXPECT_EQ(ranOn, std::this_thread::get_id());
    runTasks({});  // nothing to run
    EXPECT_TRUE(Beside().run());
    EXPECT_FALSE((Beside{{}, [] { return false; }}.run()));
}

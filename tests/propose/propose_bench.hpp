// The proposal benchmark's photos and hand-made references (samples/data/propose_bench), for
// the tests that check proposals against them.
#ifndef MULTICAGE_TESTS_PROPOSE_BENCH_HPP
#define MULTICAGE_TESTS_PROPOSE_BENCH_HPP

#include "testing.hpp"

namespace propose_bench {

inline bool haveCascades() {
    return !cv::multicage::faceCascadeFile().empty();
}

inline cv::Mat benchPhoto(const std::string& name) {
    return multicage_testing::readSample("propose_bench/" + name + ".jpg");
}

/** A benchmark reference mask: 255 on the subject a person would cage. */
inline cv::Mat benchMask(const std::string& name) {
    const cv::Mat m =
        multicage_testing::readSample("propose_bench/" + name + "_mask.png", 0 /* GRAYSCALE */);
    EXPECT_FALSE(m.empty()) << name;
    return m > 127;
}

/** Intersection over union of two masks. */
inline double maskIoU(const cv::Mat& a, const cv::Mat& b) {
    const double inter = cv::countNonZero(a & b), uni = cv::countNonZero(a | b);
    return uni > 0 ? inter / uni : 0.0;
}

/** The union of a cage's outlines (depth-1 polygons), 255 inside. */
inline cv::Mat outlinesMask(const cv::multicage::Multicage& cage) {
    cv::Mat m = cv::Mat::zeros(cage.imageSize(), CV_8U);
    for (int p = 0; p < cage.polygonCount(); ++p)
        if (cage.depth(p) == 1)
            m |= multicage_fixtures::polygonMask(cage.polygon(p), cage.imageSize());
    return m;
}

/** Outline IoU of the default proposal of a benchmark photo against its reference mask. */
inline double outlineIoU(const std::string& name) {
    return maskIoU(outlinesMask(cv::multicage::proposeProtectedMulticage(benchPhoto(name))),
                   benchMask(name));
}

/** How many inner polygons (depth 2 or more) a cage has. */
inline int innerPolygons(const cv::multicage::Multicage& cage) {
    int n = 0;
    for (int p = 0; p < cage.polygonCount(); ++p) n += cage.depth(p) >= 2;
    return n;
}

/** The boxes under `key` ("faces", "eyes", "features") of a benchmark reference. */
inline std::vector<cv::Rect> referenceBoxes(const std::string& name, const char* key) {
    cv::FileStorage fs(multicage_testing::samplePath("propose_bench/" + name + ".ref.json"),
                       cv::FileStorage::READ);
    EXPECT_TRUE(fs.isOpened()) << name;
    std::vector<cv::Rect> out;
    for (const cv::FileNode& b : fs[key]) {
        std::vector<int> v;
        b >> v;
        if (v.size() == 4) out.emplace_back(v[0], v[1], v[2], v[3]);
    }
    return out;
}

}  // namespace propose_bench

#endif

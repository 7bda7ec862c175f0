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

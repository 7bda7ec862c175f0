// Shared by the GPU tests: skip (with the reason) only where no EGL context exists at all.
#ifndef MULTICAGE_GPU_TESTING_HPP
#define MULTICAGE_GPU_TESTING_HPP

#include <opencv2/multicage/gpu.hpp>

#include "testing.hpp"

#define MULTICAGE_REQUIRE_GPU()                                        \
    do {                                                               \
        std::string why_;                                              \
        if (!cv::multicage::gpuAvailable(&why_)) GTEST_SKIP() << why_; \
    } while (0)

namespace multicage_testing {

/** A GPU deformer (BACKEND_GPU) and the CPU one for the same binding. */
inline void gpuAndCpu(const cv::Mat& image, const cv::multicage::Binding& b,
                      cv::Ptr<cv::multicage::Deformer>* gpu, cv::Ptr<cv::multicage::Deformer>* cpu,
                      cv::multicage::DeformParams params = {}) {
    params.backend = cv::multicage::BACKEND_GPU;
    *gpu = cv::multicage::Deformer::create(image, b, params);
    params.backend = cv::multicage::BACKEND_CPU;
    *cpu = cv::multicage::Deformer::create(image, b, params);
    ASSERT_EQ((*gpu)->backend(), cv::multicage::BACKEND_GPU);
}

/** The butterfly photo, its nested cage, and a GPU Deformer (BACKEND_GPU) binding them. */
struct GpuButterfly {
    cv::Mat image;
    cv::multicage::Multicage cage;
    cv::multicage::DeformParams params;  // what made the deformer: make another alike
    cv::Ptr<cv::multicage::Deformer> deformer;
};
inline GpuButterfly gpuButterfly(int gridStep, const cv::Scalar& border = cv::Scalar()) {
    GpuButterfly b;
    b.image = readSample("butterfly.jpg");
    b.cage = butterflyCage(true);
    b.params.backend = cv::multicage::BACKEND_GPU;
    b.params.gridStep = gridStep;
    b.params.borderValue = border;
    b.deformer = cv::multicage::Deformer::create(b.image, b.cage, b.params);
    return b;
}

/** Largest absolute difference, as a double. */
inline double maxAbsDiff(const cv::Mat& a, const cv::Mat& b) {
    return cv::norm(a, b, cv::NORM_INF);
}

}  // namespace multicage_testing

#endif

#include "testing.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>

namespace multicage_testing {

std::string samplePath(const std::string& name) {
    return std::string(MULTICAGE_SAMPLES_DIR) + "/" + name;
}

cv::Mat readSample(const std::string& name, int flags) {
    cv::Mat img = cv::imread(samplePath(name), flags);
    EXPECT_FALSE(img.empty()) << "cannot read " << samplePath(name);
    return img;
}

double psnr(const cv::Mat& a, const cv::Mat& b) {
    const double range = a.depth() == CV_8U ? 255.0 : a.depth() == CV_16U ? 65535.0 : 1.0;
    return cv::PSNR(a, b, range);
}

bool sameBits(const cv::Mat& a, const cv::Mat& b) {
    if (a.size() != b.size() || a.type() != b.type()) return false;
    for (int y = 0; y < a.rows; ++y)
        if (std::memcmp(a.ptr(y), b.ptr(y), a.cols * a.elemSize()) != 0) return false;
    return true;
}

MapAgreement compareMaps(const cv::Mat& a, const cv::Mat& ref, float uncovered) {
    CV_Assert(a.size() == ref.size() && a.type() == CV_32F && ref.type() == CV_32F);
    MapAgreement out;
    for (int y = 0; y < ref.rows; ++y)
        for (int x = 0; x < ref.cols; ++x) {
            const float v = a.at<float>(y, x), r = ref.at<float>(y, x);
            if ((v == uncovered) != (r == uncovered)) {
                ++out.coverage;
                continue;
            }
            const double ulp = FLT_EPSILON * std::max(1.f, std::abs(r));
            out.roundings = std::max(out.roundings, std::abs(double(v) - r) / ulp);
        }
    return out;
}

std::string tempDir(const std::string& name) {
    namespace fs = std::filesystem;
    const fs::path dir =
        fs::temp_directory_path() / ("multicage_test_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir.string();
}

cv::multicage::Multicage butterflyCage(bool withBody) {
    // Traced on butterfly.jpg: the wings, then the body between them.
    const std::vector<cv::Point2f> wings = {
        {40, 40},   {140, 20},  {246, 70},  {350, 18},  {455, 38}, {470, 150}, {420, 200},
        {460, 300}, {360, 340}, {246, 290}, {130, 340}, {30, 300}, {75, 200},  {22, 150}};
    const std::vector<cv::Point2f> body = {{225, 95},  {268, 95},  {272, 180},
                                           {262, 270}, {230, 270}, {220, 180}};
    cv::multicage::Multicage cage(cv::Size(493, 356));
    cage.addPolygon(wings);
    if (withBody) cage.addPolygon(body);
    cage.orient();
    return cage;
}

std::string slurp(const std::string& path) {
    std::ifstream f(path);
    return std::string(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

CliRun runCli(const std::string& tool, const std::string& dir, const std::string& args) {
    const int status =
        std::system((tool + " " + args + " > " + dir + "/out.txt 2> " + dir + "/err.txt").c_str());
    return {status, slurp(dir + "/out.txt"), slurp(dir + "/err.txt")};
}

PartitionErrors partitionErrors(const cv::multicage::Binding& b) {
    const int c = b.coefficientCount(), N = b.nodeCount(), m = b.gridSize.width;
    std::vector<double> sum(N, 0.0), x(N, 0.0), y(N, 0.0);
    for (int j = 0; j < c; ++j) {
        const float* cc = b.coefficients.ptr<float>(j);
        const cv::Point2f v = b.restVertices[j];
        for (int k = 0; k < N; ++k)
            sum[k] += cc[k], x[k] += cc[k] * double(v.x), y[k] += cc[k] * double(v.y);
    }
    PartitionErrors e;
    for (int k = 0; k < N; ++k) {
        const cv::Point2f node = b.node(k % m, k / m);
        e.sum = std::max(e.sum, std::abs(sum[k] - 1.0));
        e.position = std::max(e.position, std::hypot(x[k] - node.x, y[k] - node.y));
    }
    return e;
}

}  // namespace multicage_testing

#include "cli_util.hpp"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace multicage_cli {

cv::Mat readImage(const std::string& path) {
    if (!std::filesystem::is_regular_file(path)) throw Failure(path + ": no such file");
    cv::Mat img;
    try {
        img = cv::multicage::readImage(path);  // refuses truncated JPEG and PNG files
    } catch (const cv::Exception& e) {
        throw Failure(e.err);
    }
    const int depth = img.depth(), cn = img.channels();
    if (cn == 2) cv::cvtColor(img, img, cv::COLOR_GRAY2BGR);  // gray+alpha is rare; keep going
    if (depth != CV_8U && depth != CV_16U && depth != CV_32F)
        throw Failure(path + ": unsupported pixel type " + cv::typeToString(img.type()) +
                      " (use 8-bit, 16-bit or 32-bit float images)");
    return img;
}

void checkImageOutput(const std::string& path) {
    const std::filesystem::path p(path);
    const std::filesystem::path dir = p.has_parent_path() ? p.parent_path() : ".";
    if (!std::filesystem::is_directory(dir)) throw Failure("cannot write " + path + ": no folder " + dir.string());
    if (!cv::haveImageWriter(path))
        throw Failure("cannot write " + path + ": unknown image extension '" + p.extension().string() +
                      "' (use .png, .jpg, .tif, .exr, ...)");
}

void writeImage(const std::string& command, const std::string& path, const cv::Mat& image) {
    std::string note;
    const cv::Mat stored = cv::multicage::convertForImageFormat(path, image, &note);
    cv::multicage::imwriteAtomic(path, stored);
    if (!note.empty()) std::cerr << "multicage " << command << ": note: " << note << std::endl;
}

cv::multicage::Multicage loadCage(const std::string& path, cv::Size imageSize) {
    cv::multicage::Multicage cage = cv::multicage::Multicage::load(path);
    if (cage.imageSize() != imageSize) cage = cage.scaled(imageSize);
    return cage;
}

int parseBackend(const std::string& name) {
    if (name == "auto") return cv::multicage::BACKEND_AUTO;
    if (name == "cpu") return cv::multicage::BACKEND_CPU;
    if (name == "gpu") return cv::multicage::BACKEND_GPU;
    throw Failure("unknown backend '" + name + "' (auto, cpu or gpu)");
}

int parseCoordinates(const std::string& name) {
    if (name == "mvc") return cv::multicage::MEAN_VALUE;
    if (name == "harmonic") return cv::multicage::HARMONIC;
    throw Failure("unknown coordinates '" + name + "' (mvc or harmonic)");
}

const char* backendName(int backend) {
    return backend == cv::multicage::BACKEND_GPU ? "gpu" : backend == cv::multicage::BACKEND_CPU ? "cpu" : "auto";
}

std::string plural(long long n, const std::string& one, const std::string& many) {
    return std::to_string(n) + " " + (n == 1 ? one : many.empty() ? one + "s" : many);
}

double msSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

double median(std::vector<double> samples) {
    if (samples.empty()) return 0.0;
    std::sort(samples.begin(), samples.end());
    const size_t n = samples.size();
    return n % 2 ? samples[n / 2] : 0.5 * (samples[n / 2 - 1] + samples[n / 2]);
}

}  // namespace multicage_cli

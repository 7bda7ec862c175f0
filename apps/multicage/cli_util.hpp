// What the multicage subcommands share: reading inputs, parsing choices, reporting.
#ifndef MULTICAGE_CLI_UTIL_HPP
#define MULTICAGE_CLI_UTIL_HPP

#include <CLI/CLI.hpp>
#include <opencv2/multicage.hpp>
#include <string>

namespace multicage_cli {

/** A user error: main() prints "multicage CMD: MESSAGE" on one line and exits 1. */
struct Failure : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/** Reads an image as stored (depth and alpha kept), or throws a Failure that says why (a
missing, undecodable or truncated file, an unsupported pixel type). */
cv::Mat readImage(const std::string& path);
/** Throws a Failure unless `path` can be written as an image: a known extension and an
existing folder. Called before any work, so a typo costs nothing. */
void checkImageOutput(const std::string& path);
/** Writes image to path atomically, converted to a depth the format stores (float to .jpg:
8 bits x255, ...); a conversion is said in one line on stderr, "multicage COMMAND: note: ...". */
void writeImage(const std::string& command, const std::string& path, const cv::Mat& image);
/** Loads a cage file and scales it to imageSize when it was made for another size. */
cv::multicage::Multicage loadCage(const std::string& path, cv::Size imageSize);

int parseBackend(const std::string& name);       // auto | cpu | gpu
int parseCoordinates(const std::string& name);   // mvc | harmonic
const char* backendName(int backend);

/** "1 polygon", "3 polygons" (many: the plural when it is not singular + "s"). */
std::string plural(long long n, const std::string& one, const std::string& many = "");
/** Milliseconds since `start` (std::chrono::steady_clock). */
double msSince(std::chrono::steady_clock::time_point start);
/** Median of samples (copied and sorted). */
double median(std::vector<double> samples);

void addDemoCommand(CLI::App& app);
void addDeformCommand(CLI::App& app);
void addProposeCommand(CLI::App& app);
void addBenchCommand(CLI::App& app);
void addAnimateCommand(CLI::App& app);

}  // namespace multicage_cli

#endif

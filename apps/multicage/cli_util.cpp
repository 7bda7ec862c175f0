#include "cli_util.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace multicage_cli {

std::string reasonOf(const cv::Exception& e) {
    std::string s = e.err;
    for (const char* prefix : {"multicage: ", "proposeMulticage: ", "proposeSegmentation: ",
                               "protectFeatures: ", "resize: "})
        if (s.rfind(prefix, 0) == 0) s = s.substr(std::string(prefix).size());
    return s;
}

void checkInputFile(const std::string& path) {
    std::error_code error;
    const std::filesystem::file_status status = std::filesystem::status(path, error);
    if (!std::filesystem::exists(status)) throw Failure(path + ": no such file");
    if (std::filesystem::is_directory(status)) throw Failure(path + ": is a folder, not a file");
}

cv::Mat readImage(const std::string& path) {
    checkInputFile(path);
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
    if (!std::filesystem::is_directory(dir))
        throw Failure("cannot write " + path + ": no folder " + dir.string());
    if (!cv::haveImageWriter(path))
        throw Failure("cannot write " + path + ": unknown image extension '" +
                      p.extension().string() + "' (use .png, .jpg, .tif, .exr, ...)");
}

void writeImage(const std::string& command, const std::string& path, const cv::Mat& image) {
    std::string note;
    const cv::Mat stored = cv::multicage::convertForImageFormat(path, image, &note);
    cv::multicage::imwriteAtomic(path, stored);
    if (!note.empty()) std::cerr << "multicage " << command << ": note: " << note << std::endl;
}

cv::multicage::Multicage loadCage(const std::string& path, cv::Size imageSize) {
    checkInputFile(path);
    cv::multicage::Multicage cage = cv::multicage::Multicage::load(path);
    if (!imageSize.empty() && cage.imageSize() != imageSize) cage = cage.scaled(imageSize);
    return cage;
}

void addAllowInvalidFlag(CLI::App* cmd, bool& allow, const std::string& verb) {
    cmd->add_flag("--allow-invalid", allow,
                  verb +
                      " poses whose polygons cross, leave the frame or change nesting (refused "
                      "otherwise; the image folds over itself there), with a warning saying where");
}

void checkPose(const std::string& command, const std::string& cagePath,
               const cv::multicage::Multicage& cage, int poseIndex, bool allowInvalid) {
    std::string why;
    const cv::multicage::Pose& pose = cage.pose(poseIndex);
    if (cv::multicage::validatePose(cage, pose.vertices, &why)) return;
    const std::string what = cagePath + ": pose '" + pose.name + "' is invalid: " + why;
    if (!allowInvalid)
        throw Failure(what + " (fix the pose, or add --allow-invalid to " +
                      (command == "pose" ? "write" : "deform") + " it anyway)");
    std::cerr << "multicage " << command << ": warning: " << what << std::endl;
}

size_t parseMemorySize(const std::string& text) {
    size_t used = 0;
    double value = -1;
    try {
        value = std::stod(text, &used);
    } catch (const std::exception&) {
    }
    std::string unit = text.substr(std::min(used, text.size()));
    for (char& ch : unit) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
    if (unit.size() > 1 && unit.back() == 'B') unit.pop_back();  // GB, GiB -> G, Gi
    if (unit.size() > 1 && unit.back() == 'I') unit.pop_back();
    const std::string units = "KMGT";
    const size_t power = unit.empty() ? 0 : units.find(unit) + 1;
    if (value < 0 || used == 0 || unit.size() > 1 || (!unit.empty() && power == 0))
        throw UsageError("--memory-budget: '" + text +
                         "' is not a size (e.g. 2G, 512M, or 0 for no limit)");
    return static_cast<size_t>(value * std::pow(1024.0, double(power)));
}

std::string formatBytes(size_t bytes) {
    const double mib = bytes / (1024.0 * 1024.0);
    return mib >= 1024 ? cv::format("%.1f GiB", mib / 1024) : cv::format("%.0f MiB", mib);
}

int chooseGridStep(const std::string& command, cv::Size imageSize, int vertexCount, int step,
                   bool typed, size_t budget, std::string* change) {
    using namespace cv::multicage;
    change->clear();
    const int c = vertexCount + 4;
    const size_t need = bindingMemory(imageSize, c, step);
    if (budget == 0 || need <= budget) return step;
    const int fits = gridStepForBudget(imageSize, c, budget, step);
    *change = "raised from " + std::to_string(step) + " to fit the " + formatBytes(budget) +
              " memory budget";
    if (typed)
        std::cerr << "multicage " << command << ": grid step " << step << " would need "
                  << formatBytes(need) << " of memory for this " << imageSize.width << "x"
                  << imageSize.height << " image with " << plural(vertexCount, "vertex", "vertices")
                  << ", more than the " << formatBytes(budget) << " budget; using grid step "
                  << fits << " (" << formatBytes(bindingMemory(imageSize, c, fits))
                  << ") instead. To keep grid step " << step << ", add --memory-budget "
                  << (need + (size_t(1) << 30) - 1) / (size_t(1) << 30) << "G" << std::endl;
    return fits;
}

void probeAutoBackend(int backend) {
    if (backend == cv::multicage::BACKEND_AUTO) cv::multicage::autoBackendUsesGpu();
}

namespace {
std::atomic<bool> sigintSeen{false};
extern "C" void onInterrupt(int) {
    sigintSeen = true;
}
}  // namespace

InterruptGuard::InterruptGuard() {
    sigintSeen = false;
    previous_ = std::signal(SIGINT, onInterrupt);
}

InterruptGuard::~InterruptGuard() {
    std::signal(SIGINT, previous_ == SIG_ERR ? SIG_DFL : previous_);
}

bool InterruptGuard::interrupted() {
    return sigintSeen;
}

FrameProgress::FrameProgress(const std::string& command, bool quiet)
    : command_(command), quiet_(quiet), tty_(::isatty(STDERR_FILENO) != 0) {}

void FrameProgress::operator()(int done, int total) {
    if (quiet_) return;
    const bool last = total > 0 && done >= total;
    if (tty_) {
        const double s = msSince(start_) / 1000, fps = s > 0 ? done / s : 0.0;
        if (total > 0) {
            const int width = 30, filled = width * std::min(done, total) / total;
            const double left = fps > 0 ? (total - done) / fps : 0.0;
            std::fprintf(stderr, "\r[%s%s] %3d%% %d/%d frames, %.1f fps, %d:%02d left ",
                         std::string(filled, '#').c_str(), std::string(width - filled, '.').c_str(),
                         100 * done / total, done, total, fps, int(left) / 60, int(left) % 60);
        } else {
            std::fprintf(stderr, "\r%d frames, %.1f fps ", done, fps);
        }
        if (last) std::fputc('\n', stderr);
    } else if (last) {
        std::fprintf(stderr, "multicage %s: 100%% (%d/%d frames)\n", command_.c_str(), done, total);
    }
    std::fflush(stderr);
}

BindProgressLine::BindProgressLine(const std::string& command, bool quiet)
    : command_(command),
      quiet_(quiet),
      tty_(::isatty(STDERR_FILENO) != 0),
      start_(std::chrono::steady_clock::now()) {
    sigintSeen = false;
    previous_ = std::signal(SIGINT, onInterrupt);
}

BindProgressLine::~BindProgressLine() {
    std::signal(SIGINT, previous_ == SIG_ERR ? SIG_DFL : previous_);
    if (shown_ && tty_) std::fputc('\n', stderr);
    // Without a terminal (logs, CI) progress is one line at the end, not a line every 10%.
    if (shown_ && !tty_)
        std::fprintf(stderr, "multicage %s: bound in %.0f s\n", command_.c_str(),
                     msSince(start_) / 1000);
}

cv::multicage::BindProgress BindProgressLine::callback() {
    return [this](double fraction) {
        if (sigintSeen) return false;
        if (quiet_ || msSince(start_) < 1000) return true;  // quick bindings stay silent
        const int percent = static_cast<int>(100 * fraction);
        if (tty_) {
            std::fprintf(stderr, "\rmulticage %s: binding %3d%% (%.0f s; Ctrl-C stops)",
                         command_.c_str(), percent, msSince(start_) / 1000);
        } else if (!shown_) {
            std::fprintf(stderr, "multicage %s: binding (Ctrl-C stops)\n", command_.c_str());
        }
        std::fflush(stderr);
        shown_ = true;
        return true;
    };
}

void BindProgressLine::rethrow(const cv::Exception& e) const {
    if (e.err.find(cv::multicage::kBindCancelled) != std::string::npos)
        throw Failure("interrupted while binding; nothing written");
    throw e;
}

CLI::Validator wholeNumber(int lo, int hi) {
    return CLI::Validator(
        [lo, hi](std::string& text) -> std::string {
            size_t used = 0;
            long value = 0;
            try {
                value = std::stol(text, &used);
            } catch (const std::exception&) {
                used = 0;
            }
            if (used == 0 || used != text.size()) return "'" + text + "' is not a whole number";
            if (value < lo || value > hi)
                return text + " is out of range: " + std::to_string(lo) + " to " +
                       std::to_string(hi);
            return std::string();
        },
        "INT in [" + std::to_string(lo) + " - " + std::to_string(hi) + "]");
}

std::vector<std::string> backendNames() {
    std::vector<std::string> names;
    for (int b = 0; const char* name = cv::multicage::backendName(b); ++b) names.push_back(name);
    return names;
}

std::vector<std::string> coordinateNames() {
    std::vector<std::string> names;
    for (int t = 0; const char* name = cv::multicage::coordinateTypeName(t); ++t)
        names.push_back(name);
    return names;
}

namespace {
// "a, b or c".
std::string orList(const std::vector<std::string>& words) {
    std::string s;
    for (size_t i = 0; i < words.size(); ++i)
        s += (i == 0 ? "" : i + 1 == words.size() ? " or " : ", ") + words[i];
    return s;
}
}  // namespace

int backendArg(const std::string& name) {
    int backend = 0;
    if (!cv::multicage::parseBackend(name, backend))
        throw Failure("unknown backend '" + name + "' (" + orList(backendNames()) + ")");
    return backend;
}

int coordinatesArg(const std::string& name) {
    int type = 0;
    if (!cv::multicage::parseCoordinateType(name, type))
        throw Failure("unknown coordinates '" + name + "' (" + orList(coordinateNames()) + ")");
    return type;
}

void addDeformOptions(CLI::App* cmd, DeformOptions& o, int defaultCoordinates) {
    o.defaultCoordinates = defaultCoordinates;
    using namespace cv::multicage;
    std::vector<std::string>
        backends;  // "auto (a hardware GPU if there is one, else the CPU)", "cpu", "gpu"
    for (const std::string& name : backendNames())
        backends.push_back(
            name == backendName(BACKEND_AUTO)
                ? name +
                      " (a hardware GPU if there is one, else the CPU: a software OpenGL is slower)"
                : name);
    std::vector<std::string> coordinates;  // "mvc (mean value)", "harmonic"
    for (int t = 0; const char* name = coordinateTypeName(t); ++t) {
        const std::string words = coordinateTypeDescription(t);
        coordinates.push_back(words == name ? std::string(name) : name + (" (" + words + ")"));
    }
    cmd->add_option("--backend", o.backend, orList(backends))
        ->capture_default_str()
        ->check(CLI::IsMember(backendNames()));
    cmd->add_option("--coords", o.coords,
                    "Cage coordinates: " + orList(coordinates) + " (default: " +
                        (defaultCoordinates == COORDINATES_FROM_CAGE
                             ? std::string("the cage file's choice")
                             : std::string(coordinateTypeName(defaultCoordinates))) +
                        ")")
        ->check(CLI::IsMember(coordinateNames()));
    o.gridStepOption =
        cmd->add_option(
               "--grid-step", o.gridStep,
               "A mesh node every N pixels: 1 is exact, larger binds N^2 times faster (raised, "
               "and said, when the coefficients would not fit in --memory-budget)")
            ->capture_default_str()
            ->check(wholeNumber(1, 256));
    cmd->add_option("--map-step", o.mapStep,
                    "CPU: find the inverse maps on a lattice N pixels apart and interpolate them "
                    "where the pose folds nothing (an error of a grid step's kind, a fraction of "
                    "the time: for augmentation); 1 finds every pixel")
        ->capture_default_str()
        ->check(wholeNumber(1, cv::multicage::DeformParams::kMaxMapStep));
    cmd->add_option("--memory-budget", o.memoryBudget,
                    "Most memory the binding's coefficients may take, e.g. 4G or 512M; 0: no limit "
                    "(default 1G)");
    cmd->add_option("--border", o.border,
                    "Value of uncovered pixels: one value, or B G R [A], e.g. --border 255 255 255")
        ->expected(1, 4)
        ->type_name("V [V V V]");
}

cv::Ptr<cv::multicage::Deformer> createWithProgress(const std::string& command, bool quiet,
                                                    const cv::Mat& image,
                                                    const cv::multicage::Multicage& cage,
                                                    cv::multicage::DeformParams params) {
    BindProgressLine progress(command, quiet);
    params.progress = progress.callback();
    try {
        return cv::multicage::Deformer::create(image, cage, params);
    } catch (const cv::Exception& e) {
        progress.rethrow(e);
    }
}

cv::multicage::DeformParams deformParams(const DeformOptions& o, const std::string& command,
                                         cv::Size imageSize, const cv::multicage::Multicage& cage,
                                         std::string* stepChange) {
    cv::multicage::DeformParams params;
    params.backend = backendArg(o.backend);
    params.coordinates = !o.coords.empty() ? coordinatesArg(o.coords)
                         : o.defaultCoordinates == cv::multicage::COORDINATES_FROM_CAGE
                             ? cage.coordinates()
                             : o.defaultCoordinates;
    if (!o.memoryBudget.empty()) params.memoryBudget = parseMemorySize(o.memoryBudget);
    const bool typed = o.gridStepOption && o.gridStepOption->count() > 0;
    params.gridStep = chooseGridStep(command, imageSize, cage.vertexCount(), o.gridStep, typed,
                                     params.memoryBudget, stepChange);
    params.mapStep = o.mapStep;
    if (o.border.size() == 2)
        throw UsageError(
            "--border: 2 values given; give 1 (every channel), 3 (B G R) or 4 (B G R A)");
    for (size_t i = 0; i < o.border.size() && i < 4; ++i)
        params.borderValue[static_cast<int>(i)] = o.border[i];
    return params;
}

void addSegmenterOptions(CLI::App* cmd, SegmenterOptions& o) {
    using namespace cv::multicage;
    std::vector<std::string> names;
    for (int s = SEGMENTER_AUTO; s <= SEGMENTER_CLASSIC; ++s) names.push_back(segmenterName(s));
    cmd->add_option("--segmenter", o.segmenter,
                    "Where the subject cue comes from: auto (the learned subject model when one "
                    "is found, else classic), model (the learned model; none found: an error), "
                    "classic (GrabCut and threshold cues only). The model runs with --method "
                    "auto and no --rect")
        ->capture_default_str()
        ->check(CLI::IsMember(names));
    cmd->add_option("--segmenter-model", o.model,
                    "Subject model (ONNX) to run instead of the installed one (docs/models.md); "
                    "a file that is not one is an error")
        ->type_name("PATH");
}

void applySegmenterOptions(const SegmenterOptions& o, int* segmenter, cv::String* model) {
    using namespace cv::multicage;
    *segmenter = parseSegmenter(o.segmenter);
    if (*segmenter < 0)  // CLI11 checks the names; this is for a caller that did not
        throw Failure("--segmenter: '" + o.segmenter + "' is not auto, model or classic");
    if (!o.model.empty() && *segmenter == SEGMENTER_CLASSIC)
        throw Failure("--segmenter-model " + o.model +
                      ": --segmenter classic runs no model (drop one of the two)");
    if (!o.model.empty() && !std::filesystem::is_regular_file(o.model))
        throw Failure("--segmenter-model " + o.model + ": no such file");
    *model = o.model;
}

namespace {
// The library's reason without its advice to C++ callers (the tool's option is named there).
std::string toolWords(std::string why) {
    const std::string field = "ProposeParams::segmenterModel, ";
    const size_t at = why.find(field);
    if (at != std::string::npos) why.erase(at, field.size());
    return why;
}
}  // namespace

std::string subjectCueHelp() {
    using namespace cv::multicage;
    cv::String why;
    const cv::String file = segmenterModelFile(ProposeParams(), &why);
    if (file.empty()) return "Subject cue now: classic (" + toolWords(why) + ").";
    // An environment variable (MULTICAGE_SEGMENTER_MODEL, MULTICAGE_DATA_DIR), or a folder.
    const std::string where = why.rfind("MULTICAGE_", 0) == 0 ? "from " + why : "found in " + why;
    return "Subject cue now: the learned model " + file + " (" + where +
           "); --segmenter classic does without it.";
}

std::string subjectCueNote(const cv::multicage::ProposeParams& params) {
    using namespace cv::multicage;
    const bool modelMethod = params.method == PROPOSE_AUTO && params.rect.area() <= 0;
    if (!modelMethod) {
        if (params.segmenter == SEGMENTER_MODEL || !params.segmenterModel.empty())
            return std::string(
                       "the subject model did not run: it runs with --method auto and "
                       "no --rect (this was --method ") +
                   proposeMethodName(params.method) +
                   (params.rect.area() > 0 ? " with --rect)" : ")");
        return "";
    }
    if (params.segmenter != SEGMENTER_AUTO) return "";
    cv::String why;
    if (!segmenterModelFile(params, &why).empty()) return "";
    return "the classic segmentation ran: " + toolWords(why);
}

std::string plural(long long n, const std::string& one, const std::string& many) {
    return std::to_string(n) + " " + (n == 1 ? one : many.empty() ? one + "s" : many);
}

std::string lowerExtension(const std::filesystem::path& path) {
    std::string e = path.extension().string();
    for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return e;
}

double msSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
        .count();
}

}  // namespace multicage_cli

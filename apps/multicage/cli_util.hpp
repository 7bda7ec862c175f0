// What the multicage subcommands share: reading inputs, parsing choices, reporting.
#ifndef MULTICAGE_CLI_UTIL_HPP
#define MULTICAGE_CLI_UTIL_HPP

#include <CLI/CLI.hpp>
#include <chrono>
#include <filesystem>
#include <opencv2/multicage.hpp>
#include <string>
#include <vector>

#include "stats.hpp"

namespace multicage_cli {

/** A user error: main() prints "multicage CMD: MESSAGE" on one line and exits 1. */
struct Failure : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/** A command line a user must change (a flag's value out of range, a bad count of values, text
that is not a number): main() prints "multicage CMD: MESSAGE (see multicage CMD --help)" and
exits 2, as for the errors CLI11 finds itself. MESSAGE starts with the flag. */
struct UsageError : Failure {
    using Failure::Failure;
};

/** A library error as the tools print it: without the library's "multicage: " and the name of
the function or module that refused ("proposeMulticage: ", "resize: "), which the command line
already says. */
std::string reasonOf(const cv::Exception& e);

/** Throws a Failure unless path names a file: "PATH: no such file", "PATH: is a folder, not a
file" (the same words in every command). */
void checkInputFile(const std::string& path);
/** Reads an image as stored (depth and alpha kept), or throws a Failure that says why (a
missing, undecodable or truncated file, an unsupported pixel type). */
cv::Mat readImage(const std::string& path);
/** Throws a Failure unless `path` can be written as an image: a known extension and an
existing folder. Called before any work, so a typo costs nothing. */
void checkImageOutput(const std::string& path);
/** Writes image to path atomically, converted to a depth the format stores (float to .jpg:
8 bits x255, ...); a conversion is said in one line on stderr, "multicage COMMAND: note: ...". */
void writeImage(const std::string& command, const std::string& path, const cv::Mat& image);
/** Loads a cage file (checkInputFile() first) and scales it to imageSize when it was made for
another size; an empty imageSize keeps the file's. */
cv::multicage::Multicage loadCage(const std::string& path, cv::Size imageSize);

/** Adds --allow-invalid to cmd (deform, animate: what it does with such a pose is `verb`,
"Deform"; pose: "Write"), stored in allow. */
void addAllowInvalidFlag(CLI::App* cmd, bool& allow, const std::string& verb = "Deform");
/** Throws a Failure naming the pose and what validatePose() finds (polygons that cross, leave
the frame or change nesting) unless the pose keeps the multicage valid; with allowInvalid the
reason is a warning on stderr instead, and the pose is deformed as asked. */
void checkPose(const std::string& command, const std::string& cagePath,
               const cv::multicage::Multicage& cage, int poseIndex, bool allowInvalid);

/** Bytes from "2G", "512M", "1.5GiB", "300000000" (K, M, G, T: powers of 1024); "0": no limit.
Throws a Failure naming the bad text. */
size_t parseMemorySize(const std::string& text);
/** "1.0 GiB", "640 MiB". */
std::string formatBytes(size_t bytes);

/** The grid step to bind with: `step`, or when its coefficients would exceed `budget` bytes
(0: no limit) the smallest step that fits. A raised step the user typed (`typed`) is said on
stderr in plain words, with the --memory-budget that would keep it. Returns the step and, in
*change, what the normal output line should add ("" when unchanged). */
int chooseGridStep(const std::string& command, cv::Size imageSize, int vertexCount, int step,
                   bool typed, size_t budget, std::string* change);

/** Runs the EGL probe of BACKEND_AUTO now (once per process), so that it is not counted as
bind time; a no-op for cpu and gpu. */
void probeAutoBackend(int backend);

/** A progress line on stderr for bindings that take more than a second (redrawn in place on a
terminal; elsewhere a line when it starts and one when it is done), and Ctrl-C cancels the binding
cleanly: the command then fails with "interrupted while binding; nothing written". Active while the
object lives. */
class BindProgressLine {
  public:
    BindProgressLine(const std::string& command, bool quiet);
    ~BindProgressLine();
    cv::multicage::BindProgress callback();
    /** Rethrows a cancelled binding's exception as that one-line Failure. */
    [[noreturn]] void rethrow(const cv::Exception& e) const;

  private:
    std::string command_;
    bool quiet_, tty_;
    std::chrono::steady_clock::time_point start_;
    bool shown_ = false;
    void (*previous_)(int) = nullptr;
};

/** While it lives, Ctrl-C sets a flag instead of ending the process: a long loop asks
interrupted() and stops cleanly, and what it was writing is never put in place. */
class InterruptGuard {
  public:
    InterruptGuard();
    ~InterruptGuard();
    static bool interrupted();

  private:
    void (*previous_)(int) = nullptr;
};

/** A bar for work counted in frames: redrawn in place on a terminal with the rate and the time
left; elsewhere (logs, CI) one line at the end, "multicage CMD: 100% (N/N frames)". */
class FrameProgress {
  public:
    FrameProgress(const std::string& command, bool quiet);
    /** done of total frames (total <= 0: not known); the last call has done == total. */
    void operator()(int done, int total);

  private:
    std::string command_;
    bool quiet_, tty_;
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

/** Deformer::create(image, cage, params) with a BindProgressLine for `command`: a progress line
on stderr while a long binding runs, and a cancelled one as that one-line Failure. */
cv::Ptr<cv::multicage::Deformer> createWithProgress(const std::string& command, bool quiet,
                                                    const cv::Mat& image,
                                                    const cv::multicage::Multicage& cage,
                                                    cv::multicage::DeformParams params);

/** A CLI11 check for a whole number in [lo, hi] that names what is wrong ("'abc' is not a
whole number", "0 is out of range: 1 to 256"). */
CLI::Validator wholeNumber(int lo, int hi);

/** The library's names of the backends (backendName: auto, cpu, gpu) and of the coordinate
types (coordinateTypeName: mvc, harmonic, local_mvc). */
std::vector<std::string> backendNames();
std::vector<std::string> coordinateNames();
// The library's names (cv::multicage::parseBackend, parseCoordinateType), as a Failure when
// unknown.
int backendArg(const std::string& name);      // auto | cpu | gpu
int coordinatesArg(const std::string& name);  // mvc | harmonic | local_mvc

/** The options of a deformation that deform, animate and demo share, as typed. */
struct DeformOptions {
    std::string backend = "auto";  //!< --backend: a backendNames() entry
    std::string coords;            //!< --coords: a coordinateNames() entry; "": the cage's choice
    std::string memoryBudget;      //!< --memory-budget: parseMemorySize() text; "": the default
    int gridStep = 1;              //!< --grid-step
    int mapStep = 1;               //!< --map-step
    std::vector<double> border;    //!< --border: 1 to 4 channel values; empty: 0
    const CLI::Option* gridStepOption = nullptr;  //!< set by addDeformOptions: typed or not
    /** The coordinates without --coords: COORDINATES_FROM_CAGE (the cage's own) or a type the
    command prefers (resize: local mean value, so what an outline holds keeps its shape). */
    int defaultCoordinates = cv::multicage::COORDINATES_FROM_CAGE;
};
/** Adds --backend, --coords, --grid-step, --map-step, --memory-budget and --border to cmd, stored
in o (which must live as long as cmd). The valid names are the library's; defaultCoordinates is what
no --coords means (and what the help says). */
void addDeformOptions(CLI::App* cmd, DeformOptions& o,
                      int defaultCoordinates = cv::multicage::COORDINATES_FROM_CAGE);
/** The DeformParams the options ask for on this image and cage: backend and coordinates
parsed (no --coords: o.defaultCoordinates, the cage's own by default), memory budget and border, and
the grid step chooseGridStep() picks (`command` and *stepChange as there). Throws a Failure for a
bad
--memory-budget. */
cv::multicage::DeformParams deformParams(const DeformOptions& o, const std::string& command,
                                         cv::Size imageSize, const cv::multicage::Multicage& cage,
                                         std::string* stepChange);

/** Where a proposal's subject cue comes from, as typed (propose, resize): --segmenter and
--segmenter-model. */
struct SegmenterOptions {
    std::string segmenter = "auto";  //!< --segmenter: auto, model or classic
    std::string model;               //!< --segmenter-model: "" for the library's look-up
};
/** Adds --segmenter (checked against the library's names) and --segmenter-model to cmd, stored
in o (which must live as long as cmd). */
void addSegmenterOptions(CLI::App* cmd, SegmenterOptions& o);
/** The ProposeParams::segmenter and segmenterModel the options ask for. Throws a Failure for
--segmenter-model with --segmenter classic (it would not run) and for a model path that is no
file. */
void applySegmenterOptions(const SegmenterOptions& o, int* segmenter, cv::String* model);
/** For a command's help: "Subject cue: ..." which cue a default proposal runs now and why
(segmenterModelFile() of the default ProposeParams). */
std::string subjectCueHelp();
/** After a proposal with params (what the note says, without "note: "), or "" when there is
nothing to say: the default found no subject model (the classic segmentation ran, and how to
get the model), or a segmenter asked for that this method does not use. */
std::string subjectCueNote(const cv::multicage::ProposeParams& params);

/** "1 polygon", "3 polygons" (many: the plural when it is not singular + "s"). */
std::string plural(long long n, const std::string& one, const std::string& many = "");
/** The path's extension in lower case, with its dot (".mp4"), or "" for none. */
std::string lowerExtension(const std::filesystem::path& path);
/** Milliseconds since `start` (std::chrono::steady_clock). */
double msSince(std::chrono::steady_clock::time_point start);
using multicage_apps::median;  // stats.hpp

void addDemoCommand(CLI::App& app);
void addDeformCommand(CLI::App& app);
void addProposeCommand(CLI::App& app);
void addBenchCommand(CLI::App& app);
void addAnimateCommand(CLI::App& app);
void addResizeCommand(CLI::App& app);
void addPoseCommand(CLI::App& app);

}  // namespace multicage_cli

#endif

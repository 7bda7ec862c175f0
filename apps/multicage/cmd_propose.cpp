// multicage propose IMAGE -o CAGE.yml: automatic multicage proposal; with folders or several
// images, one cage per image into a folder, in parallel (a dataset ahead of training).
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <iostream>
#include <map>
#include <mutex>
#include <opencv2/imgproc.hpp>
#include <thread>

#include "cli_util.hpp"

namespace multicage_cli {

namespace {
struct ProposeOptions {
    std::vector<std::string> inputs;  // IMAGE, or images and folders for a dataset
    std::string image, output, overlay, method = "auto";
    int jobs = 0;            // dataset: images proposed at once (0: one per core)
    bool overwrite = false;  // dataset: propose again where a cage file exists
    int maxVertices = 80, maxPolygonVertices = 32, maxPolygons = 12, maxDepth = 3,
        workingSize = 512;
    float margin = -1.f;
    double minArea = 0.004;
    std::vector<int> rect;
    std::string protect,
        cascadeDir;  // protect: "" (not given: the library's default), saliency, faces, all
    bool noProtect = false;
    SegmenterOptions segmenter;  // --segmenter, --segmenter-model
};

void checkCageOutput(const std::string& path) {
    const std::filesystem::path p(path);
    const std::string ext = p.extension().string();
    if (ext != ".yml" && ext != ".yaml" && ext != ".json")
        throw Failure("cannot write " + path + ": a cage file ends in .yml, .yaml or .json");
    const std::filesystem::path dir = p.has_parent_path() ? p.parent_path() : ".";
    if (!std::filesystem::is_directory(dir))
        throw Failure("cannot write " + path + ": no folder " + dir.string());
}

cv::multicage::ProposeParams proposeParams(const ProposeOptions& o) {
    using namespace cv::multicage;
    ProposeParams params;
    params.method = parseProposeMethod(o.method);
    params.maxVertices = o.maxVertices;
    params.maxPolygonVertices = o.maxPolygonVertices;
    params.maxPolygons = o.maxPolygons;
    params.maxDepth = o.maxDepth;
    params.margin = o.margin;
    params.minRegionArea = o.minArea;
    params.workingSize = o.workingSize;
    if (o.rect.size() == 4) params.rect = cv::Rect(o.rect[0], o.rect[1], o.rect[2], o.rect[3]);
    // Not given: ProposeParams' default (all), the same as Python's and the editor's.
    if (!o.protect.empty()) params.protect = parseProtectDetector(o.protect);
    params.cascadeDir = o.cascadeDir;
    // Not given: auto, the library's default (the learned model when one is found).
    applySegmenterOptions(o.segmenter, &params.segmenter, &params.segmenterModel);
    return params;
}

bool isMaskMethod(int method) {
    return method == cv::multicage::PROPOSE_MASK || method == cv::multicage::PROPOSE_LABELS;
}

// What the proposal reads: the image, or for --method mask or labels a one-channel copy.
cv::Mat proposalInput(const ProposeOptions& o, const cv::Mat& image, int method) {
    if (!isMaskMethod(method) || image.channels() == 1) return image;
    if (method == cv::multicage::PROPOSE_LABELS)
        throw Failure(o.image + ": a label image has one channel (this one has " +
                      std::to_string(image.channels()) + ")");
    // A mask saved in colour has equal channels; a photo does not, and read as a mask it
    // is "object" almost everywhere (one polygon around the whole image): refuse it.
    std::vector<cv::Mat> ch;
    cv::split(image, ch);
    const double spread =
        (cv::norm(ch[0], ch[1], cv::NORM_L1) + cv::norm(ch[1], ch[2], cv::NORM_L1)) /
        static_cast<double>(image.total());
    if (spread > 2.0)
        throw Failure(o.image +
                      ": --method mask wants a mask (black background, non-zero object), "
                      "and this is a colour image; for a photo use --method auto");
    cv::Mat input;
    cv::cvtColor(image, input, image.channels() == 4 ? cv::COLOR_BGRA2GRAY : cv::COLOR_BGR2GRAY);
    return input;
}

// The multicage is the product: inner polygons protect the features (faces, salient blobs)
// inside each outline unless --no-protect; a mask or label input is no photo to find features
// in (--protect still protects its regions). *note: what the face search found, if it ran.
cv::multicage::Multicage proposeCage(const ProposeOptions& o,
                                     const cv::multicage::ProposeParams& params,
                                     const cv::Mat& image, const cv::Mat& input,
                                     std::string* note) {
    using namespace cv::multicage;
    if (o.noProtect) return proposeMulticage(input, params);
    if (isMaskMethod(params.method)) {
        Multicage cage = proposeMulticage(input, params);
        if (!o.protect.empty()) {
            const int top = cage.polygonCount();
            for (int p = 0; p < top; ++p)
                if (cage.depth(p) == 1) cage = protectFeatures(image, cage, p, params);
        }
        return cage;
    }
    std::vector<cv::Rect> faces;
    Multicage cage = proposeProtectedMulticage(image, params, &faces);
    const bool faceSearch = params.protect != PROTECT_SALIENCY;
    if (faceSearch && params.protect == PROTECT_ALL && faceCascadeFile(params).empty())
        *note =
            "note: no face cascade installed (Debian package opencv-data): protected "
            "salient features only";
    else if (faceSearch && faces.empty())
        *note = params.protect == PROTECT_FACES
                    ? "note: no face found: the outlines have no inner polygon"
                    : "note: no face found: protected salient features only";
    else if (faceSearch)
        *note = "protected " + plural(static_cast<int>(faces.size()), "face");
    return cage;
}

// The image with the polygons drawn, coloured by depth (a mask or label image stretched to
// be seen).
void writeOverlay(const std::string& path, const cv::Mat& image,
                  const cv::multicage::Multicage& cage, int method) {
    cv::Mat overlay;
    if (image.depth() != CV_8U) {
        cv::normalize(image, overlay, 0, 255, cv::NORM_MINMAX, CV_8U);
    } else {
        overlay = image.clone();
    }
    if (overlay.channels() == 1) cv::cvtColor(overlay, overlay, cv::COLOR_GRAY2BGR);
    if (overlay.channels() == 4) cv::cvtColor(overlay, overlay, cv::COLOR_BGRA2BGR);
    if (isMaskMethod(method)) cv::normalize(overlay, overlay, 0, 255, cv::NORM_MINMAX);
    cage.draw(overlay, std::max(1, std::max(image.cols, image.rows) / 300));
    cv::multicage::imwriteAtomic(path, overlay);
}

// The multicage of o.image with its pose 'rest', or a Failure naming the image. *image: the
// image as read; *note: what the face search found, if it ran.
cv::multicage::Multicage proposeFor(const ProposeOptions& o,
                                    const cv::multicage::ProposeParams& params, cv::Mat* image,
                                    std::string* note) {
    using namespace cv::multicage;
    *image = readImage(o.image);
    const cv::Mat input = proposalInput(o, *image, params.method);
    Multicage cage;
    try {
        cage = proposeCage(o, params, *image, input, note);
    } catch (const cv::Exception& e) {
        // A subject model that cannot be read names its file; nothing is written.
        throw Failure(o.image + ": " + reasonOf(e));
    }
    if (cage.polygonCount() == 0)
        throw Failure(o.image + ": no object found with --method " + o.method +
                      " (try another --method, or a smaller --min-area); no cage written");
    std::string why;
    if (!cage.validate(&why))
        throw Failure("internal error: the proposed multicage is invalid: " + why);
    // A pose to start from: `deform` needs one, and the file shows the format to edit.
    cage.addPose("rest", cage.vertices(), 0.0);
    return cage;
}

bool isImageFile(const std::filesystem::path& p) {
    std::string ext = p.extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    for (const char* known : {".jpg", ".jpeg", ".png", ".bmp", ".tif", ".tiff", ".webp", ".ppm",
                              ".pgm", ".pnm", ".jp2", ".exr", ".hdr", ".pfm", ".sr", ".ras"})
        if (ext == known) return true;
    return false;
}

// A dataset: the images of every folder (recursively, by extension, in name order) and every
// file given, each to <output>/<stem>.yml, the name MulticageWarp(cage_dir=) reads.
void runProposeDataset(const ProposeOptions& options) {
    namespace fs = std::filesystem;
    const auto t0 = std::chrono::steady_clock::now();
    if (!options.overlay.empty())
        throw UsageError("--overlay: one image at a time, not with a dataset");
    std::vector<std::string> images;
    for (const std::string& input : options.inputs) {
        if (!fs::exists(input)) throw Failure(input + ": no such file");
        if (!fs::is_directory(input)) {
            images.push_back(input);
            continue;
        }
        std::vector<std::string> found;
        for (const auto& entry :
             fs::recursive_directory_iterator(input, fs::directory_options::skip_permission_denied))
            if (entry.is_regular_file() && isImageFile(entry.path()))
                found.push_back(entry.path().string());
        std::sort(found.begin(), found.end());
        images.insert(images.end(), found.begin(), found.end());
    }
    if (images.empty())
        throw Failure("no images found in " + options.inputs[0] + " (.jpg, .png, .tif, ...)");
    const fs::path outDir(options.output);
    std::error_code error;
    fs::create_directories(outDir, error);
    if (!fs::is_directory(outDir))
        throw Failure("cannot write " + options.output + ": not a folder");

    // Two images with one stem would write one cage file: the later one is refused by name.
    struct Item {
        std::string image, cage, problem;
        bool skipped = false;
    };
    std::vector<Item> items;
    std::map<std::string, std::string> byStem;
    for (const std::string& image : images) {
        Item item{image, (outDir / (fs::path(image).stem().string() + ".yml")).string(), ""};
        const auto [it, fresh] = byStem.emplace(item.cage, image);
        if (!fresh)
            item.problem = "has the name of " + it->second + " (both would be " + item.cage + ")";
        item.skipped = item.problem.empty() && !options.overwrite && fs::exists(item.cage);
        items.push_back(item);
    }
    const cv::multicage::ProposeParams params = proposeParams(options);
    const int jobs =
        options.jobs > 0 ? options.jobs : std::max(1u, std::thread::hardware_concurrency());
    const bool tty = ::isatty(STDERR_FILENO) != 0;
    std::atomic<size_t> next{0};
    std::atomic<int> done{0};
    std::mutex print;
    int todo = 0;
    for (const Item& item : items) todo += !item.skipped && item.problem.empty();
    auto work = [&] {
        for (size_t i; (i = next++) < items.size();) {
            Item& item = items[i];
            if (item.skipped || !item.problem.empty()) continue;
            ProposeOptions o = options;
            o.image = item.image;
            try {
                cv::Mat image;
                std::string note;
                proposeFor(o, params, &image, &note).save(item.cage);
            } catch (const std::exception& e) {
                const cv::Exception* cv = dynamic_cast<const cv::Exception*>(&e);
                item.problem = cv ? reasonOf(*cv) : e.what();
                if (item.problem.rfind(item.image + ": ", 0) == 0)
                    item.problem = item.problem.substr(item.image.size() + 2);
            }
            const int n = ++done;
            if (tty) {
                std::lock_guard<std::mutex> lock(print);
                std::fprintf(stderr, "\rmulticage propose: %d/%d images (%.1f s)", n, todo,
                             msSince(t0) / 1000);
                if (n == todo) std::fputc('\n', stderr);
                std::fflush(stderr);
            }
        }
    };
    std::vector<std::thread> workers;
    for (int k = 0; k < std::min(jobs, std::max(todo, 1)); ++k) workers.emplace_back(work);
    for (std::thread& t : workers) t.join();

    int failed = 0, skipped = 0;
    for (const Item& item : items) {
        skipped += item.skipped;
        if (item.problem.empty()) continue;
        ++failed;
        std::cerr << "multicage propose: skipped " << item.image << ": " << item.problem
                  << std::endl;
    }
    const int written = static_cast<int>(items.size()) - failed - skipped;
    std::cout << "wrote " << plural(written, "cage file") << " to " << options.output << " ("
              << plural(static_cast<long long>(items.size()), "image") << "; " << skipped
              << " had one already" << (skipped ? ", kept (--overwrite proposes again)" : "")
              << "; " << failed << " failed; " << jobs << (jobs == 1 ? " job, " : " jobs, ")
              << cv::format("%.1f s", msSince(t0) / 1000) << ")" << std::endl;
    if (failed)
        throw Failure(plural(failed, "image") +
                      " failed (named above); the other cage files are written");
}

void runPropose(const ProposeOptions& options) {
    using namespace cv::multicage;
    namespace fs = std::filesystem;
    const bool dataset = options.inputs.size() > 1 || fs::is_directory(options.inputs[0]) ||
                         fs::is_directory(options.output) || options.output.back() == '/';
    if (dataset) return runProposeDataset(options);
    ProposeOptions o = options;
    o.image = o.inputs[0];
    const auto t0 = std::chrono::steady_clock::now();
    checkCageOutput(o.output);
    if (!o.overlay.empty()) checkImageOutput(o.overlay);
    const ProposeParams params = proposeParams(o);
    cv::Mat image;
    std::string note;
    const Multicage cage = proposeFor(o, params, &image, &note);
    cage.save(o.output);
    if (!o.overlay.empty()) writeOverlay(o.overlay, image, cage, params.method);
    int deepest = 0;
    for (int p = 0; p < cage.polygonCount(); ++p) deepest = std::max(deepest, cage.depth(p));
    std::cout << "wrote " << o.output << " (" << plural(cage.polygonCount(), "polygon") << ", "
              << plural(cage.vertexCount(), "vertex", "vertices") << ", depth up to " << deepest
              << ", pose 'rest', " << cvRound(msSince(t0)) << " ms)";
    if (!o.overlay.empty()) std::cout << " and " << o.overlay;
    std::cout << std::endl;
    if (!note.empty())
        std::cerr << "multicage propose: " << (note.rfind("note: ", 0) == 0 ? "" : "note: ") << note
                  << std::endl;
    // Which subject cue ran, when it is not what the options asked for or the default found
    // no model (a mask or label image is no photo: no cue runs).
    if (!isMaskMethod(params.method)) {
        const std::string cue = subjectCueNote(params);
        if (!cue.empty()) std::cerr << "multicage propose: note: " << cue << std::endl;
    }
}

// propose's help: the methods, the subject cues, what is protected, datasets, examples.
std::string proposeHelp() {
    return std::string() +
           "Propose a multicage for IMAGE: find its objects, put one polygon around each (a "
           "margin "
           "away), nest polygons where objects sit inside others, and simplify them to a vertex "
           "budget. The result is always valid: simple, disjoint polygons inside the image, "
           "oriented by depth.\n"
           "Methods: auto (threshold on a plain background, else grabcut), "
           "threshold (Otsu on the "
           "distance from the border colour), adaptive (local threshold, uneven light), grabcut "
           "(from --rect, or from the image frame inward where that holds the salient part), "
           "saliency (fine grained), spectral "
           "(spectral residual saliency, coarse and fast), mask (IMAGE is a mask: non-zero is "
           "object), labels (IMAGE is a label image: each label its own polygon).\n"
           "With --method auto the subject of a photo comes from a learned subject model "
           "(U^2-Net-P, docs/models.md) fused with the faces and GrabCut, when the model is "
           "installed (--segmenter auto, when no other is given), else from the classic cues "
           "alone; "
           "--segmenter classic or model picks one. " +
           subjectCueHelp() + "\n" +
           "By default the result is a multicage: an outline around each object, plus inner "
           "polygons "
           "around the faces and salient features inside it (moving the outline then leaves them "
           "almost rigid); --protect DETECTOR picks what is protected: all (the default: faces, "
           "then textured salient features and regions of a colour of their own, such as a "
           "badge, a name tag or a patch), faces (frontal and profile faces, OpenCV's Haar "
           "cascades from the Debian package opencv-data), saliency (those features only); "
           "--no-protect gives the outlines only.\n"
           "The cage file gets a pose named `rest` (every vertex at rest): edit it, or add poses, "
           "and `multicage deform` applies them.\n"
           "A dataset: several images or folders, and -o a folder: one cage per image, "
           "OUT/STEM.yml (what MulticageWarp(cage_dir=OUT) reads), proposed in parallel; cages "
           "already there are kept (an interrupted run resumes); an image that fails is named and "
           "skipped, and the exit status is 1 once the others are written.\n"
           "Examples:\n"
           "  multicage propose photo.jpg -o cage.yml --overlay check.png\n"
           "  multicage propose dataset/images/ -o dataset/cages/\n"
           "  multicage propose photo.jpg -o cage.yml --method grabcut --rect 40 30 400 300\n"
           "  multicage propose mask.png -o cage.yml --method mask --margin 12 --max-vertices 40\n"
           "Then: multicage deform photo.jpg cage.yml -o out.png --pose NAME (or multicage-editor "
           "photo.jpg "
           "cage.yml to draw a pose).";
}

// What to read and write: IMAGE (or a dataset's images and folders), -o, a dataset's --jobs and
// --overwrite, --overlay.
void addProposeInputOptions(CLI::App* cmd, ProposeOptions& o) {
    cmd->add_option("image", o.inputs,
                    "Input image (or mask / label image with --method mask / labels); for a "
                    "dataset, several images or folders (searched recursively)")
        ->required();
    cmd->add_option("-o,--output", o.output,
                    "Cage file to write (.yml, .yaml or .json), written only on success; for a "
                    "dataset, a folder (created if needed) that gets STEM.yml per image")
        ->required();
    cmd->add_option("-j,--jobs", o.jobs, "Dataset: images proposed at once (default: one per core)")
        ->check(wholeNumber(1, 256));
    cmd->add_flag("--overwrite", o.overwrite,
                  "Dataset: propose again where a cage file exists (by default it is kept, so an "
                  "interrupted run resumes where it stopped)");
    cmd->add_option("--overlay", o.overlay,
                    "Also write the image with the polygons drawn, coloured by depth");
}

// How objects are found and simplified: --method, the vertex and polygon budgets, --margin,
// --min-area, --working-size, --rect.
void addProposeShapeOptions(CLI::App* cmd, ProposeOptions& o) {
    cmd->add_option("--method", o.method, "How objects are found (see above)")
        ->capture_default_str()
        ->check(CLI::IsMember({"auto", "threshold", "adaptive", "grabcut", "saliency", "spectral",
                               "mask", "labels"}));
    cmd->add_option("--max-vertices", o.maxVertices, "Vertex budget of the whole multicage")
        ->capture_default_str()
        ->check(CLI::Range(4, 100000));
    cmd->add_option("--max-polygon-vertices", o.maxPolygonVertices, "Vertex budget of one polygon")
        ->capture_default_str()
        ->check(CLI::Range(4, 100000));
    cmd->add_option("--max-polygons", o.maxPolygons,
                    "At most this many polygons (the largest regions win)")
        ->capture_default_str()
        ->check(CLI::Range(1, 10000));
    cmd->add_option("--max-depth", o.maxDepth, "Deepest nesting (1: no polygon inside another)")
        ->capture_default_str()
        ->check(CLI::Range(1, 100));
    cmd->add_option(
           "--margin", o.margin,
           "Pixels between an object and its polygon (default: 1.2% of the image diagonal)")
        ->check(CLI::Range(0.f, 10000.f));
    cmd->add_option("--min-area", o.minArea,
                    "Drop regions and holes smaller than this fraction of the image")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 0.999));
    cmd->add_option("--working-size", o.workingSize,
                    "Segment a copy at most this many pixels wide or high (0: full size)")
        ->capture_default_str()
        ->check(CLI::Range(0, 100000));
    cmd->add_option("--rect", o.rect, "GrabCut's starting rectangle: X Y WIDTH HEIGHT in pixels")
        ->expected(4);
}

// What the inner polygons protect: --protect, --cascade-dir, --no-protect.
void addProposeProtectOptions(CLI::App* cmd, ProposeOptions& o) {
    cmd->add_option("--protect", o.protect,
                    "What the inner polygons protect: all, faces or saliency (see above). On "
                    "(all) by default except with --method mask or labels")
        ->check(CLI::IsMember({"all", "faces", "saliency"}));
    cmd->add_option("--cascade-dir", o.cascadeDir,
                    "Folder of the Haar face cascades (default: /usr/share/opencv4/haarcascades, "
                    "from the Debian package opencv-data)");
    cmd->add_flag("--no-protect", o.noProtect,
                  "Outlines only: one polygon per object, no inner polygons")
        ->excludes("--protect");
}
}  // namespace

void addProposeCommand(CLI::App& app) {
    auto o = std::make_shared<ProposeOptions>();
    CLI::App* cmd = app.add_subcommand("propose", proposeHelp());
    addProposeInputOptions(cmd, *o);
    addProposeShapeOptions(cmd, *o);
    addProposeProtectOptions(cmd, *o);
    addSegmenterOptions(cmd, o->segmenter);
    cmd->callback([o] { runPropose(*o); });
}

}  // namespace multicage_cli

// multicage resize IMAGE -o OUT --size WxH: content-aware resizing (docs/resize/README.md).
#include <filesystem>
#include <iostream>
#include <opencv2/imgproc.hpp>
#include <opencv2/multicage/resize.hpp>
#include <regex>

#include "cli_util.hpp"
#include "clip_io.hpp"
#include "resize_clip.hpp"

namespace multicage_cli {

namespace {
struct ResizeCommandOptions {
    std::string image, output, cage, overlay, protect;
    std::vector<std::string> sizes;
    int width = 0, height = 0;
    std::string aspect;
    DeformOptions deform;
    SegmenterOptions segmenter;  // the proposal's subject cue (no --cage)
    bool quiet = false, noProtect = false;
    double maxScale = cv::multicage::ResizeParams().maxScale;
    double maxWarp = cv::multicage::ResizeParams().maxWarp;
    int smoothing = cv::multicage::ReframeParams().smoothing;
};

// "WxH" (also "W*H", "WXH"), each a positive whole number.
cv::Size parseSize(const std::string& text) {
    static const std::regex form(R"(\s*(\d{1,6})\s*[xX*]\s*(\d{1,6})\s*)");
    std::smatch m;
    if (!std::regex_match(text, m, form))
        throw UsageError("--size: '" + text + "' is not WxH (two whole numbers, e.g. 1280x720)");
    return cv::Size(std::stoi(m[1]), std::stoi(m[2]));
}

// "16:9" (also "1.78"): a width-to-height ratio.
double parseAspect(const std::string& text) {
    static const std::regex ratio(R"(\s*(\d+(?:\.\d+)?)\s*[:/]\s*(\d+(?:\.\d+)?)\s*)"),
        number(R"(\s*(\d+(?:\.\d+)?)\s*)");
    std::smatch m;
    double a = 0;
    if (std::regex_match(text, m, ratio))
        a = std::stod(m[1]) / std::max(1e-12, std::stod(m[2]));
    else if (std::regex_match(text, m, number))
        a = std::stod(m[1]);
    if (!(a > 0) || !std::isfinite(a))
        throw UsageError("--aspect: '" + text +
                         "' is not a ratio W:H (e.g. 16:9) or a number (e.g. 1.78)");
    return a;
}

// Every target size asked for: --size (any number), or one from --width/--height/--aspect.
std::vector<cv::Size> targetSizes(const ResizeCommandOptions& o, cv::Size image) {
    std::vector<cv::Size> sizes;
    for (const std::string& s : o.sizes) sizes.push_back(parseSize(s));
    const bool oneSide = o.width > 0 || o.height > 0;
    if (!o.aspect.empty()) {
        if (oneSide) throw Failure("--aspect: give it alone, or --width/--height, not both");
        // The height stays (subjects keep their size in pixels), the width gives the ratio.
        const double a = parseAspect(o.aspect);
        sizes.push_back(cv::Size(std::max(1, cvRound(a * image.height)), image.height));
    } else if (oneSide) {
        // A side not given keeps the image's: --width 1536 widens, --height narrows the other way.
        sizes.push_back(
            cv::Size(o.width > 0 ? o.width : image.width, o.height > 0 ? o.height : image.height));
    }
    if (sizes.empty())
        throw Failure("no target size: give --size WxH (or --width, --height, --aspect)");
    return sizes;
}

// OUT for one size; with several, OUT's stem gets _WxH (out.png -> out_1280x720.png).
std::string outputFor(const std::string& output, cv::Size size, bool several) {
    if (!several) return output;
    const std::filesystem::path p(output);
    const std::string tag = "_" + std::to_string(size.width) + "x" + std::to_string(size.height);
    return (p.parent_path() / (p.stem().string() + tag + p.extension().string())).string();
}

// The cage at rest on the image, and resized on the output, side by side.
cv::Mat overlayPicture(const cv::Mat& image, const cv::multicage::Multicage& cage,
                       const cv::Mat& out, const std::vector<cv::Point2f>& pose) {
    using namespace cv::multicage;
    auto bgr = [](const cv::Mat& m) {
        cv::Mat c;
        m.convertTo(c, CV_8U, m.depth() == CV_16U ? 1.0 / 257 : m.depth() == CV_32F ? 255.0 : 1.0);
        if (c.channels() == 1) cv::cvtColor(c, c, cv::COLOR_GRAY2BGR);
        if (c.channels() == 4) cv::cvtColor(c, c, cv::COLOR_BGRA2BGR);
        return c;
    };
    cv::Mat left = bgr(image), right = bgr(out);
    cage.draw(left, 2);
    Multicage moved = cage.posed(pose);
    moved.setImageSize(out.size());
    moved.draw(right, 2);
    const int h = std::max(left.rows, right.rows), gap = 8;
    cv::Mat sheet(h, left.cols + gap + right.cols, CV_8UC3, cv::Scalar::all(255));
    left.copyTo(sheet(cv::Rect(0, 0, left.cols, left.rows)));
    right.copyTo(sheet(cv::Rect(left.cols + gap, 0, right.cols, right.rows)));
    return sheet;
}

// checkResizeSize() as a command-line error naming --size and --max-scale.
void checkTargetSize(cv::Size image, cv::Size size, double maxScale) {
    try {
        cv::multicage::checkResizeSize(image, size, maxScale);
    } catch (const cv::Exception& e) {
        const std::string library = "ResizeParams::maxScale sets the limit", reason = reasonOf(e);
        const size_t at = reason.find(library);
        throw UsageError("--size: " + (at == std::string::npos
                                           ? reason
                                           : reason.substr(0, at) + "--max-scale raises it" +
                                                 reason.substr(at + library.size())));
    }
}

// The options the photo and the clip share: what the proposal protects, its subject cue, the
// limits of the size and of the warp.
cv::multicage::ResizeParams resizeParams(const ResizeCommandOptions& o) {
    cv::multicage::ResizeParams rp;
    if (!o.protect.empty()) {
        rp.protect = cv::multicage::parseProtectDetector(o.protect);
        if (rp.protect < 0)
            throw Failure("--protect: '" + o.protect + "' is not saliency, faces or all");
    }
    applySegmenterOptions(o.segmenter, &rp.segmenter, &rp.segmenterModel);
    rp.maxScale = o.maxScale;
    rp.maxWarp = o.maxWarp;
    return rp;
}

// A clip: one size, a video out, the grid step 2 unless typed (a binding per frame).
void runResizeClip(const ResizeCommandOptions& o) {
    using namespace cv::multicage;
    if (!isVideoPath(o.output))
        throw UsageError(
            "-o: a clip is written as a video (.mp4, .m4v, .mov, .mkv, .avi or "
            ".webm), not '" +
            o.output + "'");
    if (!o.overlay.empty()) throw UsageError("--overlay: for photos only");
    if (o.noProtect) throw UsageError("--no-protect: for photos only");
    if (o.sizes.size() > 1) throw UsageError("--size: a clip is resized to one size");
    ClipResizeJob job;
    job.input = o.image, job.output = o.output, job.cage = o.cage, job.quiet = o.quiet;
    job.params.resize = resizeParams(o);
    job.params.smoothing = o.smoothing;
    job.params.resize.backend = backendArg(o.deform.backend);
    job.params.resize.coordinates =
        o.deform.coords.empty() ? ResizeParams().coordinates : coordinatesArg(o.deform.coords);
    if (o.deform.gridStepOption && o.deform.gridStepOption->count() > 0)
        job.params.resize.gridStep = o.deform.gridStep;
    probeAutoBackend(job.params.resize.backend);
    job.targetSize = [&o](cv::Size frame) {
        cv::Size size = targetSizes(o, frame).front();
        // Video codecs store colour at half resolution: --aspect picks an even width.
        if (!o.aspect.empty())
            size.width = std::max(2, 2 * cvRound(parseAspect(o.aspect) * frame.height / 2));
        checkTargetSize(frame, size, o.maxScale);
        return size;
    };
    resizeClip(job);
}

void runResize(const ResizeCommandOptions& o) {
    using namespace cv::multicage;
    if (isVideoPath(o.image)) return runResizeClip(o);
    if (isVideoPath(o.output))
        throw UsageError("-o: '" + o.output + "' is a video; " + o.image +
                         " is a photo: write an image (.png, .jpg, ...)");
    const auto t0 = std::chrono::steady_clock::now();
    const cv::Mat image = readImage(o.image);
    ResizeParams rp = resizeParams(o);
    // Every size and output checked before any work: a bad one writes nothing.
    const std::vector<cv::Size> sizes = targetSizes(o, image.size());
    for (const cv::Size& s : sizes) {
        checkTargetSize(image.size(), s, rp.maxScale);
        checkImageOutput(outputFor(o.output, s, sizes.size() > 1));
    }
    if (!o.overlay.empty()) checkImageOutput(o.overlay);

    const auto tp = std::chrono::steady_clock::now();
    // A subject model that cannot be read fails here, naming its file: nothing is written.
    Multicage cage = o.cage.empty() ? resizeCage(image, rp) : loadCage(o.cage, image.size());
    if (o.noProtect) {  // the outlines alone
        Multicage outlines(cage.imageSize());
        for (int p = 0; p < cage.polygonCount(); ++p)
            if (cage.depth(p) == 1) outlines.addPolygon(cage.polygon(p));
        outlines.orient();
        cage = outlines;
    }
    const double proposeMs = o.cage.empty() ? msSince(tp) : 0;
    std::string stepChange;
    DeformParams params = deformParams(o.deform, "resize", image.size(), cage, &stepChange);
    rp.gridStep = params.gridStep;
    probeAutoBackend(params.backend);
    // Past --max-warp a size shows a window of the photo (reframeWindow): its crop is bound on
    // its own; the whole photo is bound once for the sizes that show it all.
    std::vector<cv::Rect> crops;
    for (const cv::Size& s : sizes) crops.push_back(reframeCrop(cage, s, rp));
    const cv::Rect whole(cv::Point(), image.size());
    const bool anyWhole = std::count(crops.begin(), crops.end(), whole) > 0;
    const auto tb = std::chrono::steady_clock::now();
    const cv::Ptr<Deformer> deformer =
        anyWhole ? createWithProgress("resize", o.quiet, image, cage, params) : nullptr;
    const double bindMs = msSince(tb);
    if (!o.quiet)
        std::cout << "multicage resize: " << o.image << " " << image.cols << "x" << image.rows
                  << ", "
                  << (o.cage.empty()
                          ? "proposed multicage (" + std::to_string(cvRound(proposeMs)) + " ms)"
                          : o.cage)
                  << ": " << plural(cage.polygonCount(), "polygon") << ", "
                  << plural(cage.vertexCount(), "vertex", "vertices") << "; "
                  << coordinateTypeDescription(params.coordinates == COORDINATES_FROM_CAGE
                                                   ? cage.coordinates()
                                                   : params.coordinates)
                  << " coordinates, grid step " << params.gridStep
                  << (stepChange.empty() ? "" : " (" + stepChange + ")")
                  << (anyWhole ? ", bind " + std::to_string(cvRound(bindMs)) + " ms" : "")
                  << std::endl;
    for (size_t k = 0; k < sizes.size(); ++k) {
        const auto ts = std::chrono::steady_clock::now();
        cv::Ptr<Deformer> d = deformer;
        Multicage rest = cage;
        std::string window;
        if (crops[k] != whole) {
            rest = cropMulticage(cage, crops[k]);
            d = createWithProgress("resize", o.quiet, image(crops[k]), rest, params);
            window = cv::format("a %dx%d window at (%d, %d), bind %d ms, ", crops[k].width,
                                crops[k].height, crops[k].x, crops[k].y, cvRound(msSince(ts)));
        }
        const auto tp = std::chrono::steady_clock::now();
        const std::vector<cv::Point2f> pose = resizePose(rest, d->binding(), sizes[k], rp);
        cv::Mat out;
        d->deform(pose, out);
        const double ms = msSince(tp);
        const std::string path = outputFor(o.output, sizes[k], sizes.size() > 1);
        writeImage("resize", path, out);
        if (k == 0 && !o.overlay.empty())
            writeImage("resize", o.overlay, overlayPicture(image(crops[k]), rest, out, pose));
        std::cout << "wrote " << path << " (" << out.cols << "x" << out.rows << ", " << window
                  << "pose and deform " << cvRound(ms) << " ms, " << backendName(d->backend())
                  << ")" << std::endl;
    }
    if (!o.overlay.empty())
        std::cout << "wrote " << o.overlay << " (the cage at rest and resized)" << std::endl;
    if (!o.quiet) std::cout << "total " << cvRound(msSince(t0)) << " ms" << std::endl;
    if (o.cage.empty() && !o.quiet) {
        ProposeParams propose;  // resizeCage()'s
        propose.segmenter = rp.segmenter;
        propose.segmenterModel = rp.segmenterModel;
        const std::string cue = subjectCueNote(propose);
        if (!cue.empty()) std::cerr << "multicage resize: note: " << cue << std::endl;
    }
}
}  // namespace

void addResizeCommand(CLI::App& app) {
    auto o = std::make_shared<ResizeCommandOptions>();
    CLI::App* cmd = app.add_subcommand(
        "resize",
        std::string() +
            "Resize IMAGE (a photo or a clip) to another size or aspect ratio keeping faces and "
            "subjects in shape (content-aware resizing).\n"
            "The image is bound once to a multicage (proposed: an outline around each subject, "
            "inner polygons around faces and features; or --cage), then each size is one pose: "
            "the frame goes to the new frame, each subject and what it holds moves by a "
            "similarity (it keeps its size in pixels where the new frame allows), and the "
            "background absorbs the aspect change. Several --size bind once and write "
            "OUT_WxH.ext each.\n"
            "Past --max-warp (16:9 to 9:16, say) the output shows a window of the image that "
            "keeps every subject it can, as a crop would, and the warp takes the rest: subjects "
            "far apart are brought together, a face wider than the window is cut, not squeezed.\n"
            "A clip (.mp4, .m4v, .mov, .mkv, .avi, .webm) is reframed frame by frame: the "
            "multicage follows its subjects (proposed again at cuts), windows and poses are "
            "averaged over --smoothing frames each side, and the frame rate and audio are "
            "carried over; Ctrl-C or an error leaves no output.\n" +
            subjectCueHelp() + "\n" +
            "Examples:\n"
            "  multicage resize photo.jpg -o wide.png --aspect 16:9\n"
            "  multicage resize photo.jpg -o out.png --size 1536x768 --size 717x768 --overlay "
            "cage.png\n"
            "  multicage resize clip.mp4 -o vertical.mp4 --aspect 9:16");
    cmd->add_option("IMAGE", o->image, "Input image or clip")->required();
    cmd->add_option("-o,--output", o->output,
                    "Output image (with several sizes: OUT_WxH.ext each), or clip")
        ->required();
    cmd->add_option("--size", o->sizes, "Target size WxH; repeat for several sizes (one binding)");
    cmd->add_option("--width", o->width, "Target width (the height stays, unless --height)")
        ->check(wholeNumber(1, 1 << 20));
    cmd->add_option("--height", o->height, "Target height (the width stays, unless --width)")
        ->check(wholeNumber(1, 1 << 20));
    cmd->add_option("--aspect", o->aspect, "Target aspect ratio W:H (e.g. 16:9); the height stays");
    cmd->add_option("--cage", o->cage,
                    "Multicage file to use instead of the proposal (scaled to the image)");
    cmd->add_option("--overlay", o->overlay,
                    "Also write the cage at rest and resized, side by side (first size)");
    cmd->add_option("--protect", o->protect,
                    "What the proposal protects inside each outline: saliency, faces or all "
                    "(default: the proposal's)");
    cmd->add_flag("--no-protect", o->noProtect,
                  "Outlines only: the proposal without inner polygons (faces and features bend "
                  "with their subject)")
        ->excludes("--protect")
        ->excludes("--cage");
    cmd->add_option("--max-scale", o->maxScale,
                    "Largest factor a side may grow by (a guard against a typo's huge output)")
        ->capture_default_str()
        ->check(CLI::Range(1.0, 1000.0));
    cmd->add_option("--max-warp", o->maxWarp,
                    "Largest aspect change the warp takes alone; past it the output shows a "
                    "window of the image that keeps every subject it can (0: never crop)")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1000.0));
    cmd->add_option("--smoothing", o->smoothing,
                    "Clips: frames on each side that windows and poses are averaged over (the "
                    "output runs twice as many behind; 0: none)")
        ->capture_default_str()
        ->check(wholeNumber(0, 100));
    addSegmenterOptions(cmd, o->segmenter);
    addDeformOptions(cmd, o->deform, cv::multicage::ResizeParams().coordinates);
    cmd->add_flag("-q,--quiet", o->quiet, "Print only the files written");
    cmd->callback([o]() { runResize(*o); });
}

}  // namespace multicage_cli

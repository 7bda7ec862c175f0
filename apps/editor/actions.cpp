#include <epoxy/gl.h>
// GLFW after epoxy: epoxy must be the one GL header.
#include <GLFW/glfw3.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/multicage.hpp>
#include <opencv2/multicage/resize.hpp>
#include <set>
#include <stdexcept>
#include <string>

#include "actions.hpp"
#include "view.hpp"

namespace multicage_editor {

using cv::Point2f;

// ---------------------------------------------------------------------------------------
// Document helpers.

bool samePolygons(const mc::Multicage& a, const mc::Multicage& b) {
    if (a.imageSize() != b.imageSize() || a.polygonCount() != b.polygonCount()) return false;
    for (int i = 0; i < a.polygonCount(); ++i)
        if (a.polygon(i) != b.polygon(i)) return false;
    return true;
}

void updateValidity(Editor& e) {
    e.restWhy.clear();
    e.poseWhy.clear();
    e.restOk = restValid(e.doc, &e.restWhy);
    e.poseOk = e.restOk && poseValid(e.doc, &e.poseWhy);
    if (e.restOk && e.poseOk) {
        e.shown = e.doc;
    } else if (e.restOk && samePolygons(e.doc.cage, e.shown.cage)) {
        // Pose invalid: keep the last valid pose, but follow rest-level settings.
        e.shown.cage = e.doc.cage;
    }
}

void afterEdit(Editor& e) {
    if (e.mode == Mode::Rest && e.drag == Drag::None && orientDocument(e.doc)) e.selection.clear();
    updateValidity(e);
}

void edit(Editor& e) {
    e.history.push(e.doc);
}

void setDocument(Editor& e, const Document& d) {
    e.doc = d;
    e.selection.clear();
    e.creating = false;
    e.creation.clear();
    afterEdit(e);
}

// ---------------------------------------------------------------------------------------
// Actions.

namespace {

/** The live view's grid step: the smallest with at most ~16k mesh nodes, so that a pose
update stays interactive on a software renderer (llvmpipe); export uses its own step. */
int defaultGridStep(cv::Size size) {
    int step = 2;
    while (mc::gridSizeFor(size, step).area() > 16384) ++step;
    return step;
}

/** The document becomes `cage`, bound with the coordinates the cage asks for (as `multicage
deform` follows a cage file): a loaded cage file's, a proposal's (local mean value: what an
inner polygon holds follows it alone). */
void adoptCage(Editor& e, Settings& s, const mc::Multicage& cage) {
    setDocument(e, makeDocument(cage));
    s.coordinates = cage.coordinates();
}

}  // namespace

void openImage(Editor& e, View& v, Settings& s, const std::string& path) {
    cv::Mat img;
    try {
        img = mc::readImage(path);  // refuses truncated JPEG and PNG files
    } catch (const cv::Exception& ex) {
        throw std::runtime_error(ex.err);
    }
    if (img.depth() != CV_8U && img.depth() != CV_16U && img.depth() != CV_32F)
        throw std::runtime_error(path + ": unsupported pixel type (8U, 16U or 32F only)");
    e.image = img;
    e.imagePath = path;
    e.resizeTo = img.size();
    s.gridStep = defaultGridStep(img.size());
    uploadImageTexture(v, displayImage(img));
    v.deformer.reset();
    v.boundCoords = -1;
    v.rendered = false;
    e.history.clear();
    e.mode = Mode::Rest;
    e.fitPending = true;
    setDocument(e, makeDocument(img.size()));
    e.shown = e.doc;
    e.message =
        "opened " + path + " (" + std::to_string(img.cols) + "x" + std::to_string(img.rows) + ")";
}

std::string count(int n, const char* one, const char* many) {
    return std::to_string(n) + " " + (n == 1 ? one : many);
}

void openCage(Editor& e, const std::string& path, Settings& s) {
    if (e.image.empty()) throw std::runtime_error("open an image first");
    mc::Multicage cage = mc::Multicage::load(path);
    if (cage.imageSize() != e.image.size()) cage = cage.scaled(e.image.size());
    edit(e);
    adoptCage(e, s, cage);
    e.cagePath = path;
    e.message = "loaded " + path + ": " + count(cage.polygonCount(), "polygon", "polygons") + ", " +
                count(cage.poseCount(), "pose", "poses");
}

void saveCage(Editor& e, const std::string& path, const Settings& s) {
    if (!e.restOk) throw std::runtime_error("not saved: " + e.restWhy);
    // As `multicage deform` and `animate` refuse them: a crossing pose folds the image.
    for (int i = 0; i < e.doc.cage.poseCount() && !s.allowInvalid; ++i) {
        std::string why;
        const mc::Pose& pose = e.doc.cage.pose(i);
        if (!mc::validatePose(e.doc.cage, pose.vertices, &why))
            throw std::runtime_error("not saved: pose '" + pose.name + "' is invalid: " + why +
                                     " (fix it, or start the editor with --allow-invalid)");
    }
    Document d = e.doc;
    d.cage.setCoordinates(s.coordinates);
    d.cage.save(path);
    e.cagePath = path;
    e.message = "saved " + path;
}

void exportImage(Editor& e, const std::string& path, const Settings& s, GLFWwindow* window) {
    if (e.image.empty()) throw std::runtime_error("open an image first");
    // The GPU Deformer makes its own EGL context current; libglvnd refuses that while this
    // thread has the window's GLX context current (EGL_BAD_ACCESS), so let go of it meanwhile.
    struct Release {
        GLFWwindow* w;
        explicit Release(GLFWwindow* win) : w(win) { glfwMakeContextCurrent(nullptr); }
        ~Release() { glfwMakeContextCurrent(w); }
    } release(window);
    // The same library call as `multicage deform`: Deformer::create + deform + imwriteAtomic.
    mc::DeformParams params;
    params.coordinates = s.coordinates;
    params.gridStep = s.exportGridStep;
    const auto t0 = Clock::now();
    cv::Ptr<mc::Deformer> deformer = mc::Deformer::create(e.image, e.shown.cage, params);
    cv::Mat out;
    // Resize mode: the resize pose on this deformer's own binding (as `multicage resize`).
    const bool resizing = e.mode == Mode::Resize;
    deformer->deform(
        resizing ? mc::resizePose(e.shown.cage, deformer->binding(), e.resizeTo) : e.shown.pose,
        out);
    std::string
        note;  // e.g. a float image exported to .png: stored as 16 bits, said in the message
    mc::imwriteAtomic(path, mc::convertForImageFormat(path, out, &note));
    e.exportPath = path;
    char buf[1200];
    if (resizing)  // where it went, in full: the size a user asked for is easy to lose
        std::snprintf(buf, sizeof buf, "saved the %dx%d resized image to %s (%s, %.0f ms)",
                      out.cols, out.rows, std::filesystem::absolute(path).string().c_str(),
                      deformer->backend() == mc::BACKEND_GPU ? "GPU" : "CPU", msSince(t0));
    else
        std::snprintf(buf, sizeof buf, "exported %s (%dx%d, %s, %.0f ms)", path.c_str(), out.cols,
                      out.rows, deformer->backend() == mc::BACKEND_GPU ? "GPU" : "CPU",
                      msSince(t0));
    e.message = buf;
    if (!note.empty()) e.message += "; " + note;
}

void propose(Editor& e, Settings& s) {
    if (e.image.empty()) throw std::runtime_error("open an image first");
    const auto t0 = Clock::now();
    // As `multicage propose` with no flags: the library's default (outlines plus inner
    // polygons protecting the faces and the salient features inside them).
    const mc::ProposeParams params;
    mc::Multicage cage = mc::proposeProtectedMulticage(e.image, params);
    edit(e);
    if (e.mode == Mode::Resize) e.fitPending = true;  // back to the image's own size
    e.mode = Mode::Rest;
    adoptCage(e, s, cage);
    // Which subject cue ran: the learned model when the default found one, else the classic
    // segmentation (and how to get the model).
    const cv::String model = mc::segmenterModelFile(params);
    const std::string cue =
        model.empty()
            ? "classic segmentation: no subject model installed (run .ci/deps.sh, docs/models.md)"
            : "subject model " + std::filesystem::path(model).filename().string();
    e.message = "proposed " + count(cage.polygonCount(), "polygon", "polygons") + ", " +
                count(cage.vertexCount(), "vertex", "vertices") + " (" + cue + ", " +
                std::to_string(cvRound(msSince(t0))) + " ms)";
}

void setMode(Editor& e, Mode m) {
    if (m != Mode::Rest && !e.restOk) {
        e.message = std::string("fix the rest multicage before ") +
                    (m == Mode::Pose ? "posing: " : "resizing: ") + e.restWhy;
        return;
    }
    e.creating = false;
    e.creation.clear();
    // Resize mode shows another size: fit the view to it on the way in and out.
    if ((m == Mode::Resize) != (e.mode == Mode::Resize)) e.fitPending = true;
    if (m == Mode::Resize && e.resizeTo.area() <= 0) e.resizeTo = e.image.size();
    e.mode = m;
    e.message = m == Mode::Rest   ? "rest mode: edit the polygons"
                : m == Mode::Pose ? "pose mode: drag vertices to deform"
                                  : "resize mode: drag the frame's right or bottom edge, or type a "
                                    "size in the panel";
}

void finishPolygon(Editor& e) {
    if (e.creation.size() >= 3) {
        edit(e);
        addPolygon(e.doc, e.creation);
        e.message = "polygon " + std::to_string(e.doc.cage.polygonCount() - 1) + " added";
    } else {
        e.message = "a polygon needs at least 3 vertices";
    }
    e.creating = false;
    e.creation.clear();
    afterEdit(e);
}

void deleteSelection(Editor& e, bool wholePolygons) {
    if (e.mode != Mode::Rest || e.selection.empty()) return;
    edit(e);
    if (wholePolygons) {
        std::set<int> polys;
        for (int id : e.selection) polys.insert(locateVertex(e.doc.cage, id).first);
        for (auto it = polys.rbegin(); it != polys.rend(); ++it) removePolygon(e.doc, *it);
    } else {
        removeVertices(e.doc, e.selection);
    }
    e.selection.clear();
    afterEdit(e);
}

void undo(Editor& e) {
    if (e.history.undo(e.doc)) {
        e.selection.clear();
        afterEdit(e);
        if (!e.restOk) setMode(e, Mode::Rest);
    }
}

void redo(Editor& e) {
    if (e.history.redo(e.doc)) {
        e.selection.clear();
        afterEdit(e);
        if (!e.restOk) setMode(e, Mode::Rest);
    }
}

void selectPolygonOf(Editor& e, int polygon) {
    e.selection.clear();
    const int offset = e.doc.cage.polygonOffset(polygon);
    for (size_t k = 0; k < e.doc.cage.polygon(polygon).size(); ++k)
        e.selection.push_back(offset + static_cast<int>(k));
}

// ---------------------------------------------------------------------------------------
// Animation: keyframes are the cage's timed poses; playback moves only the shown pose.

void addKeyframeHere(Editor& e) {
    edit(e);
    mc::addKeyframe(e.doc.cage, e.doc.pose, e.keyTime);
    afterEdit(e);
    e.message = cv::format("keyframe at %.2f s (%d keyframes)", e.keyTime, e.doc.cage.poseCount());
    e.keyTime += 1.f;
}

void setPlaying(Editor& e, bool play) {
    std::string why;
    if (play && !mc::validateKeyframes(e.doc.cage, &why))
        throw std::runtime_error("cannot play: " + why);
    e.playing = play;
    e.playStart = Clock::now();
    if (play)
        setMode(e, Mode::Pose);
    else
        updateValidity(e);  // back to the edited pose
}

void advancePlayback(Editor& e) {
    if (!e.playing) return;
    std::string why;
    if (!e.restOk || e.mode != Mode::Pose || !mc::validateKeyframes(e.shown.cage, &why)) {
        e.playing = false;
        return;
    }
    const double period = mc::animationDuration(e.shown.cage, e.loop);
    double t = std::chrono::duration<double>(Clock::now() - e.playStart).count();
    t = e.loop ? std::fmod(t, period) : std::min(t, period);
    e.playhead = mc::animationStart(e.shown.cage) + t;
    e.shown.pose = mc::samplePose(e.shown.cage, e.playhead, mc::INTERPOLATE_CATMULL_ROM, e.loop);
}

}  // namespace multicage_editor

// The editor's state: plain structs, shared by the canvas, the side panel and the script
// runner. The document and its edits are in document.hpp.
#ifndef MULTICAGE_EDITOR_EDITOR_STATE_HPP
#define MULTICAGE_EDITOR_EDITOR_STATE_HPP

#include <epoxy/gl.h>

#include <chrono>
#include <memory>
#include <opencv2/multicage.hpp>
#include <string>
#include <vector>

#include "document.hpp"

struct GLFWwindow;

namespace multicage_editor {

namespace mc = cv::multicage;

using Clock = std::chrono::steady_clock;
inline double msSince(Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

// Layout: the side panel on the left, the canvas right of it (scripted input is placed there).
const float kPanelWidth = 340.f;

struct Settings {
    int coordinates = mc::MEAN_VALUE;
    int gridStep = 4;        // live view: defaultGridStep() of each image opened
    int exportGridStep = 1;  // export: the paper's one node per pixel, as `multicage deform`
    bool showCage = true;
    bool showHelp = false;
    bool allowInvalid = false;  // --allow-invalid: save poses whose polygons cross
};

enum class Drag { None, Vertices, Box, Pan, Frame };

/** The frame edges a Drag::Frame moves (resize mode). */
enum FrameEdge { kFrameRight = 1, kFrameBottom = 2 };

struct Editor {
    std::string imagePath, cagePath = "cage.yml", exportPath = "deformed.png";
    cv::Mat image;   // as read (BGR): what export deforms
    Document doc;    // what the user edits
    Document shown;  // the last valid document: what the view deforms
    History history{200};
    Mode mode = Mode::Rest;
    std::vector<int> selection;  // vertex ids, vertices() order
    bool creating = false;       // a polygon being clicked in
    std::vector<cv::Point2f> creation;
    Drag drag = Drag::None;
    cv::Point2f dragStart, dragLast;  // image coordinates
    Document beforeDrag;
    bool dragMoved = false;
    int frameEdges = 0;  // FrameEdge bits of a Drag::Frame
    // Resize mode: the size the image is resized to (the image's own until the user drags a
    // frame edge or types a size); a view setting like the zoom, not part of the document.
    cv::Size resizeTo;
    bool restOk = true, poseOk = true;
    std::string restWhy, poseWhy;
    std::string message;
    char poseName[64] = "pose1";
    // Animation (issue 9): the cage's timed poses are keyframes; playback shows samplePose().
    bool playing = false, loop = true;
    Clock::time_point playStart;
    float keyTime = 0.f;  // seconds: where "Add keyframe" puts the current pose
    double playhead = 0;  // seconds, while playing
    // view transform: screen = origin + zoom * (p + 0.5) + pan
    float zoom = 1.f;
    cv::Point2f pan;
    bool fitPending = true;
    cv::Size2f canvasArea;  // the canvas at the last frame: a change (window resized) refits
};

struct View {
    GLuint imageTexture = 0;
    std::unique_ptr<mc::GLDeformer> deformer;
    mc::Multicage boundRest;  // rest multicage of the binding
    int boundCoords = -1, boundStep = -1;
    mc::Binding binding;
    cv::Mat restNodes;
    double bindMs = 0;
    std::vector<cv::Point2f> renderedPose;  // the pose set last (a resize pose: with its frame)
    // Resize mode: the pose of resizeTo (vertexCount() + 4 points, frame corners last) and the
    // time resizePose() took for it.
    std::vector<cv::Point2f> resizePose;
    cv::Size resizedTo;
    int bindings = 0, resizedBinding = -1;  // bindings made; the one resizePose was made on
    double resizePoseMs = 0;
    bool rendered = false;
    int folded = 0;
    double frameMs = 0, renderMs = 0, foldMs = 0, uiMs = 0, drawMs = 0;
    bool finishForTiming = false;  // bench: glFinish after render, so its time is its own
    std::string error;
};

}  // namespace multicage_editor

#endif

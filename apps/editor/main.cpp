// multicage-editor [IMAGE [CAGE.yml]] [--script FILE]: draw or propose a multicage over an
// image, drag its vertices and see the deformation live.
//
// One flat loop (poll, new frame, describe the UI, render, swap) over plain structs: the
// document and its edits are in document.cpp, the deformation in the library (GLDeformer
// draws into a texture of this window's own GL context: no readback per frame).
#include <epoxy/gl.h>
// GLFW after epoxy: epoxy must be the one GL header.
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/multicage.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <deque>
#include <fstream>
#include <iostream>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "actions.hpp"
#include "document.hpp"
#include "editor_state.hpp"
#include "script.hpp"
#include "view.hpp"

using namespace multicage_editor;
using cv::Point2f;

namespace {

const float kStatusHeight = 26.f;
const float kPickRadius = 8.f;  // screen pixels

// Overlay colours: polygons by depth (1, 2, 3, ...), red when invalid.
const ImU32 kDepthColours[] = {IM_COL32(255, 196, 0, 255), IM_COL32(0, 220, 255, 255),
                               IM_COL32(255, 90, 220, 255), IM_COL32(120, 255, 90, 255)};
const ImU32 kInvalid = IM_COL32(255, 40, 40, 255);
const ImU32 kHandle = IM_COL32(255, 255, 0, 255);  // vertex handle fill (the test looks for it)
const ImU32 kSelected = IM_COL32(255, 100, 0, 255);
const ImU32 kOutline = IM_COL32(20, 20, 20, 255);

// ---------------------------------------------------------------------------------------
// Scripted mode state (the editor state is in editor_state.hpp).

struct Script {
    std::vector<ScriptCommand> commands;
    size_t next = 0;
    int waitFrames = 0;
    int benchFrames = 0, benchVertex = 0, benchFrame = 0;
    std::vector<Point2f> benchStart;
    std::vector<double> benchTimes, benchRender, benchFold, benchDraw;
    std::string screenshotPath, lastMessage;
    /** Synthetic input, one entry per frame (click, mouse-drag, key): fed to ImGui exactly
    where the GLFW backend's input goes, so the canvas code paths run as for a user. */
    struct Input {
        Point2f at;  // image coordinates
        bool down = false, shift = false, ctrl = false;
        int key = -1;  // a GLFW key held this frame
    };
    std::deque<Input> input;
    int heldKey = -1;
    bool failed = false;
    bool active() const { return !commands.empty(); }
};

// ---------------------------------------------------------------------------------------
// The canvas: image, overlay, mouse.

ImVec2 toScreen(const Editor& e, ImVec2 origin, Point2f p) {
    return ImVec2(origin.x + e.zoom * (p.x + 0.5f) + e.pan.x, origin.y + e.zoom * (p.y + 0.5f) + e.pan.y);
}
Point2f toImage(const Editor& e, ImVec2 origin, ImVec2 q) {
    return Point2f((q.x - origin.x - e.pan.x) / e.zoom - 0.5f, (q.y - origin.y - e.pan.y) / e.zoom - 0.5f);
}

void drawOverlay(const Editor& e, ImDrawList* dl, ImVec2 origin) {
    const std::vector<Point2f> pts = positions(e.doc, e.mode);
    const bool bad = e.mode == Mode::Rest ? !e.restOk : !e.poseOk;
    const std::set<int> selected(e.selection.begin(), e.selection.end());
    const mc::Multicage& cage = e.doc.cage;
    for (int i = 0; i < cage.polygonCount(); ++i) {
        int depth = 1;
        try {
            depth = cage.depth(i);
        } catch (const std::exception&) {
        }
        const ImU32 colour = bad ? kInvalid : kDepthColours[(std::max(depth, 1) - 1) % 4];
        const int offset = cage.polygonOffset(i);
        const int n = static_cast<int>(cage.polygon(i).size());
        std::vector<ImVec2> poly;
        for (int k = 0; k < n; ++k) poly.push_back(toScreen(e, origin, pts[static_cast<size_t>(offset + k)]));
        dl->AddPolyline(poly.data(), n, IM_COL32(0, 0, 0, 160), ImDrawFlags_Closed, 4.f);
        dl->AddPolyline(poly.data(), n, colour, ImDrawFlags_Closed, 2.f);
    }
    for (size_t i = 0; i < pts.size(); ++i) {
        const ImVec2 c = toScreen(e, origin, pts[i]);
        const float r = selected.count(static_cast<int>(i)) ? 5.f : 4.f;
        dl->AddRectFilled(ImVec2(c.x - r - 1, c.y - r - 1), ImVec2(c.x + r + 1, c.y + r + 1), kOutline);
        dl->AddRectFilled(ImVec2(c.x - r, c.y - r), ImVec2(c.x + r, c.y + r),
                          selected.count(static_cast<int>(i)) ? kSelected : kHandle);
    }
    if (e.creating && !e.creation.empty()) {
        std::vector<ImVec2> poly;
        for (const Point2f& p : e.creation) poly.push_back(toScreen(e, origin, p));
        poly.push_back(ImGui::GetIO().MousePos);
        dl->AddPolyline(poly.data(), static_cast<int>(poly.size()), IM_COL32(255, 255, 255, 230), 0, 2.f);
        for (size_t k = 0; k < e.creation.size(); ++k)
            dl->AddCircleFilled(poly[k], k == 0 ? 6.f : 4.f, k == 0 ? kSelected : kHandle);
    }
}

void canvasMouse(Editor& e, ImVec2 origin, bool hovered) {
    ImGuiIO& io = ImGui::GetIO();
    const Point2f m = toImage(e, origin, io.MousePos);
    const float radius = kPickRadius / e.zoom;
    const std::vector<Point2f> pts = positions(e.doc, e.mode);

    if (hovered && io.MouseWheel != 0.f) {  // zoom about the cursor
        const float z = std::min(32.f, std::max(0.05f, e.zoom * std::pow(1.15f, io.MouseWheel)));
        e.pan.x += (m.x + 0.5f) * (e.zoom - z);
        e.pan.y += (m.y + 0.5f) * (e.zoom - z);
        e.zoom = z;
    }
    if (hovered && (ImGui::IsMouseClicked(ImGuiMouseButton_Middle) || ImGui::IsMouseClicked(ImGuiMouseButton_Right)))
        e.drag = Drag::Pan;
    if (e.drag == Drag::Pan) {
        e.pan.x += io.MouseDelta.x;
        e.pan.y += io.MouseDelta.y;
        if (!ImGui::IsMouseDown(ImGuiMouseButton_Middle) && !ImGui::IsMouseDown(ImGuiMouseButton_Right))
            e.drag = Drag::None;
        return;
    }

    if (hovered && ImGui::IsMouseDoubleClicked(ImGuiMouseButton_Left) && e.mode == Mode::Rest && !e.creating) {
        int poly, edgeIndex;
        float t;
        if (hitVertex(pts, m, radius) < 0 && hitEdge(e.doc.cage, pts, m, radius, &poly, &edgeIndex, &t)) {
            edit(e);
            const int id = insertVertex(e.doc, poly, edgeIndex, t);
            e.selection = {id};
            e.drag = Drag::None;
            afterEdit(e);
            e.message = "vertex inserted on polygon " + std::to_string(poly) + ", edge " + std::to_string(edgeIndex);
            return;
        }
    }

    if (hovered && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
        if (e.creating) {
            if (e.creation.size() >= 3 && hitVertex({e.creation[0]}, m, radius) == 0) {
                finishPolygon(e);
            } else {
                e.creation.push_back(m);
            }
            return;
        }
        const int v = hitVertex(pts, m, radius);
        const bool wholePolygon = io.KeyCtrl || io.KeyAlt;
        const int poly = v >= 0 ? locateVertex(e.doc.cage, v).first : hitPolygon(e.doc.cage, pts, m);
        if (wholePolygon && poly >= 0) {
            selectPolygonOf(e, poly);
        } else if (v >= 0) {
            const bool isSelected = std::find(e.selection.begin(), e.selection.end(), v) != e.selection.end();
            if (io.KeyShift) {
                if (isSelected) e.selection.erase(std::find(e.selection.begin(), e.selection.end(), v));
                else e.selection.push_back(v);
            } else if (!isSelected) {
                e.selection = {v};
            }
        } else {
            e.drag = Drag::Box;
            e.dragStart = e.dragLast = m;
            return;
        }
        if (!e.selection.empty() && (v >= 0 || wholePolygon)) {
            e.drag = Drag::Vertices;
            e.dragStart = e.dragLast = m;
            e.beforeDrag = e.doc;
            e.dragMoved = false;
        }
        return;
    }

    if (e.drag == Drag::Vertices) {
        if (m != e.dragLast) {
            moveVertices(e.doc, e.mode, e.selection, m - e.dragLast);
            e.dragLast = m;
            e.dragMoved = true;
            updateValidity(e);
        }
        if (!ImGui::IsMouseDown(ImGuiMouseButton_Left)) {
            e.drag = Drag::None;
            if (e.dragMoved) {
                e.history.push(e.beforeDrag);
                afterEdit(e);
            }
        }
    } else if (e.drag == Drag::Box) {
        e.dragLast = m;
        if (!ImGui::IsMouseDown(ImGuiMouseButton_Left)) {
            e.drag = Drag::None;
            const Point2f d = e.dragLast - e.dragStart;
            if (std::abs(d.x) * e.zoom < 3 && std::abs(d.y) * e.zoom < 3) {
                // A click on empty canvas: clear the selection, or start a polygon (rest mode).
                int poly, edgeIndex;
                float t;
                if (!e.selection.empty() || io.KeyShift ||
                    hitEdge(e.doc.cage, pts, e.dragStart, radius, &poly, &edgeIndex, &t)) {
                    e.selection.clear();  // (a click on an edge may be the first of a double-click)
                } else if (e.mode == Mode::Rest) {
                    e.creating = true;
                    e.creation = {e.dragStart};
                    e.message = "new polygon: click to add vertices, click the first one or Enter to close, Esc cancels";
                }
            } else {
                const cv::Rect2f box(std::min(e.dragStart.x, m.x), std::min(e.dragStart.y, m.y), std::abs(d.x),
                                     std::abs(d.y));
                if (!io.KeyShift) e.selection.clear();
                for (size_t i = 0; i < pts.size(); ++i)
                    if (box.contains(pts[i]) &&
                        std::find(e.selection.begin(), e.selection.end(), static_cast<int>(i)) == e.selection.end())
                        e.selection.push_back(static_cast<int>(i));
            }
        }
    }
}

void keyboard(Editor& e, Settings& s, GLFWwindow* window) {
    ImGuiIO& io = ImGui::GetIO();
    if (io.WantTextInput) return;
    const bool ctrl = io.KeyCtrl;
    auto pressed = [](int key) { return ImGui::IsKeyPressed(key, false); };
    if (ctrl && pressed(GLFW_KEY_Z)) io.KeyShift ? redo(e) : undo(e);
    if (ctrl && pressed(GLFW_KEY_Y)) redo(e);
    if (ctrl && pressed(GLFW_KEY_S)) {
        try {
            saveCage(e, e.cagePath, s);
        } catch (const std::exception& ex) {
            e.message = ex.what();
        }
    }
    if (ctrl && pressed(GLFW_KEY_A)) {
        e.selection.clear();
        for (size_t i = 0; i < positions(e.doc, e.mode).size(); ++i) e.selection.push_back(static_cast<int>(i));
    }
    if (ctrl && pressed(GLFW_KEY_Q)) glfwSetWindowShouldClose(window, 1);
    if (ctrl) return;
    if (pressed(GLFW_KEY_TAB)) setMode(e, e.mode == Mode::Rest ? Mode::Pose : Mode::Rest);
    if (pressed(GLFW_KEY_H) || pressed(GLFW_KEY_F1)) s.showHelp = !s.showHelp;
    if (pressed(GLFW_KEY_C)) s.showCage = !s.showCage;
    if (pressed(GLFW_KEY_F)) e.fitPending = true;
    if (pressed(GLFW_KEY_K)) {
        try {
            addKeyframeHere(e);
        } catch (const std::exception& ex) {
            e.message = ex.what();
        }
    }
    if (pressed(GLFW_KEY_P)) {
        try {
            setPlaying(e, !e.playing);
        } catch (const std::exception& ex) {
            e.message = ex.what();
        }
    }
    if (pressed(GLFW_KEY_DELETE) || pressed(GLFW_KEY_BACKSPACE)) {
        if (e.creating && !e.creation.empty()) e.creation.pop_back();
        else deleteSelection(e, io.KeyShift);
    }
    if (e.creating && (pressed(GLFW_KEY_ENTER) || pressed(GLFW_KEY_KP_ENTER))) finishPolygon(e);
    if (pressed(GLFW_KEY_ESCAPE)) {
        if (e.creating) e.message = "polygon cancelled";
        e.creating = false;
        e.creation.clear();
        e.selection.clear();
    }
}

const char* kHelp =
    "Rest mode (Tab toggles): edit the polygons\n"
    "  click empty canvas       start a polygon; click to add vertices,\n"
    "                           click the first vertex or Enter to close,\n"
    "                           Backspace removes the last, Esc cancels\n"
    "  click / shift-click      select a vertex / add to the selection\n"
    "  drag on empty canvas     box select (shift: add)\n"
    "  drag a vertex            move the selected vertices\n"
    "  Ctrl- or Alt-drag        move a whole polygon\n"
    "  double-click an edge     insert a vertex\n"
    "  Delete                   delete selected vertices (< 3 left: the polygon)\n"
    "  Shift+Delete             delete the polygons of the selection\n"
    "Pose mode: drag vertices (Ctrl/Alt: whole polygon); the image follows\n"
    "Animation: K stores the pose as a keyframe at the time shown, P plays / stops\n"
    "View: wheel zooms, right/middle drag pans, F fits, C shows/hides the cage\n"
    "Ctrl+Z / Ctrl+Y (Ctrl+Shift+Z) undo / redo, Ctrl+S save, Ctrl+A select all\n"
    "H or F1 this help, Ctrl+Q quit\n"
    "Red polygons: the edit is invalid (reason in the status line);\n"
    "the view keeps the last valid binding and pose.";

// ---------------------------------------------------------------------------------------
// Scripted mode: one command per frame (wait N: N frames).

void writeStatus(const Editor& e, const View& v, const Settings& s, const std::string& path) {
    std::ostringstream o;
    o << "mode: " << (e.mode == Mode::Rest ? "rest" : "pose") << "\n"
      << "rest_valid: " << e.restOk << "\nrest_reason: " << e.restWhy << "\n"
      << "pose_valid: " << e.poseOk << "\npose_reason: " << e.poseWhy << "\n"
      << "polygons: " << e.doc.cage.polygonCount() << "\nvertices: " << e.doc.cage.vertexCount() << "\n"
      << "poses: " << e.doc.cage.poseCount() << "\nundo: " << e.history.undoCount() << "\n"
      << "playing: " << e.playing << "\nplayhead: " << e.playhead << "\n"
      << "folded: " << v.folded << "\nmin_conditioning: " << v.binding.minConditioning << "\n"
      << "bind_ms: " << v.bindMs << "\ngrid_step: " << s.gridStep << "\ncoordinates: "
      << (s.coordinates == mc::HARMONIC ? "harmonic" : "mean_value") << "\n"
      << "selection:";
    for (int i : e.selection) o << " " << i;
    o << "\nrest:";
    for (const Point2f& p : positions(e.doc, Mode::Rest)) o << " " << p.x << " " << p.y;
    o << "\nshown_pose:";
    for (const Point2f& p : e.shown.pose) o << " " << p.x << " " << p.y;
    o << "\nmessage: " << e.message << "\n";
    mc::writeFileAtomic(path, o.str());
}

int keyByName(const std::string& name) {
    static const std::pair<const char*, int> keys[] = {
        {"delete", GLFW_KEY_DELETE}, {"backspace", GLFW_KEY_BACKSPACE}, {"enter", GLFW_KEY_ENTER},
        {"escape", GLFW_KEY_ESCAPE}, {"tab", GLFW_KEY_TAB}, {"f1", GLFW_KEY_F1}};
    for (const auto& k : keys)
        if (name == k.first) return k.second;
    if (name.size() == 1 && std::isalpha(static_cast<unsigned char>(name[0])))
        return GLFW_KEY_A + (std::tolower(static_cast<unsigned char>(name[0])) - 'a');
    throw std::runtime_error("unknown key '" + name + "'");
}

/** click X Y [shift|ctrl], double-click X Y, mouse-drag X0 Y0 X1 Y1 [shift|ctrl], key NAME
[shift|ctrl]: frames of synthetic input, positions in image coordinates. */
void queueInput(Script& sc, const ScriptCommand& c) {
    Script::Input in;
    size_t numbers = c.verb == "mouse-drag" ? 4 : c.verb == "key" ? 0 : 2;
    if (c.args.size() < numbers) throw std::runtime_error(c.verb + ": missing coordinates");
    for (size_t i = numbers; i < c.args.size(); ++i) {
        if (c.args[i] == "shift") in.shift = true;
        else if (c.args[i] == "ctrl") in.ctrl = true;
        else if (c.verb == "key" && i == 0) in.key = keyByName(c.args[i]);
        else throw std::runtime_error(c.verb + ": unknown modifier '" + c.args[i] + "'");
    }
    auto frame = [&](Point2f at, bool down, int key = -1) {
        Script::Input f = in;
        f.at = at;
        f.down = down;
        f.key = key;
        sc.input.push_back(f);
    };
    if (c.verb == "key") {
        frame(Point2f(-1e4f, -1e4f), false, in.key);
        frame(Point2f(-1e4f, -1e4f), false);
        return;
    }
    const Point2f a(float(numberArg(c, 0)), float(numberArg(c, 1)));
    frame(a, false);
    frame(a, true);
    if (c.verb == "double-click") {
        frame(a, false);
        frame(a, true);
    } else if (c.verb == "mouse-drag") {
        const Point2f b(float(numberArg(c, 2)), float(numberArg(c, 3)));
        for (int k = 1; k <= 8; ++k) frame(a + (b - a) * (k / 8.f), true);
        frame(b, false);
        frame(b, false);
        return;
    }
    frame(a, false);
    frame(a, false);  // one quiet frame, so the release is handled before the next command
}

/** Before ImGui::NewFrame: replaces the backend's mouse and key state with the next input. */
void injectInput(Script& sc, const Editor& e) {
    ImGuiIO& io = ImGui::GetIO();
    if (sc.heldKey >= 0) io.KeysDown[sc.heldKey] = false;
    sc.heldKey = -1;
    if (sc.input.empty()) return;
    const Script::Input in = sc.input.front();
    sc.input.pop_front();
    const ImVec2 origin(kPanelWidth, 0);
    io.MousePos = in.at.x < -1e3f ? ImVec2(-FLT_MAX, -FLT_MAX) : toScreen(e, origin, in.at);
    io.MouseDown[0] = in.down;
    io.KeyShift = in.shift;
    io.KeyCtrl = in.ctrl;
    if (in.key >= 0) io.KeysDown[sc.heldKey = in.key] = true;
}

/** Runs due commands; returns false when the script says quit or fails. */
bool runScript(Script& sc, Editor& e, View& v, Settings& s, GLFWwindow* window) {
    if (sc.benchFrames > 0) {
        // Drag one pose vertex along a circle, one position per frame.
        const double a = 2 * CV_PI * sc.benchFrame / 60.0;
        e.doc.pose[static_cast<size_t>(sc.benchVertex)] =
            sc.benchStart[static_cast<size_t>(sc.benchVertex)] +
            Point2f(static_cast<float>(12 * std::sin(a)), static_cast<float>(12 * (1 - std::cos(a))));
        updateValidity(e);
        ++sc.benchFrame;
        return true;
    }
    if (!sc.input.empty()) return true;
    if (sc.waitFrames > 0) {
        --sc.waitFrames;
        return true;
    }
    while (sc.next < sc.commands.size()) {
        const ScriptCommand& c = sc.commands[sc.next++];
        const auto num = [&](size_t i) { return numberArg(c, i); };
        const auto vertexArg = [&](size_t i) {
            const int id = static_cast<int>(num(i));
            if (id < 0 || id >= e.doc.cage.vertexCount())
                throw std::runtime_error("vertex " + std::to_string(id) + " out of range (" +
                                         std::to_string(e.doc.cage.vertexCount()) + " vertices)");
            return id;
        };
        try {
            std::printf("script:%d: %s", c.line, c.verb.c_str());
            for (const std::string& a : c.args) std::printf(" %s", a.c_str());
            std::printf("\n");
            std::fflush(stdout);
            if (c.verb == "quit") return false;
            if (c.verb == "load") {
                openImage(e, v, s, c.args[0]);
                if (c.args.size() > 1) openCage(e, c.args[1], s);
            } else if (c.verb == "load-cage") {
                openCage(e, c.args[0], s);
            } else if (c.verb == "propose") {
                propose(e);
            } else if (c.verb == "mode") {
                if (c.args[0] != "rest" && c.args[0] != "pose") throw std::runtime_error("mode rest|pose");
                setMode(e, c.args[0] == "rest" ? Mode::Rest : Mode::Pose);
                if (e.mode != (c.args[0] == "rest" ? Mode::Rest : Mode::Pose)) throw std::runtime_error(e.message);
            } else if (c.verb == "drag") {
                edit(e);
                moveVertices(e.doc, e.mode, {vertexArg(0)}, Point2f(float(num(1)), float(num(2))));
                afterEdit(e);
            } else if (c.verb == "drag-polygon") {
                const int p = static_cast<int>(num(0));
                if (p < 0 || p >= e.doc.cage.polygonCount()) throw std::runtime_error("no polygon " + c.args[0]);
                selectPolygonOf(e, p);
                edit(e);
                moveVertices(e.doc, e.mode, e.selection, Point2f(float(num(1)), float(num(2))));
                afterEdit(e);
            } else if (c.verb == "add-polygon") {
                if (e.mode != Mode::Rest || c.args.size() % 2) throw std::runtime_error("add-polygon: rest mode, x y pairs");
                e.creating = true;
                e.creation.clear();
                for (size_t i = 0; i + 1 < c.args.size(); i += 2)
                    e.creation.emplace_back(float(num(i)), float(num(i + 1)));
                finishPolygon(e);
            } else if (c.verb == "insert-vertex") {
                edit(e);
                if (insertVertex(e.doc, static_cast<int>(num(0)), static_cast<int>(num(1)), float(num(2))) < 0)
                    throw std::runtime_error("no such polygon edge");
                afterEdit(e);
            } else if (c.verb == "delete-vertex") {
                if (e.mode != Mode::Rest) throw std::runtime_error("delete-vertex: rest mode only");
                e.selection = {vertexArg(0)};
                deleteSelection(e, false);
            } else if (c.verb == "coords") {
                if (c.args[0] != "mvc" && c.args[0] != "harmonic") throw std::runtime_error("coords mvc|harmonic");
                s.coordinates = c.args[0] == "harmonic" ? mc::HARMONIC : mc::MEAN_VALUE;
            } else if (c.verb == "grid-step" || c.verb == "export-grid-step") {
                const int step = static_cast<int>(num(0));
                if (step < 1 || step > 64) throw std::runtime_error("grid step must be 1..64");
                (c.verb == "grid-step" ? s.gridStep : s.exportGridStep) = step;
            } else if (c.verb == "show-cage") {
                s.showCage = num(0) != 0;
            } else if (c.verb == "help") {
                s.showHelp = num(0) != 0;
            } else if (c.verb == "undo") {
                undo(e);
            } else if (c.verb == "redo") {
                redo(e);
            } else if (c.verb == "add-pose") {
                edit(e);
                addPose(e.doc, c.args[0]);
                afterEdit(e);
            } else if (c.verb == "add-keyframe") {
                e.keyTime = static_cast<float>(num(0));
                addKeyframeHere(e);
            } else if (c.verb == "play") {
                setPlaying(e, num(0) != 0);
            } else if (c.verb == "set-pose") {
                const int i = e.doc.cage.findPose(c.args[0]);
                if (i < 0) throw std::runtime_error("no pose named " + c.args[0]);
                edit(e);
                e.doc.pose = e.doc.cage.pose(i).vertices;
                afterEdit(e);
            } else if (c.verb == "save") {
                saveCage(e, c.args[0], s);
            } else if (c.verb == "export") {
                exportImage(e, c.args[0], s, window);
            } else if (c.verb == "screenshot") {
                sc.screenshotPath = c.args[0];
                return true;  // taken after this frame is drawn
            } else if (c.verb == "status") {
                writeStatus(e, v, s, c.args[0]);
            } else if (c.verb == "wait") {
                sc.waitFrames = std::max(0, static_cast<int>(num(0)) - 1);
                return true;
            } else if (c.verb == "click" || c.verb == "double-click" || c.verb == "mouse-drag" || c.verb == "key") {
                queueInput(sc, c);
                return true;
            } else if (c.verb == "bench-drag") {
                if (e.mode != Mode::Pose) setMode(e, Mode::Pose);
                sc.benchFrames = std::max(1, static_cast<int>(num(0)));
                sc.benchVertex = c.args.size() > 1 ? vertexArg(1) : 0;
                if (e.doc.cage.vertexCount() == 0) throw std::runtime_error("bench-drag: no vertices");
                sc.benchStart = e.doc.pose;
                sc.benchFrame = 0;
                sc.benchTimes.clear();
                sc.benchRender.clear();
                sc.benchFold.clear();
                sc.benchDraw.clear();
                v.finishForTiming = true;
                return true;
            }
            if (e.message != sc.lastMessage) std::printf("  %s\n", e.message.c_str());
            sc.lastMessage = e.message;
        } catch (const std::exception& ex) {
            std::fprintf(stderr, "multicage-editor: script line %d (%s): %s\n", c.line, c.verb.c_str(), ex.what());
            sc.failed = true;
            return false;
        }
        if (c.verb == "load" || c.verb == "propose" || c.verb == "mode" || c.verb == "drag") return true;
    }
    glfwSetWindowShouldClose(window, 1);  // the script ran out without quit
    return true;
}

double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

// ---------------------------------------------------------------------------------------
// The side panel.

void section(const char* title) {
    ImGui::Spacing();
    ImGui::TextColored(ImVec4(0.65f, 0.75f, 0.9f, 1.f), "%s", title);
    ImGui::Separator();
}

bool inputPath(const char* label, std::string& s) {
    char buf[1024];
    std::snprintf(buf, sizeof buf, "%s", s.c_str());
    const bool enter = ImGui::InputText(label, buf, sizeof buf, ImGuiInputTextFlags_EnterReturnsTrue);
    s = buf;
    return enter;
}

void panel(Editor& e, View& v, Settings& s, GLFWwindow* window) {
    auto attempt = [&](auto&& f) {
        try {
            f();
        } catch (const std::exception& ex) {
            e.message = ex.what();
        }
    };
    ImGui::TextColored(ImVec4(1.f, 0.77f, 0.f, 1.f), "multicage editor");
    ImGui::SameLine(ImGui::GetWindowWidth() - 70);
    if (ImGui::SmallButton("Help (H)")) s.showHelp = !s.showHelp;
    ImGui::Separator();

    ImGui::PushItemWidth(-70);
    if (inputPath("##image", e.imagePath)) attempt([&] { openImage(e, v, s, e.imagePath); });
    ImGui::SameLine();
    if (ImGui::Button("Open", ImVec2(-1, 0))) attempt([&] { openImage(e, v, s, e.imagePath); });
    inputPath("##cage", e.cagePath);
    ImGui::PopItemWidth();
    if (ImGui::Button("Load cage")) attempt([&] { openCage(e, e.cagePath, s); });
    ImGui::SameLine();
    if (ImGui::Button("Save cage (Ctrl+S)")) attempt([&] { saveCage(e, e.cagePath, s); });
    ImGui::Spacing();

    ImGui::AlignTextToFramePadding();
    ImGui::Text("Mode (Tab)");
    ImGui::SameLine();
    if (ImGui::RadioButton("Rest", e.mode == Mode::Rest)) setMode(e, Mode::Rest);
    ImGui::SameLine();
    if (ImGui::RadioButton("Pose", e.mode == Mode::Pose)) setMode(e, Mode::Pose);
    if (ImGui::Button("Propose multicage", ImVec2(-1, 0))) attempt([&] { propose(e); });
    ImGui::BeginDisabled(e.history.undoCount() == 0);
    if (ImGui::Button("Undo")) undo(e);
    ImGui::EndDisabled();
    ImGui::SameLine();
    ImGui::BeginDisabled(e.history.redoCount() == 0);
    if (ImGui::Button("Redo")) redo(e);
    ImGui::EndDisabled();
    ImGui::SameLine();
    ImGui::BeginDisabled(e.selection.empty() || e.mode != Mode::Rest);
    if (ImGui::Button("Delete")) deleteSelection(e, false);
    ImGui::SameLine();
    if (ImGui::Button("Delete polygon")) deleteSelection(e, true);
    ImGui::EndDisabled();

    section("Deformation");
    ImGui::Checkbox("Show cage (C)", &s.showCage);
    const char* coords[] = {"Mean value", "Harmonic"};
    ImGui::Combo("Coordinates", &s.coordinates, coords, 2);
    ImGui::SliderInt("Grid step", &s.gridStep, 1, 16);
    ImGui::SliderInt("Export step", &s.exportGridStep, 1, 8);

    section("Poses");
    for (int i = 0; i < e.doc.cage.poseCount(); ++i) {
        ImGui::PushID(i);
        if (ImGui::Selectable(e.doc.cage.pose(i).name.c_str(), e.doc.pose == e.doc.cage.pose(i).vertices)) {
            edit(e);
            e.doc.pose = e.doc.cage.pose(i).vertices;
            afterEdit(e);
            if (e.restOk) setMode(e, Mode::Pose);
        }
        ImGui::PopID();
    }
    ImGui::PushItemWidth(-90);
    ImGui::InputText("##posename", e.poseName, sizeof e.poseName);
    ImGui::PopItemWidth();
    ImGui::SameLine();
    if (ImGui::Button("Add pose", ImVec2(-1, 0)) && e.poseName[0]) {
        edit(e);
        addPose(e.doc, e.poseName);
        afterEdit(e);
        e.message = std::string("pose '") + e.poseName + "' stored";
    }

    section("Animation");
    ImGui::PushItemWidth(-150);
    ImGui::InputFloat("##keytime", &e.keyTime, 0.25f, 1.f, "%.2f s");
    ImGui::PopItemWidth();
    ImGui::SameLine();
    if (ImGui::Button("Add keyframe (K)", ImVec2(-1, 0))) attempt([&] { addKeyframeHere(e); });
    std::string keyWhy;
    const bool canPlay = mc::validateKeyframes(e.doc.cage, &keyWhy);
    if (!canPlay && !e.playing) ImGui::BeginDisabled();
    if (ImGui::Button(e.playing ? "Stop (P)" : "Play (P)", ImVec2(120, 0)))
        attempt([&] { setPlaying(e, !e.playing); });
    if (!canPlay && !e.playing) {
        ImGui::EndDisabled();
        if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) ImGui::SetTooltip("%s", keyWhy.c_str());
    }
    ImGui::SameLine();
    ImGui::Checkbox("Loop", &e.loop);
    if (e.playing) ImGui::Text("t = %.2f s of %.2f s", e.playhead, mc::animationDuration(e.shown.cage, e.loop));

    section("Export");
    ImGui::PushItemWidth(-70);
    inputPath("##export", e.exportPath);
    ImGui::PopItemWidth();
    ImGui::SameLine();
    if (ImGui::Button("Export", ImVec2(-1, 0))) attempt([&] { exportImage(e, e.exportPath, s, window); });

    section("Status");
    ImGui::Text("%s, %s, %s", count(e.doc.cage.polygonCount(), "polygon", "polygons").c_str(),
                count(e.doc.cage.vertexCount(), "vertex", "vertices").c_str(),
                count(e.doc.cage.poseCount(), "pose", "poses").c_str());
    if (!e.restOk || !e.poseOk) {
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.f, 0.3f, 0.3f, 1.f));
        ImGui::TextWrapped("Invalid: %s", (!e.restOk ? e.restWhy : e.poseWhy).c_str());
        ImGui::TextWrapped("The view keeps the last valid %s.", !e.restOk ? "binding" : "pose");
        ImGui::PopStyleColor();
    }
    if (!v.error.empty()) ImGui::TextColored(ImVec4(1, 0.3f, 0.3f, 1), "%s", v.error.c_str());
    if (v.deformer) {
        ImGui::Text("binding %.0f ms (grid %dx%d, %s)", v.bindMs, v.binding.gridSize.width,
                    v.binding.gridSize.height, v.binding.coordinates == mc::HARMONIC ? "harmonic" : "mean value");
        ImGui::Text("min conditioning %.2g", v.binding.minConditioning);
        if (v.binding.minConditioning < mc::kConditioningWarning)
            ImGui::TextColored(ImVec4(1, 0.6f, 0.2f, 1), "warning: ill-conditioned near (%.0f, %.0f)",
                               v.binding.worstNode.x, v.binding.worstNode.y);
        if (v.folded > 0) ImGui::TextColored(ImVec4(1, 0.6f, 0.2f, 1), "fold-over: %d triangles", v.folded);
    }
    ImGui::Text("frame %.1f ms, pose render %.1f ms", v.frameMs, v.renderMs);
    if (!e.message.empty()) ImGui::TextWrapped("%s", e.message.c_str());
}

}  // namespace

// ---------------------------------------------------------------------------------------

int main(int argc, char** argv) {
    std::vector<std::string> positional;
    std::string scriptPath;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "-h" || a == "--help") {
            std::printf("multicage-editor [IMAGE [CAGE.yml]] [--script FILE]\n"
                        "Draw or propose a multicage over an image, drag its vertices, see the deformation live.\n"
                        "Press H in the window for the keys.\n\nScript commands (one per line, # comments):\n");
            for (const ScriptVerb& v : scriptVerbs()) std::printf("  %s\n", v.usage);
            return 0;
        } else if (a == "--script" && i + 1 < argc) {
            scriptPath = argv[++i];
        } else if (!a.empty() && a[0] == '-') {
            std::fprintf(stderr, "multicage-editor: unknown option %s (see --help)\n", a.c_str());
            return 2;
        } else {
            positional.push_back(a);
        }
    }
    if (positional.size() > 2) {
        std::fprintf(stderr, "multicage-editor: at most IMAGE and CAGE.yml (see --help)\n");
        return 2;
    }
    Script script;
    if (!scriptPath.empty()) {
        try {
            script.commands = loadScript(scriptPath);
        } catch (const std::exception& ex) {
            std::fprintf(stderr, "multicage-editor: %s\n", ex.what());
            return 2;
        }
    }

    if (!glfwInit()) {
        std::fprintf(stderr, "multicage-editor: cannot initialise GLFW (no display? try xvfb-run)\n");
        return 1;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);  // GLDeformer needs 4.3 core
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    GLFWwindow* window = glfwCreateWindow(1280, 800, "multicage editor", nullptr, nullptr);
    if (!window) {
        std::fprintf(stderr, "multicage-editor: cannot create an OpenGL 4.3 core window\n");
        glfwTerminate();
        return 1;
    }
    glfwMakeContextCurrent(window);
    glfwSwapInterval(script.active() ? 0 : 1);

    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // layout is fixed: no imgui.ini next to the user's files
    ImGui::StyleColorsDark();
    ImGuiStyle& style = ImGui::GetStyle();
    style.WindowRounding = 0.f;
    style.FrameRounding = 3.f;
    style.GrabRounding = 3.f;
    style.WindowBorderSize = 0.f;
    ImGui_ImplGlfw_InitForOpenGL(window, true);
    ImGui_ImplOpenGL3_Init("#version 410");

    Editor e;
    View v;
    Settings s;
    int rc = 0;
    try {
        if (!positional.empty()) openImage(e, v, s, positional[0]);
        if (positional.size() > 1) openCage(e, positional[1], s);
    } catch (const std::exception& ex) {
        std::fprintf(stderr, "multicage-editor: %s\n", ex.what());
        e.message = ex.what();
        if (script.active()) rc = 1;
    }

    bool running = rc == 0;
    while (running && !glfwWindowShouldClose(window)) {
        const auto frameStart = Clock::now();
        glfwPollEvents();
        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        if (script.active()) injectInput(script, e);
        ImGui::NewFrame();

        if (script.active() && !runScript(script, e, v, s, window)) running = false;
        keyboard(e, s, window);

        int fbw = 0, fbh = 0;
        glfwGetFramebufferSize(window, &fbw, &fbh);
        const ImVec2 display = ImGui::GetIO().DisplaySize;

        // Side panel.
        ImGui::SetNextWindowPos(ImVec2(0, 0));
        ImGui::SetNextWindowSize(ImVec2(kPanelWidth, display.y));
        ImGui::Begin("panel", nullptr, ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove);
        panel(e, v, s, window);
        ImGui::End();

        // Canvas.
        ImGui::SetNextWindowPos(ImVec2(kPanelWidth, 0));
        ImGui::SetNextWindowSize(ImVec2(display.x - kPanelWidth, display.y));
        ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(0, 0));
        ImGui::PushStyleColor(ImGuiCol_WindowBg, ImVec4(0.11f, 0.11f, 0.12f, 1.f));
        ImGui::Begin("canvas", nullptr, ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove |
                                            ImGuiWindowFlags_NoBringToFrontOnFocus |
                                            ImGuiWindowFlags_NoScrollWithMouse);
        const ImVec2 origin = ImGui::GetCursorScreenPos();
        const ImVec2 area(display.x - kPanelWidth, std::max(1.f, display.y - kStatusHeight));
        ImGui::InvisibleButton("canvas-area", area,
                               ImGuiButtonFlags_MouseButtonLeft | ImGuiButtonFlags_MouseButtonRight |
                                   ImGuiButtonFlags_MouseButtonMiddle);
        const bool hovered = ImGui::IsItemHovered() || ImGui::IsItemActive();
        if (!e.image.empty() && e.fitPending) {
            e.zoom = std::min(area.x / e.image.cols, area.y / e.image.rows) * 0.96f;
            e.pan = Point2f((area.x - e.zoom * e.image.cols) / 2, (area.y - e.zoom * e.image.rows) / 2);
            e.fitPending = false;
        }
        if (!e.image.empty()) canvasMouse(e, origin, hovered);
        advancePlayback(e);
        updateDeformation(e, v, s);
        ImDrawList* dl = ImGui::GetWindowDrawList();
        dl->PushClipRect(origin, ImVec2(origin.x + area.x, origin.y + area.y), true);
        if (!e.image.empty()) {
            const ImVec2 a = toScreen(e, origin, Point2f(-0.5f, -0.5f));
            const ImVec2 b = toScreen(e, origin, Point2f(e.image.cols - 0.5f, e.image.rows - 0.5f));
            const bool posed = e.mode == Mode::Pose && v.deformer && v.rendered;
            const GLuint tex = posed ? v.deformer->outputTexture() : v.imageTexture;
            dl->AddImage(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(tex)), a, b);
            dl->AddRect(a, b, IM_COL32(90, 90, 90, 255));
            if (s.showCage) drawOverlay(e, dl, origin);
            if (e.drag == Drag::Box) {
                const ImVec2 p = toScreen(e, origin, e.dragStart), q = toScreen(e, origin, e.dragLast);
                dl->AddRectFilled(p, q, IM_COL32(255, 200, 0, 40));
                dl->AddRect(p, q, IM_COL32(255, 200, 0, 200));
            }
        } else {
            dl->AddText(ImVec2(origin.x + 20, origin.y + 20), IM_COL32(200, 200, 200, 255),
                        "Open an image: type its path in the panel, or run multicage-editor IMAGE [CAGE.yml]");
        }
        dl->PopClipRect();
        // Status line.
        char status[512];
        std::snprintf(status, sizeof status, "%s mode | %s | bind %.0f ms | frame %.1f ms | folds %d%s | %s",
                      e.mode == Mode::Rest ? "REST" : "POSE",
                      e.restOk && e.poseOk ? "valid" : (!e.restOk ? e.restWhy : e.poseWhy).c_str(), v.bindMs,
                      v.frameMs, v.folded,
                      v.deformer && v.binding.minConditioning < mc::kConditioningWarning ? " | ILL-CONDITIONED" : "",
                      e.message.c_str());
        const ImVec2 sp(origin.x, origin.y + area.y);
        dl->AddRectFilled(sp, ImVec2(sp.x + area.x, sp.y + kStatusHeight), IM_COL32(30, 30, 34, 255));
        dl->AddText(ImVec2(sp.x + 8, sp.y + 5),
                    e.restOk && e.poseOk ? IM_COL32(210, 210, 210, 255) : IM_COL32(255, 80, 80, 255), status);
        ImGui::End();
        ImGui::PopStyleColor();
        ImGui::PopStyleVar();

        if (s.showHelp) {
            ImGui::SetNextWindowPos(ImVec2(kPanelWidth + 20, 20), ImGuiCond_Appearing);
            ImGui::SetNextWindowBgAlpha(0.92f);
            ImGui::Begin("Help (H)", &s.showHelp, ImGuiWindowFlags_AlwaysAutoResize);
            ImGui::TextUnformatted(kHelp);
            ImGui::End();
        }

        // Render: GLDeformer left its own bindings; the ImGui backend sets everything it uses.
        const auto drawStart = Clock::now();
        ImGui::Render();
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        glViewport(0, 0, fbw, fbh);
        glClearColor(0.11f, 0.11f, 0.12f, 1.f);
        glClear(GL_COLOR_BUFFER_BIT);
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
        if (!script.screenshotPath.empty()) {
            try {
                screenshot(window, script.screenshotPath);
                std::printf("  wrote %s\n", script.screenshotPath.c_str());
            } catch (const std::exception& ex) {
                std::fprintf(stderr, "multicage-editor: screenshot: %s\n", ex.what());
                script.failed = true;
                running = false;
            }
            script.screenshotPath.clear();
        }
        glfwSwapBuffers(window);
        if (script.benchFrames > 0) {
            glFinish();
            script.benchTimes.push_back(msSince(frameStart));
            script.benchRender.push_back(v.renderMs);
            script.benchFold.push_back(v.foldMs);
            script.benchDraw.push_back(msSince(drawStart));
            if (--script.benchFrames == 0) {
                std::printf("bench-drag: %zu frames, %dx%d image, %d vertices, grid step %d: median frame %.1f ms "
                            "(GLDeformer setPose + render %.1f ms, fold count %.1f ms, ImGui draw + swap %.1f ms)\n",
                            script.benchTimes.size(), e.image.cols, e.image.rows, e.doc.cage.vertexCount(),
                            s.gridStep, median(script.benchTimes), median(script.benchRender),
                            median(script.benchFold), median(script.benchDraw));
                v.finishForTiming = false;
                std::fflush(stdout);
            }
        }
        v.frameMs = msSince(frameStart);
    }

    v.deformer.reset();  // needs the context
    if (v.imageTexture) glDeleteTextures(1, &v.imageTexture);
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    glfwDestroyWindow(window);
    glfwTerminate();
    return script.failed ? 1 : rc;
}

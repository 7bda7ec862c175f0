#include <epoxy/gl.h>
// GLFW after epoxy: epoxy must be the one GL header.
#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <set>
#include <vector>

#include "actions.hpp"
#include "canvas.hpp"
#include "resize_mode.hpp"
#include "view.hpp"

namespace multicage_editor {

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

Point2f toImage(const Editor& e, ImVec2 origin, ImVec2 q) {
    return Point2f((q.x - origin.x - e.pan.x) / e.zoom - 0.5f,
                   (q.y - origin.y - e.pan.y) / e.zoom - 0.5f);
}

void drawOverlay(const Editor& e, ImDrawList* dl, ImVec2 origin) {
    const std::vector<Point2f> pts = positions(e.doc, e.mode);
    const std::set<int> selected(e.selection.begin(), e.selection.end());
    drawPolygons(e, pts, e.mode == Mode::Rest ? !e.restOk : !e.poseOk, dl, origin);
    for (size_t i = 0; i < pts.size(); ++i) {
        const ImVec2 c = toScreen(e, origin, pts[i]);
        const float r = selected.count(static_cast<int>(i)) ? 5.f : 4.f;
        dl->AddRectFilled(ImVec2(c.x - r - 1, c.y - r - 1), ImVec2(c.x + r + 1, c.y + r + 1),
                          kOutline);
        dl->AddRectFilled(ImVec2(c.x - r, c.y - r), ImVec2(c.x + r, c.y + r),
                          selected.count(static_cast<int>(i)) ? kSelected : kHandle);
    }
    if (e.creating && !e.creation.empty()) {
        std::vector<ImVec2> poly;
        for (const Point2f& p : e.creation) poly.push_back(toScreen(e, origin, p));
        poly.push_back(ImGui::GetIO().MousePos);
        dl->AddPolyline(poly.data(), static_cast<int>(poly.size()), IM_COL32(255, 255, 255, 230), 0,
                        2.f);
        for (size_t k = 0; k < e.creation.size(); ++k)
            dl->AddCircleFilled(poly[k], k == 0 ? 6.f : 4.f, k == 0 ? kSelected : kHandle);
    }
}

/** Wheel zoom about the cursor; right or middle drag pans. True while panning. */
bool zoomAndPan(Editor& e, Point2f m, bool hovered) {
    ImGuiIO& io = ImGui::GetIO();
    if (hovered && io.MouseWheel != 0.f) {  // zoom about the cursor
        const float z = std::min(32.f, std::max(0.05f, e.zoom * std::pow(1.15f, io.MouseWheel)));
        e.pan.x += (m.x + 0.5f) * (e.zoom - z);
        e.pan.y += (m.y + 0.5f) * (e.zoom - z);
        e.zoom = z;
    }
    if (hovered && (ImGui::IsMouseClicked(ImGuiMouseButton_Middle) ||
                    ImGui::IsMouseClicked(ImGuiMouseButton_Right)))
        e.drag = Drag::Pan;
    if (e.drag == Drag::Pan) {
        e.pan.x += io.MouseDelta.x;
        e.pan.y += io.MouseDelta.y;
        if (!ImGui::IsMouseDown(ImGuiMouseButton_Middle) &&
            !ImGui::IsMouseDown(ImGuiMouseButton_Right))
            e.drag = Drag::None;
        return true;
    }
    return false;
}

/** A double-click on an edge in rest mode inserts a vertex there; true when it did. */
bool insertOnDoubleClick(Editor& e, const std::vector<Point2f>& pts, Point2f m, float radius,
                         bool hovered) {
    if (hovered && ImGui::IsMouseDoubleClicked(ImGuiMouseButton_Left) && e.mode == Mode::Rest &&
        !e.creating) {
        int poly, edgeIndex;
        float t;
        if (hitVertex(pts, m, radius) < 0 &&
            hitEdge(e.doc.cage, pts, m, radius, &poly, &edgeIndex, &t)) {
            edit(e);
            const int id = insertVertex(e.doc, poly, edgeIndex, t);
            e.selection = {id};
            e.drag = Drag::None;
            afterEdit(e);
            e.message = "vertex inserted on polygon " + std::to_string(poly) + ", edge " +
                        std::to_string(edgeIndex);
            return true;
        }
    }
    return false;
}

/** A left press: a vertex of the polygon being created, or a selection and the start of a
vertex drag, or the start of a box drag. */
void press(Editor& e, const std::vector<Point2f>& pts, Point2f m, float radius) {
    ImGuiIO& io = ImGui::GetIO();
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
        const bool isSelected =
            std::find(e.selection.begin(), e.selection.end(), v) != e.selection.end();
        if (io.KeyShift) {
            if (isSelected)
                e.selection.erase(std::find(e.selection.begin(), e.selection.end(), v));
            else
                e.selection.push_back(v);
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
}

/** The end of a box drag: a click on empty canvas, or a box selection. */
void finishBox(Editor& e, const std::vector<Point2f>& pts, Point2f m, float radius) {
    ImGuiIO& io = ImGui::GetIO();
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
            e.message =
                "new polygon: click to add vertices, click the first one or Enter to close, Esc "
                "cancels";
        }
    } else {
        const cv::Rect2f box(std::min(e.dragStart.x, m.x), std::min(e.dragStart.y, m.y),
                             std::abs(d.x), std::abs(d.y));
        if (!io.KeyShift) e.selection.clear();
        for (size_t i = 0; i < pts.size(); ++i)
            if (box.contains(pts[i]) && std::find(e.selection.begin(), e.selection.end(),
                                                  static_cast<int>(i)) == e.selection.end())
                e.selection.push_back(static_cast<int>(i));
    }
}

/** Continues a vertex or box drag; ends it when the left button is up. */
void continueDrag(Editor& e, const std::vector<Point2f>& pts, Point2f m, float radius) {
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
            finishBox(e, pts, m, radius);
        }
    }
}

void canvasMouse(Editor& e, ImVec2 origin, bool hovered) {
    const Point2f m = toImage(e, origin, ImGui::GetIO().MousePos);
    const float radius = kPickRadius / e.zoom;
    const std::vector<Point2f> pts = positions(e.doc, e.mode);
    if (zoomAndPan(e, m, hovered)) return;
    if (e.mode == Mode::Resize) {  // the frame's edges only: no vertex edits
        resizeMouse(e, m, radius, hovered);
        return;
    }
    if (insertOnDoubleClick(e, pts, m, radius, hovered)) return;
    if (hovered && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
        press(e, pts, m, radius);
        return;
    }
    continueDrag(e, pts, m, radius);
}

/** The image, the whole of it at the next frame after an image is opened or F is pressed; in
resize mode the larger of the image and the resized one, with a quarter more room to drag the
frame out into. */
void fit(Editor& e, ImVec2 area) {
    float w = static_cast<float>(e.image.cols), h = static_cast<float>(e.image.rows);
    if (e.mode == Mode::Resize) {
        w = 1.25f * std::max(w, static_cast<float>(e.resizeTo.width));
        h = 1.25f * std::max(h, static_cast<float>(e.resizeTo.height));
    }
    e.zoom = std::min(area.x / w, area.y / h) * 0.96f;
    e.pan = Point2f((area.x - e.zoom * w) / 2, (area.y - e.zoom * h) / 2);
    e.fitPending = false;
}

/** The image (the deformation in pose mode), the overlay and the box being dragged. */
void drawImage(const Editor& e, const View& v, const Settings& s, ImDrawList* dl, ImVec2 origin) {
    if (e.mode == Mode::Resize) return drawResized(e, v, s, dl, origin);
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
}

/** The status line below the canvas (red when the edit is invalid). */
void statusLine(const Editor& e, const View& v, ImDrawList* dl, ImVec2 origin, ImVec2 area) {
    char status[512];
    const std::string mode = e.mode == Mode::Rest ? "REST"
                             : e.mode == Mode::Pose
                                 ? "POSE"
                                 : cv::format("RESIZE %dx%d", e.resizeTo.width, e.resizeTo.height);
    std::snprintf(
        status, sizeof status, "%s mode | %s | bind %.0f ms | frame %.1f ms | folds %d%s | %s",
        mode.c_str(), e.restOk && e.poseOk ? "valid" : (!e.restOk ? e.restWhy : e.poseWhy).c_str(),
        v.bindMs, v.frameMs, v.folded,
        v.deformer && v.binding.minConditioning < mc::kConditioningWarning ? " | ILL-CONDITIONED"
                                                                           : "",
        e.message.c_str());
    const ImVec2 sp(origin.x, origin.y + area.y);
    dl->AddRectFilled(sp, ImVec2(sp.x + area.x, sp.y + kStatusHeight), IM_COL32(30, 30, 34, 255));
    dl->AddText(ImVec2(sp.x + 8, sp.y + 5),
                e.restOk && e.poseOk ? IM_COL32(210, 210, 210, 255) : IM_COL32(255, 80, 80, 255),
                status);
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
    "Resize mode (R): drag the frame's right or bottom edge (or type a size\n"
    "  in the panel); faces and what the cage protects keep their shape;\n"
    "  Export saves the resized image\n"
    "Animation: K stores the pose as a keyframe at the time shown, P plays / stops\n"
    "View: wheel zooms, right/middle drag pans, F fits, C shows/hides the cage\n"
    "Ctrl+Z / Ctrl+Y (Ctrl+Shift+Z) undo / redo, Ctrl+S save, Ctrl+A select all\n"
    "H or F1 this help, Ctrl+Q quit\n"
    "Red polygons: the edit is invalid (reason in the status line);\n"
    "the view keeps the last valid binding and pose.";

}  // namespace

ImVec2 toScreen(const Editor& e, ImVec2 origin, Point2f p) {
    return ImVec2(origin.x + e.zoom * (p.x + 0.5f) + e.pan.x,
                  origin.y + e.zoom * (p.y + 0.5f) + e.pan.y);
}

void drawPolygons(const Editor& e, const std::vector<Point2f>& pts, bool bad, ImDrawList* dl,
                  ImVec2 origin) {
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
        if (offset + n > static_cast<int>(pts.size())) return;
        std::vector<ImVec2> poly;
        for (int k = 0; k < n; ++k)
            poly.push_back(toScreen(e, origin, pts[static_cast<size_t>(offset + k)]));
        dl->AddPolyline(poly.data(), n, IM_COL32(0, 0, 0, 160), ImDrawFlags_Closed, 4.f);
        dl->AddPolyline(poly.data(), n, colour, ImDrawFlags_Closed, 2.f);
    }
}

void canvas(Editor& e, View& v, const Settings& s) {
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    ImGui::SetNextWindowPos(ImVec2(kPanelWidth, 0));
    ImGui::SetNextWindowSize(ImVec2(display.x - kPanelWidth, display.y));
    ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(0, 0));
    ImGui::PushStyleColor(ImGuiCol_WindowBg, ImVec4(0.11f, 0.11f, 0.12f, 1.f));
    ImGui::Begin("canvas", nullptr,
                 ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove |
                     ImGuiWindowFlags_NoBringToFrontOnFocus | ImGuiWindowFlags_NoScrollWithMouse);
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    const ImVec2 area(display.x - kPanelWidth, std::max(1.f, display.y - kStatusHeight));
    ImGui::InvisibleButton("canvas-area", area,
                           ImGuiButtonFlags_MouseButtonLeft | ImGuiButtonFlags_MouseButtonRight |
                               ImGuiButtonFlags_MouseButtonMiddle);
    const bool hovered = ImGui::IsItemHovered() || ImGui::IsItemActive();
    const cv::Size2f areaNow(area.x, area.y);
    if (areaNow != e.canvasArea) e.fitPending = e.fitPending || e.canvasArea.area() > 0;
    e.canvasArea = areaNow;
    if (!e.image.empty() && e.fitPending) fit(e, area);
    if (!e.image.empty()) canvasMouse(e, origin, hovered);
    advancePlayback(e);
    updateDeformation(e, v, s);
    ImDrawList* dl = ImGui::GetWindowDrawList();
    dl->PushClipRect(origin, ImVec2(origin.x + area.x, origin.y + area.y), true);
    if (!e.image.empty()) {
        drawImage(e, v, s, dl, origin);
    } else {
        dl->AddText(
            ImVec2(origin.x + 20, origin.y + 20), IM_COL32(200, 200, 200, 255),
            "Open an image: type its path in the panel, or run multicage-editor IMAGE [CAGE.yml]");
    }
    dl->PopClipRect();
    statusLine(e, v, dl, origin, area);
    ImGui::End();
    ImGui::PopStyleColor();
    ImGui::PopStyleVar();
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
        for (size_t i = 0; i < positions(e.doc, e.mode).size(); ++i)
            e.selection.push_back(static_cast<int>(i));
    }
    if (ctrl && pressed(GLFW_KEY_Q)) glfwSetWindowShouldClose(window, 1);
    if (ctrl) return;
    if (pressed(GLFW_KEY_TAB)) setMode(e, e.mode == Mode::Rest ? Mode::Pose : Mode::Rest);
    if (pressed(GLFW_KEY_R)) setMode(e, e.mode == Mode::Resize ? Mode::Pose : Mode::Resize);
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
        if (e.creating && !e.creation.empty())
            e.creation.pop_back();
        else
            deleteSelection(e, io.KeyShift);
    }
    if (e.creating && (pressed(GLFW_KEY_ENTER) || pressed(GLFW_KEY_KP_ENTER))) finishPolygon(e);
    if (pressed(GLFW_KEY_ESCAPE)) {
        if (e.creating) e.message = "polygon cancelled";
        e.creating = false;
        e.creation.clear();
        e.selection.clear();
    }
}

void helpWindow(Settings& s) {
    if (s.showHelp) {
        ImGui::SetNextWindowPos(ImVec2(kPanelWidth + 20, 20), ImGuiCond_Appearing);
        ImGui::SetNextWindowBgAlpha(0.92f);
        ImGui::Begin("Help (H)", &s.showHelp, ImGuiWindowFlags_AlwaysAutoResize);
        ImGui::TextUnformatted(kHelp);
        ImGui::End();
    }
}

}  // namespace multicage_editor

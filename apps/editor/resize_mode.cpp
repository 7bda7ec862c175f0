#include "resize_mode.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/multicage/resize.hpp>

#include "canvas.hpp"

namespace multicage_editor {

using cv::Point2f;

namespace {

const ImU32 kFrameHandle = IM_COL32(255, 255, 255, 255);
const ImU32 kImageFrame = IM_COL32(150, 150, 150, 200);

}  // namespace

cv::Size clampResizeSize(cv::Size image, cv::Size wanted) {
    const int maxW = static_cast<int>(kMaxResizeScale * image.width);
    const int maxH = static_cast<int>(kMaxResizeScale * image.height);
    return cv::Size(std::min(std::max(wanted.width, 1), maxW),
                    std::min(std::max(wanted.height, 1), maxH));
}

void setResizeSize(Editor& e, cv::Size wanted, bool refit) {
    e.resizeTo = clampResizeSize(e.image.size(), wanted);
    e.fitPending = e.fitPending || refit;
    e.message = cv::format("resize to %dx%d", e.resizeTo.width, e.resizeTo.height);
    if (e.resizeTo != wanted)
        e.message += cv::format(" (each side 1 to %.0fx the image's)", kMaxResizeScale);
}

bool resizePoseFor(Editor& e, View& v) {
    if (e.resizeTo.area() <= 0) e.resizeTo = e.image.size();
    // A new binding or a new size: one resizePose() on the binding made once per rest
    // multicage. A size or binding that fails is not tried again every frame.
    if (v.resizedBinding == v.bindings && v.resizedTo == e.resizeTo) return !v.resizePose.empty();
    v.resizedTo = e.resizeTo;
    v.resizedBinding = v.bindings;
    try {
        const Clock::time_point t0 = Clock::now();
        v.resizePose = mc::resizePose(e.shown.cage, v.deformer->binding(), e.resizeTo);
        v.resizePoseMs = msSince(t0);
    } catch (const cv::Exception& ex) {
        e.message = "cannot resize: " + ex.err;
        v.resizePose.clear();
        return false;
    }
    return true;
}

bool resizeMouse(Editor& e, Point2f m, float radius, bool hovered) {
    const float right = e.resizeTo.width - 0.5f, bottom = e.resizeTo.height - 0.5f;
    if (e.drag == Drag::Frame) {
        // The dragged edge follows the mouse: the frame's right side is at W' - 0.5.
        // The view holds still under the mouse while dragging, and refits on release.
        setResizeSize(
            e,
            cv::Size(e.frameEdges & kFrameRight ? cvRound(m.x + 0.5f) : e.resizeTo.width,
                     e.frameEdges & kFrameBottom ? cvRound(m.y + 0.5f) : e.resizeTo.height),
            false);
        if (!ImGui::IsMouseDown(ImGuiMouseButton_Left)) {
            e.drag = Drag::None;
            e.fitPending = true;
            e.message = cv::format("resized to %dx%d (Export saves it)", e.resizeTo.width,
                                   e.resizeTo.height);
        }
        return true;
    }
    int edges = 0;
    if (std::abs(m.x - right) <= radius && m.y >= -0.5f - radius && m.y <= bottom + radius)
        edges |= kFrameRight;
    if (std::abs(m.y - bottom) <= radius && m.x >= -0.5f - radius && m.x <= right + radius)
        edges |= kFrameBottom;
    if (!hovered || !edges) return false;
    ImGui::SetMouseCursor(edges == kFrameRight    ? ImGuiMouseCursor_ResizeEW
                          : edges == kFrameBottom ? ImGuiMouseCursor_ResizeNS
                                                  : ImGuiMouseCursor_ResizeNWSE);
    if (!ImGui::IsMouseClicked(ImGuiMouseButton_Left)) return false;
    e.drag = Drag::Frame;
    e.frameEdges = edges;
    return true;
}

void drawResized(const Editor& e, const View& v, const Settings& s, ImDrawList* dl, ImVec2 origin) {
    const bool resized = v.deformer && v.rendered && !v.resizePose.empty();
    const cv::Size out = resized ? v.deformer->outputSize() : e.image.size();
    const ImVec2 a = toScreen(e, origin, Point2f(-0.5f, -0.5f));
    const ImVec2 b = toScreen(e, origin, Point2f(out.width - 0.5f, out.height - 0.5f));
    const GLuint tex = resized ? v.deformer->outputTexture() : v.imageTexture;
    dl->AddImage(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(tex)), a, b);
    dl->AddRect(a, toScreen(e, origin, Point2f(e.image.cols - 0.5f, e.image.rows - 0.5f)),
                kImageFrame);
    dl->AddRect(a, b, kFrameHandle, 0.f, 0, 2.f);
    if (s.showCage && resized) drawPolygons(e, v.resizePose, false, dl, origin);
    // Grips: the middle of the right and bottom edges, and the corner between them.
    for (const ImVec2 c : {ImVec2(b.x, (a.y + b.y) / 2), ImVec2((a.x + b.x) / 2, b.y), b}) {
        dl->AddRectFilled(ImVec2(c.x - 6, c.y - 6), ImVec2(c.x + 6, c.y + 6),
                          IM_COL32(20, 20, 20, 255));
        dl->AddRectFilled(ImVec2(c.x - 5, c.y - 5), ImVec2(c.x + 5, c.y + 5), kFrameHandle);
    }
}

}  // namespace multicage_editor

// The editor's resize mode (issue 25, item 7): the user drags the frame's right or bottom edge
// (or types a size) and the image is resized content-aware, live: one binding per rest
// multicage, one resizePose() and one GLDeformer pose per new size; export (actions.cpp)
// writes the resized image at full resolution.
#ifndef MULTICAGE_EDITOR_RESIZE_MODE_HPP
#define MULTICAGE_EDITOR_RESIZE_MODE_HPP

#include <imgui.h>

#include "editor_state.hpp"

namespace multicage_editor {

/** The largest factor a side may grow by (ResizeParams::maxScale's default). */
constexpr double kMaxResizeScale = 8.0;

/** wanted with each side clamped to [1, kMaxResizeScale x the image's]. */
cv::Size clampResizeSize(cv::Size image, cv::Size wanted);
/** Sets the size resize mode shows (clamped, said in the message when it was). */
void setResizeSize(Editor& e, cv::Size wanted, bool refit = true);

/** In resize mode, with v.deformer bound: v.resizePose for e.resizeTo, from the library's
resizePose() on the deformer's binding, made again only for a new size or a new binding.
False when there is no pose to show (the reason in the message). */
bool resizePoseFor(Editor& e, View& v);

/** Resize-mode mouse: a press on the frame's right edge, bottom edge or corner starts a frame
drag, which sets the size while it moves. True when it used the mouse this frame. */
bool resizeMouse(Editor& e, cv::Point2f m, float radius, bool hovered);
/** The resized image with its frame handles, the image's own frame for comparison, and the
cage where the resize pose put it. */
void drawResized(const Editor& e, const View& v, const Settings& s, ImDrawList* dl, ImVec2 origin);

}  // namespace multicage_editor

#endif

// The canvas: the image (or its deformation), the cage overlay, the status line, and the
// mouse and keyboard that edit them.
#ifndef MULTICAGE_EDITOR_CANVAS_HPP
#define MULTICAGE_EDITOR_CANVAS_HPP

#include <imgui.h>

#include "editor_state.hpp"

namespace multicage_editor {

/** Image point p on the screen, for the canvas whose top-left corner is origin. */
ImVec2 toScreen(const Editor& e, ImVec2 origin, cv::Point2f p);
/** The document's polygons at pts (user vertices in vertices() order), coloured by depth, or
red when bad. */
void drawPolygons(const Editor& e, const std::vector<cv::Point2f>& pts, bool bad, ImDrawList* dl,
                  ImVec2 origin);

/** The canvas window right of the side panel: mouse edits, then playback and the deformation
follow them, then the image, the overlay and the status line are drawn. */
void canvas(Editor& e, View& v, const Settings& s);
/** The keyboard shortcuts (none while a text field has the keyboard). */
void keyboard(Editor& e, Settings& s, GLFWwindow* window);
/** The help window (H or F1), when shown. */
void helpWindow(Settings& s);

}  // namespace multicage_editor

#endif

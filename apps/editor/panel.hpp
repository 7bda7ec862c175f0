// The side panel: files, mode, edits, deformation settings, poses, animation, export, status.
#ifndef MULTICAGE_EDITOR_PANEL_HPP
#define MULTICAGE_EDITOR_PANEL_HPP

#include "editor_state.hpp"

namespace multicage_editor {

/** The side panel window, kPanelWidth wide on the left of the window. */
void panel(Editor& e, View& v, Settings& s, GLFWwindow* window);

}  // namespace multicage_editor

#endif

// Actions shared by the UI, the keyboard and the script: open, save, export, propose, edit,
// undo, animate. Each leaves a message in Editor::message; errors are thrown.
#ifndef MULTICAGE_EDITOR_ACTIONS_HPP
#define MULTICAGE_EDITOR_ACTIONS_HPP

#include <string>

#include "editor_state.hpp"

namespace multicage_editor {

// Document helpers.
bool samePolygons(const mc::Multicage& a, const mc::Multicage& b);
void updateValidity(Editor& e);
/** Call after every edit: the rest orientation is kept and validity updated. */
void afterEdit(Editor& e);
/** Call before every edit: the state to undo to. */
void edit(Editor& e);
void setDocument(Editor& e, const Document& d);

/** "1 polygon", "2 polygons". */
std::string count(int n, const char* one, const char* many);

void openImage(Editor& e, View& v, Settings& s, const std::string& path);
void openCage(Editor& e, const std::string& path, Settings& s);
void saveCage(Editor& e, const std::string& path, const Settings& s);
void exportImage(Editor& e, const std::string& path, const Settings& s, GLFWwindow* window);
void propose(Editor& e, Settings& s);
void setMode(Editor& e, Mode m);
void finishPolygon(Editor& e);
void deleteSelection(Editor& e, bool wholePolygons);
void undo(Editor& e);
void redo(Editor& e);
void selectPolygonOf(Editor& e, int polygon);

// Animation: keyframes are the cage's timed poses; playback moves only the shown pose.
void addKeyframeHere(Editor& e);
void setPlaying(Editor& e, bool play);
/** While playing, the shown pose is the animation's pose at the playhead. */
void advancePlayback(Editor& e);

}  // namespace multicage_editor

#endif

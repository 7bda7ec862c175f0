// The view in the window's own GL context: the plain image texture, the deformation
// (GLDeformer renders into a texture of this context: no readback per frame), screenshots.
#ifndef MULTICAGE_EDITOR_VIEW_HPP
#define MULTICAGE_EDITOR_VIEW_HPP

#include <string>

#include "editor_state.hpp"

namespace multicage_editor {

/** The image GLDeformer renders for display: 8-bit RGBA, so ImGui shows it as is. */
cv::Mat displayImage(const cv::Mat& image);
/** Uploads the display image (8-bit RGBA from displayImage(), the same pixels the GLDeformer
renders in Pose mode) as is: converting it again would swap red and blue in Rest mode. */
void uploadImageTexture(View& v, const cv::Mat& rgba);
/** Writes the window's back buffer (as drawn this frame) to path. */
void screenshot(GLFWwindow* window, const std::string& path);

/** The deformation: rebind when the rest multicage changes, setPose + render when the pose
does (Pose mode), or when the size does (Resize mode: the resize pose). */
void updateDeformation(Editor& e, View& v, const Settings& s);

}  // namespace multicage_editor

#endif

#include "panel.hpp"

#include <imgui.h>

#include <cstdio>
#include <exception>
#include <string>

#include "actions.hpp"
#include "resize_mode.hpp"

namespace multicage_editor {

namespace {

void section(const char* title) {
    ImGui::Spacing();
    ImGui::TextColored(ImVec4(0.65f, 0.75f, 0.9f, 1.f), "%s", title);
    ImGui::Separator();
}

bool inputPath(const char* label, std::string& s) {
    char buf[1024];
    std::snprintf(buf, sizeof buf, "%s", s.c_str());
    const bool enter =
        ImGui::InputText(label, buf, sizeof buf, ImGuiInputTextFlags_EnterReturnsTrue);
    s = buf;
    return enter;
}

/** Runs an action; its error becomes the message. */
template <class F>
void attempt(Editor& e, F&& f) {
    try {
        f();
    } catch (const std::exception& ex) {
        e.message = ex.what();
    }
}

/** Title, image and cage files. */
void filesSection(Editor& e, View& v, Settings& s) {
    ImGui::TextColored(ImVec4(1.f, 0.77f, 0.f, 1.f), "multicage editor");
    ImGui::SameLine(ImGui::GetWindowWidth() - 70);
    if (ImGui::SmallButton("Help (H)")) s.showHelp = !s.showHelp;
    ImGui::Separator();

    ImGui::PushItemWidth(-70);
    if (inputPath("##image", e.imagePath)) attempt(e, [&] { openImage(e, v, s, e.imagePath); });
    ImGui::SameLine();
    if (ImGui::Button("Open", ImVec2(-1, 0))) attempt(e, [&] { openImage(e, v, s, e.imagePath); });
    inputPath("##cage", e.cagePath);
    ImGui::PopItemWidth();
    if (ImGui::Button("Load cage")) attempt(e, [&] { openCage(e, e.cagePath, s); });
    ImGui::SameLine();
    if (ImGui::Button("Save cage (Ctrl+S)")) attempt(e, [&] { saveCage(e, e.cagePath, s); });
    ImGui::Spacing();
}

/** Mode, propose, undo, redo, delete. */
void editSection(Editor& e, Settings& s) {
    ImGui::AlignTextToFramePadding();
    ImGui::Text("Mode (Tab)");
    ImGui::SameLine();
    if (ImGui::RadioButton("Rest", e.mode == Mode::Rest)) setMode(e, Mode::Rest);
    ImGui::SameLine();
    if (ImGui::RadioButton("Pose", e.mode == Mode::Pose)) setMode(e, Mode::Pose);
    ImGui::SameLine();
    if (ImGui::RadioButton("Resize (R)", e.mode == Mode::Resize)) setMode(e, Mode::Resize);
    if (ImGui::Button("Propose multicage", ImVec2(-1, 0))) attempt(e, [&] { propose(e, s); });
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
}

void deformationSection(Settings& s) {
    section("Deformation");
    ImGui::Checkbox("Show cage (C)", &s.showCage);
    // In the order of CoordinateType's values: the combo's index is the type.
    const char* coords[] = {"Mean value", "Harmonic", "Local mean value"};
    ImGui::Combo("Coordinates", &s.coordinates, coords, 3);
    ImGui::SliderInt("Grid step", &s.gridStep, 1, 16);
    ImGui::SliderInt("Export step", &s.exportGridStep, 1, 8);
}

/** Resize mode: the size typed (applied on Enter, so that typing "1" on the way to "1200"
does not resize to one pixel), and presets. */
void resizeSection(Editor& e, const View& v) {
    section("Resize");
    int size[2] = {e.resizeTo.width, e.resizeTo.height};
    ImGui::PushItemWidth(-90);
    if (ImGui::InputInt2("##resize", size, ImGuiInputTextFlags_EnterReturnsTrue))
        setResizeSize(e, cv::Size(size[0], size[1]));
    ImGui::PopItemWidth();
    ImGui::SameLine();
    ImGui::TextUnformatted("W x H");
    const cv::Size image = e.image.size();
    if (ImGui::Button("Original")) setResizeSize(e, image);
    ImGui::SameLine();
    if (ImGui::Button("16:9"))
        setResizeSize(e, cv::Size(cvRound(image.height * 16.0 / 9), image.height));
    ImGui::SameLine();
    if (ImGui::Button("4:3"))
        setResizeSize(e, cv::Size(cvRound(image.height * 4.0 / 3), image.height));
    ImGui::SameLine();
    if (ImGui::Button("1:1")) setResizeSize(e, cv::Size(image.height, image.height));
    ImGui::Text("resize pose %.1f ms, render %.1f ms", v.resizePoseMs, v.renderMs);
}

void posesSection(Editor& e) {
    section("Poses");
    for (int i = 0; i < e.doc.cage.poseCount(); ++i) {
        ImGui::PushID(i);
        if (ImGui::Selectable(e.doc.cage.pose(i).name.c_str(),
                              e.doc.pose == e.doc.cage.pose(i).vertices)) {
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
        const std::string problem = mc::poseNameProblem(e.poseName);  // addPose would throw
        if (!problem.empty()) {
            e.message = "pose name " + problem + ": a cage file could not keep it";
        } else {
            edit(e);
            addPose(e.doc, e.poseName);
            afterEdit(e);
            e.message = std::string("pose '") + e.poseName + "' stored";
        }
    }
}

void animationSection(Editor& e) {
    section("Animation");
    ImGui::PushItemWidth(-150);
    ImGui::InputFloat("##keytime", &e.keyTime, 0.25f, 1.f, "%.2f s");
    ImGui::PopItemWidth();
    ImGui::SameLine();
    if (ImGui::Button("Add keyframe (K)", ImVec2(-1, 0))) attempt(e, [&] { addKeyframeHere(e); });
    std::string keyWhy;
    const bool canPlay = mc::validateKeyframes(e.doc.cage, &keyWhy);
    if (!canPlay && !e.playing) ImGui::BeginDisabled();
    if (ImGui::Button(e.playing ? "Stop (P)" : "Play (P)", ImVec2(120, 0)))
        attempt(e, [&] { setPlaying(e, !e.playing); });
    if (!canPlay && !e.playing) {
        ImGui::EndDisabled();
        if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
            ImGui::SetTooltip("%s", keyWhy.c_str());
    }
    ImGui::SameLine();
    ImGui::Checkbox("Loop", &e.loop);
    if (e.playing)
        ImGui::Text("t = %.2f s of %.2f s", e.playhead,
                    mc::animationDuration(e.shown.cage, e.loop));
}

void exportSection(Editor& e, const Settings& s, GLFWwindow* window) {
    section(e.mode == Mode::Resize ? "Export (the resized image)" : "Export");
    ImGui::PushItemWidth(-70);
    inputPath("##export", e.exportPath);
    ImGui::PopItemWidth();
    ImGui::SameLine();
    if (ImGui::Button(e.mode == Mode::Resize ? "Save" : "Export", ImVec2(-1, 0)))
        attempt(e, [&] { exportImage(e, e.exportPath, s, window); });
}

void statusSection(const Editor& e, const View& v) {
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
                    v.binding.gridSize.height,
                    mc::coordinateTypeDescription(v.binding.coordinates));
        ImGui::Text("min conditioning %.2g", v.binding.minConditioning);
        if (v.binding.minConditioning < mc::kConditioningWarning)
            ImGui::TextColored(ImVec4(1, 0.6f, 0.2f, 1),
                               "warning: ill-conditioned near (%.0f, %.0f)", v.binding.worstNode.x,
                               v.binding.worstNode.y);
        if (v.folded > 0)
            ImGui::TextColored(ImVec4(1, 0.6f, 0.2f, 1), "fold-over: %d triangles", v.folded);
    }
    ImGui::Text("frame %.1f ms, pose render %.1f ms", v.frameMs, v.renderMs);
    if (!e.message.empty()) ImGui::TextWrapped("%s", e.message.c_str());
}

}  // namespace

void panel(Editor& e, View& v, Settings& s, GLFWwindow* window) {
    ImGui::SetNextWindowPos(ImVec2(0, 0));
    ImGui::SetNextWindowSize(ImVec2(kPanelWidth, ImGui::GetIO().DisplaySize.y));
    ImGui::Begin("panel", nullptr, ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove);
    filesSection(e, v, s);
    editSection(e, s);
    deformationSection(s);
    if (e.mode == Mode::Resize) resizeSection(e, v);
    posesSection(e);
    animationSection(e);
    exportSection(e, s, window);
    statusSection(e, v);
    ImGui::End();
}

}  // namespace multicage_editor

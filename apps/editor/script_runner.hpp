// Scripted mode (--script FILE): one command per frame (wait N: N frames), synthetic mouse
// and keyboard input fed to ImGui, screenshots and the bench-drag timings. The script's
// parsing and its verbs (names, argument counts, usage) are in script.hpp.
#ifndef MULTICAGE_EDITOR_SCRIPT_RUNNER_HPP
#define MULTICAGE_EDITOR_SCRIPT_RUNNER_HPP

#include <deque>
#include <string>
#include <vector>

#include "editor_state.hpp"
#include "script.hpp"

namespace multicage_editor {

/** bench-drag's times (ms), one sample per frame. */
struct BenchStats {
    std::vector<double> frame, render, fold, draw;
    void clear();
    void add(double frameMs, double renderMs, double foldMs, double drawMs);
};

struct Script {
    std::vector<ScriptCommand> commands;
    size_t next = 0;
    int waitFrames = 0;
    int benchFrames = 0, benchVertex = 0, benchFrame = 0;
    std::vector<cv::Point2f> benchStart;
    BenchStats bench;
    std::string screenshotPath, lastMessage;
    /** Synthetic input, one entry per frame (click, mouse-drag, key): fed to ImGui exactly
    where the GLFW backend's input goes, so the canvas code paths run as for a user. */
    struct Input {
        cv::Point2f at;  // image coordinates
        bool down = false, shift = false, ctrl = false;
        int key = -1;  // a GLFW key held this frame
    };
    std::deque<Input> input;
    int heldKey = -1;
    bool failed = false;
    bool active() const { return !commands.empty(); }
};

/** Before ImGui::NewFrame: replaces the backend's mouse and key state with the next input. */
void injectInput(Script& sc, const Editor& e);
/** Runs due commands; returns false when the script says quit or fails. */
bool runScript(Script& sc, Editor& e, View& v, Settings& s, GLFWwindow* window);
/** After rendering, before the swap: the screenshot a command asked for this frame, if any.
Returns false when it could not be written (the script has failed). */
bool takeScreenshot(Script& sc, GLFWwindow* window);
/** After each bench-drag frame (GL finished): records its times; after the last frame, prints
the medians and ends the bench. */
void benchFrameDone(Script& sc, const Editor& e, View& v, const Settings& s, double frameMs,
                    double drawMs);

}  // namespace multicage_editor

#endif

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
#include "canvas.hpp"
#include "document.hpp"
#include "editor_state.hpp"
#include "panel.hpp"
#include "script.hpp"
#include "view.hpp"

using namespace multicage_editor;
using cv::Point2f;

namespace {

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
        panel(e, v, s, window);
        canvas(e, v, s);
        helpWindow(s);

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

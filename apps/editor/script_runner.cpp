#include <epoxy/gl.h>
// GLFW after epoxy: epoxy must be the one GL header.
#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <cctype>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <string>

#include "actions.hpp"
#include "canvas.hpp"
#include "resize_mode.hpp"
#include "script_runner.hpp"
#include "stats.hpp"
#include "view.hpp"

namespace multicage_editor {

using cv::Point2f;

namespace {

const char* modeName(Mode m) {
    return m == Mode::Rest ? "rest" : m == Mode::Pose ? "pose" : "resize";
}

void writeStatus(const Editor& e, const View& v, const Settings& s, const std::string& path) {
    std::ostringstream o;
    const cv::Size out = v.deformer ? v.deformer->outputSize() : cv::Size();
    o << "mode: " << modeName(e.mode) << "\n"
      << "resize: " << e.resizeTo.width << " " << e.resizeTo.height << "\n"
      << "output: " << out.width << " " << out.height << "\n"
      << "view: " << e.zoom << " " << e.pan.x << " " << e.pan.y << "\n"
      << "canvas: " << e.canvasArea.width << " " << e.canvasArea.height << "\n"
      << "render_ms: " << v.renderMs << "\nresize_pose_ms: " << v.resizePoseMs << "\n"
      << "rest_valid: " << e.restOk << "\nrest_reason: " << e.restWhy << "\n"
      << "pose_valid: " << e.poseOk << "\npose_reason: " << e.poseWhy << "\n"
      << "polygons: " << e.doc.cage.polygonCount() << "\nvertices: " << e.doc.cage.vertexCount()
      << "\n"
      << "poses: " << e.doc.cage.poseCount() << "\nundo: " << e.history.undoCount() << "\n"
      << "playing: " << e.playing << "\nplayhead: " << e.playhead << "\n"
      << "folded: " << v.folded << "\nmin_conditioning: " << v.binding.minConditioning << "\n"
      << "bind_ms: " << v.bindMs << "\ngrid_step: " << s.gridStep
      << "\ncoordinates: " << mc::coordinateTypeName(s.coordinates) << "\n"
      << "selection:";
    for (int i : e.selection) o << " " << i;
    o << "\nrest:";
    for (const Point2f& p : positions(e.doc, Mode::Rest)) o << " " << p.x << " " << p.y;
    o << "\nshown_pose:";
    for (const Point2f& p : e.shown.pose) o << " " << p.x << " " << p.y;
    o << "\nresize_pose:";  // the last one resize mode rendered, frame corners last
    for (const Point2f& p : v.resizePose) o << " " << p.x << " " << p.y;
    o << "\nmessage: " << e.message << "\n";
    mc::writeFileAtomic(path, o.str());
}

int keyByName(const std::string& name) {
    static const std::pair<const char*, int> keys[] = {
        {"delete", GLFW_KEY_DELETE}, {"backspace", GLFW_KEY_BACKSPACE},
        {"enter", GLFW_KEY_ENTER},   {"escape", GLFW_KEY_ESCAPE},
        {"tab", GLFW_KEY_TAB},       {"f1", GLFW_KEY_F1}};
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
        if (c.args[i] == "shift")
            in.shift = true;
        else if (c.args[i] == "ctrl")
            in.ctrl = true;
        else if (c.verb == "key" && i == 0)
            in.key = keyByName(c.args[i]);
        else
            throw std::runtime_error(c.verb + ": unknown modifier '" + c.args[i] + "'");
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

using multicage_apps::median;

/** One bench-drag frame: drag one pose vertex along a circle, one position per frame. */
void benchStep(Script& sc, Editor& e) {
    const double a = 2 * CV_PI * sc.benchFrame / 60.0;
    e.doc.pose[static_cast<size_t>(sc.benchVertex)] =
        sc.benchStart[static_cast<size_t>(sc.benchVertex)] +
        Point2f(static_cast<float>(12 * std::sin(a)), static_cast<float>(12 * (1 - std::cos(a))));
    updateValidity(e);
    ++sc.benchFrame;
}

// ---------------------------------------------------------------------------------------
// The commands: one handler per verb of scriptVerbs() (script.cpp), which parseScript has
// checked, with its argument count, before the script starts.

/** What a handler leaves to do after its command. */
enum class Flow {
    Next,       // print the new message, run the next command in this frame
    NextFrame,  // print the new message, the next command in the next frame (its result is drawn)
    Yield,      // the next command in a later frame (screenshot, wait, input, bench-drag)
    Quit,
};

struct Session {
    Script& sc;
    Editor& e;
    View& v;
    Settings& s;
    GLFWwindow* window;
};

int vertexArg(const Editor& e, const ScriptCommand& c, size_t i) {
    const int id = static_cast<int>(numberArg(c, i));
    if (id < 0 || id >= e.doc.cage.vertexCount())
        throw std::runtime_error("vertex " + std::to_string(id) + " out of range (" +
                                 std::to_string(e.doc.cage.vertexCount()) + " vertices)");
    return id;
}

int gridStepArg(const ScriptCommand& c) {
    const int step = static_cast<int>(numberArg(c, 0));
    if (step < 1 || step > 64) throw std::runtime_error("grid step must be 1..64");
    return step;
}

/** click, double-click, mouse-drag, key: input for the next frames. */
Flow queueInputCommand(Session& r, const ScriptCommand& c) {
    queueInput(r.sc, c);
    return Flow::Yield;
}

/** bench-drag N [I]: the next N frames drag vertex I, timed (see benchFrameDone). */
Flow startBench(Session& r, const ScriptCommand& c) {
    Script& sc = r.sc;
    Editor& e = r.e;
    if (e.mode != Mode::Pose) setMode(e, Mode::Pose);
    sc.benchFrames = std::max(1, static_cast<int>(numberArg(c, 0)));
    sc.benchVertex = c.args.size() > 1 ? vertexArg(e, c, 1) : 0;
    if (e.doc.cage.vertexCount() == 0) throw std::runtime_error("bench-drag: no vertices");
    sc.benchStart = e.doc.pose;
    sc.benchFrame = 0;
    sc.bench.clear();
    r.v.finishForTiming = true;
    return Flow::Yield;
}

using Handler = Flow (*)(Session&, const ScriptCommand&);

struct Command {
    const char* verb;
    Handler run;
};

const Command kCommands[] = {
    {"load",
     [](Session& r, const ScriptCommand& c) {
         openImage(r.e, r.v, r.s, c.args[0]);
         if (c.args.size() > 1) openCage(r.e, c.args[1], r.s);
         return Flow::NextFrame;
     }},
    {"load-cage",
     [](Session& r, const ScriptCommand& c) {
         openCage(r.e, c.args[0], r.s);
         return Flow::Next;
     }},
    {"propose",
     [](Session& r, const ScriptCommand&) {
         propose(r.e, r.s);
         return Flow::NextFrame;
     }},
    {"mode",
     [](Session& r, const ScriptCommand& c) {
         Mode m = Mode::Rest;
         if (c.args[0] == "pose")
             m = Mode::Pose;
         else if (c.args[0] == "resize")
             m = Mode::Resize;
         else if (c.args[0] != "rest")
             throw std::runtime_error("mode rest|pose|resize");
         setMode(r.e, m);
         if (r.e.mode != m) throw std::runtime_error(r.e.message);
         return Flow::NextFrame;
     }},
    {"resize",
     [](Session& r, const ScriptCommand& c) {
         Editor& e = r.e;
         if (e.image.empty()) throw std::runtime_error("resize: open an image first");
         if (e.mode != Mode::Resize) setMode(e, Mode::Resize);
         if (e.mode != Mode::Resize) throw std::runtime_error(e.message);
         const double w = numberArg(c, 0), h = numberArg(c, 1);
         if (w < 1 || h < 1 || w != std::floor(w) || h != std::floor(h))
             throw std::runtime_error("resize: W and H are whole numbers of pixels, at least 1");
         const cv::Size wanted(static_cast<int>(w), static_cast<int>(h));
         setResizeSize(e, wanted);
         if (e.resizeTo != wanted) throw std::runtime_error(e.message);  // clamped: say so
         return Flow::NextFrame;  // rendered at the new size in the next frame
     }},
    {"drag",
     [](Session& r, const ScriptCommand& c) {
         Editor& e = r.e;
         edit(e);
         moveVertices(e.doc, e.mode, {vertexArg(e, c, 0)},
                      Point2f(float(numberArg(c, 1)), float(numberArg(c, 2))));
         afterEdit(e);
         return Flow::NextFrame;
     }},
    {"drag-polygon",
     [](Session& r, const ScriptCommand& c) {
         Editor& e = r.e;
         const int p = static_cast<int>(numberArg(c, 0));
         if (p < 0 || p >= e.doc.cage.polygonCount())
             throw std::runtime_error("no polygon " + c.args[0]);
         selectPolygonOf(e, p);
         edit(e);
         moveVertices(e.doc, e.mode, e.selection,
                      Point2f(float(numberArg(c, 1)), float(numberArg(c, 2))));
         afterEdit(e);
         return Flow::Next;
     }},
    {"add-polygon",
     [](Session& r, const ScriptCommand& c) {
         Editor& e = r.e;
         if (e.mode != Mode::Rest || c.args.size() % 2)
             throw std::runtime_error("add-polygon: rest mode, x y pairs");
         e.creating = true;
         e.creation.clear();
         for (size_t i = 0; i + 1 < c.args.size(); i += 2)
             e.creation.emplace_back(float(numberArg(c, i)), float(numberArg(c, i + 1)));
         finishPolygon(e);
         return Flow::Next;
     }},
    {"insert-vertex",
     [](Session& r, const ScriptCommand& c) {
         Editor& e = r.e;
         edit(e);
         if (insertVertex(e.doc, static_cast<int>(numberArg(c, 0)),
                          static_cast<int>(numberArg(c, 1)), float(numberArg(c, 2))) < 0)
             throw std::runtime_error("no such polygon edge");
         afterEdit(e);
         return Flow::Next;
     }},
    {"delete-vertex",
     [](Session& r, const ScriptCommand& c) {
         Editor& e = r.e;
         if (e.mode != Mode::Rest) throw std::runtime_error("delete-vertex: rest mode only");
         e.selection = {vertexArg(e, c, 0)};
         deleteSelection(e, false);
         return Flow::Next;
     }},
    {"coords",
     [](Session& r, const ScriptCommand& c) {
         if (!mc::parseCoordinateType(c.args[0], r.s.coordinates))
             throw std::runtime_error("coords mvc|harmonic");
         return Flow::Next;
     }},
    {"grid-step",
     [](Session& r, const ScriptCommand& c) {
         r.s.gridStep = gridStepArg(c);
         return Flow::Next;
     }},
    {"export-grid-step",
     [](Session& r, const ScriptCommand& c) {
         r.s.exportGridStep = gridStepArg(c);
         return Flow::Next;
     }},
    {"show-cage",
     [](Session& r, const ScriptCommand& c) {
         r.s.showCage = numberArg(c, 0) != 0;
         return Flow::Next;
     }},
    {"help",
     [](Session& r, const ScriptCommand& c) {
         r.s.showHelp = numberArg(c, 0) != 0;
         return Flow::Next;
     }},
    {"undo",
     [](Session& r, const ScriptCommand&) {
         undo(r.e);
         return Flow::Next;
     }},
    {"redo",
     [](Session& r, const ScriptCommand&) {
         redo(r.e);
         return Flow::Next;
     }},
    {"add-pose",
     [](Session& r, const ScriptCommand& c) {
         edit(r.e);
         addPose(r.e.doc, c.args[0]);
         afterEdit(r.e);
         return Flow::Next;
     }},
    {"set-pose",
     [](Session& r, const ScriptCommand& c) {
         Editor& e = r.e;
         const int i = e.doc.cage.findPose(c.args[0]);
         if (i < 0) throw std::runtime_error("no pose named " + c.args[0]);
         edit(e);
         e.doc.pose = e.doc.cage.pose(i).vertices;
         afterEdit(e);
         return Flow::Next;
     }},
    {"add-keyframe",
     [](Session& r, const ScriptCommand& c) {
         r.e.keyTime = static_cast<float>(numberArg(c, 0));
         addKeyframeHere(r.e);
         return Flow::Next;
     }},
    {"play",
     [](Session& r, const ScriptCommand& c) {
         setPlaying(r.e, numberArg(c, 0) != 0);
         return Flow::Next;
     }},
    {"save",
     [](Session& r, const ScriptCommand& c) {
         saveCage(r.e, c.args[0], r.s);
         return Flow::Next;
     }},
    {"export",
     [](Session& r, const ScriptCommand& c) {
         exportImage(r.e, c.args[0], r.s, r.window);
         return Flow::Next;
     }},
    {"screenshot",
     [](Session& r, const ScriptCommand& c) {
         r.sc.screenshotPath = c.args[0];
         return Flow::Yield;  // taken after this frame is drawn
     }},
    {"status",
     [](Session& r, const ScriptCommand& c) {
         writeStatus(r.e, r.v, r.s, c.args[0]);
         return Flow::Next;
     }},
    {"window",
     [](Session& r, const ScriptCommand& c) {
         const double w = numberArg(c, 0), h = numberArg(c, 1);
         if (w < kPanelWidth + 64 || h < 64 || w > 16384 || h > 16384)
             throw std::runtime_error("window: W at least the panel's width + 64, H at least 64");
         glfwSetWindowSize(r.window, static_cast<int>(w), static_cast<int>(h));
         return Flow::NextFrame;
     }},
    {"wait",
     [](Session& r, const ScriptCommand& c) {
         r.sc.waitFrames = std::max(0, static_cast<int>(numberArg(c, 0)) - 1);
         return Flow::Yield;
     }},
    {"click", queueInputCommand},
    {"double-click", queueInputCommand},
    {"mouse-drag", queueInputCommand},
    {"key", queueInputCommand},
    {"bench-drag", startBench},
    {"quit", [](Session&, const ScriptCommand&) { return Flow::Quit; }},
};

/** The handler of a verb (parseScript accepts only the verbs of scriptVerbs()). */
Handler handlerFor(const std::string& verb) {
    for (const Command& c : kCommands)
        if (verb == c.verb) return c.run;
    throw std::logic_error("script verb '" + verb + "' has no handler");
}

/** Prints the command as the script's log line. */
void echo(const ScriptCommand& c) {
    std::printf("script:%d: %s", c.line, c.verb.c_str());
    for (const std::string& a : c.args) std::printf(" %s", a.c_str());
    std::printf("\n");
    std::fflush(stdout);
}

}  // namespace

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

bool runScript(Script& sc, Editor& e, View& v, Settings& s, GLFWwindow* window) {
    if (sc.benchFrames > 0) {
        benchStep(sc, e);
        return true;
    }
    if (!sc.input.empty()) return true;
    if (sc.waitFrames > 0) {
        --sc.waitFrames;
        return true;
    }
    Session session{sc, e, v, s, window};
    while (sc.next < sc.commands.size()) {
        const ScriptCommand& c = sc.commands[sc.next++];
        Flow flow = Flow::Next;
        try {
            echo(c);
            flow = handlerFor(c.verb)(session, c);
            if (flow == Flow::Next || flow == Flow::NextFrame) {
                if (e.message != sc.lastMessage) std::printf("  %s\n", e.message.c_str());
                sc.lastMessage = e.message;
            }
        } catch (const std::exception& ex) {
            std::fprintf(stderr, "multicage-editor: script line %d (%s): %s\n", c.line,
                         c.verb.c_str(), ex.what());
            sc.failed = true;
            return false;
        }
        if (flow == Flow::Quit) return false;
        if (flow != Flow::Next) return true;
    }
    glfwSetWindowShouldClose(window, 1);  // the script ran out without quit
    return true;
}

bool takeScreenshot(Script& sc, GLFWwindow* window) {
    if (sc.screenshotPath.empty()) return true;
    bool ok = true;
    try {
        screenshot(window, sc.screenshotPath);
        std::printf("  wrote %s\n", sc.screenshotPath.c_str());
    } catch (const std::exception& ex) {
        std::fprintf(stderr, "multicage-editor: screenshot: %s\n", ex.what());
        sc.failed = true;
        ok = false;
    }
    sc.screenshotPath.clear();
    return ok;
}

void BenchStats::clear() {
    frame.clear();
    render.clear();
    fold.clear();
    draw.clear();
}

void BenchStats::add(double frameMs, double renderMs, double foldMs, double drawMs) {
    frame.push_back(frameMs);
    render.push_back(renderMs);
    fold.push_back(foldMs);
    draw.push_back(drawMs);
}

void benchFrameDone(Script& sc, const Editor& e, View& v, const Settings& s, double frameMs,
                    double drawMs) {
    sc.bench.add(frameMs, v.renderMs, v.foldMs, drawMs);
    if (--sc.benchFrames > 0) return;
    const BenchStats& b = sc.bench;
    std::printf(
        "bench-drag: %zu frames, %dx%d image, %d vertices, grid step %d: median frame %.1f ms "
        "(GLDeformer setPose + render %.1f ms, fold count %.1f ms, ImGui draw + swap %.1f ms)\n",
        b.frame.size(), e.image.cols, e.image.rows, e.doc.cage.vertexCount(), s.gridStep,
        median(b.frame), median(b.render), median(b.fold), median(b.draw));
    v.finishForTiming = false;
    std::fflush(stdout);
}

}  // namespace multicage_editor

#include "script.hpp"

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace multicage_editor {

const std::vector<ScriptVerb>& scriptVerbs() {
    static const std::vector<ScriptVerb> verbs = {
        {"load", 1, 2, "load IMAGE [CAGE]      open an image (and a cage file)"},
        {"load-cage", 1, 1, "load-cage CAGE         open a cage file for the current image"},
        {"propose", 0, 0,
         "propose                faces, outlines, features (propose --protect all)"},
        {"mode", 1, 1, "mode rest|pose|resize  edit the rest polygons, the pose, or the size"},
        {"resize", 2, 2, "resize W H             resize mode, content-aware resize to W x H"},
        {"window", 2, 2, "window W H             resize the window to W x H pixels"},
        {"drag", 3, 3, "drag I DX DY           move vertex I (vertices() order) by (DX, DY)"},
        {"drag-polygon", 3, 3, "drag-polygon P DX DY   move every vertex of polygon P"},
        {"add-polygon", 6, 1000, "add-polygon X0 Y0 X1 Y1 X2 Y2 ...   a new polygon (rest mode)"},
        {"insert-vertex", 3, 3, "insert-vertex P E T    a vertex on edge E of polygon P at T"},
        {"delete-vertex", 1, 1, "delete-vertex I        delete vertex I (rest mode)"},
        {"coords", 1, 1, "coords mvc|harmonic|local_mvc  cage coordinates (rebinds)"},
        {"grid-step", 1, 1, "grid-step N            live grid step (rebinds)"},
        {"export-grid-step", 1, 1, "export-grid-step N     grid step of export (default 1)"},
        {"show-cage", 1, 1, "show-cage 0|1          overlay on or off"},
        {"help", 1, 1, "help 0|1               help panel on or off"},
        {"undo", 0, 0, "undo"},
        {"redo", 0, 0, "redo"},
        {"add-pose", 1, 1, "add-pose NAME          store the current pose"},
        {"set-pose", 1, 1, "set-pose NAME          make a saved pose the current one"},
        {"add-keyframe", 1, 1,
         "add-keyframe T         store the current pose as the keyframe at T seconds"},
        {"play", 1, 1, "play 0|1               play the keyframes (Catmull-Rom, looped) or stop"},
        {"save", 1, 1, "save CAGE              write rest polygons and poses"},
        {"export", 1, 1,
         "export OUT             full-resolution deformed image (as multicage deform; resize mode: "
         "resized)"},
        {"screenshot", 1, 1, "screenshot OUT         the window as drawn this frame"},
        {"status", 1, 1,
         "status FILE            write the status (valid, reason, folds, ...) to FILE"},
        {"wait", 1, 1, "wait N                 let N frames pass"},
        {"click", 2, 3,
         "click X Y [shift|ctrl]  a mouse click on the canvas at image point (X, Y)"},
        {"double-click", 2, 2, "double-click X Y       (on an edge in rest mode: insert a vertex)"},
        {"mouse-drag", 4, 5, "mouse-drag X0 Y0 X1 Y1 [shift|ctrl]  press, move, release"},
        {"key", 1, 2,
         "key NAME [shift|ctrl]  delete, backspace, enter, escape, tab, f1 or a letter"},
        {"bench-drag", 1, 2,
         "bench-drag N [I]       drag vertex I (default 0) for N frames, print the median frame "
         "time"},
        {"quit", 0, 0, "quit"},
    };
    return verbs;
}

std::vector<ScriptCommand> parseScript(const std::string& text, const std::string& name) {
    std::vector<ScriptCommand> out;
    std::istringstream in(text);
    std::string line;
    int number = 0;
    while (std::getline(in, line)) {
        ++number;
        std::istringstream words(line);
        ScriptCommand c;
        c.line = number;
        if (!(words >> c.verb) || c.verb[0] == '#') continue;
        for (std::string w; words >> w;) c.args.push_back(w);
        const ScriptVerb* known = nullptr;
        for (const ScriptVerb& v : scriptVerbs())
            if (c.verb == v.verb) known = &v;
        const std::string where = name + ":" + std::to_string(number) + ": ";
        if (!known) throw std::runtime_error(where + "unknown command '" + c.verb + "'");
        const int n = static_cast<int>(c.args.size());
        if (n < known->minArgs || n > known->maxArgs)
            throw std::runtime_error(where + c.verb + " takes " +
                                     (known->minArgs == known->maxArgs
                                          ? std::to_string(known->minArgs)
                                          : std::to_string(known->minArgs) + "+") +
                                     " arguments: " + known->usage);
        out.push_back(c);
    }
    return out;
}

std::vector<ScriptCommand> loadScript(const std::string& path) {
    std::ifstream f(path);
    if (!f) throw std::runtime_error(path + ": cannot read the script");
    std::stringstream ss;
    ss << f.rdbuf();
    return parseScript(ss.str(), path);
}

double numberArg(const ScriptCommand& c, size_t i) {
    const std::string& s = c.args.at(i);
    size_t used = 0;
    double v = 0;
    try {
        v = std::stod(s, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used != s.size() || s.empty())
        throw std::runtime_error("line " + std::to_string(c.line) + ": '" + s +
                                 "' is not a number");
    return v;
}

}  // namespace multicage_editor

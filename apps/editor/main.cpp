// multicage-editor [IMAGE [CAGE.yml]] [--script FILE]: draw or propose a multicage over an
// image, drag its vertices and see the deformation live.
//
// One flat loop (poll, new frame, describe the UI, render, swap) over plain structs
// (editor_state.hpp): the document and its edits are in document.cpp, the actions on it in
// actions.cpp, the side panel in panel.cpp, the canvas in canvas.cpp, the scripted mode in
// script_runner.cpp, the deformation in the library (GLDeformer draws into a texture of this
// window's own GL context: no readback per frame, view.cpp).
#include <epoxy/gl.h>
// GLFW after epoxy: epoxy must be the one GL header.
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "actions.hpp"
#include "canvas.hpp"
#include "editor_state.hpp"
#include "panel.hpp"
#include "script.hpp"
#include "script_runner.hpp"

using namespace multicage_editor;

namespace {

struct Options {
    std::vector<std::string> positional;  // IMAGE [CAGE.yml]
    std::string scriptPath;
    bool allowInvalid = false;
};

/** Reads the command line; returns the exit code when the program should stop (--help, a
usage error), -1 to go on. */
int parseArgs(int argc, char** argv, Options& o) {
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "-h" || a == "--help") {
            std::printf(
                "multicage-editor [IMAGE [CAGE.yml]] [--script FILE] [--allow-invalid]\n"
                "Draw or propose a multicage over an image, drag its vertices, see the "
                "deformation live.\n"
                "Press H in the window for the keys.\n"
                "--allow-invalid: save poses whose polygons cross, leave the frame or change "
                "nesting (refused otherwise, as multicage deform refuses them).\n\nScript commands "
                "(one per line, # "
                "comments):\n");
            for (const ScriptVerb& v : scriptVerbs()) std::printf("  %s\n", v.usage);
            return 0;
        } else if (a == "--allow-invalid") {
            o.allowInvalid = true;
        } else if (a == "--script" && i + 1 < argc) {
            o.scriptPath = argv[++i];
        } else if (!a.empty() && a[0] == '-') {
            std::fprintf(stderr, "multicage-editor: unknown option %s (see --help)\n", a.c_str());
            return 2;
        } else {
            o.positional.push_back(a);
        }
    }
    if (o.positional.size() > 2) {
        std::fprintf(stderr, "multicage-editor: at most IMAGE and CAGE.yml (see --help)\n");
        return 2;
    }
    return -1;
}

/** The window with a GL 4.3 core context, current; null (said on stderr) when there is none. */
GLFWwindow* createWindow(bool scripted) {
    if (!glfwInit()) {
        std::fprintf(stderr,
                     "multicage-editor: cannot initialise GLFW (no display? try xvfb-run)\n");
        return nullptr;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);  // GLDeformer needs 4.3 core
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    GLFWwindow* window = glfwCreateWindow(1280, 800, "multicage editor", nullptr, nullptr);
    if (!window) {
        std::fprintf(stderr, "multicage-editor: cannot create an OpenGL 4.3 core window\n");
        glfwTerminate();
        return nullptr;
    }
    glfwMakeContextCurrent(window);
    glfwSwapInterval(scripted ? 0 : 1);
    return window;
}

void initImGui(GLFWwindow* window) {
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
}

}  // namespace

int main(int argc, char** argv) {
    Options options;
    const int usage = parseArgs(argc, argv, options);
    if (usage >= 0) return usage;
    Script script;
    if (!options.scriptPath.empty()) {
        try {
            script.commands = loadScript(options.scriptPath);
        } catch (const std::exception& ex) {
            std::fprintf(stderr, "multicage-editor: %s\n", ex.what());
            return 2;
        }
    }

    GLFWwindow* window = createWindow(script.active());
    if (!window) return 1;
    initImGui(window);

    Editor e;
    View v;
    Settings s;
    s.allowInvalid = options.allowInvalid;
    int rc = 0;
    try {
        if (!options.positional.empty()) openImage(e, v, s, options.positional[0]);
        if (options.positional.size() > 1) openCage(e, options.positional[1], s);
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
        if (!takeScreenshot(script, window)) running = false;
        glfwSwapBuffers(window);
        if (script.benchFrames > 0) {
            glFinish();  // bench: the frame's GL work is done before its time is taken
            benchFrameDone(script, e, v, s, msSince(frameStart), msSince(drawStart));
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

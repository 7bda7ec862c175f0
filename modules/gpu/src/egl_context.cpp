#include "egl_context.hpp"

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <cstring>
#include <mutex>
#include <opencv2/core.hpp>
#include <vector>

#include "gl_util.hpp"

namespace cv {
namespace multicage {
namespace gpu {

namespace {

bool hasExtension(const char* list, const char* name) {
    if (!list) return false;
    const size_t len = std::strlen(name);
    for (const char* p = list; (p = std::strstr(p, name)); p += len)
        if ((p == list || p[-1] == ' ') && (p[len] == ' ' || p[len] == '\0')) return true;
    return false;
}

struct HeadlessDisplay {
    EGLDisplay display = EGL_NO_DISPLAY;
    std::string platform;  // which platform gave the display
    std::string why;       // why there is none
};

// The display is opened once per process and never terminated: eglTerminate would pull it
// from under the contexts of every other Deformer, on every thread.
const HeadlessDisplay& headlessDisplay() {
    static HeadlessDisplay d;
    static std::once_flag once;
    std::call_once(once, [] {
        const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
        if (!client) {
            d.why = "EGL has no client extensions (no EGL 1.5 / EGL_EXT_client_extensions)";
            return;
        }
        const bool platformBase = hasExtension(client, "EGL_EXT_platform_base");
        if (platformBase && hasExtension(client, "EGL_EXT_platform_device") &&
            hasExtension(client, "EGL_EXT_device_enumeration")) {
            EGLint count = 0;
            if (eglQueryDevicesEXT(0, nullptr, &count) && count > 0) {
                std::vector<EGLDeviceEXT> devices(count);
                eglQueryDevicesEXT(count, devices.data(), &count);
                for (EGLint i = 0; i < count; ++i) {
                    const char* ext = eglQueryDeviceStringEXT(devices[i], EGL_EXTENSIONS);
                    if (hasExtension(ext, "EGL_MESA_device_software")) continue;  // llvmpipe
                    EGLDisplay dpy =
                        eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
                    EGLint major, minor;
                    if (dpy != EGL_NO_DISPLAY && eglInitialize(dpy, &major, &minor)) {
                        d.display = dpy;
                        d.platform = "EGL device " + std::to_string(i);
                        return;
                    }
                }
            }
        }
        if (platformBase && hasExtension(client, "EGL_MESA_platform_surfaceless")) {
            EGLDisplay dpy = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA,
                                                      EGL_DEFAULT_DISPLAY, nullptr);
            EGLint major, minor;
            if (dpy != EGL_NO_DISPLAY && eglInitialize(dpy, &major, &minor)) {
                d.display = dpy;
                d.platform = "Mesa surfaceless";
                return;
            }
            d.why = "eglInitialize failed on Mesa's surfaceless platform (EGL error 0x" +
                    cv::format("%x", eglGetError()) + ")";
            return;
        }
        d.why =
            "no headless EGL platform: neither a hardware EGL_EXT_platform_device nor "
            "EGL_MESA_platform_surfaceless is available";
    });
    return d;
}

}  // namespace

std::unique_ptr<EglContext> EglContext::create(std::string* why) {
    auto fail = [&](const std::string& reason) {
        if (why) *why = reason;
        return std::unique_ptr<EglContext>();
    };
    const HeadlessDisplay& d = headlessDisplay();
    if (d.display == EGL_NO_DISPLAY) return fail(d.why);
    if (!hasExtension(eglQueryString(d.display, EGL_EXTENSIONS), "EGL_KHR_surfaceless_context"))
        return fail(d.platform + " lacks EGL_KHR_surfaceless_context");
    if (!eglBindAPI(EGL_OPENGL_API)) return fail(d.platform + " has no desktop OpenGL API");
    // No surface is ever made, so any config will do: none at all where EGL allows it, else
    // any desktop GL one (surface type 0: eglChooseConfig's default would demand windows).
    EGLConfig config = EGL_NO_CONFIG_KHR;
    if (!hasExtension(eglQueryString(d.display, EGL_EXTENSIONS), "EGL_KHR_no_config_context")) {
        const EGLint configAttribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, 0,
                                        EGL_NONE};
        EGLint configs = 0;
        if (!eglChooseConfig(d.display, configAttribs, &config, 1, &configs) || configs < 1)
            return fail(d.platform + " has no EGL config for desktop OpenGL");
    }
    EGLContext ctx = EGL_NO_CONTEXT;
    for (int minor : {5, 3}) {  // 4.5 preferred; 4.3 has everything used here (compute, SSBO)
        const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                  4,
                                  EGL_CONTEXT_MINOR_VERSION,
                                  minor,
                                  EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                  EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                  EGL_NONE};
        ctx = eglCreateContext(d.display, config, EGL_NO_CONTEXT, attribs);
        if (ctx != EGL_NO_CONTEXT) break;
    }
    if (ctx == EGL_NO_CONTEXT)
        return fail(d.platform + " cannot create an OpenGL 4.3 core context (EGL error 0x" +
                    cv::format("%x", eglGetError()) + ")");
    std::unique_ptr<EglContext> c(new EglContext());
    c->display_ = d.display;
    c->context_ = ctx;
    {
        Scope scope(*c);
        const char* vendor = reinterpret_cast<const char*>(glGetString(GL_VENDOR));
        const char* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
        const char* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
        c->description_ = std::string(vendor ? vendor : "?") + ", " + (renderer ? renderer : "?") +
                          ", OpenGL " + (version ? version : "?") + ", " + d.platform;
        // Mesa's CPU rasterisers: they run the shaders on the CPU, slower than the CPU backend.
        const std::string r = renderer ? renderer : "";
        c->software_ = r.find("llvmpipe") != std::string::npos ||
                       r.find("softpipe") != std::string::npos ||
                       r.find("lavapipe") != std::string::npos;
    }
    return c;
}

EglContext::EglContext() : programs_(new ProgramCache()) {}

EglContext::~EglContext() {
    // Destroying the context frees its programs: the cache only forgets them.
    programs_->forget();
    if (context_) eglDestroyContext(display_, context_);
}

EglContext* EglContext::shared(std::string* why) {
    static EglContext* context = nullptr;  // never destroyed: see headlessDisplay()
    static std::string reason;
    static std::once_flag once;
    std::call_once(once, [] { context = create(&reason).release(); });
    if (!context && why) *why = reason;
    return context;
}

// The bound API is per thread (default OpenGL ES), and the "current context" queries answer
// for that API: bind desktop GL before looking at what is current.
static void* bindGlApi() {
    eglBindAPI(EGL_OPENGL_API);
    return eglGetCurrentDisplay();
}

EglContext::Scope::Scope(const EglContext& c)
    : lock_(c.mutex_),
      prevCache_(ProgramCache::makeCurrent(c.programs_.get())),
      prevDisplay_(bindGlApi()),
      prevContext_(eglGetCurrentContext()),
      prevDraw_(eglGetCurrentSurface(EGL_DRAW)),
      prevRead_(eglGetCurrentSurface(EGL_READ)) {
    if (!eglMakeCurrent(c.display_, EGL_NO_SURFACE, EGL_NO_SURFACE, c.context_)) {
        ProgramCache::makeCurrent(prevCache_);
        CV_Error_(Error::GpuApiCallError,
                  ("multicage: eglMakeCurrent failed (EGL error 0x%x); is this Deformer in use "
                   "on another thread?",
                   eglGetError()));
    }
}

EglContext::Scope::~Scope() {
    ProgramCache::makeCurrent(prevCache_);
    if (prevContext_ != EGL_NO_CONTEXT)
        eglMakeCurrent(prevDisplay_, prevDraw_, prevRead_, prevContext_);
    else
        eglMakeCurrent(eglGetCurrentDisplay(), EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
}

}  // namespace gpu
}  // namespace multicage
}  // namespace cv

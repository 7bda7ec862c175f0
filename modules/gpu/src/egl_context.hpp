// A headless EGL context with desktop OpenGL 4.5 (or 4.3) core (private to the gpu module).
#ifndef MULTICAGE_EGL_CONTEXT_HPP
#define MULTICAGE_EGL_CONTEXT_HPP

#include <memory>
#include <mutex>
#include <string>

namespace cv {
namespace multicage {
namespace gpu {

/** One EGL context on the process-wide headless display: a hardware EGL device first
(EGL_EXT_platform_device, skipping Mesa's software device), else Mesa's surfaceless platform
(llvmpipe on machines without a GPU). No surface: rendering goes to framebuffer objects. */
class ProgramCache;

class EglContext {
  public:
    /** nullptr with the reason in *why when no display or no GL 4.3+ core context exists. */
    static std::unique_ptr<EglContext> create(std::string* why);
    /** The process-wide context every GPU Deformer shares: made on first use (the EGL probe
    happens once per process), never destroyed. nullptr with *why when there is none; the
    reason is remembered, so a machine without a GPU is probed only once too. Sharing one
    context means one creation cost and compiled programs reused across Deformers (the
    ProgramCache); its Scope's mutex serialises threads, as the GPU would anyway. */
    static EglContext* shared(std::string* why);
    ~EglContext();
    EglContext(const EglContext&) = delete;
    EglContext& operator=(const EglContext&) = delete;

    /** "vendor, renderer, GL version, EGL platform", for logs and the bench. */
    const std::string& description() const { return description_; }
    /** True for a software renderer (Mesa llvmpipe/softpipe): OpenGL on the CPU. */
    bool software() const { return software_; }

    /** Makes the context current on this thread for its lifetime, then restores whatever
    was current before (usually nothing). A context is current on one thread at a time, so
    the Scope holds the context's (recursive) mutex: other threads wait for it. While it
    lasts, ProgramCache::current() is this context's cache. */
    class Scope {
      public:
        explicit Scope(const EglContext& context);
        ~Scope();
        Scope(const Scope&) = delete;
        Scope& operator=(const Scope&) = delete;

      private:
        std::unique_lock<std::recursive_mutex> lock_;
        ProgramCache* prevCache_;
        void* prevDisplay_;
        void* prevContext_;
        void* prevDraw_;
        void* prevRead_;
    };

  private:
    EglContext();
    void* display_ = nullptr;
    void* context_ = nullptr;
    std::string description_;
    bool software_ = false;
    mutable std::recursive_mutex mutex_;
    std::unique_ptr<ProgramCache> programs_;
};

}  // namespace gpu
}  // namespace multicage
}  // namespace cv

#endif

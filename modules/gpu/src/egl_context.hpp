// A headless EGL context with desktop OpenGL 4.5 (or 4.3) core (private to the gpu module).
#ifndef MULTICAGE_EGL_CONTEXT_HPP
#define MULTICAGE_EGL_CONTEXT_HPP

#include <memory>
#include <string>

namespace cv {
namespace multicage {
namespace gpu {

/** One EGL context on the process-wide headless display: a hardware EGL device first
(EGL_EXT_platform_device, skipping Mesa's software device), else Mesa's surfaceless platform
(llvmpipe on machines without a GPU). No surface: rendering goes to framebuffer objects. */
class EglContext {
  public:
    /** nullptr with the reason in *why when no display or no GL 4.3+ core context exists. */
    static std::unique_ptr<EglContext> create(std::string* why);
    ~EglContext();
    EglContext(const EglContext&) = delete;
    EglContext& operator=(const EglContext&) = delete;

    /** "vendor, renderer, GL version, EGL platform", for logs and the bench. */
    const std::string& description() const { return description_; }
    /** True for a software renderer (Mesa llvmpipe/softpipe): OpenGL on the CPU. */
    bool software() const { return software_; }

    /** Makes the context current on this thread for its lifetime, then restores whatever
    was current before (usually nothing). A context is current on one thread at a time:
    one Deformer must not be used by two threads at once. */
    class Scope {
      public:
        explicit Scope(const EglContext& context);
        ~Scope();
        Scope(const Scope&) = delete;
        Scope& operator=(const Scope&) = delete;

      private:
        void* prevDisplay_;
        void* prevContext_;
        void* prevDraw_;
        void* prevRead_;
    };

  private:
    EglContext() = default;
    void* display_ = nullptr;
    void* context_ = nullptr;
    std::string description_;
    bool software_ = false;
};

}  // namespace gpu
}  // namespace multicage
}  // namespace cv

#endif

// gpu_available() and auto_backend(): what backend='gpu' and backend='auto' find here.
#include <mutex>

#include "common.hpp"

namespace multicage_py {
namespace {

using namespace cv::multicage;

// --- GPU probes ------------------------------------------------------------------------
// Made once per process: a probe makes an EGL context (about 100 ms and tens of MB on Mesa),
// and the answer does not change while the process runs.

struct GpuProbe {
    bool available = false;
    std::string description;
};

std::mutex probeMutex;

const GpuProbe& gpuProbe() {
    static GpuProbe probe;
    static bool done = false;
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(probeMutex);
    if (!done) {
        probe.available = gpuAvailable(&probe.description);
        done = true;
    }
    return probe;
}

/** What BACKEND_AUTO takes here: the library's own rule (autoBackendUsesGpu, probed once
per process), not a copy of it. */
int autoBackend() {
    py::gil_scoped_release release;
    return autoBackendUsesGpu() ? BACKEND_GPU : BACKEND_CPU;
}

const char* kGpuAvailableDoc = R"doc(gpu_available() -> (available, description)

Whether an OpenGL context (headless EGL, OpenGL 4.3+) can be made here, that is whether
backend='gpu' works, with the renderer's description or the reason there is none. A software
renderer (Mesa llvmpipe, on machines without a GPU) counts: backend='gpu' runs on it, but
backend='auto' does not take it, because there the CPU backend is faster. What 'auto' takes
is auto_backend(). Probed once per process.)doc";

const char* kAutoBackendDoc = R"doc(auto_backend() -> 'gpu' or 'cpu'

The backend that backend='auto' takes here: 'gpu' where a hardware OpenGL context can be made,
'cpu' where there is none or only a software renderer (gpu_available() says which). Found
once per process by asking the library itself, so it agrees with Deformer(..., backend='auto').)doc";

}  // namespace

void defineGpu(py::module_& m) {
    m.def(
        "gpu_available",
        [] {
            const GpuProbe& probe = gpuProbe();
            return py::make_tuple(probe.available, probe.description);
        },
        kGpuAvailableDoc);
    m.def(
        "auto_backend", [] { return backendName(autoBackend()); }, kAutoBackendDoc);
}

}  // namespace multicage_py

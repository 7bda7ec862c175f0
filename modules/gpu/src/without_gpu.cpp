// The gpu module of a build configured with MULTICAGE_WITH_GPU=OFF: gpu.hpp's API without EGL
// or OpenGL. Nothing can be made (no context, no GLDeformer), so every entry point says why:
// gpuAvailable() is false, shared() is nullptr, the constructors and bindOnGpu() throw. The
// Deformer's GPU backend (deform's gpu_deformer.cpp) asks shared() and passes the reason on.
#include <opencv2/multicage/gpu.hpp>

namespace cv {
namespace multicage {

namespace gpu {
class EglContext {};  // HeadlessGLContext's members name it; none is ever made
}  // namespace gpu

namespace {

const char* const kWhy = "built without GPU support (MULTICAGE_WITH_GPU=OFF)";

[[noreturn]] void unavailable(const std::string& what) {
    CV_Error(Error::GpuNotSupported, "multicage: " + what + ": " + kWhy);
}

}  // namespace

// --- HeadlessGLContext: none can be made --------------------------------------------------

HeadlessGLContext::HeadlessGLContext() {
    unavailable("no headless OpenGL context");
}

HeadlessGLContext::~HeadlessGLContext() = default;

HeadlessGLContext* HeadlessGLContext::shared(std::string* why) {
    if (why) *why = kWhy;
    return nullptr;
}

std::string HeadlessGLContext::description() const {
    unavailable("HeadlessGLContext");
}

bool HeadlessGLContext::software() const {
    unavailable("HeadlessGLContext");
}

struct HeadlessGLContext::Scope::State {};

HeadlessGLContext::Scope::Scope(const HeadlessGLContext&) {
    unavailable("HeadlessGLContext::Scope");
}

HeadlessGLContext::Scope::~Scope() = default;

// --- GLDeformer: the constructors throw, so no member below is ever reached ---------------

struct GLDeformer::Impl {};

GLDeformer::GLDeformer(InputArray, const Binding&, const GLDeformerParams&) {
    unavailable("GLDeformer");
}

GLDeformer::GLDeformer(InputArray, const Multicage&, int, const GLDeformerParams&) {
    unavailable("GLDeformer");
}

GLDeformer::~GLDeformer() = default;

void GLDeformer::setPose(InputArray) {
    unavailable("GLDeformer");
}
void GLDeformer::setImage(InputArray) {
    unavailable("GLDeformer");
}
void GLDeformer::draw(bool) {
    unavailable("GLDeformer");
}
unsigned GLDeformer::render(const Scalar&) {
    unavailable("GLDeformer");
}
unsigned GLDeformer::renderMaps() {
    unavailable("GLDeformer");
}
void GLDeformer::readOutput(OutputArray) {
    unavailable("GLDeformer");
}
void GLDeformer::readMaps(OutputArray, OutputArray) {
    unavailable("GLDeformer");
}
void GLDeformer::readMesh(OutputArray) {
    unavailable("GLDeformer");
}
Size GLDeformer::outputSize() const {
    unavailable("GLDeformer");
}
unsigned GLDeformer::outputTexture() const {
    unavailable("GLDeformer");
}
unsigned GLDeformer::mapsTexture() const {
    unavailable("GLDeformer");
}
unsigned GLDeformer::coefficientTexture() const {
    unavailable("GLDeformer");
}
const PackLayout& GLDeformer::layout() const {
    unavailable("GLDeformer");
}
size_t GLDeformer::coefficientBytes() const {
    unavailable("GLDeformer");
}
const Binding& GLDeformer::binding() {
    unavailable("GLDeformer");
}
const GLDeformer::Timings& GLDeformer::timings() const {
    unavailable("GLDeformer");
}
void GLDeformer::finish() {
    unavailable("GLDeformer");
}
void GLDeformer::setProfiling(bool) {
    unavailable("GLDeformer");
}
GLDeformer::StageTimes GLDeformer::stageTimes() const {
    unavailable("GLDeformer");
}
int GLDeformer::pipeline() const {
    unavailable("GLDeformer");
}

// --- What runs on the shared context ------------------------------------------------------

Binding bindOnGpu(const Multicage&, int) {
    unavailable("bindOnGpu");
}

bool gpuAvailable(std::string* description) {
    return HeadlessGLContext::shared(description) != nullptr;
}

}  // namespace multicage
}  // namespace cv

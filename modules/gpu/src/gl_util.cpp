#include "gl_util.hpp"

#include <vector>

namespace cv {
namespace multicage {
namespace gpu {

static const char* glErrorName(GLenum e) {
    switch (e) {
        case GL_INVALID_ENUM:
            return "GL_INVALID_ENUM";
        case GL_INVALID_VALUE:
            return "GL_INVALID_VALUE";
        case GL_INVALID_OPERATION:
            return "GL_INVALID_OPERATION";
        case GL_INVALID_FRAMEBUFFER_OPERATION:
            return "GL_INVALID_FRAMEBUFFER_OPERATION";
        case GL_OUT_OF_MEMORY:
            return "GL_OUT_OF_MEMORY";
        default:
            return "unknown GL error";
    }
}

void checkGl(const char* where) {
    std::string errors;
    for (GLenum e; (e = glGetError()) != GL_NO_ERROR && errors.size() < 200;)
        errors +=
            std::string(errors.empty() ? "" : ", ") + glErrorName(e) + cv::format(" (0x%x)", e);
    if (!errors.empty())
        CV_Error(Error::GpuApiCallError,
                 std::string("multicage: OpenGL error in ") + where + ": " + errors);
}

static std::string_view embeddedShader(std::string_view name) {
    const std::string_view text = embedded::shaders(name);
    if (text.empty())
        CV_Error(Error::StsObjectNotFound,
                 "multicage: shader " + std::string(name) + " is not embedded in this build");
    return text;
}

// Replaces each `#include "file"` line by that file (GLSL has no includes of its own). The
// #line directives give each included file its own source-string number, so the compiler's
// messages name the right line: string 0 is the shader itself, 1, 2, ... its includes in order.
static std::string expandIncludes(std::string_view source, int* nextString) {
    std::string out;
    int line = 1;
    for (size_t at = 0; at < source.size(); ++line) {
        size_t eol = source.find('\n', at);
        if (eol == std::string_view::npos) eol = source.size();
        const std::string_view text = source.substr(at, eol - at);
        at = eol + 1;
        if (text.rfind("#include \"", 0) == 0) {
            const size_t close = text.find('"', 10);
            if (close == std::string_view::npos)
                CV_Error(Error::StsParseError,
                         "multicage: malformed shader include: " + std::string(text));
            const int number = (*nextString)++;
            out += "#line 1 " + std::to_string(number) + "\n";
            out += expandIncludes(embeddedShader(text.substr(10, close - 10)), nextString);
            out += "#line " + std::to_string(line + 1) + " 0\n";
        } else {
            out.append(text.data(), text.size()).push_back('\n');
        }
    }
    return out;
}

std::string shaderSource(std::string_view name) {
    int nextString = 1;
    return expandIncludes(embeddedShader(name), &nextString);
}

static std::string withDefines(const std::string& defines, std::string_view source) {
    // The #version line must stay first: the constants go right after it.
    const size_t eol = source.find('\n');
    if (source.substr(0, 8) != "#version" || eol == std::string_view::npos)
        CV_Error(Error::StsBadArg, "multicage: shader source must start with a #version line");
    return std::string(source.substr(0, eol + 1)) + defines + "#line 2\n" +
           std::string(source.substr(eol + 1));
}

static GLuint compile(GLenum stage, const std::string& source, const char* what) {
    GLuint s = glCreateShader(stage);
    const char* text = source.c_str();
    glShaderSource(s, 1, &text, nullptr);
    glCompileShader(s);
    GLint ok = 0, len = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        glGetShaderiv(s, GL_INFO_LOG_LENGTH, &len);
        std::vector<char> log(std::max(len, 1) + 1, '\0');
        glGetShaderInfoLog(s, len, nullptr, log.data());
        glDeleteShader(s);
        CV_Error(Error::GpuApiCallError,
                 std::string("multicage: cannot compile ") + what + ":\n" + log.data());
    }
    return s;
}

static GLuint link(std::initializer_list<GLuint> shaders, const char* what) {
    GLuint p = glCreateProgram();
    for (GLuint s : shaders) glAttachShader(p, s);
    glLinkProgram(p);
    for (GLuint s : shaders) glDeleteShader(s);
    GLint ok = 0, len = 0;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    if (!ok) {
        glGetProgramiv(p, GL_INFO_LOG_LENGTH, &len);
        std::vector<char> log(std::max(len, 1) + 1, '\0');
        glGetProgramInfoLog(p, len, nullptr, log.data());
        glDeleteProgram(p);
        CV_Error(Error::GpuApiCallError,
                 std::string("multicage: cannot link ") + what + ":\n" + log.data());
    }
    checkGl(what);
    return p;
}

static thread_local ProgramCache* currentCache = nullptr;

ProgramCache::~ProgramCache() = default;

ProgramCache* ProgramCache::current() {
    return currentCache;
}

ProgramCache* ProgramCache::makeCurrent(ProgramCache* cache) {
    ProgramCache* previous = currentCache;
    currentCache = cache;
    return previous;
}

bool ProgramCache::release(GLuint program) {
    auto it = entries_.begin();
    while (it != entries_.end() && it->second.program != program) ++it;
    if (it == entries_.end()) return false;
    --it->second.users;
    size_t unused = 0;
    for (const auto& e : entries_) unused += e.second.users == 0;
    if (unused > kKeepUnused && it->second.users == 0) {  // the one given back goes first
        glDeleteProgram(it->second.program);
        entries_.erase(it);
    }
    return true;
}

void deleteProgram(GLuint program) {
    if (!program) return;
    ProgramCache* cache = ProgramCache::current();
    if (!cache || !cache->release(program)) glDeleteProgram(program);
}

// Through the current cache, keyed by the complete sources.
template <typename Build>
static GLuint cachedProgram(const std::string& key, Build&& build) {
    ProgramCache* cache = ProgramCache::current();
    return cache ? cache->acquire(key, build) : build();
}

GLuint buildProgram(const std::string& defines, std::string_view vertex,
                    std::string_view fragment) {
    const std::string what = std::string(vertex) + " + " + std::string(fragment);
    const std::string vsText = withDefines(defines, shaderSource(vertex));
    const std::string fsText = withDefines(defines, shaderSource(fragment));
    return cachedProgram(vsText + '\0' + fsText, [&] {
        GLuint vs = compile(GL_VERTEX_SHADER, vsText, std::string(vertex).c_str());
        GLuint fs;
        try {
            fs = compile(GL_FRAGMENT_SHADER, fsText, std::string(fragment).c_str());
        } catch (...) {
            glDeleteShader(vs);
            throw;
        }
        return link({vs, fs}, what.c_str());
    });
}

GLuint buildComputeProgramFromText(const std::string& defines, const std::string& source,
                                   const char* name) {
    const std::string text = withDefines(defines, source);
    return cachedProgram(text,
                         [&] { return link({compile(GL_COMPUTE_SHADER, text, name)}, name); });
}

GLuint buildComputeProgram(const std::string& defines, std::string_view compute) {
    const std::string what(compute);
    return buildComputeProgramFromText(defines, shaderSource(compute), what.c_str());
}

int glVersion() {
    GLint major = 0, minor = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    return major * 10 + minor;
}

}  // namespace gpu
}  // namespace multicage
}  // namespace cv

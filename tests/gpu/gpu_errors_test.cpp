// GL errors and shader build logs surface as cv::Exception with the text that explains them.
#include "gl_util.hpp"
#include "gpu_testing.hpp"

using namespace cv;
using namespace cv::multicage;

static std::string messageOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const cv::Exception& e) {
        return e.what();
    }
    return "";
}

TEST(GpuErrors, ShaderCompileLogBecomesTheException) {
    MULTICAGE_REQUIRE_GPU();
    HeadlessGLContext context;
    HeadlessGLContext::Scope scope(context);
    const std::string what = messageOf([] {
        gpu::buildComputeProgramFromText("#define ANSWER 42\n",
                                         "#version 430 core\nlayout(local_size_x = 1) in;\n"
                                         "void main() { int x = undeclaredThing * ANSWER; }\n",
                                         "broken.comp");
    });
    EXPECT_NE(what.find("cannot compile broken.comp"), std::string::npos) << what;
    EXPECT_NE(what.find("undeclaredThing"), std::string::npos) << what;  // the compiler's log
}

TEST(GpuErrors, LinkLogBecomesTheException) {
    MULTICAGE_REQUIRE_GPU();
    HeadlessGLContext context;
    HeadlessGLContext::Scope scope(context);
    // A compute shader without a local size compiles but cannot link.
    const std::string what = messageOf([] {
        gpu::buildComputeProgramFromText("", "#version 430 core\nvoid main() {}\n", "nosize.comp");
    });
    EXPECT_NE(what.find("nosize.comp"), std::string::npos) << what;
    EXPECT_NE(what.find("link"), std::string::npos) << what;
}

TEST(GpuErrors, GlErrorNamesWhereAndWhat) {
    MULTICAGE_REQUIRE_GPU();
    HeadlessGLContext context;
    HeadlessGLContext::Scope scope(context);
    glBindTexture(GL_TEXTURE_2D, 0x7fffffff);  // a name never generated: an error in core GL
    const std::string what = messageOf([] { gpu::checkGl("binding a made-up texture"); });
    EXPECT_NE(what.find("binding a made-up texture"), std::string::npos) << what;
    EXPECT_NE(what.find("GL_INVALID_OPERATION"), std::string::npos) << what;
    EXPECT_EQ(messageOf([] { gpu::checkGl("nothing wrong"); }), "");
}

TEST(GpuErrors, MissingShaderIsNamed) {
    MULTICAGE_REQUIRE_GPU();
    const std::string what = messageOf([] { gpu::shaderSource("no_such.vert"); });
    EXPECT_NE(what.find("no_such.vert"), std::string::npos) << what;
}

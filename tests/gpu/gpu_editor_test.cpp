// The editor's path: GLDeformer::draw() into a framebuffer the caller owns and binds.
#include <epoxy/gl.h>

#include "gpu_testing.hpp"

using namespace cv;
using namespace cv::multicage;

TEST(GpuEditor, DrawIntoCallersFramebufferMatchesRender) {
    MULTICAGE_REQUIRE_GPU();
    const Mat image = multicage_testing::readSample("butterfly.jpg");
    const Multicage cage = multicage_testing::butterflyCage(true);
    const Binding b = bind(cage, MEAN_VALUE, 2);
    HeadlessGLContext context;
    HeadlessGLContext::Scope scope(context);
    GLDeformer gl(image, b);
    gl.setPose(multicage_fixtures::wavePose(cage, 10.f, 0.6f));
    gl.render();
    Mat expected;
    gl.readOutput(expected);

    // The caller's framebuffer: RGBA8 and twice the image size; the image goes into the
    // lower-left quarter, flipped as in a window (row 0 at the top).
    GLuint tex, fbo;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, 2 * image.cols, 2 * image.rows);
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex, 0);
    ASSERT_EQ(glCheckFramebufferStatus(GL_FRAMEBUFFER), GLenum(GL_FRAMEBUFFER_COMPLETE));
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT);
    glViewport(0, 0, image.cols, image.rows);
    gl.draw(true);
    Mat got(image.size(), CV_8UC3);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, image.cols, image.rows, GL_RGB, GL_UNSIGNED_BYTE, got.data);
    EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
    flip(got, got, 0);  // glReadPixels returns the bottom row first
    // Flipped, pixel centres exactly on a shared triangle edge may go to the other triangle
    // (GL's top-left rule is not symmetric): nearly equal, not bit-equal.
    Mat diff;
    absdiff(got, expected, diff);
    std::printf("draw() vs render(): PSNR %.1f dB, %d pixels differ by more than 2\n",
                multicage_testing::psnr(got, expected), countNonZero(diff.reshape(1) > 2));
    EXPECT_GE(multicage_testing::psnr(got, expected), 45.0);
    glDeleteFramebuffers(1, &fbo);
    glDeleteTextures(1, &tex);
}

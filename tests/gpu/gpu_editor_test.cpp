// The editor's path: GLDeformer::draw() into a framebuffer the caller owns and binds.
#include "caller_framebuffer.hpp"
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
    multicage_testing::CallerFramebuffer window(image.size() * 2);
    ASSERT_TRUE(window.complete());
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT);
    glViewport(0, 0, image.cols, image.rows);
    gl.draw(true);
    Mat got = multicage_testing::CallerFramebuffer::readRgb(image.size());
    EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
    flip(got, got, 0);  // glReadPixels returns the bottom row first
    // Flipped, pixel centres exactly on a shared triangle edge may go to the other triangle
    // (GL's top-left rule is not symmetric): nearly equal, not bit-equal.
    Mat diff;
    absdiff(got, expected, diff);
    std::printf("draw() vs render(): PSNR %.1f dB, %d pixels differ by more than 2\n",
                multicage_testing::psnr(got, expected), countNonZero(diff.reshape(1) > 2));
    EXPECT_GE(multicage_testing::psnr(got, expected), 45.0);
}

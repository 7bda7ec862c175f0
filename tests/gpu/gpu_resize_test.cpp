// Resize poses on the GPU (issue 25, item 1): a pose whose frame lies on the frame of another
// size renders that size in GL, and agrees with the CPU backend pixel for pixel.
#include <opencv2/imgproc.hpp>
#include <opencv2/multicage/resize.hpp>

#include "caller_framebuffer.hpp"
#include "gpu_testing.hpp"

using namespace cv;
using namespace cv::multicage;
using namespace multicage_testing;

namespace {

// Wider (16:9 from 4:3), narrower, taller, a thumbnail, both sides larger.
std::vector<Size> targetsFor(Size s) {
    return {Size(cvRound(1.5 * s.width), s.height), Size(cvRound(0.7 * s.width), s.height),
            Size(s.width, cvRound(1.3 * s.height)),
            Size(cvRound(0.5 * s.width), cvRound(0.4 * s.height)),
            Size(cvRound(2.0 * s.width), cvRound(1.2 * s.height))};
}

struct Agreement {
    int uncoveredGpu = 0, coverageDiffers = 0;
    double mapsMaxDiff = 0, imageMaxDiff = 0, psnr = 0;
};

// GPU against CPU for one pose: maps over every pixel, and the images.
Agreement compare(Deformer& gpu, Deformer& cpu, const std::vector<Point2f>& pose, Size target) {
    Mat gx, gy, cx, cy, g, c;
    gpu.computeMaps(pose, gx, gy);
    cpu.computeMaps(pose, cx, cy);
    gpu.deform(pose, g);
    cpu.deform(pose, c);
    EXPECT_EQ(gx.size(), target);
    EXPECT_EQ(gy.size(), target);
    EXPECT_EQ(g.size(), target);
    EXPECT_EQ(c.size(), target);
    EXPECT_EQ(g.type(), c.type());
    Agreement a;
    if (gx.size() != cx.size() || g.size() != c.size()) return a;
    const Mat gc = gx > -1e3f, cc = cx > -1e3f;
    a.uncoveredGpu = countNonZero(~gc);
    a.coverageDiffers = countNonZero(gc != cc);
    // Over every pixel: an uncovered one (-1e4 on one side only) would show as a huge difference.
    a.mapsMaxDiff = std::max(maxAbsDiff(gx, cx), maxAbsDiff(gy, cy));
    a.imageMaxDiff = maxAbsDiff(g, c);
    a.psnr = psnr(g, c);
    return a;
}

Multicage fruitsCage() {
    return multicage_fixtures::lotusMulticage(readSample("fruits.jpg").size(), 40);
}

}  // namespace

// The compute pipeline mirrors the CPU rasteriser, so at another size too the maps must be the
// CPU's pixel for pixel, every pixel covered, and the images equal up to the bilinear
// arithmetic: float weights on the GPU, cv::remap's 1/32-pixel fixed-point ones on the CPU
// (measured: at most 5 levels of 255, 56-61 dB, as for poses that keep the frame).
TEST(GpuResize, ComputePipelineMatchesCpuAtOtherSizes) {
    MULTICAGE_REQUIRE_GPU();
    struct Scene {
        const char* file;
        Multicage cage;
    };
    for (const Scene& s :
         {Scene{"butterfly.jpg", butterflyCage(true)}, Scene{"fruits.jpg", fruitsCage()}}) {
        const Mat image = readSample(s.file);
        for (int step : {1, 4}) {
            Ptr<Deformer> gpu, cpu;
            gpuAndCpu(image, bind(s.cage, MEAN_VALUE, step), &gpu, &cpu);
            for (const Size& target : targetsFor(image.size())) {
                const std::vector<Point2f> pose = resizePose(s.cage, cpu->binding(), target);
                const Agreement a = compare(*gpu, *cpu, pose, target);
                std::printf(
                    "%s, grid step %d, %dx%d -> %dx%d: maps max diff %.2g px, coverage "
                    "differs at %d pixels, %d uncovered; image max diff %.0f, %.1f dB\n",
                    s.file, step, image.cols, image.rows, target.width, target.height,
                    a.mapsMaxDiff, a.coverageDiffers, a.uncoveredGpu, a.imageMaxDiff, a.psnr);
                EXPECT_EQ(a.uncoveredGpu, 0);
                EXPECT_EQ(a.coverageDiffers, 0);
                EXPECT_LE(a.mapsMaxDiff, 1e-3);
                EXPECT_LE(a.imageMaxDiff, 255.0 / 32);  // a 1/32 weight error across a full step
                EXPECT_GE(a.psnr, 50.0);
            }
        }
    }
}

// The paper's program (GPU_PIPELINE_VERTEX_SHADER) draws the new frame too: the GPU's own
// rasteriser (top-left rule) may give a pixel on a shared edge to the other triangle, so it
// agrees with the CPU closely, not bit for bit.
TEST(GpuResize, VertexShaderPipelineRendersOtherSizes) {
    MULTICAGE_REQUIRE_GPU();
    const Mat image = readSample("fruits.jpg");
    const Multicage cage = fruitsCage();
    const Binding b = bind(cage, MEAN_VALUE, 2);
    DeformParams params;
    params.backend = BACKEND_GPU;
    params.pipeline = GPU_PIPELINE_VERTEX_SHADER;
    params.borderValue = Scalar(255, 0, 255);
    Ptr<Deformer> vertex = Deformer::create(image, b, params);
    params.backend = BACKEND_CPU;
    Ptr<Deformer> cpu = Deformer::create(image, b, params);
    for (const Size& target : targetsFor(image.size())) {
        const std::vector<Point2f> pose = resizePose(cage, b, target);
        Mat v, c, mx, my;
        vertex->deform(pose, v);
        cpu->deform(pose, c);
        vertex->computeMaps(pose, mx, my);
        ASSERT_EQ(v.size(), target);
        ASSERT_EQ(mx.size(), target);
        const double p = psnr(v, c);
        std::printf(
            "fruits, vertex-shader pipeline, %dx%d: %.1f dB against the CPU, %d uncovered\n",
            target.width, target.height, p, countNonZero(mx < -1e3f));
        EXPECT_EQ(countNonZero(mx < -1e3f), 0);
        EXPECT_GE(p, 45.0);
    }
}

// Sizes in any order give the same pictures: a target of another size is remade, the pixel
// owners of a larger output leave nothing behind for a smaller one, and the image's own size
// renders as before, bit for bit.
TEST(GpuResize, SizesInAnyOrderGiveTheSamePictures) {
    MULTICAGE_REQUIRE_GPU();
    const GpuButterfly bf = gpuButterfly(2, Scalar(255, 0, 255));
    const Mat& image = bf.image;
    const Multicage& cage = bf.cage;
    const Ptr<Deformer>& d = bf.deformer;
    const std::vector<Point2f> wave = multicage_fixtures::wavePose(cage, 12.f, 0.5f);
    const Size big(2 * image.cols, cvRound(1.2 * image.rows)),
        small(cvRound(0.6 * image.cols), image.rows);
    const std::vector<Point2f> toBig = resizePose(cage, d->binding(), big),
                               toSmall = resizePose(cage, d->binding(), small);
    Mat first, firstMx, firstMy, smallFresh;
    d->deform(wave, first);
    d->computeMaps(wave, firstMx, firstMy);
    {
        Ptr<Deformer> fresh = Deformer::create(image, cage, bf.params);
        fresh->deform(toSmall, smallFresh);
    }
    Mat out, mx, my;
    d->deform(toBig, out);
    d->computeMaps(toBig, mx, my);
    ASSERT_EQ(out.size(), big);
    d->deform(toSmall, out);
    EXPECT_EQ(maxAbsDiff(out, smallFresh), 0.0) << "the larger output left owners behind";
    d->deform(wave, out);
    d->computeMaps(wave, mx, my);
    ASSERT_EQ(out.size(), image.size());
    EXPECT_EQ(maxAbsDiff(out, first), 0.0);
    EXPECT_EQ(maxAbsDiff(mx, firstMx), 0.0);
    EXPECT_EQ(maxAbsDiff(my, firstMy), 0.0);

    // A batch of mixed sizes: each item as deform() gives it.
    std::vector<Mat> batch;
    d->deformBatch(std::vector<std::vector<Point2f>>{toBig, wave, toSmall}, batch);
    ASSERT_EQ(batch.size(), 3u);
    Mat bigOut;
    d->deform(toBig, bigOut);
    EXPECT_EQ(maxAbsDiff(batch[0], bigOut), 0.0);
    EXPECT_EQ(maxAbsDiff(batch[1], first), 0.0);
    EXPECT_EQ(maxAbsDiff(batch[2], smallFresh), 0.0);
}

// In the caller's context: outputSize(), a texture of the new size, and draw() filling the
// viewport with the new frame.
TEST(GpuResize, GLDeformerRendersAndDrawsTheNewFrame) {
    MULTICAGE_REQUIRE_GPU();
    const Mat image = readSample("butterfly.jpg");
    const Multicage cage = butterflyCage(true);
    const Binding b = bind(cage, MEAN_VALUE, 2);
    HeadlessGLContext context;
    HeadlessGLContext::Scope scope(context);
    GLDeformer gl(image, b);
    EXPECT_EQ(gl.outputSize(), image.size());
    const Size target(cvRound(1.5 * image.cols), cvRound(0.8 * image.rows));
    gl.setPose(resizePose(cage, b, target));
    EXPECT_EQ(gl.outputSize(), target);
    const GLuint tex = gl.render();
    GLint w = 0, h = 0;
    glBindTexture(GL_TEXTURE_2D, tex);
    glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_WIDTH, &w);
    glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_HEIGHT, &h);
    EXPECT_EQ(Size(w, h), target);
    Mat rendered;
    gl.readOutput(rendered);
    ASSERT_EQ(rendered.size(), target);

    CallerFramebuffer window(target);
    ASSERT_TRUE(window.complete());
    glClearColor(1, 0, 1, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glViewport(0, 0, target.width, target.height);
    gl.draw(false);  // row 0 at the bottom: what readOutput() gives, unflipped
    const Mat drawn = CallerFramebuffer::readRgb(target);
    EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
    const double p = psnr(drawn, rendered);
    std::printf("draw() vs render() at %dx%d: %.1f dB\n", target.width, target.height, p);
    EXPECT_GE(p, 45.0);
}

// An output beyond what the GPU draws is refused with a clear error, and the Deformer keeps
// working.
TEST(GpuResize, AnOutputBeyondTheGpuLimitIsRefused) {
    MULTICAGE_REQUIRE_GPU();
    const GpuButterfly bf = gpuButterfly(4);
    const Ptr<Deformer>& d = bf.deformer;
    std::vector<Point2f> pose = d->binding().restVertices;
    // The frame's right side (corners TR and BR) at x = 100000 - 0.5: a 100000-pixel-wide
    // output, wider than any GL_MAX_TEXTURE_SIZE.
    pose[pose.size() - 3].x = pose[pose.size() - 2].x = 100000.f - 0.5f;
    Mat out;
    try {
        d->deform(pose, out);
        FAIL() << "no exception";
    } catch (const cv::Exception& e) {
        EXPECT_EQ(e.code, Error::StsOutOfRange);
        EXPECT_NE(e.err.find("100000x"), std::string::npos) << e.err;
    }
    d->deform(d->binding().restVertices, out);
    EXPECT_EQ(maxAbsDiff(out, bf.image), 0.0);
}

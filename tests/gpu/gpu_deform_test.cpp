// The GPU Deformer against the CPU reference: same poses, same pictures.
#include <opencv2/imgproc.hpp>
#include <thread>

#include "gpu_testing.hpp"

using namespace cv;
using namespace cv::multicage;
using namespace multicage_testing;

TEST(GpuContext, HeadlessContextDescribesItself) {
    MULTICAGE_REQUIRE_GPU();
    HeadlessGLContext context;
    std::printf("GPU: %s\n", context.description().c_str());
    EXPECT_NE(context.description().find("OpenGL 4."), std::string::npos);
}

TEST(GpuDeform, RestPoseReproducesInput) {
    MULTICAGE_REQUIRE_GPU();
    const Mat image = readSample("butterfly.jpg");
    const Multicage cage = butterflyCage(true);
    DeformParams params;
    params.backend = BACKEND_GPU;
    Ptr<Deformer> d = Deformer::create(image, cage, params);
    ASSERT_EQ(d->backend(), BACKEND_GPU);
    Mat out;
    std::vector<Point2f> rest = cage.vertices();
    rest.resize(cage.vertexCount());
    d->deform(rest, out);
    ASSERT_EQ(out.size(), image.size());
    ASSERT_EQ(out.type(), image.type());
    const double diff = maxAbsDiff(out, image);
    std::printf("rest pose, butterfly.jpg: max abs diff %.0f\n", diff);
    EXPECT_LE(diff, 1.0);
}

static void expectAgreement(const std::string& file, const Multicage& cage,
                            const std::vector<Point2f>& pose, int gridStep) {
    const Mat image = readSample(file);
    ASSERT_EQ(image.size(), cage.imageSize());
    const Binding b = bind(cage, MEAN_VALUE, gridStep);
    Ptr<Deformer> gpu, cpu;
    gpuAndCpu(image, b, &gpu, &cpu);
    Mat g, c;
    gpu->deform(pose, g);
    cpu->deform(pose, c);
    const double p = psnr(g, c), moved = psnr(c, image);
    std::printf("%s, grid step %d: GPU vs CPU PSNR %.1f dB (deformed vs input %.1f dB)\n",
                file.c_str(), gridStep, p, moved);
    EXPECT_GE(p, 40.0);
    EXPECT_LT(moved, 30.0);  // the pose really deformed the image
}

TEST(GpuDeform, AgreesWithCpuOnButterfly) {
    MULTICAGE_REQUIRE_GPU();
    const Multicage cage = butterflyCage(true);
    // Wings stretched sideways, the body nested inside them.
    expectAgreement("butterfly.jpg", cage, multicage_fixtures::stretchPolygon(cage, 0, 1.12f, 0.9f),
                    1);
    expectAgreement("butterfly.jpg", cage, multicage_fixtures::wavePose(cage, 10.f, 0.3f), 2);
}

TEST(GpuDeform, AgreesWithCpuOnFruits) {
    MULTICAGE_REQUIRE_GPU();
    const Mat image = readSample("fruits.jpg");
    const Multicage cage = multicage_fixtures::lotusMulticage(image.size(), 40);
    expectAgreement("fruits.jpg", cage, multicage_fixtures::wavePose(cage, 14.f, 1.1f), 1);
}

// 500x333 with 400 user vertices: the paper's "hundreds of vertices" (101 blocks).
TEST(GpuDeform, HundredsOfVertices) {
    MULTICAGE_REQUIRE_GPU();
    Mat image;
    resize(readSample("fruits.jpg"), image, Size(500, 333), 0, 0, INTER_AREA);
    const Multicage cage = multicage_fixtures::lotusMulticage(image.size(), 400);
    ASSERT_EQ(cage.vertexCount(), 400);
    const Binding b = bind(cage, MEAN_VALUE, 1);
    Ptr<Deformer> gpu, cpu;
    gpuAndCpu(image, b, &gpu, &cpu);
    const std::vector<Point2f> pose = multicage_fixtures::wavePose(cage, 8.f, 0.7f);
    Mat g, c;
    gpu->deform(pose, g);
    cpu->deform(pose, c);
    const double p = psnr(g, c);
    std::printf("500x333, 400 vertices: GPU vs CPU PSNR %.1f dB\n", p);
    EXPECT_GE(p, 40.0);
    EXPECT_LT(psnr(c, image), 35.0);
}

TEST(GpuDeform, AllDepthsAndChannelCounts) {
    MULTICAGE_REQUIRE_GPU();
    Mat base;
    resize(readSample("butterfly.jpg"), base, Size(160, 120), 0, 0, INTER_AREA);
    const Multicage cage = multicage_fixtures::lotusMulticage(base.size(), 16);
    const Binding b = bind(cage, MEAN_VALUE, 1);
    const std::vector<Point2f> pose = multicage_fixtures::wavePose(cage, 4.f, 0.2f);
    std::vector<Point2f> rest = cage.vertices();
    rest.resize(cage.vertexCount());
    for (int depth : {CV_8U, CV_16U, CV_32F})
        for (int cn : {1, 3, 4}) {
            SCOPED_TRACE(typeToString(CV_MAKETYPE(depth, cn)));
            Mat img = base;
            if (cn == 1) cvtColor(base, img, COLOR_BGR2GRAY);
            if (cn == 4) cvtColor(base, img, COLOR_BGR2BGRA);
            const double scale = depth == CV_8U ? 1.0 : depth == CV_16U ? 257.0 : 1.0 / 255;
            img.convertTo(img, depth, scale);
            if (cn == 4) {  // a non-trivial alpha channel
                std::vector<Mat> ch;
                split(img, ch);
                ch[3] = ch[0].clone();
                merge(ch, img);
            }
            Ptr<Deformer> gpu, cpu;
            gpuAndCpu(img, b, &gpu, &cpu);
            Mat g, c, r;
            gpu->deform(pose, g);
            cpu->deform(pose, c);
            ASSERT_EQ(g.type(), img.type());
            ASSERT_EQ(g.size(), img.size());
            EXPECT_GE(psnr(g, c), 40.0);
            gpu->deform(rest, r);
            // One 8-bit level, in each depth's units.
            EXPECT_LE(maxAbsDiff(r, img), depth == CV_8U    ? 1.0
                                          : depth == CV_16U ? 257.0
                                                            : 1.0 / 255);
        }
}

TEST(GpuDeform, UncoveredPixelsGetBorderValue) {
    MULTICAGE_REQUIRE_GPU();
    Mat image(120, 160, CV_8UC3, Scalar(10, 20, 30));
    const Multicage cage = multicage_fixtures::lotusMulticage(image.size(), 16);
    const Binding b = bind(cage, MEAN_VALUE, 1);
    DeformParams params;
    params.borderValue = Scalar(200, 100, 50);
    Ptr<Deformer> gpu, cpu;
    gpuAndCpu(image, b, &gpu, &cpu, params);
    // The frame shrunk by 10 px on every side: a 10 px band nothing covers.
    std::vector<Point2f> pose = b.restVertices;
    const Point2f centre(79.5f, 59.5f);
    for (size_t j = pose.size() - 4; j < pose.size(); ++j)
        pose[j] = centre + (pose[j] - centre) * 0.8f;
    Mat g, c;
    gpu->deform(pose, g);
    cpu->deform(pose, c);
    EXPECT_EQ(g.at<Vec3b>(0, 0), Vec3b(200, 100, 50));
    EXPECT_EQ(g.at<Vec3b>(119, 159), Vec3b(200, 100, 50));
    EXPECT_EQ(g.at<Vec3b>(60, 80), Vec3b(10, 20, 30));
    EXPECT_GE(psnr(g, c), 40.0);
}

TEST(GpuDeform, MapsAgreeWithCpu) {
    MULTICAGE_REQUIRE_GPU();
    const Mat image = readSample("butterfly.jpg");
    const Multicage cage = butterflyCage(true);
    const Binding b = bind(cage, MEAN_VALUE, 2);
    Ptr<Deformer> gpu, cpu;
    gpuAndCpu(image, b, &gpu, &cpu);
    const std::vector<Point2f> pose = multicage_fixtures::stretchPolygon(cage, 0, 1.1f, 0.95f);
    Mat gx, gy, cx, cy;
    gpu->computeMaps(pose, gx, gy);
    cpu->computeMaps(pose, cx, cy);
    ASSERT_EQ(gx.size(), image.size());
    ASSERT_EQ(gx.type(), CV_32F);
    // Covered by both (coverage may differ along triangle edges only where a pixel centre lies
    // exactly on one: GL's top-left rule versus the CPU's inclusive edges).
    const Mat both = (gx > -1e3f) & (cx > -1e3f);
    const Mat differ = (gx > -1e3f) != (cx > -1e3f);
    EXPECT_LE(countNonZero(differ), image.total() / 1000);
    Mat dx = abs(gx - cx), dy = abs(gy - cy);
    double mx, my;
    minMaxLoc(dx, nullptr, &mx, nullptr, nullptr, both);
    minMaxLoc(dy, nullptr, &my, nullptr, nullptr, both);
    std::printf("maps: GPU vs CPU max |dx| %.4f, |dy| %.4f px, coverage differs at %d pixels\n", mx,
                my, countNonZero(differ));
    EXPECT_LT(std::max(mx, my), 0.05);
}

// The editor's path: the caller's context, no Deformer; render() into the texture, then the
// same pixels through readOutput as through the Deformer.
TEST(GpuDeform, GLDeformerInCallersContext) {
    MULTICAGE_REQUIRE_GPU();
    const Mat image = readSample("butterfly.jpg");
    const Multicage cage = butterflyCage(true);
    const Binding b = bind(cage, MEAN_VALUE, 2);
    const std::vector<Point2f> pose = multicage_fixtures::wavePose(cage, 10.f, 0.1f);
    HeadlessGLContext context;
    HeadlessGLContext::Scope scope(context);
    GLDeformer gl(image, b);
    gl.setPose(pose);
    EXPECT_NE(gl.render(), 0u);
    Mat a;
    gl.readOutput(a);
    DeformParams params;
    params.backend = BACKEND_GPU;
    Mat viaDeformer;
    Deformer::create(image, b, params)->deform(pose, viaDeformer);  // its own context
    EXPECT_EQ(maxAbsDiff(a, viaDeformer), 0.0);
    // Our context is current again after the Deformer released its own.
    gl.setPose(pose);
    gl.render();
    Mat again;
    gl.readOutput(again);
    EXPECT_EQ(maxAbsDiff(again, a), 0.0);
}

TEST(GpuDeform, TwoThreadsWithTheirOwnDeformers) {
    MULTICAGE_REQUIRE_GPU();
    Mat image;
    resize(readSample("fruits.jpg"), image, Size(200, 150), 0, 0, INTER_AREA);
    const Multicage cage = multicage_fixtures::lotusMulticage(image.size(), 20);
    const Binding b = bind(cage, MEAN_VALUE, 1);
    const std::vector<Point2f> pose = multicage_fixtures::wavePose(cage, 6.f, 0.4f);
    DeformParams params;
    params.backend = BACKEND_GPU;
    Mat expected;
    Deformer::create(image, b, params)->deform(pose, expected);
    Mat results[2];
    std::thread threads[2];
    for (int t = 0; t < 2; ++t)
        threads[t] = std::thread([&, t] {
            Ptr<Deformer> d = Deformer::create(image, b, params);
            for (int i = 0; i < 5; ++i) d->deform(pose, results[t]);
        });
    for (std::thread& t : threads) t.join();
    for (const Mat& r : results) EXPECT_EQ(maxAbsDiff(r, expected), 0.0);
}

// No vertex limit: 4096x3072, 128 vertices (132 coefficients, 33 blocks); with the texture
// limit forced to 2048 the paper's layout does not fit and the texture array takes over.
TEST(GpuDeform, NoVertexLimitFallbackLayout) {
    MULTICAGE_REQUIRE_GPU();
    Mat image;
    resize(readSample("fruits.jpg"), image, Size(4096, 3072), 0, 0, INTER_CUBIC);
    const Multicage cage = multicage_fixtures::lotusMulticage(image.size(), 128);
    const Binding b = bind(cage, MEAN_VALUE, 8);  // 513x385 nodes, 104 MB of coefficients
    const std::vector<Point2f> pose = multicage_fixtures::wavePose(cage, 40.f, 0.9f);
    HeadlessGLContext context;
    HeadlessGLContext::Scope scope(context);
    GLDeformerParams forced;
    forced.maxTextureSize = 2048;
    GLDeformer layered(image, b, forced);
    ASSERT_GT(layered.layout().layers, 1);
    EXPECT_EQ(layered.layout().layers, 33);
    GLDeformer paper(image, b);
    ASSERT_EQ(paper.layout().layers, 1);
    Mat a, p, c;
    layered.setPose(pose);
    layered.render();
    layered.readOutput(a);
    paper.setPose(pose);
    paper.render();
    paper.readOutput(p);
    EXPECT_EQ(maxAbsDiff(a, p), 0.0);  // the same coefficients, only stored elsewhere
    DeformParams cpu;
    cpu.backend = BACKEND_CPU;
    Deformer::create(image, b, cpu)->deform(pose, c);
    const double q = psnr(a, c);
    std::printf("4096x3072, 128 vertices, %d layers: GPU vs CPU PSNR %.1f dB\n",
                layered.layout().layers, q);
    EXPECT_GE(q, 40.0);
}

TEST(GpuDeform, HalfFloatCoefficients) {
    MULTICAGE_REQUIRE_GPU();
    const Mat image = readSample("butterfly.jpg");
    const Multicage cage = butterflyCage(true);
    const Binding b = bind(cage, MEAN_VALUE, 1);
    DeformParams half;
    half.halfFloat = true;
    Ptr<Deformer> gpu16, cpu;
    gpuAndCpu(image, b, &gpu16, &cpu, half);
    DeformParams full;
    full.backend = BACKEND_GPU;
    Ptr<Deformer> gpu32 = Deformer::create(image, b, full);
    // No fold-over: where the mesh folds, rounding decides which layer wins and the maps jump.
    const std::vector<Point2f> pose = multicage_fixtures::wavePose(cage, 8.f, 0.3f);
    ASSERT_EQ(gpu32->foldedTriangles(pose), 0);
    Mat x16, y16, x32, y32;
    gpu16->computeMaps(pose, x16, y16);
    gpu32->computeMaps(pose, x32, y32);
    const Mat both = (x16 > -1e3f) & (x32 > -1e3f);
    double ex, ey;
    minMaxLoc(abs(x16 - x32), nullptr, &ex, nullptr, nullptr, both);
    minMaxLoc(abs(y16 - y32), nullptr, &ey, nullptr, nullptr, both);
    std::printf("half-float vs float32 maps on the GPU, butterfly: max %.4f px\n",
                std::max(ex, ey));
    EXPECT_LT(std::max(ex, ey), 0.05);
    EXPECT_GT(std::max(ex, ey), 0.0);  // the half-float texture really is in use
    Mat g, c, r;
    gpu16->deform(pose, g);
    cpu->deform(pose, c);
    EXPECT_GE(psnr(g, c), 40.0);
    std::vector<Point2f> rest = cage.vertices();
    rest.resize(cage.vertexCount());
    gpu16->deform(rest, r);
    EXPECT_LE(maxAbsDiff(r, image), 1.0);  // displacement form: the rest pose stays exact
}

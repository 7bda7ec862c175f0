// The compute pipeline (GPU_PIPELINE_COMPUTE, the default) against the CPU backend: it
// mirrors the CPU rasteriser's arithmetic, so the maps must be the CPU's pixel for pixel.
#include <opencv2/imgproc.hpp>

#include "gl_util.hpp"  // ProgramCache (the gpu module's private header)
#include "gpu_testing.hpp"

using namespace cv;
using namespace cv::multicage;
using namespace multicage_testing;

namespace {

struct Scene {
    std::string file;
    Multicage cage;
    float foldingAmplitude;  // a wavePose amplitude that folds the mesh over at grid step 4
};

Scene butterfly() {
    return {"butterfly.jpg", butterflyCage(true), 30.f};
}
Scene fruits() {
    return {"fruits.jpg", multicage_fixtures::lotusMulticage(readSample("fruits.jpg").size(), 40),
            60.f};
}

struct MapsComparison {
    int coverageDiffers = 0, covered = 0;
    double maxDiff = 0;
};

MapsComparison compareMaps(Deformer& gpu, Deformer& cpu, const std::vector<Point2f>& pose) {
    Mat gx, gy, cx, cy;
    gpu.computeMaps(pose, gx, gy);
    cpu.computeMaps(pose, cx, cy);
    MapsComparison r;
    const Mat gc = gx > -1e3f, cc = cx > -1e3f, both = gc & cc;
    r.coverageDiffers = countNonZero(gc != cc);
    r.covered = countNonZero(both);
    double dx = 0, dy = 0;
    minMaxLoc(abs(gx - cx), nullptr, &dx, nullptr, nullptr, both);
    minMaxLoc(abs(gy - cy), nullptr, &dy, nullptr, nullptr, both);
    r.maxDiff = std::max(dx, dy);
    return r;
}

std::vector<Point2f> restPose(const Multicage& cage) {
    std::vector<Point2f> rest = cage.vertices();
    rest.resize(cage.vertexCount());
    return rest;
}

}  // namespace

// Same pixels covered, same triangle winning, same inverse map: at grid steps 1, 2 and 4, for
// a gentle pose and for one that folds the mesh over (where the later triangle must win).
TEST(GpuCompute, MapsEqualCpuIncludingFoldOvers) {
    MULTICAGE_REQUIRE_GPU();
    for (const Scene& s : {butterfly(), fruits()}) {
        const Mat image = readSample(s.file);
        for (int step : {1, 2, 4}) {
            const Binding b = bind(s.cage, MEAN_VALUE, step);
            Ptr<Deformer> gpu, cpu;
            gpuAndCpu(image, b, &gpu, &cpu);
            ASSERT_EQ(gpu->backend(), BACKEND_GPU);
            const std::vector<Point2f> gentle = multicage_fixtures::wavePose(s.cage, 6.f, 0.3f);
            const std::vector<Point2f> folding =
                multicage_fixtures::wavePose(s.cage, s.foldingAmplitude, 0.3f);
            ASSERT_GT(cpu->foldedTriangles(folding), 0) << "the pose must fold the mesh over";
            for (const auto& pose : {gentle, folding}) {
                const MapsComparison m = compareMaps(*gpu, *cpu, pose);
                std::printf(
                    "%s, grid step %d, %d folded triangles: maps max diff %.2g px, "
                    "coverage differs at %d of %d pixels\n",
                    s.file.c_str(), step, cpu->foldedTriangles(pose), m.maxDiff, m.coverageDiffers,
                    m.covered);
                EXPECT_EQ(m.coverageDiffers, 0);
                EXPECT_LE(m.maxDiff, 1e-3);
                EXPECT_EQ(m.covered, int(image.total()));  // the fixed frame keeps all covered
            }
        }
    }
}

TEST(GpuCompute, ImageAgreesWithCpuAtGridSteps124) {
    MULTICAGE_REQUIRE_GPU();
    for (const Scene& s : {butterfly(), fruits()}) {
        const Mat image = readSample(s.file);
        for (int step : {1, 2, 4}) {
            Ptr<Deformer> gpu, cpu;
            gpuAndCpu(image, bind(s.cage, MEAN_VALUE, step), &gpu, &cpu);
            const std::vector<Point2f> pose = multicage_fixtures::wavePose(s.cage, 12.f, 0.7f);
            Mat g, c;
            gpu->deform(pose, g);
            cpu->deform(pose, c);
            const double p = psnr(g, c);
            std::printf("%s, grid step %d: compute pipeline vs CPU %.1f dB (vs input %.1f dB)\n",
                        s.file.c_str(), step, p, psnr(c, image));
            EXPECT_GE(p, 45.0);
            EXPECT_LT(psnr(c, image), 35.0);  // the pose really moved the image
        }
    }
}

// The displacement form of the inverse map makes the rest pose the identity, bit for bit.
TEST(GpuCompute, RestPoseIsExactForEveryDepthAndChannelCount) {
    MULTICAGE_REQUIRE_GPU();
    Mat base;
    resize(readSample("butterfly.jpg"), base, Size(161, 119), 0, 0, INTER_AREA);
    const Multicage cage = multicage_fixtures::lotusMulticage(base.size(), 16);
    for (int step : {1, 3}) {
        const Binding b = bind(cage, MEAN_VALUE, step);
        for (int depth : {CV_8U, CV_16U, CV_32F})
            for (int cn : {1, 3, 4}) {
                SCOPED_TRACE(typeToString(CV_MAKETYPE(depth, cn)) + cv::format(", step %d", step));
                Mat img = base;
                if (cn == 1) cvtColor(base, img, COLOR_BGR2GRAY);
                if (cn == 4) cvtColor(base, img, COLOR_BGR2BGRA);
                img.convertTo(img, depth,
                              depth == CV_16U   ? 257.3
                              : depth == CV_32F ? 1 / 255.0
                                                : 1);
                DeformParams params;
                params.backend = BACKEND_GPU;
                Mat out;
                Deformer::create(img, b, params)->deform(restPose(cage), out);
                ASSERT_EQ(out.type(), img.type());
                EXPECT_EQ(maxAbsDiff(out, img), 0.0);
            }
    }
}

// The gather resets each pixel's owner for the next pose: poses in any order give the same
// pictures, and deform and computeMaps can alternate.
TEST(GpuCompute, EveryPoseStartsClean) {
    MULTICAGE_REQUIRE_GPU();
    const GpuButterfly bf = gpuButterfly(2);
    const Multicage& cage = bf.cage;
    const Ptr<Deformer>& d = bf.deformer;
    const std::vector<Point2f> a = multicage_fixtures::wavePose(cage, 30.f, 0.3f);
    // A shrunk frame: pixels a covers, b leaves uncovered.
    std::vector<Point2f> b = d->binding().restVertices;
    const Point2f centre(246.f, 177.5f);
    for (Point2f& p : b) p = centre + (p - centre) * 0.7f;
    Mat first, bOut, again, mx, my, mx2, my2;
    d->deform(a, first);
    d->computeMaps(a, mx, my);
    d->deform(b, bOut);
    d->computeMaps(b, mx2, my2);
    EXPECT_GT(countNonZero(mx2 < -1e3f), 10000);  // b really leaves pixels uncovered
    d->deform(a, again);
    EXPECT_EQ(maxAbsDiff(first, again), 0.0);
    d->computeMaps(a, mx2, my2);
    EXPECT_EQ(maxAbsDiff(mx, mx2), 0.0);
    EXPECT_EQ(maxAbsDiff(my, my2), 0.0);
}

// The paper's program stays selectable and draws the same picture.
TEST(GpuCompute, VertexShaderPipelineDrawsTheSamePicture) {
    MULTICAGE_REQUIRE_GPU();
    const Mat image = readSample("fruits.jpg");
    const Multicage cage = fruits().cage;
    const Binding b = bind(cage, MEAN_VALUE, 2);
    DeformParams params;
    params.backend = BACKEND_GPU;
    Ptr<Deformer> compute = Deformer::create(image, b, params);
    params.pipeline = GPU_PIPELINE_VERTEX_SHADER;
    Ptr<Deformer> vertex = Deformer::create(image, b, params);
    const std::vector<Point2f> pose = multicage_fixtures::wavePose(cage, 12.f, 0.7f);
    Mat c, v;
    compute->deform(pose, c);
    vertex->deform(pose, v);
    const double p = psnr(c, v);
    std::printf("fruits, grid step 2: compute vs vertex-shader pipeline %.1f dB\n", p);
    EXPECT_GE(p, 45.0);
    EXPECT_GT(maxAbsDiff(c, v), 0.0);  // two different programs really ran
}

// Both layouts (the paper's texture and the texture array) and half floats feed the compute
// pipeline's positions pass.
TEST(GpuCompute, TextureArrayAndHalfFloatLayouts) {
    MULTICAGE_REQUIRE_GPU();
    Mat image;
    resize(readSample("fruits.jpg"), image, Size(640, 480), 0, 0, INTER_AREA);
    const Multicage cage = multicage_fixtures::lotusMulticage(image.size(), 68);
    const Binding b = bind(cage, MEAN_VALUE, 1);
    const std::vector<Point2f> pose = multicage_fixtures::wavePose(cage, 10.f, 0.4f);
    HeadlessGLContext context;
    HeadlessGLContext::Scope scope(context);
    GLDeformerParams layeredParams;
    layeredParams.maxTextureSize = 1024;
    GLDeformer paper(image, b), layered(image, b, layeredParams);
    GLDeformerParams halfParams;
    halfParams.halfFloat = true;
    GLDeformer half(image, b, halfParams);
    ASSERT_EQ(paper.layout().layers, 1);
    ASSERT_GT(layered.layout().layers, 1);
    Mat outs[3];
    GLDeformer* all[3] = {&paper, &layered, &half};
    for (int i = 0; i < 3; ++i) {
        all[i]->setPose(pose);
        all[i]->render();
        all[i]->readOutput(outs[i]);
    }
    EXPECT_EQ(maxAbsDiff(outs[0], outs[1]), 0.0);
    DeformParams cpuParams;
    cpuParams.backend = BACKEND_CPU;
    Mat cpu;
    Deformer::create(image, b, cpuParams)->deform(pose, cpu);
    std::printf("640x480/68: texture array vs CPU %.1f dB, half float vs CPU %.1f dB\n",
                psnr(outs[1], cpu), psnr(outs[2], cpu));
    EXPECT_GE(psnr(outs[1], cpu), 45.0);
    EXPECT_GE(psnr(outs[2], cpu), 45.0);
    EXPECT_GT(maxAbsDiff(outs[2], outs[0]), 0.0);  // half floats really in use
}

// Deformers of the same layout share their compiled programs; another layout compiles anew.
TEST(GpuCompute, ProgramsAreCompiledOncePerLayout) {
    MULTICAGE_REQUIRE_GPU();
    Mat image;
    resize(readSample("butterfly.jpg"), image, Size(200, 150), 0, 0, INTER_AREA);
    const Multicage cage = multicage_fixtures::lotusMulticage(image.size(), 16);
    const Binding b = bind(cage, MEAN_VALUE, 1);
    HeadlessGLContext context;
    HeadlessGLContext::Scope scope(context);
    const gpu::ProgramCache* cache = gpu::ProgramCache::current();
    ASSERT_NE(cache, nullptr);
    GLDeformer first(image, b);
    const size_t programs = cache->size();
    EXPECT_EQ(programs, 4u);  // positions, raster, and two gathers
    {
        GLDeformer second(image, b);
        EXPECT_EQ(cache->size(), programs);  // nothing compiled (no timing: Mesa's disk cache
                                             // can make a first compile fast too)
    }
    GLDeformer other(image, bind(cage, MEAN_VALUE, 2));
    EXPECT_EQ(cache->size(), 2 * programs);
    // A program given back by one Deformer still serves the others.
    first.setPose(multicage_fixtures::wavePose(cage, 4.f, 0.2f));
    first.render();
    Mat out;
    first.readOutput(out);
    EXPECT_LT(psnr(out, image), 40.0);
}

TEST(GpuCompute, StageTimesFromTimerQueries) {
    MULTICAGE_REQUIRE_GPU();
    const Mat image = readSample("butterfly.jpg");
    const Binding b = bind(butterflyCage(true), MEAN_VALUE, 2);
    HeadlessGLContext context;
    HeadlessGLContext::Scope scope(context);
    for (int pipeline : {GPU_PIPELINE_COMPUTE, GPU_PIPELINE_VERTEX_SHADER}) {
        GLDeformerParams params;
        params.pipeline = pipeline;
        GLDeformer d(image, b, params);
        EXPECT_EQ(d.pipeline(), pipeline);
        d.setProfiling(true);
        d.render();
        Mat out;
        d.readOutput(out);
        const GLDeformer::StageTimes t = d.stageTimes();
        std::printf("%s: positions %.3f, raster %.3f, gather %.3f, readback %.3f ms\n",
                    pipeline == GPU_PIPELINE_COMPUTE ? "compute" : "vertex shader", t.positions,
                    t.raster, t.gather, t.readback);
        EXPECT_GE(t.raster, 0.0);
        EXPECT_GE(t.readback, 0.0);
        if (pipeline == GPU_PIPELINE_COMPUTE) {
            EXPECT_GE(t.positions, 0.0);
            EXPECT_GE(t.gather, 0.0);
        } else {
            EXPECT_EQ(t.positions, -1.0);  // one draw call does it all
        }
    }
}

// The mesh the compute pipeline rasterises is the CPU backend's to the bit: the nodes
// (Binding::apply, the coefficient sum) and the ring on the frame (mesh_raster.cpp's setFrame,
// restated here). When the maps differ, this says whether the positions or the raster differ.
TEST(GpuCompute, MeshEqualsTheCpuMesh) {
    MULTICAGE_REQUIRE_GPU();
    Mat image;
    resize(readSample("butterfly.jpg"), image, Size(161, 119), 0, 0, INTER_AREA);
    const Multicage cage = multicage_fixtures::lotusMulticage(image.size(), 16);
    HeadlessGLContext context;
    HeadlessGLContext::Scope scope(context);
    for (int step : {1, 3}) {
        const Binding b = bind(cage, MEAN_VALUE, step);
        GLDeformer gpu(image, b);
        DeformParams cpuParams;
        cpuParams.backend = BACKEND_CPU;
        const Ptr<Deformer> cpu = Deformer::create(image, b, cpuParams);
        for (const std::vector<Point2f>& pose :
             {restPose(cage), multicage_fixtures::wavePose(cage, 8.f, 0.3f)}) {
            gpu.setPose(pose);
            gpu.renderMaps();
            Mat mesh, nodes, gx, gy, cx, cy;
            gpu.readMesh(mesh);
            gpu.readMaps(gx, gy);
            cpu->computeMaps(pose, cx, cy);
            b.apply(pose, nodes);
            ASSERT_EQ(mesh.size(), b.gridSize + Size(2, 2));
            const float W = float(image.cols), H = float(image.rows);
            const std::vector<Point2f> complete = b.completePose(pose);
            const Point2f* c = &complete[complete.size() - 4];  // the frame corners
            int nodesDiffer = 0, ringDiffers = 0;
            for (int ey = 0; ey < mesh.rows; ++ey)
                for (int ex = 0; ex < mesh.cols; ++ex) {
                    const Point2f g = mesh.at<Point2f>(ey, ex);
                    const bool ring =
                        ex == 0 || ey == 0 || ex == mesh.cols - 1 || ey == mesh.rows - 1;
                    Point2f want;
                    if (!ring) {
                        want = nodes.at<Point2f>(ey - 1, ex - 1);
                    } else {
                        const Point2f source = b.node(std::clamp(ex - 1, 0, b.gridSize.width - 1),
                                                      std::clamp(ey - 1, 0, b.gridSize.height - 1));
                        const float rx = ex == 0               ? -0.5f
                                         : ex == mesh.cols - 1 ? W - 0.5f
                                                               : source.x;
                        const float ry = ey == 0               ? -0.5f
                                         : ey == mesh.rows - 1 ? H - 0.5f
                                                               : source.y;
                        const float u = (rx + 0.5f) / W, v = (ry + 0.5f) / H;
                        want = (1 - u) * (1 - v) * c[0] + u * (1 - v) * c[1] + u * v * c[2] +
                               (1 - u) * v * c[3];
                    }
                    if (g == want) continue;
                    if ((ring ? ringDiffers : nodesDiffer) < 3)
                        std::printf(
                            "  mesh vertex (%d, %d)%s: GPU (%.9g, %.9g), CPU (%.9g, %.9g)\n", ex,
                            ey, ring ? " on the ring" : "", g.x, g.y, want.x, want.y);
                    ++(ring ? ringDiffers : nodesDiffer);
                }
            int mapsDiffer = 0;
            for (int y = 0; y < gx.rows; ++y)
                for (int x = 0; x < gx.cols; ++x) {
                    const Point2f g(gx.at<float>(y, x), gy.at<float>(y, x));
                    const Point2f w(cx.at<float>(y, x), cy.at<float>(y, x));
                    // The CPU pulls fold-free meshes at small grid steps (mesh_pull.cpp), a float
                    // rounding apart from the raster the GPU mirrors: as in MapsEqualCpu.
                    if (std::abs(g.x - w.x) <= 1e-3f && std::abs(g.y - w.y) <= 1e-3f) continue;
                    if (mapsDiffer < 3)
                        std::printf("  pixel (%d, %d): GPU map (%.9g, %.9g), CPU (%.9g, %.9g)\n", x,
                                    y, g.x, g.y, w.x, w.y);
                    ++mapsDiffer;
                }
            const bool rest = pose == restPose(cage);
            // The rest pose's maps are the identity, up to the double rounding of a triangle's
            // set-up (1e-13 px at the narrow last column of cells; the image is then exact).
            int notIdentity = 0;
            for (int y = 0; rest && y < gx.rows; ++y)
                for (int x = 0; x < gx.cols; ++x) {
                    if (std::abs(gx.at<float>(y, x) - x) <= 1e-9f &&
                        std::abs(gy.at<float>(y, x) - y) <= 1e-9f)
                        continue;
                    if (notIdentity < 3)
                        std::printf("  rest pose, pixel (%d, %d): GPU map (%.9g, %.9g)\n", x, y,
                                    gx.at<float>(y, x), gy.at<float>(y, x));
                    ++notIdentity;
                }
            EXPECT_EQ(notIdentity, 0);
            std::printf(
                "grid step %d, %s pose: %d nodes and %d ring vertices differ from the CPU's, "
                "and %d pixels of the maps (by more than 1e-3 px)\n",
                step, rest ? "rest" : "wave", nodesDiffer, ringDiffers, mapsDiffer);
            EXPECT_EQ(nodesDiffer, 0);
            EXPECT_EQ(ringDiffers, 0);
            EXPECT_EQ(mapsDiffer, 0);
        }
    }
    // The paper's pipeline keeps no mesh to read: a clear error, not garbage.
    GLDeformerParams paperParams;
    paperParams.pipeline = GPU_PIPELINE_VERTEX_SHADER;
    GLDeformer paper(image, bind(cage, MEAN_VALUE, 3), paperParams);
    Mat none;
    EXPECT_THROW(paper.readMesh(none), cv::Exception);
}

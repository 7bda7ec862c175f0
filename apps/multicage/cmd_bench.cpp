// multicage bench: the paper's Table 1 cases timed with this library and with a peer
// (OpenCV's thin-plate spline warp on the same points), medians of repeated runs.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <functional>
#include <iostream>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/multicage/augment.hpp>
#include <opencv2/multicage/gpu.hpp>
#include <opencv2/shape/shape_transformer.hpp>

#include "cli_util.hpp"
#include "fixtures.hpp"

namespace multicage_cli {

namespace {

struct BenchCase {
    cv::Size size;
    int vertices;
    double paperBindSeconds;  // Table 1 of the paper; < 0 where we do not quote it
};

// The paper's Table 1 image sizes and user vertex counts. Of its figures only the 1024x768
// binding time (9.034 s) is quoted: the rest of Table 1 could not be retrieved.
const BenchCase kPaperCases[] = {{{1024, 768}, 68, 9.034}, {{800, 600}, 44, -1},
                                 {{500, 333}, 40, -1},     {{375, 500}, 35, -1},
                                 {{701, 525}, 29, -1},     {{1000, 701}, 41, -1}};

struct BenchOptions {
    int repeats = 7;
    int threads = 0;  // 0: OpenCV's default
    bool paperOnly = false, noPeer = false, noGpu = false, gpuOnly = false, half = false;
    bool augment = false;  // --augment: only the augmentation figures (printAugment)
    std::string image, json, size;
    int vertices = 68;
};

template <typename F>
double medianMs(int repeats, F&& f) {
    std::vector<double> ms;
    f();  // warm-up: first-touch page faults and lazy allocations are not what we measure
    for (int i = 0; i < repeats; ++i) {
        const auto t = std::chrono::steady_clock::now();
        f();
        ms.push_back(msSince(t));
    }
    return median(ms);
}

cv::Mat benchImage(const std::string& path, cv::Size size) {
    cv::Mat img;
    if (!path.empty()) img = readImage(path);
    if (img.empty()) {  // a smooth colourful pattern when no photograph is given
        img.create(512, 512, CV_8UC3);
        for (int y = 0; y < img.rows; ++y)
            for (int x = 0; x < img.cols; ++x)
                img.at<cv::Vec3b>(y, x) = cv::Vec3b(x / 2, y / 2, (x ^ y) & 255);
    }
    cv::resize(img, img, size, 0, 0, cv::INTER_AREA);
    return img;
}

// A table cell: the figure in fmt, or "-" for one not measured (< 0). Each row's cells stay
// valid until 24 more are made.
const char* cell(double v, const char* fmt) {
    static char buf[24][32];
    static int next = 0;
    char* b = buf[next++ % 24];
    if (v < 0)
        std::snprintf(b, 32, "-");
    else
        std::snprintf(b, 32, fmt, v);
    return b;
}

// One GPU pipeline's figures: GPU time of each stage (timer queries, medians), and the
// wall-clock time of Deformer::deform to a cv::Mat and of computeMaps.
struct PipelineFigures {
    double positions = -1, raster = -1, gather = -1, readback = -1, gpuTotal = -1;
    double deform = -1, maps = -1;
};

struct GpuFigures {
    double bind = -1, packUpload = -1, coefMB = -1;
    double createFirst = -1, createAgain = -1;  // Deformer::create, GPU binding, cold and warm
    double pose = -1, poseRead = -1;            // the default (compute) pipeline, for Table 1
    PipelineFigures pipelines[2];               // indexed by GpuPipeline
};

const char* pipelineName(int pipeline) {
    return pipeline == cv::multicage::GPU_PIPELINE_COMPUTE ? "compute" : "vertex shader";
}

// Stage times of `pipeline` in the bench's own context, and Deformer wall times (the
// process's shared context).
// With no CPU binding (--gpu-only) both bind on the GPU, so nothing is read back.
PipelineFigures pipelineFigures(const BenchOptions& o, const cv::Mat& image,
                                const cv::multicage::Multicage& cage,
                                const cv::multicage::Binding& binding,
                                const std::vector<cv::Point2f>& pose, int pipeline) {
    using namespace cv::multicage;
    PipelineFigures f;
    {
        GLDeformerParams params;
        params.pipeline = pipeline;
        params.halfFloat = o.half;
        std::unique_ptr<GLDeformer> bound(binding.empty() ? new GLDeformer(image, cage, 1, params)
                                                          : new GLDeformer(image, binding, params));
        GLDeformer& d = *bound;
        d.setProfiling(true);
        std::vector<double> positions, raster, gather, readback, total;
        cv::Mat out;
        for (int i = 0; i <= o.repeats; ++i) {
            d.setPose(pose);
            d.render();
            d.readOutput(out);
            const GLDeformer::StageTimes t = d.stageTimes();
            if (i == 0) continue;  // warm-up
            positions.push_back(t.positions), raster.push_back(t.raster);
            gather.push_back(t.gather), readback.push_back(t.readback);
            total.push_back(std::max(0.0, t.positions) + t.raster + std::max(0.0, t.gather));
        }
        f.positions = median(positions), f.raster = median(raster), f.gather = median(gather);
        f.readback = median(readback), f.gpuTotal = median(total);
    }
    DeformParams params;
    params.backend = BACKEND_GPU;
    params.pipeline = pipeline;
    params.halfFloat = o.half;
    params.gpuBinding = 1;
    params.memoryBudget = 0;  // grid step 1 whatever the size: the GPU holds it
    cv::Ptr<Deformer> d = binding.empty() ? Deformer::create(image, cage, params)
                                          : Deformer::create(image, binding, params);
    cv::Mat out, mapx, mapy;
    f.deform = medianMs(o.repeats, [&] { d->deform(pose, out); });
    f.maps = medianMs(o.repeats, [&] { d->computeMaps(pose, mapx, mapy); });
    return f;
}

// Keeps the GPU busy with poses for at least `seconds` before anything is timed: an idle GPU
// clocks down and takes a few hundred milliseconds of work to clock up again, which the first
// timed poses would pay (docs/gpu/README.md has the H200 figures). On llvmpipe this costs one pose.
void warmUpGpu(const cv::Mat& image, const cv::multicage::Multicage& cage,
               const std::vector<cv::Point2f>& pose, const cv::multicage::GLDeformerParams& params,
               double seconds) {
    const auto start = std::chrono::steady_clock::now();
    cv::multicage::GLDeformer d(image, cage, 1, params);
    cv::Mat out;
    do {
        d.setPose(pose);
        d.render();
        d.readOutput(out);  // waits for the GPU: the loop times work done, not work queued
    } while (msSince(start) < 1000.0 * seconds);
}

// The GPU figures of one case: binding in the compute shader, packing + upload of a CPU
// binding, building the programs, Deformer creation, and both pipelines.
GpuFigures gpuFigures(const BenchOptions& o, const cv::Mat& image,
                      const cv::multicage::Multicage& cage, const cv::multicage::Binding& binding,
                      const std::vector<cv::Point2f>& pose) {
    using namespace cv::multicage;
    GpuFigures f;
    std::vector<double> bindMs, uploadMs;
    GLDeformerParams glParams;
    glParams.halfFloat = o.half;
    warmUpGpu(image, cage, pose, glParams, 0.5);
    for (int i = 0; i < o.repeats; ++i) {
        GLDeformer bound(image, cage, 1, glParams);
        bindMs.push_back(bound.timings().binding);
    }
    std::unique_ptr<GLDeformer> d;
    for (int i = 0; i < o.repeats && !binding.empty(); ++i) {
        d.reset();
        d.reset(new GLDeformer(image, binding, glParams));
        uploadMs.push_back(d->timings().packUpload);
        if (i == 0) f.coefMB = d->coefficientBytes() / (1024.0 * 1024.0);
    }
    f.bind = median(bindMs), f.packUpload = uploadMs.empty() ? -1 : median(uploadMs);
    d.reset();

    // What a user pays: Deformer::create binding on the GPU. The first of a layout compiles
    // its programs (and the first of the process makes the EGL context); later ones reuse them.
    DeformParams params;
    params.backend = BACKEND_GPU;
    params.gpuBinding = 1;
    params.halfFloat = o.half;
    params.memoryBudget = 0;
    auto create = [&] {
        const auto t = std::chrono::steady_clock::now();
        cv::Ptr<Deformer> created = Deformer::create(image, cage, params);
        return msSince(t);
    };
    f.createFirst = create();
    std::vector<double> again;
    for (int i = 0; i < o.repeats; ++i) again.push_back(create());
    f.createAgain = median(again);

    for (int pipeline : {GPU_PIPELINE_COMPUTE, GPU_PIPELINE_VERTEX_SHADER})
        f.pipelines[pipeline] = pipelineFigures(o, image, cage, binding, pose, pipeline);
    f.pose = f.pipelines[GPU_PIPELINE_COMPUTE].gpuTotal;
    f.poseRead = f.pipelines[GPU_PIPELINE_COMPUTE].deform;
    return f;
}

// One case's figures for --json.
struct CaseRecord {
    cv::Size size;
    int vertices = 0;
    double cpuBind = -1, cpuPose = -1, cpuPose4 = -1, cpuMaps = -1, tps = -1;
    GpuFigures gpu;
};

void writeJson(const std::string& path, const std::string& device, const BenchOptions& o,
               const std::vector<CaseRecord>& cases) {
    cv::FileStorage fs(".json", cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
    fs << "device" << device << "threads" << cv::getNumThreads() << "repeats" << o.repeats
       << "half_float" << o.half << "opencv" << CV_VERSION;
    fs << "cases"
       << "[";
    for (const CaseRecord& c : cases) {
        fs << "{"
           << "width" << c.size.width << "height" << c.size.height << "vertices" << c.vertices;
        fs << "cpu"
           << "{"
           << "bind_ms" << c.cpuBind << "pose_ms" << c.cpuPose << "pose_step4_ms" << c.cpuPose4
           << "maps_ms" << c.cpuMaps << "tps_ms" << c.tps << "}";
        const GpuFigures& g = c.gpu;
        fs << "gpu"
           << "{"
           << "bind_ms" << g.bind << "pack_upload_ms" << g.packUpload << "create_first_ms"
           << g.createFirst << "create_again_ms" << g.createAgain << "coefficients_mib" << g.coefMB;
        for (int p :
             {cv::multicage::GPU_PIPELINE_COMPUTE, cv::multicage::GPU_PIPELINE_VERTEX_SHADER}) {
            const PipelineFigures& f = g.pipelines[p];
            fs << (p == cv::multicage::GPU_PIPELINE_COMPUTE ? "compute" : "vertex_shader") << "{"
               << "positions_ms" << f.positions << "raster_ms" << f.raster << "gather_ms"
               << f.gather << "readback_ms" << f.readback << "gpu_total_ms" << f.gpuTotal
               << "deform_ms" << f.deform << "compute_maps_ms" << f.maps << "}";
        }
        fs << "}"
           << "}";
    }
    fs << "]";
    cv::multicage::writeFileAtomic(path, fs.releaseAndGetString());
}

void printGpuTable(const std::vector<CaseRecord>& cases) {
    std::printf(
        "\nGPU pose update per pipeline: GPU time of each stage (timer queries) and wall "
        "time of Deformer calls, ms\n");
    std::printf("%-10s %4s %-13s | %9s %9s %9s %9s %9s | %9s %9s | %9s %9s\n", "image", "V",
                "pipeline", "positions", "raster", "gather", "GPU total", "readback", "deform",
                "maps", "create 1st", "create");
    for (const CaseRecord& c : cases) {
        for (int p :
             {cv::multicage::GPU_PIPELINE_COMPUTE, cv::multicage::GPU_PIPELINE_VERTEX_SHADER}) {
            const PipelineFigures& f = c.gpu.pipelines[p];
            char size[16];
            std::snprintf(size, sizeof size, "%dx%d", c.size.width, c.size.height);
            std::printf("%-10s %4d %-13s | %9s %9s %9s %9s %9s | %9s %9s |", size, c.vertices,
                        pipelineName(p), cell(f.positions, "%.3f"), cell(f.raster, "%.3f"),
                        cell(f.gather, "%.3f"), cell(f.gpuTotal, "%.3f"), cell(f.readback, "%.3f"),
                        cell(f.deform, "%.3f"), cell(f.maps, "%.3f"));
            if (p == cv::multicage::GPU_PIPELINE_COMPUTE)
                std::printf(" %10.1f %9.1f\n", c.gpu.createFirst, c.gpu.createAgain);
            else
                std::printf("\n");
        }
    }
    std::printf(
        "positions: the coefficient sum (compute pipeline); raster: the mesh into per-pixel "
        "triangle owners (compute) or the whole draw call (vertex shader: sum, raster and "
        "fragments); gather: inverse map + bilinear sampling; GPU total: the three; readback: "
        "glReadPixels into a cv::Mat. deform / maps: Deformer::deform to a cv::Mat and "
        "computeMaps, wall clock. create: Deformer::create with GPU binding, the first of its "
        "layout (compiles the programs) and again (programs cached). On a software renderer "
        "(llvmpipe) these are CPU times and say nothing of a GPU.\n");
}

cv::Size parseSize(const std::string& text) {
    int w = 0, h = 0;
    char x = 0, extra = 0;
    if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') ||
        w < 16 || h < 16 || w > 16384 || h > 16384)
        throw Failure("--size wants WIDTHxHEIGHT between 16 and 16384, e.g. 4096x3072; got '" +
                      text + "'");
    return {w, h};
}

// --- CPU backend figures (printed after the table) ---

// The first pose after Deformer::create, what the CLI and deformImage pay, next to a warm one:
// each of `repeats` fresh Deformers (made from one binding) is timed on its first deform.
void printCpuFirstCall(const BenchOptions& o, const cv::Mat& image,
                       const cv::multicage::Binding& binding,
                       const std::vector<cv::Point2f>& pose) {
    using namespace cv::multicage;
    DeformParams cpu;
    cpu.backend = BACKEND_CPU;
    std::vector<double> createMs, firstMs, oneShotMs;
    cv::Mat out;
    for (int i = 0; i < o.repeats; ++i) {
        cv::Mat fresh;  // a new output, as a first call has
        auto t = std::chrono::steady_clock::now();
        cv::Ptr<Deformer> d = Deformer::create(image, binding, cpu);
        createMs.push_back(msSince(t));
        t = std::chrono::steady_clock::now();
        d->deform(pose, fresh);
        firstMs.push_back(msSince(t));
    }
    cv::Ptr<Deformer> d = Deformer::create(image, binding, cpu);
    const double warm = medianMs(o.repeats, [&] { d->deform(pose, out); });
    std::printf(
        "CPU backend, %dx%d, %d vertices, grid step 1, %d threads: Deformer::create from a "
        "binding %.1f ms, first deform %.1f ms, warm deform %.1f ms\n",
        image.cols, image.rows, binding.coefficientCount() - 4, cv::getNumThreads(),
        median(createMs), median(firstMs), warm);
}

// Bind and pose times for 1, 2, 4, ... threads up to the current count, with the speed-up.
void printCpuScaling(const BenchOptions& o, const cv::Mat& image,
                     const cv::multicage::Multicage& cage, const std::vector<cv::Point2f>& pose) {
    using namespace cv::multicage;
    const int maxThreads = cv::getNumThreads();
    std::vector<int> counts;
    for (int t = 1; t < maxThreads; t *= 2) counts.push_back(t);
    counts.push_back(maxThreads);
    std::printf("CPU scaling, %dx%d, %d vertices (medians of %d runs):\n", image.cols, image.rows,
                cage.vertexCount(), o.repeats);
    std::printf("%8s %9s %9s %9s %9s %9s %9s\n", "threads", "bind ms", "pose ms", "s=4 ms",
                "bind x", "pose x", "s=4 x");
    double base[3] = {0, 0, 0};
    for (int t : counts) {
        cv::setNumThreads(t);
        DeformParams cpu;
        cpu.backend = BACKEND_CPU;
        Binding binding;
        const double bindMs = medianMs(o.repeats, [&] { binding = bind(cage, MEAN_VALUE, 1); });
        cv::Mat out;
        cv::Ptr<Deformer> d1 = Deformer::create(image, binding, cpu);
        const double poseMs = medianMs(o.repeats, [&] { d1->deform(pose, out); });
        d1.release();
        binding = Binding();
        cpu.gridStep = 4;
        cv::Ptr<Deformer> d4 = Deformer::create(image, cage, cpu);
        const double pose4Ms = medianMs(o.repeats, [&] { d4->deform(pose, out); });
        if (t == counts.front()) base[0] = bindMs, base[1] = poseMs, base[2] = pose4Ms;
        std::printf("%8d %9.1f %9.1f %9.2f %9.2f %9.2f %9.2f\n", t, bindMs, poseMs, pose4Ms,
                    base[0] / bindMs, base[1] / poseMs, base[2] / pose4Ms);
        std::fflush(stdout);
    }
    cv::setNumThreads(maxThreads);
}

// One case's inputs, kept for the CPU sections after the table (they use the first case).
struct CaseInputs {
    cv::Mat image;
    cv::multicage::Multicage cage;
    cv::multicage::Binding binding;  // grid step 1, mean value; empty with --gpu-only
    std::vector<cv::Point2f> pose;
};

// The cases to run: Table 1's, or the first of them, or one of --size.
std::vector<BenchCase> benchCases(const BenchOptions& o) {
    std::vector<BenchCase> cases(std::begin(kPaperCases), std::end(kPaperCases));
    if (!o.size.empty()) cases = {{parseSize(o.size), o.vertices, -1}};
    if (o.paperOnly) cases.resize(1);
    return cases;
}

// The bench's own GL context, or none (said, with why, in *device and on stdout).
std::unique_ptr<cv::multicage::HeadlessGLContext> openGpu(std::string* device) {
    std::unique_ptr<cv::multicage::HeadlessGLContext> gl;
    try {
        gl.reset(new cv::multicage::HeadlessGLContext());
        *device = gl->description();
        std::printf("GPU: %s\n", device->c_str());
    } catch (const cv::Exception& e) {
        *device = "none (" + e.err + ")";
        std::printf("GPU: %s; GPU columns show -\n", device->c_str());
    }
    return gl;
}

const char* const kTableRow =
    "%-10s %4s | %8s %8s %8s | %8s %8s | %8s %8s %8s | %8s %8s %8s | %8s %7s | %7s %7s\n";

void printTableHeader() {
    std::printf(kTableRow, "image", "V", "bind", "bind", "paper", "pack+up", "create", "pose",
                "deform", "pose", "pose", "maps", "TPS", "TPS", "TPS/gpu", "coef MB", "coef MB");
    std::printf(kTableRow, "", "", "CPU ms", "GPU ms", "bind ms", "GPU ms", "GPU ms", "GPU ms",
                "GPU ms", "CPU ms", "CPU s=4", "CPU ms", "warp ms", "/CPU", "deform", "CPU",
                "texture");
}

// The CPU figures of one case: binding at grid step 1 (kept in in.binding), pose and maps from
// it, and a pose at grid step 4.
void measureCpu(const BenchOptions& o, CaseInputs& in, CaseRecord& r) {
    using namespace cv::multicage;
    r.cpuBind = medianMs(o.repeats, [&] { in.binding = bind(in.cage, MEAN_VALUE, 1); });
    DeformParams cpu;
    cpu.backend = BACKEND_CPU;
    cv::Ptr<Deformer> d1 = Deformer::create(in.image, in.binding, cpu);
    cv::Mat out, mapx, mapy;
    r.cpuPose = medianMs(o.repeats, [&] { d1->deform(in.pose, out); });
    r.cpuMaps = medianMs(o.repeats, [&] { d1->computeMaps(in.pose, mapx, mapy); });
    cpu.gridStep = 4;
    cv::Ptr<Deformer> d4 = Deformer::create(in.image, in.cage, cpu);
    r.cpuPose4 = medianMs(o.repeats, [&] { d4->deform(in.pose, out); });
}

// The peer: one thin-plate spline through the same vertices (rest -> pose).
double measurePeer(const BenchOptions& o, const CaseInputs& in) {
    std::vector<cv::Point2f> rest = in.cage.vertices();
    rest.resize(in.cage.vertexCount());
    std::vector<cv::DMatch> matches;
    for (int i = 0; i < in.cage.vertexCount(); ++i) matches.emplace_back(i, i, 0.f);
    cv::Ptr<cv::ThinPlateSplineShapeTransformer> tps = cv::createThinPlateSplineShapeTransformer();
    cv::Mat tpsOut;
    // warpImage maps output to input, so the estimate goes from pose to rest.
    return medianMs(std::max(1, o.repeats / 2), [&] {
        tps->estimateTransformation(cv::Mat(in.pose).reshape(2, 1), cv::Mat(rest).reshape(2, 1),
                                    matches);
        tps->warpImage(in.image, tpsOut);
    });
}

// Every figure of one case; its inputs come back in `in`.
CaseRecord measureCase(const BenchOptions& o, const BenchCase& c,
                       cv::multicage::HeadlessGLContext* gl, CaseInputs& in) {
    using namespace cv::multicage;
    CaseRecord r;
    r.size = c.size, r.vertices = c.vertices;
    in.image = benchImage(o.image, c.size);
    in.cage = multicage_fixtures::lotusMulticage(c.size, c.vertices);
    in.pose = multicage_fixtures::wavePose(in.cage, 12.f, 0.5f);
    if (!o.gpuOnly) measureCpu(o, in, r);
    if (gl) {
        HeadlessGLContext::Scope scope(*gl);
        r.gpu = gpuFigures(o, in.image, in.cage, in.binding, in.pose);
    }
    if (!o.noPeer && !o.gpuOnly) r.tps = measurePeer(o, in);
    return r;
}

void printCaseRow(const BenchCase& c, const CaseRecord& r, const cv::multicage::Binding& binding) {
    const double coefMB =
        binding.empty() ? -1 : binding.coefficients.total() * sizeof(float) / (1024.0 * 1024.0);
    const GpuFigures& g = r.gpu;
    char size[16];
    std::snprintf(size, sizeof size, "%dx%d", c.size.width, c.size.height);
    std::printf(kTableRow, size, std::to_string(c.vertices).c_str(), cell(r.cpuBind, "%.1f"),
                cell(g.bind, "%.1f"), cell(c.paperBindSeconds * 1000, "%.0f"),
                cell(g.packUpload, "%.1f"), cell(g.createAgain, "%.1f"), cell(g.pose, "%.3f"),
                cell(g.poseRead, "%.3f"), cell(r.cpuPose, "%.1f"), cell(r.cpuPose4, "%.2f"),
                cell(r.cpuMaps, "%.1f"), cell(r.tps, "%.1f"),
                cell(r.tps > 0 && r.cpuPose > 0 ? r.tps / r.cpuPose : -1, "%.1f"),
                cell(r.tps > 0 && g.poseRead > 0 ? r.tps / g.poseRead : -1, "%.1f"),
                cell(coefMB, "%.1f"), cell(g.coefMB, "%.1f"));
    std::fflush(stdout);
}

void printTableNotes() {
    std::printf(
        "bind: Algorithm 1 over every pixel (grid step 1): CPU on all threads, GPU in the compute "
        "shader (float, double near vertices/edges); paper: Table 1's binding time (only the "
        "1024x768 figure is quoted). pack+up: Eq. 6-7 packing of a CPU binding straight into a "
        "mapped buffer and its upload; create: Deformer::create binding on the GPU, programs "
        "cached. pose: GPU time of one pose in the compute pipeline (timer queries); deform: "
        "Deformer::deform to a cv::Mat, wall clock; CPU pose: CPU backend to a cv::Mat (grid "
        "step 1 and 4); maps: CPU inverse maps only. TPS: cv::ThinPlateSplineShapeTransformer "
        "estimate + warpImage with the same points. coef MB: planar float32 coefficients on the "
        "CPU, and the packed texture (empty blocks included) on the GPU.\n");
}

// --- multicage bench --augment: random_pose + deform against the floor of the same run ---
//
// Speeds differ by machine and by load, so every figure is measured next to its floor in the
// same run, interleaved round by round (a burst of load hits both), and printed as a ratio:
// (1) one thread, 512x512: randomPose (as MulticageWarp draws it: the fold check on its own
// mesh) + deform against a plain cv::remap of the same image with the maps of a random pose, and
// the usual elastic recipe (Simard et al. 2003: a uniform random field per axis, Gaussian-smoothed,
// sigma 4, alpha 34, then cv::remap); (2) 2 threads, 1024x768, 68 vertices: the first deform after
// Deformer::create (grid step 1) and a warm grid-step-4 deform against reading every
// coefficient of the grid-step-1 binding once with the same threads, and a plain cv::remap of
// the image with the grid-step-4 maps beside them.

// Seconds of f() per item, medians over rounds; the callables are timed in turn each round.
std::vector<double> interleavedMs(int rounds, const std::vector<std::function<void()>>& fs) {
    std::vector<std::vector<double>> ms(fs.size());
    for (const auto& f : fs) f();  // warm-up
    for (int r = 0; r < rounds; ++r)
        for (size_t i = 0; i < fs.size(); ++i) {
            const auto t = std::chrono::steady_clock::now();
            fs[i]();
            ms[i].push_back(msSince(t));
        }
    std::vector<double> out;
    for (auto& m : ms) out.push_back(median(m));
    return out;
}

double loadAverage() {
    double load[1] = {-1};
    return getloadavg(load, 1) == 1 ? load[0] : -1;
}

// The elastic recipe: displacement fields of uniform noise smoothed by a Gaussian, then remap.
// Its fields and maps are kept between calls (fresh buffers would add page faults that are no
// part of the recipe).
struct ElasticBuffers {
    cv::Mat noiseX, noiseY, blurX, blurY, mapx, mapy;
};

void elasticWarp(const cv::Mat& image, cv::Mat& out, cv::RNG& rng, const cv::Mat& gridX,
                 const cv::Mat& gridY, ElasticBuffers& b) {
    const double alpha = 34, sigma = 4;
    b.noiseX.create(image.size(), CV_32F), b.noiseY.create(image.size(), CV_32F);
    rng.fill(b.noiseX, cv::RNG::UNIFORM, -1, 1);
    rng.fill(b.noiseY, cv::RNG::UNIFORM, -1, 1);
    cv::GaussianBlur(b.noiseX, b.blurX, cv::Size(), sigma);
    cv::GaussianBlur(b.noiseY, b.blurY, cv::Size(), sigma);
    cv::scaleAdd(b.blurX, alpha, gridX, b.mapx);
    cv::scaleAdd(b.blurY, alpha, gridY, b.mapy);
    cv::remap(image, out, b.mapx, b.mapy, cv::INTER_LINEAR, cv::BORDER_REFLECT_101);
}

// The grid and map steps both augmentation tables time: each grid step with its maps found at
// every pixel, and on a lattice of the grid step (DeformParams::mapStep, MulticageWarp's).
struct StepPair {
    int grid, map;
};
constexpr StepPair kAugmentSteps[] = {{4, 1}, {4, 4}, {2, 1}, {2, 2}};

// The case both augmentation tables time: 512x512, the lotus multicage of 40 vertices, random
// poses of amplitude 12 px, batches of 16 images, medians of at least 5 rounds, one thread.
struct AugmentCase {
    cv::Size size;
    cv::Mat image;
    cv::multicage::Multicage cage;
    double amplitude;
    int batch, rounds;
    explicit AugmentCase(const BenchOptions& o)
        : size(512, 512),
          image(benchImage(o.image, size)),
          cage(multicage_fixtures::lotusMulticage(size, 40)),
          amplitude(12),
          batch(16),
          rounds(std::max(5, o.repeats)) {
        cv::setNumThreads(1);
    }
};

void printAugmentRates(const BenchOptions& o) {
    using namespace cv::multicage;
    const AugmentCase ac(o);
    cv::Mat gridX(ac.size, CV_32F), gridY(ac.size, CV_32F);
    for (int y = 0; y < ac.size.height; ++y)
        for (int x = 0; x < ac.size.width; ++x)
            gridX.at<float>(y, x) = float(x), gridY.at<float>(y, x) = float(y);
    std::printf(
        "augmentation, 1 thread, %dx%d, %d vertices, amplitude %.0f px, %d images per timing, "
        "medians of %d interleaved rounds, load average %.2f:\n",
        ac.size.width, ac.size.height, ac.cage.vertexCount(), ac.amplitude, ac.batch, ac.rounds,
        loadAverage());
    std::printf("%9s %8s %15s %15s %15s %9s %15s %9s\n", "grid step", "map step", "pose+deform/s",
                "cv::remap/s", "pose/s", "ratio", "elastic/s", "ratio");
    for (const StepPair sp : kAugmentSteps) {
        const int step = sp.grid;
        DeformParams cpu;
        cpu.backend = BACKEND_CPU;
        cpu.gridStep = step;
        cpu.mapStep = sp.map;
        cv::Ptr<Deformer> d = Deformer::create(ac.image, ac.cage, cpu);
        cv::RNG rng(7);
        cv::Mat mapx, mapy, out;
        d->computeMaps(randomPose(ac.cage, d->binding(), ac.amplitude, rng), mapx, mapy);
        uint64 seed = 1;
        std::vector<std::vector<cv::Point2f>> poses(ac.batch);
        ElasticBuffers elasticBuffers;
        const std::vector<double> ms = interleavedMs(
            ac.rounds, {[&] {
                            for (int k = 0; k < ac.batch; ++k) {
                                cv::RNG r(seed++);
                                d->deform(randomPose(ac.cage, ac.amplitude, r), out);
                            }
                        },
                        [&] {
                            for (int k = 0; k < ac.batch; ++k)
                                cv::remap(ac.image, out, mapx, mapy, cv::INTER_LINEAR,
                                          cv::BORDER_CONSTANT);
                        },
                        [&] {
                            for (int k = 0; k < ac.batch; ++k) {
                                cv::RNG r(seed++);
                                poses[k] = randomPose(ac.cage, ac.amplitude, r);
                            }
                        },
                        [&] {
                            for (int k = 0; k < ac.batch; ++k)
                                elasticWarp(ac.image, out, rng, gridX, gridY, elasticBuffers);
                        }});
        const double ours = ms[0] / ac.batch, floor = ms[1] / ac.batch, pose = ms[2] / ac.batch,
                     elastic = ms[3] / ac.batch;
        std::printf("%9d %8d %15.1f %15.1f %15.1f %8.2fx %15.1f %8.2fx\n", step, sp.map, 1e3 / ours,
                    1e3 / floor, 1e3 / pose, ours / floor, 1e3 / elastic, ours / elastic);
        std::fflush(stdout);
    }
    std::printf(
        "  ratio: time per image over cv::remap's (the floor; target 1.5x at step 4, 3x at step "
        "2), "
        "and over the elastic recipe's (< 1: faster). pose/s: randomPose alone (its fold check on "
        "its own mesh of about 160 nodes along the longer side, as multicage.MulticageWarp "
        "draws). map step: DeformParams::mapStep (1: the maps found at every pixel; the grid "
        "step: found on a lattice that far apart and interpolated, as MulticageWarp deforms).\n");
}

// Thread CPU time of f() in ms (wall clock where the platform has no per-thread clock): what a
// stage costs on one thread, less disturbed than wall time by other processes on a loaded machine.
double threadCpuMs(const std::function<void()>& f) {
#if defined(CLOCK_THREAD_CPUTIME_ID)
    timespec a, b;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &a);
    f();
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &b);
    return (b.tv_sec - a.tv_sec) * 1e3 + (b.tv_nsec - a.tv_nsec) * 1e-6;
#else
    const auto t = std::chrono::steady_clock::now();
    f();
    return msSince(t);
#endif
}

// Where the time of printAugmentRates goes, stage by stage (one thread, thread CPU time, medians
// of rounds of `batch` images): the pose draw, the inverse maps (coefficient sum and raster, as
// computeMaps makes them), the whole deform (maps and sampling), and cv::remap with those maps.
void printAugmentStages(const BenchOptions& o) {
    using namespace cv::multicage;
    const AugmentCase ac(o);
    std::printf("  per image, one thread's CPU time (ms), medians of %d rounds of %d:\n", ac.rounds,
                ac.batch);
    std::printf("%11s %8s %9s %9s %9s %9s %11s\n", "grid step", "map step", "pose", "maps",
                "deform", "sampling", "cv::remap");
    for (const StepPair sp : kAugmentSteps) {
        const int step = sp.grid;
        DeformParams cpu;
        cpu.backend = BACKEND_CPU;
        cpu.gridStep = step;
        cpu.mapStep = sp.map;
        cv::Ptr<Deformer> d = Deformer::create(ac.image, ac.cage, cpu);
        std::vector<std::vector<cv::Point2f>> poses(ac.batch);
        cv::Mat mapx, mapy, out;
        uint64 seed = 1;
        std::vector<double> pose, maps, deform, remap;
        for (int r = 0; r <= ac.rounds; ++r) {  // round 0 warms up
            const double tPose = threadCpuMs([&] {
                for (auto& p : poses) {
                    cv::RNG rng(seed++);
                    p = randomPose(ac.cage, ac.amplitude, rng);
                }
            });
            const double tMaps = threadCpuMs([&] {
                for (const auto& p : poses) d->computeMaps(p, mapx, mapy);
            });
            const double tDeform = threadCpuMs([&] {
                for (const auto& p : poses) d->deform(p, out);
            });
            const double tRemap = threadCpuMs([&] {
                for (int k = 0; k < ac.batch; ++k)
                    cv::remap(ac.image, out, mapx, mapy, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
            });
            if (r == 0) continue;
            pose.push_back(tPose / ac.batch), maps.push_back(tMaps / ac.batch);
            deform.push_back(tDeform / ac.batch), remap.push_back(tRemap / ac.batch);
        }
        const double m = median(maps), dm = median(deform);
        std::printf("%11d %8d %9.3f %9.3f %9.3f %9.3f %11.3f\n", step, sp.map, median(pose), m, dm,
                    dm - m, median(remap));
    }
    std::printf(
        "  maps: the coefficient sum and the raster (computeMaps); sampling: deform less maps "
        "(the backend's own bilinear sampler where the CPU has AVX2 or AVX-512, cv::remap's "
        "bits).\n");
}

void printAugmentFirstDeform(const BenchOptions& o) {
    using namespace cv::multicage;
    const cv::Size size(1024, 768);
    const cv::Mat image = benchImage(o.image, size);
    const Multicage cage = multicage_fixtures::lotusMulticage(size, 68);
    const std::vector<cv::Point2f> pose = multicage_fixtures::wavePose(cage, 12.f, 0.5f);
    cv::setNumThreads(2);
    const Binding binding = bind(cage, MEAN_VALUE, 1);
    DeformParams cpu;
    cpu.backend = BACKEND_CPU;
    const cv::Mat& c = binding.coefficients;
    volatile float sink = 0;
    auto readOnce = [&] {  // every coefficient once, rows split between the threads
        std::vector<float> sums(c.rows, 0.f);
        cv::parallel_for_(cv::Range(0, c.rows), [&](const cv::Range& r) {
            for (int j = r.start; j < r.end; ++j) {
                const float* p = c.ptr<float>(j);
                float a[8] = {0, 0, 0, 0, 0, 0, 0, 0};
                for (int k = 0; k + 8 <= c.cols; k += 8)
                    for (int i = 0; i < 8; ++i) a[i] += p[k + i];
                sums[j] = a[0] + a[1] + a[2] + a[3] + a[4] + a[5] + a[6] + a[7];
            }
        });
        sink = sink + sums[0];
    };
    cpu.gridStep = 4;
    cv::Ptr<Deformer> d4 = Deformer::create(image, cage, cpu);
    cpu.mapStep = 4;
    cv::Ptr<Deformer> d4lattice = Deformer::create(image, d4->binding(), cpu);
    cpu.gridStep = 1, cpu.mapStep = 1;
    cv::Mat out4, remapped, mapx4, mapy4;
    d4->computeMaps(pose, mapx4, mapy4);
    const int rounds = std::max(5, o.repeats);
    // The warm grid-step-4 deform, interleaved with reads and with its peer: a plain cv::remap
    // of the same image with the same maps (the floor of any deform that samples through maps).
    const std::vector<double> ms = interleavedMs(
        rounds,
        {readOnce, [&] { d4->deform(pose, out4); },
         [&] { cv::remap(image, remapped, mapx4, mapy4, cv::INTER_LINEAR, cv::BORDER_CONSTANT); },
         [&] { d4lattice->deform(pose, out4); }});
    // A fresh Deformer each round, its first deform timed, then a read in the same round.
    // (and, in the same rounds, the same with map step 2: the maps found on a lattice 2 px apart)
    std::vector<double> firstMs, latticeMs, readMs;
    DeformParams lattice = cpu;
    lattice.mapStep = 2;
    for (int r = 0; r < rounds; ++r) {
        for (const DeformParams* p : {&cpu, &lattice}) {
            cv::Ptr<Deformer> d = Deformer::create(image, binding, *p);
            cv::Mat fresh;  // a new output, as a first call has
            auto t = std::chrono::steady_clock::now();
            d->deform(pose, fresh);
            (p == &cpu ? firstMs : latticeMs).push_back(msSince(t));
            t = std::chrono::steady_clock::now();
            readOnce();
            readMs.push_back(msSince(t));
        }
    }
    const double read = median(readMs), firstDeform = median(firstMs),
                 firstLattice = median(latticeMs);
    std::printf(
        "first deform, 2 threads, %dx%d, %d vertices (%.0f MB of coefficients), medians of %d "
        "interleaved rounds, load average %.2f:\n  read the coefficients once %.1f ms; first "
        "deform after create (grid step 1) %.1f ms = %.2fx the read (target 1.6x), with map step "
        "2 %.1f ms = %.2fx\n  read %.1f ms; warm grid-step-4 deform %.2f ms = %.2fx the read "
        "(target 0.35x), with map step 4 %.2f ms = %.2fx; cv::remap of the same image with its "
        "maps %.2f ms = %.2fx the read\n",
        size.width, size.height, cage.vertexCount(), c.total() * 4.0 / 1e6, rounds, loadAverage(),
        read, firstDeform, firstDeform / read, firstLattice, firstLattice / read, ms[0], ms[1],
        ms[1] / ms[0], ms[3], ms[3] / ms[0], ms[2], ms[2] / ms[0]);
}

void printAugment(const BenchOptions& o) {
    const int threads = cv::getNumThreads();
    printAugmentRates(o);
    printAugmentStages(o);
    printAugmentFirstDeform(o);
    cv::setNumThreads(threads);
}

void runBench(const BenchOptions& o) {
    using namespace cv::multicage;
    // Everything that can fail on bad input fails before the first line of output.
    const std::vector<BenchCase> cases = benchCases(o);
    if (!o.image.empty()) readImage(o.image);
    if (o.augment) {
        printAugment(o);
        return;
    }
    if (o.threads > 0) cv::setNumThreads(o.threads);
    std::printf("multicage bench: medians of %d runs, %d threads, OpenCV %s%s\n", o.repeats,
                cv::getNumThreads(), CV_VERSION,
                o.half ? ", half-float coefficients on the GPU" : "");
    std::unique_ptr<HeadlessGLContext> gl;
    std::string device = "none";
    if (!o.noGpu) gl = openGpu(&device);
    printTableHeader();
    CaseInputs firstCase;  // the CPU sections below use the first case
    std::vector<CaseRecord> records;
    for (const BenchCase& c : cases) {
        CaseInputs in;
        const CaseRecord r = measureCase(o, c, gl.get(), in);
        printCaseRow(c, r, in.binding);
        if (records.empty()) firstCase = in;
        records.push_back(r);
    }
    printTableNotes();
    if (gl) printGpuTable(records);
    if (!o.json.empty()) {
        writeJson(o.json, device, o, records);
        std::printf("figures written to %s\n", o.json.c_str());
    }
    if (!o.gpuOnly) {
        printCpuFirstCall(o, firstCase.image, firstCase.binding, firstCase.pose);
        firstCase.binding = Binding();
        printCpuScaling(o, firstCase.image, firstCase.cage, firstCase.pose);
    }
}
}  // namespace

void addBenchCommand(CLI::App& app) {
    auto o = std::make_shared<BenchOptions>();
    CLI::App* cmd = app.add_subcommand(
        "bench",
        "Time binding and pose updates on the paper's Table 1 cases (two 'lotus' multicages of "
        "68, 44, 40, 35, 29 and 41 vertices) next to OpenCV's thin-plate spline warp, and the "
        "GPU stages of both pipelines (compute and the paper's vertex shader) from timer queries.\n"
        "On an NVIDIA machine, one command fills the README's GPU table:\n"
        "  multicage bench --first --json gpu.json && multicage bench --size 4096x3072 --half "
        "--gpu-only --json gpu_4k.json");
    cmd->add_option("--repeats", o->repeats, "Timed runs per figure (the median is printed)")
        ->capture_default_str()
        ->check(CLI::Range(1, 1000));
    cmd->add_flag("--first", o->paperOnly, "Only the first case (1024x768, 68 vertices)");
    cmd->add_flag(
        "--augment", o->augment,
        "Only the augmentation figures: randomPose + deform at 512x512 (1 thread, grid "
        "steps 4 and 2, each with the maps found at every pixel and on a lattice of the grid "
        "step, DeformParams::mapStep) against cv::remap and the elastic recipe in the same run, "
        "and the first deform (map steps 1 and 2) and a warm grid-step-4 deform (map steps 1 "
        "and 4) at 1024x768 (2 threads) against reading the coefficients once, with a plain "
        "cv::remap of that image beside them");
    cmd->add_flag("--no-peer", o->noPeer, "Skip the thin-plate spline peer");
    cmd->add_flag("--no-gpu", o->noGpu, "Skip the GPU columns");
    cmd->add_option(
           "--threads", o->threads,
           "CPU threads (cv::setNumThreads) for the whole bench; the scaling table goes up "
           "to this count (default: OpenCV's, all cores)")
        ->check(CLI::Range(1, 1024));
    cmd->add_option("--image", o->image,
                    "Photograph to resize for every case (default: a pattern)");
    cmd->add_option("--size", o->size,
                    "One case of this size (WIDTHxHEIGHT, e.g. 4096x3072) instead of Table 1's");
    cmd->add_option("--vertices", o->vertices, "User vertices of the --size case")
        ->capture_default_str()
        ->check(CLI::Range(8, 4096));
    cmd->add_flag("--half", o->half, "Half-float coefficients on the GPU (RGBA16F)");
    cmd->add_flag("--gpu-only", o->gpuOnly,
                  "GPU figures only (no CPU binding, no peer): for sizes whose CPU binding would "
                  "not fit in memory");
    cmd->add_option("--json", o->json, "Also write every figure to this JSON file (atomically)");
    cmd->callback([o] { runBench(*o); });
}

}  // namespace multicage_cli

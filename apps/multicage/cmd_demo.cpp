// multicage demo: the embedded default job, end to end.
#include <chrono>
#include <filesystem>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string_view>

#include "cli_util.hpp"

namespace cv {
namespace multicage {
namespace embedded {
std::string_view demo(std::string_view file);
}
}  // namespace multicage
}  // namespace cv

namespace multicage_cli {

namespace {
struct DemoOptions {
    std::string outDir = "multicage-demo", backend = "auto";
    int gridStep = 1;
};

cv::Mat decodeEmbeddedImage(std::string_view name) {
    const std::string_view bytes = cv::multicage::embedded::demo(name);
    const std::vector<uchar> buffer(bytes.begin(), bytes.end());
    return cv::imdecode(buffer, cv::IMREAD_COLOR);
}

cv::multicage::Multicage embeddedCage(std::string_view name) {
    const std::string_view text = cv::multicage::embedded::demo(name);
    cv::FileStorage fs(std::string(text), cv::FileStorage::READ | cv::FileStorage::MEMORY);
    cv::multicage::Multicage cage;
    cage.read(fs.root());
    return cage;
}

void runDemo(const DemoOptions& o) {
    using namespace cv::multicage;
    namespace fs = std::filesystem;
    fs::create_directories(o.outDir);
    const cv::Mat image = decodeEmbeddedImage("butterfly.jpg");
    std::cout << "multicage demo: butterfly.jpg (" << image.cols << "x" << image.rows << ")\n";
    Multicage cage = embeddedCage("butterfly.yml");
    cage.orient();
    std::cout << "  multicage: " << cage.polygonCount() << " polygons, " << cage.vertexCount()
              << " vertices (the body polygon protects the body while the wings move)\n";
    DeformParams params;
    params.backend = parseBackend(o.backend);
    params.gridStep = o.gridStep;
    auto t = std::chrono::steady_clock::now();
    cv::Ptr<Deformer> deformer = Deformer::create(image, cage, params);
    std::cout << "  bound " << deformer->binding().nodeCount() << " nodes to "
              << deformer->binding().coefficientCount() << " vertices in " << cvRound(msSince(t))
              << " ms (min conditioning " << deformer->binding().minConditioning << ")\n";
    const Pose& pose = cage.pose(0);
    t = std::chrono::steady_clock::now();
    cv::Mat deformed;
    deformer->deform(pose.vertices, deformed);
    std::cout << "  deformed to pose '" << pose.name << "' on the " << backendName(deformer->backend())
              << " in " << cvRound(msSince(t)) << " ms\n";

    cv::Mat overlay = image.clone(), posed = deformed.clone();
    cage.draw(overlay, 2);
    Multicage posedCage(cage.imageSize());
    for (int p = 0; p < cage.polygonCount(); ++p) {
        const int offset = cage.polygonOffset(p), n = static_cast<int>(cage.polygon(p).size());
        posedCage.addPolygon(std::vector<cv::Point2f>(pose.vertices.begin() + offset,
                                                      pose.vertices.begin() + offset + n));
    }
    posedCage.draw(posed, 2);
    cv::Mat sideBySide;
    cv::hconcat(overlay, posed, sideBySide);
    const std::vector<std::pair<std::string, cv::Mat>> outputs = {
        {"input.png", image}, {"overlay.png", overlay}, {"deformed.png", deformed},
        {"deformed_overlay.png", posed}, {"side_by_side.png", sideBySide}};
    for (const auto& [name, img] : outputs) imwriteAtomic((fs::path(o.outDir) / name).string(), img);
    cage.save((fs::path(o.outDir) / "cage.yml").string());
    std::cout << "  wrote " << o.outDir << "/{input,overlay,deformed,deformed_overlay,side_by_side}.png"
              << " and cage.yml\n  next: multicage deform " << o.outDir << "/input.png " << o.outDir
              << "/cage.yml -o out.png" << std::endl;
}
}  // namespace

void addDemoCommand(CLI::App& app) {
    auto o = std::make_shared<DemoOptions>();
    CLI::App* cmd = app.add_subcommand(
        "demo",
        "Run the built-in example: a butterfly photo, a multicage (wings outside, body inside), "
        "a pose that moves the wings, and the output images in a folder.");
    cmd->add_option("-o,--output-dir", o->outDir, "Folder for the outputs")->capture_default_str();
    cmd->add_option("--backend", o->backend, "auto, cpu or gpu")->capture_default_str()
        ->check(CLI::IsMember({"auto", "cpu", "gpu"}));
    cmd->add_option("--grid-step", o->gridStep, "A mesh node every N pixels")->capture_default_str()->check(CLI::Range(1, 256));
    cmd->callback([o] { runDemo(*o); });
}

}  // namespace multicage_cli

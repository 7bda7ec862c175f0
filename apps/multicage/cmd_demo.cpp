// multicage demo: the embedded default job, end to end.
#include <chrono>
#include <filesystem>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string_view>

#include "cli_util.hpp"
#include "fixtures.hpp"

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
    std::string outDir = "multicage-demo";
    DeformOptions deform;
};

cv::Mat decodeEmbeddedImage(std::string_view name) {
    const std::string_view bytes = cv::multicage::embedded::demo(name);
    const std::vector<uchar> buffer(bytes.begin(), bytes.end());
    return cv::imdecode(buffer, cv::IMREAD_COLOR);
}

void runDemo(const DemoOptions& o) {
    using namespace cv::multicage;
    namespace fs = std::filesystem;
    fs::create_directories(o.outDir);
    const cv::Mat image = decodeEmbeddedImage("butterfly.jpg");
    std::cout << "multicage demo: butterfly.jpg (" << image.cols << "x" << image.rows << ")\n";
    // The multicage is proposed from the image: an outer polygon around the butterfly, then
    // inner polygons protecting the salient features inside it.
    auto t = std::chrono::steady_clock::now();
    Multicage cage = proposeProtectedMulticage(image);  // what `multicage propose` does by default
    if (cage.polygonCount() == 0) throw Failure("the proposal found no object in the demo image");
    std::cout << "  proposed a multicage in " << cvRound(msSince(t)) << " ms: " << cage.polygonCount()
              << " polygons, " << cage.vertexCount()
              << " vertices (inner polygons protect the wing patterns while the outline moves)\n";
    // The pose: the outline stretched outwards (kept 4 px inside the image), so the band
    // between it and the protected patterns takes the stretch; the inner polygons stay at rest.
    std::vector<cv::Point2f> stretch = multicage_fixtures::stretchPolygon(cage, 0, 1.04f, 1.15f);
    for (cv::Point2f& p : stretch) {
        p.x = std::min(std::max(p.x, 4.f), image.cols - 5.f);
        p.y = std::min(std::max(p.y, 4.f), image.rows - 5.f);
    }
    cage.addPose("stretch", stretch, 1.0);
    std::string stepChange;
    const DeformParams params = deformParams(o.deform, "demo", image.size(), cage, &stepChange);
    if (!stepChange.empty())
        std::cout << "  grid step " << params.gridStep << " (" << stepChange << ")\n";
    probeAutoBackend(params.backend);  // once, and not counted as bind time
    t = std::chrono::steady_clock::now();
    cv::Ptr<Deformer> deformer = Deformer::create(image, cage, params);
    std::cout << "  bound " << deformer->binding().nodeCount() << " nodes to "
              << deformer->binding().coefficientCount() << " vertices in " << cvRound(msSince(t))
              << " ms (min conditioning " << deformer->binding().minConditioning << ")\n";
    const Pose& pose = cage.pose(0);
    if (const int folded = deformer->foldedTriangles(pose.vertices))
        std::cout << "  note: the pose folds " << folded << " mesh triangles over\n";
    t = std::chrono::steady_clock::now();
    cv::Mat deformed;
    deformer->deform(pose.vertices, deformed);
    std::cout << "  deformed to pose '" << pose.name << "' on the " << backendName(deformer->backend())
              << " in " << cvRound(msSince(t)) << " ms\n";

    cv::Mat overlay = image.clone(), posed = deformed.clone();
    cage.draw(overlay, 2);
    cage.posed(pose.vertices).draw(posed, 2);
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
        "Run the built-in example: a butterfly photo, a multicage proposed from it (an outline "
        "around the butterfly, inner polygons protecting its wing patterns), a pose that "
        "stretches the outline, and the output images in a folder.");
    cmd->add_option("-o,--output-dir", o->outDir, "Folder for the outputs")->capture_default_str();
    addDeformOptions(cmd, o->deform);
    cmd->callback([o] { runDemo(*o); });
}

}  // namespace multicage_cli

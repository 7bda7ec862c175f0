// multicage demo: the embedded default job, end to end; --faces: the face scene (issue 16).
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
    std::string outDir;  // default: multicage-demo, or multicage-demo-faces with --faces
    bool faces = false;
    DeformOptions deform;
};

// What the demo deforms: an image, the multicage proposed for it with its pose "stretch",
// and for the face scene the faces it protects.
struct Scene {
    std::string name;
    cv::Mat image;
    cv::multicage::Multicage cage;
    std::vector<cv::Rect> faces;
    int lineWidth = 2;  // of the polygons drawn on the pictures
};

cv::Mat decodeEmbeddedImage(std::string_view name) {
    const std::string_view bytes = cv::multicage::embedded::demo(name);
    const std::vector<uchar> buffer(bytes.begin(), bytes.end());
    return cv::imdecode(buffer, cv::IMREAD_COLOR);
}

// Polygon `polygon` scaled by (sx, sy) about its centroid; the other vertices at rest. Near the
// image border (within 5% of the shorter side, at least 4 px) a vertex does not move, and none
// moves into that strip: squeezed or dragged along between the polygon and the fixed frame,
// the strip's mesh folds.
std::vector<cv::Point2f> stretchInside(const cv::multicage::Multicage& cage, int polygon, float sx,
                                       float sy) {
    std::vector<cv::Point2f> pose = multicage_fixtures::stretchPolygon(cage, polygon, sx, sy);
    const std::vector<cv::Point2f> rest = cage.vertices();
    const cv::Size size = cage.imageSize();
    const float near = std::max(4.f, 0.05f * std::min(size.width, size.height));
    const float right = size.width - 1 - near, bottom = size.height - 1 - near;
    const int begin = cage.polygonOffset(polygon);
    const int end = begin + static_cast<int>(cage.polygon(polygon).size());
    for (int i = begin; i < end; ++i) {
        const cv::Point2f r = rest[i];
        cv::Point2f& p = pose[i];
        if (r.x < near || r.y < near || r.x > right || r.y > bottom) {
            p = r;
            continue;
        }
        p.x = std::min(std::max(p.x, near), right);
        p.y = std::min(std::max(p.y, near), bottom);
    }
    return pose;
}

void printProposal(const cv::multicage::Multicage& cage, double ms, const char* what) {
    std::cout << "  proposed a multicage in " << cvRound(ms)
              << " ms: " << plural(cage.polygonCount(), "polygon") << ", "
              << plural(cage.vertexCount(), "vertex", "vertices") << " (" << what << ")\n";
}

Scene butterflyScene() {
    using namespace cv::multicage;
    Scene s{"butterfly.jpg", decodeEmbeddedImage("butterfly.jpg"), {}, {}, 2};
    std::cout << "multicage demo: " << s.name << " (" << s.image.cols << "x" << s.image.rows
              << ")\n";
    // The multicage is proposed from the image: an outer polygon around the butterfly, then
    // inner polygons protecting the salient features inside it.
    const auto t = std::chrono::steady_clock::now();
    s.cage = proposeProtectedMulticage(s.image);  // what `multicage propose` does by default
    if (s.cage.polygonCount() == 0) throw Failure("the proposal found no object in the demo image");
    // Inner polygons only where a region is more textured than the butterfly around it (the
    // proposal's texture rule): say what this proposal holds, not what it used to.
    printProposal(s.cage, msSince(t),
                  s.cage.polygonCount() > 1
                      ? "inner polygons protect what they hold while the outline moves"
                      : "an outline around the butterfly; no region inside is more textured "
                        "than the butterfly itself, so no inner polygon");
    // The pose: the outline stretched outwards, so the band between it and the protected
    // patterns takes the stretch; the inner polygons stay at rest.
    s.cage.addPose("stretch", stretchInside(s.cage, 0, 1.04f, 1.15f), 1.0);
    return s;
}

// The index of the outline (depth 1) around a face, or -1.
int outlineAround(const cv::multicage::Multicage& cage, const cv::Rect& face) {
    const cv::Point2f c(face.x + 0.5f * face.width, face.y + 0.5f * face.height);
    for (int p = 0; p < cage.polygonCount(); ++p)
        if (cage.depth(p) == 1 && cv::pointPolygonTest(cage.polygon(p), c, false) > 0) return p;
    return -1;
}

Scene facesScene() {
    using namespace cv::multicage;
    Scene s{"messi5.jpg", decodeEmbeddedImage("messi5.jpg"), {}, {}, 1};  // thin: a small face
    std::cout << "multicage demo --faces: " << s.name << " (" << s.image.cols << "x" << s.image.rows
              << ")\n";
    ProposeParams params;
    params.protect = PROTECT_FACES;  // the face only: the rest of the body takes the stretch
    if (faceCascadeFile(params).empty())
        throw Failure(std::string("demo --faces needs OpenCV's face cascades (") +
                      MULTICAGE_DEBIAN_CASCADE_DIR + "): install the Debian package opencv-data");
    const auto t = std::chrono::steady_clock::now();
    s.cage = proposeProtectedMulticage(s.image, params, &s.faces);
    if (s.faces.empty()) throw Failure("no face found in the demo image " + s.name);
    const int outline = outlineAround(s.cage, s.faces[0]);
    if (outline < 0) throw Failure("internal error: the face has no outline around it");
    printProposal(s.cage, msSince(t),
                  "an outline around the player, a rounded box hugging the face");
    // The pose: the body's outline stretched 20% wider about its centre; the face's polygon
    // stays at rest.
    s.cage.addPose("stretch", stretchInside(s.cage, outline, 1.2f, 1.0f), 1.0);
    return s;
}

// How far each face is from a similarity under the pose, over the mesh nodes inside it.
void printFaceResiduals(const Scene& s, const cv::multicage::Binding& binding,
                        const std::vector<cv::Point2f>& pose) {
    for (const cv::Rect& f : s.faces) {
        if (multicage_fixtures::boxNodes(binding, f).size() < 3) continue;
        std::printf(
            "  face at %d,%d (%dx%d) stays a face: %.2f px from a similarity over its box's "
            "inner 80%% (%s coordinates)\n",
            f.x, f.y, f.width, f.height, multicage_fixtures::boxResidual(binding, pose, f),
            cv::multicage::coordinateTypeDescription(binding.coordinates));
    }
    std::fflush(stdout);
}

void writeOutputs(const std::string& dir, const Scene& s, const cv::Mat& deformed) {
    using namespace cv::multicage;
    namespace fs = std::filesystem;
    const Pose& pose = s.cage.pose(0);
    cv::Mat overlay = s.image.clone(), posed = deformed.clone();
    s.cage.draw(overlay, s.lineWidth);
    s.cage.posed(pose.vertices).draw(posed, s.lineWidth);
    cv::Mat sideBySide;
    cv::hconcat(overlay, posed, sideBySide);
    const std::vector<std::pair<std::string, cv::Mat>> outputs = {{"input.png", s.image},
                                                                  {"overlay.png", overlay},
                                                                  {"deformed.png", deformed},
                                                                  {"deformed_overlay.png", posed},
                                                                  {"side_by_side.png", sideBySide}};
    for (const auto& [name, img] : outputs) imwriteAtomic((fs::path(dir) / name).string(), img);
    s.cage.save((fs::path(dir) / "cage.yml").string());
    std::cout << "  wrote " << dir << "/{input,overlay,deformed,deformed_overlay,side_by_side}.png"
              << " and cage.yml\n  next: multicage deform " << dir << "/input.png " << dir
              << "/cage.yml -o out.png" << std::endl;
}

void runDemo(const DemoOptions& o) {
    using namespace cv::multicage;
    const std::string dir = !o.outDir.empty() ? o.outDir
                            : o.faces         ? "multicage-demo-faces"
                                              : "multicage-demo";
    std::filesystem::create_directories(dir);
    const Scene s = o.faces ? facesScene() : butterflyScene();
    std::string stepChange;
    const DeformParams params = deformParams(o.deform, "demo", s.image.size(), s.cage, &stepChange);
    if (!stepChange.empty())
        std::cout << "  grid step " << params.gridStep << " (" << stepChange << ")\n";
    probeAutoBackend(params.backend);  // once, and not counted as bind time
    auto t = std::chrono::steady_clock::now();
    cv::Ptr<Deformer> deformer = Deformer::create(s.image, s.cage, params);
    std::cout << "  bound " << deformer->binding().nodeCount() << " nodes to "
              << deformer->binding().coefficientCount() << " vertices in " << cvRound(msSince(t))
              << " ms (min conditioning " << deformer->binding().minConditioning << ")\n";
    const Pose& pose = s.cage.pose(0);
    if (const int folded = deformer->foldedTriangles(pose.vertices))
        std::cout << "  note: the pose folds " << folded << " mesh triangles over\n";
    t = std::chrono::steady_clock::now();
    cv::Mat deformed;
    deformer->deform(pose.vertices, deformed);
    std::cout << "  deformed to pose '" << pose.name << "' on the "
              << backendName(deformer->backend()) << " in " << cvRound(msSince(t)) << " ms\n";
    printFaceResiduals(s, deformer->binding(), pose.vertices);
    writeOutputs(dir, s, deformed);
}
}  // namespace

void addDemoCommand(CLI::App& app) {
    auto o = std::make_shared<DemoOptions>();
    CLI::App* cmd = app.add_subcommand(
        "demo",
        "Run the built-in example: a butterfly photo, a multicage proposed from it (an outline "
        "around the butterfly, and inner polygons around what is more textured than it), a pose "
        "that "
        "stretches the outline, and the output images in a folder.\n"
        "--faces: the face scene instead: a footballer (messi5.jpg), an outline around him and "
        "a polygon hugging his face (found by OpenCV's face cascades, Debian package "
        "opencv-data); the pose stretches the body 20% wider and the face stays a face.");
    cmd->add_option("-o,--output-dir", o->outDir,
                    "Folder for the outputs (default: multicage-demo, with --faces "
                    "multicage-demo-faces)");
    cmd->add_flag("--faces", o->faces, "Show face protection on messi5.jpg (see above)");
    addDeformOptions(cmd, o->deform);
    cmd->callback([o] { runDemo(*o); });
}

}  // namespace multicage_cli

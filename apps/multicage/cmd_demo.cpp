// multicage demo: the embedded default job, end to end: the astronaut, an outline with a face
// polygon nested in it and eye polygons nested in that, and a pose that widens the outline
// while the nested polygons move as rigid pieces and nothing folds (issue 39); --faces: the
// face scene (issue 16).
#include <algorithm>
#include <chrono>
#include <cmath>
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

// What the demo deforms: an image, the multicage proposed for it (its pose "stretch" is added
// once the image is bound: it is chosen so that it folds nothing), the outline the pose widens,
// and the faces the proposal protects.
struct Scene {
    std::string name;
    cv::Mat image;
    cv::multicage::Multicage cage;
    std::vector<cv::Rect> faces;
    int outline = -1;   // the polygon the pose widens
    int lineWidth = 2;  // of the polygons drawn on the pictures
};

cv::Mat decodeEmbeddedImage(std::string_view name) {
    const std::string_view bytes = cv::multicage::embedded::demo(name);
    const std::vector<uchar> buffer(bytes.begin(), bytes.end());
    return cv::imdecode(buffer, cv::IMREAD_COLOR);
}

cv::Point2f meanOf(const std::vector<cv::Point2f>& points) {
    cv::Point2f c(0, 0);
    for (const cv::Point2f& p : points) c += p;
    return c * (1.f / points.size());
}

// Whether polygon `inner` lies inside polygon `outer` (the polygons of a valid multicage do
// not cross, so one vertex tells).
bool nestedIn(const cv::multicage::Multicage& cage, int outer, int inner) {
    return inner != outer && cage.depth(inner) > cage.depth(outer) &&
           cv::pointPolygonTest(cage.polygon(outer), cage.polygon(inner)[0], false) > 0;
}

// The polygons one level inside `outline` (each with what is nested in it: a rigid piece).
std::vector<int> childrenOf(const cv::multicage::Multicage& cage, int outline) {
    std::vector<int> children;
    for (int p = 0; p < cage.polygonCount(); ++p)
        if (cage.depth(p) == cage.depth(outline) + 1 && nestedIn(cage, outline, p))
            children.push_back(p);
    return children;
}

int nestedCount(const cv::multicage::Multicage& cage, int outline) {
    int n = 0;
    for (int p = 0; p < cage.polygonCount(); ++p) n += nestedIn(cage, outline, p);
    return n;
}

// The outline to widen: the one around the first face, else the largest top-level polygon.
int chooseOutline(const cv::multicage::Multicage& cage, const std::vector<cv::Rect>& faces) {
    if (!faces.empty()) {
        const int around = multicage_fixtures::outlineAround(cage, faces[0]);
        if (around >= 0) return around;
    }
    int best = -1;
    for (int p = 0; p < cage.polygonCount(); ++p)
        if (cage.depth(p) == 1 &&
            (best < 0 || std::abs(cage.signedArea(p)) > std::abs(cage.signedArea(best))))
            best = p;
    return best;
}

// The demo's pose: the middle of the outline widened, the polygons nested in it moved as rigid
// pieces. Each outline vertex at x moves sideways by A sin(pi (x - c) / r) within r of the
// outline's centre c (A = strength r / pi): left of c to the left, right of it to the right,
// most at r/2, not at all at c and beyond r. That map of the line is monotone (strength < 1),
// so the outline stays simple and its parts keep their order; the body around the centre is
// widened by up to 1 + strength, and the arms, legs or helmet at the sides are pushed out
// less, or not at all, where a tip pushed along its own axis into the fixed background would
// fold the mesh around it. Vertices within 5% of the shorter side of the image frame stay
// (a vertex dragged along the fixed frame folds the thin strip between them), and the motion
// fades in over the next 5%. A polygon nested in the outline (with everything nested in it)
// moves by the displacement of its centre: rigidly, a translation.
std::vector<cv::Point2f> widenPose(const cv::multicage::Multicage& cage, int outline,
                                   float strength) {
    const std::vector<cv::Point2f> rest = cage.vertices();
    std::vector<cv::Point2f> pose(rest.begin(), rest.begin() + cage.vertexCount());
    const cv::Size size = cage.imageSize();
    const float c = meanOf(cage.polygon(outline)).x, r = 0.28f * size.width;
    const float amplitude = strength * r / static_cast<float>(CV_PI);
    auto shift = [&](float x) {
        const float t = (x - c) / r;
        return std::abs(t) >= 1 ? 0.f : amplitude * std::sin(static_cast<float>(CV_PI) * t);
    };
    const float near = std::max(4.f, 0.05f * std::min(size.width, size.height));
    const int begin = cage.polygonOffset(outline);
    for (int i = begin; i < begin + static_cast<int>(cage.polygon(outline).size()); ++i) {
        const cv::Point2f p = rest[i];
        const float border = std::min({p.x, p.y, size.width - 1 - p.x, size.height - 1 - p.y});
        const float fade = std::min(1.f, std::max(0.f, (border - near) / near));
        pose[i].x = p.x + fade * shift(p.x);
    }
    for (const int child : childrenOf(cage, outline)) {
        const cv::Point2f move(shift(meanOf(cage.polygon(child)).x), 0.f);
        for (int p = 0; p < cage.polygonCount(); ++p) {
            if (p != child && !nestedIn(cage, child, p)) continue;
            const int b = cage.polygonOffset(p);
            for (int i = b; i < b + static_cast<int>(cage.polygon(p).size()); ++i)
                pose[i] = rest[i] + move;
        }
    }
    return pose;
}

// The strongest widening (from 0.8 down) that keeps the multicage valid (validatePose) and
// folds no triangle of the deformer's mesh; the rest pose when none does. Says which.
std::vector<cv::Point2f> chooseStretch(const Scene& s, const cv::multicage::Deformer& deformer) {
    using namespace cv::multicage;
    const std::vector<cv::Point2f> rest = s.cage.vertices();
    float strength = 0.8f;
    for (int attempt = 0; attempt < 12; ++attempt, strength *= 0.85f) {
        const std::vector<cv::Point2f> pose = widenPose(s.cage, s.outline, strength);
        if (!validatePose(s.cage, pose) || deformer.foldedTriangles(pose) != 0) continue;
        double most = 0;
        const int begin = s.cage.polygonOffset(s.outline);
        for (int i = begin; i < begin + static_cast<int>(s.cage.polygon(s.outline).size()); ++i)
            most = std::max(most, cv::norm(pose[i] - rest[i]));
        const int nested = nestedCount(s.cage, s.outline);
        std::cout << "  pose 'stretch': the outline's middle widened up to "
                  << cvRound(100 * strength) << "% (its vertices moved up to " << cvRound(most)
                  << " px), "
                  << (nested > 0 ? "the " + plural(nested, "polygon") +
                                       " nested in it moved with it as rigid pieces"
                                 : std::string("no polygon nested in it to keep rigid"))
                  << "; the pose folds nothing (0 mesh triangles over)\n";
        return pose;
    }
    std::cout << "  note: every widening tried folds the mesh over; the pose 'stretch' is the "
                 "rest pose (it folds nothing)\n";
    return std::vector<cv::Point2f>(rest.begin(), rest.begin() + s.cage.vertexCount());
}

void printProposal(const cv::multicage::Multicage& cage, double ms, const std::string& what) {
    std::cout << "  proposed a multicage in " << cvRound(ms)
              << " ms: " << plural(cage.polygonCount(), "polygon") << ", "
              << plural(cage.vertexCount(), "vertex", "vertices") << " (" << what << ")\n";
}

// What the outline holds, in words: "nested in it, a polygon around the face and, in that,
// 2 around its eyes", counted from the cage.
std::string describeNesting(const cv::multicage::Multicage& cage, int outline,
                            const std::vector<cv::Rect>& faces, const std::string& subject) {
    using namespace cv::multicage;
    std::string words = "an outline around " + subject;
    const std::vector<int> children = childrenOf(cage, outline);
    if (children.empty())
        return words +
               " and nothing nested in it: no face found inside it (the face cascades are the "
               "Debian package opencv-data) and no region more textured than the subject";
    int facePolygons = 0, inFaces = 0, others = 0;
    for (const int child : children) {
        bool face = false;
        for (const cv::Rect& f : faces)
            face = face || cv::pointPolygonTest(cage.polygon(child),
                                                cv::Point2f(f.x + 0.5f * f.width,
                                                            f.y + 0.5f * f.height),
                                                false) > 0;
        const int inside = nestedCount(cage, child);
        if (face)
            ++facePolygons, inFaces += inside;
        else
            others += 1 + inside;
    }
    words += "; nested in it, ";
    if (facePolygons > 0) {
        words += facePolygons == 1 ? "a polygon around the face"
                                   : std::to_string(facePolygons) + " polygons around faces";
        if (inFaces > 0)
            words += " and, in that, " + std::to_string(inFaces) +
                     (cage.coordinates() == MEAN_VALUE ? " anchoring it" : " around the eyes");
        if (others > 0) words += ", and ";
    }
    if (others > 0) words += plural(others, "polygon") + " around textured features";
    return words;
}

Scene astronautScene() {
    using namespace cv::multicage;
    Scene s{"astronaut.jpg", decodeEmbeddedImage("astronaut.jpg"), {}, {}, -1, 2};
    std::cout << "multicage demo: " << s.name << " (" << s.image.cols << "x" << s.image.rows
              << ")\n";
    // The multicage is proposed from the image, as `multicage propose` does by default: an
    // outline around the astronaut, then inner polygons protecting her face (and, nested in
    // it, her eyes) and the textured features inside it. Without the subject model the
    // classic cues find the same; without the face cascades there may be no inner polygon.
    const auto t = std::chrono::steady_clock::now();
    s.cage = proposeProtectedMulticage(s.image, ProposeParams(), &s.faces);
    s.outline = chooseOutline(s.cage, s.faces);
    if (s.outline < 0) throw Failure("the proposal found no object in the demo image");
    printProposal(s.cage, msSince(t), describeNesting(s.cage, s.outline, s.faces, "the astronaut"));
    return s;
}

Scene facesScene() {
    using namespace cv::multicage;
    Scene s{"messi5.jpg", decodeEmbeddedImage("messi5.jpg"), {}, {}, -1, 1};  // thin: a small face
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
    s.outline = multicage_fixtures::outlineAround(s.cage, s.faces[0]);
    if (s.outline < 0) throw Failure("internal error: the face has no outline around it");
    printProposal(s.cage, msSince(t), describeNesting(s.cage, s.outline, s.faces, "the player"));
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
    const Pose& pose = s.cage.pose(s.cage.findPose("stretch"));
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
    Scene s = o.faces ? facesScene() : astronautScene();
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
    s.cage.addPose("stretch", chooseStretch(s, *deformer), 1.0);
    const Pose& pose = s.cage.pose(s.cage.findPose("stretch"));
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
        "Run the built-in example: a photo of an astronaut (NASA, public domain), the "
        "multicage `multicage propose` gives it (an outline around her; nested in it a polygon "
        "around her face, and in that polygons around her eyes), a pose that widens the "
        "outline's middle while the nested polygons move as rigid pieces (the strongest "
        "widening that folds nothing), and the output images in a folder.\n"
        "--faces: the face scene instead: a footballer (messi5.jpg), an outline around him and "
        "a polygon hugging his face (found by OpenCV's face cascades, Debian package "
        "opencv-data); the pose widens the body and the face stays a face.");
    cmd->add_option("-o,--output-dir", o->outDir,
                    "Folder for the outputs (default: multicage-demo, with --faces "
                    "multicage-demo-faces)");
    cmd->add_flag("--faces", o->faces, "Show face protection on messi5.jpg (see above)");
    addDeformOptions(cmd, o->deform);
    cmd->callback([o] { runDemo(*o); });
}

}  // namespace multicage_cli

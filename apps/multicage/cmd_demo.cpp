// multicage demo: the embedded default job, end to end: the astronaut, an outline with a face
// polygon nested in it and eye polygons nested in that, and a pose that widens the outline
// while the nested polygons move as rigid pieces and nothing folds (issue 39); --faces: the
// face protection alone (issue 16).
#include <algorithm>
#include <cfloat>
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
// centre c (A = strength r / pi): left of c to the left, right of it to the right, most at r/2,
// not at all at c and beyond r. That map of the line is monotone (strength < 1), so the
// outline stays simple and its parts keep their order; the body around the centre is widened
// by up to 1 + strength, and the arms, legs or helmet at the sides are pushed out less, or not
// at all, where a tip pushed along its own axis into the fixed background would fold the mesh
// around it. Vertices within 5% of the shorter side of the image frame stay (a vertex dragged
// along the fixed frame folds the thin strip between them), and the motion fades in over the
// next 5%; so do they near another object's outline, which stays where it is (a thin gap
// between it and a moving outline would be sheared and fold). A polygon nested in the
// outline, with everything nested in it, moves by the displacement of its centre: rigidly.
std::vector<cv::Point2f> widenPose(const cv::multicage::Multicage& cage, int outline, float c,
                                   float strength) {
    const std::vector<cv::Point2f> rest = cage.vertices();
    std::vector<cv::Point2f> pose(rest.begin(), rest.begin() + cage.vertexCount());
    const cv::Size size = cage.imageSize();
    const float r = 0.28f * size.width, amplitude = strength * r / static_cast<float>(CV_PI);
    const float near = std::max(4.f, 0.05f * std::min(size.width, size.height));
    auto shift = [&](float x) {
        const float t = (x - c) / r;
        return std::abs(t) >= 1 ? 0.f : amplitude * std::sin(static_cast<float>(CV_PI) * t);
    };
    auto fade = [&](const std::vector<cv::Point2f>& points) {
        float border = FLT_MAX;
        for (const cv::Point2f& p : points)
            border = std::min({border, p.x, p.y, size.width - 1 - p.x, size.height - 1 - p.y});
        return std::min(1.f, std::max(0.f, (border - near) / near));
    };
    std::vector<int> others;  // the other objects' outlines: they stay, as the frame does
    for (int p = 0; p < cage.polygonCount(); ++p)
        if (p != outline && cage.depth(p) == 1) others.push_back(p);
    const int begin = cage.polygonOffset(outline);
    for (int i = begin; i < begin + static_cast<int>(cage.polygon(outline).size()); ++i) {
        float f = fade({rest[i]});
        for (const int other : others) {
            const float gap =
                static_cast<float>(-cv::pointPolygonTest(cage.polygon(other), rest[i], true));
            f = std::min(f, std::min(1.f, std::max(0.f, (gap - near) / near)));
        }
        pose[i].x = rest[i].x + f * shift(rest[i].x);
    }
    const std::vector<int> pieces = childrenOf(cage, outline);
    for (const int piece : pieces) {
        const std::vector<cv::Point2f> polygon = cage.polygon(piece);
        const cv::Point2f move(fade(polygon) * shift(meanOf(polygon).x), 0.f);
        for (int p = 0; p < cage.polygonCount(); ++p) {
            if (p != piece && !nestedIn(cage, piece, p)) continue;
            const int b = cage.polygonOffset(p);
            for (int i = b; i < b + static_cast<int>(cage.polygon(p).size()); ++i)
                pose[i] = rest[i] + move;
        }
    }
    return pose;
}

// The strongest widening (from 0.8 down), about the outline's centre or the face's, that keeps
// the multicage valid (validatePose) and folds no triangle of the deformer's mesh; the rest
// pose when none does. Says which.
std::vector<cv::Point2f> chooseStretch(const Scene& s, const cv::multicage::Deformer& deformer) {
    using namespace cv::multicage;
    const std::vector<cv::Point2f> rest = s.cage.vertices();
    std::vector<float> centres = {meanOf(s.cage.polygon(s.outline)).x};
    for (const cv::Rect& f : s.faces)
        if (cv::pointPolygonTest(s.cage.polygon(s.outline),
                                 cv::Point2f(f.x + 0.5f * f.width, f.y + 0.5f * f.height),
                                 false) > 0) {
            centres.push_back(f.x + 0.5f * f.width);
            break;
        }
    float strength = 0.8f;
    for (int attempt = 0; attempt < 16; ++attempt, strength *= 0.9f)
        for (const float centre : centres) {
            const std::vector<cv::Point2f> pose = widenPose(s.cage, s.outline, centre, strength);
            if (!validatePose(s.cage, pose) || deformer.foldedTriangles(pose) != 0) continue;
            double most = 0;
            const int begin = s.cage.polygonOffset(s.outline);
            for (int i = begin; i < begin + static_cast<int>(s.cage.polygon(s.outline).size()); ++i)
                most = std::max(most, cv::norm(pose[i] - rest[i]));
            const int nested = nestedCount(s.cage, s.outline);
            const int others = s.cage.polygonCount() - 1 - nested;
            std::cout << "  pose 'stretch': the outline's middle widened by up to "
                      << cvRound(100 * strength) << "% (its vertices moved up to " << cvRound(most)
                      << " px), "
                      << (nested > 0 ? "the " + plural(nested, "polygon") +
                                           " nested in it moved along rigidly"
                                     : std::string("no polygon nested in it to keep rigid"))
                      << (others > 0 ? ", the " + plural(others, "other polygon") + " at rest" : "")
                      << "; the pose folds nothing (0 mesh triangles over)\n";
            return pose;
        }
    std::cerr << "multicage demo: note: every widening tried folds the mesh over; the pose "
                 "'stretch' is the "
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
    const int elsewhere = cage.polygonCount() - 1 - nestedCount(cage, outline);
    const std::string rest =
        elsewhere > 0 ? "; " + plural(elsewhere, "polygon") + " around other objects" : "";
    const std::vector<int> children = childrenOf(cage, outline);
    if (children.empty())
        return words +
               " and nothing nested in it: no face found in it (face detection needs the Debian "
               "package opencv-data) and no region in it more textured than the subject" +
               rest;
    int facePolygons = 0, inFaces = 0, others = 0;
    for (const int child : children) {
        bool face = false;
        for (const cv::Rect& f : faces)
            face = face || cv::pointPolygonTest(
                               cage.polygon(child),
                               cv::Point2f(f.x + 0.5f * f.width, f.y + 0.5f * f.height), false) > 0;
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
    return words + rest;
}

// The demo's scene: the astronaut and the multicage proposed for her, as `multicage propose`
// does by default (facesOnly: as with --protect faces, the face's polygon and what it holds
// only). An outline around the astronaut, then inner polygons protecting her face and, nested
// in it, her eyes (and the textured features inside the outline, where there are any).
// Without the subject model the classic cues find the same; without the face cascades the
// default finds no inner polygon here, and --faces stops with a line naming the package.
Scene astronautScene(bool facesOnly) {
    using namespace cv::multicage;
    Scene s{"astronaut.jpg", decodeEmbeddedImage("astronaut.jpg"), {}, {}, -1, 2};
    std::cout << "multicage demo" << (facesOnly ? " --faces: " : ": ") << s.name << " ("
              << s.image.cols << "x" << s.image.rows << ")\n";
    ProposeParams params;
    if (facesOnly) {
        params.protect = PROTECT_FACES;  // the face only: the rest of the body takes the stretch
        if (faceCascadeFile(params).empty())
            throw Failure(std::string("demo --faces needs OpenCV's face cascades (") +
                          MULTICAGE_DEBIAN_CASCADE_DIR +
                          "): install the Debian package opencv-data");
    }
    const auto t = std::chrono::steady_clock::now();
    s.cage = proposeProtectedMulticage(s.image, params, &s.faces);
    if (facesOnly && s.faces.empty()) throw Failure("no face found in the demo image " + s.name);
    s.outline = chooseOutline(s.cage, s.faces);
    if (s.outline < 0) throw Failure("the proposal found no object in the demo image");
    printProposal(s.cage, msSince(t), describeNesting(s.cage, s.outline, s.faces, "the astronaut"));
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
    Scene s = astronautScene(o.faces);
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
        "--faces: face protection only (as `multicage propose --protect faces`): the outline "
        "and the polygon hugging her face, found by OpenCV's face cascades (Debian package "
        "opencv-data), with her eyes' polygons in it; the body widens and the face stays a "
        "face.");
    cmd->add_option("-o,--output-dir", o->outDir,
                    "Folder for the outputs (default: multicage-demo, with --faces "
                    "multicage-demo-faces)");
    cmd->add_flag("--faces", o->faces, "Protect the face only (see above)");
    addDeformOptions(cmd, o->deform);
    cmd->callback([o] { runDemo(*o); });
}

}  // namespace multicage_cli

// multicage-editor: the GL-free document (edits, undo, validity, script parsing), and a
// scripted session in the real window under Xvfb on llvmpipe.

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/multicage/resize.hpp>
#include <sstream>

#include "document.hpp"
#include "script.hpp"
#include "testing.hpp"

using namespace cv;
using namespace cv::multicage;
using namespace multicage_editor;

namespace {

// Two octagons side by side over a 493x356 image: polygon 0 on the left, 1 on the right.
std::vector<Point2f> octagon(Point2f c, float r) {
    std::vector<Point2f> p;
    for (int k = 0; k < 8; ++k) {
        const double a = -CV_PI / 2 + k * CV_PI / 4;
        p.emplace_back(c.x + r * static_cast<float>(std::cos(a)),
                       c.y + r * static_cast<float>(std::sin(a)));
    }
    return p;
}

Multicage twoOctagons() {
    Multicage cage(Size(493, 356));
    cage.addPolygon(octagon(Point2f(130, 178), 100));
    cage.addPolygon(octagon(Point2f(362, 178), 100));
    cage.orient();
    return cage;
}

// A textured image: every sub-pixel move shows (checkerboard of 12 px squares on a colour ramp).
Mat texturedImage(Size size) {
    Mat img(size, CV_8UC3);
    for (int y = 0; y < size.height; ++y)
        for (int x = 0; x < size.width; ++x) {
            const bool dark = ((x / 12) + (y / 12)) % 2;
            img.at<Vec3b>(y, x) =
                Vec3b(static_cast<uchar>(dark ? 40 : 200), static_cast<uchar>(x * 255 / size.width),
                      static_cast<uchar>(
                          y * 180 / size.height));  // no saturated red: that is the invalid colour
        }
    return img;
}

std::string readText(const std::string& path) {
    std::ifstream f(path);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

/** Pixels within tol of colour (B, G, R). */
int countColour(const Mat& bgr, Vec3b colour, int tol) {
    Mat mask;
    inRange(bgr, Scalar(colour[0] - tol, colour[1] - tol, colour[2] - tol),
            Scalar(colour[0] + tol, colour[1] + tol, colour[2] + tol), mask);
    return countNonZero(mask);
}

double meanAbsDiff(const Mat& a, const Mat& b, Rect r) {
    Mat d;
    absdiff(a(r), b(r), d);
    const Scalar m = mean(d);
    return (m[0] + m[1] + m[2]) / 3;
}

}  // namespace

// ------------------------------------------------------------------ document (GL-free)

TEST(EditorDocument, UndoRedoKeepsAtLeastFiftySteps) {
    Document doc = makeDocument(twoOctagons());
    const Document start = doc;
    History history;
    for (int i = 0; i < 60; ++i) {
        history.push(doc);
        moveVertices(doc, i % 2 ? Mode::Pose : Mode::Rest, {i % 16}, Point2f(0.5f, -0.25f));
    }
    const Document end = doc;
    for (int i = 0; i < 60; ++i) ASSERT_TRUE(history.undo(doc)) << "undo step " << i;
    EXPECT_FALSE(history.undo(doc));
    EXPECT_EQ(positions(doc, Mode::Rest), positions(start, Mode::Rest));
    EXPECT_EQ(doc.pose, start.pose);
    for (int i = 0; i < 60; ++i) ASSERT_TRUE(history.redo(doc));
    EXPECT_EQ(positions(doc, Mode::Rest), positions(end, Mode::Rest));
    EXPECT_EQ(doc.pose, end.pose);
}

TEST(EditorDocument, RestEditKeepsThePoseDisplacement) {
    Document doc = makeDocument(twoOctagons());
    moveVertices(doc, Mode::Pose, {3}, Point2f(10, 5));
    moveVertices(doc, Mode::Rest, {3}, Point2f(-2, 1));
    const std::vector<Point2f> rest = positions(doc, Mode::Rest);
    EXPECT_EQ(doc.pose[3] - rest[3], Point2f(10, 5));
    EXPECT_EQ(doc.pose[4], rest[4]);
}

TEST(EditorDocument, InsertAndDeleteVerticesKeepPoseInStep) {
    Document doc = makeDocument(twoOctagons());
    moveVertices(doc, Mode::Pose, {9}, Point2f(6, 0));  // polygon 1, vertex 1
    const int id = insertVertex(doc, 1, 0, 0.5f);
    EXPECT_EQ(id, 9);
    ASSERT_EQ(doc.cage.vertexCount(), 17);
    ASSERT_EQ(doc.pose.size(), 17u);
    // The new pose vertex is halfway along the posed edge.
    EXPECT_NEAR(doc.pose[9].x, 0.5f * (doc.pose[8].x + doc.pose[10].x), 1e-4);
    EXPECT_TRUE(restValid(doc, nullptr));
    removeVertices(doc, {9, 10});
    EXPECT_EQ(doc.cage.vertexCount(), 15);
    EXPECT_EQ(doc.pose.size(), 15u);
    // Leaving fewer than 3 vertices removes the polygon.
    removeVertices(doc, {0, 1, 2, 3, 4, 5});
    EXPECT_EQ(doc.cage.polygonCount(), 1);
    EXPECT_EQ(doc.pose.size(), 7u);
}

TEST(EditorDocument, CrossingPolygonsAreInvalidWithAReason) {
    Document doc = makeDocument(twoOctagons());
    EXPECT_TRUE(restValid(doc, nullptr));
    moveVertices(doc, Mode::Rest, {0}, Point2f(240, 100));  // into polygon 1
    std::string why;
    EXPECT_FALSE(restValid(doc, &why));
    EXPECT_FALSE(why.empty());
    Document posed = makeDocument(twoOctagons());
    moveVertices(posed, Mode::Pose, {0}, Point2f(240, 100));
    EXPECT_TRUE(restValid(posed, nullptr));
    EXPECT_FALSE(poseValid(posed, &why));
    EXPECT_EQ(why.rfind("pose: ", 0), 0u) << why;
    // A pose may leave the image frame.
    Document outside = makeDocument(twoOctagons());
    moveVertices(outside, Mode::Pose, {0}, Point2f(0, -150));
    EXPECT_TRUE(poseValid(outside, nullptr));
}

TEST(EditorDocument, EmptyAndDegenerateDocumentsDoNotThrow) {
    Document doc = makeDocument(Size(100, 80));
    std::string why;
    EXPECT_TRUE(restValid(doc, &why)) << why;
    EXPECT_TRUE(poseValid(doc, &why)) << why;
    EXPECT_EQ(hitVertex(positions(doc, Mode::Rest), Point2f(5, 5), 3), -1);
    int p, e;
    float t;
    EXPECT_FALSE(hitEdge(doc.cage, doc.pose, Point2f(5, 5), 3, &p, &e, &t));
    EXPECT_EQ(hitPolygon(doc.cage, doc.pose, Point2f(5, 5)), -1);
    EXPECT_EQ(insertVertex(doc, 0, 0, 0.5f), -1);
    removeVertices(doc, {0, 3});
    removePolygon(doc, 2);
    EXPECT_FALSE(orientDocument(doc));
    // A polygon with two vertices (an editor may hold it): invalid, no crash.
    addPolygon(doc, {Point2f(10, 10), Point2f(30, 10)});
    EXPECT_FALSE(restValid(doc, &why));
    EXPECT_FALSE(orientDocument(doc));
    EXPECT_EQ(hitPolygon(doc.cage, doc.pose, Point2f(20, 10)), -1);
}

TEST(EditorDocument, HitTestsFindVertexEdgeAndDeepestPolygon) {
    Document doc = makeDocument(Size(400, 400));
    addPolygon(doc, {Point2f(50, 50), Point2f(350, 50), Point2f(350, 350), Point2f(50, 350)});
    addPolygon(doc, {Point2f(150, 150), Point2f(250, 150), Point2f(250, 250), Point2f(150, 250)});
    EXPECT_EQ(hitVertex(doc.pose, Point2f(352, 49), 4), 1);
    int p = -1, e = -1;
    float t = -1;
    ASSERT_TRUE(hitEdge(doc.cage, doc.pose, Point2f(200, 152), 4, &p, &e, &t));
    EXPECT_EQ(p, 1);
    EXPECT_EQ(e, 0);
    EXPECT_NEAR(t, 0.5f, 1e-5);
    EXPECT_EQ(hitPolygon(doc.cage, doc.pose, Point2f(200, 200)), 1);
    EXPECT_EQ(hitPolygon(doc.cage, doc.pose, Point2f(100, 100)), 0);
}

TEST(EditorDocument, AddPoseStoresAndReplacesByName) {
    Document doc = makeDocument(twoOctagons());
    moveVertices(doc, Mode::Pose, {2}, Point2f(3, 4));
    EXPECT_EQ(addPose(doc, "a"), 0);
    moveVertices(doc, Mode::Pose, {2}, Point2f(3, 4));
    EXPECT_EQ(addPose(doc, "a"), 0);
    EXPECT_EQ(doc.cage.poseCount(), 1);
    EXPECT_EQ(doc.cage.pose(0).vertices, doc.pose);
}

TEST(EditorScript, RejectsUnknownCommandsAndBadArgumentsWithTheLine) {
    EXPECT_EQ(parseScript("# comment\n\nload a.png\nwait 3\nquit\n", "s").size(), 3u);
    try {
        parseScript("load a.png\nfrobnicate\n", "s.txt");
        FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("s.txt:2"), std::string::npos) << e.what();
    }
    EXPECT_THROW(parseScript("drag 1 2\n", "s"), std::runtime_error);
    const std::vector<ScriptCommand> c = parseScript("drag 1 x 2\n", "s");
    EXPECT_THROW(numberArg(c[0], 1), std::runtime_error);
}

// ------------------------------------------------------------------ the window, scripted

namespace {

// The scripted session: a rest edit (vertex 5 by (4, 0)) and a pose edit (vertex 0 by
// (30, -20)), screenshots with and without the cage, the pose saved as "bent" and exported,
// then a crossing rest edit (invalid: screenshot, status, export), undone, and a harmonic export.
std::string sessionScript(const std::string& dir) {
    std::ostringstream s;
    s << "load " << dir << "/in.png " << dir << "/cage.yml\n"
      << "wait 2\n"
         "drag 5 4 0\n"  // rest edit
         "mode pose\n"
         "drag 0 30 -20\n"  // pose edit
         "wait 3\n"
      << "screenshot " << dir << "/pose.png\n"
      << "show-cage 0\nwait 2\n"
      << "screenshot " << dir << "/nocage.png\n"
      << "show-cage 1\n"
         "add-pose bent\n"
      << "save " << dir << "/out.yml\n"
      << "export " << dir << "/mvc.png\n"
      << "status " << dir << "/status.txt\n"
      << "mode rest\n"
         "drag 0 240 100\n"  // into polygon 1: crossing
         "wait 2\n"
      << "screenshot " << dir << "/invalid.png\n"
      << "status " << dir << "/status_invalid.txt\n"
      << "export " << dir << "/invalid_export.png\n"
      << "undo\n"
         "mode pose\n"
         "coords harmonic\n"
         "export-grid-step 2\n"
         "wait 2\n"
      << "export " << dir << "/harmonic.png\n"
      << "quit\n";
    return s.str();
}

// The screenshot shows the image and the cage: not blank, vertex handles (pure yellow, drawn
// only with the overlay) present, and far fewer without the overlay.
void expectScreenshotShowsTheCage(const std::string& dir, const std::string& log) {
    const Mat pose = imread(dir + "/pose.png"), nocage = imread(dir + "/nocage.png");
    ASSERT_FALSE(pose.empty()) << log;
    ASSERT_FALSE(nocage.empty()) << log;
    EXPECT_EQ(pose.size(), Size(1280, 800));
    Scalar m, sd;
    meanStdDev(pose, m, sd);
    EXPECT_GT(sd[0] + sd[1] + sd[2], 30.0) << "the screenshot looks blank";
    const int handles = countColour(pose, Vec3b(0, 255, 255), 8);
    const int handlesHidden = countColour(nocage, Vec3b(0, 255, 255), 8);
    std::printf("handle-coloured pixels: %d with the cage, %d without\n", handles, handlesHidden);
    EXPECT_GT(handles, 16 * 30);  // 16 vertices, 8x8 px each
    EXPECT_GT(handles, 4 * handlesHidden + 100);
}

// An invalid edit is drawn in red, with the reason in the status.
void expectInvalidEditInRedWithReason(const std::string& dir) {
    const Mat pose = imread(dir + "/pose.png"), invalid = imread(dir + "/invalid.png");
    ASSERT_FALSE(invalid.empty());
    const int red = countColour(invalid, Vec3b(40, 40, 255), 30),
              redBefore = countColour(pose, Vec3b(40, 40, 255), 30);
    std::printf("red pixels: %d invalid, %d valid\n", red, redBefore);
    EXPECT_GT(red, 300);
    EXPECT_GT(red, 3 * redBefore);
    const std::string statusInvalid = readText(dir + "/status_invalid.txt");
    EXPECT_NE(statusInvalid.find("rest_valid: 0"), std::string::npos) << statusInvalid;
    EXPECT_EQ(statusInvalid.find("rest_reason: \n"), std::string::npos) << statusInvalid;
    EXPECT_NE(readText(dir + "/status.txt").find("rest_valid: 1"), std::string::npos);
}

// The saved cage round-trips: rest with the rest edit, the pose "bent" with the pose edit.
void expectSavedCageHoldsTheEdits(const std::string& dir, const std::vector<Point2f>& expectedRest,
                                  const std::vector<Point2f>& expectedPose) {
    const Multicage saved = Multicage::load(dir + "/out.yml");
    ASSERT_EQ(saved.polygonCount(), 2);
    const std::vector<Point2f> savedRest = saved.vertices();
    for (int i = 0; i < 16; ++i)
        EXPECT_NEAR(norm(savedRest[i] - expectedRest[i]), 0, 1e-3) << "vertex " << i;
    const int bent = saved.findPose("bent");
    ASSERT_GE(bent, 0);
    for (int i = 0; i < 16; ++i)
        EXPECT_NEAR(norm(saved.pose(bent).vertices[i] - expectedPose[i]), 0, 1e-3)
            << "pose vertex " << i;
    EXPECT_TRUE(saved.validate());
}

// The export is the library's deformation of the saved pose: it moved near the dragged vertex,
// and agrees with a CPU Deformer reference everywhere. While the rest was invalid, export kept
// the last valid binding and pose.
void expectExportIsTheLibrarysDeformation(const std::string& dir, const Mat& image,
                                          const std::vector<Point2f>& expectedPose, Rect near) {
    const Multicage saved = Multicage::load(dir + "/out.yml");
    const Mat mvc = imread(dir + "/mvc.png");
    ASSERT_EQ(mvc.size(), image.size());
    EXPECT_GT(meanAbsDiff(mvc, image, near), 20.0)
        << "the image did not move near the dragged vertex";
    DeformParams cpu;
    cpu.backend = BACKEND_CPU;
    Mat reference;
    Deformer::create(image, saved, cpu)->deform(expectedPose, reference);
    const double agreement = multicage_testing::psnr(mvc, reference);
    std::printf("export vs CPU reference: PSNR %.1f dB\n", agreement);
    EXPECT_GT(agreement, 35.0);
    const Mat invalidExport = imread(dir + "/invalid_export.png");
    ASSERT_EQ(invalidExport.size(), image.size());
    EXPECT_EQ(norm(invalidExport, mvc, NORM_INF), 0.0);
}

// Harmonic coordinates: the inside of polygon 1 depends only on polygon 1, which did not move,
// so it equals the input exactly; near the dragged vertex it moved.
void expectHarmonicExportKeepsTheUnmovedPolygon(const std::string& dir, const Mat& image,
                                                Rect near) {
    const Mat harmonic = imread(dir + "/harmonic.png");
    ASSERT_EQ(harmonic.size(), image.size());
    const Rect inside1(362 - 50, 178 - 50, 100, 100);
    Mat d;
    absdiff(harmonic(inside1), image(inside1), d);
    double maxDiff = 0;
    minMaxLoc(d.reshape(1), nullptr, &maxDiff);
    EXPECT_LE(maxDiff, 1.0) << "pixels inside the unmoved polygon changed";
    EXPECT_GT(meanAbsDiff(harmonic, image, near), 20.0);
}

}  // namespace

namespace {
// Runs the editor with `args` on a virtual display (xvfb-run), its output in dir/LOG; returns
// the editor's own exit status (-1 when it did not end). The status comes from a file the shell
// writes after the editor: xvfb-run now and then fails to remove its temporary folder once the
// editor has ended and then exits 5 itself, which says nothing about the editor.
int runEditor(const std::string& dir, const std::string& args, const std::string& log = "log.txt") {
    const std::string status = dir + "/editor_exit_status.txt";
    std::filesystem::remove(status);
    const std::string cmd =
        "MESA_SHADER_CACHE_DIR='" MULTICAGE_SHADER_CACHE "' '" MULTICAGE_XVFB_RUN
        "' -a -s '-screen 0 1280x800x24' sh -c '\"$0\" \"$@\"; echo $? > " +
        status + "' '" MULTICAGE_EDITOR "' " + args + " > '" + dir + "/" + log + "' 2>&1";
    std::system(cmd.c_str());
    std::ifstream in(status);
    int rc = -1;
    return in >> rc ? rc : -1;
}
}  // namespace

TEST(EditorWindow, ScriptedSessionUnderXvfb) {
    const std::string xvfb = MULTICAGE_XVFB_RUN;
    ASSERT_FALSE(xvfb.empty())
        << "xvfb-run was not found at configure time: install xvfb and xauth "
           "(.ci/deps.sh) and reconfigure; the editor test needs a display";
    const std::string dir = multicage_testing::tempDir("editor_script");
    const Mat image = texturedImage(Size(493, 356));
    const Multicage cage = twoOctagons();
    ASSERT_TRUE(imwrite(dir + "/in.png", image));
    cage.save(dir + "/cage.yml");
    const std::vector<Point2f> rest0 = cage.vertices();

    std::ofstream(dir + "/script.txt") << sessionScript(dir);
    const int rc = runEditor(dir, "--script '" + dir + "/script.txt'");
    const std::string log = readText(dir + "/log.txt");
    ASSERT_EQ(rc, 0) << log;

    ASSERT_NO_FATAL_FAILURE(expectScreenshotShowsTheCage(dir, log));
    ASSERT_NO_FATAL_FAILURE(expectInvalidEditInRedWithReason(dir));
    std::vector<Point2f> expectedRest(rest0.begin(), rest0.begin() + 16);
    expectedRest[5] += Point2f(4, 0);
    std::vector<Point2f> expectedPose = expectedRest;
    expectedPose[0] += Point2f(30, -20);
    ASSERT_NO_FATAL_FAILURE(expectSavedCageHoldsTheEdits(dir, expectedRest, expectedPose));
    const Point2f v0 = expectedPose[0];
    const Rect near(cvRound(v0.x) - 15, cvRound(v0.y) + 5, 30, 30);
    ASSERT_NO_FATAL_FAILURE(expectExportIsTheLibrarysDeformation(dir, image, expectedPose, near));
    expectHarmonicExportKeepsTheUnmovedPolygon(dir, image, near);
}

namespace {
/** The value after "key: " in a status file written by the script's `status` command. */
std::string field(const std::string& statusText, const std::string& key) {
    const std::string status = "\n" + statusText;
    const size_t at = status.find("\n" + key + ":");
    const size_t begin = at == std::string::npos ? std::string::npos : at + key.size() + 2;
    if (begin == std::string::npos) return "<missing " + key + ">";
    const size_t end = status.find('\n', begin);
    std::string v = status.substr(begin, end - begin);
    return v.empty() || v[0] != ' ' ? v : v.substr(1);
}

/** The numbers of a status field, as points. */
std::vector<Point2f> points(const std::string& value) {
    std::istringstream in(value);
    std::vector<Point2f> p;
    for (float x, y; in >> x >> y;) p.emplace_back(x, y);
    return p;
}

/** Whether some point of the list lies within tol of p (mouse positions are whole screen
pixels: at the fitted zoom of about 1.8, image positions come within 0.6 px). */
bool hasPoint(const std::vector<Point2f>& list, Point2f p, float tol = 1.f) {
    for (const Point2f& q : list)
        if (norm(q - p) <= tol) return true;
    return false;
}

// The editor's log; expects its exit status to be `expectedStatus` (a failed script line: 1).
std::string runEditorScript(const std::string& dir, const std::string& script,
                            const std::string& options = "", int expectedStatus = 0) {
    std::ofstream(dir + "/script.txt") << script;
    const int rc = runEditor(dir, options + " --script '" + dir + "/script.txt'");
    const std::string log = readText(dir + "/log.txt");
    EXPECT_EQ(rc, expectedStatus) << log;
    return log;
}
}  // namespace

// Mouse and keyboard through the canvas code (synthetic input in place of GLFW's): create a
// polygon by clicking, close it on its first vertex or with Enter, cancel with Esc, insert a
// vertex by double-clicking an edge, box-select, Delete, Ctrl+Z, Ctrl-drag a polygon, drag a
// vertex, Tab to pose mode and drag there.
TEST(EditorWindow, MouseAndKeyboardEditing) {
    ASSERT_FALSE(std::string(MULTICAGE_XVFB_RUN).empty())
        << "xvfb-run not found: install xvfb (.ci/deps.sh)";
    const std::string dir = multicage_testing::tempDir("editor_mouse");
    ASSERT_TRUE(imwrite(dir + "/in.png", texturedImage(Size(493, 356))));
    std::ostringstream s;
    const auto status = [&](const std::string& n) {
        s << "status " << dir << "/" << n << ".txt\n";
    };
    s << "load " << dir << "/in.png\n"
      << "click 100 100\nclick 200 100\nclick 200 200\nclick 100 200\nclick 100 100\n";
    status("created");
    s << "double-click 150 100\n";
    status("inserted");
    s << "mouse-drag 90 90 160 110\n";
    status("boxed");
    s << "key delete\n";
    status("deleted");
    s << "key z ctrl\n";
    status("undone");
    s << "mouse-drag 150 150 170 160 ctrl\nkey escape\n";
    status("moved");
    s << "mouse-drag 120 110 125 110\n";
    status("dragged");
    s << "click 300 250\nclick 350 250\nkey escape\n";
    status("cancelled");
    s << "click 300 250\nclick 400 250\nclick 400 300\nkey enter\n";
    status("entered");
    s << "key tab\nmouse-drag 220 210 230 220\n";
    status("posed");
    s << "quit\n";
    const std::string log = runEditorScript(dir, s.str());
    const auto st = [&](const std::string& n) { return readText(dir + "/" + n + ".txt"); };

    EXPECT_EQ(field(st("created"), "polygons"), "1") << log;
    EXPECT_EQ(field(st("created"), "vertices"), "4");
    EXPECT_EQ(field(st("created"), "rest_valid"), "1");
    EXPECT_EQ(field(st("inserted"), "vertices"), "5");
    EXPECT_TRUE(hasPoint(points(field(st("inserted"), "rest")), Point2f(150, 100)))
        << field(st("inserted"), "rest");
    EXPECT_EQ(field(st("boxed"), "selection").size(), 3u)
        << "two vertices in the box: " << field(st("boxed"), "selection");
    EXPECT_EQ(field(st("deleted"), "vertices"), "3");
    EXPECT_EQ(field(st("undone"), "vertices"), "5");
    // Ctrl-drag moved every vertex by (20, 10).
    const std::vector<Point2f> undone = points(field(st("undone"), "rest")),
                               moved = points(field(st("moved"), "rest"));
    ASSERT_EQ(moved.size(), 5u);
    ASSERT_EQ(undone.size(), 5u);
    for (size_t i = 0; i < 5; ++i)
        EXPECT_LE(norm(moved[i] - undone[i] - Point2f(20, 10)), 1.0) << "vertex " << i;
    const std::vector<Point2f> dragged = points(field(st("dragged"), "rest"));
    ASSERT_EQ(dragged.size(), 5u);
    EXPECT_LE(norm(dragged[0] - moved[0] - Point2f(5, 0)), 1.0);
    EXPECT_EQ(dragged[1], moved[1]);
    EXPECT_EQ(field(st("cancelled"), "polygons"), "1");
    EXPECT_EQ(field(st("entered"), "polygons"), "2");
    EXPECT_EQ(field(st("entered"), "vertices"), "8");
    EXPECT_EQ(field(st("posed"), "mode"), "pose");
    EXPECT_EQ(field(st("posed"), "rest"), field(st("entered"), "rest"))
        << "a pose drag moved the rest";
    EXPECT_TRUE(hasPoint(points(field(st("posed"), "shown_pose")), Point2f(230, 220), 1.5f))
        << field(st("posed"), "shown_pose");
}

// Issue 9 item 3: the editor adds keyframes from the current pose and plays them.
TEST(EditorWindow, KeyframesFromThePoseAndPlayback) {
    const std::string xvfb = MULTICAGE_XVFB_RUN;
    ASSERT_FALSE(xvfb.empty()) << "xvfb-run was not found at configure time (.ci/deps.sh)";
    const std::string dir = multicage_testing::tempDir("editor_keyframes");
    ASSERT_TRUE(imwrite(dir + "/in.png", texturedImage(Size(493, 356))));
    const Multicage cage = twoOctagons();
    cage.save(dir + "/cage.yml");
    std::ofstream(dir + "/script.txt") << "load " << dir << "/in.png " << dir << "/cage.yml\n"
                                       << "mode pose\n"
                                          "add-keyframe 0\n"  // the rest pose at t = 0
                                          "drag 0 30 -20\n"
                                          "add-keyframe 1.5\n"  // the dragged pose at t = 1.5
                                          "play 1\n"
                                          "wait 20\n"
                                       << "status " << dir << "/playing.txt\n"
                                       << "play 0\n"
                                       << "status " << dir << "/stopped.txt\n"
                                       << "save " << dir << "/keys.yml\n"
                                       << "quit\n";
    ASSERT_EQ(runEditor(dir, "--script '" + dir + "/script.txt'"), 0) << readText(dir + "/log.txt");
    const std::string playing = readText(dir + "/playing.txt");
    EXPECT_EQ(field(playing, "playing"), "1") << playing;
    const double playhead = std::stod(field(playing, "playhead"));
    EXPECT_GT(playhead, 0.0);  // 20 frames of playback moved the playhead
    EXPECT_LT(playhead, 3.0);  // within the looped period (1.5 s x 2 keyframes / 1)
    EXPECT_EQ(field(readText(dir + "/stopped.txt"), "playing"), "0");

    const Multicage keys = Multicage::load(dir + "/keys.yml");
    ASSERT_EQ(keys.poseCount(), 2);
    std::vector<double> times = {keys.pose(0).time, keys.pose(1).time};
    std::sort(times.begin(), times.end());
    EXPECT_EQ(times[0], 0.0);
    EXPECT_EQ(times[1], 1.5);
    const int late = keys.pose(0).time == 1.5 ? 0 : 1;
    std::vector<Point2f> rest = cage.vertices();
    EXPECT_NEAR(keys.pose(late).vertices[0].x, rest[0].x + 30, 1e-3);
    EXPECT_NEAR(keys.pose(late).vertices[0].y, rest[0].y - 20, 1e-3);
    EXPECT_EQ(keys.pose(1 - late).vertices[0], rest[0]);
}

// Issue 13 item 1: Rest mode showed the image with red and blue swapped (its texture was
// converted BGR->RGBA twice). Four quadrants of distinct, non-grey colours: each must appear
// on the canvas in its own colour, and not with red and blue swapped, in both modes.
TEST(EditorWindow, CanvasShowsTheImageColoursInRestAndPoseMode) {
    ASSERT_FALSE(std::string(MULTICAGE_XVFB_RUN).empty())
        << "xvfb-run not found: install xvfb (.ci/deps.sh)";
    const std::string dir = multicage_testing::tempDir("editor_colours");
    const Size size(493, 356);
    const std::vector<Vec3b> colours = {Vec3b(40, 140, 230), Vec3b(220, 120, 30),
                                        Vec3b(60, 200, 120),
                                        Vec3b(200, 40, 150)};  // BGR: orange, blue, green, purple
    Mat image(size, CV_8UC3);
    for (int q = 0; q < 4; ++q)
        image(Rect((q % 2) * size.width / 2, (q / 2) * size.height / 2, size.width / 2 + 1,
                   size.height / 2 + 1) &
              Rect(Point(), size))
            .setTo(Scalar(colours[q][0], colours[q][1], colours[q][2]));
    ASSERT_TRUE(imwrite(dir + "/in.png", image));
    twoOctagons().save(dir + "/cage.yml");
    runEditorScript(dir, "load " + dir + "/in.png " + dir + "/cage.yml\n" +
                             "show-cage 0\nwait 2\n" + "screenshot " + dir + "/rest.png\n" +
                             "mode pose\nwait 3\n" + "screenshot " + dir + "/pose.png\nquit\n");
    for (const std::string mode : {"rest", "pose"}) {
        const Mat shot = imread(dir + "/" + mode + ".png");
        ASSERT_FALSE(shot.empty()) << mode;
        // The canvas shows the image at about 1.8x: each quadrant covers well over 20k pixels.
        for (const Vec3b& c : colours) {
            const int right = countColour(shot, c, 12),
                      swapped = countColour(shot, Vec3b(c[2], c[1], c[0]), 12);
            std::printf(
                "%s mode, colour (%d %d %d): %d pixels right, %d with red and blue swapped\n",
                mode.c_str(), c[0], c[1], c[2], right, swapped);
            EXPECT_GT(right, 20000) << mode << " mode";
            EXPECT_LT(swapped, right / 100 + 10) << mode << " mode";
        }
    }
}

// Issue 16: the editor's Propose protects faces (as propose --protect all): on messi5.jpg the
// saved cage has an inner polygon around the face the frontal cascade finds at 227,94.
TEST(EditorWindow, ProposeProtectsTheFace) {
    ASSERT_FALSE(std::string(MULTICAGE_XVFB_RUN).empty())
        << "xvfb-run not found: install xvfb (.ci/deps.sh)";
    if (faceCascadeFile().empty()) GTEST_SKIP() << "opencv-data is not installed";
    const std::string dir = multicage_testing::tempDir("editor_propose_faces");
    std::ostringstream s;
    s << "load " << multicage_testing::samplePath("messi5.jpg") << "\n"
      << "propose\nwait 2\n"
      << "save " << dir << "/cage.yml\n"
      << "quit\n";
    const std::string log = runEditorScript(dir, s.str());
    // Issue 39 item 7: the message says which subject cue ran (the default's: the model when
    // one is found, else the classic segmentation).
    const std::string model = segmenterModelFile();
    EXPECT_NE(log.find(model.empty() ? std::string("(classic segmentation: no subject model")
                                     : "(subject model " + model.substr(model.rfind('/') + 1)),
              std::string::npos)
        << log;
    const Multicage cage = Multicage::load(dir + "/cage.yml");
    std::string why;
    ASSERT_TRUE(cage.validate(&why)) << why << "\n" << log;
    EXPECT_EQ(cage.imageSize(), Size(548, 342));
    // The editor binds and saves with the coordinates the proposal asks for, as `multicage
    // propose` writes them (it bound and saved mean value coordinates, in which the outline's
    // motion leaks into the face).
    EXPECT_EQ(cage.coordinates(), LOCAL_MEAN_VALUE) << log;
    // The face's box (the frontal cascade's 38x38 at 227,94 at full size; the search works on
    // a smaller copy, so a few pixels either way): inside an inner polygon, and the outline
    // around that.
    const Rect face(229, 96, 34, 34);
    int inner = -1;
    for (int p = 0; p < cage.polygonCount(); ++p) {
        bool all = true;
        for (Point2f c : {Point2f(face.x, face.y), Point2f(face.br().x, face.y),
                          Point2f(face.br().x, face.br().y), Point2f(face.x, face.br().y)})
            all &= pointPolygonTest(cage.polygon(p), c, false) > 0;
        if (all && cage.depth(p) >= 2 && (inner < 0 || cage.depth(p) < cage.depth(inner)))
            inner = p;
    }
    ASSERT_GE(inner, 0) << "no inner polygon holds the face\n" << log;
    EXPECT_EQ(cage.depth(inner), 2);
    // It hugs the face: a polygon around the whole body would hold the face too.
    EXPECT_LE(std::abs(contourArea(cage.polygon(inner))), 6.0 * face.area());
}

namespace {
/** The canvas region where the image point rectangle (-0.5,-0.5)-(size - 0.5) is drawn, from
the status's view (zoom, pan) and the panel width, shrunk by `inset` screen pixels. */
Rect onScreen(const std::string& status, Size size, int inset) {
    std::istringstream view(field(status, "view"));
    float zoom = 0, panX = 0, panY = 0;
    view >> zoom >> panX >> panY;
    const float x0 = 340.f + panX, y0 = panY;  // kPanelWidth: the canvas starts right of it
    return Rect(cvRound(x0) + inset, cvRound(y0) + inset, cvRound(zoom * size.width) - 2 * inset,
                cvRound(zoom * size.height) - 2 * inset);
}

Size sizeField(const std::string& status, const std::string& key) {
    std::istringstream in(field(status, key));
    Size s;
    in >> s.width >> s.height;
    return s;
}
}  // namespace

// Issue 25 item 7: resize mode. `resize W H` and drags of the frame's right and bottom edges
// set the size; the view shows the GLDeformer's render of the library's resize pose on the
// editor's binding, at that size; export saves the resized image at full resolution and says
// where; a size beyond the limit fails the script with one line.
TEST(EditorWindow, ResizeModeFollowsTheFrameAndSavesTheNewSize) {
    ASSERT_FALSE(std::string(MULTICAGE_XVFB_RUN).empty())
        << "xvfb-run not found: install xvfb (.ci/deps.sh)";
    const std::string dir = multicage_testing::tempDir("editor_resize");
    Mat image = texturedImage(Size(493, 356));
    GaussianBlur(image, image, Size(0, 0), 1.5);  // the screen comparison resamples it
    ASSERT_TRUE(imwrite(dir + "/in.png", image));
    const Multicage cage = twoOctagons();
    cage.save(dir + "/cage.yml");
    std::ostringstream s;
    s << "load " << dir << "/in.png " << dir << "/cage.yml\n"
      << "show-cage 0\nresize 740 356\nwait 3\n"
      << "status " << dir << "/wide.txt\n"
      << "screenshot " << dir << "/wide.png\n"
      << "export " << dir << "/wide_out.png\n"
      << "mouse-drag 739.5 178 600 178\n"  // the right edge, in to x = 600
      << "mouse-drag 300 355.5 300 420\n"  // the bottom edge, out to y = 420
      << "wait 2\n"
      << "status " << dir << "/dragged.txt\n"
      << "export " << dir << "/dragged_out.png\n"
      << "quit\n";
    const std::string log = runEditorScript(dir, s.str());
    const std::string wide = readText(dir + "/wide.txt"), dragged = readText(dir + "/dragged.txt");
    EXPECT_EQ(field(wide, "mode"), "resize") << log;
    EXPECT_EQ(sizeField(wide, "resize"), Size(740, 356));
    EXPECT_EQ(sizeField(wide, "output"), Size(740, 356)) << "the GLDeformer renders the new size";

    // The live pose is the library's resize pose on the editor's binding.
    const int step = std::stoi(field(wide, "grid_step"));
    const Binding live = bind(cage, MEAN_VALUE, step);
    const std::vector<Point2f> expected = resizePose(cage, live, Size(740, 356));
    const std::vector<Point2f> shown = points(field(wide, "resize_pose"));
    ASSERT_EQ(shown.size(), expected.size());
    for (size_t k = 0; k < shown.size(); ++k)
        EXPECT_LE(norm(shown[k] - expected[k]), 1e-3) << "vertex " << k;

    // The canvas shows that render: closer to the deformation of that pose than to the plain
    // stretch (which widens the octagons 1.5x where the resize pose keeps them).
    const Mat shot = imread(dir + "/wide.png");
    ASSERT_FALSE(shot.empty());
    const Rect region = onScreen(wide, Size(740, 356), 3);
    ASSERT_TRUE((region & Rect(Point(), shot.size())) == region) << region;
    DeformParams cpu;
    cpu.backend = BACKEND_CPU;
    Mat liveRef, stretched, a, b;
    Deformer::create(image, live, cpu)->deform(expected, liveRef);
    cv::resize(image, stretched, Size(740, 356));
    cv::resize(liveRef, a, Size(region.width + 6, region.height + 6), 0, 0, INTER_AREA);
    cv::resize(stretched, b, Size(region.width + 6, region.height + 6), 0, 0, INTER_AREA);
    const Rect inner(3, 3, region.width, region.height);
    const double toPose = meanAbsDiff(shot(region), a(inner), Rect(Point(), region.size())),
                 toStretch = meanAbsDiff(shot(region), b(inner), Rect(Point(), region.size()));
    std::printf(
        "canvas against the resize pose's render: %.1f, against cv::resize: %.1f (mean abs diff)\n",
        toPose, toStretch);
    EXPECT_LT(toPose, 0.5 * toStretch);

    // Export: the full-resolution resized image, as the library makes it, and where it went.
    const Mat out = imread(dir + "/wide_out.png");
    ASSERT_EQ(out.size(), Size(740, 356)) << log;
    Ptr<Deformer> d = Deformer::create(image, cage, cpu);
    Mat reference;
    d->deform(resizePose(cage, d->binding(), Size(740, 356)), reference);
    const double p = multicage_testing::psnr(out, reference);
    std::printf("saved resized image against the library's: %.1f dB\n", p);
    EXPECT_GE(p, 40.0);
    EXPECT_NE(log.find("saved the 740x356 resized image to " + dir + "/wide_out.png"),
              std::string::npos)
        << log;

    // The drags moved the right edge to x = 600 and the bottom one to y = 420 (mouse positions
    // are whole screen pixels at a zoom near 1: within a pixel).
    const Size afterDrag = sizeField(dragged, "resize");
    EXPECT_NEAR(afterDrag.width, 600, 1) << log;
    EXPECT_NEAR(afterDrag.height, 420, 1);
    EXPECT_EQ(sizeField(dragged, "output"), afterDrag);
    EXPECT_EQ(imread(dir + "/dragged_out.png").size(), afterDrag);

    // Beyond 8x the image: the script fails with one line, and no output.
    std::ofstream(dir + "/bad.txt") << "load " << dir << "/in.png " << dir << "/cage.yml\n"
                                    << "resize 5000 356\nexport " << dir << "/bad.png\nquit\n";
    EXPECT_EQ(runEditor(dir, "--script '" + dir + "/bad.txt'", "bad_log.txt"), 1);
    const std::string badLog = readText(dir + "/bad_log.txt");
    EXPECT_NE(badLog.find("script line 2 (resize)"), std::string::npos) << badLog;
    EXPECT_NE(badLog.find("8x"), std::string::npos) << badLog;
    EXPECT_FALSE(std::ifstream(dir + "/bad.png").good());
}

// Issue 40 item 6: after a resize to a wider or taller size, and after the window is resized,
// the whole image and the whole resized frame are inside the canvas.
TEST(EditorWindow, TheViewRefitsAfterAResizeAndAWindowResize) {
    ASSERT_FALSE(std::string(MULTICAGE_XVFB_RUN).empty())
        << "xvfb-run not found: install xvfb (.ci/deps.sh)";
    const std::string dir = multicage_testing::tempDir("editor_refit");
    ASSERT_TRUE(imwrite(dir + "/in.png", texturedImage(Size(493, 356))));
    twoOctagons().save(dir + "/cage.yml");
    std::ostringstream s;
    s << "load " << dir << "/in.png " << dir << "/cage.yml\n"
      << "resize 910 512\nwait 2\nstatus " << dir << "/wide.txt\n"
      << "window 800 500\nwait 3\nstatus " << dir << "/small_window.txt\n"
      << "resize 493 700\nwait 2\nstatus " << dir << "/tall.txt\n"
      << "quit\n";
    const std::string log = runEditorScript(dir, s.str());
    for (const char* name : {"wide", "small_window", "tall"}) {
        const std::string status = readText(dir + "/" + name + ".txt");
        float zoom = 0;
        Point2f pan;
        std::istringstream(field(status, "view")) >> zoom >> pan.x >> pan.y;
        const std::vector<Point2f> canvas = points(field(status, "canvas"));
        ASSERT_EQ(canvas.size(), 1u) << name << "\n" << status << log;
        const Size resized = sizeField(status, "resize");
        // screen = origin + zoom * (p + 0.5) + pan: the frame spans 0 .. zoom * size
        const float w = zoom * std::max(493, resized.width),
                    h = zoom * std::max(356, resized.height);
        EXPECT_GT(zoom, 0.f) << name;
        EXPECT_GE(pan.x, 0.f) << name << "\n" << status;
        EXPECT_GE(pan.y, 0.f) << name << "\n" << status;
        EXPECT_LE(pan.x + w, canvas[0].x + 0.5f) << name << "\n" << status;
        EXPECT_LE(pan.y + h, canvas[0].y + 0.5f) << name << "\n" << status;
        if (std::string(name) == "small_window") EXPECT_LT(canvas[0].x, 800.f) << status;
    }
}

// Issue 40 item 3: Save refuses a cage whose pose crosses (a file opened with one, as `multicage
// deform` refuses it), naming the pose and the polygons; --allow-invalid saves it.
TEST(EditorWindow, SaveRefusesACrossingPoseUnlessAllowed) {
    ASSERT_FALSE(std::string(MULTICAGE_XVFB_RUN).empty())
        << "xvfb-run not found: install xvfb (.ci/deps.sh)";
    const std::string dir = multicage_testing::tempDir("editor_crossing");
    ASSERT_TRUE(imwrite(dir + "/in.png", texturedImage(Size(493, 356))));
    Multicage cage = twoOctagons();
    std::vector<Point2f> pose = cage.vertices();
    pose.resize(cage.vertexCount());
    for (int i = 8; i < 16; ++i) pose[i].x -= 150;  // the right octagon onto the left one
    cage.addPose("crossing", pose);
    cage.save(dir + "/cage.yml");
    const std::string script =
        "load " + dir + "/in.png " + dir + "/cage.yml\nsave " + dir + "/out.yml\nquit\n";
    const std::string log = runEditorScript(dir, script, "", 1);
    EXPECT_NE(log.find("not saved: pose 'crossing' is invalid: posed: polygon"), std::string::npos)
        << log;
    EXPECT_NE(log.find("--allow-invalid"), std::string::npos) << log;
    EXPECT_FALSE(std::filesystem::exists(dir + "/out.yml"));
    runEditorScript(dir, script, "--allow-invalid");
    ASSERT_TRUE(std::filesystem::exists(dir + "/out.yml"));
    EXPECT_EQ(Multicage::load(dir + "/out.yml").pose(0).vertices, pose);
}

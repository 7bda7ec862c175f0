// Cage files: round trips, scaling, and errors that name the field.
#include <filesystem>
#include <fstream>

#include "testing.hpp"

using namespace cv;
using namespace cv::multicage;
namespace fs = std::filesystem;

namespace {
Multicage sampleCage() {
    Multicage cage = multicage_testing::butterflyCage(true);
    std::vector<Point2f> pose = cage.vertices();
    pose.resize(cage.vertexCount());
    for (Point2f& p : pose) p = p * 1.01f + Point2f(0.123456789f, -1.0f / 3.0f);
    cage.addPose("stretch", pose, 1.5);
    cage.addPose("rest", cage.vertices());
    cage.setCoordinates(1);
    return cage;
}
void writeText(const std::string& path, const std::string& text) {
    std::ofstream(path) << text;
}
std::string loadError(const std::string& path) {
    try {
        Multicage::load(path);
    } catch (const cv::Exception& e) {
        return e.err;
    }
    ADD_FAILURE() << path << " loaded without error";
    return {};
}
const char* kHeader = "%YAML:1.0\n---\n";
}  // namespace

TEST(CageFile, RoundTripIsExactInYamlAndJson) {
    const std::string dir = multicage_testing::tempDir("roundtrip");
    const Multicage cage = sampleCage();
    for (const char* name : {"/cage.yml", "/cage.json", "/cage.yaml"}) {
        cage.save(dir + name);
        const Multicage back = Multicage::load(dir + name);
        EXPECT_EQ(back.imageSize(), cage.imageSize());
        EXPECT_EQ(back.coordinates(), 1) << name;
        ASSERT_EQ(back.polygonCount(), cage.polygonCount());
        for (int p = 0; p < cage.polygonCount(); ++p)
            EXPECT_EQ(back.polygon(p), cage.polygon(p)) << name;
        ASSERT_EQ(back.poseCount(), 2);
        EXPECT_EQ(back.pose(0).name, "stretch");
        EXPECT_EQ(back.pose(0).time, 1.5);
        EXPECT_EQ(back.pose(0).vertices, cage.pose(0).vertices) << name;  // bit for bit
    }
    // No temporary file is left behind.
    int files = 0;
    for (const auto& entry : fs::directory_iterator(dir)) ++files, (void)entry;
    EXPECT_EQ(files, 3);
}

TEST(CageFile, TheClipFrameIsKeptAndLeftOutWhenZero) {
    const std::string dir = multicage_testing::tempDir("clipframe");
    Multicage cage = sampleCage();
    EXPECT_EQ(cage.clipFrame(), 0);
    EXPECT_THROW(cage.setClipFrame(-1), cv::Exception);
    for (const char* name : {"/first.yml", "/first.json"}) {
        cage.save(dir + name);
        std::ifstream in(dir + name);
        const std::string text((std::istreambuf_iterator<char>(in)), {});
        EXPECT_EQ(text.find("clip_frame"), std::string::npos) << name << ": " << text;
    }
    cage.setClipFrame(120);
    for (const char* name : {"/later.yml", "/later.json"}) {
        cage.save(dir + name);
        const Multicage back = Multicage::load(dir + name);
        EXPECT_EQ(back.clipFrame(), 120) << name;
        EXPECT_EQ(back.scaled(Size(100, 80)).clipFrame(), 120) << name;
        EXPECT_EQ(back.posed(back.vertices()).clipFrame(), 120) << name;
        EXPECT_EQ(back.polygon(0), cage.polygon(0)) << name;
    }
}

TEST(CageFile, AppliedToAnotherSizeIsScaled) {
    const Multicage cage = sampleCage();
    const Multicage big = cage.scaled(Size(986, 712));
    for (int i = 0; i < cage.vertexCount(); ++i) {
        const Point2f a = cage.vertices()[i], b = big.vertices()[i];
        EXPECT_NEAR(b.x, (a.x + 0.5f) * 2 - 0.5f, 1e-3);
        EXPECT_NEAR(b.y, (a.y + 0.5f) * 2 - 0.5f, 1e-3);
        const Point2f pa = cage.pose(0).vertices[i], pb = big.pose(0).vertices[i];
        EXPECT_NEAR(pb.x, (pa.x + 0.5f) * 2 - 0.5f, 1e-3);
    }
    EXPECT_TRUE(big.validate());
}

TEST(CageFile, MalformedFilesNameTheField) {
    const std::string dir = multicage_testing::tempDir("malformed");
    struct Case {
        const char* body;
        const char* expected;
    } cases[] = {
        {"polygons:\n  - [ 1, 1, 5, 1, 5, 5 ]\n", "image_size: missing"},
        {"image_size: [ 10 ]\npolygons: []\n", "image_size: must be [ width, height ]"},
        {"image_size: [ 10, 10 ]\n", "polygons: missing"},
        {"image_size: [ 10, 10 ]\ncoordinates: wachspress\npolygons: []\n",
         "coordinates: must be mean_value, harmonic or local_mean_value"},
        {"image_size: [ 10, 10 ]\npolygons:\n  - [ 1, 1, 5, 1, 5, 5 ]\n  - [ 1, 7, 2, 7, 2 ]\n",
         "polygons[1]: odd number of coordinates (5)"},
        {"image_size: [ 10, 10 ]\npolygons:\n  - [ 1, 1, 5, one, 5, 5 ]\n",
         "polygons[0]: coordinate 3 (of vertex 1) is not a number"},
        {"image_size: [ 10, 10 ]\npolygons:\n  - [ 1, 1, 5, 1 ]\n",
         "polygons[0]: fewer than 3 vertices (2)"},
        {"image_size: [ 10, 10 ]\npolygons:\n  - [ 1, 1, 5, 1, 5, 5 ]\nposes:\n"
         "  - { name: up, vertices: [ 1, 1, 5, 1 ] }\n",
         "poses[0] (\"up\").vertices: has 2 vertices, the polygons have 3"},
        {"image_size: [ 10, 10 ]\npolygons:\n  - [ 1, 1, 5, 1, 5, 5 ]\nposes:\n"
         "  - { name: up, time: soon, vertices: [ 1, 1, 5, 1, 5, 5 ] }\n",
         "poses[0].time: is not a number"},
        {"image_size: [ 10, 10 ]\npolygons:\n  - [ 1, 1, 5, 1, 5, 5 ]\n  - [ 1, 1, 5, 1, 5, 5 ]\n",
         "polygon 1 crosses polygon 0"},
        {"image_size: [ 10, 10 ]\npolygons: [ [ 1, 1, 5, 1, 5, 5 ]\n", "not valid YAML/JSON"},
        {"image_size: [ 10, 10 ]\nclip_frame: -3\npolygons: []\n", "clip_frame: must be a whole"},
        {"image_size: [ 10, 10 ]\nclip_frame: 2.5\npolygons: []\n", "clip_frame: must be a whole"},
    };
    int i = 0;
    for (const Case& c : cases) {
        const std::string path = dir + "/case" + std::to_string(i++) + ".yml";
        writeText(path, std::string(kHeader) + c.body);
        const std::string err = loadError(path);
        EXPECT_NE(err.find(c.expected), std::string::npos)
            << "got: " << err << "\nwanted: " << c.expected;
        EXPECT_NE(err.find(path), std::string::npos) << "the message names the file: " << err;
    }
    EXPECT_NE(loadError(dir + "/absent.yml").find("cannot be opened"), std::string::npos);
    EXPECT_NE(loadError(dir + "/cage.txt").find(".yml, .yaml or .json"), std::string::npos);
}

TEST(CageFile, FailedSaveLeavesNoFile) {
    const Multicage cage = sampleCage();
    EXPECT_THROW(cage.save("/nonexistent-dir/cage.yml"), cv::Exception);
    const std::string dir = multicage_testing::tempDir("failedsave");
    const std::string path = dir + "/cage.yml";
    cage.save(path);
    const auto before = fs::file_size(path);
    EXPECT_THROW(cage.save(dir + "/cage.png"), cv::Exception);
    EXPECT_EQ(fs::file_size(path), before);
    EXPECT_FALSE(fs::exists(dir + "/cage.png"));
}

// Issue 13 item 14: a valid YAML cage file without OpenCV's "%YAML:1.0" line was refused as
// "Unsupported file storage format".
TEST(CageFile, YamlWithoutTheOpenCvHeaderLoads) {
    const std::string dir = multicage_testing::tempDir("cage_no_header");
    const std::string body =
        "image_size: [ 493, 356 ]\npolygons:\n  - [ 100, 100, 200, 100, 200, 200 ]\n"
        "poses:\n  - { name: up, time: 0, vertices: [ 100, 90, 200, 90, 200, 190 ] }\n";
    std::ofstream(dir + "/plain.yml") << body;
    std::ofstream(dir + "/dashes.yaml") << "---\n" << body;
    for (const char* name : {"plain.yml", "dashes.yaml"}) {
        const Multicage cage = Multicage::load(dir + "/" + name);
        EXPECT_EQ(cage.imageSize(), Size(493, 356)) << name;
        EXPECT_EQ(cage.polygonCount(), 1) << name;
        ASSERT_EQ(cage.poseCount(), 1) << name;
        EXPECT_EQ(cage.pose(0).vertices[0], Point2f(100, 90)) << name;
    }
    // Errors still name the line of the user's file (line 3 here, not 4).
    std::ofstream(dir + "/bad.yml") << "image_size: [ 493, 356 ]\npolygons:\n   - [ 1, 2\n  - ]\n";
    try {
        Multicage::load(dir + "/bad.yml");
        ADD_FAILURE() << "a malformed file loaded";
    } catch (const cv::Exception& e) {
        std::printf("%s\n", e.err.c_str());
        EXPECT_NE(e.err.find("bad.yml"), std::string::npos) << e.err;
    }
}

// Issue 22 item 1: every pose name that loads (or that addPose takes) saves back exactly, in
// YAML and JSON, with its time and vertices; the names a cage file cannot keep are refused
// on load and by addPose/setPose, with one line that shows the name.
TEST(CageFile, EveryNameThatLoadsSavesBackExactly) {
    const std::string dir = multicage_testing::tempDir("cage_names");
    Multicage cage = multicage_testing::butterflyCage(true);
    cage.setCoordinates(HARMONIC);
    std::vector<Point2f> pose = cage.vertices();
    pose.resize(cage.vertexCount());
    // Names that look like other YAML/JSON values or hold its punctuation, kept as text.
    const std::string names[] = {"",
                                 "p",
                                 "a b",
                                 "a  b",
                                 "p:q",
                                 "a: b",
                                 "x#y",
                                 "#x",
                                 "-x",
                                 "x,y",
                                 "1",
                                 "1.5",
                                 "true",
                                 "null",
                                 "~",
                                 ".nan",
                                 "a\"b",
                                 "a'b",
                                 "a\\b",
                                 "x]",
                                 "x}",
                                 "\xc3\xa9t\xc3\xa9",
                                 "\xc2\xa0nbsp\xc2\xa0"};
    const double times[] = {0.0, 0.1, -2.5, 1e-300, 1e300, 1.0 / 3.0};
    int k = 0;
    for (const std::string& name : names) {
        std::vector<Point2f> moved = pose;
        moved[k % moved.size()] += Point2f(0.1f * k, -1.0f / (k + 3));
        cage.addPose(name, moved, times[k % 6]);
        ++k;
    }
    for (const char* file : {"/names.yml", "/names.json"}) {
        cage.save(dir + file);
        const Multicage back = Multicage::load(dir + file);
        EXPECT_EQ(back.coordinates(), HARMONIC) << file;
        ASSERT_EQ(back.poseCount(), cage.poseCount()) << file;
        for (int i = 0; i < cage.poseCount(); ++i) {
            EXPECT_EQ(back.pose(i).name, cage.pose(i).name) << file;
            EXPECT_EQ(back.pose(i).time, cage.pose(i).time) << file << " " << cage.pose(i).name;
            EXPECT_EQ(back.pose(i).vertices, cage.pose(i).vertices)
                << file << " " << cage.pose(i).name;
        }
    }
}

TEST(CageFile, NamesACageFileCannotKeepAreRefused) {
    const std::string dir = multicage_testing::tempDir("cage_bad_names");
    Multicage cage = multicage_testing::butterflyCage(true);
    std::vector<Point2f> pose = cage.vertices();
    pose.resize(cage.vertexCount());
    const std::pair<std::string, std::string> refused[] = {
        {"p ", "\"p \" starts or ends with a space"},
        {" p", "\" p\" starts or ends with a space"},
        {" ", "\" \" starts or ends with a space"},
        {"a\tb", "\"a\\x09b\" contains a control character (0x09)"},
        {"a\nb", "\"a\\x0Ab\" contains a control character (0x0A)"},
        {"a\x7f", "\"a\\x7F\" contains a control character (0x7F)"},
        {"[x", "\"[x\" starts with ["},
        {"{x", "\"{x\" starts with {"},
        {"\\[x", "\"\\[x\" starts with \\"},
        {"'x'", "\"'x'\" starts with '"},
        {"\"x\"", "\"\"x\"\" starts with \""},
    };
    cage.addPose("ok", pose);
    for (const auto& [name, why] : refused) {
        EXPECT_EQ(poseNameProblem(name), why);
        try {
            cage.addPose(name, pose);
            ADD_FAILURE() << "addPose took " << why;
        } catch (const cv::Exception& e) {
            EXPECT_EQ(e.err, "multicage: pose name " + why + " (a cage file could not keep it)");
        }
        Pose renamed = cage.pose(0);
        renamed.name = name;
        EXPECT_THROW(cage.setPose(0, renamed), cv::Exception) << why;
    }
    EXPECT_EQ(cage.poseCount(), 1);
    EXPECT_EQ(cage.pose(0).name, "ok");

    // In a file: refused on load, one line naming the pose and the file, in both formats
    // (JSON strings and quoted YAML strings can hold every one of these names).
    std::string vertices;
    for (const Point2f& p : pose)
        vertices += format("%s%g, %g", vertices.empty() ? "" : ", ", p.x, p.y);
    const Size size = cage.imageSize();
    std::string polygons;
    for (int p = 0; p < cage.polygonCount(); ++p) {
        polygons += p ? ", [" : "[";
        for (size_t v = 0; v < cage.polygon(p).size(); ++v)
            polygons +=
                format("%s%g, %g", v ? ", " : "", cage.polygon(p)[v].x, cage.polygon(p)[v].y);
        polygons += "]";
    }
    const std::pair<std::string, std::string> inFile[] = {
        {"p ", "p "}, {" p", " p"}, {"a\\tb", "a\\x09b"}, {"[x", "[x"}, {"\\\"x\\\"", "\"x\""}};
    for (const char* ext : {".json", ".yml"}) {
        for (const auto& [escaped, shown] : inFile) {
            const std::string path = dir + "/bad" + ext;
            const bool json = std::string(ext) == ".json";
            std::ofstream(path) << format(
                json ? "{\"image_size\": [%d, %d], \"polygons\": [%s], \"poses\": [\n"
                       "  {\"name\": \"ok\", \"vertices\": [%s]},\n"
                       "  {\"name\": \"%s\", \"time\": 2, \"vertices\": [%s]}]}\n"
                     : "image_size: [%d, %d]\npolygons: [%s]\nposes:\n"
                       "  - { name: ok, vertices: [%s] }\n"
                       "  - { name: \"%s\", time: 2, vertices: [%s] }\n",
                size.width, size.height, polygons.c_str(), vertices.c_str(), escaped.c_str(),
                vertices.c_str());
            const std::string err = loadError(path);
            EXPECT_EQ(err.find('\n'), std::string::npos) << err;
            EXPECT_NE(err.find(path + ": cage file: poses[1].name: \"" + shown + "\""),
                      std::string::npos)
                << err;
            EXPECT_NE(err.find("which a cage file does not keep exactly: rename the pose"),
                      std::string::npos)
                << err;
        }
    }
}

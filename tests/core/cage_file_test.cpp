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
void writeText(const std::string& path, const std::string& text) { std::ofstream(path) << text; }
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
        for (int p = 0; p < cage.polygonCount(); ++p) EXPECT_EQ(back.polygon(p), cage.polygon(p)) << name;
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
        {"image_size: [ 10, 10 ]\ncoordinates: wachspress\npolygons: []\n", "coordinates: must be mean_value or harmonic"},
        {"image_size: [ 10, 10 ]\npolygons:\n  - [ 1, 1, 5, 1, 5, 5 ]\n  - [ 1, 7, 2, 7, 2 ]\n",
         "polygons[1]: odd number of coordinates (5)"},
        {"image_size: [ 10, 10 ]\npolygons:\n  - [ 1, 1, 5, one, 5, 5 ]\n",
         "polygons[0]: coordinate 3 (of vertex 1) is not a number"},
        {"image_size: [ 10, 10 ]\npolygons:\n  - [ 1, 1, 5, 1 ]\n", "polygons[0]: fewer than 3 vertices (2)"},
        {"image_size: [ 10, 10 ]\npolygons:\n  - [ 1, 1, 5, 1, 5, 5 ]\nposes:\n"
         "  - { name: up, vertices: [ 1, 1, 5, 1 ] }\n",
         "poses[0] (\"up\").vertices: has 2 vertices, the polygons have 3"},
        {"image_size: [ 10, 10 ]\npolygons:\n  - [ 1, 1, 5, 1, 5, 5 ]\nposes:\n"
         "  - { name: up, time: soon, vertices: [ 1, 1, 5, 1, 5, 5 ] }\n",
         "poses[0].time: is not a number"},
        {"image_size: [ 10, 10 ]\npolygons:\n  - [ 1, 1, 5, 1, 5, 5 ]\n  - [ 1, 1, 5, 1, 5, 5 ]\n",
         "polygon 1 crosses polygon 0"},
        {"image_size: [ 10, 10 ]\npolygons: [ [ 1, 1, 5, 1, 5, 5 ]\n", "not valid YAML/JSON"},
    };
    int i = 0;
    for (const Case& c : cases) {
        const std::string path = dir + "/case" + std::to_string(i++) + ".yml";
        writeText(path, std::string(kHeader) + c.body);
        const std::string err = loadError(path);
        EXPECT_NE(err.find(c.expected), std::string::npos) << "got: " << err << "\nwanted: " << c.expected;
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
    const std::string body = "image_size: [ 493, 356 ]\npolygons:\n  - [ 100, 100, 200, 100, 200, 200 ]\n"
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

// Regression tests for what the fuzzers and the sanitizer build found (issue 8). Each test
// names its finding; the fix is in the commit that added the test.
#include <cmath>
#include <fstream>

#include "testing.hpp"

using namespace cv;
using namespace cv::multicage;

namespace {
bool mapsSane(const Mat& mapx, const Mat& mapy) {
    const Mat uncovered = (mapx == -1e4f) & (mapy == -1e4f);
    const Mat inside = (mapx >= -1) & (mapx <= mapx.cols) & (mapy >= -1) & (mapy <= mapx.rows);
    return countNonZero(uncovered | inside) == mapx.rows * mapx.cols;
}
}  // namespace

// fuzz_deform, finding 1: nodes pushed 1e31 px away (or to infinity) by a pose made the CPU
// rasteriser convert their bounds to int: undefined behaviour (UBSan: "6.93858e+31 is outside
// the range of representable values of type 'int'", mesh_raster.cpp). Fixed by clamping in
// double first. Under the sanitizer build this test aborts without the fix; everywhere it
// checks that such meshes give sane maps.
TEST(Regression, RasteriserTakesNodesFarBeyondIntRange) {
    const Size grid(5, 4), out(40, 30);
    Mat rest(grid, CV_32FC2);
    for (int y = 0; y < grid.height; ++y)
        for (int x = 0; x < grid.width; ++x)
            rest.at<Point2f>(y, x) = Point2f(x * 9.75f, y * 9.667f);
    const float far[] = {6.9e31f, -6.9e31f, 3e38f, INFINITY, -INFINITY, NAN, 2.2e9f, -2.2e9f};
    for (float v : far) {
        for (int which = 0; which < 3; ++which) {
            Mat moved = rest.clone();
            Point2f& p = moved.at<Point2f>(1 + which % 2, 2);
            (which == 0 ? p.x : p.y) = v;
            if (which == 2) p = Point2f(v, -v);
            Mat mapx, mapy;
            rasterizeMaps(moved, rest, out, mapx, mapy);
            EXPECT_TRUE(mapsSane(mapx, mapy)) << "node at " << p;
            EXPECT_GE(countFoldedTriangles(moved, rest), 0);
        }
    }
}

// The same through a Deformer: a pose vertex at the largest float moves nodes by ~1e38 px.
TEST(Regression, PoseAtTheLargestFloatGivesAPicture) {
    const Mat image(32, 32, CV_8UC1, Scalar(100));
    Multicage cage(image.size());
    cage.addPolygon(std::vector<Point2f>{{8, 8}, {24, 8}, {24, 24}, {8, 24}});
    DeformParams cpu;
    cpu.backend = BACKEND_CPU;
    Ptr<Deformer> d = Deformer::create(image, cage, cpu);
    std::vector<Point2f> pose = cage.vertices();
    pose.resize(4);
    pose[2] = Point2f(3.4e38f, 3.4e38f);
    Mat dst, mapx, mapy;
    d->deform(pose, dst);
    EXPECT_EQ(dst.size(), image.size());
    d->computeMaps(pose, mapx, mapy);
    EXPECT_TRUE(mapsSane(mapx, mapy));
}

// fuzz_cage_file, finding 2: OpenCV 4.6's YAML parser throws std::length_error (not a
// cv::Exception) on a flow mapping whose key is empty ("{ :name"), and Multicage::load let it
// through, so callers catching cv::Exception terminated. load() now reports it as invalid YAML.
TEST(Regression, CageFileParserStandardExceptionBecomesCvException) {
    const std::string path = multicage_testing::tempDir("regression_yaml") + "/cage.yml";
    {
        FILE* f = std::fopen(path.c_str(), "wb");
        ASSERT_TRUE(f);
        std::fputs(
            "%YAML:1.0\n---\nimage_size: [ 64, 48 ]\npolygons:\n   - [ 10, 10, 50, 10, 50, 40 ]\n"
            "poses:\n   - { :name",
            f);
        std::fclose(f);
    }
    try {
        Multicage::load(path);
        FAIL() << "no error";
    } catch (const cv::Exception& e) {
        EXPECT_NE(e.err.find("cage file " + path + ": not valid YAML/JSON"), std::string::npos)
            << e.err;
    } catch (const std::exception& e) {
        FAIL() << "a " << typeid(e).name() << " escaped Multicage::load: " << e.what();
    }
}

// fuzz_cage_file, finding 6: image_size [ 64, 888888848 ] loaded, and every width x height
// taken as an int overflowed (undefined behaviour; UBSan stops here): in scaled(), which
// `multicage deform` calls to fit a cage file to its image, and in the coefficient grids.
// Cage files and validate() now refuse images over 2^30 pixels, cv::imread's own limit.
TEST(Regression, ImageSizeWhosePixelCountOverflowsIntIsRefused) {
    Multicage huge(Size(64, 888888848));
    huge.addPolygon(std::vector<Point2f>{{10, 10}, {50, 10}, {50, 40}});
    std::string why;
    EXPECT_FALSE(huge.validate(&why));
    EXPECT_EQ(why, "the image size 64x888888848 is over the limit of 2^30 pixels");
    // Scaling such a cage to a real image is plain arithmetic and stays defined.
    const Multicage fitted = huge.scaled(Size(64, 48));
    EXPECT_EQ(fitted.imageSize(), Size(64, 48));
    EXPECT_TRUE(fitted.validateGeometry(&why)) << why;
    // The largest size allowed is exactly 2^30 pixels.
    EXPECT_TRUE(Multicage(Size(32768, 32768)).validateGeometry(&why)) << why;
    EXPECT_FALSE(Multicage(Size(32768, 32769)).validateGeometry());
}

// fuzz_cage_file, finding 3: OpenCV 4.6's YAML parser loops forever when a second document
// starts with '-', which it reaches when the first document ends early (an indented or
// non-map top level, a '...' line), so Multicage::load hung. load() now refuses such layouts
// before parsing; without the fix this test never returns and CTest's timeout fails it.
TEST(Regression, MalformedYamlThatHungOpenCvsParserIsRefused) {
    const std::string dir = multicage_testing::tempDir("regression_hang");
    const std::string texts[] = {
        "%YAML:1.\n -]\ns: -\n",                              // the fuzzer's input, minimised
        "%YAML:1.\n -]\ns: -\n_",                             // the same from memory
        "%YAML:1.0\n---\n image_size: [ 10, 10 ]\npo: -\n_",  // indented top level
        "%YAML:1.0\n---\nimage_size: [ 10, 10 ]\n...\n-\n_",  // a document end marker
        "%YAML:1.0\n---\n[ 1, 2 ]\nabc-\n_",                  // a flow sequence on top
        "%YAML:1.0\n---\n{ a: 2 }\nabc-\n_",                  // a flow map on top
    };
    int i = 0;
    for (const std::string& text : texts) {
        const std::string path = dir + "/hang" + std::to_string(i++) + ".yml";
        FILE* f = std::fopen(path.c_str(), "wb");
        ASSERT_TRUE(f);
        std::fwrite(text.data(), 1, text.size(), f);
        std::fclose(f);
        try {
            Multicage::load(path);
            ADD_FAILURE() << "accepted " << text;
        } catch (const cv::Exception& e) {
            std::printf("[ answer ] %s", e.err.c_str());
            EXPECT_NE(e.err.find("cage file " + path), std::string::npos) << e.err;
        }
    }
}

// With the file read by the library, a NUL byte (a binary file given as a cage) is refused
// by name instead of being cut off silently where OpenCV's memory reader stops.
TEST(Regression, CageFileWithNulByteIsRefused) {
    const std::string path = multicage_testing::tempDir("regression_nul") + "/cage.yml";
    const std::string text(
        "%YAML:1.0\n---\nimage_size: [ 10, 10 ]\npolygons:\n  - [ 1, 1, 5, 1, 5, 5 ]\n\0junk", 77);
    FILE* f = std::fopen(path.c_str(), "wb");
    ASSERT_TRUE(f);
    std::fwrite(text.data(), 1, text.size(), f);
    std::fclose(f);
    try {
        Multicage::load(path);
        FAIL() << "accepted a file with a NUL byte";
    } catch (const cv::Exception& e) {
        EXPECT_NE(e.err.find("not valid YAML/JSON: a NUL byte at offset 72 (not a text file)"),
                  std::string::npos)
            << e.err;
    }
}

// fuzz_cage_file, finding 4 (issue 22): a JSON pose named "p " (trailing space) loaded, but
// save() wrote it as YAML's plain `name:p ` and the next load read "p": the pose was renamed.
// Names a cage file cannot keep exactly are now refused on load with one line (and by
// addPose/setPose), see poseNameProblem. The fuzzer's input, as it wrote it, is in the seed
// corpus (regression-pose-name-trailing-space.json).
TEST(Regression, PoseNameACageFileCannotKeepIsRefused) {
    const std::string path = multicage_testing::tempDir("regression_name") + "/cage.json";
    {
        std::ofstream out(path);
        out << R"({"image_size": [32, 32], "coordinates": "mean_value", "polygons": [[4, 4, 20, 4, 12, 20]],)"
            << R"( "poses": [{"name": "p ", "time": 1, "vertices": [4, 2, 20, 4, 12, 25]}]})";
    }
    try {
        Multicage::load(path);
        FAIL() << "accepted a pose named \"p \"";
    } catch (const cv::Exception& e) {
        EXPECT_EQ(
            e.err,
            path +
                ": cage file: poses[0].name: \"p \" starts or ends with a space, which a cage "
                "file does not keep exactly: rename the pose");
    }
    // The same name without the space loads, and saves back to a file that loads equal.
    {
        std::ofstream out(path);
        out << R"({"image_size": [32, 32], "coordinates": "mean_value", "polygons": [[4, 4, 20, 4, 12, 20]],)"
            << R"( "poses": [{"name": "p", "time": 1, "vertices": [4, 2, 20, 4, 12, 25]}]})";
    }
    const Multicage cage = Multicage::load(path);
    for (const char* ext : {".yml", ".json"}) {
        const std::string again = path + ext;
        cage.save(again);
        const Multicage back = Multicage::load(again);
        ASSERT_EQ(back.poseCount(), 1);
        EXPECT_EQ(back.pose(0).name, "p");
        EXPECT_EQ(back.pose(0).time, 1.0);
        EXPECT_EQ(back.pose(0).vertices, cage.pose(0).vertices);
    }
}

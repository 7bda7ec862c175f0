// The multicage tool as a user meets it: help, exit codes, one-line errors, no partial files.
#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "testing.hpp"

namespace fs = std::filesystem;

namespace {
struct Result {
    int code;
    std::string out, err;
};

// Runs `multicage ARGS` with stdout and stderr captured in files.
Result run(const std::string& args, const std::string& dir) {
    const std::string out = dir + "/captured.1", err = dir + "/captured.2";
    const std::string cmd = std::string(MULTICAGE_CLI) + " " + args + " >" + out + " 2>" + err;
    const int status = std::system(cmd.c_str());
    auto slurp = [](const std::string& p) {
        std::ifstream f(p);
        return std::string(std::istreambuf_iterator<char>(f), {});
    };
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
}

int lines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }
std::string sample(const std::string& name) { return multicage_testing::samplePath(name); }
}  // namespace

TEST(Cli, HelpOnEveryCommandExitsZero) {
    const std::string dir = multicage_testing::tempDir("cli_help");
    for (const char* cmd : {"--help", "demo --help", "deform --help", "propose --help", "animate --help", "bench --help"}) {
        const Result r = run(cmd, dir);
        EXPECT_EQ(r.code, 0) << cmd << ": " << r.err;
        EXPECT_NE(r.out.find("Usage"), std::string::npos) << cmd;
    }
    EXPECT_NE(run("deform --help", dir).out.find("--grid-step"), std::string::npos);
}

TEST(Cli, DeformWritesTheImage) {
    const std::string dir = multicage_testing::tempDir("cli_deform");
    const Result r = run("deform " + sample("butterfly.jpg") + " " + sample("../butterfly.yml") + " -o " + dir +
                             "/out.png --backend cpu --grid-step 2",
                         dir);
    ASSERT_EQ(r.code, 0) << r.err;
    const cv::Mat out = cv::imread(dir + "/out.png", cv::IMREAD_UNCHANGED);
    const cv::Mat in = cv::imread(sample("butterfly.jpg"));
    ASSERT_EQ(out.size(), in.size());
    EXPECT_GT(cv::norm(out, in, cv::NORM_L1) / in.total(), 1.0);  // it moved something
    // The cage file is for 493x356; on a doubled image it is scaled, not refused.
    cv::Mat big;
    cv::resize(in, big, cv::Size(), 2, 2);
    cv::imwrite(dir + "/big.png", big);
    const Result scaled = run("deform " + dir + "/big.png " + sample("../butterfly.yml") + " -o " + dir +
                                  "/big_out.png --backend cpu --grid-step 4",
                              dir);
    EXPECT_EQ(scaled.code, 0) << scaled.err;
    EXPECT_EQ(cv::imread(dir + "/big_out.png").size(), big.size());
}

TEST(Cli, BadInputGivesOneLineAndNoOutput) {
    const std::string dir = multicage_testing::tempDir("cli_bad");
    std::ofstream(dir + "/broken.yml") << "%YAML:1.0\n---\nimage_size: [ 493, 356 ]\npolygons:\n  - [ 1, 2, 3 ]\n";
    std::ofstream(dir + "/not_an_image.png") << "hello";
    std::ofstream(dir + "/noposes.yml") << "%YAML:1.0\n---\nimage_size: [ 493, 356 ]\npolygons:\n"
                                           "  - [ 100, 100, 200, 100, 200, 200 ]\n";
    const std::string cage = sample("../butterfly.yml"), image = sample("butterfly.jpg");
    struct Case {
        std::string args, expected;
    } cases[] = {
        {"deform " + dir + "/missing.png " + cage + " -o " + dir + "/out.png", "no such file"},
        {"deform " + dir + "/not_an_image.png " + cage + " -o " + dir + "/out.png", "not an image"},
        {"deform " + image + " " + dir + "/broken.yml -o " + dir + "/out.png", "odd number of coordinates"},
        {"deform " + image + " " + dir + "/noposes.yml -o " + dir + "/out.png", "has no poses"},
        {"deform " + image + " " + cage + " -o " + dir + "/out.png --pose nope", "no pose named 'nope'"},
        {"deform " + image + " " + cage + " -o " + dir + "/out.png --grid-step 0", "--grid-step"},
        {"deform " + image + " " + cage + " -o " + dir + "/out.xyz --backend cpu", "out.xyz"},
        {"deform " + image + " " + cage + " -o /nonexistent-dir/out.png --backend cpu", "cannot write"},
        {"frobnicate", "unknown command 'frobnicate'"},
    };
    for (const Case& c : cases) {
        const Result r = run(c.args, dir);
        EXPECT_NE(r.code, 0) << c.args;
        EXPECT_EQ(lines(r.err), 1) << c.args << "\n" << r.err;
        EXPECT_NE(r.err.find(c.expected), std::string::npos) << c.args << "\n" << r.err;
    }
    for (const auto& entry : fs::directory_iterator(dir)) {
        const std::string name = entry.path().filename().string();
        EXPECT_NE(name.rfind("out", 0), 0u) << "left behind: " << name;
    }
}

TEST(Cli, DemoWritesItsOutputs) {
    const std::string dir = multicage_testing::tempDir("cli_demo");
    const Result r = run("demo --backend cpu -o " + dir + "/demo", dir);
    ASSERT_EQ(r.code, 0) << r.err;
    for (const char* f : {"input.png", "overlay.png", "deformed.png", "side_by_side.png", "cage.yml"})
        EXPECT_TRUE(fs::exists(dir + "/demo/" + f)) << f;
    const cv::multicage::Multicage cage = cv::multicage::Multicage::load(dir + "/demo/cage.yml");
    EXPECT_TRUE(cage.validate());
    EXPECT_GE(cage.poseCount(), 1);
}

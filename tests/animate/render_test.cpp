// Rendering: every frame written, first and last frames equal single deform calls, consecutive
// frames change smoothly, and a failed render leaves nothing behind.
#include <gif_lib.h>
#include <sys/wait.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/multicage/animate.hpp>
#include <opencv2/multicage/gpu.hpp>
#include <opencv2/videoio.hpp>

#include "testing.hpp"

using namespace cv::multicage;
namespace fs = std::filesystem;

namespace {
const std::string kFlap = std::string(MULTICAGE_SAMPLE_CAGES) + "/butterfly_flap.yml";

// 12 frames of the butterfly flapping: 0.8 s at 13.75 fps (11 steps), clamped.
AnimationParams twelveFrames() {
    AnimationParams p;
    p.fps = 13.75;
    return p;
}

std::vector<cv::Mat> readFrames(const std::string& dir) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().string());
    std::sort(names.begin(), names.end());
    std::vector<cv::Mat> frames;
    for (const std::string& n : names) frames.push_back(cv::imread(n, cv::IMREAD_UNCHANGED));
    return frames;
}

double meanAbsDiff(const cv::Mat& a, const cv::Mat& b) {
    return cv::norm(a, b, cv::NORM_L1) / static_cast<double>(a.total() * a.channels());
}

// Nothing in dir but the listed names (no temporary files left over).
std::vector<std::string> listing(const std::string& dir) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

// Renders to a PNG folder with `backend`, then checks frame count, ends and smoothness.
void checkPngRender(int backend, const std::string& name) {
    const cv::Mat image = multicage_testing::readSample("butterfly.jpg");
    const Multicage cage = Multicage::load(kFlap);
    DeformParams dp;
    dp.backend = backend;
    dp.gridStep = 2;
    cv::Ptr<Deformer> deformer = Deformer::create(image, cage, dp);
    ASSERT_EQ(deformer->backend(), backend);
    const std::string dir = multicage_testing::tempDir(name);
    int calls = 0;
    const AnimationStats stats = renderAnimation(*deformer, cage, dir + "/frames/", twelveFrames(),
                                                 [&calls](int done, int total) {
                                                     EXPECT_EQ(done, ++calls);
                                                     EXPECT_EQ(total, 12);
                                                 });
    EXPECT_EQ(stats.frames, 12);
    EXPECT_EQ(calls, 12);
    EXPECT_EQ(listing(dir), std::vector<std::string>{"frames"});
    const std::vector<cv::Mat> frames = readFrames(dir + "/frames");
    ASSERT_EQ(frames.size(), 12u);
    EXPECT_EQ(listing(dir + "/frames").front(), "frame_0000.png");
    EXPECT_EQ(listing(dir + "/frames").back(), "frame_0011.png");

    // First and last frames: single deform calls on the first and last keyframes, bit for bit.
    const std::vector<int> order = keyframeOrder(cage);
    cv::Mat first, last;
    deformer->deform(cage.pose(order.front()).vertices, first);
    deformer->deform(cage.pose(order.back()).vertices, last);
    ASSERT_EQ(frames.front().size(), image.size());
    ASSERT_EQ(frames.front().type(), image.type());
    EXPECT_EQ(cv::norm(frames.front(), first, cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::norm(frames.back(), last, cv::NORM_INF), 0.0);
    EXPECT_GT(meanAbsDiff(first, last), 5.0);  // the animation goes somewhere

    // Smooth: every step moves a little, and no step is a jump (max <= 3x the median).
    std::vector<double> steps;
    for (size_t i = 1; i < frames.size(); ++i)
        steps.push_back(meanAbsDiff(frames[i - 1], frames[i]));
    std::vector<double> sorted = steps;
    std::sort(sorted.begin(), sorted.end());
    const double median = sorted[sorted.size() / 2], largest = sorted.back();
    for (size_t i = 0; i < steps.size(); ++i)
        EXPECT_GT(steps[i], 0.05) << "frames " << i << " and " << i + 1;
    EXPECT_LE(largest, 3 * median)
        << "a frame jumps: largest step " << largest << ", median " << median;
}
}  // namespace

TEST(Render, PngFramesMatchSingleDeformCallsOnTheCpu) {
    checkPngRender(BACKEND_CPU, "animate_cpu");
}

TEST(Render, PngFramesMatchSingleDeformCallsOnTheGpu) {
    std::string why;
    if (!gpuAvailable(&why)) GTEST_SKIP() << why;
    checkPngRender(BACKEND_GPU, "animate_gpu");
}

TEST(Render, VideoHoldsEveryFrame) {
    const cv::Mat image = multicage_testing::readSample("butterfly.jpg");
    const Multicage cage = Multicage::load(kFlap);
    DeformParams dp;
    dp.backend = BACKEND_CPU;
    dp.gridStep = 4;
    cv::Ptr<Deformer> deformer = Deformer::create(image, cage, dp);
    cv::Mat first;
    deformer->deform(cage.pose(keyframeOrder(cage).front()).vertices, first);
    const std::string dir = multicage_testing::tempDir("animate_video");
    for (const std::string name : {"flap.avi", "flap.mp4"}) {
        renderAnimation(*deformer, cage, dir + "/" + name, twelveFrames());
        cv::VideoCapture cap(dir + "/" + name);
        ASSERT_TRUE(cap.isOpened()) << name;
        std::vector<cv::Mat> frames;
        for (cv::Mat f; cap.read(f);) frames.push_back(f.clone());
        ASSERT_EQ(frames.size(), 12u) << name;
        ASSERT_GE(frames.front().cols, image.cols) << name;
        ASSERT_GE(frames.front().rows, image.rows) << name;
        // Odd widths are padded for 4:2:0 video; the picture itself is the first pose, lossy.
        const cv::Mat decoded = frames.front()(cv::Rect(0, 0, image.cols, image.rows));
        EXPECT_GT(multicage_testing::psnr(decoded, first), 28.0) << name;
        EXPECT_NEAR(cap.get(cv::CAP_PROP_FPS), 13.75, 0.01) << name;
    }
    EXPECT_EQ(listing(dir), (std::vector<std::string>{"flap.avi", "flap.mp4"}));
}

TEST(Render, GifHoldsEveryFrameAndTheCompositeIsTheLastPose) {
    if (!multicage_testing::kHaveGif) GTEST_SKIP() << "built without giflib (MULTICAGE_WITH_GIF)";
    const cv::Mat image = multicage_testing::readSample("butterfly.jpg");
    const Multicage cage = Multicage::load(kFlap);
    DeformParams dp;
    dp.backend = BACKEND_CPU;
    dp.gridStep = 4;
    cv::Ptr<Deformer> deformer = Deformer::create(image, cage, dp);
    const std::string dir = multicage_testing::tempDir("animate_gif");
    const std::string path = dir + "/flap.gif";
    renderAnimation(*deformer, cage, path, twelveFrames());
    EXPECT_EQ(listing(dir), std::vector<std::string>{"flap.gif"});

    int error = 0;
    GifFileType* gif = DGifOpenFileName(path.c_str(), &error);
    ASSERT_NE(gif, nullptr) << GifErrorString(error);
    ASSERT_EQ(DGifSlurp(gif), GIF_OK) << GifErrorString(gif->Error);
    EXPECT_EQ(gif->ImageCount, 12);
    EXPECT_EQ(gif->SWidth, image.cols);
    EXPECT_EQ(gif->SHeight, image.rows);
    // Replay the frames (unchanged pixels are transparent) and compare with the last pose.
    cv::Mat canvas(image.size(), CV_8UC3, cv::Scalar::all(0));
    const ColorMapObject* map = gif->SColorMap;
    ASSERT_NE(map, nullptr);
    int totalDelay = 0;
    for (int i = 0; i < gif->ImageCount; ++i) {
        const SavedImage& frame = gif->SavedImages[i];
        GraphicsControlBlock gcb;
        DGifSavedExtensionToGCB(gif, i, &gcb);
        totalDelay += gcb.DelayTime;
        const GifImageDesc& d = frame.ImageDesc;
        for (int y = 0; y < d.Height; ++y)
            for (int x = 0; x < d.Width; ++x) {
                const int index = frame.RasterBits[y * d.Width + x];
                if (index == gcb.TransparentColor) continue;
                const GifColorType c = map->Colors[index];
                canvas.at<cv::Vec3b>(d.Top + y, d.Left + x) = cv::Vec3b(c.Blue, c.Green, c.Red);
            }
        if (i == 0) EXPECT_EQ(gcb.TransparentColor, NO_TRANSPARENT_COLOR);
    }
    DGifCloseFile(gif, &error);
    EXPECT_NEAR(totalDelay, 12 * 100 / 13.75, 1.0);  // 1/100 s units, rounding does not add up
    cv::Mat last;
    deformer->deform(cage.pose(keyframeOrder(cage).back()).vertices, last);
    EXPECT_GT(multicage_testing::psnr(canvas, last), 28.0);
}

TEST(Render, FailuresLeaveNoOutputAndSayWhy) {
    const std::string dir = multicage_testing::tempDir("animate_fail");
    auto message = [](const std::string& path) {
        try {
            checkAnimationOutput(path);
        } catch (const cv::Exception& e) {
            return e.err;
        }
        return std::string("(no error)");
    };
    EXPECT_NE(message(dir + "/out.mov").find("unknown animation type '.mov'"), std::string::npos);
    EXPECT_NE(message(dir + "/out").find("unknown animation type ''"), std::string::npos);
    EXPECT_NE(message(dir + "/missing/out.mp4").find("no folder"), std::string::npos);
    EXPECT_NE(message(dir + "/missing/frames/").find("no folder"), std::string::npos);
    fs::create_directory(dir + "/busy");
    std::ofstream(dir + "/busy/notes.txt") << "mine";
    EXPECT_NE(message(dir + "/busy").find("holds other files (notes.txt)"), std::string::npos);
    if (multicage_testing::kHaveGif)
        EXPECT_EQ(checkAnimationOutput(dir + "/out.GIF"), ANIMATION_GIF);
    else
        EXPECT_NE(message(dir + "/out.GIF").find("install libgif-dev"), std::string::npos);

    // A writer dropped before finish() (a render that failed half way) leaves nothing.
    const cv::Mat frame(40, 60, CV_8UC3, cv::Scalar(10, 200, 30));
    for (const std::string name : {"a.gif", "a.avi", "a.mp4", "frames/"}) {
        if (name == "a.gif" && !multicage_testing::kHaveGif) continue;
        cv::Ptr<AnimationWriter> w = AnimationWriter::create(dir + "/" + name, 10);
        w->write(frame);
        w->write(frame);
        EXPECT_THROW(w->write(cv::Mat(41, 60, CV_8UC3)), cv::Exception);  // another size
    }
    EXPECT_EQ(listing(dir), (std::vector<std::string>{"busy"}));

    // A failed render (bad keyframes) leaves nothing either, and an old frames folder is
    // replaced only when complete.
    const cv::Mat image = multicage_testing::readSample("butterfly.jpg");
    const Multicage flap = Multicage::load(kFlap);
    Multicage single = flap;
    while (single.poseCount() > 1) single.removePose(single.poseCount() - 1);
    DeformParams dp;
    dp.backend = BACKEND_CPU;
    dp.gridStep = 8;
    EXPECT_THROW(
        renderAnimation(image, single, dir + "/one" + multicage_testing::animationExtension(),
                        twelveFrames(), dp),
        cv::Exception);
    AnimationParams few;
    few.fps = 2.5;  // 0.8 s -> 3 frames
    renderAnimation(image, flap, dir + "/frames/", few, dp);
    EXPECT_EQ(listing(dir + "/frames").size(), 3u);
    renderAnimation(image, flap, dir + "/frames", twelveFrames(), dp);
    EXPECT_EQ(listing(dir + "/frames").size(), 12u);
    EXPECT_EQ(listing(dir), (std::vector<std::string>{"busy", "frames"}));
}

#ifdef MULTICAGE_CLI
namespace {
struct Result {
    int code;
    std::string out, err;
};
Result cli(const std::string& args, const std::string& dir) {
    const std::string out = dir + "/captured.1", err = dir + "/captured.2";
    const int status =
        std::system((std::string(MULTICAGE_CLI) + " " + args + " >" + out + " 2>" + err).c_str());
    auto slurp = [](const std::string& p) {
        std::ifstream f(p);
        return std::string(std::istreambuf_iterator<char>(f), {});
    };
    Result r{WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
    fs::remove(out);
    fs::remove(err);
    return r;
}
}  // namespace

TEST(AnimateCommand, WritesFramesAndReportsProgress) {
    const std::string dir = multicage_testing::tempDir("animate_cli");
    const std::string image = multicage_testing::samplePath("butterfly.jpg");
    const Result r = cli("animate " + image + " " + kFlap + " -o " + dir +
                             "/f/ --fps 10 --duration 1.1 "
                             "--backend cpu --grid-step 4 --interpolation linear",
                         dir);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(listing(dir + "/f").size(), 12u);
    EXPECT_NE(r.out.find("12 frames"), std::string::npos) << r.out;
    EXPECT_NE(r.err.find("100% (12/12 frames)"), std::string::npos)
        << r.err;  // not a TTY: percentages
    EXPECT_NE(cli("animate --help", dir).out.find("--interpolation"), std::string::npos);
}

TEST(AnimateCommand, BadInputGivesOneLineAndNoOutput) {
    const std::string dir = multicage_testing::tempDir("animate_cli_bad");
    const std::string image = multicage_testing::samplePath("butterfly.jpg");
    const std::string onePose = std::string(MULTICAGE_SAMPLE_CAGES) + "/butterfly.yml";
    std::ofstream(dir + "/same_time.yml")
        << "%YAML:1.0\n---\nimage_size: [ 493, 356 ]\npolygons:\n  - [ 100, 100, 200, 100, 200, "
           "200 ]\n"
           "poses:\n  - { name: a, time: 1, vertices: [ 100, 100, 200, 100, 200, 200 ] }\n"
           "  - { name: b, time: 1, vertices: [ 110, 100, 200, 100, 200, 200 ] }\n";
    const std::string ext = multicage_testing::animationExtension();
    struct Case {
        std::string args, expected;
    } cases[] = {
        {image + " " + onePose + " -o " + dir + "/out" + ext, "needs at least two timed poses"},
        {image + " " + dir + "/same_time.yml -o " + dir + "/out" + ext,
         "'a' and 'b' are both at time 1"},
        {image + " " + kFlap + " -o " + dir + "/out.webm", "unknown animation type '.webm'"},
        {image + " " + kFlap + " -o " + dir + "/nowhere/out.mp4", "no folder"},
        {image + " " + kFlap + " -o " + dir + "/out" + ext + " --fps 0", "--fps"},
    };
    for (const Case& c : cases) {
        const Result r = cli("animate " + c.args, dir);
        EXPECT_EQ(r.code, c.expected == "--fps" ? 2 : 1) << c.args;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_NE(r.err.find(c.expected), std::string::npos) << r.err;
    }
    EXPECT_EQ(listing(dir), std::vector<std::string>{"same_time.yml"});
}
#endif

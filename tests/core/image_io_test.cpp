// Image files in and out (issue 13 items 2 and 3): truncated JPEG/PNG inputs are refused,
// outputs are converted to a depth the format holds with the scale that keeps white white.
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/multicage/imageio.hpp>

#include "testing.hpp"

using namespace cv;
using namespace cv::multicage;

namespace {
std::vector<uchar> encode(const std::string& ext, const Mat& image,
                          const std::vector<int>& params = {}) {
    std::vector<uchar> bytes;
    EXPECT_TRUE(imencode(ext, image, bytes, params));
    return bytes;
}

void writeBytes(const std::string& path, const std::vector<uchar>& bytes, size_t count) {
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(count));
}

Mat photo() {
    return imread(multicage_testing::samplePath("butterfly.jpg"), IMREAD_COLOR);
}
}  // namespace

TEST(ImageIo, TruncatedJpegIsRefusedAtEveryCutWholeOneIsRead) {
    const Mat image = photo();
    ASSERT_FALSE(image.empty());
    for (bool progressive : {false, true}) {
        const std::vector<uchar> jpg =
            encode(".jpg", image, {IMWRITE_JPEG_PROGRESSIVE, progressive ? 1 : 0});
        EXPECT_EQ(truncatedImageReason(jpg), "") << "progressive " << progressive;
        // Data after the end marker (camera trailers, motion photos) does not make it truncated.
        std::vector<uchar> trailer = jpg;
        for (uchar b : {0xFF, 0xDA, 0x00, 0x08, 0x12, 0xFF}) trailer.push_back(b);
        EXPECT_EQ(truncatedImageReason(trailer), "");
        for (size_t cut : {size_t(3000), jpg.size() / 2, jpg.size() - 2, jpg.size() - 1}) {
            const std::vector<uchar> part(jpg.begin(), jpg.begin() + long(cut));
            EXPECT_NE(truncatedImageReason(part).find("truncated"), std::string::npos)
                << "progressive " << progressive << ", cut after " << cut << " of " << jpg.size()
                << " bytes";
        }
    }
}

TEST(ImageIo, TruncatedPngIsRefusedAtEveryCutWholeOneIsRead) {
    const std::vector<uchar> png = encode(".png", photo());
    EXPECT_EQ(truncatedImageReason(png), "");
    for (size_t cut : {size_t(40), size_t(3000), png.size() / 2, png.size() - 1, png.size() - 12}) {
        const std::vector<uchar> part(png.begin(), png.begin() + long(cut));
        EXPECT_NE(truncatedImageReason(part).find("truncated"), std::string::npos)
            << "cut after " << cut;
    }
}

TEST(ImageIo, ReadImageNamesTheTruncatedFileAndReadsEverySample) {
    const std::string dir = multicage_testing::tempDir("image_io_read");
    const std::vector<uchar> jpg = encode(".jpg", photo());
    writeBytes(dir + "/cut.jpg", jpg, 3000);
    // OpenCV itself decodes the cut file with only a libjpeg warning: that is the defect.
    EXPECT_FALSE(imread(dir + "/cut.jpg").empty());
    try {
        readImage(dir + "/cut.jpg");
        ADD_FAILURE() << "a JPEG cut after 3000 bytes was read";
    } catch (const cv::Exception& e) {
        EXPECT_NE(e.err.find(dir + "/cut.jpg: the file is truncated"), std::string::npos) << e.err;
    }
    EXPECT_THROW(readImage(dir + "/missing.png"), cv::Exception);
    for (const char* name : {"butterfly.jpg", "building.jpg", "fruits.jpg", "HappyFish.jpg",
                             "messi5.jpg", "smarties.png"}) {
        const Mat m = readImage(multicage_testing::samplePath(name));
        EXPECT_FALSE(m.empty()) << name;
    }
}

// Issue 22 item 3: the reader every tool and the Python module share (multicage.imread) says
// in one line, naming the file, what is wrong with each kind of damaged file.
TEST(ImageIo, ReadImageSaysWhyInOneLineForEveryDamagedFile) {
    const std::string dir = multicage_testing::tempDir("image_io_damaged");
    const std::vector<uchar> jpg = encode(".jpg", photo());
    writeBytes(dir + "/cut.jpg", jpg, 2000);
    writeBytes(dir + "/empty.jpg", jpg, 0);
    const std::string text = "not an image, a note\n";
    writeBytes(dir + "/notes.png", std::vector<uchar>(text.begin(), text.end()), text.size());
    const std::pair<std::string, std::string> expected[] = {
        {"cut.jpg",
         "cut.jpg: the file is truncated (a JPEG ends with an end-of-image marker FF D9; this one "
         "stops after 2000 bytes, in the middle of its data)"},
        {"empty.jpg", "empty.jpg: the file is empty"},
        {"notes.png", "notes.png: not an image OpenCV can read"},
        {"missing.png", "missing.png: no such file, or it cannot be read"},
    };
    for (const auto& [name, why] : expected) {
        try {
            readImage(dir + "/" + name);
            ADD_FAILURE() << name << " was read";
        } catch (const cv::Exception& e) {
            EXPECT_EQ(e.err, dir + "/" + why);
        }
    }
}

TEST(ImageIo, ConversionKeepsWhiteWhiteAndTheDepthWhereTheFormatCan) {
    Mat u16(4, 4, CV_16UC3, Scalar(65535, 32896, 0)), f32(4, 4, CV_32FC3, Scalar(1.0, 0.5, 0.0));
    std::string note;
    // Kept where the format holds it.
    EXPECT_EQ(convertForImageFormat("a.png", u16, &note).depth(), CV_16U);
    EXPECT_EQ(note, "");
    EXPECT_EQ(convertForImageFormat("a.TIF", f32, &note).depth(), CV_32F);
    EXPECT_EQ(note, "");
    // 16 bits to JPEG: x1/257, white stays 255.
    Mat m = convertForImageFormat("out.jpg", u16, &note);
    EXPECT_EQ(m.type(), CV_8UC3);
    EXPECT_EQ(m.at<Vec3b>(0, 0), Vec3b(255, 128, 0));
    EXPECT_NE(note.find("scaled by 1/257"), std::string::npos) << note;
    // Float in [0, 1] to JPEG: x255; to PNG: 16 bits, x65535.
    m = convertForImageFormat("out.jpg", f32, &note);
    EXPECT_EQ(m.at<Vec3b>(0, 0), Vec3b(255, 128, 0));
    EXPECT_NE(note.find("scaled by 255"), std::string::npos) << note;
    m = convertForImageFormat("out.png", f32, &note);
    EXPECT_EQ(m.type(), CV_16UC3);
    EXPECT_EQ(m.at<Vec3w>(0, 0)[0], 65535);
    // A lossy float codec overshoots 1 a little: still [0, 1].
    m = convertForImageFormat("out.jpg", Mat(2, 2, CV_32FC1, Scalar(1.02)), &note);
    EXPECT_EQ(m.at<uchar>(0, 0), 255);
    // Floats holding 0-255 values are kept as such.
    m = convertForImageFormat("out.jpg", Mat(2, 2, CV_32FC1, Scalar(200.0)), &note);
    EXPECT_EQ(m.at<uchar>(0, 0), 200);
    // 8 bits to a float-only format: x1/255.
    m = convertForImageFormat("out.exr", Mat(2, 2, CV_8UC1, Scalar(255)), &note);
    EXPECT_EQ(m.type(), CV_32FC1);
    EXPECT_FLOAT_EQ(m.at<float>(0, 0), 1.f);
}

// cv::imwrite refuses colour in .pgm/.pbm and grey or alpha in .ppm ("Portable bitmap(.pgm)
// expects gray image"), after the work was done, and drops a JPEG's alpha without a word.
TEST(ImageIo, ChannelsAreConvertedToWhatTheFormatStoresAndSaid) {
    const std::string dir = multicage_testing::tempDir("image_io_channels");
    const Mat bgr(4, 6, CV_8UC3, Scalar(10, 100, 200)), grey(4, 6, CV_8UC1, Scalar(77));
    const Mat bgra(4, 6, CV_8UC4, Scalar(10, 100, 200, 128));
    std::string note;
    struct Case {
        const char* file;
        Mat image;
        int type;
        const char* said;
    } cases[] = {
        {"a.pgm", bgr, CV_8UC1, ".pgm does not store 3 channels; wrote the colour image as grey"},
        {"a.pbm", bgra, CV_8UC1, ".pbm does not store 4 channels; wrote the colour image as grey"},
        {"a.ppm", grey, CV_8UC3, ".ppm does not store 1 channels; wrote the grey image as colour"},
        {"a.ppm", bgra, CV_8UC3,
         ".ppm does not store 4 channels; wrote the colour image without its alpha channel"},
        {"a.jpg", bgra, CV_8UC3,
         ".jpg does not store 4 channels; wrote the colour image without its alpha channel"},
        {"a.hdr", bgra, CV_32FC3,
         ".hdr does not store 4 channels; wrote the colour image without its alpha channel; "
         ".hdr does not store 8-bit pixels; wrote float"},
        {"a.png", bgra, CV_8UC4, ""},
        {"a.pgm", grey, CV_8UC1, ""},
    };
    for (const Case& c : cases) {
        const Mat m = convertForImageFormat(dir + "/" + c.file, c.image, &note);
        EXPECT_EQ(m.type(), c.type) << c.file << " from " << c.image.channels();
        if (*c.said)
            EXPECT_NE(note.find(c.said), std::string::npos) << note;
        else
            EXPECT_EQ(note, "") << c.file;
        EXPECT_TRUE(imwrite(dir + "/" + c.file, m)) << c.file;  // and OpenCV writes it
    }
    // Grey is the image's luminance: (10, 100, 200) BGR is 0.114*10 + 0.587*100 + 0.299*200.
    EXPECT_EQ(convertForImageFormat("a.pgm", bgr).at<uchar>(0, 0), 120);
}

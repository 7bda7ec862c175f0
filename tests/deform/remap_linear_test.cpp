// The CPU backend's own bilinear sampler against cv::remap, bit for bit: inside, on the last row
// and column, across the border, far outside, NaN and huge map values, odd sizes and strides.
#include "remap_linear.hpp"

#include <opencv2/imgproc.hpp>

#include "testing.hpp"

using namespace cv;
using namespace cv::multicage;

namespace {

// Every path this CPU can take: its own (AVX-512 where it has it), and AVX2.
void expectSameAsRemap(const Mat& src, const Mat& mapx, const Mat& mapy, const Scalar& border,
                       const char* what) {
    Mat theirs;
    remap(src, theirs, mapx, mapy, INTER_LINEAR, BORDER_CONSTANT, border);
    for (RemapPath path : {RemapPath::best, RemapPath::avx2}) {
        if (!preferRemapPath(path)) continue;
        Mat ours;
        remapLinear(src, ours, mapx, mapy, border);
        preferRemapPath(RemapPath::best);
        const char* which = path == RemapPath::avx2 ? " (AVX2 path)" : " (path of this CPU)";
        ASSERT_EQ(ours.size(), theirs.size()) << what << which;
        ASSERT_EQ(ours.type(), theirs.type()) << what << which;
        Mat diff = ours != theirs;
        diff = diff.reshape(1);
        EXPECT_EQ(countNonZero(diff), 0) << what << which;
    }
}

}  // namespace

TEST(RemapLinear, TakesItsOwnPathWhereTheCpuHasIt) {
    // Says which path the comparisons below test; on a CPU without AVX2 they test the fallback
    // (cv::remap itself), which is trivially equal.
    std::cout << "[ remap ] own path for CV_8UC3: " << remapLinearOwnPath(CV_8UC3) << "\n";
    EXPECT_FALSE(remapLinearOwnPath(CV_32FC3));
}

TEST(RemapLinear, SameBitsAsCvRemap) {
    RNG rng(12345);
    for (Size size : {Size(37, 23), Size(64, 48), Size(301, 199)}) {
        Mat src(size, CV_8UC3);
        rng.fill(src, RNG::UNIFORM, 0, 256);
        const Size out(size.width + 13, size.height + 5);
        Mat mapx(out, CV_32F), mapy(out, CV_32F);
        // Inside (every sample in the image: the vector path), then with the last row and column
        // exactly (their right and lower samples are outside, with weight 0).
        rng.fill(mapx, RNG::UNIFORM, 0, size.width - 1.05);
        rng.fill(mapy, RNG::UNIFORM, 0, size.height - 1.05);
        expectSameAsRemap(src, mapx, mapy, Scalar(9, 200, 31), "inside");
        for (int y = 0; y < out.height; ++y)
            for (int x = 0; x < out.width; x += 7) {
                mapx.at<float>(y, x) = float(size.width - 1);
                mapy.at<float>(y, std::min(x + 3, out.width - 1)) = float(size.height - 1);
            }
        mapx.at<float>(0, 0) = mapy.at<float>(0, 0) = 0.f;
        expectSameAsRemap(src, mapx, mapy, Scalar(9, 200, 31), "last row and column");
        // Across the border and far away: partly outside samples mix in the border value.
        rng.fill(mapx, RNG::UNIFORM, -2, size.width + 1);
        rng.fill(mapy, RNG::UNIFORM, -2, size.height + 1);
        expectSameAsRemap(src, mapx, mapy, Scalar(9, 200, 31), "across the border");
        rng.fill(mapx, RNG::UNIFORM, -1e6, 1e6);
        expectSameAsRemap(src, mapx, mapy, Scalar::all(0), "far away");
        // Ties of the rounding (k/64), NaN, infinities and values past 16 bits.
        for (int y = 0; y < out.height; ++y)
            for (int x = 0; x < out.width; ++x) {
                mapx.at<float>(y, x) = float((x * 7 + y) % (64 * size.width)) / 64.f;
                mapy.at<float>(y, x) = float((y * 5 + x) % (64 * size.height)) / 64.f;
            }
        mapx.at<float>(1, 2) = NAN, mapy.at<float>(2, 1) = NAN;
        mapx.at<float>(1, 3) = INFINITY, mapy.at<float>(2, 3) = -INFINITY;
        mapx.at<float>(1, 4) = 5e4f, mapy.at<float>(2, 5) = -7e4f, mapx.at<float>(3, 3) = 3e9f;
        expectSameAsRemap(src, mapx, mapy, Scalar(1, 2, 3), "ties and special values");
        // A source with a row stride of its own (a view), and maps that are views.
        Mat big(size.height + 4, size.width + 9, CV_8UC3);
        rng.fill(big, RNG::UNIFORM, 0, 256);
        Mat view = big(Rect(3, 2, size.width, size.height));
        Mat bigMaps[2] = {Mat(out.height + 1, out.width + 3, CV_32F),
                          Mat(out.height + 1, out.width + 3, CV_32F)};
        rng.fill(bigMaps[0], RNG::UNIFORM, -1, size.width);
        rng.fill(bigMaps[1], RNG::UNIFORM, -1, size.height);
        expectSameAsRemap(view, bigMaps[0](Rect(1, 1, out.width, out.height)),
                          bigMaps[1](Rect(2, 0, out.width, out.height)), Scalar(255, 0, 128),
                          "views");
    }
}

// Smooth warps, as deformations make them: neighbouring pixels sample neighbouring source
// pixels, so the vector path reads two output pixels' samples with one 16-byte load. Scales from
// 0.5 to 4 source pixels per output pixel (beyond 3 the loads no longer serve a pair), rows that
// cross a source row between two neighbours, and samples up to the last row and column.
TEST(RemapLinear, SmoothWarpsSameBitsAsCvRemap) {
    RNG rng(99);
    for (Size size : {Size(64, 48), Size(301, 199)}) {
        Mat src(size, CV_8UC3);
        rng.fill(src, RNG::UNIFORM, 0, 256);
        for (float scale : {0.5f, 1.f, 2.9f, 3.1f, 4.f})
            for (float shear : {0.f, 0.13f}) {
                Mat mapx(size, CV_32F), mapy(size, CV_32F);
                for (int y = 0; y < size.height; ++y)
                    for (int x = 0; x < size.width; ++x) {
                        mapx.at<float>(y, x) = x * scale + 2.f * std::sin(y * 0.1f) - 1.f;
                        mapy.at<float>(y, x) = y * 0.97f + shear * x + std::cos(x * 0.07f);
                    }
                expectSameAsRemap(src, mapx, mapy, Scalar(4, 5, 6),
                                  format("scale %.1f shear %.2f", scale, shear).c_str());
                // the same warp pushed against the bottom-right corner
                mapx += Scalar(size.width * (1 - scale) + 0.5f);
                mapy += Scalar(2.f);
                expectSameAsRemap(
                    src, mapx, mapy, Scalar(4, 5, 6),
                    format("scale %.1f shear %.2f, bottom right", scale, shear).c_str());
            }
    }
}

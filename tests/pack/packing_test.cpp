// Packing cage coordinates into the Eq. 6-7 texture, and the fallback layouts.
#include <cstring>

#include "testing.hpp"

using namespace cv;
using namespace cv::multicage;

TEST(Packing, PaperFigure6Layout) {
    // 1024x768, 68 user vertices + the 4 frame corners: the paper's Fig. 6.
    const Multicage cage = multicage_fixtures::lotusMulticage(Size(1024, 768), 68);
    ASSERT_EQ(cage.vertexCount(), 68);
    const int c = static_cast<int>(cage.vertices().size());
    EXPECT_EQ(c, 72);
    const PackLayout l = paperPackLayout(Size(1024, 768), c);
    EXPECT_EQ(l.blocks, 18);
    EXPECT_EQ(l.cols, 5);
    EXPECT_EQ(l.rows, 4);
    EXPECT_EQ(l.textureSize, Size(5120, 3072));
    EXPECT_EQ(l.cols * l.rows - l.blocks, 2);  // empty blocks
    EXPECT_EQ(l.layers, 1);
}

TEST(Packing, PortraitSwapsRoles) {
    const PackLayout l = paperPackLayout(Size(768, 1024), 72);
    EXPECT_EQ(l.blocks, 18);
    EXPECT_EQ(l.cols, 4);
    EXPECT_EQ(l.rows, 5);
    EXPECT_EQ(l.textureSize, Size(3072, 5120));
    // floor(m/n) widens the block grid along the long side: 3 blocks of 300x100 need 3x1.
    const PackLayout wide = paperPackLayout(Size(300, 100), 12);
    EXPECT_EQ(wide.cols, 3);
    EXPECT_EQ(wide.rows, 1);
    const PackLayout tall = paperPackLayout(Size(100, 300), 12);
    EXPECT_EQ(tall.cols, 1);
    EXPECT_EQ(tall.rows, 3);
    EXPECT_EQ(tall.textureSize, Size(100, 900));
}

TEST(Packing, FallbackWhenTooLarge) {
    const PackLayout fits = choosePackLayout(Size(1024, 768), 72, 16384);
    EXPECT_EQ(fits.layers, 1);
    EXPECT_EQ(fits.textureSize, Size(5120, 3072));
    const PackLayout layered = choosePackLayout(Size(1024, 768), 72, 4096);
    EXPECT_EQ(layered.layers, 18);
    EXPECT_EQ(layered.textureSize, Size(1024, 768));
    EXPECT_EQ(layered.blocksPerLayer(), 1);
    EXPECT_THROW(choosePackLayout(Size(5000, 100), 8, 4096), cv::Exception);
}

static Binding randomBinding(Size grid, int c, uint64 seed) {
    Binding b;
    b.gridSize = grid;
    b.imageSize = grid;
    b.restVertices.resize(c);
    b.coefficients.create(c, grid.area(), CV_32F);
    RNG rng(seed);
    rng.fill(b.coefficients, RNG::NORMAL, 0.0, 0.3);
    // Values whose bits matter: denormals, negative zero, the extremes of float.
    b.coefficients.at<float>(0, 0) = 1e-42f;
    b.coefficients.at<float>(1, 1) = -0.f;
    b.coefficients.at<float>(c - 1, grid.area() - 1) = 3.4e38f;
    return b;
}

static void expectBitExactRoundTrip(const Binding& b, const PackLayout& layout) {
    Mat packed, back;
    packCoefficients(b, layout, packed);
    ASSERT_EQ(packed.type(), CV_32FC4);
    ASSERT_EQ(packed.size(),
              Size(layout.textureSize.width, layout.textureSize.height * layout.layers));
    unpackCoefficients(packed, layout, b.coefficientCount(), back);
    ASSERT_EQ(back.size(), b.coefficients.size());
    EXPECT_EQ(
        0, std::memcmp(back.ptr(), b.coefficients.ptr(), b.coefficients.total() * sizeof(float)));
}

TEST(Packing, PackUnpackBitExact) {
    // c = 23: the last block has 3 used channels; 6 blocks leave empty blocks in the grid.
    const Binding b = randomBinding(Size(37, 21), 23, 7);
    const PackLayout paper = paperPackLayout(b.gridSize, 23);
    expectBitExactRoundTrip(b, paper);
    expectBitExactRoundTrip(b, choosePackLayout(b.gridSize, 23, 40));  // layered
    const Binding portrait = randomBinding(Size(13, 40), 30, 8);
    expectBitExactRoundTrip(portrait, paperPackLayout(portrait.gridSize, 30));
}

TEST(Packing, TexelPlacementFollowsEq6) {
    const Binding b = randomBinding(Size(10, 6), 21, 9);
    const PackLayout l = paperPackLayout(b.gridSize, 21);  // B = 6, cols = ceil(sqrt(6)) = 3
    ASSERT_EQ(l.cols, 3);
    Mat packed;
    packCoefficients(b, l, packed);
    for (int j = 0; j < 21; ++j) {
        const int blk = j / 4, x = 7, y = 4;
        const Vec4f t = packed.at<Vec4f>(y + (blk / l.cols) * 6, x + (blk % l.cols) * 10);
        EXPECT_EQ(t[j % 4], b.coefficients.at<float>(j, y * 10 + x)) << "coefficient " << j;
    }
    // Coefficient 21..23 do not exist: block 5's G, B, A channels are 0.
    const Vec4f last = packed.at<Vec4f>(6 + 1, 20 + 1);
    EXPECT_EQ(last[1], 0.f);
    EXPECT_EQ(last[3], 0.f);
}

TEST(Packing, HalfFloatRoundsToNearest) {
    const Binding b = randomBinding(Size(16, 9), 9, 10);
    const PackLayout l = paperPackLayout(b.gridSize, 9);
    Mat half, back, expected;
    packCoefficients(b, l, half, CV_16F);
    ASSERT_EQ(half.type(), CV_16FC4);
    unpackCoefficients(half, l, 9, back);
    b.coefficients.convertTo(expected, CV_16F);
    expected.convertTo(expected, CV_32F);
    EXPECT_EQ(0, std::memcmp(back.ptr(), expected.ptr(), expected.total() * sizeof(float)));
}

// The position error half-float storage costs, against float32 coefficients: the paper's
// 1024x768 / 68-vertex case (grid step 4 to keep the test quick) and the nested butterfly with
// its wings stretched, in the displacement form and in the plain sum sum_j CC_j v'_j.
struct HalfError {
    double displacement, plain, maxMove, maxCoefficient;
};

static HalfError halfFloatError(const Binding& b, const std::vector<Point2f>& pose) {
    Binding h = b;
    b.coefficients.convertTo(h.coefficients, CV_16F);
    h.coefficients.convertTo(h.coefficients, CV_32F);
    Mat p32, p16;
    b.apply(pose, p32);
    h.apply(pose, p16);
    HalfError e{norm(p32, p16, NORM_INF), 0, 0, norm(b.coefficients, NORM_INF)};
    const std::vector<Point2f> full = b.completePose(pose);
    for (int j = 0; j < b.coefficientCount(); ++j)
        e.maxMove = std::max(e.maxMove, double(norm(full[j] - b.restVertices[j])));
    for (int k = 0; k < b.nodeCount(); ++k) {
        Point2d s(0, 0);
        for (int j = 0; j < b.coefficientCount(); ++j)
            s += Point2d(full[j]) * double(h.coefficients.at<float>(j, k));
        const Point2d exact(p32.at<Point2f>(k / b.gridSize.width, k % b.gridSize.width));
        e.plain = std::max(e.plain, norm(s - exact));
    }
    return e;
}

TEST(Packing, HalfFloatPositionErrorIsSmallInDisplacementForm) {
    const Multicage lotus = multicage_fixtures::lotusMulticage(Size(1024, 768), 68);
    const Multicage butterfly = multicage_testing::butterflyCage(true);
    const Binding bl = bind(lotus, MEAN_VALUE, 4), bb = bind(butterfly, MEAN_VALUE, 1);
    const HalfError el = halfFloatError(bl, multicage_fixtures::wavePose(lotus, 12.f, 0.5f));
    const HalfError eb =
        halfFloatError(bb, multicage_fixtures::stretchPolygon(butterfly, 0, 1.12f, 0.9f));
    for (const auto& [name, e] : {std::make_pair("lotus 1024x768/68, wave 12 px", el),
                                  std::make_pair("butterfly, wings x1.12 y0.9", eb)})
        std::printf(
            "half-float position error, %s (vertices moved up to %.1f px, max |CC| %.2f): "
            "displacement form %.4f px, plain form %.4f px\n",
            name, e.maxMove, e.maxCoefficient, e.displacement, e.plain);
    // Half floats carry 11 significant bits: the error is about 2^-11 * |CC| * |v' - v| summed
    // over the vertices, i.e. a small fraction of a pixel for moves of tens of pixels.
    EXPECT_LT(el.displacement, 0.05);
    EXPECT_LT(eb.displacement, 0.15);
    EXPECT_GT(el.plain, el.displacement);  // why the displacement form is used
    EXPECT_GT(eb.plain, eb.displacement);
    // The rest pose is exact in displacement form whatever the storage.
    Binding h = bl;
    bl.coefficients.convertTo(h.coefficients, CV_16F);
    h.coefficients.convertTo(h.coefficients, CV_32F);
    Mat r16;
    h.apply(std::vector<Point2f>(bl.restVertices.begin(), bl.restVertices.end() - 4), r16);
    EXPECT_EQ(norm(r16, bl.nodes(), NORM_INF), 0.0);
}

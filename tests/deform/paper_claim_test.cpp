// The paper's claim, measured: an inner polygon keeps what it encloses almost rigid when only
// the outer polygon moves.
#include <cstdlib>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "testing.hpp"

using namespace cv;
using namespace cv::multicage;

TEST(PaperClaim, InnerPolygonKeepsBodyRigidFiveTimesBetter) {
    const Mat image = multicage_testing::readSample("butterfly.jpg");
    const Multicage single = multicage_testing::butterflyCage(false);
    const Multicage multi = multicage_testing::butterflyCage(true);
    // The same outer pose for both: wings 6% wider, 20% flatter, and bent into a "V".
    std::vector<Point2f> outerPose = multicage_fixtures::stretchPolygon(single, 0, 1.06f, 0.8f);
    for (Point2f& p : outerPose) p.y -= 0.0006f * (p.x - 246) * (p.x - 246) - 12;
    std::vector<Point2f> multiPose = outerPose;
    const std::vector<Point2f> body = multi.polygon(1);
    multiPose.insert(multiPose.end(), body.begin(), body.end());  // the body polygon stays at rest

    const Binding bs = bind(single, MEAN_VALUE, 1), bm = bind(multi, MEAN_VALUE, 1);
    Mat ps, pm;
    bs.apply(outerPose, ps);
    bm.apply(multiPose, pm);
    std::vector<Point2f> rest, movedSingle, movedMulti;
    for (int y = 0; y < image.rows; ++y)
        for (int x = 0; x < image.cols; ++x)
            if (pointPolygonTest(body, Point2f(float(x), float(y)), false) > 0) {
                rest.emplace_back(float(x), float(y));
                movedSingle.push_back(ps.at<Point2f>(y, x));
                movedMulti.push_back(pm.at<Point2f>(y, x));
            }
    ASSERT_GT(rest.size(), 5000u);
    const double residualSingle = multicage_testing::similarityResidual(rest, movedSingle);
    const double residualMulti = multicage_testing::similarityResidual(rest, movedMulti);
    std::cout << "[ residual ] single cage " << residualSingle << " px, multicage " << residualMulti
              << " px, ratio " << residualSingle / residualMulti << std::endl;
    EXPECT_GE(residualSingle, 5.0 * residualMulti);

    if (const char* dir = std::getenv("MULTICAGE_DOCS_DIR")) {  // regenerate the README picture
        DeformParams params;
        params.backend = BACKEND_CPU;
        Mat outSingle, outMulti, left, right, row;
        Deformer::create(image, bs, params)->deform(outerPose, outSingle);
        Deformer::create(image, bm, params)->deform(multiPose, outMulti);
        Multicage posedSingle(image.size()), posedMulti(image.size());
        posedSingle.addPolygon(outerPose);
        posedMulti.addPolygon(outerPose);
        posedMulti.addPolygon(body);
        Mat input = image.clone();
        multi.draw(input, 2);
        posedSingle.draw(outSingle, 2);
        posedMulti.draw(outMulti, 2);
        hconcat(std::vector<Mat>{input, outSingle, outMulti}, row);
        imwriteAtomic(std::string(dir) + "/paper_claim.png", row);
    }
}

// Writes the pictures of docs/propose: for each sample photo the proposed multicage over the
// image with the segmentation tinted, and the feature-protection before/after.
// Usage: propose_docs OUTDIR [METHOD]   (built with the tests, not run by ctest)
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/multicage.hpp>

#include "fixtures.hpp"

using namespace cv::multicage;

static cv::Mat overlay(const cv::Mat& image, const cv::Mat& segmentation, const Multicage& cage) {
    cv::Mat out = image.clone(), tint(image.size(), image.type(), cv::Scalar(255, 0, 255));
    cv::Mat blended;
    cv::addWeighted(image, 0.65, tint, 0.35, 0, blended);
    if (!segmentation.empty()) blended.copyTo(out, segmentation);
    cage.draw(out, std::max(1, std::max(image.cols, image.rows) / 300));
    return out;
}

int main(int argc, char** argv) {
    if (argc < 2) {
        std::cerr << "usage: propose_docs OUTDIR [METHOD]\n";
        return 2;
    }
    const std::string out = argv[1];
    ProposeParams params;
    if (argc > 2) params.method = parseProposeMethod(argv[2]);
    const std::string dir = MULTICAGE_SAMPLES_DIR;
    for (const char* name : {"butterfly.jpg", "fruits.jpg", "messi5.jpg", "HappyFish.jpg",
                             "building.jpg", "smarties.png"}) {
        const cv::Mat image = cv::imread(dir + "/" + name, cv::IMREAD_COLOR);
        cv::Mat seg;
        proposeSegmentation(image, seg, params);
        const Multicage cage = proposeMulticage(image, params);
        std::string why;
        const bool valid = cage.validate(&why);
        std::string stem = name;
        stem = stem.substr(0, stem.find('.'));
        cv::imwrite(out + "/" + stem + "_" + proposeMethodName(params.method) + ".png",
                    overlay(image, seg, cage));
        std::cout << name << ": " << cage.polygonCount() << " polygons, " << cage.vertexCount()
                  << " vertices, " << (valid ? "valid" : "INVALID: " + why) << "\n";
    }
    return 0;
}

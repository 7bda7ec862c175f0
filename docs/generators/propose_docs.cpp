// Writes the pictures of docs/propose: for each sample photo the proposed multicage over the
// image with the segmentation tinted, and the feature-protection before/after.
// Usage: propose_docs OUTDIR [METHOD]   (docs/generators; run by hand)
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
    // Feature protection: the butterfly's outer polygon stretched, without and with the
    // polygons protectFeatures() adds; the inner polygons stay at rest.
    const cv::Mat image = cv::imread(dir + "/butterfly.jpg", cv::IMREAD_COLOR);
    ProposeParams autoParams;
    const Multicage plain = proposeMulticage(image, autoParams);
    const Multicage guarded = protectFeatures(image, plain, 0, autoParams);
    std::vector<cv::Mat> panels;
    for (const Multicage* cage : {&plain, &guarded}) {
        const std::vector<cv::Point2f> pose =
            multicage_fixtures::stretchPolygon(*cage, 0, 1.2f, 0.8f);
        DeformParams dp;
        dp.backend = BACKEND_CPU;
        dp.gridStep = 2;
        dp.borderValue = cv::Scalar(255, 255, 255);
        cv::Mat deformed;
        deformImage(image, *cage, pose, deformed, dp);
        Multicage posed(cage->imageSize());
        for (int p = 0; p < cage->polygonCount(); ++p) {
            const int offset = cage->polygonOffset(p),
                      n = static_cast<int>(cage->polygon(p).size());
            posed.addPolygon(
                std::vector<cv::Point2f>(pose.begin() + offset, pose.begin() + offset + n));
        }
        cv::Mat rest = image.clone();
        cage->draw(rest, 2);
        posed.draw(deformed, 2);
        cv::Mat row;
        cv::hconcat(rest, deformed, row);
        panels.push_back(row);
    }
    cv::Mat both;
    cv::vconcat(panels, both);
    cv::imwrite(out + "/protect_butterfly.png", both);
    std::cout << "protect: " << plain.polygonCount() << " -> " << guarded.polygonCount()
              << " polygons, " << guarded.vertexCount() << " vertices\n";
    return 0;
}

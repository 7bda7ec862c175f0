// Writes docs/animate: butterfly_flap.gif (the looped flap of samples/butterfly_flap.yml) and
// butterfly_flap_strip.jpg (six frames of it, the posed multicage drawn on each).
// Usage: animate_docs OUTDIR   (docs/generators; run by hand)
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/multicage/animate.hpp>

using namespace cv::multicage;

int main(int argc, char** argv) {
    if (argc < 2) {
        std::cerr << "usage: animate_docs OUTDIR\n";
        return 2;
    }
    const std::string out = argv[1], samples = MULTICAGE_SAMPLES_DIR;
    cv::Mat image = cv::imread(samples + "/data/butterfly.jpg", cv::IMREAD_COLOR);
    // Three quarters of the size keeps the GIF small for a README.
    cv::resize(image, image, cv::Size(), 0.75, 0.75, cv::INTER_AREA);
    const Multicage cage = Multicage::load(samples + "/butterfly_flap.yml").scaled(image.size());
    DeformParams dp;
    dp.gridStep = 2;
    cv::Ptr<Deformer> deformer = Deformer::create(image, cage, dp);
    AnimationParams params;
    params.loop = true;
    params.fps = 20;
    const AnimationStats s = renderAnimation(*deformer, cage, out + "/butterfly_flap.gif", params);
    std::cout << "butterfly_flap.gif: " << s.frames << " frames, " << s.fps()
              << " frames/s rendered\n";
    for (double t : animationFrameTimes(cage, params)) {
        const int folded =
            deformer->foldedTriangles(samplePose(cage, t, params.interpolation, true));
        if (folded > 0) std::cout << "warning: t = " << t << " folds " << folded << " triangles\n";
    }

    // The strip: six frames over one cycle, each with the posed polygons drawn on it.
    const int count = 6;
    const double period = animationDuration(cage, true);
    std::vector<cv::Mat> tiles;
    for (int i = 0; i < count; ++i) {
        const double t = animationStart(cage) + period * i / count;
        const std::vector<cv::Point2f> pose = samplePose(cage, t, params.interpolation, true);
        cv::Mat frame;
        deformer->deform(pose, frame);
        Multicage posed(image.size());
        for (int p = 0; p < cage.polygonCount(); ++p) {
            const int first = cage.polygonOffset(p), n = static_cast<int>(cage.polygon(p).size());
            posed.addPolygon(
                std::vector<cv::Point2f>(pose.begin() + first, pose.begin() + first + n));
        }
        posed.draw(frame, 1, false);
        char label[32];
        std::snprintf(label, sizeof(label), "t = %.2f s", t);
        cv::putText(frame, label, {8, frame.rows - 10}, cv::FONT_HERSHEY_SIMPLEX, 0.5,
                    cv::Scalar::all(255), 1, cv::LINE_AA);
        cv::copyMakeBorder(frame, frame, 2, 2, 2, 2, cv::BORDER_CONSTANT, cv::Scalar::all(255));
        tiles.push_back(frame);
    }
    cv::Mat top, bottom, strip;
    cv::hconcat(std::vector<cv::Mat>(tiles.begin(), tiles.begin() + 3), top);
    cv::hconcat(std::vector<cv::Mat>(tiles.begin() + 3, tiles.end()), bottom);
    cv::vconcat(top, bottom, strip);
    imwriteAtomic(out + "/butterfly_flap_strip.jpg", strip, {cv::IMWRITE_JPEG_QUALITY, 88});
    std::cout << "butterfly_flap_strip.jpg: " << strip.cols << "x" << strip.rows << "\n";
    return 0;
}

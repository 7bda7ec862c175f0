// The README's example: bind an image to a multicage once, deform it to a pose, save it.
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/multicage.hpp>

int main(int argc, char** argv) {
    using namespace cv::multicage;
    if (argc != 3) return 2;  // usage: deform_example IMAGE OUT.png
    cv::Mat image;
    try {
        image =
            readImage(argv[1], cv::IMREAD_COLOR);  // as the CLI reads: a cut JPEG or PNG is refused
    } catch (const cv::Exception& e) {
        std::fprintf(stderr, "deform_example: %s\n", e.err.c_str());
        return 1;
    }
    Multicage cage(image.size());
    cv::Point2f c(image.cols / 2.f, image.rows / 2.f);
    float a = image.rows * 0.4f, b = image.rows * 0.15f;
    cage.addPolygon(std::vector<cv::Point2f>{c + cv::Point2f(-a, -a), c + cv::Point2f(a, -a),
                                             c + cv::Point2f(a, a), c + cv::Point2f(-a, a)});
    cage.addPolygon(std::vector<cv::Point2f>{c + cv::Point2f(-b, -b), c + cv::Point2f(b, -b),
                                             c + cv::Point2f(b, b), c + cv::Point2f(-b, b)});
    cage.orient();  // the orientation rule; users never care

    std::vector<cv::Point2f> pose = cage.vertices();  // rest positions, frame last
    pose[1].x += 30;                                  // pull the outer polygon's top-right corner
    pose[2] += cv::Point2f(20, 20);
    cv::Mat out;
    deformImage(image, cage, pose, out);  // the inner square stays intact
    return cv::imwrite(argv[2], out) ? 0 : 1;
}

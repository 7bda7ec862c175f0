#include "eyes.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/objdetect.hpp>

namespace cv {
namespace multicage {
namespace propose_detail {

namespace {

const char* const kEyeCascades[] = {"haarcascade_eye.xml", "haarcascade_eye_tree_eyeglasses.xml"};

// The face is searched at this width: the cascades' 20 px window then sees eyes of 12-45%
// of the face, and a large face costs no more than a small one. On the 117 faces of
// docs/faces/README.md ("Eyes") 160 found 74 pairs, 120 found 61 (glasses, half-closed eyes),
// and neither a false one.
constexpr int kSearchWidth = 160;

// One classifier per cascade file, for the process; detectMultiScale keeps per-image state,
// so a search holds the lock (25-35 ms a cascade on a face, one core).
struct EyeCascade {
    std::mutex mutex;
    CascadeClassifier classifier;
};

EyeCascade* eyeCascade(const std::string& path) {
    static std::mutex mutex;
    static std::map<std::string, std::unique_ptr<EyeCascade>> loaded;
    std::lock_guard<std::mutex> lock(mutex);
    std::unique_ptr<EyeCascade>& c = loaded[path];
    if (!c) {
        c = std::make_unique<EyeCascade>();
        if (!c->classifier.load(path))
            CV_Error_(Error::StsParseError,
                      ("multicage: cannot read the eye cascade %s (reinstall opencv-data)",
                       path.c_str()));
    }
    return c.get();
}

Point2d centre(const Rect2d& r) {
    return Point2d(r.x + 0.5 * r.width, r.y + 0.5 * r.height);
}

// How unlike a pair of eyes two detections are (face pixels, relative to the face's top left
// corner), or a negative number when they cannot be one: see findEyes.
double pairCost(const Rect2d& a, const Rect2d& b, const Size& face) {
    const Point2d ca = centre(a), cb = centre(b);
    const double dx = cb.x - ca.x, dy = std::abs(cb.y - ca.y);
    const double w = face.width, h = face.height;
    if (!(ca.x < 0.5 * w && cb.x > 0.5 * w)) return -1;
    if (dx < 0.25 * w || dx > 0.55 * w || dy > 0.25 * dx) return -1;
    for (double y : {ca.y, cb.y})
        if (y < 0.15 * h || y > 0.6 * h) return -1;
    const double big = std::max(a.width, b.width), small = std::min(a.width, b.width);
    // A face turned a little shows its far eye smaller: within 1.4 times (eyes.hpp).
    if (big > 1.4 * small) return -1;
    // Symmetric about the face's middle, level, alike.
    return std::abs(0.5 * (ca.x + cb.x) - 0.5 * w) / w + dy / dx + (big - small) / big;
}

// The detections (relative to the face's top left corner) that look most like a pair of eyes,
// left first, in input pixels; empty when no two can be one.
std::vector<Rect> bestPair(const std::vector<Rect2d>& found, const Rect& face) {
    double best = HUGE_VAL;
    std::vector<Rect> pair;
    for (const Rect2d& a : found)
        for (const Rect2d& b : found) {
            const double cost = pairCost(a, b, face.size());
            if (cost < 0 || cost >= best) continue;
            best = cost;
            pair.clear();
            for (const Rect2d& e : {a, b})
                pair.push_back(Rect(cvRound(face.x + e.x), cvRound(face.y + e.y), cvRound(e.width),
                                    cvRound(e.height)));
        }
    return pair;
}

}  // namespace

std::vector<Rect> findEyes(const Mat& gray, const Rect& face, const ProposeParams& params) {
    CV_Assert(gray.type() == CV_8UC1);
    if (face.width < kEyeFaceMin) return {};
    const String frontal = faceCascadeFile(params);
    if (frontal.empty()) return {};
    const std::filesystem::path dir = std::filesystem::path(frontal).parent_path();
    // The eyes are in the upper 60% of a cascade's face box.
    const Rect upper =
        Rect(face.x, face.y, face.width, cvRound(0.6 * face.height)) & Rect(Point(), gray.size());
    if (upper.width < face.width / 2 || upper.height < face.height / 4) return {};
    const double k = kSearchWidth / static_cast<double>(face.width);
    Mat crop;
    resize(gray(upper), crop, Size(), k, k, k < 1 ? INTER_AREA : INTER_LINEAR);
    equalizeHist(crop, crop);
    // Both cascades, always. Running the glasses cascade only where the plain one finds no
    // pair gives the same 74 pairs on the 117 faces in half the time (31 ms a face instead of
    // 58, one thread, loaded machine), but the plain cascade's boxes alone sit off some eyes:
    // megamind_closeup's right eye was then held at 87% by its polygon, not 100%.
    // The two cascades search side by side (a second core halves the wall time of the search),
    // each into its own slot, and their boxes are joined in a fixed order: the same pair on any
    // number of threads.
    constexpr int kCascades = sizeof(kEyeCascades) / sizeof(kEyeCascades[0]);
    std::vector<Rect> eyes[kCascades];
    parallel_for_(Range(0, kCascades), [&](const Range& range) {
        for (int i = range.start; i < range.end; ++i) {
            std::error_code ec;
            const std::filesystem::path path = dir / kEyeCascades[i];
            if (!std::filesystem::is_regular_file(path, ec)) continue;
            EyeCascade* c = eyeCascade(path.string());
            std::lock_guard<std::mutex> lock(c->mutex);
            // Scale steps of 5% and 2 agreeing windows: eyes are small and few windows see
            // them (steps of 10%: 64 pairs of 74); the pair test throws out what this lets
            // through.
            c->classifier.detectMultiScale(
                crop, eyes[i], 1.05, 2, CASCADE_SCALE_IMAGE,
                Size(cvRound(0.12 * kSearchWidth), cvRound(0.12 * kSearchWidth)),
                Size(cvRound(0.45 * kSearchWidth), cvRound(0.45 * kSearchWidth)));
        }
    });
    std::vector<Rect2d> found;
    for (const std::vector<Rect>& boxes : eyes)
        for (const Rect& e : boxes)
            found.emplace_back(e.x / k + (upper.x - face.x), e.y / k + (upper.y - face.y),
                               e.width / k, e.height / k);
    const std::vector<Rect> pair = bestPair(found, face);
    if (std::getenv("MULTICAGE_DEBUG_EYES")) {
        std::fprintf(stderr, "eyes: face %d,%d %dx%d:", face.x, face.y, face.width, face.height);
        for (const Rect2d& e : found) std::fprintf(stderr, " [%.0f,%.0f %.0f]", e.x, e.y, e.width);
        std::fprintf(stderr, " -> %s\n", pair.empty() ? "no pair" : "a pair");
    }
    return pair;
}

Polygon eyePolygon(const Rect2d& eye, double margin) {
    const Point2d c(eye.x + 0.5 * eye.width - 0.5, eye.y + 0.5 * eye.height - 0.5);
    const double a = 0.42 * eye.width + margin, b = 0.3 * eye.height + margin;
    Polygon p;
    for (int i = 0; i < kEyeVertices; ++i) {
        // Vertices on the ellipse, the polygon's edges cut inside it: the ellipse through
        // the vertices is grown by 1/cos(pi/n) so that the edges stay outside the eye's.
        const double t = 2 * CV_PI * i / kEyeVertices, grow = 1.0 / std::cos(CV_PI / kEyeVertices);
        p.emplace_back(static_cast<float>(c.x + grow * a * std::cos(t)),
                       static_cast<float>(c.y + grow * b * std::sin(t)));
    }
    return p;  // t grows clockwise on screen (y down): signed area > 0
}

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv

// Face detection for protectFeatures(PROTECT_FACES / PROTECT_ALL): OpenCV's Haar cascades
// (Debian package opencv-data), loaded once per file and shared (detection is serialised per
// cascade: CascadeClassifier keeps per-image state).
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <opencv2/multicage/propose.hpp>
#include <opencv2/objdetect.hpp>

#include "segment.hpp"

namespace cv {
namespace multicage {

namespace {

const char* const kFrontal = "haarcascade_frontalface_alt2.xml";
const char* const kProfile = "haarcascade_profileface.xml";
const char* const kEye = "haarcascade_eye.xml";

std::string findCascade(const ProposeParams& params, const char* name) {
    namespace fs = std::filesystem;
    std::vector<std::string> dirs;
    if (!params.cascadeDir.empty()) {
        dirs.push_back(params.cascadeDir);  // the caller's word: only there
    } else {
        dirs.push_back(MULTICAGE_DEBIAN_CASCADE_DIR);
        dirs.push_back("/usr/share/opencv/haarcascades");
    }
    for (const std::string& d : dirs) {
        std::error_code ec;
        const fs::path p = fs::path(d) / name;
        if (fs::is_regular_file(p, ec)) return p.string();
    }
    return {};
}

struct Cascade {
    std::mutex mutex;
    CascadeClassifier classifier;
};

// The cascade `name`, loaded once; null when not installed. Throws when `required`.
std::shared_ptr<Cascade> cascade(const ProposeParams& params, const char* name, bool required) {
    static std::mutex mutex;
    static std::map<std::string, std::shared_ptr<Cascade>> cache;
    const std::string path = findCascade(params, name);
    if (path.empty()) {
        if (!required) return nullptr;
        CV_Error_(Error::StsObjectNotFound,
                  ("multicage: no face cascade %s in %s: the Debian package opencv-data "
                   "provides it (apt-get install opencv-data), or set the cascade folder",
                   name, params.cascadeDir.empty() ? MULTICAGE_DEBIAN_CASCADE_DIR
                                                   : params.cascadeDir.c_str()));
    }
    std::lock_guard<std::mutex> lock(mutex);
    std::shared_ptr<Cascade>& c = cache[path];
    if (!c) {
        auto fresh = std::make_shared<Cascade>();
        if (!fresh->classifier.load(path))
            CV_Error_(Error::StsParseError,
                      ("multicage: cannot read the face cascade %s (reinstall opencv-data)",
                       path.c_str()));
        c = fresh;
    }
    return c;
}

std::vector<Rect> detect(Cascade& c, const Mat& gray, int minNeighbors, Size minSize) {
    std::vector<Rect> found;
    std::lock_guard<std::mutex> lock(c.mutex);
    c.classifier.detectMultiScale(gray, found, 1.1, minNeighbors, CASCADE_SCALE_IMAGE, minSize);
    return found;
}

// Rectangles that overlap, merged into their bounding boxes until none overlap.
std::vector<Rect> mergeOverlapping(std::vector<Rect> rects) {
    for (bool merged = true; merged;) {
        merged = false;
        for (size_t i = 0; i < rects.size() && !merged; ++i)
            for (size_t j = i + 1; j < rects.size() && !merged; ++j)
                if ((rects[i] & rects[j]).area() > 0) {
                    rects[i] |= rects[j];
                    rects.erase(rects.begin() + static_cast<long>(j));
                    merged = true;
                }
    }
    std::sort(rects.begin(), rects.end(), [](const Rect& a, const Rect& b) { return a.area() > b.area(); });
    return rects;
}

}  // namespace

String faceCascadeFile(const ProposeParams& params) { return findCascade(params, kFrontal); }

std::vector<Rect> detectFaces(InputArray image, const ProposeParams& params) {
    const Mat img = image.getMat();
    if (img.empty()) CV_Error(Error::StsBadArg, "multicage: detectFaces: the image is empty");
    const std::shared_ptr<Cascade> frontal = cascade(params, kFrontal, true);
    const std::shared_ptr<Cascade> profile = cascade(params, kProfile, false);
    Mat gray = propose_detail::to8Bit(img);
    if (gray.channels() == 3) cvtColor(gray, gray, COLOR_BGR2GRAY);
    if (gray.channels() == 4) cvtColor(gray, gray, COLOR_BGRA2GRAY);
    const int longer = std::max(img.cols, img.rows);
    const double scale = params.faceWorkingSize > 0 && longer > params.faceWorkingSize
                             ? longer / static_cast<double>(params.faceWorkingSize)
                             : 1.0;
    if (scale > 1.0)
        resize(gray, gray, Size(cvRound(img.cols / scale), cvRound(img.rows / scale)), 0, 0,
               INTER_AREA);
    equalizeHist(gray, gray);
    std::vector<Rect> found = detect(*frontal, gray, 3, Size(24, 24));
    if (profile) {
        for (const Rect& r : detect(*profile, gray, 4, Size(24, 24))) found.push_back(r);
        Mat flipped;
        flip(gray, flipped, 1);  // the profile cascade knows faces looking one way
        for (const Rect& r : detect(*profile, flipped, 4, Size(24, 24)))
            found.emplace_back(gray.cols - r.x - r.width, r.y, r.width, r.height);
    }
    if (params.faceEyes && !found.empty()) {
        const std::shared_ptr<Cascade> eye = cascade(params, kEye, true);
        std::vector<Rect> confirmed;
        for (const Rect& f : found) {
            const Rect upper = Rect(f.x, f.y, f.width, f.height * 6 / 10) & Rect(Point(), gray.size());
            const int least = std::max(8, f.width / 8);
            if (!detect(*eye, gray(upper), 3, Size(least, least)).empty()) confirmed.push_back(f);
        }
        found.swap(confirmed);
    }
    for (Rect& r : found) {
        const Rect2d s(r.x * scale, r.y * scale, r.width * scale, r.height * scale);
        r = Rect(Point(cvFloor(s.x), cvFloor(s.y)), Point(cvCeil(s.br().x), cvCeil(s.br().y))) &
            Rect(Point(), img.size());
    }
    return mergeOverlapping(found);
}

const char* protectDetectorName(int detector) {
    static const char* names[] = {"saliency", "faces", "all"};
    return detector >= PROTECT_SALIENCY && detector <= PROTECT_ALL ? names[detector] : "unknown";
}

int parseProtectDetector(const String& name) {
    for (int d = PROTECT_SALIENCY; d <= PROTECT_ALL; ++d)
        if (name == protectDetectorName(d)) return d;
    return -1;
}

}  // namespace multicage
}  // namespace cv

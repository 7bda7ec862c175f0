// Face detection for protectFeatures(PROTECT_FACES / PROTECT_ALL): OpenCV's Haar cascades
// (Debian package opencv-data), and the polygon a face gets (faces.hpp).
#include "faces.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <numeric>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/multicage/internal/geometry.hpp>
#include <opencv2/objdetect.hpp>
#include <tuple>

#include "segment.hpp"

namespace cv {
namespace multicage {

namespace {

const char* const kFrontal = "haarcascade_frontalface_alt2.xml";
const char* const kProfile = "haarcascade_profileface.xml";
const char* const kEye = "haarcascade_eye.xml";

// The cascades' own window: the smallest face a search finds, in pixels of its copy.
constexpr int kLeastFace = 24;

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

// The classifiers of one cascade file. detectMultiScale keeps per-image state in the
// classifier, so each search borrows one of its own; classifiers are loaded once per process
// and kept (a second one is loaded only when two searches overlap, as the profile cascade's
// two directions do).
class CascadePool {
  public:
    explicit CascadePool(std::string path) : path_(std::move(path)) {}

    std::unique_ptr<CascadeClassifier> borrow() {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            if (!idle_.empty()) {
                std::unique_ptr<CascadeClassifier> c = std::move(idle_.back());
                idle_.pop_back();
                return c;
            }
        }
        auto c = std::make_unique<CascadeClassifier>();
        if (!c->load(path_))
            CV_Error_(Error::StsParseError,
                      ("multicage: cannot read the face cascade %s (reinstall opencv-data)",
                       path_.c_str()));
        return c;
    }

    void giveBack(std::unique_ptr<CascadeClassifier> c) {
        std::lock_guard<std::mutex> lock(mutex_);
        idle_.push_back(std::move(c));
    }

  private:
    const std::string path_;
    std::mutex mutex_;
    std::vector<std::unique_ptr<CascadeClassifier>> idle_;
};

// The pool of cascade `name`; null when it is not installed. Throws when `required`.
CascadePool* cascade(const ProposeParams& params, const char* name, bool required) {
    static std::mutex mutex;
    static std::map<std::string, std::unique_ptr<CascadePool>> pools;
    const std::string path = findCascade(params, name);
    if (path.empty()) {
        if (!required) return nullptr;
        CV_Error_(
            Error::StsObjectNotFound,
            ("multicage: no face cascade %s in %s: the Debian package opencv-data "
             "provides it (apt-get install opencv-data), or set the cascade folder",
             name,
             params.cascadeDir.empty() ? MULTICAGE_DEBIAN_CASCADE_DIR : params.cascadeDir.c_str()));
    }
    std::lock_guard<std::mutex> lock(mutex);
    std::unique_ptr<CascadePool>& pool = pools[path];
    if (!pool) pool = std::make_unique<CascadePool>(path);
    return pool.get();
}

// One cascade run over a copy of the image (mirrored for the profile cascade's other direction).
struct Search {
    CascadePool* pool;
    bool frontal, mirrored;
    int copy = 0;    // which copy: 0 the working copy, 1 the larger one for small faces
    Size maxSize{};  // the largest face it looks for (empty: no limit)
    std::unique_ptr<CascadeClassifier> classifier;
    std::vector<Rect> found;
    std::vector<int> windows;  // how many windows of the search agreed on each face found
};

void run(Search& s, const Mat& gray, const Mat& mirrored) {
    const Mat& img = s.mirrored ? mirrored : gray;
    // Scale steps of 20% (half the pyramid levels of OpenCV's sample's 10%: 40% less time),
    // a face where at least 2 windows agree, and the cascades' own 24 pixels as the smallest
    // face. What the coarser search lets through in a colour photo the skin test throws out;
    // on the samples it finds the faces of messi5.jpg, astronaut.png and camera.png, and none
    // on the five other photos.
    s.classifier->detectMultiScale(img, s.found, s.windows, 1.2, 2, CASCADE_SCALE_IMAGE,
                                   Size(kLeastFace, kLeastFace), s.maxSize);
    if (s.mirrored)
        for (Rect& r : s.found) r.x = img.cols - r.x - r.width;
    // A search on several threads finds the same faces in an order that depends on the
    // threads: give them one, so that a proposal does not.
    std::vector<size_t> order(s.found.size());
    std::iota(order.begin(), order.end(), size_t(0));
    auto key = [&](size_t i) {
        const Rect& r = s.found[i];
        return std::make_tuple(r.y, r.x, r.height, r.width, s.windows[i]);
    };
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return key(a) < key(b); });
    std::vector<Rect> found;
    std::vector<int> windows;
    for (size_t i : order) found.push_back(s.found[i]), windows.push_back(s.windows[i]);
    s.found = std::move(found), s.windows = std::move(windows);
}

// True when the image has colour (not grey stored in three channels): mean chroma distance
// from grey above 2 levels.
bool hasColour(const Mat& ycrcb) {
    Mat deviation;
    absdiff(ycrcb, Scalar(0, 128, 128), deviation);
    const Scalar d = mean(deviation);
    return d[1] + d[2] > 2.0;
}

// In a colour photo the middle of a face is skin: Chai and Ngan's (1999) YCrCb box
// (133 <= Cr <= 173, 77 <= Cb <= 127), and clearly reddish (Cr - Cb >= 12, not grey). Haar
// cascades also fire on crowds and clothing: on messi5.jpg a 78x78 box on the shoulder has
// 10% skin in its middle, the face 99%.
bool skinInMiddle(const Mat& ycrcb, const Rect& box) {
    const Rect middle = Rect(box.x + box.width / 4, box.y + box.height / 4,
                             std::max(1, box.width / 2), std::max(1, box.height / 2)) &
                        Rect(Point(), ycrcb.size());
    if (middle.empty()) return false;
    int skin = 0;
    for (int y = middle.y; y < middle.br().y; ++y) {
        const Vec3b* p = ycrcb.ptr<Vec3b>(y);
        for (int x = middle.x; x < middle.br().x; ++x) {
            const int cr = p[x][1], cb = p[x][2];
            skin += cr >= 133 && cr <= 173 && cb >= 77 && cb <= 127 && cr - cb >= 12;
        }
    }
    return skin >= 0.3 * middle.area();
}

// Two detections are one face when they share at least this much of the smaller box: the
// frontal and the mirrored profile cascade's boxes of messi5's face share 36% (at the search's
// 320 px); a man's face behind a woman's in a Megamind frame touched her profile box (7% of
// his), and the two merged into one box over both heads, whose person prior (person.cpp) put
// a body 3.6 such boxes wide under it and the outline on the frame.
constexpr double kSameFace = 0.25;

// Detections of one face merged into their bounding boxes until no two are one face.
std::vector<Rect> mergeOverlapping(std::vector<Rect> rects) {
    auto sameFace = [](const Rect& a, const Rect& b) {
        return (a & b).area() >= kSameFace * std::min(a.area(), b.area()) && (a & b).area() > 0;
    };
    for (bool merged = true; merged;) {
        merged = false;
        for (size_t i = 0; i < rects.size() && !merged; ++i)
            for (size_t j = i + 1; j < rects.size() && !merged; ++j)
                if (sameFace(rects[i], rects[j])) {
                    rects[i] |= rects[j];
                    rects.erase(rects.begin() + static_cast<long>(j));
                    merged = true;
                }
    }
    std::sort(rects.begin(), rects.end(),
              [](const Rect& a, const Rect& b) { return a.area() > b.area(); });
    return rects;
}

// True when the eye cascade finds an eye in the upper part of a face.
bool eyeIn(CascadeClassifier& eye, const Mat& gray, const Rect& face) {
    const Rect upper =
        Rect(face.x, face.y, face.width, face.height * 6 / 10) & Rect(Point(), gray.size());
    const int least = std::max(8, face.width / 8);
    std::vector<Rect> eyes;
    eye.detectMultiScale(gray(upper), eyes, 1.1, 3, CASCADE_SCALE_IMAGE, Size(least, least));
    return !eyes.empty();
}

// A frontal face in a photo without colour, where no skin test can refuse what the cascade
// finds on a pattern, stands when this many of the search's windows agree on it or an eye is
// found in it. Measured on grey copies (320 px, as searched): the false faces on a coin
// (scikit-image's coins.png), a box of tea (OpenCV's box_in_scene.png), a grey 3D head and a
// chessboard had 3-4 windows and no eye; the real ones 6-18 (astronaut, messi5, Grace
// Hopper, Megamind frames), except a cartoon face with closed eyes at 4 and one at 4 whose
// eye is found. Profile faces keep the cascade's word: the eye cascade knows frontal eyes
// only, and the camera man's profile (skimage's camera.png) has 3-4 windows.
constexpr int kGreyFrontalWindows = 5;

// A search's box around a face is sometimes a head and what it holds (the camera man's profile
// and his camera, 1.9 times the face's width): a box that holds at least 90% of another one at
// most half its area, on which at least as many windows agreed, is that face's too large box,
// and only the smaller one stands. (Boxes merged instead grow to the larger one.)
bool holdsASmallerSurerFace(const std::vector<Rect>& boxes, const std::vector<int>& windows,
                            size_t b) {
    for (size_t i = 0; i < boxes.size(); ++i)
        if (i != b && 2 * boxes[i].area() <= boxes[b].area() &&
            (boxes[i] & boxes[b]).area() >= 0.9 * boxes[i].area() && windows[i] >= windows[b])
            return true;
    return false;
}

}  // namespace

String faceCascadeFile(const ProposeParams& params) {
    return findCascade(params, kFrontal);
}

namespace propose_detail {

// A grey, histogram-equalised copy of the image (and its mirror image for the profile
// searches, and its colours where it has any) that cascades search.
struct Copy {
    double scale = 1.0;  // input pixels per pixel of the copy
    Mat gray, mirrored, ycrcb;
};

// `longest`: the copy's longer side; 0 for the image's own size; a larger one enlarges it.
Copy makeCopy(const Mat& img8, int longest, bool mirrored) {
    Copy c;
    Mat small = img8;
    const int longer = std::max(img8.cols, img8.rows);
    c.scale = longest > 0 ? longer / static_cast<double>(longest) : 1.0;
    if (c.scale != 1.0)  // (a side of a thin image keeps at least a pixel)
        resize(img8, small,
               Size(std::max(1, cvRound(img8.cols / c.scale)),
                    std::max(1, cvRound(img8.rows / c.scale))),
               0, 0, c.scale > 1.0 ? INTER_AREA : INTER_LINEAR);
    if (small.channels() == 3) {
        cvtColor(small, c.gray, COLOR_BGR2GRAY);
        cvtColor(small, c.ycrcb, COLOR_BGR2YCrCb);
        if (!hasColour(c.ycrcb)) c.ycrcb.release();
    } else {
        c.gray = small;
    }
    equalizeHist(c.gray, c.gray);
    if (mirrored) flip(c.gray, c.mirrored, 1);
    return c;
}

struct FaceSearch::State {
    ProposeParams params;
    Size size;                     // the input's
    std::vector<Copy> copies;      // the working copy; the larger one for small faces, if any
    std::vector<Search> searches;  // the frontal search, the profile cascade's two, small faces
    std::vector<std::vector<Rect>> kept;  // what stands of each search's faces (its copy's pixels)
    std::vector<std::vector<int>> keptWindows;  // and how many windows agreed on each

    // Whether a face search `s` found stands: in a colour photo its middle is skin; in a grey
    // one a frontal face needs kGreyFrontalWindows windows or an eye; with faceEyes, an eye.
    bool stands(const Search& s, size_t i) const {
        const Rect& r = s.found[i];
        const Mat& gray = copies[s.copy].gray;
        const Mat& ycrcb = copies[s.copy].ycrcb;
        CascadePool* eyes = nullptr;
        auto eyeFound = [&] {
            if (!eyes && !(eyes = cascade(params, kEye, params.faceEyes))) return false;
            std::unique_ptr<CascadeClassifier> eye = eyes->borrow();
            const bool found = eyeIn(*eye, gray, r);
            eyes->giveBack(std::move(eye));
            return found;
        };
        const bool kept = !ycrcb.empty()
                              ? skinInMiddle(ycrcb, r)
                              : !s.frontal || s.windows[i] >= kGreyFrontalWindows || eyeFound();
        return kept && (!params.faceEyes || eyeFound());
    }

    void search(size_t k) {
        Search& s = searches[k];
        run(s, copies[s.copy].gray, copies[s.copy].mirrored);
        s.pool->giveBack(std::move(s.classifier));
        for (size_t i = 0; i < s.found.size(); ++i)
            if (stands(s, i)) kept[k].push_back(s.found[i]), keptWindows[k].push_back(s.windows[i]);
    }
};

FaceSearch::FaceSearch(InputArray image, const ProposeParams& params)
    : state_(std::make_unique<State>()) {
    State& st = *state_;
    const Mat img = image.getMat();
    if (img.empty()) CV_Error(Error::StsBadArg, "multicage: detectFaces: the image is empty");
    st.params = params;
    st.size = img.size();
    CascadePool* frontal = cascade(params, kFrontal, true);
    st.searches.push_back({frontal, true, false});
    if (CascadePool* profile = cascade(params, kProfile, false)) {
        // The profile cascade knows faces looking one way: the mirror image finds the others.
        st.searches.push_back({profile, false, false});
        st.searches.push_back({profile, false, true});
    }
    const Mat img8 = propose_detail::to8Bit(img);
    const int longer = std::max(img.cols, img.rows);
    const int working = params.faceWorkingSize > 0 ? std::min(longer, params.faceWorkingSize) : 0;
    st.copies.push_back(makeCopy(img8, working, true));
    // Faces under the working copy's least face (a full figure's, a group's): the frontal
    // cascade on a copy twice as large, for those faces only. It is enlarged where the image is
    // smaller, up to the default's 640 px (so that what is found does not depend on the image's
    // size), not beyond the image for a larger working size.
    const int large = std::min(2 * working, std::max(longer, 2 * ProposeParams().faceWorkingSize));
    const int most = working > 0 ? cvCeil(kLeastFace * large / double(working)) - 1 : 0;
    if (most > kLeastFace) {
        st.copies.push_back(makeCopy(img8, large, false));  // frontal only
        Search small{frontal, true, false};
        small.copy = 1, small.maxSize = Size(most, most);
        st.searches.push_back(std::move(small));
    }
    for (Search& s : st.searches) s.classifier = s.pool->borrow();  // load errors first
    st.kept.resize(st.searches.size());
    st.keptWindows.resize(st.searches.size());
}

FaceSearch::~FaceSearch() {
    for (Search& s : state_->searches)  // the searches never run
        if (s.classifier) s.pool->giveBack(std::move(s.classifier));
}

bool FaceSearch::frontal() {
    // On every core: detectMultiScale shares its scales out between threads.
    state_->search(0);
    return !state_->kept[0].empty();
}

Tasks FaceSearch::remaining(bool profiles) {
    Tasks tasks;
    State& st = *state_;
    for (size_t k = 1; k < st.searches.size(); ++k)  // the small faces' first: the largest copy
        if (st.searches[k].copy == 1) tasks.push_back([&st, k] { st.search(k); });
    for (size_t k = 1; k < st.searches.size() && profiles; ++k)
        if (!st.searches[k].frontal) tasks.push_back([&st, k] { st.search(k); });
    return tasks;
}

std::vector<Rect> FaceSearch::faces() const {
    const State& st = *state_;
    std::vector<Rect> boxes;  // input pixels
    std::vector<int> windows;
    std::vector<char> small;  // found on the larger copy
    for (size_t k = 0; k < st.searches.size(); ++k)
        for (size_t i = 0; i < st.kept[k].size(); ++i) {
            const Rect& r = st.kept[k][i];
            const double scale = st.copies[st.searches[k].copy].scale;
            const Rect2d s(r.x * scale, r.y * scale, r.width * scale, r.height * scale);
            boxes.push_back(
                Rect(Point(cvFloor(s.x), cvFloor(s.y)), Point(cvCeil(s.br().x), cvCeil(s.br().y))) &
                Rect(Point(), st.size));
            windows.push_back(st.keptWindows[k][i]);
            small.push_back(st.searches[k].copy == 1);
        }
    // A small face where the working copy's searches found one is that face, seen smaller.
    for (size_t b = boxes.size(); b-- > 0;) {
        bool seen = false;
        for (size_t o = 0; o < boxes.size() && small[b] && !seen; ++o)
            seen = !small[o] && (boxes[o] & boxes[b]).area() > 0;
        if (seen) boxes.erase(boxes.begin() + long(b)), windows.erase(windows.begin() + long(b));
    }
    std::vector<Rect> found;
    for (size_t b = 0; b < boxes.size(); ++b)
        if (!holdsASmallerSurerFace(boxes, windows, b)) found.push_back(boxes[b]);
    return mergeOverlapping(found);
}

}  // namespace propose_detail

std::vector<Rect> detectFaces(InputArray image, const ProposeParams& params) {
    // The frontal search on every core, then the others one core each (runTasks). The frontal
    // one alone first: three side by side, where one core ran two of them, took longer on 2
    // cores (90-148 ms against 80-131 ms at 320 px).
    propose_detail::FaceSearch search(image, params);
    search.frontal();
    propose_detail::runTasks(search.remaining(true));
    return search.faces();
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

namespace propose_detail {

double faceMargin(const Rect& face) {
    return std::max(2.0, 0.02 * std::max(face.width, face.height));
}

namespace {

// The superellipse |x|^8 + |y|^8 = 1 at `vertices` parameters t, one on each diagonal.
std::vector<Point2d> unitFace(int vertices) {
    const double phase = std::fmod(vertices / 8.0, 1.0);  // i + phase = n / 8 lands on 45 degrees
    auto along = [](double cs) {
        return std::copysign(std::pow(std::abs(cs), 2.0 / kFaceExponent), cs);
    };
    std::vector<Point2d> u;
    for (int i = 0; i < vertices; ++i) {
        const double t = 2 * CV_PI * (i + phase) / vertices;
        u.emplace_back(along(std::cos(t)), along(std::sin(t)));
    }
    return u;
}

// The point of the boundary of `polygon` nearest to `v`.
Point2d nearestOnBoundary(const std::vector<Point2f>& polygon, Point2d v) {
    Point2d best = polygon[0];
    double least = HUGE_VAL;
    for (size_t i = 0; i < polygon.size(); ++i) {
        const Point2d q =
            geometry::nearestOnSegment(v, polygon[i], polygon[(i + 1) % polygon.size()]);
        if (norm(q - v) < least) least = norm(q - v), best = q;
    }
    return best;
}

}  // namespace

std::vector<Point2f> facePolygon(const Rect2d& detected, double margin, int vertices) {
    return facePolygon(detected, Vec4d::all(margin), vertices);
}

std::vector<Point2f> facePolygon(const Rect2d& detected, const Vec4d& margins, int vertices) {
    CV_Assert(vertices >= 4 && vertices % 4 == 0);
    // The frontal cascade's box runs from the brow to the lower lip; the polygon takes in the
    // forehead and the chin, which an outline hugging the head (the subject model's) would
    // otherwise stretch with the hair.
    const Rect2d box(detected.x, detected.y - kFaceForehead * detected.height, detected.width,
                     detected.height * (1 + kFaceForehead + kFaceChin));
    // The superellipse |x/a|^8 + |y/b|^8 = 1 through the box's corners has semi-axes 2^(1/8)
    // times the half sides, and its point at parameter t = 45 degrees is the corner.
    const double k = std::pow(2.0, 1.0 / kFaceExponent);
    const double left = k * 0.5 * box.width + margins[0], top = k * 0.5 * box.height + margins[1],
                 right = k * 0.5 * box.width + margins[2],
                 bottom = k * 0.5 * box.height + margins[3];
    const Point2d c(box.x + 0.5 * box.width - 0.5, box.y + 0.5 * box.height - 0.5);
    std::vector<Point2f> p;
    for (const Point2d& u : unitFace(vertices))
        p.emplace_back(static_cast<float>(c.x + (u.x < 0 ? left : right) * u.x),
                       static_cast<float>(c.y + (u.y < 0 ? top : bottom) * u.y));
    return p;  // t grows clockwise on screen (y down): signed area > 0
}

std::vector<Point2f> faceInOutline(const Rect2d& box, double margin, int vertices,
                                   const std::vector<Point2f>& outline, double band,
                                   const std::function<bool(const std::vector<Point2f>&)>& fits) {
    const double step = 0.25 * margin;
    const std::vector<Point2d> unit = unitFace(vertices);
    Vec4d margins = Vec4d::all(margin);
    for (;;) {
        std::vector<Point2f> p = facePolygon(box, margins, vertices);
        if (fits(p)) return p;
        // For each vertex too near, the side whose pull moves it away from the outline's
        // nearest point (the one facing that point); where those have no margin left, the
        // sides of its quarter (a corner's two); where none is near (another polygon refused
        // it), every side.
        bool facing[4] = {false, false, false, false}, quarter[4] = {false, false, false, false};
        for (int i = 0; i < vertices; ++i) {  // sides: left, top, right, bottom
            if (pointPolygonTest(outline, p[i], true) >= band) continue;
            const Point2d u = unit[i], d = nearestOnBoundary(outline, p[i]) - Point2d(p[i]);
            if (std::abs(d.x) >= std::abs(d.y) && d.x * u.x > 0) facing[d.x < 0 ? 0 : 2] = true;
            if (std::abs(d.y) >= std::abs(d.x) && d.y * u.y > 0) facing[d.y < 0 ? 1 : 3] = true;
            if (std::abs(u.x) > 0.5) quarter[u.x < 0 ? 0 : 2] = true;
            if (std::abs(u.y) > 0.5) quarter[u.y < 0 ? 1 : 3] = true;
        }
        bool every[4] = {true, true, true, true};
        bool moved = false;
        for (const bool* sides : {facing, quarter, every}) {
            for (int side = 0; side < 4; ++side)
                if (sides[side] && margins[side] > 0) {
                    margins[side] = std::max(0.0, margins[side] - step);
                    moved = true;
                }
            if (moved) break;
        }
        if (!moved) return {};
    }
}

std::vector<std::vector<Point2f>> faceAnchors(const Rect2d& box) {
    const double hw = 0.5 * box.width, hh = 0.5 * box.height;
    const Point2d c(box.x + hw - 0.5, box.y + hh - 0.5);
    // 0.4 of the shorter half side: gaps of at least 0.1 half sides between anchors, and
    // between the anchors and the box.
    const double r = 0.4 * std::min(hw, hh);
    std::vector<std::vector<Point2f>> anchors;
    for (const Point2d o : {Point2d(-0.5 * hw, -0.4 * hh), Point2d(0.5 * hw, -0.4 * hh),
                            Point2d(-0.5 * hw, 0.5 * hh), Point2d(0.5 * hw, 0.5 * hh)}) {
        const Point2d m = c + o;
        anchors.push_back({Point2f(m.x, m.y - r), Point2f(m.x + r, m.y), Point2f(m.x, m.y + r),
                           Point2f(m.x - r, m.y)});
    }
    return anchors;
}

std::vector<Rect> mergeNearFaces(std::vector<Rect> faces, double gap) {
    auto grown = [gap](const Rect& r) {
        // The polygon's extent: 2^(1/8) times the half sides plus the margin, plus the gap.
        const double k = std::pow(2.0, 1.0 / kFaceExponent), m = faceMargin(r) + gap;
        const double hw = k * 0.5 * r.width + m, hh = k * 0.5 * r.height + m;
        const Point2d c(r.x + 0.5 * r.width, r.y + 0.5 * r.height);
        return Rect2d(c.x - hw, c.y - hh, 2 * hw, 2 * hh);
    };
    for (bool merged = true; merged;) {
        merged = false;
        for (size_t i = 0; i < faces.size() && !merged; ++i)
            for (size_t j = i + 1; j < faces.size() && !merged; ++j)
                if ((grown(faces[i]) & grown(faces[j])).area() > 0) {
                    faces[i] |= faces[j];
                    faces.erase(faces.begin() + static_cast<long>(j));
                    merged = true;
                }
    }
    std::sort(faces.begin(), faces.end(),
              [](const Rect& a, const Rect& b) { return a.area() > b.area(); });
    return faces;
}

}  // namespace propose_detail

}  // namespace multicage
}  // namespace cv

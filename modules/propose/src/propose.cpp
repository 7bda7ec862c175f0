// proposeMulticage and protectFeatures: segmentation -> nested regions -> polygons.
//
// Where polygons come from: the objects are dilated by the margin and closed by a small gap
// (objects nearer than two gaps share a polygon), and every outer contour of that "cage
// mask" (findContours, RETR_TREE) is one polygon; an object inside another object's hole is
// one level deeper. Distinct contours of the cage mask are at least two gaps apart, so
// simplifying each within a tolerance below the gap cannot make them cross; a tolerance
// forced higher by the vertex budget is checked and repaired.
#include <algorithm>
#include <cmath>
#include <deque>
#include <functional>
#include <future>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <opencv2/multicage/propose.hpp>

#include <opencv2/multicage/internal/geometry.hpp>
#include "faces.hpp"
#include "segment.hpp"

namespace cv {
namespace multicage {

using geometry::Polygon;
using namespace propose_detail;

namespace {

constexpr int kMinPolygonVertices = 4;  // the bounding-box fallback needs 4
// Around a face's polygon, in face sizes (faceSize): the room the outline leaves (faceRoom),
// and the band no salient polygon may enter (faces take precedence, and a fixed polygon
// beside the face weakens its polygon's shield; see placeFaces).
constexpr double kFaceRoom = 2.0;
constexpr double kFaceKeepOut = 1.0;

void checkParams(const ProposeParams& p) {
    auto bad = [](const char* what, double value, const char* want) {
        CV_Error_(Error::StsOutOfRange,
                  ("multicage: ProposeParams::%s = %g is out of range (%s)", what, value, want));
    };
    if (p.method < PROPOSE_AUTO || p.method > PROPOSE_LABELS)
        bad("method", p.method, "a ProposeMethod");
    if (p.maxVertices < kMinPolygonVertices) bad("maxVertices", p.maxVertices, ">= 4");
    if (p.maxPolygonVertices < kMinPolygonVertices)
        bad("maxPolygonVertices", p.maxPolygonVertices, ">= 4");
    if (p.maxPolygons < 1) bad("maxPolygons", p.maxPolygons, ">= 1");
    if (p.maxDepth < 1) bad("maxDepth", p.maxDepth, ">= 1");
    if (!(p.margin < 1e6f)) bad("margin", p.margin, "a finite number of pixels");
    if (!(p.minRegionArea >= 0 && p.minRegionArea < 1))
        bad("minRegionArea", p.minRegionArea, "[0, 1)");
    if (p.workingSize != 0 && p.workingSize < 32) bad("workingSize", p.workingSize, "0 or >= 32");
    if (p.grabCutIterations < 1) bad("grabCutIterations", p.grabCutIterations, ">= 1");
    if (p.grabCutMaxSide < 32) bad("grabCutMaxSide", p.grabCutMaxSide, ">= 32");
    if (p.protect < PROTECT_SALIENCY || p.protect > PROTECT_ALL)
        bad("protect", p.protect, "a ProtectDetector");
    if (p.faceWorkingSize != 0 && p.faceWorkingSize < 48)
        bad("faceWorkingSize", p.faceWorkingSize, "0 or >= 48");
}

// The parameters in pixels of the working copy.
struct Work {
    Size full, size;
    double scale = 1.0;    // full pixels per work pixel
    float margin = 0.f;    // distance from object to polygon
    float gap = 0.f;       // half the least distance between two polygons
    int radius = 0;        // cleaning
    double minArea = 0.0;  // pixels
};

Work resolve(Size full, const ProposeParams& p) {
    Work w;
    w.full = full;
    const int longer = std::max(full.width, full.height);
    w.scale = p.workingSize > 0 && longer > p.workingSize
                  ? longer / static_cast<double>(p.workingSize)
                  : 1.0;
    w.size = w.scale > 1.0 ? Size(std::max(1, cvRound(full.width / w.scale)),
                                  std::max(1, cvRound(full.height / w.scale)))
                           : full;
    const double diagonal = std::hypot(full.width, full.height);
    const double margin = p.margin >= 0 ? p.margin : std::max(3.0, 0.012 * diagonal);
    w.margin = static_cast<float>(std::max(1.0, margin / w.scale));
    w.gap = std::max(1.5f, 0.4f * w.margin);
    const int wlonger = std::max(w.size.width, w.size.height);
    w.radius = p.morphologyRadius >= 0 ? cvRound(p.morphologyRadius / w.scale)
                                       : std::max(1, cvRound(0.005 * wlonger));
    w.minArea = p.minRegionArea * w.size.area();
    return w;
}

Mat toWork(const Mat& img, const Work& w, int interpolation) {
    if (img.size() == w.size) return img;
    Mat out;
    resize(img, out, w.size, 0, 0, interpolation);
    return out;
}

Mat fromWork(const Mat& mask, const Work& w) {
    if (mask.size() == w.full) return mask;
    Mat out;
    resize(mask, out, w.full, 0, 0, INTER_LINEAR);
    threshold(out, out, 127, 255, THRESH_BINARY);
    return out;
}

// Distance of every pixel to the nearest zero pixel of `src` (exact Euclidean).
Mat distanceTo(const Mat& src) {
    Mat d;
    distanceTransform(src, d, DIST_L2, DIST_MASK_PRECISE, CV_32F);
    return d;
}

// dilate(objects, margin), closed by gap. The image is padded first so that an object cut by
// the image edge is dilated and closed as if it went on: its polygon then follows the edge.
Mat cageMaskFromObjects(const Mat& objects, const Work& w) {
    const int pad = static_cast<int>(std::ceil(w.margin + 2 * w.gap)) + 2;
    Mat padded;
    copyMakeBorder(objects, padded, pad, pad, pad, pad, BORDER_REPLICATE);
    const Mat near = distanceTo(~padded) <= (w.margin + w.gap);
    const Mat closed = distanceTo(near) > w.gap;
    return closed(Rect(pad, pad, objects.cols, objects.rows)).clone();
}

// For a label image: each label component dilated by the margin into the pixels nearer to
// it than to any other label, less a band of `gap` along the split, so that touching labels
// get separate polygons and a label inside another one is nested in it.
Mat cageMaskFromLabels(const Mat& labels, const Work& w) {
    Mat objects = labels != 0;
    Mat dist, nearest;
    distanceTransform(~objects, dist, nearest, DIST_L2, DIST_MASK_5, DIST_LABEL_PIXEL);
    // Every object pixel is a zero pixel with its own index: map indices back to labels.
    double maxIndex;
    minMaxLoc(nearest, nullptr, &maxIndex);
    std::vector<int> owner(static_cast<size_t>(maxIndex) + 1, 0);
    for (int y = 0; y < labels.rows; ++y)
        for (int x = 0; x < labels.cols; ++x)
            if (labels.at<int>(y, x) != 0) owner[nearest.at<int>(y, x)] = labels.at<int>(y, x);
    Mat own(labels.size(), CV_32S);
    for (int y = 0; y < labels.rows; ++y)
        for (int x = 0; x < labels.cols; ++x) own.at<int>(y, x) = owner[nearest.at<int>(y, x)];
    Mat region = dist <= w.margin;
    Mat split(labels.size(), CV_8U, Scalar(0));
    for (int y = 0; y < labels.rows; ++y)
        for (int x = 0; x < labels.cols; ++x) {
            if (!region.at<uchar>(y, x)) continue;
            const int o = own.at<int>(y, x);
            if ((x + 1 < labels.cols && region.at<uchar>(y, x + 1) && own.at<int>(y, x + 1) != o) ||
                (y + 1 < labels.rows && region.at<uchar>(y + 1, x) && own.at<int>(y + 1, x) != o))
                split.at<uchar>(y, x) = 255;
        }
    const Mat nearSplit = distanceTo(~split) <= w.gap;
    region.setTo(0, nearSplit);
    return region;
}

// One polygon to make: an outer contour of the cage mask.
struct Region {
    std::vector<Point> contour;
    int depth = 1;
    double area = 0;
    Mat distance;  // from the filled contour, within `roi`; made when first needed
    Rect roi;
    Mat limit;  // work-size mask the grown region must stay in (empty: the image)
};

// Outer contours at even levels of the contour tree, as regions with their depth.
std::vector<Region> nestedRegions(const Mat& cageMask, int maxDepth, double minArea) {
    Mat padded;  // a zero frame, so that a region filling the image still has a contour
    copyMakeBorder(cageMask, padded, 1, 1, 1, 1, BORDER_CONSTANT, 0);
    std::vector<std::vector<Point>> contours;
    std::vector<Vec4i> hierarchy;
    findContours(padded, contours, hierarchy, RETR_TREE, CHAIN_APPROX_SIMPLE, Point(-1, -1));
    const int n = static_cast<int>(contours.size());
    std::vector<int> level(n, -1);
    std::vector<char> kept(n, 0);
    std::vector<Region> regions;
    // Parents come before children in findContours' order only sometimes: resolve levels by
    // walking up, then keep a region when every outer ancestor was kept.
    for (int i = 0; i < n; ++i) {
        int l = 0;
        for (int p = hierarchy[i][3]; p >= 0; p = hierarchy[p][3]) ++l;
        level[i] = l;
    }
    std::vector<int> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return level[a] < level[b]; });
    for (int i : order) {
        if (level[i] % 2 != 0) {  // a hole: alive when its object is
            kept[i] = kept[hierarchy[i][3]] && contourArea(contours[i]) >= minArea;
            continue;
        }
        const int hole = hierarchy[i][3];
        const int depth = level[i] / 2 + 1;
        const double area = contourArea(contours[i]);
        if ((hole >= 0 && !kept[hole]) || depth > maxDepth || area < minArea || area <= 0) continue;
        kept[i] = 1;
        Region r;
        r.contour = contours[i], r.depth = depth, r.area = area;
        regions.push_back(std::move(r));
    }
    std::stable_sort(regions.begin(), regions.end(),
                     [](const Region& a, const Region& b) { return a.area > b.area; });
    return regions;
}

bool isSimple(const Polygon& p) {
    if (p.size() < 3 || std::abs(geometry::signedArea(p)) < 1e-6) return false;
    for (size_t i = 0; i < p.size(); ++i)
        if (p[i] == p[(i + 1) % p.size()]) return false;
    return !geometry::findCrossing({p}, nullptr);
}

Polygon toPolygon(const std::vector<Point>& points) {
    Polygon p;
    for (const Point& q : points)
        if (p.empty() || Point2f(q) != p.back()) p.emplace_back(q);
    while (p.size() > 1 && p.front() == p.back()) p.pop_back();
    return p;
}

enum Mode { MODE_APPROX = 0, MODE_HULL = 1, MODE_BOX = 2 };

// Douglas-Peucker within tolerance e; when that is not simple, the convex hull simplified
// the same way (a subset of a convex polygon's vertices is convex, hence simple); when that
// degenerates, the bounding box. `mode` is where to start and comes back as what was used.
Polygon simplify(const std::vector<Point>& contour, double e, int* mode) {
    std::vector<Point> approx;
    if (*mode <= MODE_APPROX) {
        approxPolyDP(contour, approx, e, true);
        Polygon p = toPolygon(approx);
        if (isSimple(p)) return *mode = MODE_APPROX, p;
    }
    if (*mode <= MODE_HULL) {
        std::vector<Point> hull;
        convexHull(contour, hull);
        approxPolyDP(hull, approx, e, true);
        Polygon p = toPolygon(approx);
        if (isSimple(p)) return *mode = MODE_HULL, p;
    }
    *mode = MODE_BOX;
    const Rect r = boundingRect(contour);
    const float x0 = r.x, y0 = r.y, x1 = r.x + std::max(1, r.width - 1),
                y1 = r.y + std::max(1, r.height - 1);
    return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

// Work pixels -> input pixels. Contour points lie on pixel centres in [0, w-1]; those on the
// image edge move 0.3 work pixels outwards so the edge pixels are strictly inside the
// polygon, and everything stays strictly inside the frame (-0.5, -0.5)-(W-0.5, H-0.5).
Polygon toFull(const Polygon& p, const Work& w) {
    Polygon out;
    out.reserve(p.size());
    const float right = w.size.width - 1.f, bottom = w.size.height - 1.f;
    const float sx = static_cast<float>(w.full.width) / w.size.width;
    const float sy = static_cast<float>(w.full.height) / w.size.height;
    for (Point2f q : p) {
        if (q.x <= 0.f) q.x = -0.3f;
        if (q.y <= 0.f) q.y = -0.3f;
        if (q.x >= right) q.x = right + 0.3f;
        if (q.y >= bottom) q.y = bottom + 0.3f;
        out.emplace_back((q.x + 0.5f) * sx - 0.5f, (q.y + 0.5f) * sy - 0.5f);
    }
    return out;
}

struct Candidate {
    Region* region = nullptr;
    double e = 0;
    int mode = MODE_APPROX;
    int refinements = 0;
    Polygon polygon;  // input pixels
    bool alive = true;
};

// The region grown by `grow` pixels (its outer contour). Douglas-Peucker cuts corners by up to
// its tolerance; approximating the contour of the region grown by that much instead keeps
// the polygon around the region, so a tolerance forced above the margin by the vertex budget
// still encloses the objects.
std::vector<Point> grownContour(Region& r, double grow, Size size) {
    if (grow <= 0) return r.contour;
    if (r.distance.empty()) {
        const int pad = std::max(size.width, size.height) / 4 + 2;
        const Rect box = boundingRect(r.contour);
        r.roi = Rect(box.x - pad, box.y - pad, box.width + 2 * pad, box.height + 2 * pad) &
                Rect(Point(), size);
        Mat filled(r.roi.size(), CV_8U, Scalar(0));
        drawContours(filled, std::vector<std::vector<Point>>{r.contour}, 0, Scalar(255), FILLED,
                     LINE_8, noArray(), INT_MAX, -r.roi.tl());
        r.distance = distanceTo(~filled);
    }
    Mat grown;
    Mat within = r.distance <= grow;
    if (!r.limit.empty()) within &= r.limit(r.roi);
    copyMakeBorder(within, grown, 1, 1, 1, 1, BORDER_CONSTANT, 0);
    std::vector<std::vector<Point>> contours;
    findContours(grown, contours, RETR_EXTERNAL, CHAIN_APPROX_SIMPLE, r.roi.tl() - Point(1, 1));
    if (contours.empty()) return r.contour;
    return *std::max_element(contours.begin(), contours.end(), [](const auto& a, const auto& b) {
        return contourArea(a) < contourArea(b);
    });
}

void make(Candidate& c, const Work& w) {
    // The margin absorbs half of the tolerance: the polygon stays at least margin / 2 away.
    const double grow = c.e + 1.0 - 0.5 * w.margin;
    c.polygon = toFull(simplify(grownContour(*c.region, grow, w.size), c.e, &c.mode), w);
}

int aliveVertices(const std::vector<Candidate>& cs) {
    int n = 0;
    for (const Candidate& c : cs) n += c.alive ? static_cast<int>(c.polygon.size()) : 0;
    return n;
}

// Simplifies every region within the vertex budgets. One tolerance for all (uniform
// accuracy), raised until the total fits; a polygon over its own budget raises its own.
std::vector<Candidate> simplifyAll(std::vector<Region>& regions, const Work& w, int budget,
                                   int polygonBudget) {
    std::vector<Candidate> cs;
    for (Region& r : regions) {
        Candidate c;
        c.region = &r;
        cs.push_back(c);
    }
    const double eMax = 4.0 * std::hypot(w.size.width, w.size.height);
    for (double e = 0.5;; e *= 1.15) {
        for (Candidate& c : cs) {
            c.e = e, c.mode = MODE_APPROX;
            make(c, w);
            while (static_cast<int>(c.polygon.size()) > polygonBudget) {
                c.e *= 1.15;
                if (c.e > eMax) c.mode = MODE_BOX;
                make(c, w);
            }
        }
        if (aliveVertices(cs) <= budget) return cs;
        if (e > eMax) {  // cannot happen with 4 vertices per region planned; be safe anyway
            for (Candidate& c : cs) c.mode = MODE_BOX, make(c, w);
            while (aliveVertices(cs) > budget) {
                auto last = std::find_if(cs.rbegin(), cs.rend(),
                                         [](const Candidate& c) { return c.alive; });
                last->alive = false;
            }
            return cs;
        }
    }
}

// Raises c's tolerance until it fits `cap` vertices.
void fit(Candidate& c, const Work& w, int cap) {
    make(c, w);
    while (static_cast<int>(c.polygon.size()) > cap) {
        c.e *= 1.15;
        make(c, w);
    }
}

// Makes the polygons (with `fixed` ones that must stay as they are) pairwise disjoint and
// simple, and keeps the nesting the regions had:
// - a polygon that intersects itself falls back to its hull, then its box;
// - of two crossing polygons at different depths, the inner one is simplified more finely
//   while the budget allows, else dropped (its region lies inside the outer one anyway);
// - two crossing siblings are first refined the same way, then merged into one polygon
//   around both (the convex hull of their regions), so that no object is left uncaged;
// - a polygon that came to contain a sibling (a large tolerance grows polygons) swallows it:
//   the sibling is dropped, as its region is inside;
// - a polygon that contains a fixed one is dropped.
// `depthOffset` is the depth of the polygon the regions sit in (0 for a whole image).
void repair(std::vector<Candidate>& cs, const std::vector<Polygon>& fixed, const Work& w,
            int budget, int cap, int depthOffset) {
    std::deque<Region> merged;  // regions made here; candidates point into it
    auto refine = [&](int i) {
        if (cs[i].refinements >= 3 || cs[i].mode != MODE_APPROX) return false;
        Candidate finer = cs[i];
        finer.e *= 0.5, ++finer.refinements;
        make(finer, w);
        const int total = aliveVertices(cs) - static_cast<int>(cs[i].polygon.size()) +
                          static_cast<int>(finer.polygon.size());
        if (finer.mode != MODE_APPROX || total > budget ||
            static_cast<int>(finer.polygon.size()) > cap)
            return false;
        cs[i] = finer;
        return true;
    };
    for (int iteration = 0; iteration < 1000; ++iteration) {
        std::vector<Polygon> all = fixed;
        std::vector<int> index(fixed.size(), -1);
        for (int i = 0; i < static_cast<int>(cs.size()); ++i)
            if (cs[i].alive) all.push_back(cs[i].polygon), index.push_back(i);
        geometry::Crossing x;
        if (!geometry::findCrossing(all, &x)) {
            const std::vector<int> depth = geometry::depths(all);
            bool changed = false;
            // A new polygon around a fixed one (a ring-shaped region closes around it) would
            // swallow it: the fixed one wins (in protectFeatures, faces placed first).
            for (size_t k = fixed.size(); k < all.size() && !changed; ++k)
                for (size_t f = 0; f < fixed.size() && !changed; ++f)
                    if (geometry::contains(all[k], all[f][0]))
                        cs[index[k]].alive = false, changed = true;
            for (size_t k = fixed.size(); k < all.size() && !changed; ++k) {
                const Candidate& c = cs[index[k]];
                if (depth[k] <= c.region->depth + depthOffset) continue;
                for (size_t j = fixed.size(); j < all.size() && !changed; ++j)
                    if (j != k && cs[index[j]].region->depth >= c.region->depth &&
                        geometry::contains(all[j], all[k][0]))
                        cs[index[k]].alive = false, changed = true;
            }
            if (!changed) return;
            continue;
        }
        const int a = index[x.polygonA], b = index[x.polygonB];
        if (a < 0 && b < 0)
            CV_Error(Error::StsBadArg,
                     "multicage: the given multicage's polygons cross (validate() it first)");
        if (x.polygonA == x.polygonB) {
            Candidate& c = cs[a];
            if (c.mode == MODE_BOX)
                c.alive = false;
            else
                ++c.mode, make(c, w);
            continue;
        }
        if (a < 0 || b < 0) {  // against a fixed polygon: only ours can give way
            const int v = a < 0 ? b : a;
            if (!refine(v)) cs[v].alive = false;
            continue;
        }
        if (cs[a].region->depth != cs[b].region->depth) {
            const int v = cs[a].region->depth > cs[b].region->depth ? a : b;
            if (!refine(v)) cs[v].alive = false;
            continue;
        }
        const int small = cs[a].region->area < cs[b].region->area ? a : b;
        const int large = small == a ? b : a;
        if (refine(small) || refine(large)) continue;
        Region m;
        std::vector<Point> both = cs[a].region->contour;
        both.insert(both.end(), cs[b].region->contour.begin(), cs[b].region->contour.end());
        convexHull(both, m.contour);
        m.depth = cs[a].region->depth;
        m.area = cs[a].region->area + cs[b].region->area;
        merged.push_back(std::move(m));
        Candidate c;
        c.region = &merged.back();
        c.e = std::max(cs[a].e, cs[b].e);
        cs[a].alive = cs[b].alive = false;
        fit(c, w, cap);
        cs.push_back(c);
        Candidate& added = cs.back();
        while (aliveVertices(cs) > budget && added.mode != MODE_BOX) {
            added.e *= 1.3;
            make(added, w);
        }
    }
    CV_Error(Error::StsInternal,
             "multicage: proposeMulticage: repairing the polygons did not converge");
}

// Regions in priority order (largest first) that fit the polygon count and vertex budget.
std::vector<Region> selectRegions(std::vector<Region> regions, int maxPolygons, int budget) {
    const int most = std::min(maxPolygons, budget / kMinPolygonVertices);
    if (static_cast<int>(regions.size()) > most) regions.resize(std::max(0, most));
    return regions;
}

struct Segmentation {
    Mat objects;  // work size, 255 on objects (cleaned)
    Mat labels;   // work size CV_32S for PROPOSE_LABELS, else empty
};

Segmentation segmentForProposal(const Mat& image, const Work& w, const ProposeParams& params) {
    Segmentation s;
    if (params.method == PROPOSE_MASK || params.method == PROPOSE_LABELS) {
        if (image.empty())
            CV_Error(Error::StsBadArg, "multicage: proposeMulticage: the mask is empty");
        if (image.channels() != 1)
            CV_Error_(Error::StsBadArg,
                      ("multicage: proposeMulticage: a %s must have one channel (it has %d)",
                       params.method == PROPOSE_MASK ? "mask" : "label image", image.channels()));
        if (params.method == PROPOSE_MASK) {
            s.objects = toWork(image != 0, w, INTER_NEAREST);
            s.objects = cleanMask(s.objects, w.radius, w.minArea);
        } else {
            if (image.depth() != CV_8U && image.depth() != CV_16U && image.depth() != CV_32S)
                CV_Error(
                    Error::StsBadArg,
                    "multicage: proposeMulticage: a label image must be CV_8U, CV_16U or CV_32S");
            Mat l;
            image.convertTo(l, CV_32S);
            s.labels = toWork(l, w, INTER_NEAREST);
            // Labels are the user's word: only regions below the minimum area go.
            s.objects = cleanMask(s.labels != 0, 0, w.minArea);
            s.labels.setTo(0, s.objects == 0);
        }
        return s;
    }
    const Mat img8 = to8Bit(image);
    if (isConstant(img8))
        CV_Error(Error::StsBadArg,
                 "multicage: proposeMulticage: the image is constant (every pixel has the "
                 "same value): there is nothing to segment");
    const Mat work = toWork(img8, w, INTER_AREA);
    int method = params.method;
    if (method == PROPOSE_AUTO) {
        // A plain background (most of the border strip near its median colour) is what a
        // threshold wants; on anything else GrabCut, seeded by saliency, finds whole objects
        // where saliency alone lights up texture.
        const Mat strip = borderStrip(work.size());
        const Mat far = (backgroundDistance(work, strip) > 24) & strip;
        method =
            countNonZero(far) < 0.25 * countNonZero(strip) ? PROPOSE_THRESHOLD : PROPOSE_GRABCUT;
    }
    s.objects = cleanMask(segmentImage(work, method, params, w.scale), w.radius, w.minArea);
    return s;
}

// What new polygons may take: polygon slots, vertices in all, and vertices of one polygon.
struct Budget {
    int polygons, vertices, polygonVertices;
};

// How a proposal's result is checked: proposeMulticage promises a valid multicage (validate()),
// protectFeatures the geometry its input had to have (validateGeometry()).
enum class Check { VALID, GEOMETRY };

// The tail both proposals share: the regions that fit the budget (in priority order) become
// polygons, simplified within the budget and repaired against the polygons `cage` already
// has; those that survive (and that `accept`, when given, accepts) are added to it, and the
// result is oriented and checked. `depth`:
// of the polygon the regions sit in (0 for a whole image); `who` names the public function in
// the error an invalid result raises.
Multicage addPolygons(Multicage cage, std::vector<Region> found, const Work& w,
                      const Budget& budget, int depth, const char* who, Check check,
                      const std::function<bool(const Polygon&)>& accept = nullptr) {
    std::vector<Region> regions = selectRegions(std::move(found), budget.polygons, budget.vertices);
    std::vector<Candidate> cs = simplifyAll(regions, w, budget.vertices, budget.polygonVertices);
    std::vector<Polygon> fixed;
    for (int j = 0; j < cage.polygonCount(); ++j) fixed.push_back(cage.polygon(j));
    repair(cs, fixed, w, budget.vertices, budget.polygonVertices, depth);
    // Dropping polygons from disjoint ones leaves them disjoint: `accept` cannot break them.
    for (const Candidate& c : cs)
        if (c.alive && (!accept || accept(c.polygon))) cage.addPolygon(c.polygon);
    cage.orient();
    std::string why;
    if (!(check == Check::VALID ? cage.validate(&why) : cage.validateGeometry(&why)))
        CV_Error_(Error::StsInternal,
                  ("multicage: %s made an invalid multicage: %s", who, why.c_str()));
    return cage;
}

}  // namespace

const char* proposeMethodName(int method) {
    static const char* names[] = {"auto",     "threshold", "adaptive", "grabcut",
                                  "saliency", "spectral",  "mask",     "labels"};
    return method >= 0 && method <= PROPOSE_LABELS ? names[method] : "unknown";
}

int parseProposeMethod(const String& name) {
    for (int m = PROPOSE_AUTO; m <= PROPOSE_LABELS; ++m)
        if (name == proposeMethodName(m)) return m;
    return -1;
}

void proposeSegmentation(InputArray image, OutputArray mask, const ProposeParams& params) {
    checkParams(params);
    const Mat img = image.getMat();
    if (img.empty())
        CV_Error(Error::StsBadArg, "multicage: proposeSegmentation: the image is empty");
    const Work w = resolve(img.size(), params);
    fromWork(segmentForProposal(img, w, params).objects, w).copyTo(mask);
}

namespace {
// Fills a polygon given in input pixels into a work-size mask.
void fillWork(Mat& mask, const Polygon& p, const Work& w, const Scalar& value) {
    const double sx = w.size.width / static_cast<double>(w.full.width);
    const double sy = w.size.height / static_cast<double>(w.full.height);
    std::vector<std::vector<Point>> q(1);
    for (Point2f v : p)
        q[0].emplace_back(cvRound(((v.x + 0.5) * sx - 0.5) * 16),
                          cvRound(((v.y + 0.5) * sy - 0.5) * 16));
    fillPoly(mask, q, value, LINE_8, 4);
}

// Room between a face's polygon and the outline around it, in input pixels. Mean value
// coordinates are global: the outline's motion leaks through the face's polygon into the face
// (a partial stretch plus a bump that is zero on the polygon), in proportion to the polygon's
// size over its distance to the outline. Measured on three photos (docs/faces/README.md), with
// the outline stretched 20% the face's similarity residual is 1.0-1.6 px at 0.6 face sizes of
// room, 0.5-1.1 px at 1.5 and 0.45-0.9 px at 2 (less where the image border stops the room).
// The room is a rounded box too: the outline then keeps its distance at the face's corners.
double faceRoom(const Rect& face) {
    return kFaceRoom * faceSize(face);
}

// The outlines of a segmentation (proposeMulticage's tail). Every face in `faces` is enclosed
// with its polygon's room: the outline goes around it.
Multicage outlinesOf(Segmentation s, Size size, const Work& w, const ProposeParams& params,
                     const std::vector<Rect>& faces) {
    if (!faces.empty()) {
        Mat room = Mat::zeros(w.size, CV_8U);
        for (const Rect& f : faces)
            fillWork(room, facePolygon(f, faceMargin(f) + faceRoom(f), 32), w, Scalar(255));
        // The room stops two margins short of the image border (the outline one margin from
        // it): an outline along the border moves against the fixed frame a fraction of a pixel
        // away, and the pixels between fold.
        const int edge = cvCeil(2 * w.margin);
        if (2 * edge < std::min(w.size.width, w.size.height)) {
            Mat inner = Mat::zeros(w.size, CV_8U);
            inner(Rect(edge, edge, w.size.width - 2 * edge, w.size.height - 2 * edge)).setTo(255);
            room &= inner;
        }
        s.objects |= room;
    }
    const Mat cage = params.method == PROPOSE_LABELS ? cageMaskFromLabels(s.labels, w)
                                                     : cageMaskFromObjects(s.objects, w);
    return addPolygons(Multicage(size), nestedRegions(cage, params.maxDepth, w.minArea), w,
                       Budget{params.maxPolygons, params.maxVertices, params.maxPolygonVertices}, 0,
                       "proposeMulticage", Check::VALID);
}

bool wantsFaces(const ProposeParams& params) {
    const bool maskInput = params.method == PROPOSE_MASK || params.method == PROPOSE_LABELS;
    // PROTECT_ALL goes on without cascades (salient features only); PROTECT_FACES says why not.
    return !maskInput && params.protect != PROTECT_SALIENCY &&
           (params.protect == PROTECT_FACES || !faceCascadeFile(params).empty());
}

Multicage protectImpl(InputArray image, const Multicage& cage, int polygon,
                      const ProposeParams& params, const std::vector<Rect>* knownFaces);
}  // namespace

Multicage proposeMulticage(InputArray image, const ProposeParams& params) {
    checkParams(params);
    const Mat img = image.getMat();
    if (img.empty()) CV_Error(Error::StsBadArg, "multicage: proposeMulticage: the image is empty");
    const Work w = resolve(img.size(), params);
    return outlinesOf(segmentForProposal(img, w, params), img.size(), w, params, {});
}

Multicage proposeProtectedMulticage(InputArray image, const ProposeParams& params) {
    return proposeProtectedMulticage(image, params, nullptr);
}

Multicage proposeProtectedMulticage(InputArray image, const ProposeParams& params,
                                    std::vector<Rect>* facesOut) {
    checkParams(params);
    if (facesOut) facesOut->clear();
    const Mat img = image.getMat();
    if (img.empty()) CV_Error(Error::StsBadArg, "multicage: proposeMulticage: the image is empty");
    // The face search and the segmentation do not need each other: side by side they take
    // the longer of the two (the cascades on one core, GrabCut on the other).
    std::future<std::vector<Rect>> search;
    // Without the cascade, PROTECT_FACES fails now (the exception names the package), not
    // after the segmentation.
    if (params.protect == PROTECT_FACES && faceCascadeFile(params).empty())
        detectFaces(img, params);
    if (wantsFaces(params))
        search =
            std::async(std::launch::async, [&img, &params] { return detectFaces(img, params); });
    const Work w = resolve(img.size(), params);
    Segmentation s = segmentForProposal(img, w, params);
    const std::vector<Rect> faces =
        search.valid() ? mergeNearFaces(search.get(), w.margin * w.scale) : std::vector<Rect>();
    if (facesOut) *facesOut = faces;
    ProposeParams outlineParams = params;
    if (!faces.empty())  // leave the faces a share of the budget
        outlineParams.maxVertices = std::max(
            kMinPolygonVertices,
            params.maxVertices -
                std::min(params.maxVertices / 2,
                         static_cast<int>(faces.size()) *
                             (kFaceVertices + (params.faceAnchors ? 4 * kFaceAnchors : 0))));
    Multicage cage = outlinesOf(std::move(s), img.size(), w, outlineParams, faces);
    if (params.method == PROPOSE_MASK || params.method == PROPOSE_LABELS) return cage;
    const int top = cage.polygonCount();  // protectFeatures appends; only the outlines get it
    for (int p = 0; p < top; ++p)
        if (cage.depth(p) == 1) cage = protectImpl(img, cage, p, params, &faces);
    return cage;
}

Multicage protectFeatures(InputArray image, const Multicage& cage, int polygon,
                          const ProposeParams& params) {
    return protectImpl(image, cage, polygon, params, nullptr);
}

namespace {
void checkProtectInput(const Mat& img, const Multicage& cage, int polygon) {
    if (img.empty()) CV_Error(Error::StsBadArg, "multicage: protectFeatures: the image is empty");
    if (img.size() != cage.imageSize())
        CV_Error_(
            Error::StsBadSize,
            ("multicage: protectFeatures: the image is %dx%d, the multicage was made for %dx%d",
             img.cols, img.rows, cage.imageSize().width, cage.imageSize().height));
    if (polygon < 0 || polygon >= cage.polygonCount())
        CV_Error_(Error::StsOutOfRange,
                  ("multicage: protectFeatures: polygon %d does not exist (the multicage has %d)",
                   polygon, cage.polygonCount()));
    std::string why;
    if (!cage.validateGeometry(&why))
        CV_Error_(Error::StsBadArg,
                  ("multicage: protectFeatures: the multicage is not valid: %s", why.c_str()));
}

// The polygons nested directly or deeper inside polygon `polygon`.
std::vector<int> nestedIn(const Multicage& cage, int polygon) {
    std::vector<int> inner;
    const Polygon outer = cage.polygon(polygon);
    for (int j = 0; j < cage.polygonCount(); ++j)
        if (j != polygon && geometry::contains(outer, cage.polygon(j)[0])) inner.push_back(j);
    return inner;
}

// Where protection may go, in work pixels: inside the polygon, outside the polygons already
// inside it.
Mat protectableArea(const Multicage& cage, int polygon, const Work& w) {
    Mat inside(w.size, CV_8U, Scalar(0));
    fillWork(inside, cage.polygon(polygon), w, Scalar(255));
    for (int j : nestedIn(cage, polygon)) fillWork(inside, cage.polygon(j), w, Scalar(0));
    return inside;
}

// Least distance between the boundaries of two polygons that do not cross.
double boundaryDistance(const Polygon& a, const Polygon& b) {
    auto toSegment = [](Point2d p, Point2d q0, Point2d q1) {
        const Point2d d = q1 - q0;
        const double len2 = d.dot(d);
        const double t = len2 > 0 ? std::min(1.0, std::max(0.0, (p - q0).dot(d) / len2)) : 0.0;
        return norm(p - (q0 + t * d));
    };
    double best = HUGE_VAL;
    for (int pass = 0; pass < 2; ++pass) {
        const Polygon& p = pass == 0 ? a : b;
        const Polygon& q = pass == 0 ? b : a;
        for (const Point2f& v : p)
            for (size_t i = 0; i < q.size(); ++i)
                best = std::min(best, toSegment(v, q[i], q[(i + 1) % q.size()]));
    }
    return best;
}

// True when `face` lies strictly inside the image and inside polygon `polygon`, outside the
// polygons nested in it and the faces already placed, at least `band` pixels from each.
bool faceFits(const Polygon& face, const Multicage& cage, int polygon,
              const std::vector<Polygon>& placed, double band) {
    const Size size = cage.imageSize();
    for (const Point2f& v : face)
        if (!(v.x > 0.f && v.y > 0.f && v.x < size.width - 1.f && v.y < size.height - 1.f))
            return false;
    if (!geometry::contains(cage.polygon(polygon), face[0])) return false;
    std::vector<Polygon> near = placed;
    near.push_back(cage.polygon(polygon));
    for (int j : nestedIn(cage, polygon)) near.push_back(cage.polygon(j));
    for (const Polygon& q : near) {
        if (q != cage.polygon(polygon) &&
            (geometry::contains(q, face[0]) || geometry::contains(face, q[0])))
            return false;
        if (geometry::findCrossing({q, face}, nullptr) || boundaryDistance(q, face) < band)
            return false;
    }
    return true;
}

// The faces protectFeatures protects inside a polygon: those with their centre in the free
// area. `knownFaces`: already detected (nullptr: detect here).
std::vector<Rect> facesInside(const Mat& img, const ProposeParams& params,
                              const std::vector<Rect>* knownFaces, const Mat& inside,
                              const Work& w) {
    std::vector<Rect> faces, in;
    if (knownFaces)
        faces = *knownFaces;
    else if (wantsFaces(params))
        faces = mergeNearFaces(detectFaces(img, params), w.margin * w.scale);
    for (const Rect& f : faces) {
        const Point c(std::min(w.size.width - 1, cvFloor((f.x + 0.5 * f.width) / w.scale)),
                      std::min(w.size.height - 1, cvFloor((f.y + 0.5 * f.height) / w.scale)));
        if (inside.at<uchar>(c)) in.push_back(f);
    }
    return in;
}

// What the faces inside a polygon become. A face gets its own polygon (facePolygon) when one
// fits, at its margin or a smaller one, and its anchors inside (faceAnchors) when the budget
// allows; otherwise it becomes a region like a salient blob, clipped to where a polygon may go
// (mask, zone), and goes first in the budget.
struct FacePlan {
    std::vector<Polygon> polygons;  // placed (faces and their anchors), input pixels
    std::vector<char> isFace;       // per polygon: a face's (not an anchor)
    std::vector<double> sizes;      // per polygon: its face's size
    Mat keepOut;                    // work pixels: placed polygons and a band around them
    Mat mask, zone;                 // the faces that became regions, and where theirs may go
    std::vector<Point2f> centres;   // of those faces, work pixels
};

FacePlan placeFaces(const std::vector<Rect>& faces, const Multicage& cage, int polygon,
                    const ProposeParams& params, const Mat& insideDistance, const Work& w) {
    const float faceBand = w.margin + 2 * w.gap;  // work pixels, as for blobs but thinner
    FacePlan plan;
    plan.keepOut = Mat::zeros(w.size, CV_8U);
    plan.mask = Mat::zeros(w.size, CV_8U);
    plan.zone = Mat::zeros(w.size, CV_8U);
    int budget = params.maxVertices - cage.vertexCount();
    int slots = params.maxPolygons - cage.polygonCount();
    for (const Rect& f : faces) {
        const int n = std::min({kFaceVertices, params.maxPolygonVertices, budget}) / 4 * 4;
        if (n < 4 || slots < 1) break;
        Polygon placed;
        for (double m : {faceMargin(f), 0.5 * faceMargin(f), 0.0}) {
            Polygon p = facePolygon(f, m, n);
            if (faceFits(p, cage, polygon, plan.polygons, faceBand * w.scale)) {
                placed = std::move(p);
                break;
            }
        }
        if (!placed.empty()) {
            plan.polygons.push_back(placed);
            plan.isFace.push_back(1), plan.sizes.push_back(faceSize(f));
            fillWork(plan.keepOut, facePolygon(f, faceMargin(f) + kFaceKeepOut * faceSize(f), n), w,
                     Scalar(255));
            budget -= n, --slots;
            if (params.faceAnchors && budget >= 4 * kFaceAnchors && slots >= kFaceAnchors) {
                for (Polygon& a : faceAnchors(f)) {
                    plan.polygons.push_back(std::move(a));
                    plan.isFace.push_back(0), plan.sizes.push_back(faceSize(f));
                }
                budget -= 4 * kFaceAnchors, slots -= kFaceAnchors;
            }
            continue;
        }
        fillWork(plan.mask, facePolygon(f, faceMargin(f), 16), w, Scalar(255));
        fillWork(plan.zone, facePolygon(f, faceMargin(f) + (w.margin + 3 * w.gap) * w.scale, 16), w,
                 Scalar(255));
        plan.centres.emplace_back((f.x + 0.5f * f.width) / w.scale,
                                  (f.y + 0.5f * f.height) / w.scale);
    }
    // Salient polygons keep a band from the faces' polygons.
    plan.keepOut = distanceTo(~plan.keepOut) <= 2 * w.margin + w.gap;
    plan.mask &= insideDistance > (faceBand + w.margin);
    plan.zone &= insideDistance > faceBand;
    return plan;
}

// The objects to protect inside the polygon (work size, 255 on objects, not yet cleaned);
// empty for a constant image.
Mat objectsInside(const Mat& img, const ProposeParams& params, const Mat& inside, const Work& w) {
    const bool maskInput = params.method == PROPOSE_MASK || params.method == PROPOSE_LABELS;
    if (maskInput) return toWork(img != 0, w, INTER_NEAREST);
    if (params.protect == PROTECT_FACES) return Mat::zeros(w.size, CV_8U);
    const Mat img8 = to8Bit(img);
    if (isConstant(img8)) return Mat();
    const Mat work = toWork(img8, w, INTER_AREA);
    const Rect roi = boundingRect(inside);
    const int method = params.method == PROPOSE_AUTO ? PROPOSE_SALIENCY : params.method;
    // Segment the polygon's bounding box only, thresholds computed inside the polygon:
    // what stands out there, not in the whole image.
    Mat objects = Mat::zeros(w.size, CV_8U);
    segmentImage(work(roi), method, params, w.scale, inside(roi)).copyTo(objects(roi));
    return objects;
}

// The regions around the objects, each limited to `limit`, those with a face first: they get
// the polygon slots and the budget first.
std::vector<Region> protectiveRegions(const Mat& objects, const FacePlan& faces, const Mat& limit,
                                      const Work& w) {
    Mat cageMask = cageMaskFromObjects(objects, w);
    cageMask &= limit;
    double minArea = w.minArea;
    if (!faces.centres.empty())
        minArea = std::min(minArea, 0.5 * countNonZero(faces.mask) / faces.centres.size());
    std::vector<Region> found = nestedRegions(cageMask, 1, minArea);
    std::stable_partition(found.begin(), found.end(), [&](const Region& r) {
        for (const Point2f& c : faces.centres)
            if (pointPolygonTest(r.contour, c, false) >= 0) return true;
        return false;
    });
    for (Region& r : found) r.limit = limit;
    return found;
}

Multicage protectImpl(InputArray image, const Multicage& cage, int polygon,
                      const ProposeParams& params, const std::vector<Rect>* knownFaces) {
    checkParams(params);
    const Mat img = image.getMat();
    checkProtectInput(img, cage, polygon);
    if (params.maxVertices - cage.vertexCount() < kMinPolygonVertices ||
        params.maxPolygons - cage.polygonCount() < 1)
        return cage;

    const Work w = resolve(img.size(), params);
    const Mat inside = protectableArea(cage, polygon, w);
    const Mat insideDistance = distanceTo(inside);
    const FacePlan faces = placeFaces(facesInside(img, params, knownFaces, inside, w), cage,
                                      polygon, params, insideDistance, w);
    Multicage out = cage;  // faces first: the salient features get what is left
    for (const Polygon& p : faces.polygons) out.addPolygon(p);
    out.orient();
    const int budget = params.maxVertices - out.vertexCount();
    const int slots = params.maxPolygons - out.polygonCount();
    if (budget < kMinPolygonVertices || slots < 1) return out;
    // A protective polygon keeps a band of two margins to the moved polygon: the band is
    // what absorbs the deformation, and a thin one would fold.
    const float band = 2 * w.margin + w.gap;
    Mat objects = objectsInside(img, params, inside, w);
    if (objects.empty()) return out;
    objects &= (insideDistance > (band + w.margin)) & ~faces.keepOut;
    objects = cleanMask(objects, w.radius, w.minArea);
    objects |= faces.mask;
    if (countNonZero(objects) == 0) return out;
    const Mat limit = ((insideDistance > band) | faces.zone) & ~faces.keepOut;
    // The mask keeps salient regions a face size from the faces' polygons; what simplifying
    // or merging brings within half of that is dropped.
    auto clearOfFaces = [&faces](const Polygon& p) {
        for (size_t i = 0; i < faces.polygons.size(); ++i)
            if (faces.isFace[i] &&
                boundaryDistance(p, faces.polygons[i]) < 0.5 * kFaceKeepOut * faces.sizes[i])
                return false;
        return true;
    };
    return addPolygons(out, protectiveRegions(objects, faces, limit, w), w,
                       Budget{slots, budget, params.maxPolygonVertices}, cage.depth(polygon),
                       "protectFeatures", Check::GEOMETRY, clearOfFaces);
}
}  // namespace

}  // namespace multicage
}  // namespace cv

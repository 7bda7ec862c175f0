#include "polygons.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <numeric>
#include <opencv2/imgproc.hpp>

namespace cv {
namespace multicage {
namespace propose_detail {

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

namespace {

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
    Polygon plain;    // Douglas-Peucker's own where `polygon` was fitted to the region, else empty
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

// Douglas-Peucker keeps its vertices on the line it approximates, the region's grown by the
// tolerance beyond half the margin (make): the coarser the tolerance, the further out the
// polygon runs around the region. fitToRegion moves the vertices so that the polygon follows
// the region's own line (the objects grown by the margin) instead, as far inside it as outside
// (the least area between the two, measured as the distance to the line integrated along the
// edges), while every edge stays at least margin / 2 from the objects (as Douglas-Peucker's
// do), inside the region's limit, and the polygon simple; a vertex on the image's edge slides
// along it. Budget-bound outlines of thin limbs, tails and legs gain most
// (docs/propose/README.md, "Outlines").
Polygon fitToRegion(const Polygon& start, const Region& r, const Work& w) {
    Polygon p = start;
    const int n = static_cast<int>(p.size());
    if (n < 4) return p;
    // Distances to the region's boundary, the image's edge a boundary too, around the polygon.
    const Rect image(0, 0, w.size.width, w.size.height);
    const int pad = cvCeil(2 * w.margin) + 8;
    const Rect box = boundingRect(start) | boundingRect(r.contour);
    const Rect roi =
        Rect(box.x - pad, box.y - pad, box.width + 2 * pad, box.height + 2 * pad) & image;
    Mat filled(roi.height + 2, roi.width + 2, CV_8U, Scalar(0));
    drawContours(filled, std::vector<std::vector<Point>>{r.contour}, 0, Scalar(255), FILLED, LINE_8,
                 noArray(), INT_MAX, Point(1, 1) - roi.tl());
    const Mat inside = distanceTo(filled), outside = distanceTo(~filled);
    const float deepest = 0.5f * w.margin;  // how far an edge may go into the region
    const float right = w.size.width - 1.f, bottom = w.size.height - 1.f;
    // The cost of the edge a-b, or infinity where it breaks a constraint.
    auto edgeCost = [&](Point2f a, Point2f b) {
        const float length = static_cast<float>(norm(b - a));
        const int steps = std::max(1, cvCeil(length));
        double cost = 0;
        for (int k = 0; k <= steps; ++k) {
            const Point2f q = a + (b - a) * (static_cast<float>(k) / steps);
            const Point at(cvRound(q.x), cvRound(q.y));
            if (!roi.contains(at)) return HUGE_VAL;
            const Point local = at - roi.tl() + Point(1, 1);
            const float in = inside.at<float>(local);
            if (in > deepest) return HUGE_VAL;
            if (!r.limit.empty() && !r.limit.at<uchar>(at)) return HUGE_VAL;
            cost += in > 0 ? in : outside.at<float>(local);
        }
        return cost * length / (steps + 1);
    };
    // True when vertex i moved to q makes one of its edges cross an edge it shares no end with.
    auto crossesOthers = [&](int i, Point2f q) {
        const Point2f a = p[(i + n - 1) % n], b = p[(i + 1) % n];
        for (int j = 0; j < n; ++j) {
            const Point2f c = p[j], d = p[(j + 1) % n];
            if (j == i || (j + 1) % n == i) continue;
            if ((c != a && d != a && geometry::segmentsIntersect(a, q, c, d)) ||
                (c != b && d != b && geometry::segmentsIntersect(q, b, c, d)))
                return true;
        }
        return false;
    };
    const Point2f directions[8] = {{1, 0}, {-1, 0}, {0, 1},  {0, -1},
                                   {1, 1}, {1, -1}, {-1, 1}, {-1, -1}};
    for (float step : {4.f, 2.f, 1.f, 0.5f}) {
        for (int sweep = 0; sweep < 20; ++sweep) {
            bool moved = false;
            for (int i = 0; i < n; ++i) {
                const Point2f a = p[(i + n - 1) % n], b = p[(i + 1) % n];
                double best = edgeCost(a, p[i]) + edgeCost(p[i], b);
                Point2f to = p[i];
                // A vertex on the image's left or right edge keeps its x, on the top or bottom
                // its y: it slides along the edge.
                const bool sideways = p[i].x <= 0.f || p[i].x >= right;
                const bool upright = p[i].y <= 0.f || p[i].y >= bottom;
                for (const Point2f& d : directions) {
                    const Point2f q = p[i] + d * step;
                    if ((sideways && q.x != p[i].x) || (upright && q.y != p[i].y)) continue;
                    const double cost = edgeCost(a, q) + edgeCost(q, b);
                    if (cost < best - 1e-6 && !crossesOthers(i, q)) best = cost, to = q;
                }
                if (to != p[i]) p[i] = to, moved = true;
            }
            if (!moved) break;
        }
    }
    return isSimple(p) ? p : start;
}

void make(Candidate& c, const Work& w, bool fitted = false) {
    // The margin absorbs half of the tolerance: the polygon stays at least margin / 2 away.
    const double grow = c.e + 1.0 - 0.5 * w.margin;
    const Polygon p = simplify(grownContour(*c.region, grow, w.size), c.e, &c.mode);
    c.polygon = toFull(p, w);
    c.plain.clear();
    if (fitted && c.mode == MODE_APPROX) {
        const Polygon f = fitToRegion(p, *c.region, w);
        if (f != p) c.plain = c.polygon, c.polygon = toFull(f, w);
    }
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
    // A polygon fitted to its region gives way first by going back to Douglas-Peucker's (as it
    // was before the fit), then by a finer tolerance.
    auto unfit = [&](int i) {
        if (cs[i].plain.empty()) return false;
        cs[i].polygon = cs[i].plain, cs[i].plain.clear();
        return true;
    };
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
            if (!unfit(v) && !refine(v)) cs[v].alive = false;
            continue;
        }
        if (cs[a].region->depth != cs[b].region->depth) {
            const int v = cs[a].region->depth > cs[b].region->depth ? a : b;
            if (!unfit(v) && !refine(v)) cs[v].alive = false;
            continue;
        }
        const int small = cs[a].region->area < cs[b].region->area ? a : b;
        const int large = small == a ? b : a;
        if (unfit(small) || unfit(large) || refine(small) || refine(large)) continue;
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

}  // namespace

// The tail both proposals share: the regions that fit the budget (in priority order) become
// polygons, simplified within the budget and repaired against the polygons `cage` already
// has; those that survive (and that `accept`, when given, accepts) are added to it, and the
// result is oriented and checked. `depth`:
// of the polygon the regions sit in (0 for a whole image); `who` names the public function in
// the error an invalid result raises.
Multicage addPolygons(Multicage cage, std::vector<Region> found, const Work& w,
                      const Budget& budget, int depth, const char* who, Check check,
                      const std::function<bool(const Polygon&)>& accept) {
    std::vector<Region> regions = selectRegions(std::move(found), budget.polygons, budget.vertices);
    std::vector<Candidate> cs = simplifyAll(regions, w, budget.vertices, budget.polygonVertices);
    for (Candidate& c : cs) make(c, w, true);
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

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv

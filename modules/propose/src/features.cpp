#include "features.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "distinct.hpp"
#include "eyes.hpp"
#include "faces.hpp"
#include "masks.hpp"
#include "polygons.hpp"
#include "segment.hpp"
#include "texture.hpp"

namespace cv {
namespace multicage {
namespace propose_detail {

namespace {

// Around a face's polygon, in face sizes (faceSize): the band no salient polygon may enter
// (faces take precedence). Under the paper's global sums a fixed polygon beside the face weakens
// its polygon's shield (see placeFaces): a face size. Local coordinates confine what a polygon
// does to its neighbourhood: a quarter, which leaves a name tag or ribbons on a uniform their
// polygons (docs/propose/README.md, "Features").
double faceKeepOut(const Multicage& cage) {
    return cage.coordinates() == MEAN_VALUE ? 1.0 : 0.25;
}

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
        return norm(p - geometry::nearestOnSegment(p, q0, q1));
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
// area, with their eyes where they were found already. `known`: already detected (nullptr:
// detect here).
KnownFaces facesInside(const Mat& img, const ProposeParams& params, const KnownFaces* known,
                       const Mat& inside, const Work& w) {
    KnownFaces faces, in;
    if (known)
        faces = *known;
    else if (wantsFaces(params))
        faces.boxes = mergeNearFaces(detectFaces(img, params), w.margin * w.scale);
    for (size_t i = 0; i < faces.boxes.size(); ++i) {
        const Rect& f = faces.boxes[i];
        const Point c(std::min(w.size.width - 1, cvFloor((f.x + 0.5 * f.width) / w.scale)),
                      std::min(w.size.height - 1, cvFloor((f.y + 0.5 * f.height) / w.scale)));
        if (!inside.at<uchar>(c)) continue;
        in.boxes.push_back(f);
        if (i < faces.eyes.size() && in.eyes.size() + 1 == in.boxes.size())
            in.eyes.push_back(faces.eyes[i]);
    }
    return in;
}

// True when `inner` lies inside `outer` at least `band` pixels from its boundary.
bool nestsIn(const Polygon& inner, const Polygon& outer, double band) {
    for (const Point2f& v : inner)
        if (!geometry::contains(outer, v)) return false;
    return !geometry::findCrossing({outer, inner}, nullptr) &&
           boundaryDistance(outer, inner) >= band;
}

// The fixed polygons inside a face's polygon `face`: its eyes where findEyes finds both (what
// a person protects, and what a retouch moves), or the four anchors (faceAnchors()) for a cage
// bound with mean value coordinates when `params` asks for them.
//
// Why anchors only there: with local mean value or harmonic coordinates the inside of a
// face's polygon depends on that polygon and its children alone, so a face polygon at rest
// keeps its face exact, anchors or not (face residual 0.00-0.01 px on the benchmark's five
// faces with the anchors, with the eyes and with neither). With Algorithm 1's global sums the
// outline leaks into the face and the anchors cut the leak; eyes are smaller than the anchors
// they would replace and cut less (docs/faces/README.md, "Eyes": the astronaut's face 0.77 px
// from a similarity with the four anchors, 1.18 with its eyes alone, over 1 px with its eyes
// and the lower two anchors), so a mean value cage keeps the anchors.
std::vector<Polygon> innerFacePolygons(const Mat& gray, const Rect& f, const Polygon& face,
                                       const std::vector<Rect>* eyes, const Multicage& cage,
                                       const ProposeParams& params, const Work& w, int budget,
                                       int slots) {
    std::vector<Polygon> inner;
    if (cage.coordinates() == MEAN_VALUE && params.faceAnchors) {
        inner = faceAnchors(f);
    } else {
        const double band = std::max(1.0, w.gap * w.scale);  // input pixels
        const std::vector<Rect> found = eyes ? *eyes : findEyes(gray, f, params);
        // At a margin of 5% of the eye, else none, else 5% inside: close-set eyes get
        // thinner polygons rather than none.
        for (double margin : {0.05, 0.0, -0.05}) {
            if (found.size() != 2) break;
            inner = {eyePolygon(found[0], margin * found[0].width),
                     eyePolygon(found[1], margin * found[1].width)};
            if (nestsIn(inner[0], face, band) && nestsIn(inner[1], face, band) &&
                boundaryDistance(inner[0], inner[1]) >= band)
                break;
            inner.clear();
        }
    }
    int vertices = 0;
    for (const Polygon& p : inner) vertices += static_cast<int>(p.size());
    if (vertices > budget || static_cast<int>(inner.size()) > slots) inner.clear();  // all or none
    return inner;
}

// What the faces inside a polygon become. A face gets its own polygon (facePolygon) when one
// fits, at its margin or a smaller one, and its eyes or anchors inside (innerFacePolygons)
// when the budget allows; otherwise it becomes a region like a salient blob, clipped to where a
// polygon may go (mask, zone), and goes first in the budget.
struct FacePlan {
    std::vector<Polygon> polygons;  // placed (faces and their anchors), input pixels
    std::vector<char> isFace;       // per polygon: a face's (not an anchor)
    std::vector<double> sizes;      // per polygon: its face's size
    Mat keepOut;                    // work pixels: placed polygons and a band around them
    Mat mask, zone;                 // the faces that became regions, and where theirs may go
    std::vector<Point2f> centres;   // of those faces, work pixels
};

FacePlan placeFaces(const KnownFaces& faces, const Mat& gray, const Multicage& cage, int polygon,
                    const ProposeParams& params, const Mat& insideDistance, const Work& w) {
    const float faceBand = w.margin + 2 * w.gap;  // work pixels, as for blobs but thinner
    FacePlan plan;
    plan.keepOut = Mat::zeros(w.size, CV_8U);
    plan.mask = Mat::zeros(w.size, CV_8U);
    plan.zone = Mat::zeros(w.size, CV_8U);
    int budget = params.maxVertices - cage.vertexCount();
    int slots = params.maxPolygons - cage.polygonCount();
    const double keepOut = faceKeepOut(cage);
    for (size_t i = 0; i < faces.boxes.size(); ++i) {
        const Rect& f = faces.boxes[i];
        const std::vector<Rect>* eyes = i < faces.eyes.size() ? &faces.eyes[i] : nullptr;
        const int n = std::min({kFaceVertices, params.maxPolygonVertices, budget}) / 4 * 4;
        if (n < 4 || slots < 1) break;
        const Polygon placed = faceInOutline(
            f, faceMargin(f), n, cage.polygon(polygon), faceBand * w.scale, [&](const Polygon& p) {
                return faceFits(p, cage, polygon, plan.polygons, faceBand * w.scale);
            });
        if (!placed.empty()) {
            plan.polygons.push_back(placed);
            plan.isFace.push_back(1), plan.sizes.push_back(faceSize(f));
            fillWork(plan.keepOut, facePolygon(f, faceMargin(f) + keepOut * faceSize(f), n), w,
                     Scalar(255));
            budget -= n, --slots;
            for (Polygon& a :
                 innerFacePolygons(gray, f, placed, eyes, cage, params, w, budget, slots)) {
                budget -= static_cast<int>(a.size()), --slots;
                plan.polygons.push_back(std::move(a));
                plan.isFace.push_back(0), plan.sizes.push_back(faceSize(f));
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

// Under each face, its centre line from the chin down one face height (work pixels): where a
// garment opens. A white shirt between lapels, a tie or a collar is as distinct from the jacket
// as a badge is, and every suit shows one; it is the garment's cut, not a thing on it (a badge,
// a name tag, a patch sits off that line).
Mat necklines(const std::vector<Rect>& faces, const Work& w) {
    Mat lines = Mat::zeros(w.size, CV_8U);
    for (const Rect& f : faces) {
        const double x = (f.x + 0.5 * f.width) / w.scale, top = f.br().y / w.scale;
        line(lines, Point(cvRound(x), cvRound(top)),
             Point(cvRound(x), cvRound(top + f.height / w.scale)), Scalar(255));
    }
    return lines;
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

}  // namespace

Mat grayOf(const Mat& img) {
    Mat gray = to8Bit(img);
    if (gray.channels() == 3) cvtColor(gray, gray, COLOR_BGR2GRAY);
    if (gray.channels() == 4) cvtColor(gray, gray, COLOR_BGRA2GRAY);
    return gray;
}

bool wantsFaces(const ProposeParams& params) {
    const bool maskInput = params.method == PROPOSE_MASK || params.method == PROPOSE_LABELS;
    // PROTECT_ALL goes on without cascades (salient features only); PROTECT_FACES says why not.
    return !maskInput && params.protect != PROTECT_SALIENCY &&
           (params.protect == PROTECT_FACES || !faceCascadeFile(params).empty());
}

Multicage protectInPolygon(InputArray image, const Multicage& cage, int polygon,
                           const ProposeParams& params, const KnownFaces* known) {
    checkParams(params);
    const Mat img = image.getMat();
    checkProtectInput(img, cage, polygon);
    if (params.maxVertices - cage.vertexCount() < kMinPolygonVertices ||
        params.maxPolygons - cage.polygonCount() < 1)
        return cage;

    const Work w = resolve(img.size(), params);
    const Mat inside = protectableArea(cage, polygon, w);
    const Mat insideDistance = distanceTo(inside);
    const KnownFaces inFaces = facesInside(img, params, known, inside, w);
    // The grey image only where an eye search is left to do here.
    const bool searchEyes = inFaces.eyes.size() < inFaces.boxes.size();
    const FacePlan faces = placeFaces(inFaces, searchEyes ? grayOf(img) : Mat(), cage, polygon,
                                      params, insideDistance, w);
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
    const Mat allowed = (insideDistance > (band + w.margin)) & ~faces.keepOut;
    objects = cleanMask(objects & allowed, w.radius, w.minArea);
    const bool maskInput = params.method == PROPOSE_MASK || params.method == PROPOSE_LABELS;
    if (!maskInput) {  // the user's regions stay
        const Mat garmentCuts = necklines(inFaces.boxes, w);
        const Mat edges = textureEdges(img, w);
        objects &= ~piecesHolding(objects, garmentCuts);
        objects = texturedOnly(objects, edges, inside);
        // Saliency merges a badge or a name tag into the garment it is on: the colour-distinct
        // regions find them (distinct.hpp), with the same texture rule on plain surroundings.
        if (params.protect != PROTECT_FACES) {
            Mat distinct =
                cleanMask(distinctRegions(to8Bit(img), inside, w) & allowed, w.radius, w.minArea);
            distinct &= ~piecesHolding(distinct, garmentCuts);
            objects |= texturedOnly(distinct, edges, inside, true);
        }
    }
    objects |= faces.mask;
    if (countNonZero(objects) == 0) return out;
    const Mat limit = ((insideDistance > band) | faces.zone) & ~faces.keepOut;
    // The mask keeps regions faceKeepOut() from the faces' polygons; what simplifying or
    // merging brings within half of that is dropped.
    auto clearOfFaces = [&faces, keepOut = faceKeepOut(cage)](const Polygon& p) {
        for (size_t i = 0; i < faces.polygons.size(); ++i)
            if (faces.isFace[i] &&
                boundaryDistance(p, faces.polygons[i]) < 0.5 * keepOut * faces.sizes[i])
                return false;
        return true;
    };
    return addPolygons(out, protectiveRegions(objects, faces, limit, w), w,
                       Budget{slots, budget, params.maxPolygonVertices}, cage.depth(polygon),
                       "protectFeatures", Check::GEOMETRY, clearOfFaces);
}

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv

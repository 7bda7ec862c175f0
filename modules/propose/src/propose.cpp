// proposeMulticage and protectFeatures, the public entry points: how a proposal flows through
// the module's files, each with one job (docs/propose/README.md, "How a proposal flows"):
//
//   work.cpp      ProposeParams checked and resolved into pixels of a downscaled copy
//   faces.cpp     face detection (Haar cascades) and the polygon hugging a face
//   person.cpp    the person prior: where a face is, the head and the body below it
//   segmenter.cpp the subject model (a salient-object network through OpenCV's dnn): found,
//                 checked, read once per process (at the input size onnx_input.cpp
//                 declares), run on the working copy
//   segment.cpp   image -> mask of objects (threshold, GrabCut seeded by the person prior or
//                 from the frame inward, saliency; with a subject map, fuse.cpp)
//   fuse.cpp      the subject model's map fused with the person prior and the frame-inward
//                 GrabCut
//   subject.cpp   the frame-inward GrabCut of a photo without faces: the frame is background
//                 except where the subject goes on past it
//   grabcut.cpp   GrabCut itself (cv::grabCut's colour models and energy), on
//   grid_cut.cpp  a max-flow over the pixel grid that keeps its flow between iterations
//   polygons.cpp  mask -> nested regions -> polygons within the budgets, simplified and
//                 repaired until simple and disjoint
//   features.cpp  the inner polygons: faces, then textured salient regions (eyes.cpp,
//                 texture.cpp)
//   tasks.cpp     independent work shared out between the cores (the face searches)
#include <algorithm>
#include <cmath>
#include <exception>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/multicage/propose.hpp>
#include <thread>

#include "eyes.hpp"
#include "faces.hpp"
#include "features.hpp"
#include "person.hpp"
#include "polygons.hpp"
#include "segment.hpp"
#include "segmenter.hpp"
#include "tasks.hpp"
#include "work.hpp"

namespace cv {
namespace multicage {

using namespace propose_detail;

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

namespace {
// Around a face's polygon through its box's corners (facePolygon at margin 0), in work gaps:
// what the outline keeps clear, the room that polygon and its band need (placeFaces: a margin
// and two gaps). Beyond that the outline follows the subject, and the face's polygon takes its
// margin where the subject leaves room, less on a side where the outline runs closer
// (faceInOutline): a person draws a face's polygon inside the head and the outline along it.
// An outline kept 0.1 face sizes clear of the polygon with its margin instead ran through the
// background beside a head as wide as its face (docs/propose/history.md, "The room around a
// face").
constexpr double kFaceClearance = 3.0;

// The outlines of a segmentation (proposeMulticage's tail). Every face in `faces` is enclosed
// with the room its polygon needs: the outline goes around it.
Multicage outlinesOf(Segmentation s, Size size, const Work& w, const ProposeParams& params,
                     const std::vector<Rect>& faces) {
    if (!faces.empty()) {
        Mat corners = Mat::zeros(w.size, CV_8U);
        for (const Rect& f : faces) fillWork(corners, facePolygon(f, 0.0, 32), w, Scalar(255));
        Mat room = distanceTo(~corners) <= kFaceClearance * w.gap;
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

// The subject model's map of a photo (segmenter.hpp), run on the proposal's working copy; empty
// where no model runs: a method other than PROPOSE_AUTO, a rectangle from the caller, no model
// found under SEGMENTER_AUTO, or an image too plain to segment (segmentForProposal says so).
Mat subjectFor(const Mat& img, const Work& w, const ProposeParams& params,
               const SubjectModel& model) {
    if (model.empty()) return Mat();
    const Mat img8 = to8Bit(img);
    if (isConstant(img8)) return Mat();
    return subjectMapOf(toWork(img8, w, INTER_AREA), model);
}

SubjectModel modelFor(const ProposeParams& params) {
    if (params.method != PROPOSE_AUTO || params.rect.area() > 0) return SubjectModel();
    return modelToRun(params);
}

// The subject model's map, with the face search beside it on a thread of its own (the network
// takes OpenCV's worker threads): `found` receives the faces when it is not null.
Mat subjectBesideFaces(const Mat& img, const Work& w, const ProposeParams& params,
                       const SubjectModel& model, std::vector<Rect>* found) {
    if (!found) return subjectFor(img, w, params, model);
    std::exception_ptr failed;
    std::thread search([&] {
        try {
            FaceSearch faces(img, params);
            const bool frontal = faces.frontal();
            for (const auto& task : faces.remaining(!frontal)) task();
            *found = faces.faces();
        } catch (...) {
            failed = std::current_exception();
        }
    });
    Mat subject;
    try {
        subject = subjectFor(img, w, params, model);
    } catch (...) {
        search.join();
        throw;
    }
    search.join();
    if (failed) std::rethrow_exception(failed);
    return subject;
}
}  // namespace

void proposeSegmentation(InputArray image, OutputArray mask, const ProposeParams& params) {
    checkParams(params);
    const Mat img = image.getMat();
    if (img.empty())
        CV_Error(Error::StsBadArg, "multicage: proposeSegmentation: the image is empty");
    const Work w = resolve(img.size(), params);
    const Mat subject = subjectFor(img, w, params, modelFor(params));
    fromWork(segmentForProposal(img, w, params, Mat(), {}, subject).objects, w).copyTo(mask);
}

Multicage proposeMulticage(InputArray image, const ProposeParams& params) {
    checkParams(params);
    const Mat img = image.getMat();
    if (img.empty()) CV_Error(Error::StsBadArg, "multicage: proposeMulticage: the image is empty");
    const Work w = resolve(img.size(), params);
    const Mat subject = subjectFor(img, w, params, modelFor(params));
    return outlinesOf(segmentForProposal(img, w, params, Mat(), {}, subject), img.size(), w, params,
                      {});
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
    // Without the cascade, PROTECT_FACES fails now (the exception names the package), not
    // after the segmentation.
    if (params.protect == PROTECT_FACES && faceCascadeFile(params).empty())
        detectFaces(img, params);
    const Work w = resolve(img.size(), params);
    // Faces first: a face found means a person, and the person prior seeds the segmentation
    // (person.hpp); the cascades run on a small copy (faceWorkingSize), so waiting costs less
    // than the outline a face-blind GrabCut draws.
    // Faces too near for a polygon each share one (mergeNearFaces), but each is still a
    // person's head: the person prior takes them as found (two heads, not one head the size of
    // both with a body four times as wide under it).
    // The searches, with the model or without: frontal, the small faces', and the two profile
    // ones only where no frontal face was found (so both paths find the same faces).
    // Most photos have no frontal face: then the small faces' and the profile searches decide
    // whether the face-blind segmentation is wanted, and run beside it where it leaves a core
    // idle (a close-up whose salient part is the whole picture runs one chain of GrabCuts: the
    // baboon's proposal 270 -> 213 ms at 1024 px, the apple's 205 -> 165), else before it,
    // which they spare when they find a face (segment.hpp). A profile face beside it costs the
    // chain's time (the close-up of a face in profile); a frontal face changes nothing.
    // With a subject model, the network runs while the faces are searched, and its map joins
    // the person prior in the segmentation (fuse.hpp).
    std::vector<Rect> found;
    Segmentation s;
    bool segmented = false;
    const SubjectModel model = modelFor(params);
    Mat subject;
    if (!model.empty()) {
        subject = subjectBesideFaces(img, w, params, model, wantsFaces(params) ? &found : nullptr);
    } else if (wantsFaces(params)) {
        FaceSearch search(img, params);
        if (search.frontal()) {
            runTasks(search.remaining(false));
        } else {  // the small faces' search too runs beside the face-blind segmentation
            const Beside beside{search.remaining(true),
                                [&search] { return search.faces().empty(); }};
            s = segmentForProposal(img, w, params, Mat(), beside);
            segmented = true;
        }
        found = search.faces();
    }
    const std::vector<Rect> faces = mergeNearFaces(found, w.margin * w.scale);
    KnownFaces known{faces, {}};
    const Mat person = personSeed(found, w);
    if (faces.empty()) {  // (a mask or label input has none: wantsFaces)
        if (!segmented) s = segmentForProposal(img, w, params, person, {}, subject);
    } else {
        // The eyes need the faces alone: they are searched on the second core while the
        // person prior's GrabCut, one thread, runs on the first (a face's two eye cascades
        // then run one after the other; each search's answer does not depend on the thread).
        known.eyes.resize(faces.size());
        const Mat gray = grayOf(img);
        runTasks({[&] { s = segmentForProposal(img, w, params, person, {}, subject); },
                  [&] {
                      for (size_t i = 0; i < faces.size(); ++i)
                          known.eyes[i] = findEyes(gray, faces[i], params);
                  }});
    }
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
    // What the inner polygons protect should follow them alone: with Algorithm 1's global sums
    // a face moves with its outline and the frame too (1-8 px on close-ups when the outline
    // stretches 20%). The cage asks for local mean value coordinates (docs/coordinates.md);
    // the cage file says so, and every binding that follows the cage uses them.
    cage.setCoordinates(LOCAL_MEAN_VALUE);  // before protectInPolygon: it places for them
    // The outlines share the budgets (maxVertices, maxPolygons) in the order they are
    // protected: those holding a face go first, so that a face's polygon and its eyes are not
    // left without vertices by a salient feature of another outline (faces first, as
    // PROTECT_ALL says: the astronaut at 1.1x has her head and her suit in two outlines, and a
    // salient polygon in the suit's, protected first, took the vertices of her eyes).
    const int top = cage.polygonCount();  // protectFeatures appends; only the outlines get it
    std::vector<int> outlines;
    for (int p = 0; p < top; ++p)
        if (cage.depth(p) == 1) outlines.push_back(p);
    std::stable_partition(outlines.begin(), outlines.end(), [&](int p) {
        const std::vector<Point2f> outline = cage.polygon(p);
        return std::any_of(faces.begin(), faces.end(), [&](const Rect& f) {
            const Point2f centre(f.x + 0.5f * f.width, f.y + 0.5f * f.height);
            return pointPolygonTest(outline, centre, false) > 0;
        });
    });
    for (int p : outlines) cage = protectInPolygon(img, cage, p, params, &known);
    return cage;
}

Multicage protectFeatures(InputArray image, const Multicage& cage, int polygon,
                          const ProposeParams& params) {
    return protectInPolygon(image, cage, polygon, params, nullptr);
}

}  // namespace multicage
}  // namespace cv

// libFuzzer target: multicage validation and orientation on polygons decoded from bytes.
// Coordinates are quantised to half pixels on a small image, so that shared vertices,
// collinear edges, touching and crossing polygons, spikes and zero areas are frequent.
// Contract: validate()/validateGeometry() answer with a reason, never crash or hang; when the
// geometry is valid, orient() makes validate() pass, keeps depths, and flips each signed area
// only in sign; a pose follows its polygon's reversal.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <opencv2/core/utility.hpp>
#include <opencv2/multicage.hpp>

#include "fuzz_common.hpp"

using namespace cv;
using namespace cv::multicage;
using multicage_fuzz::Bytes;

namespace {

[[noreturn]] void finding(const char* what) {
    multicage_fuzz::finding("fuzz_validate", what);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    setNumThreads(1);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size > 2048) return -1;
    Bytes in{data, size};
    const int w = 1 + in.next() % 64, h = 1 + in.next() % 64;
    Multicage cage(Size(w, h));
    const int polygons = in.next() % 6;
    for (int p = 0; p < polygons && in.n; ++p) {
        const int n = in.next() % 13;  // 0..12: fewer than 3 is a case too
        std::vector<Point2f> polygon;
        for (int v = 0; v < n; ++v) {
            const uint8_t kind = in.next();
            Point2f q(in.next() * 0.5f - 8.f, in.next() * 0.5f - 8.f);
            if (kind == 0xff)
                q.x = NAN;
            else if (kind == 0xfe)
                q.y = INFINITY;
            else if (kind == 0xfd)
                q.x = -1e30f;
            else if (kind == 0xfc && !polygon.empty())
                q = polygon.back();  // repeated vertex
            polygon.push_back(q);
        }
        cage.addPolygon(polygon);
    }
    const bool withPose = in.next() & 1;
    if (withPose) {  // rest positions nudged by a few bytes, sometimes NaN
        std::vector<Point2f> pose = cage.vertices();
        pose.resize(cage.vertexCount());
        for (Point2f& q : pose) {
            const uint8_t b = in.next();
            q += Point2f((b & 15) - 8.f, (b >> 4) - 8.f);
            if (b == 0x77) q.y = NAN;
        }
        try {
            cage.addPose("fuzz", pose);
        } catch (const cv::Exception&) {
            finding("addPose refused a pose of vertexCount() points");
        }
    }

    std::string why;
    const bool geometry = cage.validateGeometry(&why);
    if (!geometry && why.empty()) finding("validateGeometry gave no reason");
    why.clear();
    const bool valid = cage.validate(&why);
    if (!valid && why.empty()) finding("validate gave no reason");
    if (valid && !geometry) finding("validate passed where validateGeometry failed");
    if (!geometry) {
        cage.orient();  // must not crash on invalid input either
        return 0;
    }
    std::vector<int> depth(cage.polygonCount());
    std::vector<double> area(cage.polygonCount());
    for (int p = 0; p < cage.polygonCount(); ++p)
        depth[p] = cage.depth(p), area[p] = cage.signedArea(p);
    const std::vector<Point2f> restBefore = cage.vertices();
    const std::vector<Point2f> poseBefore =
        withPose ? cage.pose(0).vertices : std::vector<Point2f>();
    cage.orient();
    if (!cage.validate(&why)) {
        std::fprintf(stderr, "%s\n", why.c_str());
        finding("valid geometry fails validate() after orient()");
    }
    for (int p = 0; p < cage.polygonCount(); ++p) {
        if (cage.depth(p) != depth[p]) finding("orient() changed a depth");
        if (std::abs(std::abs(cage.signedArea(p)) - std::abs(area[p])) >
            1e-9 * (1 + std::abs(area[p])))
            finding("orient() changed an area's magnitude");
    }
    if (withPose) {  // the pose's displacement of each rest vertex is kept
        const std::vector<Point2f> rest = cage.vertices();
        const std::vector<Point2f>& pose = cage.pose(0).vertices;
        for (int i = 0; i < cage.vertexCount(); ++i) {
            int j = 0;  // where rest vertex i was before orient()
            while (j < cage.vertexCount() && restBefore[j] != rest[i]) ++j;
            if (j == cage.vertexCount()) finding("orient() invented a vertex");
            const Point2f a = pose[i] - rest[i], b = poseBefore[j] - restBefore[j];
            if (!(a == b) && !(std::isnan(a.x + a.y) && std::isnan(b.x + b.y)))
                finding("orient() separated a pose vertex from its rest vertex");
        }
    }
    return 0;
}

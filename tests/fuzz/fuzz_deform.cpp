// libFuzzer target: binding and CPU deformation with random poses on small images.
// Bytes pick an image (size <= 64x64, type, sometimes an unsupported one), a multicage (star
// polygons side by side or nested, so that most are valid; sometimes raw polygons that may
// cross), coordinates, grid step, memory budget, and a pose in which each vertex is kept,
// nudged, thrown far away (+-1e6), collapsed with its polygon onto one point, swapped with
// another (fold-over), set to NaN or infinity, or given raw float bits.
// Contract: a cv::Exception or an output of the input's size and type whose maps hold either
// the "uncovered" value or a source position inside the image; never a crash, a hang, or
// undefined behaviour (the build runs ASan and UBSan without recovery).
#include <opencv2/core/utility.hpp>
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/multicage.hpp>

#include "fuzz_common.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

using namespace cv;
using namespace cv::multicage;
using multicage_fuzz::Bytes;

namespace {

[[noreturn]] void finding(const char* what) { multicage_fuzz::finding("fuzz_deform", what); }

std::vector<Point2f> star(Bytes& in, Point2f centre, float rMin, float rMax) {
    const int n = 3 + in.next() % 6;
    std::vector<Point2f> v;
    for (int i = 0; i < n; ++i) {
        const float a = static_cast<float>(2 * CV_PI) * (i + 0.8f * in.unit()) / n;
        const float r = rMin + (rMax - rMin) * in.unit();
        v.emplace_back(centre.x + r * std::cos(a), centre.y + r * std::sin(a));
    }
    return v;
}

Multicage makeCage(Bytes& in, Size size) {
    Multicage cage(size);
    const float w = static_cast<float>(size.width), h = static_cast<float>(size.height);
    switch (in.next() % 4) {
        case 0:  // one polygon
            cage.addPolygon(star(in, Point2f(w / 2 - 0.5f, h / 2 - 0.5f), 0.5f, 0.45f * std::min(w, h)));
            break;
        case 1:  // nested: the inner polygon protects its region
            cage.addPolygon(star(in, Point2f(w / 2 - 0.5f, h / 2 - 0.5f), 0.3f * std::min(w, h),
                                 0.45f * std::min(w, h)));
            cage.addPolygon(star(in, Point2f(w / 2 - 0.5f, h / 2 - 0.5f), 0.5f, 0.25f * std::min(w, h)));
            break;
        case 2:  // side by side
            cage.addPolygon(star(in, Point2f(w / 4, h / 2), 0.5f, 0.22f * std::min(w, h)));
            cage.addPolygon(star(in, Point2f(3 * w / 4 - 1, h / 2), 0.5f, 0.22f * std::min(w, h)));
            break;
        default: {  // raw polygons: often crossing, touching or outside; bind must refuse them
            const int polygons = 1 + in.next() % 3;
            for (int p = 0; p < polygons; ++p) {
                std::vector<Point2f> v(3 + in.next() % 5);
                for (Point2f& q : v) q = Point2f(in.unit() * (w + 2) - 1.5f, in.unit() * (h + 2) - 1.5f);
                cage.addPolygon(v);
            }
        }
    }
    if (in.next() & 1) cage.orient();
    return cage;
}

std::vector<Point2f> makePose(Bytes& in, const Multicage& cage) {
    std::vector<Point2f> pose = cage.vertices();
    const int user = cage.vertexCount();
    const bool withFrame = in.next() % 4 == 0;  // the frame corners may move too
    const int movable = withFrame ? user + 4 : user;
    for (int i = 0; i < movable; ++i) {
        const uint8_t mode = in.next();
        switch (mode % 16) {
            case 0: case 1: case 2: case 3: case 4: break;  // at rest
            case 5: case 6: case 7:  // nudged by up to +-16 px
                pose[i] += Point2f((in.unit() - 0.5f) * 32, (in.unit() - 0.5f) * 32);
                break;
            case 8:  // far outside the image
                pose[i] = Point2f(in.next() & 1 ? 1e6f : -1e6f, in.next() & 1 ? 1e6f : -1e6f);
                break;
            case 9: {  // collapse vertex i's polygon onto one point
                for (int p = 0, first = 0; p < cage.polygonCount(); first += static_cast<int>(cage.polygon(p).size()), ++p) {
                    const int n = static_cast<int>(cage.polygon(p).size());
                    if (i >= first && i < first + n)
                        for (int k = first; k < first + n; ++k) pose[k] = pose[i];
                }
                break;
            }
            case 10:  // swap with another vertex: folds the mesh over
                std::swap(pose[i], pose[in.next() % movable]);
                break;
            case 11:  // mirror through the image centre
                pose[i] = Point2f(cage.imageSize().width - 1.f, cage.imageSize().height - 1.f) - pose[i];
                break;
            case 12:
                pose[i].x = mode & 16 ? NAN : INFINITY;
                break;
            case 13:
                pose[i].y = mode & 16 ? -INFINITY : NAN;
                break;
            default:  // any float at all, huge and tiny ones included
                pose[i] = Point2f(in.raw(), in.raw());
        }
    }
    if (!withFrame) pose.resize(user);
    return pose;
}

bool mapsAreSane(const Mat& mapx, const Mat& mapy, Size size) {
    if (mapx.size() != size || mapy.size() != size || mapx.type() != CV_32F || mapy.type() != CV_32F)
        return false;
    for (int y = 0; y < size.height; ++y)
        for (int x = 0; x < size.width; ++x) {
            const float u = mapx.at<float>(y, x), v = mapy.at<float>(y, x);
            const bool uncovered = u == -1e4f && v == -1e4f;
            const bool inside = u >= -1.f && u <= size.width && v >= -1.f && v <= size.height;
            if (!uncovered && !inside) {
                std::fprintf(stderr, "map at (%d, %d) = (%g, %g)\n", x, y, u, v);
                return false;
            }
        }
    return true;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    multicage_fuzz::quietLibrary();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size > 1024) return -1;
    Bytes in{data, size};
    const Size imageSize(1 + in.next() % 64, 1 + in.next() % 64);
    static const int types[] = {CV_8UC1, CV_8UC3, CV_8UC4, CV_16UC1, CV_16UC3, CV_32FC1,
                                CV_32FC4, CV_8UC3, CV_8UC1, CV_8UC3, CV_64FC1, CV_8UC2};
    const uint8_t typeByte = in.next();
    const int type = types[typeByte % 12];
    Mat image(imageSize, type);
    randu(image, Scalar::all(0), Scalar::all(type == CV_32FC1 || type == CV_32FC4 ? 1 : 255));
    const Multicage cage = makeCage(in, imageSize);
    DeformParams params;
    params.backend = BACKEND_CPU;
    params.coordinates = in.next() % 8 == 0 ? HARMONIC : MEAN_VALUE;
    params.gridStep = 1 + in.next() % 4;
    const uint8_t budget = in.next();
    if (budget < 16) {  // tiny budgets: raise the grid step, or refuse
        params.memoryBudget = size_t(budget) * 1024;
        params.autoGridStep = budget & 1;
    }
    const std::vector<Point2f> pose = makePose(in, cage);

    Ptr<Deformer> d;
    try {
        d = Deformer::create(image, cage, params);
    } catch (const cv::Exception&) {
        return 0;  // invalid multicage, unsupported image, over budget: refused with a message
    }
    if (d->backend() != BACKEND_CPU) finding("BACKEND_CPU gave another backend");
    try {
        Mat out, mapx, mapy;
        d->deform(pose, out);
        if (out.size() != image.size() || out.type() != image.type()) finding("output of another size or type");
        d->computeMaps(pose, mapx, mapy);
        if (!mapsAreSane(mapx, mapy, imageSize)) finding("a map entry is neither uncovered nor in the image");
        if (d->foldedTriangles(pose) < 0) finding("negative fold-over count");
    } catch (const cv::Exception&) {
        return 0;  // a bad pose (count, NaN, infinity) refused with a message
    }
    return 0;
}

// libFuzzer target: binding and CPU deformation with random poses on small images.
// Bytes pick an image (size <= 64x64, type, sometimes an unsupported one), a multicage (star
// polygons side by side or nested, so that most are valid; sometimes raw polygons that may
// cross), coordinates, grid step, memory budget, and a pose in which each vertex is kept,
// nudged, thrown far away (+-1e6), collapsed with its polygon onto one point, swapped with
// another (fold-over), set to NaN or infinity, or given raw float bits.
// Contract: a cv::Exception or an output of the input's size and type whose maps hold either
// the "uncovered" value or a source position inside the image; never a crash, a hang, or
// undefined behaviour (the build runs ASan and UBSan without recovery).
// Then the entry points that take arrays (Python's transform_points, random_pose, deform_many;
// issue 22 item 2), on the same Deformer once it accepted the pose:
// - transformPoints: points inside, outside, on cage vertices, non-finite or raw floats, as
//   float, double or int arrays: a cv::Exception exactly when a point is not finite, else one
//   point out per point in, finite for finite moderate input, and at the rest pose every
//   point stays where it is.
// - randomPose: any amplitude (0, small, huge, negative, NaN, infinity), few or many
//   attempts: a cv::Exception only for a bad amplitude or a multicage that fails
//   validateGeometry(); else a pose within the amplitude that validatePose() accepts and that
//   folds no triangle of the Deformer's mesh.
// - deformBatch: the fuzzed pose, the rest pose and the random pose, with the Deformer's own
//   image or one image per pose: the same bits as deform() one at a time, the Deformer's own
//   image untouched; images of another size or type, or a count that does not match, refused.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <opencv2/core/utility.hpp>
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/multicage.hpp>
#include <string>
#include <vector>

#include "fuzz_common.hpp"

using namespace cv;
using namespace cv::multicage;
using multicage_fuzz::Bytes;

namespace {

[[noreturn]] void finding(const char* what) {
    multicage_fuzz::finding("fuzz_deform", what);
}

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
            cage.addPolygon(
                star(in, Point2f(w / 2 - 0.5f, h / 2 - 0.5f), 0.5f, 0.45f * std::min(w, h)));
            break;
        case 1:  // nested: the inner polygon protects its region
            cage.addPolygon(star(in, Point2f(w / 2 - 0.5f, h / 2 - 0.5f), 0.3f * std::min(w, h),
                                 0.45f * std::min(w, h)));
            cage.addPolygon(
                star(in, Point2f(w / 2 - 0.5f, h / 2 - 0.5f), 0.5f, 0.25f * std::min(w, h)));
            break;
        case 2:  // side by side
            cage.addPolygon(star(in, Point2f(w / 4, h / 2), 0.5f, 0.22f * std::min(w, h)));
            cage.addPolygon(star(in, Point2f(3 * w / 4 - 1, h / 2), 0.5f, 0.22f * std::min(w, h)));
            break;
        default: {  // raw polygons: often crossing, touching or outside; bind must refuse them
            const int polygons = 1 + in.next() % 3;
            for (int p = 0; p < polygons; ++p) {
                std::vector<Point2f> v(3 + in.next() % 5);
                for (Point2f& q : v)
                    q = Point2f(in.unit() * (w + 2) - 1.5f, in.unit() * (h + 2) - 1.5f);
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
            case 0:
            case 1:
            case 2:
            case 3:
            case 4:
                break;  // at rest
            case 5:
            case 6:
            case 7:  // nudged by up to +-16 px
                pose[i] += Point2f((in.unit() - 0.5f) * 32, (in.unit() - 0.5f) * 32);
                break;
            case 8:  // far outside the image
                pose[i] = Point2f(in.next() & 1 ? 1e6f : -1e6f, in.next() & 1 ? 1e6f : -1e6f);
                break;
            case 9: {  // collapse vertex i's polygon onto one point
                for (int p = 0, first = 0; p < cage.polygonCount();
                     first += static_cast<int>(cage.polygon(p).size()), ++p) {
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
                pose[i] =
                    Point2f(cage.imageSize().width - 1.f, cage.imageSize().height - 1.f) - pose[i];
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

/** Points for transformPoints, as bytes choose: mostly inside the image frame, some on cage
vertices, some far outside, some non-finite or raw float bits. */
std::vector<Point2f> makePoints(Bytes& in, const Multicage& cage) {
    const float w = static_cast<float>(cage.imageSize().width),
                h = static_cast<float>(cage.imageSize().height);
    const std::vector<Point2f> vertices = cage.vertices();
    std::vector<Point2f> points(in.next() % 9);
    for (Point2f& q : points) {
        const uint8_t mode = in.next();
        switch (mode % 8) {
            case 0:
            case 1:
            case 2:
            case 3:
                q = Point2f(in.unit() * w - 0.5f, in.unit() * h - 0.5f);
                break;
            case 4:
                q = vertices[in.next() % vertices.size()];
                break;  // a cage vertex or frame corner
            case 5:
                q = Point2f((in.unit() - 0.5f) * 8 * w, (in.unit() - 0.5f) * 8 * h);
                break;
            case 6:
                q = Point2f(mode & 8 ? NAN : INFINITY, mode & 16 ? -INFINITY : 0.f);
                break;
            default:
                q = Point2f(in.raw(), in.raw());
        }
    }
    return points;
}

bool finite(const std::vector<Point2f>& points, float limit = INFINITY) {
    for (const Point2f& p : points)
        if (!(std::abs(p.x) < limit && std::abs(p.y) < limit)) return false;
    return true;
}

/** points as the array type bytes choose: std::vector<Point2f>, an Nx2 CV_64F matrix, or an
Nx1 CV_32SC2 one (non-finite and huge values clamped to int, as a caller would). */
Mat pointsArray(uint8_t kind, const std::vector<Point2f>& points, std::vector<Point2f>& asGiven) {
    asGiven = points;
    const int n = static_cast<int>(points.size());
    if (kind % 3 == 1) {
        Mat m(n, 2, CV_64F);
        for (int i = 0; i < n; ++i)
            m.at<double>(i, 0) = points[i].x, m.at<double>(i, 1) = points[i].y;
        return m;
    }
    if (kind % 3 == 2) {
        Mat m(n, 1, CV_32SC2);
        for (int i = 0; i < n; ++i) {
            auto toInt = [](float v) {
                return std::isfinite(v) ? static_cast<int>(std::max(-1e6f, std::min(1e6f, v))) : 0;
            };
            m.at<Vec2i>(i) = Vec2i(toInt(points[i].x), toInt(points[i].y));
            asGiven[i] = Point2f(static_cast<float>(m.at<Vec2i>(i)[0]),
                                 static_cast<float>(m.at<Vec2i>(i)[1]));
        }
        return m;
    }
    return Mat(asGiven, false).reshape(2, n);
}

/** Bit for bit (NaN pixels included). */
bool sameMat(const Mat& a, const Mat& b) {
    if (a.size() != b.size() || a.type() != b.type()) return false;
    const Mat x = a.isContinuous() ? a : a.clone(), y = b.isContinuous() ? b : b.clone();
    return x.empty() || std::memcmp(x.data, y.data, x.total() * x.elemSize()) == 0;
}

bool mapsAreSane(const Mat& mapx, const Mat& mapy, Size size) {
    if (mapx.size() != size || mapy.size() != size || mapx.type() != CV_32F ||
        mapy.type() != CV_32F)
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

/** What the bytes pick before the Deformer exists: the image, the multicage, the parameters and
the pose (in this order of bytes). */
struct FuzzCase {
    Size imageSize;
    int type = 0;
    Mat image;
    Multicage cage;
    DeformParams params;
    std::vector<Point2f> pose;
};

Mat randomImage(Size size, int type) {
    Mat image(size, type);
    randu(image, Scalar::all(0), Scalar::all(type == CV_32FC1 || type == CV_32FC4 ? 1 : 255));
    return image;
}

FuzzCase makeCase(Bytes& in) {
    FuzzCase c;
    // Up to 40x40 (was 64x64: 2.6 times the pixels for no other kind of input; issue 22).
    c.imageSize = Size(1 + in.next() % 40, 1 + in.next() % 40);
    static const int types[] = {CV_8UC1,  CV_8UC3, CV_8UC4, CV_16UC1, CV_16UC3, CV_32FC1,
                                CV_32FC4, CV_8UC3, CV_8UC1, CV_8UC3,  CV_64FC1, CV_8UC2};
    const uint8_t typeByte = in.next();
    c.type = types[typeByte % 12];
    c.image = randomImage(c.imageSize, c.type);
    c.cage = makeCage(in, c.imageSize);
    DeformParams& params = c.params;
    params.backend = BACKEND_CPU;
    params.coordinates = in.next() % 8 == 0 ? HARMONIC : MEAN_VALUE;
    params.gridStep = 1 + in.next() % 4;
    // A harmonic binding factorises a sparse system of one unknown per node: at most ~12x12
    // nodes here (a coarser grid on larger images), else it takes most of the fuzzing time.
    if (params.coordinates == HARMONIC)
        params.gridStep =
            std::max(params.gridStep, (std::max(c.imageSize.width, c.imageSize.height) + 11) / 12);
    const uint8_t budget = in.next();
    if (budget < 16) {  // tiny budgets: raise the grid step, or refuse
        params.memoryBudget = size_t(budget) * 1024;
        params.autoGridStep = budget & 1;
    }
    c.pose = makePose(in, c.cage);
    return c;
}

/** deform, computeMaps and foldedTriangles at the fuzzed pose: false when the pose is refused
with a message, a finding when an output breaks the contract. */
bool deformsWithinContract(Deformer& d, const FuzzCase& c) {
    try {
        Mat out, mapx, mapy;
        d.deform(c.pose, out);
        if (out.size() != c.image.size() || out.type() != c.image.type())
            finding("output of another size or type");
        d.computeMaps(c.pose, mapx, mapy);
        if (!mapsAreSane(mapx, mapy, c.imageSize))
            finding("a map entry is neither uncovered nor in the image");
        if (d.foldedTriangles(c.pose) < 0) finding("negative fold-over count");
    } catch (const cv::Exception&) {
        return false;  // a bad pose (count, NaN, infinity) refused with a message
    }
    return true;
}

/** At rest every point stays, up to rounding. Checked up to 1e6 px: far beyond that the
frame's bilinear map (expanded, with u*v terms ~ (p/W)(p/H)) cancels and loses relative
precision (a point at 3e20 moved by 8e15 px, 2.5e-5 of it). */
void checkPointsStayAtRest(const std::vector<Point2f>& given, const std::vector<Point2f>& out) {
    for (size_t i = 0; i < out.size(); ++i) {
        const Point2f p = given[i], q = out[i];
        if (!finite(std::vector<Point2f>{p}, 1e6f)) continue;
        const float tolerance = 1e-3f + 1e-6f * std::max(std::abs(p.x), std::abs(p.y));
        if (!(std::abs(q.x - p.x) <= tolerance && std::abs(q.y - p.y) <= tolerance)) {
            std::fprintf(stderr, "(%g, %g) landed at (%g, %g)\n", p.x, p.y, q.x, q.y);
            finding("at the rest pose transformPoints moved a point");
        }
    }
}

/** transformPoints, at the fuzzed pose and at rest. */
void checkTransformPoints(Bytes& in, Deformer& d, const Multicage& cage,
                          const std::vector<Point2f>& pose, const std::vector<Point2f>& rest) {
    std::vector<Point2f> given;
    const std::vector<Point2f> points = makePoints(in, cage);
    const Mat array = pointsArray(in.next(), points, given);
    const bool pointsFinite = finite(given);
    for (int atRest = 0; atRest < 2; ++atRest) {
        Mat landed;
        try {
            if (atRest)
                d.transformPoints(rest, array, landed);
            else
                d.transformPoints(pose, array, landed);
        } catch (const cv::Exception& e) {
            if (!pointsFinite) continue;
            std::fprintf(stderr, "%s\n", e.what());
            finding("transformPoints refused finite points at a pose deform() accepted");
        }
        if (!pointsFinite) finding("transformPoints took a point that is not finite");
        if (landed.total() != given.size() || (!given.empty() && landed.type() != CV_32FC2))
            finding("transformPoints gave another number of points or not CV_32FC2");
        if (given.empty()) continue;
        const std::vector<Point2f> out(landed.begin<Point2f>(), landed.end<Point2f>());
        if (finite(given, 1e6f) && finite(pose, 1e6f) && !finite(out))
            finding("transformPoints gave a non-finite point for finite moderate input");
        if (atRest) checkPointsStayAtRest(given, out);
    }
}

/** A pose randomPose gave: within the amplitude, valid, folding nothing of the Deformer's mesh. */
void checkDrawnPose(Deformer& d, const Multicage& cage, const std::vector<Point2f>& rest,
                    const std::vector<Point2f>& drawn, double amplitude) {
    if (static_cast<int>(drawn.size()) != cage.vertexCount())
        finding("randomPose gave another vertex count");
    for (int j = 0; j < cage.vertexCount(); ++j)
        if (!(norm(drawn[j] - rest[j]) <= amplitude * (1 + 1e-5) + 1e-3))
            finding("randomPose moved a vertex beyond the amplitude");
    std::string why;
    if (!validatePose(cage, drawn, &why)) {
        std::fprintf(stderr, "%s\n", why.c_str());
        finding("randomPose gave a pose validatePose() refuses");
    }
    if (d.foldedTriangles(drawn) != 0)
        finding("randomPose gave a pose that folds the Deformer's mesh");
}

/** randomPose on the Deformer's binding; the pose it drew (empty when it refused). */
std::vector<Point2f> checkRandomPose(Bytes& in, Deformer& d, const Multicage& cage,
                                     const std::vector<Point2f>& rest) {
    const Binding& binding = d.binding();
    std::vector<Point2f> drawn;
    static const double amplitudes[] = {0.0, 0.5, 2.0, 8.0, 40.0, 1e6, -1.0, NAN, INFINITY, 3.0};
    const double amplitude = amplitudes[in.next() % 10];
    RNG rng(1 + in.next() * 257u + in.next());
    RandomPoseParams rp;
    rp.attempts = 1 + in.next() % 4;
    rp.scaleDowns = in.next() % 4;
    const bool cageMatchesBinding =
        cage.imageSize() == binding.imageSize && rest == cage.vertices();
    const bool mayRefuse = !(amplitude >= 0 && std::isfinite(amplitude)) ||
                           !cage.validateGeometry() || !cageMatchesBinding;
    try {
        drawn = randomPose(cage, binding, amplitude, rng, rp);
    } catch (const cv::Exception& e) {
        if (!mayRefuse) {
            std::fprintf(stderr, "%s\n", e.what());
            finding("randomPose refused a valid multicage and amplitude");
        }
    }
    if (!drawn.empty()) {
        if (mayRefuse && !cageMatchesBinding)
            finding("randomPose took a binding of another multicage");
        checkDrawnPose(d, cage, rest, drawn, amplitude);
    }
    return drawn;
}

/** deformBatch: the same bits as deform() one at a time; own is the Deformer's deform() of
the fuzzed pose before the batch. */
void checkDeformBatch(Bytes& in, Deformer& d, const FuzzCase& c, const std::vector<Point2f>& rest,
                      const std::vector<Point2f>& drawn, const Mat& own) {
    std::vector<std::vector<Point2f>> poses = {
        c.pose, std::vector<Point2f>(rest.begin(), rest.begin() + c.cage.vertexCount())};
    if (!drawn.empty()) poses.push_back(drawn);
    const int n = static_cast<int>(poses.size());
    const uint8_t mode = in.next() % 4;
    std::vector<Mat> images;
    if (mode >= 1) {  // one image per pose; 2: the last of another size; 3: one too few
        for (int k = 0; k < n; ++k) images.push_back(randomImage(c.imageSize, c.type));
        if (mode == 2)
            images.back() = Mat(c.imageSize.height + 1, c.imageSize.width, c.type, Scalar::all(1));
        if (mode == 3) images.pop_back();
    }
    std::vector<Mat> outs;
    try {
        d.deformBatch(poses, outs, images);
    } catch (const cv::Exception& e) {
        if (mode <= 1) {
            std::fprintf(stderr, "%s\n", e.what());
            finding("deformBatch refused poses deform() accepted");
        }
        return;
    }
    if (mode >= 2) finding("deformBatch took images of another size, or another number of them");
    if (static_cast<int>(outs.size()) != n) finding("deformBatch gave another number of images");
    Mat again;
    d.deform(c.pose, again);
    if (!sameMat(again, own)) finding("deformBatch changed the Deformer's own image");
    for (int k = 0; k < n; ++k) {
        if (mode == 1) d.setImage(images[k]);
        Mat one;
        d.deform(poses[k], one);
        if (!sameMat(one, outs[k])) finding("deformBatch differs from deform() one at a time");
    }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    multicage_fuzz::quietLibrary();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size > 1024) return -1;
    Bytes in{data, size};
    const FuzzCase c = makeCase(in);
    Ptr<Deformer> d;
    try {
        d = Deformer::create(c.image, c.cage, c.params);
    } catch (const cv::Exception&) {
        return 0;  // invalid multicage, unsupported image, over budget: refused with a message
    }
    if (d->backend() != BACKEND_CPU) finding("BACKEND_CPU gave another backend");
    if (!deformsWithinContract(*d, c)) return 0;
    Mat own;
    d->deform(c.pose, own);
    const Binding& binding = d->binding();
    const std::vector<Point2f> rest(binding.restVertices.begin(), binding.restVertices.end());
    checkTransformPoints(in, *d, c.cage, c.pose, rest);
    const std::vector<Point2f> drawn = checkRandomPose(in, *d, c.cage, rest);
    checkDeformBatch(in, *d, c, rest, drawn, own);
    return 0;
}

#include "fixtures.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace multicage_fixtures {

using cv::Point2f;
using cv::multicage::Multicage;

std::vector<Point2f> starPolygon(Point2f centre, const std::vector<float>& radii, float phase) {
    std::vector<Point2f> out;
    const int n = static_cast<int>(radii.size());
    for (int i = 0; i < n; ++i) {
        const float a = phase + static_cast<float>(2 * CV_PI * i / n);
        out.emplace_back(centre.x + radii[i] * std::cos(a), centre.y + radii[i] * std::sin(a));
    }
    return out;
}

Multicage lotusMulticage(cv::Size size, int vertices) {
    CV_Assert(vertices >= 12);
    Multicage cage(size);
    // Split: each flower gets half; within a flower 60% outer petals, 40% inner heart.
    const int flowerA = vertices / 2, flowerB = vertices - flowerA;
    const float R = 0.23f * std::min(size.width / 2.f, static_cast<float>(size.height));
    for (int f = 0; f < 2; ++f) {
        const int n = f == 0 ? flowerA : flowerB;
        const int outer = std::max(3, (n * 3 + 2) / 5), inner = n - outer;
        const Point2f c(size.width * (f == 0 ? 0.28f : 0.72f), size.height * 0.5f);
        std::vector<float> petals(outer), heart(inner);
        for (int i = 0; i < outer; ++i) petals[i] = R * (i % 2 ? 1.6f : 1.15f);  // petal tips
        for (int i = 0; i < inner; ++i) heart[i] = R * (i % 2 ? 0.45f : 0.55f);
        cage.addPolygon(starPolygon(c, petals));
        cage.addPolygon(starPolygon(c, heart, 0.1f));
    }
    cage.orient();
    return cage;
}

namespace {
void addNested(cv::RNG& rng, Multicage& cage, Point2f c, float radius, int depth, int maxDepth,
               int perPolygon) {
    const int n = std::max(3, perPolygon / 2 + rng.uniform(0, perPolygon + 1));
    std::vector<float> radii(n);
    for (float& r : radii) r = radius * rng.uniform(0.75f, 1.f);
    cage.addPolygon(starPolygon(c, radii, rng.uniform(0.f, 6.28f)));
    if (depth < maxDepth && rng.uniform(0, 4) != 0) {
        const int children = rng.uniform(1, 3);
        if (children == 1) {
            addNested(rng, cage, c, radius * rng.uniform(0.3f, 0.6f), depth + 1, maxDepth,
                      perPolygon);
        } else {  // two children side by side inside the inner disk of radius 0.75*radius
            const float r = radius * 0.3f;
            addNested(rng, cage, c + Point2f(-0.37f * radius, 0), r, depth + 1, maxDepth,
                      perPolygon);
            addNested(rng, cage, c + Point2f(0.37f * radius, 0), r, depth + 1, maxDepth,
                      perPolygon);
        }
    }
}
}  // namespace

Multicage randomMulticage(cv::RNG& rng, cv::Size size, int maxTop, int maxDepth, int perPolygon) {
    Multicage cage(size);
    std::vector<cv::Vec3f> disks;  // x, y, r
    const int top = rng.uniform(1, maxTop + 1);
    for (int attempt = 0; attempt < 200 && static_cast<int>(disks.size()) < top; ++attempt) {
        const float rmax = 0.45f * std::min(size.width, size.height);
        const float r = rng.uniform(0.25f * rmax, rmax);
        // One draw per statement (y first, GCC's order of arguments): the same fixture
        // from every compiler.
        const float cy = rng.uniform(r + 2.f, size.height - r - 2.f);
        const Point2f c(rng.uniform(r + 2.f, size.width - r - 2.f), cy);
        bool free = true;
        for (const cv::Vec3f& d : disks)
            free = free && std::hypot(c.x - d[0], c.y - d[1]) > r + d[2] + 2.f;
        if (!free) continue;
        disks.emplace_back(c.x, c.y, r);
        addNested(rng, cage, c, r, 1, maxDepth, perPolygon);
    }
    cage.orient();
    return cage;
}

std::vector<Point2f> stretchPolygon(const Multicage& cage, int polygon, float sx, float sy,
                                    Point2f shift) {
    std::vector<Point2f> pose = cage.vertices();
    pose.resize(cage.vertexCount());
    const std::vector<Point2f> p = cage.polygon(polygon);
    Point2f c(0, 0);
    for (const Point2f& q : p) c += q;
    c *= 1.f / p.size();
    const int offset = cage.polygonOffset(polygon);
    for (size_t i = 0; i < p.size(); ++i) {
        const Point2f d = p[i] - c;
        pose[offset + i] = c + Point2f(d.x * sx, d.y * sy) + shift;
    }
    return pose;
}

std::vector<Point2f> wavePose(const Multicage& cage, float amplitude, float phase) {
    std::vector<Point2f> pose = cage.vertices();
    pose.resize(cage.vertexCount());
    const cv::Size s = cage.imageSize();
    for (Point2f& p : pose) {
        const float u = p.x / s.width, v = p.y / s.height;
        p += amplitude * Point2f(std::sin(6.f * v + phase), std::cos(5.f * u + 0.7f * phase));
    }
    return pose;
}

double similarityResidual(const std::vector<Point2f>& rest, const std::vector<Point2f>& moved) {
    const size_t n = std::min(rest.size(), moved.size());
    if (n < 2) return INFINITY;
    // The least-squares similarity in closed form: centre both sets, then q = [a -b; b a] p.
    cv::Point2d cp(0, 0), cq(0, 0);
    for (size_t i = 0; i < n; ++i) cp += cv::Point2d(rest[i]), cq += cv::Point2d(moved[i]);
    cp *= 1.0 / n, cq *= 1.0 / n;
    double a = 0, b = 0, norm2 = 0;
    for (size_t i = 0; i < n; ++i) {
        const cv::Point2d p = cv::Point2d(rest[i]) - cp, q = cv::Point2d(moved[i]) - cq;
        a += p.x * q.x + p.y * q.y, b += p.x * q.y - p.y * q.x, norm2 += p.dot(p);
    }
    if (!(norm2 > 0)) return INFINITY;
    a /= norm2, b /= norm2;
    double sum = 0;
    for (size_t i = 0; i < n; ++i) {
        const cv::Point2d p = cv::Point2d(rest[i]) - cp;
        sum += cv::norm(cq + cv::Point2d(a * p.x - b * p.y, b * p.x + a * p.y) -
                        cv::Point2d(moved[i]));
    }
    return sum / n;
}

namespace {
cv::Rect2d innerBox(const cv::Rect2d& box, double inner) {
    const double dx = 0.5 * (1 - inner) * box.width, dy = 0.5 * (1 - inner) * box.height;
    return cv::Rect2d(box.x + dx, box.y + dy, box.width - 2 * dx, box.height - 2 * dy);
}
}  // namespace

std::vector<Point2f> boxNodes(const cv::multicage::Binding& binding, const cv::Rect2d& box,
                              double inner) {
    const cv::Rect2d r = innerBox(box, inner);
    std::vector<Point2f> nodes;
    for (int gy = 0; gy < binding.gridSize.height; ++gy)
        for (int gx = 0; gx < binding.gridSize.width; ++gx) {
            const Point2f p = binding.node(gx, gy);
            if (r.contains(cv::Point2d(p))) nodes.push_back(p);
        }
    return nodes;
}

double boxResidual(const cv::multicage::Binding& binding, const std::vector<Point2f>& pose,
                   const cv::Rect2d& box, double inner) {
    cv::Mat moved;
    binding.apply(pose, moved);
    const cv::Rect2d r = innerBox(box, inner);
    std::vector<Point2f> rest, after;
    for (int gy = 0; gy < binding.gridSize.height; ++gy)
        for (int gx = 0; gx < binding.gridSize.width; ++gx) {
            const Point2f p = binding.node(gx, gy);
            if (!r.contains(cv::Point2d(p))) continue;
            rest.push_back(p);
            after.push_back(moved.at<Point2f>(gy, gx));
        }
    return rest.size() < 3 ? INFINITY : similarityResidual(rest, after);
}

cv::Mat polygonMask(const std::vector<cv::Point2f>& polygon, cv::Size size) {
    cv::Mat m = cv::Mat::zeros(size, CV_8U);
    std::vector<cv::Point> pts;
    for (const cv::Point2f& p : polygon) pts.emplace_back(cvRound(p.x), cvRound(p.y));
    cv::fillPoly(m, std::vector<std::vector<cv::Point>>{pts}, cv::Scalar(255));
    return m;
}

namespace {

// The inner polygons (depth 2 or more) of cage holding at least `share` of `target`'s pixels
// (255 on the thing held) and at most `maxArea` pixels in all.
std::vector<int> innerHolders(const cv::multicage::Multicage& cage, const cv::Mat& target,
                              double share, double maxArea) {
    const double need = share * cv::countNonZero(target);
    std::vector<int> holders;
    for (int p = 0; p < cage.polygonCount(); ++p) {
        if (cage.depth(p) < 2) continue;
        const cv::Mat m = polygonMask(cage.polygon(p), cage.imageSize());
        if (cv::countNonZero(m & target) >= need && cv::countNonZero(m) <= maxArea)
            holders.push_back(p);
    }
    return holders;
}

// 255 on `box` (clipped to the image), 0 elsewhere.
cv::Mat boxMask(const cv::Rect& box, cv::Size size) {
    cv::Mat m = cv::Mat::zeros(size, CV_8U);
    m(box & cv::Rect(cv::Point(), size)).setTo(255);
    return m;
}

}  // namespace

std::vector<int> eyeHolders(const cv::multicage::Multicage& cage, const cv::Rect& eye) {
    cv::Mat almond = cv::Mat::zeros(cage.imageSize(), CV_8U);
    cv::ellipse(almond,
                cv::RotatedRect(
                    cv::Point2f(eye.x + 0.5f * eye.width - 0.5f, eye.y + 0.5f * eye.height - 0.5f),
                    cv::Size2f(eye.width, eye.height), 0.f),
                cv::Scalar(255), cv::FILLED);
    return innerHolders(cage, almond, 0.95, 3.0 * eye.area());
}

std::vector<int> faceHolders(const cv::multicage::Multicage& cage, const cv::Rect& face) {
    const cv::Rect inner80(face.x + face.width / 10, face.y + face.height / 10,
                           face.width - 2 * (face.width / 10),
                           face.height - 2 * (face.height / 10));
    return innerHolders(cage, boxMask(inner80, cage.imageSize()), 0.95, 3.0 * face.area());
}

std::vector<int> featureHolders(const cv::multicage::Multicage& cage, const cv::Rect& feature) {
    const cv::Rect box = feature & cv::Rect(cv::Point(), cage.imageSize());
    if (box.empty()) return {};
    return innerHolders(cage, boxMask(box, cage.imageSize()), 0.9, 4.0 * box.area());
}

int outlineAround(const cv::multicage::Multicage& cage, const cv::Rect& box) {
    int around = -1;
    const cv::Point2f centre(box.x + box.width / 2.f, box.y + box.height / 2.f);
    for (int p = 0; p < cage.polygonCount(); ++p)
        if (cage.depth(p) == 1 && cv::pointPolygonTest(cage.polygon(p), centre, false) > 0)
            around = p;
    return around;
}

}  // namespace multicage_fixtures

#include "document.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <set>

namespace multicage_editor {

using cv::Point2f;
using cv::multicage::Multicage;

Document makeDocument(cv::Size imageSize) {
    Document doc;
    doc.cage = Multicage(imageSize);
    return doc;
}

Document makeDocument(const Multicage& cage) {
    Document doc;
    doc.cage = cage;
    doc.pose = cage.poseCount() > 0 ? cage.pose(0).vertices : positions(doc, Mode::Rest);
    if (static_cast<int>(doc.pose.size()) != cage.vertexCount())
        doc.pose = positions(doc, Mode::Rest);
    return doc;
}

std::vector<Point2f> positions(const Document& doc, Mode mode) {
    if (mode == Mode::Pose) return doc.pose;
    std::vector<Point2f> v = doc.cage.vertices();
    v.resize(static_cast<size_t>(doc.cage.vertexCount()));  // drop the frame corners
    return v;
}

std::pair<int, int> locateVertex(const Multicage& cage, int id) {
    if (id < 0) return {-1, -1};
    for (int i = 0; i < cage.polygonCount(); ++i) {
        const int n = static_cast<int>(cage.polygon(i).size());
        if (id < n) return {i, id};
        id -= n;
    }
    return {-1, -1};
}

void moveVertices(Document& doc, Mode mode, const std::vector<int>& ids, Point2f delta) {
    const int nv = doc.cage.vertexCount();
    std::set<int> moved;
    for (int id : ids)
        if (id >= 0 && id < nv) moved.insert(id);
    for (int id : moved) doc.pose[static_cast<size_t>(id)] += delta;
    if (mode == Mode::Pose) return;
    std::set<int> polygons;
    for (int id : moved) polygons.insert(locateVertex(doc.cage, id).first);
    for (int i : polygons) {
        std::vector<Point2f> p = doc.cage.polygon(i);
        const int offset = doc.cage.polygonOffset(i);
        for (size_t k = 0; k < p.size(); ++k)
            if (moved.count(offset + static_cast<int>(k))) p[k] += delta;
        doc.cage.setPolygon(i, p);  // same count: saved poses are kept
    }
}

int addPolygon(Document& doc, const std::vector<Point2f>& points) {
    const int i = doc.cage.addPolygon(points);
    doc.pose.insert(doc.pose.end(), points.begin(), points.end());
    return i;
}

void removePolygon(Document& doc, int i) {
    if (i < 0 || i >= doc.cage.polygonCount()) return;
    const auto begin = doc.pose.begin() + doc.cage.polygonOffset(i);
    doc.pose.erase(begin, begin + static_cast<std::ptrdiff_t>(doc.cage.polygon(i).size()));
    doc.cage.removePolygon(i);
}

void removeVertices(Document& doc, const std::vector<int>& ids) {
    const std::set<int> gone(ids.begin(), ids.end());
    // From the last polygon down, so earlier indices and offsets stay valid.
    for (int i = doc.cage.polygonCount() - 1; i >= 0; --i) {
        const int offset = doc.cage.polygonOffset(i);
        const std::vector<Point2f> rest = doc.cage.polygon(i);
        std::vector<Point2f> keptRest, keptPose;
        for (size_t k = 0; k < rest.size(); ++k) {
            const int id = offset + static_cast<int>(k);
            if (gone.count(id)) continue;
            keptRest.push_back(rest[k]);
            keptPose.push_back(doc.pose[static_cast<size_t>(id)]);
        }
        if (keptRest.size() == rest.size()) continue;
        if (keptRest.size() < 3) {
            removePolygon(doc, i);
            continue;
        }
        const auto begin = doc.pose.begin() + offset;
        doc.pose.erase(begin, begin + static_cast<std::ptrdiff_t>(rest.size()));
        doc.pose.insert(doc.pose.begin() + offset, keptPose.begin(), keptPose.end());
        doc.cage.setPolygon(i, keptRest);
    }
}

int insertVertex(Document& doc, int polygon, int edge, float t) {
    if (polygon < 0 || polygon >= doc.cage.polygonCount()) return -1;
    std::vector<Point2f> rest = doc.cage.polygon(polygon);
    const int n = static_cast<int>(rest.size());
    if (edge < 0 || edge >= n) return -1;
    t = std::min(1.f, std::max(0.f, t));
    const int offset = doc.cage.polygonOffset(polygon);
    const int a = edge, b = (edge + 1) % n;
    const Point2f pa = doc.pose[static_cast<size_t>(offset + a)];
    const Point2f pb = doc.pose[static_cast<size_t>(offset + b)];
    rest.insert(rest.begin() + a + 1, rest[a] + t * (rest[b] - rest[a]));
    doc.pose.insert(doc.pose.begin() + offset + a + 1, pa + t * (pb - pa));
    doc.cage.setPolygon(polygon, rest);
    return offset + a + 1;
}

bool orientDocument(Document& doc) {
    if (!doc.cage.validateGeometry()) return false;
    const std::vector<Point2f> before = positions(doc, Mode::Rest);
    Multicage withCurrent = doc.cage;
    const int k = withCurrent.addPose("__current", doc.pose);
    withCurrent.orient();
    doc.pose = withCurrent.pose(k).vertices;
    withCurrent.removePose(k);
    doc.cage = withCurrent;
    return positions(doc, Mode::Rest) != before;
}

int addPose(Document& doc, const std::string& name) {
    const int existing = doc.cage.findPose(name);
    if (existing >= 0) {
        cv::multicage::Pose p = doc.cage.pose(existing);
        p.vertices = doc.pose;
        doc.cage.setPose(existing, p);
        return existing;
    }
    const double time =
        doc.cage.poseCount() > 0 ? doc.cage.pose(doc.cage.poseCount() - 1).time + 1.0 : 0.0;
    return doc.cage.addPose(name, doc.pose, time);
}

bool restValid(const Document& doc, std::string* why) {
    return doc.cage.validateGeometry(why);
}

bool poseValid(const Document& doc, std::string* why) {
    // A pose may leave the image frame, so check it in a frame three times as large, shifted.
    const cv::Size s = doc.cage.imageSize();
    Multicage posed(cv::Size(3 * s.width, 3 * s.height));
    const Point2f shift(static_cast<float>(s.width), static_cast<float>(s.height));
    for (int i = 0; i < doc.cage.polygonCount(); ++i) {
        std::vector<Point2f> p(doc.pose.begin() + doc.cage.polygonOffset(i),
                               doc.pose.begin() + doc.cage.polygonOffset(i) +
                                   static_cast<std::ptrdiff_t>(doc.cage.polygon(i).size()));
        for (Point2f& q : p) q += shift;
        posed.addPolygon(p);
    }
    std::string reason;
    if (posed.validateGeometry(&reason)) return true;
    if (why) *why = "pose: " + reason;
    return false;
}

int hitVertex(const std::vector<Point2f>& pts, Point2f p, float radius) {
    int best = -1;
    float bestD = radius * radius;
    for (size_t i = 0; i < pts.size(); ++i) {
        const Point2f d = pts[i] - p;
        const float d2 = d.dot(d);
        if (d2 <= bestD) {
            bestD = d2;
            best = static_cast<int>(i);
        }
    }
    return best;
}

bool hitEdge(const Multicage& cage, const std::vector<Point2f>& pts, Point2f p, float radius,
             int* polygon, int* edge, float* t) {
    float bestD = radius * radius;
    bool found = false;
    for (int i = 0; i < cage.polygonCount(); ++i) {
        const int offset = cage.polygonOffset(i);
        const int n = static_cast<int>(cage.polygon(i).size());
        for (int k = 0; k < n; ++k) {
            const Point2f a = pts[static_cast<size_t>(offset + k)];
            const Point2f b = pts[static_cast<size_t>(offset + (k + 1) % n)];
            const Point2f ab = b - a;
            const float len2 = ab.dot(ab);
            const float s = len2 > 0 ? std::min(1.f, std::max(0.f, (p - a).dot(ab) / len2)) : 0.f;
            const Point2f d = a + s * ab - p;
            if (d.dot(d) <= bestD) {
                bestD = d.dot(d);
                *polygon = i;
                *edge = k;
                *t = s;
                found = true;
            }
        }
    }
    return found;
}

int hitPolygon(const Multicage& cage, const std::vector<Point2f>& pts, Point2f p) {
    int best = -1, bestDepth = -1;
    for (int i = 0; i < cage.polygonCount(); ++i) {
        const int offset = cage.polygonOffset(i);
        const std::vector<Point2f> poly(
            pts.begin() + offset,
            pts.begin() + offset + static_cast<std::ptrdiff_t>(cage.polygon(i).size()));
        if (poly.size() < 3 || cv::pointPolygonTest(poly, p, false) < 0) continue;
        const int d = cage.depth(i);
        if (d > bestDepth) {
            bestDepth = d;
            best = i;
        }
    }
    return best;
}

void History::push(const Document& before) {
    undo_.push_back(before);
    if (undo_.size() > capacity_) undo_.pop_front();
    redo_.clear();
}

bool History::undo(Document& doc) {
    if (undo_.empty()) return false;
    redo_.push_back(doc);
    doc = undo_.back();
    undo_.pop_back();
    return true;
}

bool History::redo(Document& doc) {
    if (redo_.empty()) return false;
    undo_.push_back(doc);
    doc = redo_.back();
    redo_.pop_back();
    return true;
}

}  // namespace multicage_editor

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <opencv2/multicage/internal/backend_contract.hpp>
#include <opencv2/multicage/internal/geometry.hpp>
#include <opencv2/multicage/internal/point_input.hpp>
#include <opencv2/multicage/multicage.hpp>

namespace cv {
namespace multicage {

std::vector<Point2f> toPoints(InputArray points, const char* what) {
    std::vector<Point2f> out;
    if (points.empty()) return out;
    Mat m = points.getMat();
    const int depth = m.depth();
    if (depth != CV_32F && depth != CV_64F && depth != CV_32S)
        CV_Error_(Error::StsBadArg,
                  ("multicage: %s must be CV_32F, CV_64F or CV_32S points", what));
    if (m.channels() == 2 && (m.cols == 1 || m.rows == 1)) {
        m = m.reshape(1, static_cast<int>(m.total()));
    } else if (!(m.channels() == 1 && m.cols == 2)) {
        CV_Error_(
            Error::StsBadSize,
            ("multicage: %s must be N points (Nx2, or Nx1 with 2 channels), got %dx%d with %d "
             "channels",
             what, m.rows, m.cols, m.channels()));
    }
    Mat f;
    m.convertTo(f, CV_32F);
    out.resize(f.rows);
    for (int i = 0; i < f.rows; ++i) out[i] = Point2f(f.at<float>(i, 0), f.at<float>(i, 1));
    return out;
}

Multicage::Multicage() = default;
Multicage::Multicage(Size imageSize) : imageSize_(imageSize) {}

int Multicage::addPolygon(InputArray points) {
    const std::vector<Point2f> polygon = toPoints(points, "polygon");
    const int offset = vertexCount();
    polygons_.push_back(polygon);
    for (Pose& pose : poses_)
        pose.vertices.insert(pose.vertices.begin() + offset, polygon.begin(), polygon.end());
    return polygonCount() - 1;
}

void Multicage::setPolygon(int i, InputArray points) {
    CV_Assert(0 <= i && i < polygonCount());
    std::vector<Point2f> polygon = toPoints(points, "polygon");
    const int offset = polygonOffset(i), oldCount = static_cast<int>(polygons_[i].size());
    if (static_cast<int>(polygon.size()) != oldCount) {
        for (Pose& pose : poses_) {
            pose.vertices.erase(pose.vertices.begin() + offset,
                                pose.vertices.begin() + offset + oldCount);
            pose.vertices.insert(pose.vertices.begin() + offset, polygon.begin(), polygon.end());
        }
    }
    polygons_[i] = std::move(polygon);
}

void Multicage::removePolygon(int i) {
    CV_Assert(0 <= i && i < polygonCount());
    const int offset = polygonOffset(i), count = static_cast<int>(polygons_[i].size());
    for (Pose& pose : poses_)
        pose.vertices.erase(pose.vertices.begin() + offset, pose.vertices.begin() + offset + count);
    polygons_.erase(polygons_.begin() + i);
}

void Multicage::orient() {
    const std::vector<int> depth = geometry::depths(polygons_);
    for (int i = 0; i < polygonCount(); ++i) {
        std::vector<Point2f>& polygon = polygons_[i];
        const double area = geometry::signedArea(polygon);
        const bool wantPositive = wantsPositiveArea(depth[i]);
        if (area == 0.0 || (area > 0) == wantPositive) continue;
        // Reverse keeping vertex 0 first, so vertex numbering changes as little as possible.
        std::reverse(polygon.begin() + 1, polygon.end());
        const int offset = polygonOffset(i);
        for (Pose& pose : poses_)
            if (static_cast<int>(pose.vertices.size()) == vertexCount())
                std::reverse(pose.vertices.begin() + offset + 1,
                             pose.vertices.begin() + offset + static_cast<int>(polygon.size()));
    }
}

static bool fail(std::string* why, const std::string& message) {
    if (why) *why = message;
    return false;
}

bool Multicage::validateGeometry(std::string* why) const {
    if (imageSize_.width <= 0 || imageSize_.height <= 0)
        return fail(why, format("the image size %dx%d is not positive", imageSize_.width,
                                imageSize_.height));
    // The node mesh a binding makes needs two nodes each way (one per pixel at grid step 1).
    if (imageSize_.width < 2 || imageSize_.height < 2)
        return fail(why, format("the image size %dx%d is too small: a multicage needs at least "
                                "2x2 pixels",
                                imageSize_.width, imageSize_.height));
    if (int64_t(imageSize_.width) * imageSize_.height > kMaxImagePixels)
        return fail(why, format("the image size %dx%d is over the limit of 2^30 pixels",
                                imageSize_.width, imageSize_.height));
    const float right = imageSize_.width - 0.5f, bottom = imageSize_.height - 0.5f;
    for (int p = 0; p < polygonCount(); ++p) {
        const std::vector<Point2f>& polygon = polygons_[p];
        const int n = static_cast<int>(polygon.size());
        if (n < 3) return fail(why, format("polygon %d has fewer than 3 vertices (%d)", p, n));
        for (int v = 0; v < n; ++v) {
            const Point2f q = polygon[v];
            if (!geometry::isFinite(q))
                return fail(why, format("polygon %d, vertex %d is not a finite number (%g, %g)", p,
                                        v, q.x, q.y));
            if (!(q.x > -0.5f && q.x < right && q.y > -0.5f && q.y < bottom))
                return fail(why, format("polygon %d is not inside the image frame: vertex %d at "
                                        "(%g, %g) is outside (-0.5, -0.5)-(%g, %g)",
                                        p, v, q.x, q.y, right, bottom));
            if (q == polygon[(v + 1) % n])
                return fail(why,
                            format("polygon %d repeats vertex %d at (%g, %g)", p, v, q.x, q.y));
        }
        if (std::abs(geometry::signedArea(polygon)) < 1e-9)
            return fail(why, format("polygon %d has zero area", p));
    }
    geometry::Crossing c;
    if (geometry::findCrossing(polygons_, &c)) {
        if (c.polygonA == c.polygonB)
            return fail(why, format("polygon %d intersects itself at edges %d and %d", c.polygonA,
                                    c.edgeA, c.edgeB));
        return fail(why, format("polygon %d crosses polygon %d at edge %d (edge %d of polygon %d)",
                                c.polygonA, c.polygonB, c.edgeA, c.edgeB, c.polygonB));
    }
    for (int i = 0; i < poseCount(); ++i) {
        const Pose& pose = poses_[i];
        if (static_cast<int>(pose.vertices.size()) != vertexCount())
            return fail(why, format("pose %d (\"%s\") has %d vertices, the multicage has %d", i,
                                    pose.name.c_str(), static_cast<int>(pose.vertices.size()),
                                    vertexCount()));
        for (size_t v = 0; v < pose.vertices.size(); ++v)
            if (!geometry::isFinite(pose.vertices[v]))
                return fail(why, format("pose %d (\"%s\"), vertex %d is not a finite number", i,
                                        pose.name.c_str(), static_cast<int>(v)));
    }
    return true;
}

bool Multicage::validate(std::string* why) const {
    if (!validateGeometry(why)) return false;
    for (int p = 0; p < polygonCount(); ++p) {
        const int d = depth(p);
        const double area = signedArea(p);
        if (orientationSign(*this, p) < 0)
            return fail(why, format("polygon %d at depth %d has signed area %g; the orientation "
                                    "rule wants %s (call orient())",
                                    p, d, area, wantsPositiveArea(d) ? "> 0" : "< 0"));
    }
    return true;
}

Size Multicage::imageSize() const {
    return imageSize_;
}
void Multicage::setImageSize(Size size) {
    imageSize_ = size;
}
int Multicage::polygonCount() const {
    return static_cast<int>(polygons_.size());
}

int Multicage::vertexCount() const {
    int n = 0;
    for (const auto& polygon : polygons_) n += static_cast<int>(polygon.size());
    return n;
}

std::vector<Point2f> Multicage::polygon(int i) const {
    CV_Assert(0 <= i && i < polygonCount());
    return polygons_[i];
}

int Multicage::polygonOffset(int i) const {
    CV_Assert(0 <= i && i <= polygonCount());
    int n = 0;
    for (int p = 0; p < i; ++p) n += static_cast<int>(polygons_[p].size());
    return n;
}

int Multicage::depth(int i) const {
    CV_Assert(0 <= i && i < polygonCount());
    return geometry::depths(polygons_)[i];
}

double Multicage::signedArea(int i) const {
    CV_Assert(0 <= i && i < polygonCount());
    return geometry::signedArea(polygons_[i]);
}

std::vector<Point2f> Multicage::frame() const {
    const std::array<Point2f, 4> corners = frameCorners(imageSize_);
    return std::vector<Point2f>(corners.begin(), corners.end());
}

std::vector<Point2f> Multicage::vertices() const {
    std::vector<Point2f> all;
    for (const auto& polygon : polygons_) all.insert(all.end(), polygon.begin(), polygon.end());
    const std::vector<Point2f> corners = frame();
    all.insert(all.end(), corners.begin(), corners.end());
    return all;
}

std::string poseNameProblem(const std::string& name) {
    // What cv::FileStorage 4.6 writes and reads back differently (tried byte by byte, every
    // string of up to three characters, YAML and JSON; fuzz_cage_file checks the rest).
    std::string shown = "\"";  // the name for a one-line message: control characters as \xNN
    int control = -1;
    for (const char c : name) {
        const unsigned char u = static_cast<unsigned char>(c);
        if (u < 0x20 || u == 0x7F) {
            if (control < 0) control = u;
            shown += format("\\x%02X", u);
        } else {
            shown += c;
        }
    }
    shown += "\"";
    if (control >= 0) return shown + format(" contains a control character (0x%02X)", control);
    if (!name.empty() && (name.front() == ' ' || name.back() == ' '))
        return shown + " starts or ends with a space";
    if (!name.empty() && std::string("[]{}\\'\"").find(name.front()) != std::string::npos)
        return shown + " starts with " + name.front();
    return "";
}

int Multicage::addPose(const std::string& name, InputArray vertices, double time) {
    const std::string problem = poseNameProblem(name);
    if (!problem.empty())
        CV_Error(Error::StsBadArg,
                 "multicage: pose name " + problem + " (a cage file could not keep it)");
    std::vector<Point2f> v = toPoints(vertices, "pose");
    const int n = vertexCount();
    if (static_cast<int>(v.size()) == n + 4) v.resize(n);
    if (static_cast<int>(v.size()) != n)
        CV_Error_(Error::StsBadSize,
                  ("multicage: pose \"%s\" has %d vertices, the multicage has %d "
                   "(or %d with the frame corners)",
                   name.c_str(), static_cast<int>(v.size()), n, n + 4));
    poses_.push_back(Pose{name, time, std::move(v)});
    return poseCount() - 1;
}

void Multicage::setPose(int i, const Pose& pose) {
    CV_Assert(0 <= i && i < poseCount());
    const std::string problem = poseNameProblem(pose.name);
    if (!problem.empty())
        CV_Error(Error::StsBadArg,
                 "multicage: pose name " + problem + " (a cage file could not keep it)");
    poses_[i] = pose;
}

void Multicage::removePose(int i) {
    CV_Assert(0 <= i && i < poseCount());
    poses_.erase(poses_.begin() + i);
}

int Multicage::poseCount() const {
    return static_cast<int>(poses_.size());
}

const Pose& Multicage::pose(int i) const {
    CV_Assert(0 <= i && i < poseCount());
    return poses_[i];
}

int Multicage::findPose(const std::string& name) const {
    for (int i = 0; i < poseCount(); ++i)
        if (poses_[i].name == name) return i;
    return -1;
}

int Multicage::coordinates() const {
    return coordinates_;
}

const char* coordinateTypeName(int type) {
    switch (type) {
        case MEAN_VALUE:
            return "mvc";
        case HARMONIC:
            return "harmonic";
        case LOCAL_MEAN_VALUE:
            return "local_mvc";
        case COORDINATES_FROM_CAGE:
            return "cage";
        default:
            return nullptr;
    }
}

const char* coordinateTypeDescription(int type) {
    switch (type) {
        case MEAN_VALUE:
            return "mean value";
        case HARMONIC:
            return "harmonic";
        case LOCAL_MEAN_VALUE:
            return "local mean value";
        default:
            return "the cage's";
    }
}

bool parseCoordinateType(const String& name, int& type) {
    if (name == "mvc" || name == "mean_value")
        type = MEAN_VALUE;
    else if (name == "harmonic")
        type = HARMONIC;
    else if (name == "local_mvc" || name == "local_mean_value")
        type = LOCAL_MEAN_VALUE;
    else
        return false;
    return true;
}

void Multicage::setCoordinates(int coordinates) {
    if (coordinates != MEAN_VALUE && coordinates != HARMONIC && coordinates != LOCAL_MEAN_VALUE)
        CV_Error_(Error::StsOutOfRange,
                  ("multicage: unknown coordinate type %d (0 mean value, 1 harmonic, 2 local mean "
                   "value)",
                   coordinates));
    coordinates_ = coordinates;
}

int Multicage::clipFrame() const {
    return clipFrame_;
}

void Multicage::setClipFrame(int frame) {
    if (frame < 0) CV_Error_(Error::StsOutOfRange, ("multicage: clip frame %d is negative", frame));
    clipFrame_ = frame;
}

Multicage Multicage::posed(InputArray poseIn) const {
    std::vector<Point2f> pose = toPoints(poseIn, "pose");
    const int n = vertexCount();
    if (static_cast<int>(pose.size()) != n && static_cast<int>(pose.size()) != n + 4)
        CV_Error_(Error::StsBadSize, ("multicage: the pose has %d vertices, the multicage has %d",
                                      static_cast<int>(pose.size()), n));
    Multicage out(imageSize_);
    out.coordinates_ = coordinates_;
    out.clipFrame_ = clipFrame_;
    for (int p = 0, offset = 0; p < polygonCount();
         offset += static_cast<int>(polygons_[p].size()), ++p)
        out.polygons_.emplace_back(pose.begin() + offset,
                                   pose.begin() + offset + polygons_[p].size());
    return out;
}

Multicage Multicage::scaled(Size newSize) const {
    CV_Assert(!imageSize_.empty() && !newSize.empty());
    const float sx = static_cast<float>(newSize.width) / imageSize_.width;
    const float sy = static_cast<float>(newSize.height) / imageSize_.height;
    auto map = [&](std::vector<Point2f>& points) {
        for (Point2f& p : points) p = Point2f((p.x + 0.5f) * sx - 0.5f, (p.y + 0.5f) * sy - 0.5f);
    };
    Multicage out = *this;
    out.imageSize_ = newSize;
    for (auto& polygon : out.polygons_) map(polygon);
    for (Pose& pose : out.poses_) map(pose.vertices);
    return out;
}

void Multicage::draw(InputOutputArray image, int thickness, bool drawVertices) const {
    static const Scalar colours[] = {{0, 220, 255}, {255, 128, 0}, {0, 200, 0}, {220, 0, 220}};
    Mat img = image.getMat();
    const double scale = img.cols / static_cast<double>(std::max(1, imageSize_.width));
    for (int p = 0; p < polygonCount(); ++p) {
        std::vector<Point> pts;
        for (Point2f q : polygons_[p])
            pts.emplace_back(cvRound((q.x + 0.5) * scale - 0.5),
                             cvRound((q.y + 0.5) * scale - 0.5));
        const Scalar colour = colours[(depth(p) - 1) % 4];
        polylines(img, pts, true, colour, thickness, LINE_AA);
        if (drawVertices)
            for (const Point& q : pts) circle(img, q, thickness + 2, colour, FILLED, LINE_AA);
    }
}

}  // namespace multicage
}  // namespace cv

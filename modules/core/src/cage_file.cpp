// Cage files: the multicage and its poses as YAML or JSON, read and written as the standards
// have them (cage_text.cpp), and as cv::FileStorage nodes (write(), read()).
#include <algorithm>
#include <cctype>
#include <fstream>
#include <iterator>
#include <opencv2/multicage/multicage.hpp>

#include "cage_text.hpp"

namespace cv {
namespace multicage {

namespace {

[[noreturn]] void malformed(const std::string& where, const std::string& what) {
    CV_Error(Error::StsParseError, "cage file: " + where + ": " + what);
}

// A flat list of numbers [x0, y0, x1, y1, ...] as points; `where` names it in errors.
std::vector<Point2f> readCoordinates(const FileNode& node, const std::string& where) {
    if (node.empty() && !node.isSeq()) malformed(where, "missing");
    if (!node.isSeq()) malformed(where, "is not a list of numbers [x0, y0, x1, y1, ...]");
    const int n = static_cast<int>(node.size());
    if (n % 2 != 0) malformed(where, format("odd number of coordinates (%d)", n));
    std::vector<Point2f> points(n / 2);
    for (int i = 0; i < n; ++i) {
        const FileNode v = node[i];
        if (!v.isInt() && !v.isReal())
            malformed(where, format("coordinate %d (of vertex %d) is not a number", i, i / 2));
        (i % 2 ? points[i / 2].y : points[i / 2].x) = static_cast<float>(static_cast<double>(v));
    }
    return points;
}

void writeCoordinates(FileStorage& fs, const std::vector<Point2f>& points) {
    fs << "[:";
    for (const Point2f& p : points) fs << p.x << p.y;
    fs << "]";
}

std::string lowerExtension(const String& path) {
    const size_t dot = path.find_last_of('.');
    std::string ext = dot == String::npos ? std::string() : path.substr(dot);
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    return ext;
}

std::string checkedFormat(const String& path) {
    const std::string ext = lowerExtension(path);
    if (ext != ".yml" && ext != ".yaml" && ext != ".json")
        CV_Error(Error::StsBadArg,
                 "cage file " + path + ": the name must end in .yml, .yaml or .json");
    return ext;
}

// OpenCV 4.6's YAML parser loops forever when a second document starts with '-' (its
// document loop neither advances nor fails there), and it reaches a second document whenever
// the first one ends before the end of the text: at a "..." line, or when the top level is
// indented, a flow collection or a sequence. A cage file is one document whose top level is a
// block map at column 0; anything else is refused here, before the parser sees it (found by
// fuzz_cage_file: "%YAML:1.0\n -]\ns: -\n" hung Multicage::load).
void checkYamlLayout(const std::string& text, const std::string& where) {
    bool first = true;
    int lineNo = 0;
    for (size_t begin = 0; begin < text.size(); ++lineNo) {
        size_t end = text.find('\n', begin);
        if (end == std::string::npos) end = text.size();
        const std::string line = text.substr(begin, end - begin);
        begin = end + 1;
        const size_t content = line.find_first_not_of(" \t\r");
        if (content == std::string::npos || line[content] == '#') continue;  // blank or comment
        if (line.compare(0, 3, "...") == 0)
            CV_Error(Error::StsParseError,
                     format("%s: not valid YAML/JSON: line %d: a document end "
                            "marker '...' (a cage file is one document)",
                            where.c_str(), lineNo + 1));
        if (!first) continue;
        if (line[0] == '%' || (line.compare(0, 3, "---") == 0 &&
                               line.find_first_not_of(" \t\r", 3) == std::string::npos))
            continue;  // the %YAML directive and the document start
        const unsigned char c = static_cast<unsigned char>(line[0]);
        if (!(std::isalnum(c) || c == '_' || c == '"' || c == '\''))
            CV_Error(Error::StsParseError, format("%s: not valid YAML/JSON: line %d: the top level "
                                                  "must be a map of keys at column 0 (image_size, "
                                                  "polygons, poses)",
                                                  where.c_str(), lineNo + 1));
        first = false;
    }
}

}  // namespace

// The file spells mean value coordinates out (parseCoordinateType reads both spellings).
static const char* coordinatesKeyword(int coordinates) {
    return coordinates == HARMONIC           ? "harmonic"
           : coordinates == LOCAL_MEAN_VALUE ? "local_mean_value"
                                             : "mean_value";
}

void Multicage::write(FileStorage& fs) const {
    fs << "image_size"
       << "[:" << imageSize_.width << imageSize_.height << "]";
    fs << "coordinates" << coordinatesKeyword(coordinates_);
    if (clipFrame_ > 0) fs << "clip_frame" << clipFrame_;
    fs << "polygons"
       << "[";
    for (const auto& polygon : polygons_) writeCoordinates(fs, polygon);
    fs << "]";
    fs << "poses"
       << "[";
    for (const Pose& pose : poses_) {
        fs << "{:"
           << "name" << pose.name << "time" << pose.time << "vertices";
        writeCoordinates(fs, pose.vertices);
        fs << "}";
    }
    fs << "]";
}

void Multicage::read(const FileNode& root) {
    if (!root.isMap()) malformed("top level", "is not a map with image_size, polygons and poses");
    Multicage cage;
    const FileNode size = root["image_size"];
    if (size.empty()) malformed("image_size", "missing");
    if (!size.isSeq() || size.size() != 2 || !size[0].isInt() || !size[1].isInt() ||
        static_cast<int>(size[0]) <= 0 || static_cast<int>(size[1]) <= 0)
        malformed("image_size", "must be [ width, height ] with two positive integers");
    cage.imageSize_ = Size(static_cast<int>(size[0]), static_cast<int>(size[1]));
    if (int64_t(cage.imageSize_.width) * cage.imageSize_.height > kMaxImagePixels)
        malformed("image_size", format("%dx%d is over the limit of 2^30 pixels",
                                       cage.imageSize_.width, cage.imageSize_.height));

    const FileNode coordinates = root["coordinates"];  // optional, mean value by default
    if (!coordinates.empty()) {
        const std::string name =
            coordinates.isString() ? static_cast<std::string>(coordinates) : "";
        if (!parseCoordinateType(name, cage.coordinates_))
            malformed("coordinates", "must be mean_value, harmonic or local_mean_value");
    }

    const FileNode clipFrame = root["clip_frame"];  // optional, the first frame by default
    if (!clipFrame.empty()) {
        if (!clipFrame.isInt() || static_cast<int>(clipFrame) < 0)
            malformed("clip_frame",
                      "must be a whole number >= 0 (a frame of the clip, 0: the first)");
        cage.clipFrame_ = static_cast<int>(clipFrame);
    }

    const FileNode polygons = root["polygons"];
    if (polygons.empty() && !polygons.isSeq()) malformed("polygons", "missing");
    if (!polygons.isSeq()) malformed("polygons", "is not a list of polygons");
    for (int p = 0; p < static_cast<int>(polygons.size()); ++p) {
        std::vector<Point2f> polygon = readCoordinates(polygons[p], format("polygons[%d]", p));
        if (polygon.size() < 3)
            malformed(format("polygons[%d]", p),
                      format("fewer than 3 vertices (%d)", static_cast<int>(polygon.size())));
        cage.polygons_.push_back(std::move(polygon));
    }

    const FileNode poses = root["poses"];  // optional
    if (!poses.empty() || poses.isSeq()) {
        if (!poses.isSeq()) malformed("poses", "is not a list of poses");
        const int n = cage.vertexCount();
        for (int i = 0; i < static_cast<int>(poses.size()); ++i) {
            const FileNode node = poses[i];
            const std::string where = format("poses[%d]", i);
            if (!node.isMap()) malformed(where, "is not a map { name, time, vertices }");
            Pose pose;
            if (!node["name"].empty()) {
                if (!node["name"].isString()) malformed(where + ".name", "is not a string");
                pose.name = static_cast<std::string>(node["name"]);
                // Refused, not changed: a name save() could not write back would rename the
                // pose on the next load (fuzz_cage_file: "p " came back as "p").
                const std::string problem = poseNameProblem(pose.name);
                if (!problem.empty())
                    malformed(
                        where + ".name",
                        problem + ", which a cage file does not keep exactly: rename the pose");
            }
            if (!node["time"].empty()) {
                if (!node["time"].isInt() && !node["time"].isReal())
                    malformed(where + ".time", "is not a number");
                pose.time = static_cast<double>(node["time"]);
            }
            const std::string label =
                pose.name.empty() ? where : where + " (\"" + pose.name + "\")";
            pose.vertices = readCoordinates(node["vertices"], label + ".vertices");
            if (static_cast<int>(pose.vertices.size()) != n)
                malformed(label + ".vertices", format("has %d vertices, the polygons have %d",
                                                      static_cast<int>(pose.vertices.size()), n));
            cage.poses_.push_back(std::move(pose));
        }
    }
    *this = std::move(cage);
}

Multicage Multicage::load(const String& path) {
    const std::string ext = checkedFormat(path);
    // Read here and parsed from memory, not by FileStorage::open(path): OpenCV 4.6's file
    // reader loops forever on some malformed YAML ("%YAML:1.0\n -]\ns: -\n", found by
    // fuzz_cage_file) where its memory reader answers. The extension picks the format, as
    // the file reader does.
    std::ifstream in(path, std::ios::binary);
    if (!in) CV_Error(Error::StsError, "cage file " + path + ": cannot be opened");
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) CV_Error(Error::StsError, "cage file " + path + ": cannot be read");
    const size_t nul = text.find('\0');
    if (nul != std::string::npos)
        CV_Error(Error::StsParseError,
                 format("cage file %s: not valid YAML/JSON: a NUL byte at offset "
                        "%d (not a text file)",
                        path.c_str(), static_cast<int>(nul)));
    if (text.empty()) CV_Error(Error::StsParseError, "cage file " + path + ": the file is empty");
    if (ext != ".json") checkYamlLayout(text, "cage file " + path);
    // YAML goes through yaml-cpp to JSON: cv::FileStorage's YAML reader takes only the subset
    // FileStorage writes. Files that FileStorage wrote (its "%YAML:1.0" first line; "name:rest"
    // in them is one key to any other reader) are still read by it.
    const bool fileStorageYaml = ext != ".json" && text.rfind("%YAML:", 0) == 0;
    const std::string parsed =
        ext == ".json" || fileStorageYaml ? text : yamlAsJson(text, "cage file " + path);
    FileStorage fs;
    try {
        const int flags = FileStorage::READ | FileStorage::MEMORY |
                          (fileStorageYaml ? FileStorage::FORMAT_YAML : FileStorage::FORMAT_JSON);
        if (!fs.open(parsed, flags))
            CV_Error(Error::StsParseError, "cage file " + path + ": not valid YAML/JSON");
    } catch (const cv::Exception& e) {
        if (e.err.rfind("cage file", 0) == 0) throw;
        // OpenCV 4.6's parser puts its function name in err and the reason, with the line,
        // in func ("(4): Incorrect indentation" style): say the reason when there is one.
        std::string reason = e.func.find(':') != std::string::npos ? e.func : e.err;
        const size_t close = reason.find("): ");
        if (reason[0] == '(' && close != std::string::npos)  // "(4): why" -> "line 4: why"
            reason = "line " + std::to_string(std::atoi(reason.c_str() + 1)) + ": " +
                     reason.substr(close + 3);
        CV_Error(Error::StsParseError, "cage file " + path + ": not valid YAML/JSON: " + reason);
    } catch (const std::exception& e) {
        // OpenCV's parser can also throw standard exceptions on malformed text (4.6: "{ :name"
        // gives std::length_error; fuzz_cage_file): still a cv::Exception for our callers.
        CV_Error(Error::StsParseError, "cage file " + path + ": not valid YAML/JSON: " + e.what());
    }
    Multicage cage;
    try {
        cage.read(fs.root());
    } catch (const cv::Exception& e) {
        CV_Error(e.code, path + ": " + e.err);
    }
    std::string why;
    if (!cage.validateGeometry(&why)) CV_Error(Error::StsBadArg, "cage file " + path + ": " + why);
    return cage;
}

void Multicage::save(const String& path) const {
    const bool json = checkedFormat(path) == ".json";
    writeFileAtomic(path, cageText(imageSize_, coordinatesKeyword(coordinates_), clipFrame_,
                                   polygons_, poses_, json));
}

}  // namespace multicage
}  // namespace cv

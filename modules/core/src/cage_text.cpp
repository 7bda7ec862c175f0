// Cage file text. Written here rather than by cv::FileStorage, whose "%YAML:1.0" directive and
// "{:name:rest" flow maps stop PyYAML, yq and JSON tools; read through yaml-cpp, since
// FileStorage's YAML reader refuses what those tools write ("- - 1.5", a key's list at its
// own indentation).
#include "cage_text.hpp"

#include <yaml-cpp/yaml.h>

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>

namespace cv {
namespace multicage {

namespace {

// The shortest text that reads back as exactly this number (std::to_chars), with a '.' before
// any exponent: YAML 1.1 readers such as PyYAML take "1e-05" for a string, "1.0e-05" for a float.
template <typename T>
void appendNumber(std::string& out, T value, bool json) {
    if (!std::isfinite(value)) {
        if (json)
            CV_Error(Error::StsBadArg,
                     "cage file: JSON cannot hold a coordinate or time that is not "
                     "finite (NaN or infinity): fix the pose or save as .yml");
        out += std::isnan(value) ? ".nan" : value > 0 ? ".inf" : "-.inf";
        return;
    }
    char text[64];
    const std::to_chars_result r = std::to_chars(text, text + sizeof text, value);
    std::string number(text, r.ptr);
    const size_t e = number.find('e');
    if (e != std::string::npos && number.find('.') == std::string::npos) number.insert(e, ".0");
    if (value == 0 && std::signbit(value)) number = "-0.0";  // "-0" reads back as the integer 0
    out += number;
}

void appendCoordinates(std::string& out, const std::vector<Point2f>& points, bool json) {
    out += '[';
    for (size_t i = 0; i < points.size(); ++i) {
        if (i) out += ", ";
        appendNumber(out, points[i].x, json);
        out += ", ";
        appendNumber(out, points[i].y, json);
    }
    out += ']';
}

// A double-quoted string, valid in JSON and YAML alike, so that a name such as "yes", "1.5" or
// "a: b" stays a string.
void appendJsonString(std::string& out, const std::string& text) {
    out += '"';
    for (const char c : text) {
        // Short escapes only: cv::FileStorage 4.6's JSON reader has no \uXXXX. Other control
        // characters stay raw, for poseNameProblem to name.
        const char* shortEscape = c == '\b'   ? "\\b"
                                  : c == '\f' ? "\\f"
                                  : c == '\n' ? "\\n"
                                  : c == '\r' ? "\\r"
                                  : c == '\t' ? "\\t"
                                              : nullptr;
        if (shortEscape) {
            out += shortEscape;
            continue;
        }
        if (c == '"' || c == '\\') out += '\\';
        out += c;
    }
    out += '"';
}

// A plain YAML scalar that is a number, as JSON writes it ("+1", ".5", "1." and "0x1f" are
// YAML numbers and not JSON ones); false for anything else.
bool appendIfNumber(std::string& out, const std::string& text) {
    if (text.empty() || text.find_first_of(" \t\n") != std::string::npos) return false;
    // YAML's not-a-number and infinities, in the spelling cv::FileStorage's JSON reader takes.
    std::string lower = text;
    for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (lower == ".nan" || lower == ".inf" || lower == "+.inf" || lower == "-.inf") {
        out += lower == ".nan" ? ".nan" : lower == "-.inf" ? "-.inf" : ".inf";
        return true;
    }
    const char* begin = text.c_str();
    char* end = nullptr;
    const bool hex = text.find("0x") == 0 || text.find("0X") == 0;
    const bool octal = text.find("0o") == 0;
    const double value = hex     ? double(std::strtoll(begin + 2, &end, 16))
                         : octal ? double(std::strtoll(begin + 2, &end, 8))
                                 : std::strtod(begin, &end);
    if (end != begin + text.size() || (hex || octal ? text.size() == 2 : !std::isfinite(value)))
        return false;
    if (text.find_first_of("xXnNiI") != std::string::npos && !hex) return false;  // "nan", "inf"
    appendNumber(out, value, true);
    return true;
}

void appendAsJson(std::string& out, const YAML::Node& node, size_t limit,
                  const std::string& where) {
    // Anchors and aliases can make a small text expand without bound ("billion laughs").
    if (out.size() > limit)
        CV_Error(Error::StsParseError,
                 where + ": not valid YAML: its aliases expand to more than a cage holds");
    switch (node.Type()) {
        case YAML::NodeType::Scalar:
            // "!" is the tag of a quoted scalar: "1.5" in quotes stays a string.
            if (node.Tag() == "!" || !appendIfNumber(out, node.Scalar()))
                appendJsonString(out, node.Scalar());
            break;
        case YAML::NodeType::Sequence: {
            out += '[';
            bool first = true;
            for (const YAML::Node& item : node) {
                if (!first) out += ", ";
                first = false;
                appendAsJson(out, item, limit, where);
            }
            out += ']';
            break;
        }
        case YAML::NodeType::Map: {
            out += '{';
            bool first = true;
            for (const auto& item : node) {
                if (!first) out += ", ";
                first = false;
                if (!item.first.IsScalar())
                    CV_Error(Error::StsParseError,
                             format("%s: not valid YAML/JSON: line %d: a key that is not a name",
                                    where.c_str(), item.first.Mark().line + 1));
                appendJsonString(out, item.first.Scalar());
                out += ": ";
                appendAsJson(out, item.second, limit, where);
            }
            out += '}';
            break;
        }
        default:
            out += "null";
    }
}

}  // namespace

// The cage file's text: image_size, coordinates, clip_frame, polygons and poses, one polygon or
// pose a line.
std::string cageText(const Size& imageSize, const char* coordinates, int clipFrame,
                     const std::vector<std::vector<Point2f>>& polygons,
                     const std::vector<Pose>& poses, bool json) {
    // "%YAML 1.2" rather than FileStorage's "%YAML:1.0": standard, and FileStorage reads both.
    std::string out = json ? "{\n  \"image_size\": [" : "%YAML 1.2\n---\nimage_size: [";
    out += std::to_string(imageSize.width) + ", " + std::to_string(imageSize.height) + "]";
    out += json ? ",\n  \"coordinates\": \"" + std::string(coordinates) + "\""
                : "\ncoordinates: " + std::string(coordinates);
    if (clipFrame > 0)  // written only where it says something: most cages are for one image
        out += (json ? ",\n  \"clip_frame\": " : "\nclip_frame: ") + std::to_string(clipFrame);
    out += json ? ",\n  \"polygons\": [" : "\npolygons:";
    if (!json && polygons.empty()) out += " []";
    for (size_t i = 0; i < polygons.size(); ++i) {
        out += json ? (i ? ",\n    " : "\n    ") : "\n  - ";
        appendCoordinates(out, polygons[i], json);
    }
    if (json) out += polygons.empty() ? "]" : "\n  ]";
    out += json ? ",\n  \"poses\": [" : "\nposes:";
    if (!json && poses.empty()) out += " []";
    for (size_t i = 0; i < poses.size(); ++i) {
        out += json ? (i ? ",\n    {" : "\n    {") : "\n  - {";
        out += json ? "\"name\": " : "name: ";
        appendJsonString(out, poses[i].name);
        out += json ? ", \"time\": " : ", time: ";
        appendNumber(out, poses[i].time, json);
        out += json ? ", \"vertices\": " : ", vertices: ";
        appendCoordinates(out, poses[i].vertices, json);
        out += '}';
    }
    if (json) out += poses.empty() ? "]\n}" : "\n  ]\n}";
    out += '\n';
    return out;
}

std::string yamlAsJson(const std::string& text, const std::string& where) {
    YAML::Node root;
    try {
        root = YAML::Load(text);
    } catch (const YAML::ParserException& e) {
        CV_Error(Error::StsParseError, format("%s: not valid YAML/JSON: line %d: %s", where.c_str(),
                                              e.mark.line + 1, e.msg.c_str()));
    } catch (const YAML::Exception& e) {
        CV_Error(Error::StsParseError, where + ": not valid YAML/JSON: " + e.what());
    }
    std::string json;
    appendAsJson(json, root, 4 * text.size() + (1 << 20), where);
    return json;
}

}  // namespace multicage
}  // namespace cv

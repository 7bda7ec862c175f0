// The text of cage files: standard YAML 1.2 and JSON out, any YAML in (through yaml-cpp).
#ifndef MULTICAGE_CORE_CAGE_TEXT_HPP
#define MULTICAGE_CORE_CAGE_TEXT_HPP

#include <opencv2/multicage/multicage.hpp>
#include <string>
#include <vector>

namespace cv {
namespace multicage {

/** A cage file's text, YAML or JSON: image_size, coordinates, clip_frame (when not 0), then one
line per polygon and per pose; every number as short as it can be and still read back bit for bit.
Throws for a number JSON cannot hold (NaN, infinity). */
std::string cageText(const Size& imageSize, const char* coordinates, int clipFrame,
                     const std::vector<std::vector<Point2f>>& polygons,
                     const std::vector<Pose>& poses, bool json);

/** YAML text (block or flow style, anchors, any indentation: what PyYAML, yq or a person
writes) as the same data in JSON, for cv::FileStorage's JSON reader, whose YAML reader takes
only the subset cv::FileStorage writes. Plain scalars that are numbers become JSON numbers, all
other scalars strings. Throws a cv::Exception (StsParseError) "WHERE: not valid YAML: line N:
why" for text that is not YAML. */
std::string yamlAsJson(const std::string& text, const std::string& where);

}  // namespace multicage
}  // namespace cv

#endif

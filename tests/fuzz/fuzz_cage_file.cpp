// libFuzzer target: the cage file reader. Bytes are a YAML or JSON document, read through
// Multicage::load (a file, the library's entry point: a cage or a cv::Exception, never a crash,
// a hang or another exception); JSON and cv::FileStorage's own YAML ("%YAML:" first) also from
// memory through cv::FileStorage and Multicage::read, the parser load() uses for them. Then
// validate and orient. What is read, write() writes back so that read() gives the same
// multicage again, and save() too so that load() does, in YAML and in JSON: image size,
// coordinate type, polygons, and every pose's name, time and vertices.
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <opencv2/core/utility.hpp>
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/multicage.hpp>
#include <string>

#include "fuzz_common.hpp"

using namespace cv;
using namespace cv::multicage;

namespace {

bool sameFloat(double a, double b) {
    return a == b || (std::isnan(a) && std::isnan(b));
}

bool samePoints(const std::vector<Point2f>& a, const std::vector<Point2f>& b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i)
        if (!sameFloat(a[i].x, b[i].x) || !sameFloat(a[i].y, b[i].y)) return false;
    return true;
}

[[noreturn]] void finding(const char* what) {
    multicage_fuzz::finding("fuzz_cage_file", what);
}

/** The first byte picks the format as a file name would: an opening brace (0x7b) JSON, anything
else YAML. */
bool isJson(const uint8_t* data, size_t size) {
    return size > 0 && data[0] == 0x7b;
}

/** The input as a file, stem + ".json" or ".yml" as isJson() picks; empty when it cannot be
written. */
std::string writeInputFile(const uint8_t* data, size_t size, const std::string& stem) {
    const std::string path = stem + (isJson(data, size) ? ".json" : ".yml");
    FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) return "";
    std::fwrite(data, 1, size, f);
    std::fclose(f);
    return path;
}

/** The multicage in the input: through Multicage::load (anything but a cv::Exception escapes
and is a finding), else, for JSON and cv::FileStorage's own YAML, through cv::FileStorage and
Multicage::read from memory. False when both refuse it. */
bool readCage(const std::string& text, bool json, const std::string& path, Multicage& cage) {
    try {
        cage = Multicage::load(path);
        return true;
    } catch (const cv::Exception& e) {
        // What load() refuses as text never reaches OpenCV's parser directly below: that
        // parser hangs on some layouts load() screens out (docs/robustness.md).
        if (e.err.find("not valid YAML/JSON") != std::string::npos ||
            e.err.find("the file is empty") != std::string::npos)
            return false;
    }
    // Other YAML is read by yaml-cpp in load(): OpenCV's YAML parser never sees it.
    const bool fileStorageText = json || text.rfind("%YAML:", 0) == 0;
    if (!fileStorageText) return false;
    try {
        FileStorage fs(text, FileStorage::READ | FileStorage::MEMORY |
                                 (json ? FileStorage::FORMAT_JSON : FileStorage::FORMAT_YAML));
        cage.read(fs.root());
    } catch (const cv::Exception&) {
        return false;  // malformed: refused with a message
    }
    return true;
}

/** What read() accepts: a positive image size within the pixel limit, polygons of at least 3
vertices, poses of every vertex; a failed validateGeometry() says why. Whether the geometry is
valid. */
bool checkWhatWasRead(const Multicage& cage) {
    std::string why;
    const bool geometry = cage.validateGeometry(&why);
    if (!geometry && why.empty()) finding("validateGeometry failed without a reason");
    cage.validate(&why);
    const int64_t pixels = int64_t(cage.imageSize().width) * cage.imageSize().height;
    if (cage.imageSize().width <= 0 || cage.imageSize().height <= 0)
        finding("read() accepted a non-positive image size");
    if (pixels > Multicage::kMaxImagePixels) finding("read() accepted an image over 2^30 pixels");
    for (int p = 0; p < cage.polygonCount(); ++p)
        if (cage.polygon(p).size() < 3) finding("read() accepted a polygon with < 3 vertices");
    for (int i = 0; i < cage.poseCount(); ++i)
        if (static_cast<int>(cage.pose(i).vertices.size()) != cage.vertexCount())
            finding("read() accepted a pose with the wrong vertex count");
    return geometry;
}

/** write() then read(), in YAML and in JSON, gives the same multicage. */
void checkWriteReadRoundTrip(const Multicage& cage) {
    for (const char* ext : {".yml", ".json"}) {
        FileStorage out(ext, FileStorage::WRITE | FileStorage::MEMORY);
        cage.write(out);
        const std::string written = out.releaseAndGetString();
        Multicage again;
        try {
            FileStorage in(written, FileStorage::READ | FileStorage::MEMORY);
            again.read(in.root());
        } catch (const cv::Exception& e) {
            std::fprintf(stderr, "%s\n%s\n", written.c_str(), e.what());
            finding("write() produced a file read() refuses");
        }
        if (again.imageSize() != cage.imageSize() || again.polygonCount() != cage.polygonCount() ||
            again.poseCount() != cage.poseCount() || again.coordinates() != cage.coordinates())
            finding("round trip changed the structure");
        for (int p = 0; p < cage.polygonCount(); ++p)
            if (!samePoints(again.polygon(p), cage.polygon(p)))
                finding("round trip changed a polygon");
        for (int i = 0; i < cage.poseCount(); ++i)
            if (!samePoints(again.pose(i).vertices, cage.pose(i).vertices) ||
                again.pose(i).name != cage.pose(i).name ||
                !sameFloat(again.pose(i).time, cage.pose(i).time)) {
                std::fprintf(stderr, "%s\n", written.c_str());
                finding("round trip changed a pose");
            }
    }
}

bool sameCage(const Multicage& a, const Multicage& b) {
    bool same = a.imageSize() == b.imageSize() && a.polygonCount() == b.polygonCount() &&
                a.poseCount() == b.poseCount() && a.coordinates() == b.coordinates();
    for (int p = 0; same && p < b.polygonCount(); ++p)
        same = samePoints(a.polygon(p), b.polygon(p));
    for (int i = 0; same && i < b.poseCount(); ++i)
        same = samePoints(a.pose(i).vertices, b.pose(i).vertices) &&
               a.pose(i).name == b.pose(i).name && sameFloat(a.pose(i).time, b.pose(i).time);
    return same;
}

/** save() then load(), through the files save() writes (standard YAML 1.2 and JSON), gives
the same multicage. */
void checkSaveLoadRoundTrip(const Multicage& cage, const std::string& stem) {
    for (const char* ext : {".yml", ".json"}) {
        const std::string saved = stem + ".saved" + ext;
        try {
            cage.save(saved);
        } catch (const cv::Exception& e) {
            if (std::string(ext) == ".json" && e.err.find("JSON cannot hold") != std::string::npos)
                continue;  // NaN or infinity: said, and nothing written
            std::fprintf(stderr, "%s\n", e.what());
            finding("save() refused a multicage read() accepted");
        }
        Multicage again;
        try {
            again = Multicage::load(saved);
        } catch (const cv::Exception& e) {
            std::fprintf(stderr, "%s\n", e.what());
            finding("save() wrote a file load() refuses");
        }
        if (!sameCage(again, cage)) finding("save() and load() changed the multicage");
    }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    multicage_fuzz::quietLibrary();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size > 4096) return -1;  // cage files are small; longer inputs only slow the search
    const std::string text(reinterpret_cast<const char*>(data), size);
    static const std::string stem = [] {
        const char* dir = std::getenv("TMPDIR");
        return std::string(dir ? dir : "/tmp") + "/fuzz_cage_file." + std::to_string(getpid());
    }();
    const std::string path = writeInputFile(data, size, stem);
    if (path.empty()) return 0;
    Multicage cage;
    if (!readCage(text, isJson(data, size), path, cage)) return 0;
    const bool geometry = checkWhatWasRead(cage);
    checkWriteReadRoundTrip(cage);
    if (geometry) {
        checkSaveLoadRoundTrip(cage, stem);
        cage.orient();
        std::string why;
        if (!cage.validate(&why))
            finding("a multicage with valid geometry fails validate() after orient()");
    }
    return 0;
}

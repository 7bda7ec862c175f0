// Image files in and out: refuse truncated JPEG/PNG inputs, convert outputs to a depth the
// format holds (see opencv2/multicage/imageio.hpp).
#include <algorithm>
#include <cctype>
#include <fstream>
#include <iterator>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/multicage/imageio.hpp>

namespace cv {
namespace multicage {

namespace {

bool startsWith(const std::vector<uchar>& b, std::initializer_list<uchar> prefix) {
    return b.size() >= prefix.size() && std::equal(prefix.begin(), prefix.end(), b.begin());
}

// Walks the JPEG marker segments from SOI to EOI; entropy-coded data after each SOS is skipped
// up to the next real marker (FF followed by neither 00, a stuffed byte, nor RST0-7). Data after
// EOI (camera trailers, motion-photo videos) is ignored.
std::string truncatedJpeg(const std::vector<uchar>& b) {
    const size_t n = b.size();
    size_t i = 2;  // after SOI
    while (true) {
        while (i < n && b[i] != 0xFF) ++i;  // tolerate junk between segments, as libjpeg does
        while (i < n && b[i] == 0xFF) ++i;  // fill bytes
        if (i >= n) break;
        const uchar marker = b[i++];
        if (marker == 0xD9) return "";                                       // EOI: complete
        if (marker == 0x01 || (marker >= 0xD0 && marker <= 0xD8)) continue;  // no length
        if (i + 2 > n) break;
        const size_t length = (size_t(b[i]) << 8) | b[i + 1];
        if (length < 2 || i + length > n) break;
        i += length;
        if (marker != 0xDA) continue;
        // SOS: entropy-coded data up to the next marker.
        while (i + 1 < n &&
               !(b[i] == 0xFF && b[i + 1] != 0x00 && !(b[i + 1] >= 0xD0 && b[i + 1] <= 0xD7)))
            ++i;
        if (i + 1 >= n) break;
    }
    return "the file is truncated (a JPEG ends with an end-of-image marker FF D9; this one stops "
           "after " +
           std::to_string(n) + " bytes, in the middle of its data)";
}

// Walks the PNG chunks (length, type, data, CRC) up to IEND.
std::string truncatedPng(const std::vector<uchar>& b) {
    const size_t n = b.size();
    size_t i = 8;  // after the signature
    while (i + 8 <= n) {
        const size_t length =
            (size_t(b[i]) << 24) | (size_t(b[i + 1]) << 16) | (size_t(b[i + 2]) << 8) | b[i + 3];
        const bool iend = std::equal(b.begin() + i + 4, b.begin() + i + 8, "IEND");
        if (length > n || i + 12 + length > n) break;
        if (iend) return "";
        i += 12 + length;
    }
    return "the file is truncated (a PNG ends with an IEND chunk; this one stops after " +
           std::to_string(n) + " bytes, in the middle of its data)";
}

std::string lowerExtension(const String& path) {
    const size_t dot = path.find_last_of('.');
    if (dot == String::npos || path.find('/', dot) != String::npos) return "";
    std::string ext = path.substr(dot + 1);
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    return ext;
}

const char* depthWords(int depth) {
    return depth == CV_8U    ? "8-bit"
           : depth == CV_16U ? "16-bit"
           : depth == CV_32F ? "float"
                             : "other";
}

}  // namespace

std::string truncatedImageReason(const std::vector<uchar>& bytes) {
    if (startsWith(bytes, {0xFF, 0xD8, 0xFF})) return truncatedJpeg(bytes);
    if (startsWith(bytes, {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A}))
        return truncatedPng(bytes);
    return "";
}

Mat readImage(const String& path, int flags) {
    std::ifstream in(path, std::ios::binary);
    if (!in) CV_Error(Error::StsObjectNotFound, path + ": no such file, or it cannot be read");
    const std::vector<uchar> bytes((std::istreambuf_iterator<char>(in)),
                                   std::istreambuf_iterator<char>());
    if (bytes.empty()) CV_Error(Error::StsBadArg, path + ": the file is empty");
    const std::string truncated = truncatedImageReason(bytes);
    if (!truncated.empty()) CV_Error(Error::StsBadArg, path + ": " + truncated);
    Mat image;
    try {
        image = imdecode(bytes, flags);
    } catch (const cv::Exception& e) {
        CV_Error(Error::StsBadArg, path + ": cannot be decoded: " + e.err);
    }
    if (image.empty()) CV_Error(Error::StsBadArg, path + ": not an image OpenCV can read");
    return image;
}

std::vector<int> imageFormatDepths(const String& path) {
    const std::string ext = lowerExtension(path);
    if (ext == "png" || ext == "ppm" || ext == "pgm" || ext == "pnm" || ext == "jp2")
        return {CV_8U, CV_16U};
    if (ext == "tif" || ext == "tiff") return {CV_8U, CV_16U, CV_32F};
    if (ext == "exr" || ext == "hdr" || ext == "pic") return {CV_32F};
    return {CV_8U};
}

std::vector<int> imageFormatChannels(const String& path) {
    const std::string ext = lowerExtension(path);
    if (ext == "pgm" || ext == "pbm") return {1};
    if (ext == "ppm") return {3};
    if (ext == "pnm" || ext == "hdr" || ext == "pic" || ext == "pfm") return {1, 3};
    // OpenCV writes these without their alpha channel, silently: said here instead.
    if (ext == "jpg" || ext == "jpeg" || ext == "jpe" || ext == "bmp" || ext == "dib" ||
        ext == "ras" || ext == "sr")
        return {1, 3};
    return {1, 3, 4};
}

namespace {

// image with a channel count the format stores: colour to grey, grey to colour, alpha dropped.
Mat convertChannels(const Mat& image, const std::vector<int>& channels, std::string& what) {
    const int from = image.channels();
    if (std::find(channels.begin(), channels.end(), from) != channels.end()) return image;
    const bool grey = std::find(channels.begin(), channels.end(), 1) != channels.end();
    Mat out;
    if (from == 4 && std::find(channels.begin(), channels.end(), 3) != channels.end()) {
        cvtColor(image, out, COLOR_BGRA2BGR), what = "the colour image without its alpha channel";
    } else if (from == 1) {
        cvtColor(image, out, COLOR_GRAY2BGR), what = "the grey image as colour";
    } else if (grey) {
        cvtColor(image, out, from == 4 ? COLOR_BGRA2GRAY : COLOR_BGR2GRAY);
        what = "the colour image as grey";
    } else {
        return image;  // (no format here wants that); the writer says what it refuses
    }
    return out;
}

// image at a depth the format stores (imageFormatDepths); `said` what was done, "" if nothing.
Mat convertDepth(const String& path, const std::string& ext, const Mat& image, std::string& said) {
    const std::vector<int> depths = imageFormatDepths(path);
    const int from = image.depth();
    if (std::find(depths.begin(), depths.end(), from) != depths.end()) return image;
    // The deepest the format holds (floats lose least in 16 bits; 8 bits go to float when
    // float is all there is).
    const int to = depths.back();
    double scale = 1.0;
    std::string range;
    if (from == CV_16U && to == CV_8U)
        scale = 1.0 / 257;
    else if (from == CV_8U && to == CV_32F)
        scale = 1.0 / 255;
    else if (from == CV_16U && to == CV_32F)
        scale = 1.0 / 65535;
    else if (from == CV_32F || from == CV_64F) {
        double lo = 0, hi = 0;
        minMaxLoc(image.reshape(1), &lo, &hi);
        const bool unit = hi <= 2.0;
        range = unit ? " (values 0-1)" : " (values taken as 0-255)";
        scale = (to == CV_8U ? 1.0 : 257.0) * (unit ? 255.0 : 1.0);
    } else {
        CV_Error(Error::StsUnsupportedFormat,
                 "cannot write " + path + ": unsupported pixel type " + typeToString(image.type()));
    }
    Mat out;
    image.convertTo(out, to, scale);
    said = "." + ext + " does not store " + depthWords(from) + " pixels; wrote " + depthWords(to) +
           ", the " + depthWords(from) + " image" + range + " scaled by " +
           (scale < 1 ? "1/" + format("%g", 1.0 / scale) : format("%g", scale));
    return out;
}

}  // namespace

Mat convertForImageFormat(const String& path, InputArray imageIn, std::string* note) {
    if (note) note->clear();
    const Mat image = imageIn.getMat();
    const std::string ext = lowerExtension(path);
    // Depth first (it gives 8 bits, 16 bits or float, which every channel conversion takes),
    // then the channels; the note says the channels first.
    std::string depthNote, channelWords;
    const Mat deep = convertDepth(path, ext, image, depthNote);
    const Mat out = convertChannels(deep, imageFormatChannels(path), channelWords);
    if (note) {
        std::vector<std::string> said;
        if (!channelWords.empty())
            said.push_back("." + ext + " does not store " + std::to_string(image.channels()) +
                           " channels; wrote " + channelWords);
        if (!depthNote.empty()) said.push_back(depthNote);
        for (size_t i = 0; i < said.size(); ++i) *note += (i ? "; " : path + ": ") + said[i];
    }
    return out;
}

}  // namespace multicage
}  // namespace cv

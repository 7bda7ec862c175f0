// imread(): image files read as the CLI reads them (imageio.hpp's readImage), so that a
// truncated or unreadable file raises instead of coming back grey, black or None.
#include <opencv2/multicage/imageio.hpp>

#include "common.hpp"

namespace multicage_py {
namespace {

using namespace cv::multicage;

const char* kImreadDoc = R"doc(imread(path, flags=cv2.IMREAD_UNCHANGED) -> numpy array

Reads an image file with the checks `multicage deform` makes (cv::multicage::readImage):
a missing or unreadable file, an empty file, a JPEG or PNG cut short (cv2.imread decodes it
with only a libjpeg/libpng warning, the missing rows grey or black) and a file that is not
an image OpenCV decodes all raise multicage.Error, with the path and the reason in one line.
path is a str or an os.PathLike (pathlib.Path). flags are cv2.imread's; the default keeps the
image as stored (depth, alpha), as the CLI reads it: pass cv2.IMREAD_COLOR for cv2.imread's
default (3-channel BGR, 8 bits). Returns the image as cv2.imread does (HxW, HxWx3 BGR,
HxWx4 BGRA). The GIL is released while the file is read and decoded.)doc";

}  // namespace

void defineImageIo(py::module_& m) {
    m.def(
        "imread",
        [](const py::object& path, const py::object& flags) {
            const std::string file = pathArg(path, "path");
            const int f = intArg(flags, "flags");
            cv::Mat image;
            {
                py::gil_scoped_release release;
                image = readImage(file, f);
            }
            return arrayFromMat(image);
        },
        py::arg("path"), py::arg("flags") = -1, kImreadDoc);
}

}  // namespace multicage_py

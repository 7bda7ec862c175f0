#include <opencv2/multicage/internal/backend_contract.hpp>

namespace cv {
namespace multicage {

void checkImageType(int type) {
    const int depth = CV_MAT_DEPTH(type), cn = CV_MAT_CN(type);
    if ((depth != CV_8U && depth != CV_16U && depth != CV_32F) || (cn != 1 && cn != 3 && cn != 4))
        CV_Error_(Error::StsUnsupportedFormat,
                  ("multicage: unsupported image type %s; use CV_8U, CV_16U or CV_32F with 1, 3 or "
                   "4 channels",
                   typeToString(type).c_str()));
}

void checkImage(InputArray image) {
    if (image.empty()) CV_Error(Error::StsBadArg, "multicage: the image is empty");
    checkImageType(image.type());
    if (image.dims() > 2) CV_Error(Error::StsBadArg, "multicage: the image must be 2-dimensional");
}

}  // namespace multicage
}  // namespace cv

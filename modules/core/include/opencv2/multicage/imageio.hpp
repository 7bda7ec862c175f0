/** @file
@brief Reading and writing image files without silent damage: truncated inputs are refused,
and outputs are converted to a depth and channels the file format can hold, said out loud.
@ingroup multicage_core
*/
#ifndef OPENCV2_MULTICAGE_IMAGEIO_HPP
#define OPENCV2_MULTICAGE_IMAGEIO_HPP

#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace cv {
namespace multicage {

//! @addtogroup multicage_core
//! @{

/** @brief Why the bytes of an image file are incomplete, or "" when they look whole.

Checked: a JPEG must end its last scan with the end-of-image marker (FF D9), a PNG must run
chunk by chunk up to its IEND chunk. Other formats are not checked (""). Why check first:
OpenCV decodes a cut JPEG or PNG with no more than a libjpeg/libpng warning on stderr and grey
or black rows.
@param bytes the whole file.
@return one sentence saying where the file stops, or "".
@sa readImage
*/
CV_EXPORTS std::string truncatedImageReason(const std::vector<uchar>& bytes);

/** @brief Reads an image file as stored (depth and alpha kept).
@param path the image file.
@param flags as cv::imread's; the default -1 is IMREAD_UNCHANGED.
@return the decoded image, never empty.
@throws cv::Exception naming the file when it does not exist, is empty, cannot be decoded,
or is truncated (see truncatedImageReason: "photo.jpg: the file is truncated (a JPEG ends
with an FF D9 marker; this one stops in the middle of its image data)").
*/
CV_EXPORTS Mat readImage(const String& path, int flags = -1 /* IMREAD_UNCHANGED */);

/** @brief The depths the image format of path (by its extension) stores.

PNG, PPM/PGM/PNM and JPEG 2000: 8 and 16 bits; TIFF: 8, 16 bits and float; OpenEXR and
Radiance HDR: float only; the others (JPEG, BMP, WebP, ...): 8 bits.
@param path a file name; only its extension is read.
@return the depths (CV_8U, CV_16U, CV_32F), the deepest last.
@sa convertForImageFormat
*/
CV_EXPORTS std::vector<int> imageFormatDepths(const String& path);

/** @brief The channel counts the image format of path (by its extension) stores.

PGM and PBM grey only, PPM colour only, PNM, Radiance HDR and PFM grey or colour; JPEG, BMP
and Sun raster grey or colour (OpenCV would drop an alpha channel without a word); the others
1, 3 or 4.
@param path a file name; only its extension is read.
@return the channel counts.
@sa convertForImageFormat
*/
CV_EXPORTS std::vector<int> imageFormatChannels(const String& path);

/** @brief image converted, if needed, to channels and a depth the format of path stores.

Channels (imageFormatChannels): colour to grey, grey to colour, the alpha channel dropped.
Depth (imageFormatDepths): the deepest the format stores. The scales keep white white: 16 to
8 bits x1/257; float to 8 bits x255 and to 16 bits x65535 when the values are in [0, 1] (the
usual range of float images; a maximum up to 2 still counts, as lossy float codecs
overshoot), otherwise the floats are taken as 0-255 (x1 and x257); 8 bits to float x1/255, 16
bits to float x1/65535. A depth the format holds is never changed: 16 bits stay 16 bits in
PNG and TIFF, float stays float in TIFF and EXR.
@param path the file the image is for; only its extension is read.
@param image the image: CV_8U, CV_16U, CV_32F or CV_64F, 1, 3 or 4 channels.
@param[out] note when not null, receives one sentence saying what was done ("" when nothing
is).
@return the image to write, image itself when nothing needed converting.
@throws cv::Exception (StsUnsupportedFormat) for another depth the format does not store.
@sa imwriteAtomic
*/
CV_EXPORTS Mat convertForImageFormat(const String& path, InputArray image,
                                     std::string* note = nullptr);

//! @} multicage_core

}  // namespace multicage
}  // namespace cv

#endif

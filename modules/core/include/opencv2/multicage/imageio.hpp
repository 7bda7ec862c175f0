// Reading and writing image files without silent damage: truncated inputs are refused, and
// outputs are converted to a depth and channels the file format can hold, said out loud.
#ifndef OPENCV2_MULTICAGE_IMAGEIO_HPP
#define OPENCV2_MULTICAGE_IMAGEIO_HPP

#include <opencv2/core.hpp>

#include <string>
#include <vector>

namespace cv {
namespace multicage {

/** Why the bytes of an image file are incomplete, or "" when they look whole. Checked: a JPEG
must end its last scan with the end-of-image marker (FF D9), a PNG must run chunk by chunk up
to its IEND chunk. Other formats are not checked (""). OpenCV decodes a cut JPEG or PNG with
no more than a libjpeg/libpng warning on stderr and grey or black rows, so check first. */
CV_EXPORTS std::string truncatedImageReason(const std::vector<uchar>& bytes);

/** Reads an image file as stored (depth and alpha kept; flags as cv::imread). Throws a
cv::Exception naming the file when it does not exist, cannot be decoded, or is truncated (see
truncatedImageReason: "photo.jpg: the file is truncated (a JPEG ends with an FF D9 marker;
this one stops in the middle of its image data)"). */
CV_EXPORTS Mat readImage(const String& path, int flags = -1 /* IMREAD_UNCHANGED */);

/** The depths the image format of path (by its extension) stores: PNG, PPM/PGM and JPEG 2000
8 and 16 bits; TIFF 8, 16 bits and float; OpenEXR and Radiance HDR float only; the others
(JPEG, BMP, WebP, ...) 8 bits. */
CV_EXPORTS std::vector<int> imageFormatDepths(const String& path);

/** The channel counts the image format of path (by its extension) stores: PGM and PBM grey
only, PPM colour only, PNM, Radiance HDR and PFM grey or colour; JPEG, BMP and Sun raster grey
or colour (OpenCV would drop an alpha channel without a word); the others 1, 3 or 4. */
CV_EXPORTS std::vector<int> imageFormatChannels(const String& path);

/** image converted, if needed, to a channel count (imageFormatChannels: colour to grey, grey
to colour, the alpha channel dropped) and a depth the format of path stores
(imageFormatDepths), and in *note one sentence saying what was done ("" when nothing is). The
scales keep white white: 16 to 8 bits x1/257; float to 8 bits x255 and to 16 bits x65535
when the values are in [0, 1] (the usual range of float images; a maximum up to 2 still
counts, as lossy float codecs overshoot), otherwise the floats are taken as 0-255 (x1 and
x257); 8 bits to float x1/255, 16 bits to float x1/65535. A depth the format holds is never
changed: 16 bits stay 16 bits in PNG and TIFF, float stays float in TIFF and EXR. */
CV_EXPORTS Mat convertForImageFormat(const String& path, InputArray image, std::string* note = nullptr);

}  // namespace multicage
}  // namespace cv

#endif

// Writing files so that no reader ever sees a partial one: temporary file, fsync, rename.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/multicage/multicage.hpp>

namespace cv {
namespace multicage {

void writeFileAtomic(const String& path, const std::string& bytes) {
    // The temporary file sits in the target's folder: rename() is atomic only within a file system.
    std::string tmp = path + ".tmp-XXXXXX";
    const int fd = mkstemp(&tmp[0]);
    if (fd < 0) CV_Error(Error::StsError, "cannot write " + path + ": " + std::strerror(errno));
    size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            const std::string reason = std::strerror(errno);
            ::close(fd);
            ::unlink(tmp.c_str());
            CV_Error(Error::StsError, "cannot write " + path + ": " + reason);
        }
        done += static_cast<size_t>(n);
    }
    fchmod(fd, 0644);
    const bool ok = ::fsync(fd) == 0 && ::close(fd) == 0;
    if (!ok || std::rename(tmp.c_str(), path.c_str()) != 0) {
        const std::string reason = std::strerror(errno);
        ::unlink(tmp.c_str());
        CV_Error(Error::StsError, "cannot write " + path + ": " + reason);
    }
}

void imwriteAtomic(const String& path, InputArray image, const std::vector<int>& params) {
    const size_t dot = path.find_last_of('.');
    if (dot == String::npos || path.find('/', dot) != String::npos)
        CV_Error(Error::StsBadArg, "cannot write " + path +
                                       ": the name needs an image extension "
                                       "(.png, .jpg, .tif, ...)");
    std::vector<uchar> buffer;
    bool ok = false;
    try {
        ok = imencode(path.substr(dot), image, buffer, params);
    } catch (const cv::Exception& e) {
        CV_Error(Error::StsBadArg, "cannot write " + path + ": " + e.err);
    }
    if (!ok) CV_Error(Error::StsBadArg, "cannot write " + path + ": no encoder for this extension");
    writeFileAtomic(path, std::string(buffer.begin(), buffer.end()));
}

}  // namespace multicage
}  // namespace cv

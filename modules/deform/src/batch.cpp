#include "batch.hpp"

#include <climits>
#include <opencv2/multicage/internal/backend_contract.hpp>
#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace cv {
namespace multicage {

Mat hugePageMat(Size size, int type, std::vector<Mat>& owners) {
    const size_t bytes = size_t(size.area()) * CV_ELEM_SIZE(type);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    constexpr size_t kHuge = size_t(2) << 20;
    if (bytes >= kHuge) {
        const size_t span = (bytes + kHuge - 1) & ~(kHuge - 1);
        Mat block(1, static_cast<int>(std::min<size_t>(span + kHuge, INT_MAX)), CV_8U);
        if (block.total() == span + kHuge) {
            uchar* aligned = alignPtr(block.data, static_cast<int>(kHuge));
            madvise(aligned, span, MADV_HUGEPAGE);
            owners.push_back(block);
            return Mat(size, type, aligned);
        }
    }
#endif
    (void)owners;
    return Mat(size, type);
}

void checkSameImage(InputArray image, Size size, int type) {
    checkImage(image);
    if (image.size() != size)
        CV_Error_(Error::StsBadSize,
                  ("multicage: the image is %dx%d but the Deformer was made for %dx%d "
                   "images; make a Deformer (or bind) for that size",
                   image.cols(), image.rows(), size.width, size.height));
    if (image.type() != type)
        CV_Error_(Error::StsUnmatchedFormats,
                  ("multicage: the image is %s but the Deformer was made for %s images",
                   typeToString(image.type()).c_str(), typeToString(type).c_str()));
}

Mat ownedHugePageMat(Size size, int type) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    constexpr size_t kHuge = size_t(2) << 20;
    const size_t elemSize = CV_ELEM_SIZE1(type), elems = size_t(size.area()) * CV_MAT_CN(type);
    const size_t bytes = elems * elemSize, slack = kHuge / elemSize;
    if (bytes >= kHuge && elems + slack <= size_t(INT_MAX)) {
        // A view of one reference-counted block, from a 2 MB boundary, advised to 2 MB pages.
        Mat block(1, static_cast<int>(elems + slack), CV_MAKETYPE(CV_MAT_DEPTH(type), 1));
        const size_t skip = (alignPtr(block.data, static_cast<int>(kHuge)) - block.data) / elemSize;
        madvise(block.data + skip * elemSize, (bytes / kHuge) * kHuge, MADV_HUGEPAGE);
        const int begin = static_cast<int>(skip);
        return block.colRange(begin, begin + static_cast<int>(elems))
            .reshape(CV_MAT_CN(type), size.height);
    }
#endif
    return Mat(size, type);
}

std::vector<Mat> batchOutputs(int count, Size size, int type) {
    std::vector<Mat> out(count);
    const size_t itemElems = size_t(size.area()) * CV_MAT_CN(type);
    const size_t elemSize = CV_ELEM_SIZE1(type), bytes = itemElems * count * elemSize;
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    constexpr size_t kHuge = size_t(2) << 20;
    const size_t slack = kHuge / elemSize;
    if (count > 1 && bytes >= kHuge && itemElems * count + slack <= size_t(INT_MAX)) {
        // One block for the whole batch, in 2 MB pages where the kernel offers them; each output
        // a view that keeps the block alive (reference counted like any Mat).
        Mat block(1, static_cast<int>(itemElems * count + slack),
                  CV_MAKETYPE(CV_MAT_DEPTH(type), 1));
        const size_t skip = (alignPtr(block.data, static_cast<int>(kHuge)) - block.data) / elemSize;
        madvise(block.data + skip * elemSize, (bytes / kHuge) * kHuge, MADV_HUGEPAGE);
        for (int k = 0; k < count; ++k) {
            const int begin = static_cast<int>(skip + itemElems * k);
            out[k] = block.colRange(begin, begin + static_cast<int>(itemElems))
                         .reshape(CV_MAT_CN(type), size.height);
            CV_Assert(out[k].size() == size && out[k].type() == type);
        }
        return out;
    }
#endif
    for (Mat& m : out) m.create(size, type);
    return out;
}

[[noreturn]] void rethrowForItem(const Exception& e, int k) {
    std::string what = e.err;
    const std::string prefix = "multicage: ";
    if (what.compare(0, prefix.size(), prefix) == 0) what = what.substr(prefix.size());
    CV_Error_(e.code, ("multicage: batch item %d: %s", k, what.c_str()));
}

void setBatchOutput(OutputArrayOfArrays dst, std::vector<Mat>& items) {
    const int count = static_cast<int>(items.size());
    if (dst.kind() == _InputArray::STD_VECTOR_MAT) {
        dst.create(count, 1, items.empty() ? CV_8U : items[0].type());
        for (int k = 0; k < count; ++k) dst.getMatRef(k) = items[k];
        return;
    }
    dst.create(count, 1, items.empty() ? CV_8U : items[0].type());
    for (int k = 0; k < count; ++k) {
        dst.create(items[k].size(), items[k].type(), k);
        Mat d = dst.getMat(k);
        items[k].copyTo(d);
    }
}

void batchInputs(InputArrayOfArrays posesIn, InputArrayOfArrays imagesIn,
                 const std::function<std::vector<Point2f>(InputArray)>& readPose, Size size,
                 int type, std::vector<std::vector<Point2f>>& poses, std::vector<Mat>& images) {
    const int count = posesIn.empty() ? 0 : static_cast<int>(posesIn.total());
    poses.resize(count);
    for (int k = 0; k < count; ++k) {
        try {
            poses[k] = readPose(posesIn.getMat(k));
        } catch (const Exception& e) {
            rethrowForItem(e, k);
        }
    }
    images.clear();
    if (imagesIn.empty()) return;
    if (static_cast<int>(imagesIn.total()) != count)
        CV_Error_(Error::StsBadSize,
                  ("multicage: the batch has %d poses but %d images (give one image "
                   "per pose, or none to deform the Deformer's own image)",
                   count, static_cast<int>(imagesIn.total())));
    imagesIn.getMatVector(images);
    for (int k = 0; k < count; ++k) {
        try {
            checkSameImage(images[k], size, type);
        } catch (const Exception& e) {
            rethrowForItem(e, k);
        }
    }
}

}  // namespace multicage
}  // namespace cv

// What both backends share (private): the inputs and outputs of Deformer::deformBatch, and the
// large buffers outputs and meshes live in, in 2 MB pages where the kernel offers them.
#ifndef MULTICAGE_DEFORM_BATCH_HPP
#define MULTICAGE_DEFORM_BATCH_HPP

#include <functional>
#include <opencv2/core.hpp>
#include <vector>

namespace cv {
namespace multicage {

/** checkImage, and the given size and type (a Deformer's setImage and batches). */
void checkSameImage(InputArray image, Size size, int type);
/** The inputs of Deformer::deformBatch checked and converted: every pose completed with its
frame corners (readPose), images empty or one per pose of this size and type. Errors name the item.
*/
void batchInputs(InputArrayOfArrays poses, InputArrayOfArrays images,
                 const std::function<std::vector<Point2f>(InputArray)>& readPose, Size size,
                 int type, std::vector<std::vector<Point2f>>& posesOut,
                 std::vector<Mat>& imagesOut);
/** The outputs of a batch, allocated together: one block in 2 MB pages where the kernel offers
them (a fresh 4 KiB page costs ~12 us on this project's VM, a batch of 32 512x512 BGR outputs
6,000 of them), each output a view of it that keeps it alive. */
std::vector<Mat> batchOutputs(int count, Size size, int type);

/** A Mat that owns its memory (reference counted, so it may outlive whoever made it), in 2 MB
pages where the kernel offers them. */
Mat ownedHugePageMat(Size size, int type);
/** Throws e again, its message prefixed with "batch item k". */
[[noreturn]] void rethrowForItem(const Exception& e, int k);
/** dst (a std::vector<Mat> or another array of arrays) gets the items, without copies where it
can take the matrices themselves. */
void setBatchOutput(OutputArrayOfArrays dst, std::vector<Mat>& items);

/** A matrix for a large buffer that stays with a Deformer. From 2 MB up it is backed by memory
the kernel may give 2 MB pages (madvise MADV_HUGEPAGE; `owners` keeps the allocation alive):
touching a fresh 4 KiB page costs about 12 us on a VM like this project's machine (3 ms per
MB), a 2 MB page a small part of that. */
Mat hugePageMat(Size size, int type, std::vector<Mat>& owners);

}  // namespace multicage
}  // namespace cv

#endif

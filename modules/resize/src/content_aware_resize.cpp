// contentAwareResize: bind once to a (proposed) multicage, deform to the resize pose.
#include <opencv2/multicage/resize.hpp>

namespace cv {
namespace multicage {

Multicage resizeCage(InputArray image, const ResizeParams& params) {
    ProposeParams propose;
    if (params.protect >= 0) propose.protect = params.protect;
    propose.margin = params.margin;
    propose.segmenter = params.segmenter;
    propose.segmenterModel = params.segmenterModel;
    try {
        return proposeProtectedMulticage(image, propose);
    } catch (const Exception& e) {
        // A sliver (a row of pixels, a strip too thin for a cage) holds nothing a cage could
        // protect: it scales plainly, as an image where no object is found does.
        if (e.code != Error::StsBadSize) throw;
        return Multicage(image.size());
    }
}

void contentAwareResize(InputArray image, Size newSize, OutputArray dst, const Multicage& cage,
                        const ResizeParams& params) {
    if (image.empty()) CV_Error(Error::StsBadArg, "multicage: resize: the image is empty");
    checkResizeSize(image.size(), newSize, params.maxScale);
    // An empty cage means the default proposal; a cage drawn on another size follows the image.
    Multicage rest =
        cage.imageSize().empty() && cage.polygonCount() == 0 ? resizeCage(image, params) : cage;
    if (rest.imageSize() != image.size()) rest = rest.scaled(image.size());
    DeformParams deform;
    deform.coordinates = params.coordinates;
    deform.gridStep = params.gridStep;
    deform.backend = params.backend;
    // Past params.maxWarp the output shows a window of the image: bind its crop alone.
    const Rect crop = reframeCrop(rest, newSize, params);
    if (crop.size() == image.size()) {
        Ptr<Deformer> deformer = Deformer::create(image, rest, deform);
        deformer->deform(resizePose(rest, deformer->binding(), newSize, params), dst);
        return;
    }
    const Multicage cropped = cropMulticage(rest, crop);
    Ptr<Deformer> deformer = Deformer::create(image.getMat()(crop), cropped, deform);
    const std::vector<Point2f> pose = resizePose(cropped, deformer->binding(), newSize, params);
    deformer->deform(pose, dst);
}

}  // namespace multicage
}  // namespace cv

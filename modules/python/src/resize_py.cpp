// resize_pose() and content_aware_resize(): content-aware resizing (resize.hpp).
#include <algorithm>
#include <iterator>
#include <opencv2/multicage/resize.hpp>

#include "common.hpp"

namespace multicage_py {

using namespace cv::multicage;

const char* const kResizeKeywords =
    "coordinates, grid_step, backend, protect, margin, segmenter, segmenter_model, max_scale, "
    "max_warp";

bool resizeParam(ResizeParams& p, const std::string& key, const py::handle& v) {
    static const char* const keys[] = {"coordinates",     "grid_step", "backend",
                                       "protect",         "margin",    "segmenter",
                                       "segmenter_model", "max_scale", "max_warp"};
    if (std::find(std::begin(keys), std::end(keys), key) == std::end(keys)) return false;
    if (v.is_none()) return true;  // the default
    if (key == "coordinates") {
        p.coordinates = parseCoordinates(v);
    } else if (key == "grid_step") {
        p.gridStep = intArg(v, key);
        if (p.gridStep < 1)
            throw py::value_error("grid_step: must be >= 1, got " + std::to_string(p.gridStep));
    } else if (key == "backend") {
        p.backend = parseBackend(v);
    } else if (key == "margin") {
        p.margin = static_cast<float>(numberArg(v, key));
    } else if (key == "max_scale") {
        p.maxScale = numberArg(v, key);
    } else if (key == "max_warp") {
        p.maxWarp = numberArg(v, key);
    } else if (key == "segmenter") {
        p.segmenter = segmenterArg(v);
    } else if (key == "segmenter_model") {
        p.segmenterModel = segmenterModelArg(v);
    } else if (py::isinstance<py::str>(v)) {  // protect
        const std::string name = v.cast<std::string>();
        p.protect = parseProtectDetector(name);
        if (p.protect < 0)
            throw py::value_error("protect: '" + name + "' is not saliency, faces or all");
    } else {
        throw py::type_error("protect: expected 'saliency', 'faces' or 'all', got " +
                             shortValue(v));
    }
    return true;
}

namespace {

/** ResizeParams from keyword arguments: coordinates, grid_step, backend, protect (a detector
name), margin, segmenter, segmenter_model, max_scale, max_warp. */
ResizeParams resizeParams(const py::kwargs& kwargs) {
    ResizeParams p;
    for (const auto& item : kwargs) {
        const std::string key = item.first.cast<std::string>();
        const py::handle v = item.second;
        if (v.is_none()) continue;
        if (!resizeParam(p, key, v))
            throw py::type_error("content_aware_resize: unexpected keyword '" + key + "' (" +
                                 kResizeKeywords + ")");
    }
    checkSegmenterPair(p.segmenter, p.segmenterModel);
    return p;
}

}  // namespace

void defineResize(py::module_& m) {
    m.def(
        "resize_pose",
        [](const Multicage& cage, const py::handle& size, const py::object& bindingObj,
           const py::kwargs& kwargs) {
            const cv::Size newSize = sizeFromObject(size, "size");
            const ResizeParams params = resizeParams(kwargs);
            // A Deformer's own binding (or a Binding): the pose is checked on the very mesh
            // that will deform, whatever coordinates and grid step it was bound with.
            const Binding* binding = nullptr;
            py::object keep;
            if (!bindingObj.is_none()) {
                keep = py::hasattr(bindingObj, "deform") ? bindingObj.attr("binding") : bindingObj;
                if (!py::isinstance<Binding>(keep))
                    throw py::type_error("binding: expected a Binding or a Deformer, got " +
                                         shortValue(bindingObj));
                binding = &keep.cast<const Binding&>();
            }
            std::vector<cv::Point2f> pose;
            {
                py::gil_scoped_release release;
                pose = binding ? resizePose(cage, *binding, newSize, params)
                               : resizePose(cage, newSize, params);
            }
            return arrayFromPoints(pose);
        },
        py::arg("cage"), py::arg("size"), py::arg("binding") = py::none(),
        R"doc(The pose that resizes an image bound to cage into an image of size (w, h).

Returns a (vertex_count + 4) x 2 float32 array, frame corners last: the frame goes to the new
frame, each outline and the polygons inside it move by one similarity (the subject keeps its
size in pixels where the new frame allows), the background absorbs the aspect change. Always
valid, and fold-free on the binding it is checked on: binding (a Deformer or a Binding) checks
it on that one, the mesh that will deform it; without it, on a binding made here with the
keywords coordinates ('local_mvc' by default) and grid_step (1), so deform it with a Deformer
bound the same way. Deformer.deform, compute_maps and transform_points answer in the new size.
Keywords: coordinates, grid_step, max_scale (8: the largest growth of a side).)doc");
    m.def(
        "content_aware_resize",
        [](const py::handle& imageObj, const py::handle& size, const py::object& cageObj,
           const py::kwargs& kwargs) {
            py::object keep;
            const cv::Mat image = imageFromArray(imageObj, "image", keep);
            const cv::Size newSize = sizeFromObject(size, "size");
            const ResizeParams params = resizeParams(kwargs);
            Multicage cage;
            if (!cageObj.is_none()) cage = multicageArg(cageObj, "cage");
            cv::Mat dst;
            {
                py::gil_scoped_release release;
                contentAwareResize(image, newSize, dst, cage, params);
            }
            return arrayFromMat(dst);
        },
        py::arg("image"), py::arg("size"), py::arg("cage") = py::none(),
        R"doc(The image resized to size (w, h), faces and subjects keeping their shape.

cage: a Multicage (scaled to the image when drawn on another size), or None for the default
proposal (propose_multicage with protection). Keywords: coordinates, grid_step, backend,
protect ('saliency', 'faces', 'all'), margin, segmenter ('auto', 'model', 'classic') and
segmenter_model (as propose_multicage's), max_scale, max_warp (1.5: the largest aspect change
the warp takes alone; past it the output shows a window of the image, reframe_window()).
Returns an h x w array of the image's dtype and channels.)doc");
}

}  // namespace multicage_py

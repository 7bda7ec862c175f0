// propose_multicage() and its friends: `multicage propose` in Python.
#include <cmath>
#include <sstream>

#include "common.hpp"

namespace multicage_py {
namespace {

using namespace cv::multicage;

/** The keywords of propose_multicage and friends. They are the CLI's options with '-' as
'_' (`--min-region-area` is min_region_area); min_area is accepted too, as the CLI's older
`--min-area`. */
struct ProposeOptions {
    ProposeParams params;
    /** As `multicage propose`: inner polygons protect the features inside each outline
    (proposeProtectedMulticage) unless protect=False. */
    bool protect = true;
};

const char* kProposeKeywords =
    "method, max_vertices, max_polygon_vertices, max_polygons, max_depth, margin, min_region_area, "
    "working_size, rect, protect, cascade_dir, segmenter, segmenter_model, morphology_radius, "
    "grabcut_iterations, grabcut_max_side";

ProposeOptions proposeOptions(const py::kwargs& kwargs, const char* function, bool takesProtect) {
    ProposeOptions o;
    ProposeParams& p = o.params;
    bool haveMinArea = false;
    for (const auto& item : kwargs) {
        const std::string key = item.first.cast<std::string>();
        const py::handle v = item.second;
        if (key == "method") {
            if (py::isinstance<py::str>(v)) {
                p.method = parseProposeMethod(v.cast<std::string>());
                if (p.method < 0)
                    throw py::value_error(
                        "method: '" + v.cast<std::string>() +
                        "' is not one of auto, threshold, adaptive, grabcut, saliency, "
                        "spectral, mask, labels");
            } else {
                p.method = enumFromObject(v, "method", {}, PROPOSE_LABELS + 1);
            }
        } else if (key == "max_vertices")
            p.maxVertices = intArg(v, key);
        else if (key == "max_polygon_vertices")
            p.maxPolygonVertices = intArg(v, key);
        else if (key == "max_polygons")
            p.maxPolygons = intArg(v, key);
        else if (key == "max_depth")
            p.maxDepth = intArg(v, key);
        else if (key == "margin")
            p.margin = static_cast<float>(numberArg(v, key));
        else if (key == "min_region_area" || key == "min_area") {
            if (haveMinArea)
                throw py::type_error(std::string(function) +
                                     "() got both min_region_area and min_area "
                                     "(the same keyword; use min_region_area)");
            haveMinArea = true;
            p.minRegionArea = numberArg(v, key);
        } else if (key == "morphology_radius")
            p.morphologyRadius = intArg(v, key);
        else if (key == "working_size")
            p.workingSize = intArg(v, key);
        else if (key == "grabcut_iterations")
            p.grabCutIterations = intArg(v, key);
        else if (key == "grabcut_max_side")
            p.grabCutMaxSide = intArg(v, key);
        else if (key == "protect" && takesProtect) {
            // True/False as --protect/--no-protect, or a detector name as --protect DETECTOR.
            if (py::isinstance<py::str>(v)) {
                const std::string name = v.cast<std::string>();
                const int detector = parseProtectDetector(name);
                if (detector < 0)
                    throw py::value_error("protect: '" + name +
                                          "' is not one of saliency, faces, all");
                o.protect = true;
                p.protect = detector;
            } else {
                o.protect = boolArg(v, key);
            }
        } else if (key == "cascade_dir") {
            if (!py::isinstance<py::str>(v))
                throw py::type_error("cascade_dir: expected a folder name (str), got " +
                                     shortValue(v));
            p.cascadeDir = v.cast<std::string>();
        } else if (key == "segmenter") {
            p.segmenter = segmenterArg(v);
        } else if (key == "segmenter_model") {
            p.segmenterModel = segmenterModelArg(v);
        } else if (key == "rect") {
            if (py::isinstance<py::str>(v) || !py::isinstance<py::sequence>(v))
                throw py::type_error("rect: expected (x, y, width, height), got " + shortValue(v));
            const py::sequence r = py::reinterpret_borrow<py::sequence>(v);
            if (py::len(r) != 4)
                throw py::value_error("rect: expected (x, y, width, height), got " +
                                      std::to_string(py::len(r)) + " values");
            p.rect = cv::Rect(intArg(r[0], "rect[0]"), intArg(r[1], "rect[1]"),
                              intArg(r[2], "rect[2]"), intArg(r[3], "rect[3]"));
        } else {
            throw py::type_error(std::string(function) + "() got an unexpected keyword argument '" +
                                 key + "' (it takes " + kProposeKeywords + ")");
        }
    }
    if (!std::isfinite(p.margin)) throw py::value_error("margin: must be finite");
    if (!std::isfinite(p.minRegionArea)) throw py::value_error("min_region_area: must be finite");
    checkSegmenterPair(p.segmenter, p.segmenterModel);
    return o;
}

/** The multicage `multicage propose` gives for the same options: protected by default, and a
mask or label input (no photo to find features in) only when protect=True is explicit. */
Multicage proposeProtected(const cv::Mat& image, const ProposeOptions& o, bool protectGiven) {
    const bool maskInput = o.params.method == PROPOSE_MASK || o.params.method == PROPOSE_LABELS;
    if (!o.protect || (maskInput && !protectGiven)) return proposeMulticage(image, o.params);
    if (!maskInput) return proposeProtectedMulticage(image, o.params);
    Multicage cage = proposeMulticage(image, o.params);
    const int top = cage.polygonCount();
    for (int p = 0; p < top; ++p)
        if (cage.depth(p) == 1) cage = protectFeatures(image, cage, p, o.params);
    return cage;
}

/** The defaults of the propose keywords: the library's ProposeParams(). */
py::dict proposeDefaults() {
    const ProposeOptions o;
    const ProposeParams& p = o.params;
    py::dict d;
    d["method"] = proposeMethodName(p.method);
    d["max_vertices"] = p.maxVertices;
    d["max_polygon_vertices"] = p.maxPolygonVertices;
    d["max_polygons"] = p.maxPolygons;
    d["max_depth"] = p.maxDepth;
    d["margin"] = p.margin;
    d["min_region_area"] = p.minRegionArea;
    d["working_size"] = p.workingSize;
    d["rect"] = py::make_tuple(p.rect.x, p.rect.y, p.rect.width, p.rect.height);
    d["protect"] = o.protect;
    d["cascade_dir"] = std::string(p.cascadeDir);
    d["segmenter"] = segmenterName(p.segmenter);
    d["segmenter_model"] = py::none();  // the library's look-up (segmenter_model_file())
    d["morphology_radius"] = p.morphologyRadius;
    d["grabcut_iterations"] = p.grabCutIterations;
    d["grabcut_max_side"] = p.grabCutMaxSide;
    return d;
}

const char* kProposeMulticageDoc =
    "propose_multicage(image, **keywords) -> Multicage\n\n"
    "Proposes a valid, oriented multicage enclosing the objects of an image, as `multicage "
    "propose` "
    "does: the keywords are its options with '_' for '-' (--min-region-area: min_region_area; "
    "min_area is accepted too). Raises NoObjectFoundError (a multicage.Error) when it finds no "
    "object, where the CLI says \"no object found\".\n\n"
    "method: 'auto', 'threshold', 'adaptive', 'grabcut', 'saliency', 'spectral', 'mask', 'labels' "
    "or a ProposeMethod. protect=True (the default, as the CLI and the editor) adds inner "
    "polygons around the faces, then the textured salient features inside every outer polygon "
    "(the multicage proper: what they enclose stays almost rigid when the outline moves); "
    "protect='faces' or 'saliency' protects only those; protect=False gives outlines only. "
    "segmenter: where the subject of a photo comes from (method='auto' without rect): 'auto' "
    "(the learned subject model when one is found, else 'classic'), 'model' (the model; none "
    "found: multicage.Error), 'classic' (GrabCut and threshold cues only); segmenter_model: an "
    "ONNX subject model to run instead of the installed one (docs/models.md; a file that is "
    "not one raises multicage.Error naming it); segmenter_model_file() says which would run. "
    "margin < 0 and morphology_radius < 0 "
    "pick a size from the image. Defaults (the library's ProposeParams, also "
    "multicage.propose_defaults()):\n";

void defineProposeMulticage(py::module_& m) {
    // The keyword list with the library's defaults, so that the docs never drift from them.
    std::string proposeKeywordDoc;
    for (const auto& item : proposeDefaults())
        proposeKeywordDoc += "    " + item.first.cast<std::string>() + "=" +
                             py::repr(item.second).cast<std::string>() + "\n";

    m.def(
        "propose_multicage",
        [](const py::object& image, const py::kwargs& kwargs) {
            const ProposeOptions options = proposeOptions(kwargs, "propose_multicage", true);
            const bool protectGiven = kwargs.contains("protect");
            py::object keep;
            const cv::Mat src = imageFromArray(image, "image", keep, true);
            Multicage cage;
            {
                py::gil_scoped_release release;
                cage = proposeProtected(src, options, protectGiven);
            }
            if (cage.polygonCount() == 0) {
                std::ostringstream s;
                s << "propose_multicage: no object found with method='"
                  << proposeMethodName(options.params.method)
                  << "' (no region larger than min_region_area=" << options.params.minRegionArea
                  << " of the image); try another method, a smaller min_region_area, or a mask "
                     "(method='mask')";
                raise(noObjectErrorType, s.str());
            }
            return cage;
        },
        py::arg("image"), (kProposeMulticageDoc + proposeKeywordDoc).c_str());
}

/** segmenter_model_file(segmenter='auto', segmenter_model=None) -> (path, why). */
py::tuple segmenterModelFileOf(const py::object& segmenter, const py::object& model) {
    ProposeParams p;
    p.segmenter = segmenterArg(segmenter);
    p.segmenterModel = segmenterModelArg(model);
    checkSegmenterPair(p.segmenter, p.segmenterModel);
    cv::String why;
    const cv::String file = segmenterModelFile(p, &why);
    return py::make_tuple(std::string(file), std::string(why));
}

}  // namespace

void defineProposal(py::module_& m) {
    defineProposeMulticage(m);
    m.def("propose_defaults", &proposeDefaults,
          "The default of every propose_multicage keyword, from the library's ProposeParams().");
    m.def(
        "propose_segmentation",
        [](const py::object& image, const py::kwargs& kwargs) {
            const ProposeParams params =
                proposeOptions(kwargs, "propose_segmentation", true).params;
            py::object keep;
            const cv::Mat src = imageFromArray(image, "image", keep, true);
            cv::Mat mask;
            {
                py::gil_scoped_release release;
                proposeSegmentation(src, mask, params);
            }
            return arrayFromMat(mask);
        },
        py::arg("image"),
        "The cleaned segmentation propose_multicage encloses: HxW uint8, 255 on object pixels "
        "(all 0 where it finds no object). Same keywords as propose_multicage; the subject "
        "model runs as there, but no face is searched (protect changes nothing here), so no "
        "person prior joins it.");
    m.def(
        "protect_features",
        [](const py::object& image, const py::object& cageObj, const py::object& polygonObj,
           const py::kwargs& kwargs) {
            const Multicage& cage = multicageArg(cageObj, "multicage");
            const int polygon = intArg(polygonObj, "polygon");
            const ProposeParams params = proposeOptions(kwargs, "protect_features", false).params;
            py::object keep;
            const cv::Mat src = imageFromArray(image, "image", keep);
            checkIndex(polygon, cage.polygonCount(), "polygon");
            py::gil_scoped_release release;
            return protectFeatures(src, cage, polygon, params);
        },
        py::arg("image"), py::arg("multicage"), py::arg("polygon"),
        "A copy of the multicage with protective polygons added around the salient features inside "
        "polygon `polygon` (unchanged when there is none). Same keywords as propose_multicage, "
        "except protect.");
    m.def(
        "subject_map",
        [](const py::object& image, const py::object& model) {
            ProposeParams params;
            params.segmenterModel = segmenterModelArg(model);
            py::object keep;
            const cv::Mat src = imageFromArray(image, "image", keep);
            cv::Mat map;
            {
                py::gil_scoped_release release;
                subjectMap(src, map, params);
            }
            return arrayFromMat(map);
        },
        py::arg("image"), py::arg("segmenter_model") = py::none(),
        "The learned subject map of an image: HxW float32, 0 (background) to 1 (subject), what "
        "the subject model sees as the subject (segmenter_model, else the installed model: "
        "segmenter_model_file()). Raises multicage.Error when no model is found, or naming the "
        "file when it is not a subject model.");
    m.def("segmenter_model_file", &segmenterModelFileOf, py::arg("segmenter") = "auto",
          py::arg("segmenter_model") = py::none(),
          "(path, why): the subject model propose_multicage would run with these keywords, and "
          "how it was found ('ProposeParams::segmenterModel' for segmenter_model, "
          "'MULTICAGE_SEGMENTER_MODEL', 'the build tree', 'the install prefix'); path is '' when "
          "none runs, and why then says why and how to get one. A path given (segmenter_model "
          "or the environment variable) is returned as given, whether or not it exists.");
}

}  // namespace multicage_py

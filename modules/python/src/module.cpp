// The Python module `multicage._multicage`: bindings over the C++ library, nothing more.
// Conventions follow cv2: images are numpy arrays (HxW, HxWx3 BGR, HxWx4 BGRA; uint8, uint16,
// float32), points are Nx2 arrays of (x, y), sizes are (width, height). The GIL is released
// while the library binds, deforms, proposes or computes coordinates.
#include "convert.hpp"

#include <opencv2/multicage.hpp>
#include <pybind11/stl.h>

#include <algorithm>
#include <mutex>

namespace multicage_py {
namespace {

using namespace cv::multicage;

PyObject* errorType = nullptr;  // multicage.Error, alive as long as the interpreter

// --- argument parsing -----------------------------------------------------------------------

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}

/** A string name, one of the enum's members, or its integer value. */
int enumFromObject(const py::handle& obj, const char* what,
                   const std::vector<std::pair<std::string, int>>& names, int count) {
    if (py::isinstance<py::str>(obj)) {
        const std::string s = lower(obj.cast<std::string>());
        std::string known;
        for (const auto& n : names) {
            if (n.first == s) return n.second;
            known += (known.empty() ? "'" : ", '") + n.first + "'";
        }
        throw py::value_error(std::string(what) + ": '" + obj.cast<std::string>() + "' is not one of " + known);
    }
    int v;
    try {
        v = py::int_(py::reinterpret_borrow<py::object>(obj)).cast<int>();
    } catch (const py::error_already_set&) {
        throw py::type_error(std::string(what) + ": expected a name or an enum value, got " + typeName(obj));
    }
    if (v < 0 || v >= count)
        throw py::value_error(std::string(what) + ": " + std::to_string(v) + " is out of range");
    return v;
}

int parseBackend(const py::handle& obj) {
    return enumFromObject(obj, "backend", {{"auto", BACKEND_AUTO}, {"cpu", BACKEND_CPU}, {"gpu", BACKEND_GPU}}, 3);
}

int parseCoordinates(const py::handle& obj) {
    return enumFromObject(obj, "coordinates",
                          {{"mvc", MEAN_VALUE}, {"mean_value", MEAN_VALUE}, {"harmonic", HARMONIC}}, 2);
}

const char* backendName(int b) { return b == BACKEND_GPU ? "gpu" : b == BACKEND_CPU ? "cpu" : "auto"; }
const char* coordinatesName(int c) { return c == HARMONIC ? "harmonic" : "mvc"; }

DeformParams deformParams(const py::object& coordinates, int gridStep, const py::object& backend,
                          const py::object& borderValue, bool halfFloat, bool gpuBinding) {
    DeformParams p;
    p.coordinates = parseCoordinates(coordinates);
    if (gridStep < 1) throw py::value_error("grid_step: must be >= 1, got " + std::to_string(gridStep));
    p.gridStep = gridStep;
    p.backend = parseBackend(backend);
    p.borderValue = scalarFromObject(borderValue, "border_value");
    p.halfFloat = halfFloat;
    p.gpuBinding = gpuBinding;
    return p;
}

ProposeParams proposeParams(const py::kwargs& kwargs, const char* function) {
    ProposeParams p;
    static const char* known =
        "method, max_vertices, max_polygon_vertices, max_polygons, max_depth, margin, "
        "min_region_area, morphology_radius, working_size, rect, grabcut_iterations, grabcut_max_side";
    for (const auto& item : kwargs) {
        const std::string key = item.first.cast<std::string>();
        const py::handle v = item.second;
        if (key == "method") {
            if (py::isinstance<py::str>(v)) {
                p.method = parseProposeMethod(v.cast<std::string>());
                if (p.method < 0)
                    throw py::value_error("method: '" + v.cast<std::string>() +
                                          "' is not one of auto, threshold, adaptive, grabcut, saliency, "
                                          "spectral, mask, labels");
            } else {
                p.method = py::int_(py::reinterpret_borrow<py::object>(v)).cast<int>();
            }
        } else if (key == "max_vertices") p.maxVertices = v.cast<int>();
        else if (key == "max_polygon_vertices") p.maxPolygonVertices = v.cast<int>();
        else if (key == "max_polygons") p.maxPolygons = v.cast<int>();
        else if (key == "max_depth") p.maxDepth = v.cast<int>();
        else if (key == "margin") p.margin = v.cast<float>();
        else if (key == "min_region_area") p.minRegionArea = v.cast<double>();
        else if (key == "morphology_radius") p.morphologyRadius = v.cast<int>();
        else if (key == "working_size") p.workingSize = v.cast<int>();
        else if (key == "grabcut_iterations") p.grabCutIterations = v.cast<int>();
        else if (key == "grabcut_max_side") p.grabCutMaxSide = v.cast<int>();
        else if (key == "rect") {
            const auto r = v.cast<std::vector<int>>();
            if (r.size() != 4) throw py::value_error("rect: expected (x, y, width, height)");
            p.rect = cv::Rect(r[0], r[1], r[2], r[3]);
        } else {
            throw py::type_error(std::string(function) + "() got an unexpected keyword argument '" + key +
                                 "' (it takes " + known + ")");
        }
    }
    return p;
}

void checkIndex(int i, int count, const char* what) {
    if (i < 0 || i >= count)
        throw py::index_error(std::string(what) + " " + std::to_string(i) + " does not exist (there " +
                              (count == 1 ? "is 1 " : "are " + std::to_string(count) + " ") + what +
                              (count == 1 ? ")" : "s)"));
}

py::tuple sizeTuple(cv::Size s) { return py::make_tuple(s.width, s.height); }

/** validate()/validateGeometry() as (ok, reason), or raising multicage.Error. */
py::tuple validation(bool ok, const std::string& why, bool raiseError) {
    if (!ok && raiseError) {
        PyErr_SetString(errorType, why.c_str());
        throw py::error_already_set();
    }
    return py::make_tuple(ok, why);
}

// --- the Deformer ---------------------------------------------------------------------------

/** A Deformer behind a mutex: the GIL is released while it works, and one instance holds
mutable state (CPU positions, a GL context), so Python threads sharing it take turns. */
struct PyDeformer {
    cv::Ptr<Deformer> deformer;
    std::mutex mutex;
};

std::unique_ptr<PyDeformer> makeDeformer(const py::handle& imageObj, const py::handle& rest,
                                         const DeformParams& params) {
    py::object keep;
    const cv::Mat image = imageFromArray(imageObj, "image", keep);
    auto d = std::make_unique<PyDeformer>();
    if (py::isinstance<Multicage>(rest)) {
        const Multicage& cage = rest.cast<const Multicage&>();
        py::gil_scoped_release release;
        d->deformer = Deformer::create(image, cage, params);
    } else if (py::isinstance<Binding>(rest)) {
        const Binding& binding = rest.cast<const Binding&>();
        py::gil_scoped_release release;
        d->deformer = Deformer::create(image, binding, params);
    } else {
        throw py::type_error("rest: expected a multicage.Multicage or a multicage.Binding, got " + typeName(rest));
    }
    return d;
}

const char* kDeformerDoc = R"doc(Binds an image to a multicage once, then deforms it for any number of poses.

Deformer(image, rest, *, coordinates='mvc', grid_step=1, backend='auto', border_value=None,
         half_float=False, gpu_binding=False)

image        numpy array as cv2 gives it: uint8, uint16 or float32; HxW, HxWx3 or HxWx4
rest         a Multicage of the image's size (with multicage.Multicage.scaled for another
             size), or a Binding made by multicage.bind()
coordinates  'mvc' (mean value) or 'harmonic', or a CoordinateType
grid_step    a mesh node every grid_step pixels (1 is the paper's method)
backend      'auto' (GPU when an EGL context can be made, else CPU), 'cpu' or 'gpu', or a Backend
border_value output pixels no deformed triangle covers: a number (every channel) or up to 4
half_float   GPU: store coefficients as 16-bit floats
gpu_binding  GPU: compute the mean value binding in a compute shader

A pose is an Nx2 array of vertex_count points (or vertex_count + 4 with the frame corners
last). The GIL is released while binding and deforming.)doc";

}  // namespace
}  // namespace multicage_py

PYBIND11_MODULE(_multicage, m) {
    using namespace multicage_py;
    m.doc() = "multicage: multicage image deformation (bindings over the C++ library)";
    m.attr("__version__") = MULTICAGE_VERSION;

    errorType = PyErr_NewExceptionWithDoc(
        "multicage.Error",
        "An error reported by the multicage library (a cv::Exception); the message is the "
        "library's own. Attributes: code (OpenCV error code), func (the C++ function).",
        PyExc_ValueError, nullptr);
    m.attr("Error") = py::handle(errorType);
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const cv::Exception& e) {
            py::object exc = py::reinterpret_borrow<py::object>(errorType)(e.err);
            exc.attr("code") = e.code;
            exc.attr("func") = e.func;
            PyErr_SetObject(errorType, exc.ptr());
        }
    });

    py::enum_<Backend>(m, "Backend", "Where a Deformer runs.")
        .value("AUTO", BACKEND_AUTO)
        .value("CPU", BACKEND_CPU)
        .value("GPU", BACKEND_GPU);
    py::enum_<CoordinateType>(m, "CoordinateType", "Cage coordinates.")
        .value("MEAN_VALUE", MEAN_VALUE)
        .value("HARMONIC", HARMONIC);
    py::enum_<ProposeMethod>(m, "ProposeMethod", "How propose_multicage finds objects.")
        .value("AUTO", PROPOSE_AUTO)
        .value("THRESHOLD", PROPOSE_THRESHOLD)
        .value("ADAPTIVE", PROPOSE_ADAPTIVE)
        .value("GRABCUT", PROPOSE_GRABCUT)
        .value("SALIENCY", PROPOSE_SALIENCY)
        .value("SPECTRAL_RESIDUAL", PROPOSE_SPECTRAL_RESIDUAL)
        .value("MASK", PROPOSE_MASK)
        .value("LABELS", PROPOSE_LABELS);
    m.attr("CONDITIONING_WARNING") = kConditioningWarning;

    // --- Pose ---
    py::class_<Pose>(m, "Pose", "A named, timed position of every user vertex.")
        .def(py::init([](std::string name, const py::object& vertices, double time) {
                 Pose p;
                 p.name = std::move(name);
                 p.time = time;
                 p.vertices = pointsFromArray(vertices, "vertices");
                 return p;
             }),
             py::arg("name"), py::arg("vertices"), py::arg("time") = 0.0)
        .def_readwrite("name", &Pose::name)
        .def_readwrite("time", &Pose::time)
        .def_property(
            "vertices", [](const Pose& p) { return arrayFromPoints(p.vertices); },
            [](Pose& p, const py::object& v) { p.vertices = pointsFromArray(v, "vertices"); },
            "Nx2 float32 array (a copy: assign to change it)")
        .def("__repr__", [](const Pose& p) {
            return "<multicage.Pose '" + p.name + "' time=" + py::repr(py::float_(p.time)).cast<std::string>() +
                   ", " + std::to_string(p.vertices.size()) + " vertices>";
        });

    // --- Multicage ---
    py::class_<Multicage>(m, "Multicage", R"doc(Disjoint simple polygons over an image, plus the image frame.

Multicage(size=None): size is (width, height), as cv2 sizes are (not image.shape);
Multicage.for_image(image) takes it from an array. Points are (x, y) with pixel (x, y) at its
centre; the frame corners are (-0.5, -0.5) and (W-0.5, H-0.5). Vertices are numbered polygon
by polygon, then the 4 frame corners.)doc")
        .def(py::init([](const py::object& size) {
                 return size.is_none() ? Multicage() : Multicage(sizeFromObject(size, "size"));
             }),
             py::arg("size") = py::none())
        .def_static(
            "for_image",
            [](const py::object& image) {
                py::object keep;
                return Multicage(imageFromArray(image, "image", keep).size());
            },
            py::arg("image"), "An empty multicage of the image's size.")
        .def_property(
            "image_size", [](const Multicage& c) { return sizeTuple(c.imageSize()); },
            [](Multicage& c, const py::object& s) { c.setImageSize(sizeFromObject(s, "image_size")); },
            "(width, height)")
        .def_property_readonly("polygon_count", &Multicage::polygonCount)
        .def_property_readonly("vertex_count", &Multicage::vertexCount, "user vertices (frame excluded)")
        .def_property_readonly("pose_count", &Multicage::poseCount)
        .def(
            "add_polygon",
            [](Multicage& c, const py::object& points) { return c.addPolygon(pointsFromArray(points, "points")); },
            py::arg("points"),
            "Adds a polygon (Nx2 points, N >= 3) and returns its index. Geometry is checked by validate().")
        .def(
            "set_polygon",
            [](Multicage& c, int i, const py::object& points) {
                checkIndex(i, c.polygonCount(), "polygon");
                c.setPolygon(i, pointsFromArray(points, "points"));
            },
            py::arg("i"), py::arg("points"))
        .def(
            "remove_polygon",
            [](Multicage& c, int i) {
                checkIndex(i, c.polygonCount(), "polygon");
                c.removePolygon(i);
            },
            py::arg("i"))
        .def(
            "polygon",
            [](const Multicage& c, int i) {
                checkIndex(i, c.polygonCount(), "polygon");
                return arrayFromPoints(c.polygon(i));
            },
            py::arg("i"), "Rest positions of polygon i, Nx2 float32.")
        .def("polygons",
             [](const Multicage& c) {
                 py::list out;
                 for (int i = 0; i < c.polygonCount(); ++i) out.append(arrayFromPoints(c.polygon(i)));
                 return out;
             })
        .def(
            "polygon_offset",
            [](const Multicage& c, int i) {
                checkIndex(i, c.polygonCount(), "polygon");
                return c.polygonOffset(i);
            },
            py::arg("i"), "Index in vertices() of polygon i's first vertex.")
        .def(
            "depth",
            [](const Multicage& c, int i) {
                checkIndex(i, c.polygonCount(), "polygon");
                return c.depth(i);
            },
            py::arg("i"), "1 + the number of polygons containing polygon i (the frame is depth 0).")
        .def(
            "signed_area",
            [](const Multicage& c, int i) {
                checkIndex(i, c.polygonCount(), "polygon");
                return c.signedArea(i);
            },
            py::arg("i"), "> 0: clockwise on screen.")
        .def(
            "vertices", [](const Multicage& c) { return arrayFromPoints(c.vertices()); },
            "User vertices in order, then the 4 frame corners: (vertex_count + 4) x 2 float32.")
        .def(
            "rest_pose",
            [](const Multicage& c) {
                std::vector<cv::Point2f> v = c.vertices();
                v.resize(static_cast<size_t>(c.vertexCount()));
                return arrayFromPoints(v);
            },
            "The user vertices at rest, vertex_count x 2 float32: the identity pose, to move.")
        .def("frame", [](const Multicage& c) { return arrayFromPoints(c.frame()); })
        .def("orient", &Multicage::orient, "Applies the orientation rule (alternating with depth).")
        .def(
            "validate",
            [](const Multicage& c, bool raiseError) {
                std::string why;
                const bool ok = c.validate(&why);
                return validation(ok, why, raiseError);
            },
            py::arg("raise_error") = false,
            "Returns (ok, reason); with raise_error=True raises multicage.Error(reason) instead of "
            "returning False.")
        .def(
            "validate_geometry",
            [](const Multicage& c, bool raiseError) {
                std::string why;
                const bool ok = c.validateGeometry(&why);
                return validation(ok, why, raiseError);
            },
            py::arg("raise_error") = false, "As validate(), ignoring the orientation rule.")
        .def(
            "add_pose",
            [](Multicage& c, const std::string& name, const py::object& vertices, double time) {
                return c.addPose(name, pointsFromArray(vertices, "vertices"), time);
            },
            py::arg("name"), py::arg("vertices"), py::arg("time") = 0.0,
            "Adds a named pose (vertex_count points, or vertex_count + 4); returns its index.")
        .def(
            "pose",
            [](const Multicage& c, const py::object& key) {
                if (py::isinstance<py::str>(key)) {
                    const std::string name = key.cast<std::string>();
                    const int i = c.findPose(name);
                    if (i < 0) {
                        std::string names;
                        for (int j = 0; j < c.poseCount(); ++j) names += (j ? ", " : "") + c.pose(j).name;
                        throw py::key_error("no pose named '" + name + "' (the multicage has: " +
                                            (names.empty() ? "no poses" : names) + ")");
                    }
                    return c.pose(i);
                }
                const int i = key.cast<int>();
                checkIndex(i, c.poseCount(), "pose");
                return c.pose(i);
            },
            py::arg("key"), "A pose by index or by name (a copy).")
        .def_property_readonly(
            "poses",
            [](const Multicage& c) {
                std::vector<Pose> out;
                for (int i = 0; i < c.poseCount(); ++i) out.push_back(c.pose(i));
                return out;
            },
            "All poses (copies).")
        .def("find_pose", &Multicage::findPose, py::arg("name"), "Index of the pose called name, or -1.")
        .def(
            "set_pose",
            [](Multicage& c, int i, const Pose& p) {
                checkIndex(i, c.poseCount(), "pose");
                c.setPose(i, p);
            },
            py::arg("i"), py::arg("pose"))
        .def(
            "remove_pose",
            [](Multicage& c, int i) {
                checkIndex(i, c.poseCount(), "pose");
                c.removePose(i);
            },
            py::arg("i"))
        .def(
            "scaled", [](const Multicage& c, const py::object& s) { return c.scaled(sizeFromObject(s, "size")); },
            py::arg("size"), "The same multicage for an image of size (width, height).")
        .def_static("load", &Multicage::load, py::arg("path"), "Loads a YAML or JSON cage file.")
        .def("save", &Multicage::save, py::arg("path"), "Saves a YAML or JSON cage file (atomically).")
        .def(
            "draw",
            [](const Multicage& c, const py::object& image, int thickness, bool drawVertices) {
                py::object keep;
                cv::Mat canvas = imageFromArray(image, "image", keep).clone();
                c.draw(canvas, thickness, drawVertices);
                return arrayFromMat(canvas);
            },
            py::arg("image"), py::arg("thickness") = 1, py::arg("draw_vertices") = true,
            "A copy of image with the polygons drawn, coloured by depth.")
        .def("__copy__", [](const Multicage& c) { return Multicage(c); })
        .def("__deepcopy__", [](const Multicage& c, const py::object&) { return Multicage(c); }, py::arg("memo"))
        .def("__repr__", [](const Multicage& c) {
            return "<multicage.Multicage " + std::to_string(c.imageSize().width) + "x" +
                   std::to_string(c.imageSize().height) + ", " + std::to_string(c.polygonCount()) + " polygons, " +
                   std::to_string(c.vertexCount()) + " vertices, " + std::to_string(c.poseCount()) + " poses>";
        });

    // --- Binding ---
    py::class_<Binding>(m, "Binding", "Every grid node bound to every vertex of a multicage (Algorithm 1).")
        .def_property_readonly("image_size", [](const Binding& b) { return sizeTuple(b.imageSize); })
        .def_readonly("grid_step", &Binding::gridStep)
        .def_property_readonly("grid_size", [](const Binding& b) { return sizeTuple(b.gridSize); },
                               "(nodes in x, nodes in y)")
        .def_property_readonly("coordinates", [](const Binding& b) { return coordinatesName(b.coordinates); })
        .def_property_readonly(
            "coefficients", [](const Binding& b) { return arrayFromMat(b.coefficients, false); },
            "coefficient_count x node_count float32 (read-only view): row j is coefficient j of every "
            "node, node (gx, gy) at column gy * grid_size[0] + gx.")
        .def_property_readonly("rest_vertices", [](const Binding& b) { return arrayFromPoints(b.restVertices); })
        .def_readonly("min_conditioning", &Binding::minConditioning)
        .def_property_readonly("worst_node", [](const Binding& b) { return py::make_tuple(b.worstNode.x, b.worstNode.y); })
        .def_property_readonly("coefficient_count", &Binding::coefficientCount)
        .def_property_readonly("node_count", &Binding::nodeCount)
        .def(
            "nodes", [](const Binding& b) { return arrayFromMat(b.nodes()); },
            "Rest positions of the nodes, grid height x grid width x 2 float32.")
        .def(
            "apply",
            [](const Binding& b, const py::object& pose) {
                const std::vector<cv::Point2f> p = pointsFromArray(pose, "pose");
                cv::Mat positions;
                {
                    py::gil_scoped_release release;
                    b.apply(p, positions);
                }
                return arrayFromMat(positions);
            },
            py::arg("pose"), "Deformed node positions for a pose, grid height x grid width x 2 float32.")
        .def("__repr__", [](const Binding& b) {
            return "<multicage.Binding " + std::string(coordinatesName(b.coordinates)) + ", " +
                   std::to_string(b.gridSize.width) + "x" + std::to_string(b.gridSize.height) + " nodes, " +
                   std::to_string(b.coefficientCount()) + " coefficients>";
        });

    m.def(
        "bind",
        [](const Multicage& cage, const py::object& coordinates, int gridStep, bool onGpu) {
            const int coords = parseCoordinates(coordinates);
            if (onGpu && coords != MEAN_VALUE)
                throw py::value_error("on_gpu: the GPU binds mean value coordinates only");
            py::gil_scoped_release release;
            return onGpu ? bindOnGpu(cage, gridStep) : bind(cage, coords, gridStep);
        },
        py::arg("multicage"), py::arg("coordinates") = "mvc", py::arg("grid_step") = 1, py::arg("on_gpu") = false,
        "Binds every grid node to every vertex (Algorithm 1); a Binding can feed several Deformers. "
        "The GIL is released while it runs.");

    // --- Deformer ---
    auto create = [](const py::object& image, const py::object& rest, const py::object& coordinates, int gridStep,
                     const py::object& backend, const py::object& borderValue, bool halfFloat, bool gpuBinding) {
        return makeDeformer(image, rest,
                            deformParams(coordinates, gridStep, backend, borderValue, halfFloat, gpuBinding));
    };
    py::class_<PyDeformer>(m, "Deformer", kDeformerDoc)
        .def(py::init(create), py::arg("image"), py::arg("rest"), py::kw_only(), py::arg("coordinates") = "mvc",
             py::arg("grid_step") = 1, py::arg("backend") = "auto", py::arg("border_value") = py::none(),
             py::arg("half_float") = false, py::arg("gpu_binding") = false)
        .def_static("create", create, py::arg("image"), py::arg("rest"), py::kw_only(),
                    py::arg("coordinates") = "mvc", py::arg("grid_step") = 1, py::arg("backend") = "auto",
                    py::arg("border_value") = py::none(), py::arg("half_float") = false,
                    py::arg("gpu_binding") = false, "Same as Deformer(...).")
        .def(
            "deform",
            [](PyDeformer& d, const py::object& pose) {
                const std::vector<cv::Point2f> p = pointsFromArray(pose, "pose");
                cv::Mat out;
                {
                    py::gil_scoped_release release;
                    std::lock_guard<std::mutex> lock(d.mutex);
                    d.deformer->deform(p, out);
                }
                return arrayFromMat(out);
            },
            py::arg("pose"), "The image deformed to pose: same shape and dtype as the input.")
        .def(
            "compute_maps",
            [](PyDeformer& d, const py::object& pose) {
                const std::vector<cv::Point2f> p = pointsFromArray(pose, "pose");
                cv::Mat mapx, mapy;
                {
                    py::gil_scoped_release release;
                    std::lock_guard<std::mutex> lock(d.mutex);
                    d.deformer->computeMaps(p, mapx, mapy);
                }
                return py::make_tuple(arrayFromMat(mapx), arrayFromMat(mapy));
            },
            py::arg("pose"),
            "Inverse maps (mapx, mapy) for cv2.remap, HxW float32: for each output pixel its source "
            "position; uncovered pixels get -1e4. Remap masks and labels with cv2.INTER_NEAREST.")
        .def(
            "folded_triangles",
            [](PyDeformer& d, const py::object& pose) {
                const std::vector<cv::Point2f> p = pointsFromArray(pose, "pose");
                py::gil_scoped_release release;
                std::lock_guard<std::mutex> lock(d.mutex);
                return d.deformer->foldedTriangles(p);
            },
            py::arg("pose"), "Number of mesh triangles the pose turns over (0: no fold-over).")
        .def_property_readonly(
            "backend", [](const PyDeformer& d) { return backendName(d.deformer->backend()); },
            "'cpu' or 'gpu': the backend in use.")
        .def_property_readonly(
            "binding",
            [](PyDeformer& d) {
                // The GPU backend may read its binding back on first use.
                py::gil_scoped_release release;
                std::lock_guard<std::mutex> lock(d.mutex);
                return d.deformer->binding();
            },
            "The Binding in use.")
        .def_property_readonly("image_size",
                               [](const PyDeformer& d) { return sizeTuple(d.deformer->binding().imageSize); })
        .def_property_readonly(
            "vertex_count", [](const PyDeformer& d) { return d.deformer->binding().coefficientCount() - 4; },
            "user vertices: a pose has this many points (or 4 more).")
        .def("__repr__", [](const PyDeformer& d) {
            const Binding& b = d.deformer->binding();
            return "<multicage.Deformer " + std::string(backendName(d.deformer->backend())) + ", " +
                   std::to_string(b.imageSize.width) + "x" + std::to_string(b.imageSize.height) + ", " +
                   std::to_string(b.coefficientCount() - 4) + " vertices, grid step " +
                   std::to_string(b.gridStep) + ">";
        });

    m.def(
        "deform_image",
        [](const py::object& image, const Multicage& rest, const py::object& pose, const py::object& coordinates,
           int gridStep, const py::object& backend, const py::object& borderValue, bool halfFloat,
           bool gpuBinding) {
            const DeformParams params =
                deformParams(coordinates, gridStep, backend, borderValue, halfFloat, gpuBinding);
            py::object keep;
            const cv::Mat src = imageFromArray(image, "image", keep);
            const std::vector<cv::Point2f> p = pointsFromArray(pose, "pose");
            cv::Mat out;
            {
                py::gil_scoped_release release;
                deformImage(src, rest, p, out, params);
            }
            return arrayFromMat(out);
        },
        py::arg("image"), py::arg("rest"), py::arg("pose"), py::kw_only(), py::arg("coordinates") = "mvc",
        py::arg("grid_step") = 1, py::arg("backend") = "auto", py::arg("border_value") = py::none(),
        py::arg("half_float") = false, py::arg("gpu_binding") = false,
        "One shot: binds, deforms once, returns the image. Prefer a Deformer for several poses.");

    // --- coordinates, proposal, GPU ---
    m.def(
        "mean_value_coordinates",
        [](const py::object& polygon, const py::object& points, bool normalize) {
            const std::vector<cv::Point2f> poly = pointsFromArray(polygon, "polygon");
            const std::vector<cv::Point2f> pts = pointsFromArray(points, "points");
            cv::Mat weights;
            {
                py::gil_scoped_release release;
                meanValueCoordinates(poly, pts, weights, normalize);
            }
            return arrayFromMat(weights);
        },
        py::arg("polygon"), py::arg("points"), py::arg("normalize") = true,
        "Mean value coordinates (Hormann & Floater 2006) of N points for an n-gon: N x n float32. "
        "A point on a vertex or an edge gets the exact interpolating values.");

    m.def(
        "propose_multicage",
        [](const py::object& image, const py::kwargs& kwargs) {
            const ProposeParams params = proposeParams(kwargs, "propose_multicage");
            py::object keep;
            const cv::Mat src = imageFromArray(image, "image", keep, true);
            py::gil_scoped_release release;
            return proposeMulticage(src, params);
        },
        py::arg("image"),
        "Proposes a valid, oriented multicage enclosing the objects of an image. Keywords (all "
        "optional): method ('auto', 'threshold', 'adaptive', 'grabcut', 'saliency', 'spectral', "
        "'mask', 'labels' or a ProposeMethod), max_vertices, max_polygon_vertices, max_polygons, "
        "max_depth, margin, min_region_area, morphology_radius, working_size, rect (x, y, w, h), "
        "grabcut_iterations, grabcut_max_side.");
    m.def(
        "propose_segmentation",
        [](const py::object& image, const py::kwargs& kwargs) {
            const ProposeParams params = proposeParams(kwargs, "propose_segmentation");
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
        "The cleaned segmentation propose_multicage encloses: HxW uint8, 255 on object pixels. "
        "Same keywords as propose_multicage.");
    m.def(
        "protect_features",
        [](const py::object& image, const Multicage& cage, int polygon, const py::kwargs& kwargs) {
            const ProposeParams params = proposeParams(kwargs, "protect_features");
            py::object keep;
            const cv::Mat src = imageFromArray(image, "image", keep);
            checkIndex(polygon, cage.polygonCount(), "polygon");
            py::gil_scoped_release release;
            return protectFeatures(src, cage, polygon, params);
        },
        py::arg("image"), py::arg("multicage"), py::arg("polygon"),
        "A copy of the multicage with protective polygons added around the salient features inside "
        "polygon `polygon`. Same keywords as propose_multicage.");

    m.def(
        "gpu_available",
        [] {
            std::string description;
            bool ok;
            {
                py::gil_scoped_release release;
                ok = gpuAvailable(&description);
            }
            return py::make_tuple(ok, description);
        },
        "(available, description): whether a headless EGL/OpenGL context can be made here.");
}

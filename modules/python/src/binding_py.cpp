// multicage.Binding and bind(), and mean_value_coordinates(): the coordinates a multicage
// gives the points of an image.
#include <algorithm>

#include "common.hpp"

namespace multicage_py {
namespace {

using namespace cv::multicage;

// --- pickling (the format: common.hpp) ----------------------------------------------------

py::tuple bindingState(const Binding& b) {
    return py::make_tuple(kPickleVersion, sizeTuple(b.imageSize), b.gridStep, sizeTuple(b.gridSize),
                          b.coordinates, arrayFromMat(b.coefficients, false),
                          arrayFromPoints(b.restVertices), b.minConditioning,
                          py::make_tuple(b.worstNode.x, b.worstNode.y));
}

Binding bindingFromState(const py::tuple& state) {
    checkState(state, 9, "Binding");
    Binding b;
    b.imageSize = sizeFromObject(state[1], "Binding state: image size");
    b.gridStep = state[2].cast<int>();
    b.gridSize = sizeFromObject(state[3], "Binding state: grid size");
    b.coordinates = state[4].cast<int>();
    b.restVertices = pointsFromArray(state[6], "Binding state: rest vertices", -1, false);
    b.minConditioning = state[7].cast<double>();
    const auto worst = state[8].cast<std::pair<float, float>>();
    b.worstNode = cv::Point2f(worst.first, worst.second);
    // The coefficients are copied into a Mat of their own: the Binding outlives the array.
    auto coefficients =
        py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(state[5]);
    if (!coefficients || coefficients.ndim() != 2 ||
        coefficients.shape(0) != b.coefficientCount() ||
        coefficients.shape(1) != b.gridSize.area() || b.gridStep < 1 ||
        b.gridSize != gridSizeFor(b.imageSize, b.gridStep))
        throw py::value_error(
            "cannot unpickle a multicage.Binding: its coefficients, grid and vertices disagree");
    b.coefficients.create(static_cast<int>(coefficients.shape(0)),
                          static_cast<int>(coefficients.shape(1)), CV_32F);
    std::copy(coefficients.data(), coefficients.data() + coefficients.size(),
              b.coefficients.ptr<float>());
    return b;
}

}  // namespace

void defineBinding(py::module_& m) {
    py::class_<Binding>(m, "Binding",
                        "Every grid node bound to every vertex of a multicage (Algorithm 1).")
        .def_property_readonly("image_size",
                               [](const Binding& b) { return sizeTuple(b.imageSize); })
        .def_readonly("grid_step", &Binding::gridStep)
        .def_property_readonly(
            "grid_size", [](const Binding& b) { return sizeTuple(b.gridSize); },
            "(nodes in x, nodes in y)")
        .def_property_readonly("coordinates",
                               [](const Binding& b) { return coordinatesName(b.coordinates); })
        .def_property_readonly(
            "coefficients", [](const Binding& b) { return arrayFromMat(b.coefficients, false); },
            "coefficient_count x node_count float32 (read-only view): row j is coefficient j of "
            "every "
            "node, node (gx, gy) at column gy * grid_size[0] + gx.")
        .def_property_readonly(
            "rest_vertices",
            [](const Binding& b) {
                py::array a = arrayFromPoints(b.restVertices);
                a.attr("setflags")(py::arg("write") = false);
                return a;
            },
            "(coefficient_count x 2) float32, read-only: user vertices, then the 4 frame corners.")
        .def(py::pickle([](const Binding& b) { return bindingState(b); },
                        [](const py::tuple& state) { return bindingFromState(state); }))
        .def_readonly("min_conditioning", &Binding::minConditioning)
        .def_property_readonly(
            "worst_node",
            [](const Binding& b) { return py::make_tuple(b.worstNode.x, b.worstNode.y); })
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
            py::arg("pose"),
            "Deformed node positions for a pose, grid height x grid width x 2 float32.")
        .def(
            "transform_points",
            [](const Binding& b, const py::object& pose, const py::object& points) {
                const std::vector<cv::Point2f> p = pointsFromArray(pose, "pose");
                return transformPointsArray(
                    points, [&](const std::vector<cv::Point2f>& in, std::vector<cv::Point2f>& out) {
                        py::gil_scoped_release release;
                        transformPoints(b, p, in, out);
                    });
            },
            py::arg("pose"), py::arg("points"),
            "Where rest points (shape (..., 2)) land for a pose: as Deformer.transform_points, "
            "for any image deformed with this binding.")
        .def("__repr__", [](const Binding& b) {
            return "<multicage.Binding " + std::string(coordinatesName(b.coordinates)) + ", " +
                   std::to_string(b.gridSize.width) + "x" + std::to_string(b.gridSize.height) +
                   " nodes, " + std::to_string(b.coefficientCount()) + " coefficients>";
        });

    m.def(
        "bind",
        [](const py::object& cageObj, const py::object& coordinates, const py::object& gridStepObj,
           const py::object& onGpuObj) {
            const Multicage& cage = multicageArg(cageObj, "multicage");
            const int coords =
                coordinates.is_none() ? cage.coordinates() : parseCoordinates(coordinates);
            const int gridStep = intArg(gridStepObj, "grid_step");
            if (gridStep < 1)
                throw py::value_error("grid_step: must be >= 1, got " + std::to_string(gridStep));
            const bool onGpu = boolArg(onGpuObj, "on_gpu");
            if (onGpu && coords != MEAN_VALUE)
                throw py::value_error("on_gpu: the GPU binds mean value coordinates only");
            py::gil_scoped_release release;
            return onGpu ? bindOnGpu(cage, gridStep) : bind(cage, coords, gridStep);
        },
        py::arg("multicage"), py::arg("coordinates") = py::none(), py::arg("grid_step") = 1,
        py::arg("on_gpu") = false,
        "Binds every grid node to every vertex (Algorithm 1, or its local variant for "
        "'local_mvc'); a Binding can feed several Deformers "
        "of images of the multicage's size. coordinates None follows multicage.coordinates. The "
        "GIL "
        "is released while it runs.");
}

void defineCoordinates(py::module_& m) {
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
}

}  // namespace multicage_py

// multicage.Pose and multicage.Multicage.
#include "common.hpp"

namespace multicage_py {
namespace {

using namespace cv::multicage;

/** validate()/validateGeometry() as (ok, reason), or raising multicage.Error. */
py::tuple validation(bool ok, const std::string& why, bool raiseError) {
    if (!ok && raiseError) {
        PyErr_SetString(errorType, why.c_str());
        throw py::error_already_set();
    }
    return py::make_tuple(ok, why);
}

// --- pickling (the format: common.hpp) ----------------------------------------------------

py::tuple poseState(const Pose& p) {
    return py::make_tuple(p.name, arrayFromPoints(p.vertices), p.time);
}

Pose poseFromState(const py::handle& name, const py::handle& vertices, const py::handle& time) {
    Pose p;
    p.name = name.cast<std::string>();
    p.vertices = pointsFromArray(vertices, "Pose state: vertices");
    p.time = time.cast<double>();
    return p;
}

py::tuple multicageState(const Multicage& c) {
    py::list polygons, poses;
    for (int i = 0; i < c.polygonCount(); ++i) polygons.append(arrayFromPoints(c.polygon(i)));
    for (int i = 0; i < c.poseCount(); ++i) poses.append(poseState(c.pose(i)));
    return py::make_tuple(kPickleVersion, py::make_tuple(c.imageSize().width, c.imageSize().height),
                          polygons, poses, c.coordinates(), c.clipFrame());
}

Multicage multicageFromState(const py::tuple& state) {
    // Six fields; five before clip_frame was kept (a pickle of then loads with frame 0).
    checkState(state, state.size() == 5 ? 5 : 6, "Multicage");
    const auto size = state[1].cast<std::pair<int, int>>();
    Multicage c(cv::Size(size.first, size.second));
    for (const py::handle polygon : state[2])
        c.addPolygon(pointsFromArray(polygon, "Multicage state: polygon", -1, false));
    for (const py::handle pose : state[3]) {
        const py::tuple t = pose.cast<py::tuple>();
        const Pose p = poseFromState(t[0], t[1], t[2]);
        c.addPose(p.name, p.vertices, p.time);
    }
    c.setCoordinates(state[4].cast<int>());
    if (state.size() == 6) c.setClipFrame(state[5].cast<int>());
    return c;
}

// --- Multicage, in parts (one class_ chain would be one very long function) ----------------

const char* kMulticageDoc = R"doc(Disjoint simple polygons over an image, plus the image frame.

Multicage(size=None): size is (width, height), as cv2 sizes are (not image.shape);
Multicage.for_image(image) takes it from an array. Points are (x, y) with pixel (x, y) at its
centre; the frame corners are (-0.5, -0.5) and (W-0.5, H-0.5). Vertices are numbered polygon
by polygon, then the 4 frame corners.)doc";

using MulticageClass = py::class_<Multicage>;

/** The polygons: adding, changing and reading them. */
void defineMulticagePolygons(MulticageClass& cls) {
    cls.def(
           "add_polygon",
           [](Multicage& c, const py::object& points) {
               return c.addPolygon(pointsFromArray(points, "points"));
           },
           py::arg("points"),
           "Adds a polygon (Nx2 points, N >= 3) and returns its index. Geometry is checked by "
           "validate().")
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
                 for (int i = 0; i < c.polygonCount(); ++i)
                     out.append(arrayFromPoints(c.polygon(i)));
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
            py::arg("i"), "> 0: clockwise on screen.");
}

/** The vertices as arrays, and validation. */
void defineMulticageVertices(MulticageClass& cls) {
    cls.def(
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
            py::arg("raise_error") = false, "As validate(), ignoring the orientation rule.");
}

void defineMulticagePoses(MulticageClass& cls) {
    cls.def(
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
                        for (int j = 0; j < c.poseCount(); ++j)
                            names += (j ? ", " : "") + c.pose(j).name;
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
        .def("find_pose", &Multicage::findPose, py::arg("name"),
             "Index of the pose called name, or -1.")
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
            py::arg("i"));
}

/** Scaling, files, drawing, the coordinates, and the Python protocols (pickle, copy, repr). */
void defineMulticageUses(MulticageClass& cls) {
    cls.def(
           "scaled",
           [](const Multicage& c, const py::object& s) {
               return c.scaled(sizeFromObject(s, "size"));
           },
           py::arg("size"), "The same multicage for an image of size (width, height).")
        .def_static("load", &Multicage::load, py::arg("path"), "Loads a YAML or JSON cage file.")
        .def("save", &Multicage::save, py::arg("path"),
             "Saves a YAML or JSON cage file (atomically).")
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
        .def_property(
            "coordinates", [](const Multicage& c) { return coordinatesName(c.coordinates()); },
            [](Multicage& c, const py::object& v) { c.setCoordinates(parseCoordinates(v)); },
            "'mvc' or 'harmonic': the coordinates this multicage is meant to be bound with (a cage "
            "file's "
            "`coordinates:`). Deformer, deform_image and bind follow it unless given coordinates=.")
        .def_property("clip_frame", &Multicage::clipFrame, &Multicage::setClipFrame,
                      "The frame of a clip the polygons and poses were drawn on (0: the first; a "
                      "cage file's `clip_frame:`).")
        .def(py::pickle([](const Multicage& c) { return multicageState(c); },
                        [](const py::tuple& state) { return multicageFromState(state); }))
        .def("__copy__", [](const Multicage& c) { return Multicage(c); })
        .def(
            "__deepcopy__", [](const Multicage& c, const py::object&) { return Multicage(c); },
            py::arg("memo"))
        .def("__repr__", [](const Multicage& c) {
            return "<multicage.Multicage " + std::to_string(c.imageSize().width) + "x" +
                   std::to_string(c.imageSize().height) + ", " + std::to_string(c.polygonCount()) +
                   " polygons, " + std::to_string(c.vertexCount()) + " vertices, " +
                   std::to_string(c.poseCount()) + " poses>";
        });
}

}  // namespace

void definePose(py::module_& m) {
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
            "vertices",
            [](const Pose& p) {
                // Read-only: a copy that silently ignored `pose.vertices[0] = ...` would lose the
                // edit; writing raises instead ("assignment destination is read-only").
                py::array a = arrayFromPoints(p.vertices);
                a.attr("setflags")(py::arg("write") = false);
                return a;
            },
            [](Pose& p, const py::object& v) { p.vertices = pointsFromArray(v, "vertices"); },
            "Nx2 float32 array, read-only: to change it, assign a whole array "
            "(v = pose.vertices.copy(); v[0] = ...; pose.vertices = v).")
        .def(py::pickle(
            [](const Pose& p) {
                return py::make_tuple(kPickleVersion, p.name, arrayFromPoints(p.vertices), p.time);
            },
            [](const py::tuple& state) {
                checkState(state, 4, "Pose");
                return poseFromState(state[1], state[2], state[3]);
            }))
        .def("__eq__",
             [](const Pose& a, const py::object& other) {
                 if (!py::isinstance<Pose>(other)) return false;
                 const Pose& b = other.cast<const Pose&>();
                 return a.name == b.name && a.time == b.time && a.vertices == b.vertices;
             })
        .def("__repr__", [](const Pose& p) {
            return "<multicage.Pose '" + p.name +
                   "' time=" + py::repr(py::float_(p.time)).cast<std::string>() + ", " +
                   std::to_string(p.vertices.size()) + " vertices>";
        });
}

void defineMulticage(py::module_& m) {
    MulticageClass cls(m, "Multicage", kMulticageDoc);
    cls.def(py::init([](const py::object& size) {
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
            [](Multicage& c, const py::object& s) {
                c.setImageSize(sizeFromObject(s, "image_size"));
            },
            "(width, height)")
        .def_property_readonly("polygon_count", &Multicage::polygonCount)
        .def_property_readonly("vertex_count", &Multicage::vertexCount,
                               "user vertices (frame excluded)")
        .def_property_readonly("pose_count", &Multicage::poseCount);
    defineMulticagePolygons(cls);
    defineMulticageVertices(cls);
    defineMulticagePoses(cls);
    defineMulticageUses(cls);
}

}  // namespace multicage_py

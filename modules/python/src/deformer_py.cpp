// multicage.Deformer and deform_image().
#include <algorithm>
#include <memory>
#include <mutex>

#include "common.hpp"

namespace multicage_py {
namespace {

using namespace cv::multicage;

/** A pose given in the coordinates of a multicage drawn for `from`, in those of an image of
size `to`. The user vertices go through Multicage::scaled itself, so that Python and the CLI
(which scales the cage file's poses with it) agree bit for bit. Frame corners, when the pose
has them (vertexCount + 4 points), are mapped in double: in float the rest frame would land a
rounding error off the new frame and move the border. */
std::vector<cv::Point2f> scalePose(std::vector<cv::Point2f> pose, int vertexCount, cv::Size from,
                                   cv::Size to) {
    if (from == to || pose.empty()) return pose;
    const int users = std::min<int>(vertexCount, static_cast<int>(pose.size()));
    if (users > 0) {
        Multicage m(from);
        m.addPolygon(std::vector<cv::Point2f>(pose.begin(), pose.begin() + users));
        const std::vector<cv::Point2f> scaled = m.scaled(to).polygon(0);
        std::copy(scaled.begin(), scaled.end(), pose.begin());
    }
    const double sx = static_cast<double>(to.width) / from.width,
                 sy = static_cast<double>(to.height) / from.height;
    for (size_t i = static_cast<size_t>(users); i < pose.size(); ++i)
        pose[i] = cv::Point2f(static_cast<float>((pose[i].x + 0.5) * sx - 0.5),
                              static_cast<float>((pose[i].y + 0.5) * sy - 0.5));
    return pose;
}

/** The rest multicage for an image: the multicage itself, or scaled to the image as
`multicage deform` scales a cage file (edit small, render big). */
Multicage restForImage(const Multicage& cage, cv::Size imageSize) {
    if (cage.imageSize().empty())
        throw py::value_error(
            "rest: the multicage has no image size; make it with Multicage((width, height)) "
            "or Multicage.for_image(image)");
    return cage.imageSize() == imageSize ? cage : cage.scaled(imageSize);
}

/** A Deformer behind a mutex: the GIL is released while it works, and one instance holds
mutable state (CPU positions, a GL context), so Python threads sharing it take turns.
It also keeps what re-creates it in another process (pickling): a read-only copy of the
image and the parameters asked for; the binding comes from the deformer itself. */
struct PyDeformer {
    cv::Ptr<Deformer> deformer;
    std::mutex mutex;
    py::array image;      // read-only copy of the input image
    DeformParams params;  // as asked for: backend may be BACKEND_AUTO
    cv::Size cageSize;    // the size the rest multicage was drawn for: poses are in its coordinates
    cv::Size imageSize;
    int vertexCount =
        0;  // user vertices (kept here: a GPU binding is read back only when asked for)

    /** The binding, under the mutex and without the GIL: a GPU deformer reads it back from its
    texture on first use, in its own GL context. */
    const Binding& binding() {
        py::gil_scoped_release release;
        std::lock_guard<std::mutex> lock(mutex);
        return deformer->binding();
    }

    std::vector<cv::Point2f> pose(const py::handle& obj) const {
        return scalePose(pointsFromArray(obj, "pose"), vertexCount, cageSize, imageSize);
    }
};

/** A read-only C-order copy of an image array (the Deformer's own), and its Mat. */
py::array ownImage(const py::handle& imageObj, cv::Mat& mat) {
    py::object keep;
    imageFromArray(imageObj, "image", keep);  // the checks, with their messages
    py::array copy = py::module_::import("numpy").attr("array")(imageObj, py::arg("order") = "C");
    copy.attr("setflags")(py::arg("write") = false);
    mat = imageFromArray(copy, "image", keep);
    return copy;
}

std::unique_ptr<PyDeformer> makeDeformer(const py::handle& imageObj, const py::handle& rest,
                                         const py::object& coordinates, const py::object& gridStep,
                                         const py::object& backend, const py::object& borderValue,
                                         const py::object& halfFloat, const py::object& gpuBinding,
                                         const py::object& memoryBudget,
                                         const py::object& mapStep) {
    auto d = std::make_unique<PyDeformer>();
    cv::Mat image;
    d->image = ownImage(imageObj, image);
    if (py::isinstance<Multicage>(rest)) {
        const Multicage& cage = rest.cast<const Multicage&>();
        d->params = deformParams(coordinates, gridStep, backend, borderValue, halfFloat, gpuBinding,
                                 memoryBudget, mapStep, cage.coordinates());
        const Multicage scaled = restForImage(cage, image.size());
        d->cageSize = cage.imageSize();
        d->vertexCount = cage.vertexCount();
        d->imageSize = image.size();
        py::gil_scoped_release release;
        d->deformer = Deformer::create(image, scaled, d->params);
    } else if (py::isinstance<Binding>(rest)) {
        const Binding& binding = rest.cast<const Binding&>();
        d->params = deformParams(coordinates, gridStep, backend, borderValue, halfFloat, gpuBinding,
                                 memoryBudget, mapStep, binding.coordinates);
        if (d->params.coordinates != binding.coordinates)
            throw py::value_error(std::string("coordinates: the binding holds ") +
                                  coordinatesName(binding.coordinates) + " coordinates, not " +
                                  coordinatesName(d->params.coordinates) +
                                  "; bind again with multicage.bind(cage, coordinates=...)");
        if (binding.imageSize != image.size())
            throw py::value_error("image: the image is " + sizeString(image.size()) +
                                  " but the binding was made for " + sizeString(binding.imageSize) +
                                  "; pass the Multicage instead (it is scaled to "
                                  "the image) or bind cage.scaled((" +
                                  std::to_string(image.cols) + ", " + std::to_string(image.rows) +
                                  "))");
        d->cageSize = binding.imageSize;
        d->vertexCount = binding.coefficientCount() - 4;
        d->imageSize = image.size();
        py::gil_scoped_release release;
        d->deformer = Deformer::create(image, binding, d->params);
    } else {
        throw py::type_error("rest: expected a multicage.Multicage or a multicage.Binding, got " +
                             shortValue(rest));
    }
    return d;
}

/** An image argument checked against the deformer's image: same shape and dtype, else a
ValueError naming both. */
cv::Mat sameImage(PyDeformer& d, const py::handle& obj, const char* what, py::object& keep) {
    const cv::Mat m = imageFromArray(obj, what, keep);
    py::object mineKeep;
    const cv::Mat mine = imageFromArray(d.image, "image", mineKeep);
    if (m.size() != mine.size() || m.type() != mine.type())
        throw py::value_error(std::string(what) + ": " + matDescription(m) +
                              ", but the deformer was made for " + matDescription(mine) +
                              "; make a Deformer for it (or bind once per size)");
    return m;
}

/** An output map given by the caller: a writeable C-contiguous HxW float32 array of the
deformer's image size, as a Mat over its memory. */
cv::Mat mapOut(const py::object& obj, const char* what, cv::Size size) {
    if (!py::isinstance<py::array>(obj))
        throw py::type_error(std::string(what) + ": expected a numpy array, got " +
                             shortValue(obj));
    py::array a = py::reinterpret_borrow<py::array>(obj);
    const bool ok = a.ndim() == 2 && a.dtype().is(py::dtype::of<float>()) &&
                    (a.flags() & py::array::c_style) && a.writeable() &&
                    a.shape(0) == size.height && a.shape(1) == size.width;
    if (!ok)
        throw py::value_error(std::string(what) + ": expected a writeable C-contiguous " +
                              std::to_string(size.height) + "x" + std::to_string(size.width) +
                              " float32 array, got " + shortValue(obj));
    return cv::Mat(size, CV_32F, a.mutable_data());
}

/** Deformer.deform_many: the inputs converted under the GIL, the batch run without it. */
py::list deformMany(PyDeformer& d, const py::object& posesObj, const py::object& imagesObj) {
    if (py::isinstance<py::str>(posesObj) || !py::hasattr(posesObj, "__len__"))
        throw py::type_error("poses: expected a sequence of poses, got " + shortValue(posesObj));
    const py::sequence poses = py::reinterpret_borrow<py::sequence>(posesObj);
    std::vector<std::vector<cv::Point2f>> p;
    for (size_t k = 0; k < poses.size(); ++k) {
        const std::string what = "poses[" + std::to_string(k) + "]";
        p.push_back(scalePose(pointsFromArray(poses[k], what.c_str()), d.vertexCount, d.cageSize,
                              d.imageSize));
    }
    std::vector<cv::Mat> images;
    std::vector<py::object> keep;
    if (!imagesObj.is_none()) {
        if (py::isinstance<py::str>(imagesObj) || !py::hasattr(imagesObj, "__len__"))
            throw py::type_error("images: expected None or a sequence of images, got " +
                                 shortValue(imagesObj));
        const py::sequence seq = py::reinterpret_borrow<py::sequence>(imagesObj);
        if (seq.size() != poses.size())
            throw py::value_error("images: " + std::to_string(seq.size()) + " images for " +
                                  std::to_string(poses.size()) +
                                  " poses; give one image per pose, or None");
        keep.resize(seq.size());
        for (size_t k = 0; k < seq.size(); ++k) {
            const std::string what = "images[" + std::to_string(k) + "]";
            images.push_back(sameImage(d, seq[k], what.c_str(), keep[k]));
        }
    }
    std::vector<cv::Mat> out;
    {
        py::gil_scoped_release release;
        std::lock_guard<std::mutex> lock(d.mutex);
        if (images.empty())
            d.deformer->deformBatch(p, out);
        else
            d.deformer->deformBatch(p, out, images);
    }
    py::list result;
    for (const cv::Mat& m : out) result.append(arrayFromMat(m));
    return result;
}

// --- pickling (the format: common.hpp) ----------------------------------------------------

py::tuple deformerState(PyDeformer& d) {
    Binding binding = d.binding();
    const DeformParams& p = d.params;
    py::dict params;
    params["coordinates"] = coordinatesName(p.coordinates);
    params["grid_step"] = p.gridStep;
    params["backend"] = backendName(p.backend);
    params["border_value"] =
        py::make_tuple(p.borderValue[0], p.borderValue[1], p.borderValue[2], p.borderValue[3]);
    params["half_float"] = p.halfFloat;
    params["gpu_binding"] =
        p.gpuBinding < 0 ? py::object(py::none()) : py::object(py::bool_(p.gpuBinding > 0));
    params["memory_budget"] = p.memoryBudget;
    params["map_step"] = p.mapStep;
    return py::make_tuple(kPickleVersion, d.image, py::cast(std::move(binding)), params,
                          sizeTuple(d.cageSize));
}

std::unique_ptr<PyDeformer> deformerFromState(const py::tuple& state) {
    checkState(state, 5, "Deformer");
    const py::dict params = state[3].cast<py::dict>();
    const py::object binding = state[2];
    std::unique_ptr<PyDeformer> d;
    try {
        d = makeDeformer(state[1], binding, params["coordinates"], params["grid_step"],
                         params["backend"], params["border_value"], params["half_float"],
                         params["gpu_binding"], params["memory_budget"],
                         // (pickles of before map_step: 1, as they deformed)
                         params.contains("map_step") ? params["map_step"] : py::int_(1));
    } catch (const cv::Exception& e) {
        // Say what failed and why: the usual case is a GPU deformer sent to a process
        // or machine without a GPU.
        raise(errorType, "cannot re-create the pickled multicage.Deformer (backend='" +
                             params["backend"].cast<std::string>() + "') here: " + e.err +
                             (params["backend"].cast<std::string>() == "gpu"
                                  ? "; make deformers that travel with backend='auto' or 'cpu'"
                                  : ""));
    }
    d->cageSize = sizeFromObject(state[4], "Deformer state: cage size");
    return d;
}

std::string deformerRepr(const py::handle& self) {
    // A failed __init__ leaves an instance that tracebacks (pytest's among them) still
    // show: its repr must not touch the PyDeformer it never got.
    auto* inst = reinterpret_cast<py::detail::instance*>(self.ptr());
    if (!inst->get_value_and_holder(py::detail::get_type_info(typeid(PyDeformer)))
             .holder_constructed())
        return std::string("<multicage.Deformer (not initialised)>");
    PyDeformer& d = self.cast<PyDeformer&>();
    const Binding& b = d.binding();
    return "<multicage.Deformer " + std::string(backendName(d.deformer->backend())) + ", " +
           std::to_string(b.imageSize.width) + "x" + std::to_string(b.imageSize.height) + ", " +
           std::to_string(b.coefficientCount() - 4) + " vertices, grid step " +
           std::to_string(b.gridStep) + ">";
}

// --- the Python class and deform_image ----------------------------------------------------

const char* kDeformerDoc =
    R"doc(Binds an image to a multicage once, then deforms it for any number of poses.

Deformer(image, rest, *, coordinates=None, grid_step=1, backend='auto', border_value=None,
         half_float=False, gpu_binding=None, memory_budget=None, map_step=1)

image         numpy array as cv2 gives it: uint8, uint16 or float32; HxW, HxWx3 or HxWx4
rest          a Multicage, or a Binding made by multicage.bind() for an image of this size.
              A Multicage drawn for another image size is scaled to this image, as
              `multicage deform` scales a cage file (edit small, render big); poses are then
              given in the multicage's own coordinates and scaled the same way.
coordinates   'mvc' (mean value) or 'harmonic', or a CoordinateType; None (the default)
              follows the multicage's choice (Multicage.coordinates, a cage file's
              `coordinates:`), as `multicage deform` does without --coords    [--coords]
grid_step     a mesh node every grid_step pixels (1 is the paper's method)   [--grid-step]
backend       'auto', 'cpu' or 'gpu', or a Backend. 'auto' takes the GPU when a hardware
              OpenGL context can be made, else the CPU (multicage.auto_backend() says which);
              deformer.backend says which one this deformer uses        [--backend]
border_value  output pixels no deformed triangle covers: a number (every channel) or up to 4
                                                                             [--border]
half_float    GPU: store coefficients as 16-bit floats
gpu_binding   GPU: compute the mean value binding in a compute shader (None: where the GPU
              is a hardware one; True: always with the GPU backend; False: never)
memory_budget most bytes the coefficients may take (None: the library's 1 GiB; 0: no limit);
              above it the grid step is raised (deformer.grid_step says the step used)
map_step      CPU: 1 finds the inverse maps at every pixel; from 2 up, where a pose folds
              nothing, they are found on a lattice at most map_step pixels apart and
              interpolated (about a grid step's own error, a fraction of the time: for
              augmentation; MulticageWarp uses its grid step)                  [--map-step]
[--name]: the `multicage deform` option that sets the same thing.

A pose is an Nx2 array of vertex_count points (or vertex_count + 4 with the frame corners
last). The GIL is released while binding and deforming.

Augmentation: deform(pose, image=other) deforms another image of the same shape and dtype with
this binding, set_image(other) replaces the image, deform_many(poses, images=None) deforms a
batch on all cores, transform_points(pose, points) moves keypoints, boxes and polygons with the
image; multicage.random_pose(cage, amplitude, seed) draws valid random poses.

A Deformer pickles (pickle, multiprocessing with 'spawn', Dask) as its image, its binding and
these parameters, and is re-created from them without binding again; it keeps a read-only
copy of the image for that. Unpickling raises multicage.Error where the deformer cannot be
made (backend='gpu' in a process without a GPU).)doc";

using DeformerClass = py::class_<PyDeformer>;

/** The deformed image: of one pose, of many, and of another image on the same binding. */
void defineDeformerImageCalls(DeformerClass& cls) {
    cls.def(
           "deform",
           [](PyDeformer& d, const py::object& pose, const py::object& image) {
               const std::vector<cv::Point2f> p = d.pose(pose);
               cv::Mat out;
               if (image.is_none()) {
                   py::gil_scoped_release release;
                   std::lock_guard<std::mutex> lock(d.mutex);
                   d.deformer->deform(p, out);
                   return arrayFromMat(out);
               }
               py::object keep;
               const cv::Mat other = sameImage(d, image, "image", keep);
               std::vector<cv::Mat> outs;
               {
                   py::gil_scoped_release release;
                   std::lock_guard<std::mutex> lock(d.mutex);
                   d.deformer->deformBatch(std::vector<std::vector<cv::Point2f>>{p}, outs,
                                           std::vector<cv::Mat>{other});
               }
               return arrayFromMat(outs[0]);
           },
           py::arg("pose"), py::arg("image") = py::none(),
           "The image deformed to pose: same shape and dtype as the input. image: another image "
           "of the same shape and dtype to deform instead, with this deformer's binding (no "
           "rebinding; the deformer keeps its own image).")
        .def(
            "deform_many",
            [](PyDeformer& d, const py::object& poses, const py::object& images) {
                return deformMany(d, poses, images);
            },
            py::arg("poses"), py::arg("images") = py::none(),
            "Deforms a batch in one call, using all cores with the GIL released: a list of "
            "images[k] (or this deformer's image when images is None) deformed to poses[k]. "
            "poses: a sequence of poses (or a K x N x 2 array); images: None or a sequence of as "
            "many images, each of this deformer's shape and dtype. The same pixels as deform() "
            "one at a time. CPU backend: the items run in parallel, each worker with its own mesh "
            "and maps on the shared binding; GPU: one after another.")
        .def(
            "set_image",
            [](PyDeformer& d, const py::object& image) {
                py::object keep;
                const cv::Mat other = sameImage(d, image, "image", keep);
                cv::Mat mine;
                py::array copy = ownImage(image, mine);
                {
                    py::gil_scoped_release release;
                    std::lock_guard<std::mutex> lock(d.mutex);
                    d.deformer->setImage(other);
                }
                d.image = copy;  // what a pickle of the deformer carries from now on
            },
            py::arg("image"),
            "Replaces the image this deformer deforms by another of the same shape and dtype, "
            "keeping the binding (no rebinding).");
}

/** What a pose does to points and pixels: moved points, the remap maps, the fold-over count. */
void defineDeformerPoseCalls(DeformerClass& cls) {
    cls.def(
           "transform_points",
           [](PyDeformer& d, const py::object& pose, const py::object& points) {
               const std::vector<cv::Point2f> p = d.pose(pose);
               return transformPointsArray(
                   points, [&](const std::vector<cv::Point2f>& in, std::vector<cv::Point2f>& out) {
                       py::gil_scoped_release release;
                       std::lock_guard<std::mutex> lock(d.mutex);
                       d.deformer->transformPoints(p, in, out);
                   });
           },
           py::arg("pose"), py::arg("points"),
           "Where rest points (keypoints, polygon annotations, box corners: an array of shape "
           "(..., 2) of (x, y) in the image's pixels) land in the image deformed to pose; the "
           "same "
           "shape, float32. A feature of the image at a point lands where the point lands (the "
           "image's own mesh, at any grid step); cage vertices land exactly on the pose. Points "
           "outside the image follow the frame (with the frame fixed, they stay).")
        .def(
            "compute_maps",
            [](PyDeformer& d, const py::object& pose, const py::object& mapxObj,
               const py::object& mapyObj) {
                const std::vector<cv::Point2f> p = d.pose(pose);
                cv::Mat mapx, mapy;
                if (mapxObj.is_none() != mapyObj.is_none())
                    throw py::value_error("mapx, mapy: give both output maps, or neither");
                if (!mapxObj.is_none()) {
                    // Written in place: fresh maps every call cost page faults (two maps of a
                    // 512x512 image are 512 fresh 4 KiB pages) that can exceed the raster.
                    mapx = mapOut(mapxObj, "mapx", d.imageSize);
                    mapy = mapOut(mapyObj, "mapy", d.imageSize);
                    if (mapx.data == mapy.data)
                        throw py::value_error("mapx, mapy: the same array given twice");
                }
                {
                    py::gil_scoped_release release;
                    std::lock_guard<std::mutex> lock(d.mutex);
                    d.deformer->computeMaps(p, mapx, mapy);
                }
                if (!mapxObj.is_none()) return py::make_tuple(mapxObj, mapyObj);
                return py::make_tuple(arrayFromMat(mapx), arrayFromMat(mapy));
            },
            py::arg("pose"), py::arg("mapx") = py::none(), py::arg("mapy") = py::none(),
            "Inverse maps (mapx, mapy) for cv2.remap, HxW float32: for each output pixel its "
            "source position; uncovered pixels get -1e4. Remap masks and labels with "
            "cv2.INTER_NEAREST. mapx, mapy: C-contiguous writeable HxW float32 arrays to write "
            "into (returned), reused between calls to save fresh memory's page faults.")
        .def(
            "folded_triangles",
            [](PyDeformer& d, const py::object& pose) {
                const std::vector<cv::Point2f> p = d.pose(pose);
                py::gil_scoped_release release;
                std::lock_guard<std::mutex> lock(d.mutex);
                return d.deformer->foldedTriangles(p);
            },
            py::arg("pose"), "Number of mesh triangles the pose turns over (0: no fold-over).");
}

void defineDeformerProperties(DeformerClass& cls) {
    cls.def_property_readonly(
           "backend", [](const PyDeformer& d) { return backendName(d.deformer->backend()); },
           "'cpu' or 'gpu': the backend in use.")
        .def_property_readonly(
            "binding", [](PyDeformer& d) { return d.binding(); },
            "The Binding in use (for the image's size: a scaled multicage's).")
        .def_property_readonly("image_size",
                               [](const PyDeformer& d) { return sizeTuple(d.imageSize); })
        .def_property_readonly(
            "cage_size", [](const PyDeformer& d) { return sizeTuple(d.cageSize); },
            "(width, height) the rest multicage was drawn for: poses are in its coordinates (equal "
            "to "
            "image_size unless the multicage was scaled to the image).")
        .def_property_readonly(
            "grid_step", [](PyDeformer& d) { return d.binding().gridStep; },
            "The grid step in use (raised above the one asked for when memory_budget requires it).")
        .def_property_readonly(
            "coordinates", [](PyDeformer& d) { return coordinatesName(d.binding().coordinates); },
            "'mvc' or 'harmonic': the coordinates in use.")
        .def_property_readonly(
            "vertex_count", [](const PyDeformer& d) { return d.vertexCount; },
            "user vertices: a pose has this many points (or 4 more).");
}

void defineDeformImage(py::module_& m) {
    m.def(
        "deform_image",
        [](const py::object& image, const py::object& restObj, const py::object& pose,
           const py::object& coordinates, const py::object& gridStep, const py::object& backend,
           const py::object& borderValue, const py::object& halfFloat, const py::object& gpuBinding,
           const py::object& memoryBudget, const py::object& mapStep) {
            const Multicage& rest = multicageArg(restObj, "rest");
            const DeformParams params =
                deformParams(coordinates, gridStep, backend, borderValue, halfFloat, gpuBinding,
                             memoryBudget, mapStep, rest.coordinates());
            py::object keep;
            const cv::Mat src = imageFromArray(image, "image", keep);
            const Multicage scaled = restForImage(rest, src.size());
            const std::vector<cv::Point2f> p = scalePose(
                pointsFromArray(pose, "pose"), rest.vertexCount(), rest.imageSize(), src.size());
            cv::Mat out;
            {
                py::gil_scoped_release release;
                deformImage(src, scaled, p, out, params);
            }
            return arrayFromMat(out);
        },
        py::arg("image"), py::arg("rest"), py::arg("pose"), py::kw_only(),
        py::arg("coordinates") = py::none(), py::arg("grid_step") = 1, py::arg("backend") = "auto",
        py::arg("border_value") = py::none(), py::arg("half_float") = false,
        py::arg("gpu_binding") = py::none(), py::arg("memory_budget") = py::none(),
        py::arg("map_step") = 1,
        "One shot: binds, deforms once, returns the image. Same keywords and scaling as Deformer; "
        "prefer a Deformer for several poses.");
}

}  // namespace

void defineDeformer(py::module_& m) {
    // Every keyword is taken as an object and converted here, so that a wrong type gets a
    // TypeError naming the keyword (pybind11's own message would print every argument,
    // the whole image included).
    auto create = [](const py::object& image, const py::object& rest, const py::object& coordinates,
                     const py::object& gridStep, const py::object& backend,
                     const py::object& borderValue, const py::object& halfFloat,
                     const py::object& gpuBinding, const py::object& memoryBudget,
                     const py::object& mapStep) {
        return makeDeformer(image, rest, coordinates, gridStep, backend, borderValue, halfFloat,
                            gpuBinding, memoryBudget, mapStep);
    };
    DeformerClass cls(m, "Deformer", kDeformerDoc);
    cls.def(py::init(create), py::arg("image"), py::arg("rest"), py::kw_only(),
            py::arg("coordinates") = py::none(), py::arg("grid_step") = 1,
            py::arg("backend") = "auto", py::arg("border_value") = py::none(),
            py::arg("half_float") = false, py::arg("gpu_binding") = py::none(),
            py::arg("memory_budget") = py::none(), py::arg("map_step") = 1)
        .def_static("create", create, py::arg("image"), py::arg("rest"), py::kw_only(),
                    py::arg("coordinates") = py::none(), py::arg("grid_step") = 1,
                    py::arg("backend") = "auto", py::arg("border_value") = py::none(),
                    py::arg("half_float") = false, py::arg("gpu_binding") = py::none(),
                    py::arg("memory_budget") = py::none(), py::arg("map_step") = 1,
                    "Same as Deformer(...).");
    defineDeformerImageCalls(cls);
    defineDeformerPoseCalls(cls);
    defineDeformerProperties(cls);
    cls.def(py::pickle([](PyDeformer& d) { return deformerState(d); },
                       [](const py::tuple& state) { return deformerFromState(state); }))
        .def("__repr__", [](const py::handle& self) { return deformerRepr(self); });

    defineDeformImage(m);
}

}  // namespace multicage_py

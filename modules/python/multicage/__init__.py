"""multicage: multicage image deformation for OpenCV pipelines in Python.

Bindings over the C++ library (paper "Multicage Image Deformation On GPU"). Conventions are
cv2's: images are numpy arrays as cv2.imread gives them (uint8, uint16 or float32; HxW,
HxWx3 BGR or HxWx4 BGRA), points are Nx2 arrays of (x, y) with pixel (x, y) at its centre,
sizes are (width, height).

    import cv2, multicage
    image = multicage.imread("samples/data/butterfly.jpg")  # paths from the source folder
    cage = multicage.propose_multicage(image)            # or Multicage.load("samples/butterfly.yml")
    deformer = multicage.Deformer(image, cage, backend="cpu")
    pose = cage.rest_pose(); pose[:, 1] -= 10            # move every vertex up 10 px
    out = deformer.deform(pose)                          # same shape and dtype as image
    mapx, mapy = deformer.compute_maps(pose)             # for cv2.remap of masks, labels
    mask = multicage.propose_segmentation(image)         # or any HxW mask of the image's size
    mask_out = cv2.remap(mask, mapx, mapy, cv2.INTER_NEAREST)

A multicage made for another image size is scaled to the image (poses too), as the CLI does;
Deformer follows the multicage's coordinates (a cage file's `coordinates:`) unless given
coordinates=; propose_multicage takes the CLI's options as keywords and raises
NoObjectFoundError where the CLI says "no object found". By default (segmenter='auto') a
proposal finds the subject of a photo with the learned subject model when one is installed
(docs/models.md), else with the classic cues; segmenter_model_file() says which runs and why,
subject_map(image) gives the model's map. gpu_available() says whether
backend='gpu' works, auto_backend() what backend='auto' takes. Multicage, Pose, Binding and
Deformer pickle (multiprocessing, Dask). For augmentation: random_pose(cage, amplitude, seed)
draws valid random poses, Deformer.transform_points moves keypoints with the image, and
Deformer.deform(pose, image=...) and Deformer.deform_many deform other images of the same size
with one binding. MulticageWarp (multicage.transforms) does all of it as one transform,
called as albumentations transforms are: warp(image=, mask=, masks=, keypoints=, bboxes=)
returns the same keys moved by one deformation, seeded per sample and replayable;
TorchMulticageWarp is the same inside a torchvision Compose on CHW tensors.

VideoReframer(size) reframes a clip to another size or aspect ratio frame by frame, its
subjects tracked and kept in shape: push(frame), pop(), finish(), or reframe(frames) as a
generator of output frames (numpy frames from cv2.VideoCapture or any reader).

imread(path) reads an image as the CLI does: a truncated JPEG or PNG, an empty file or one
that is not an image raises multicage.Error naming the file (cv2.imread decodes a cut file
with a warning, or returns None).

Errors reported by the library raise multicage.Error (a ValueError) with the library's
message; wrong array types raise TypeError, wrong shapes ValueError. The GIL is released
while the library binds, deforms, proposes or computes coordinates.
"""


import functools as _functools

from . import _multicage


def _short(value):
    """An argument as a message shows it: arrays by shape and dtype, never their pixels."""
    shape, dtype = getattr(value, "shape", None), getattr(value, "dtype", None)
    if shape is not None and dtype is not None:
        return f"{type(value).__module__}.{type(value).__name__}(shape={tuple(shape)}, dtype={dtype})"
    try:
        text = repr(value)
    except Exception:  # an object whose repr fails still gets a message
        text = f"<{type(value).__module__}.{type(value).__name__}>"
    return text if len(text) <= 80 else text[:77] + "..."


def _rewrite(message, args, kwargs):
    """pybind11's 'incompatible function arguments' message with the arguments shown short.
    pybind11 prints the repr of every argument, which for an image is hundreds of lines."""
    head = message.split("\nInvoked with:", 1)[0].rstrip().replace("multicage._multicage.", "multicage.")
    shown = [_short(a) for a in args] + [f"{k}={_short(v)}" for k, v in kwargs.items()]
    text = f"{head}\n\nInvoked with: {', '.join(shown)}"
    if ", *," in head or "(*, " in head or "**kwargs" in head:
        text += "\n(the parameters after '*' and the **kwargs options are keyword-only: pass them as name=value)"
    return text


def _wrap(function, constructor=False):
    @_functools.wraps(function)
    def call(*args, **kwargs):
        try:
            return function(*args, **kwargs)
        except TypeError as e:
            if "Invoked with:" not in str(e):
                raise
            # pybind11 leaves the (not yet constructed) self out of a constructor's arguments
            raise TypeError(_rewrite(str(e), args[1:] if constructor else args, kwargs)) from None
    return call


def _wrap_module():
    # Every function and method of the extension, so that a misuse anywhere gets a short
    # message; properties convert their values themselves, pickling is left alone.
    for name in dir(_multicage):
        obj = getattr(_multicage, name)
        if type(obj).__name__ == "builtin_function_or_method":
            setattr(_multicage, name, _wrap(obj))
        elif isinstance(obj, type) and obj.__module__.startswith("multicage"):
            for attr, member in list(vars(obj).items()):
                if attr in ("__getstate__", "__setstate__", "__repr__", "__eq__", "__copy__", "__deepcopy__"):
                    continue
                if attr != "__init__" and attr.startswith("__"):
                    continue
                if isinstance(member, staticmethod):
                    setattr(obj, attr, staticmethod(_wrap(member.__func__)))
                elif type(member).__name__ == "instancemethod":
                    setattr(obj, attr, _wrap(member.__func__, constructor=attr == "__init__"))


_wrap_module()


def _reframe(self, frames):
    """Reframes a whole clip: pushes each frame of the iterable `frames` (numpy arrays, as
    cv2.VideoCapture.read or PyAV give them) and yields each output image as soon as it is
    ready; at the end of the iterable calls finish() and yields the rest. Every frame pushed
    comes out, in order. For the other fields of each output frame, push() and pop()."""
    for frame in frames:
        self.push(frame)
        while (out := self.pop()) is not None:
            yield out["image"]
    self.finish()
    while (out := self.pop()) is not None:
        yield out["image"]


_reframe.__name__, _reframe.__qualname__ = "reframe", "VideoReframer.reframe"
_multicage.VideoReframer.reframe = _reframe

from ._multicage import (
    CONDITIONING_WARNING,
    MAX_MAP_STEP,
    Backend,
    Binding,
    CageTracker,
    CoordinateType,
    Deformer,
    Error,
    NoObjectFoundError,
    Multicage,
    Pose,
    ProposeMethod,
    VideoReframer,
    __version__,
    auto_backend,
    bind,
    carry_pose,
    content_aware_resize,
    crop_multicage,
    deform_image,
    gpu_available,
    imread,
    mean_value_coordinates,
    propose_defaults,
    propose_multicage,
    propose_segmentation,
    protect_features,
    random_pose,
    reframe_window,
    resize_pose,
    segmenter_model_file,
    subject_map,
    validate_pose,
)
from .transforms import MulticageWarp, TorchMulticageWarp, box_outline, default_multicage, sample_seed

__all__ = [
    "CONDITIONING_WARNING",
    "MAX_MAP_STEP",
    "Backend",
    "Binding",
    "CageTracker",
    "CoordinateType",
    "Deformer",
    "Error",
    "NoObjectFoundError",
    "Multicage",
    "Pose",
    "ProposeMethod",
    "VideoReframer",
    "auto_backend",
    "bind",
    "carry_pose",
    "content_aware_resize",
    "crop_multicage",
    "deform_image",
    "gpu_available",
    "imread",
    "mean_value_coordinates",
    "propose_defaults",
    "propose_multicage",
    "propose_segmentation",
    "protect_features",
    "random_pose",
    "reframe_window",
    "resize_pose",
    "segmenter_model_file",
    "subject_map",
    "validate_pose",
    "MulticageWarp",
    "TorchMulticageWarp",
    "box_outline",
    "default_multicage",
    "sample_seed",
]

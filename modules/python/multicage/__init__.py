"""multicage: multicage image deformation for OpenCV pipelines in Python.

Bindings over the C++ library (paper "Multicage Image Deformation On GPU"). Conventions are
cv2's: images are numpy arrays as cv2.imread gives them (uint8, uint16 or float32; HxW,
HxWx3 BGR or HxWx4 BGRA), points are Nx2 arrays of (x, y) with pixel (x, y) at its centre,
sizes are (width, height).

    import cv2, multicage
    image = cv2.imread("butterfly.jpg")
    cage = multicage.propose_multicage(image)            # or Multicage.load("cage.yml")
    deformer = multicage.Deformer(image, cage, backend="cpu")
    pose = cage.rest_pose(); pose[:, 1] -= 10            # move every vertex up 10 px
    out = deformer.deform(pose)                          # same shape and dtype as image
    mapx, mapy = deformer.compute_maps(pose)             # for cv2.remap of masks, labels
    mask_out = cv2.remap(mask, mapx, mapy, cv2.INTER_NEAREST)

Errors reported by the library raise multicage.Error (a ValueError) with the library's
message; wrong array types raise TypeError, wrong shapes ValueError. The GIL is released
while the library binds, deforms, proposes or computes coordinates.
"""

from ._multicage import (
    CONDITIONING_WARNING,
    Backend,
    Binding,
    CoordinateType,
    Deformer,
    Error,
    NoObjectFoundError,
    Multicage,
    Pose,
    ProposeMethod,
    __version__,
    auto_backend,
    bind,
    deform_image,
    gpu_available,
    mean_value_coordinates,
    propose_defaults,
    propose_multicage,
    propose_segmentation,
    protect_features,
)

__all__ = [
    "CONDITIONING_WARNING",
    "Backend",
    "Binding",
    "CoordinateType",
    "Deformer",
    "Error",
    "NoObjectFoundError",
    "Multicage",
    "Pose",
    "ProposeMethod",
    "auto_backend",
    "bind",
    "deform_image",
    "gpu_available",
    "mean_value_coordinates",
    "propose_defaults",
    "propose_multicage",
    "propose_segmentation",
    "protect_features",
]

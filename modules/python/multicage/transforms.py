"""MulticageWarp: multicage deformation as a data-augmentation transform.

Called the way albumentations transforms are called, with the same keys back:

    import multicage
    warp = multicage.MulticageWarp(amplitude=12, grid_step=4, seed=0)
    out = warp(image=image, mask=mask, keypoints=points, bboxes=boxes, index=i)
    out["image"], out["mask"], out["keypoints"], out["bboxes"], out["keypoints_visible"]

Every target moves by the same deformation: images bilinear, masks nearest (cv2.remap of the
deformer's inverse maps), keypoints through Deformer.transform_points (the image's own mesh),
boxes as the bounds of their moved outline sampled every pixel (so a box follows a bent edge:
it matches the box of the moved mask of the box within 1 px, where the box of four moved
corners is too small).

Conventions are the package's: images as cv2 gives them (HxW, HxWxC; uint8, uint16, float32;
float64 is warped as float32 and returned as float64), points (x, y) with pixel (x, y) at its
centre, so the image spans [-0.5, w - 0.5) in x; boxes are pascal_voc (x_min, y_min, x_max,
y_max) in pixel edges (the box of mask pixels x0..x1-1 is x0..x1), as albumentations has them;
columns after the first 2 (keypoints) or 4 (boxes) are carried along unchanged (labels...).

Boxes and keypoints as albumentations users give them (its BboxParams and KeypointParams, as
keywords of the transform; boxes and keypoints come back in the format they were given in):

    warp = multicage.MulticageWarp(amplitude=12, bbox_format="coco", label_fields=["classes"],
                                   keypoint_format="xyas", remove_invisible=True, seed=0)
    out = warp(image=image, bboxes=[(300, 50, 100, 100)], classes=["cat"],
               keypoints=[(120, 80, 45.0, 10.0)], index=i)
    out["bboxes"], out["classes"]  # a class per box still there

bbox_format: 'pascal_voc' (the default, above), 'coco' (x_min, y_min, width, height in
pixels), 'yolo' (x_center, y_center, width, height divided by the image's width and height) or
'albumentations' (pascal_voc divided by the image's width and height). A box is moved as its
pascal_voc pixel box is; a box the warp leaves where it was comes back exactly as given.
Errors speak the format's terms (a coco box with a negative width says so), and a normalised
box reaching outside [0, 1] is refused (it is a box in pixels under a normalised name).

label_fields / keypoint_label_fields: names of the call's keywords holding one label per box /
keypoint (a list or an array); with remove_invisible they lose the items of dropped boxes /
keypoints, so labels and boxes stay in step.

keypoint_format: 'xy' (the default), 'yx', 'xya', 'xys', 'xyas' or 'xysa'. An angle (degrees by
default, angle_in_degrees=False for radians) is a direction (cos a, sin a) in image axes (x
right, y down: positive angles turn clockwise on screen, as albumentations' Affine has them); it
is carried by the deformation's local linear map at the keypoint (central differences of
transform_points half a pixel either side), so an arrow drawn at the keypoint points the same
way after the warp, and comes back in [0, 360) ([0, 2 pi)): a region moved by a rotation adds
that rotation. A scale is multiplied by the local scale, the square root of that map's
determinant (the factor of a scaled region). Columns after the format's pass through unchanged.

Seeding: a call with index=i (a dataset index) draws from SeedSequence([seed, i]): the same
sample gets the same augmentation in one process, in DataLoader workers (fork or spawn) and
in Dask tasks, whichever worker runs it. A call with seed=s uses s itself; a call with neither
draws a fresh seed from the operating system.

Replay: warp(..., return_params=True) adds out["replay"], a dict of what was applied (applied,
seed, pose, cage key, the cage itself, image size, grid step); warp.replay(params, image=...,
...) applies exactly that again (same pose, same cage, same pixels), in any process: the dict
pickles.
"""

import hashlib
import os
import threading
from collections import OrderedDict

import cv2
import numpy as np

from . import _multicage as _mc

__all__ = ["MulticageWarp", "TorchMulticageWarp", "box_outline", "default_multicage", "sample_seed"]

_BORDER_MODES = {
    "constant": cv2.BORDER_CONSTANT,
    "replicate": cv2.BORDER_REPLICATE,
    "reflect": cv2.BORDER_REFLECT,
    "reflect_101": cv2.BORDER_REFLECT_101,
    "wrap": cv2.BORDER_WRAP,
}

NO_SUBJECT_CHOICES = ("default", "skip", "raise")

# Box formats (albumentations' names): what the four coordinates are, as error messages say it.
BBOX_FORMATS = {
    "pascal_voc": "x_min, y_min, x_max, y_max",
    "coco": "x_min, y_min, width, height in pixels",
    "yolo": "x_center, y_center, width, height divided by the image's width and height",
    "albumentations": "x_min, y_min, x_max, y_max divided by the image's width and height",
}

# Keypoint formats (albumentations' names): the column of x, y, angle and scale (None: absent).
KEYPOINT_FORMATS = {
    "xy": (0, 1, None, None),
    "yx": (1, 0, None, None),
    "xya": (0, 1, 2, None),
    "xys": (0, 1, None, 2),
    "xyas": (0, 1, 2, 3),
    "xysa": (0, 1, 3, 2),
}

# Normalised boxes may overshoot [0, 1] by this much: the rounding of label files written with
# 6 decimals, far below what a box in pixels given by mistake shows.
_NORMALISED_SLACK = 1e-4

# Half the step of the finite differences that find the local linear map at a keypoint: well
# inside one mesh triangle's size, well above float32's resolution of a pixel coordinate.
_JACOBIAN_STEP = 0.5

# The call's own keywords: a label field of one of these names would shadow it.
_CALL_KEYWORDS = ("image", "mask", "masks", "keypoints", "bboxes", "name", "index", "seed", "return_params",
                  "keypoints_visible", "bboxes_visible", "replay")


# What cv2.remap carries unchanged: other mask dtypes go through their indices (_move_mask).
_REMAP_DTYPES = tuple(np.dtype(t) for t in (np.uint8, np.int8, np.uint16, np.int16, np.int32,
                                            np.float32, np.float64))


def sample_seed(seed, index):
    """The seed of sample `index` of a run seeded with `seed` (both integers >= 0): a pure
    function (numpy's SeedSequence), so every process gives every sample the same seed."""
    state = np.random.SeedSequence([int(seed), int(index)]).generate_state(2, np.uint32)
    return (int(state[0]) << 31) ^ int(state[1])


def default_multicage(size):
    """The documented cage for an image without a subject (no object found): one octagon
    around the centre, a quarter of the image in from each side. The centre moves as a
    whole, the frame stays: a smooth, gentle warp of the whole picture."""
    w, h = size
    cx, cy, rx, ry = (w - 1) / 2.0, (h - 1) / 2.0, w / 4.0, h / 4.0
    angles = np.pi / 8 + np.arange(8) * (np.pi / 4)
    points = np.stack([cx + rx * np.cos(angles), cy + ry * np.sin(angles)], axis=1).astype(np.float32)
    cage = _mc.Multicage((int(w), int(h)))
    cage.add_polygon(points)
    cage.orient()
    return cage


def box_outline(box, spacing=1.0):
    """Points on the outline of a pascal_voc box (pixel edges) in pixel-centre coordinates,
    one every `spacing` px at most, corners included: the outline a mask of the box has."""
    x0, y0, x1, y1 = (float(v) for v in box[:4])
    x0, y0, x1, y1 = x0 - 0.5, y0 - 0.5, x1 - 0.5, y1 - 0.5
    nx = max(1, int(np.ceil(abs(x1 - x0) / spacing)))
    ny = max(1, int(np.ceil(abs(y1 - y0) / spacing)))
    xs = np.linspace(x0, x1, nx + 1)
    ys = np.linspace(y0, y1, ny + 1)
    top = np.stack([xs, np.full_like(xs, y0)], 1)
    bottom = np.stack([xs, np.full_like(xs, y1)], 1)
    left = np.stack([np.full_like(ys, x0), ys], 1)
    right = np.stack([np.full_like(ys, x1), ys], 1)
    return np.concatenate([top, right, bottom, left]).astype(np.float32)


def _field_names(names, what):
    """A tuple of label field names (one name may be given as a str), none shadowing a call
    keyword."""
    names = (names,) if isinstance(names, str) else tuple(names or ())
    for n in names:
        if not isinstance(n, str) or not n:
            raise TypeError(f"{what}: names of the call's keywords (str), got {n!r}")
        if n in _CALL_KEYWORDS:
            raise ValueError(f"{what}: {n!r} is a keyword of the call itself; name the labels otherwise")
    if len(set(names)) != len(names):
        raise ValueError(f"{what}: a name appears twice in {names!r}")
    return names


def _float32(image):
    """The image a float64 image is warped as: float32, what cv2.remap and the deformer take
    (other dtypes as given)."""
    return image.astype(np.float32) if image.dtype == np.float64 else image


def _cage_digest(cage):
    """A key for a multicage's content (size, polygons, coordinates): bindings are cached by it,
    so that a replay with another transform's cage never meets a binding of a different cage."""
    h = hashlib.sha1(repr((tuple(cage.image_size), cage.coordinates,
                           [len(cage.polygon(i)) for i in range(cage.polygon_count)])).encode())
    h.update(np.ascontiguousarray(cage.vertices(), np.float32).tobytes())
    return h.hexdigest()


def _image_key(image):
    h = hashlib.sha1()
    h.update(repr((image.shape, image.dtype.str)).encode())
    h.update(np.ascontiguousarray(image).data)
    return "sha1:" + h.hexdigest()[:16]


class MulticageWarp:
    """A random multicage deformation of an image and its annotations (albumentations-style).

    MulticageWarp(amplitude=10, grid_step=4, *, map_step=None, p=1.0, seed=None, coordinates=None,
                  cage=None, cages=None, cage_dir=None, propose=True, protect=True,
                  propose_options=None, no_subject='default', border_mode='constant',
                  border_value=0, mask_value=0, remove_invisible=False, backend='cpu',
                  pose_options=None, fold_check='coarse', cache_size=16,
                  bbox_format='pascal_voc', label_fields=(), keypoint_format='xy',
                  keypoint_label_fields=(), angle_in_degrees=True)

    amplitude       most pixels a cage vertex moves (multicage.random_pose)
    grid_step       a mesh node every grid_step pixels (1: the paper's per-pixel method;
                    4: what augmentation needs, much faster)
    map_step        the inverse maps found on a lattice at most map_step pixels apart and
                    interpolated where a pose folds nothing (Deformer's map_step; None: the
                    grid step, an error of the grid step's own kind; 1: at every pixel)
    p               probability of applying it (drawn from the sample's seed)
    seed            base seed: with index=i a call draws from sample_seed(seed, i)
    coordinates     'mvc' or 'harmonic' (None: the cage's own)
    cage            a Multicage or a cage file path, for every image (scaled to each size) ...
    cages           ... or a mapping from image name (the call's name=) to a Multicage or a
                    cage file path; names not in it fall through to the next source
    propose         propose a multicage for an image on first use (multicage.propose_multicage
                    with protect= and propose_options=, e.g. {'segmenter': 'classic'} or
                    {'segmenter_model': path}; none: the library's default, the learned subject
                    model when one is installed), cached in memory by name= (or by the
                    image's content when no name is given) ...
    cage_dir        ... and as <cage_dir>/<name>.yml cage files, read back on later runs
    no_subject      what an image where no object is found gets: 'default' (the documented
                    default_multicage: an octagon around the centre, so the picture still
                    warps gently), 'skip' (returned unchanged, replay says not applied), or
                    'raise' (multicage.NoObjectFoundError)
    border_mode     'constant' (border_value), 'replicate', 'reflect', 'reflect_101', 'wrap' or
                    a cv2.BORDER_* constant: what uncovered output pixels show
    mask_value      what uncovered mask pixels get (border_mode 'constant')
    remove_invisible drop keypoints that land outside the output and boxes with nothing left
                    inside it (the flags are returned either way)
    pose_options    extra keywords of multicage.random_pose (max_rotation, jitter, ...)
    fold_check      'coarse' (default): random_pose checks fold-over on its own mesh of about
                    160 nodes along the longer side (and around every cage vertex), as
                    random_pose(cage, amplitude, seed) does; 'exact': on the mesh the image is
                    deformed with (slower at fine grid steps: every node, every draw)
    cache_size      bindings (and deformers) kept, the most recently used: a binding is made
                    once per cage and image size and reused while it stays in the cache
    bbox_format     how bboxes= are given and returned: 'pascal_voc' (x_min, y_min, x_max,
                    y_max in pixels), 'coco' (x_min, y_min, width, height in pixels), 'yolo'
                    (x_center, y_center, width, height) or 'albumentations' (x_min, y_min,
                    x_max, y_max), those two divided by the image's width and height
    label_fields    names of call keywords with one label per box (albumentations' BboxParams
                    label_fields): filtered with the boxes when remove_invisible drops some
    keypoint_format how keypoints= are given and returned: 'xy', 'yx', 'xya', 'xys', 'xyas',
                    'xysa' (a: angle, turned with the deformation's local linear map; s: scale,
                    multiplied by the local scale; see the module's doc)
    keypoint_label_fields  names of call keywords with one label per keypoint, filtered with them
    angle_in_degrees keypoint angles in degrees (True, albumentations' default) or radians

    The transform pickles (without its caches) for workers.
    """

    def __init__(self, amplitude=10.0, grid_step=4, *, map_step=None, p=1.0, seed=None, coordinates=None, cage=None,
                 cages=None, cage_dir=None, propose=True, protect=True, propose_options=None,
                 no_subject="default", border_mode="constant", border_value=0, mask_value=0,
                 remove_invisible=False, backend="cpu", pose_options=None, fold_check="coarse",
                 cache_size=16, bbox_format="pascal_voc", label_fields=(), keypoint_format="xy",
                 keypoint_label_fields=(), angle_in_degrees=True):
        if not (float(amplitude) >= 0):
            raise ValueError(f"amplitude: must be >= 0, got {amplitude!r}")
        if int(grid_step) < 1:
            raise ValueError(f"grid_step: must be >= 1, got {grid_step!r}")
        map_step = int(grid_step) if map_step is None else int(map_step)
        if not 1 <= map_step <= _mc.MAX_MAP_STEP:
            raise ValueError(f"map_step: must be in [1, {_mc.MAX_MAP_STEP}] (or None: the grid step), "
                             f"got {map_step!r}")
        if not (0.0 <= float(p) <= 1.0):
            raise ValueError(f"p: a probability in [0, 1], got {p!r}")
        if fold_check not in ("coarse", "exact"):
            raise ValueError(f"fold_check: 'coarse' or 'exact', got {fold_check!r}")
        if no_subject not in NO_SUBJECT_CHOICES:
            raise ValueError(f"no_subject: one of {NO_SUBJECT_CHOICES}, got {no_subject!r}")
        if bbox_format not in BBOX_FORMATS:
            raise ValueError(f"bbox_format: one of {tuple(BBOX_FORMATS)}, got {bbox_format!r}")
        if keypoint_format not in KEYPOINT_FORMATS:
            raise ValueError(f"keypoint_format: one of {tuple(KEYPOINT_FORMATS)}, got {keypoint_format!r}")
        label_fields = _field_names(label_fields, "label_fields")
        keypoint_label_fields = _field_names(keypoint_label_fields, "keypoint_label_fields")
        both = sorted(set(label_fields) & set(keypoint_label_fields))
        if both:
            raise ValueError(f"label_fields and keypoint_label_fields both name {both[0]!r}: a list is "
                             "filtered by the boxes or by the keypoints, not both")
        if isinstance(border_mode, str):
            if border_mode not in _BORDER_MODES:
                raise ValueError(f"border_mode: one of {sorted(_BORDER_MODES)} or a cv2.BORDER_*, got {border_mode!r}")
            border_mode = _BORDER_MODES[border_mode]
        self.amplitude = float(amplitude)
        self.grid_step = int(grid_step)
        self.map_step = map_step
        self.p = float(p)
        self.seed = None if seed is None else int(seed)
        self.coordinates = coordinates
        self.cage = _mc.Multicage.load(cage) if isinstance(cage, (str, os.PathLike)) else cage
        self.cages = dict(cages) if cages is not None else {}
        self.cage_dir = None if cage_dir is None else os.fspath(cage_dir)
        self.propose = bool(propose)
        self.protect = bool(protect)
        self.propose_options = dict(propose_options or {})
        self.no_subject = no_subject
        self.border_mode = int(border_mode)
        self.border_value = border_value
        self.mask_value = mask_value
        self.remove_invisible = bool(remove_invisible)
        self.backend = backend
        self.pose_options = dict(pose_options or {})
        self.fold_check = fold_check
        self.cache_size = max(1, int(cache_size))
        self.bbox_format = bbox_format
        self.label_fields = label_fields
        self.keypoint_format = keypoint_format
        self.keypoint_label_fields = keypoint_label_fields
        self.angle_in_degrees = bool(angle_in_degrees)
        self._init_caches()

    def _init_caches(self):
        self._lock = threading.Lock()
        self._cages = {}      # cage key -> Multicage (rest, as drawn)
        # The most recently used bindings and deformers, at most cache_size of each: a dataset
        # of proposed cages has one per image, and a binding is megabytes.
        self._bindings = OrderedDict()   # (cage digest, size) -> (scaled cage, Binding)
        self._deformers = OrderedDict()  # (cage digest, shape, dtype) -> Deformer
        self._local = threading.local()  # per thread: map buffers reused between calls

    def __getstate__(self):
        state = dict(self.__dict__)
        for k in ("_lock", "_cages", "_bindings", "_deformers", "_local"):
            state.pop(k)
        return state

    def __setstate__(self, state):
        self.__dict__.update(state)
        self.__dict__.setdefault("map_step", 1)  # pickled before map_step: every pixel, as then
        for key, value in (("bbox_format", "pascal_voc"), ("label_fields", ()), ("keypoint_format", "xy"),
                           ("keypoint_label_fields", ()), ("angle_in_degrees", True)):
            self.__dict__.setdefault(key, value)  # pickled before the formats: today's behaviour
        self._init_caches()

    def __repr__(self):
        return (f"MulticageWarp(amplitude={self.amplitude}, grid_step={self.grid_step}, "
                f"map_step={self.map_step}, p={self.p}, "
                f"seed={self.seed})")

    # --- where the cage comes from -----------------------------------------------------------

    def _cage_for(self, image, name):
        """(key, Multicage) for an image, or (key, None) when it has no subject and is skipped."""
        if self.cage is not None:
            return "given", self.cage
        if name is not None and name in self.cages:
            key = "name:" + str(name)
            with self._lock:
                cached = self._cages.get(key)
            if cached is None:
                value = self.cages[name]
                cached = _mc.Multicage.load(os.fspath(value)) if isinstance(value, (str, os.PathLike)) else value
                with self._lock:
                    self._cages[key] = cached
            return key, cached
        if not self.propose:
            return self._no_subject(image, "default:" + str(image.shape[1]) + "x" + str(image.shape[0]))
        key = "proposed:" + (str(name) if name is not None else _image_key(image))
        with self._lock:
            cached = self._cages.get(key)
        if cached is not None:
            return (key, cached) if cached is not False else self._no_subject(image, key)
        path = self._cage_path(name, key)
        if path is not None and os.path.exists(path):
            cached = _mc.Multicage.load(path)
        else:
            try:
                # A constant image has no subject (the library refuses to segment it).
                cached = (False if image.size == 0 or image.min() == image.max() else
                          _mc.propose_multicage(image, protect=self.protect, **self.propose_options))
            except _mc.NoObjectFoundError:
                cached = False
            if cached is not False and path is not None:
                os.makedirs(self.cage_dir, exist_ok=True)
                cached.save(path)  # atomically: parallel workers may write the same file
        with self._lock:
            self._cages[key] = cached
        return (key, cached) if cached is not False else self._no_subject(image, key)

    def _cage_path(self, name, key):
        if self.cage_dir is None:
            return None
        stem = os.path.splitext(os.path.basename(str(name)))[0] if name is not None else key.split(":", 1)[1]
        return os.path.join(self.cage_dir, stem + ".yml")

    def _no_subject(self, image, key):
        if self.no_subject == "raise":
            raise _mc.NoObjectFoundError(f"MulticageWarp: no object found in the image ({key})")
        if self.no_subject == "skip":
            return key, None
        size = (image.shape[1], image.shape[0])
        return "default:%dx%d" % size, default_multicage(size)

    def _binding(self, cage, size):
        """The cage scaled to the image size and its Binding, made once per (cage, size)."""
        bkey = (_cage_digest(cage), size)
        with self._lock:
            found = self._bindings.get(bkey)
            if found is not None:
                self._bindings.move_to_end(bkey)
        if found is None:
            scaled = cage if tuple(cage.image_size) == size else cage.scaled(size)
            found = (scaled, _mc.bind(scaled, coordinates=self.coordinates, grid_step=self.grid_step))
            with self._lock:
                self._bindings[bkey] = found
                while len(self._bindings) > self.cache_size:
                    self._bindings.popitem(last=False)
        return found

    def _deformer(self, cage, image):
        dkey = (_cage_digest(cage), image.shape, image.dtype.str)
        with self._lock:
            d = self._deformers.get(dkey)
            if d is not None:
                self._deformers.move_to_end(dkey)
        if d is None:
            size = (image.shape[1], image.shape[0])
            _, binding = self._binding(cage, size)
            d = _mc.Deformer(image, binding, backend=self.backend, border_value=self._border_tuple(),
                             map_step=self.map_step)
            with self._lock:
                self._deformers[dkey] = d
                while len(self._deformers) > self.cache_size:
                    self._deformers.popitem(last=False)
        return d

    def _map_buffers(self, w, h):
        """This thread's two map arrays for an image size, reused call after call (fresh maps
        every call cost page faults that can exceed the raster)."""
        buffers = getattr(self._local, "maps", None)
        if buffers is None or buffers[0].shape != (h, w):
            buffers = (np.empty((h, w), np.float32), np.empty((h, w), np.float32))
            self._local.maps = buffers
        return buffers

    def _border_tuple(self):
        v = self.border_value
        return v if isinstance(v, (int, float)) else tuple(v)

    # --- the call ---------------------------------------------------------------------------

    def _draw(self, index, seed):
        """(applied, pose seed) for a call."""
        if seed is None:
            if index is not None:
                seed = sample_seed(self.seed if self.seed is not None else 0, index)
            else:
                seed = int.from_bytes(os.urandom(8), "little") >> 1
        seed = int(seed)
        if self.p >= 1.0:  # always applied: no draw (a generator costs a tenth of a warp)
            return True, seed
        # The draw of p has a stream of its own beside the pose's (0x6d63: "mc" in ASCII), so a
        # pose is the same whether p is 1 or not.
        rng = np.random.default_rng(np.random.SeedSequence([seed, 0x6d63]))
        return rng.random() < self.p, seed

    def __call__(self, *, image=None, mask=None, masks=None, keypoints=None, bboxes=None, name=None,
                 index=None, seed=None, return_params=False, **other):
        """The targets moved by one random deformation: a dict with the keys given (other keys
        are passed through unchanged, label fields filtered with their boxes or keypoints),
        plus 'keypoints_visible' / 'bboxes_visible' (a bool per input keypoint / box: inside
        the output) when keypoints / boxes were given, and 'replay' when return_params.
        name: the image's name (cage mapping, proposal cache); index: the sample's index
        (seeding, see the module's doc); seed: this call's seed."""
        if image is None:
            raise ValueError("MulticageWarp: image= is required (the deformation is drawn for its size)")
        image = np.asarray(image)
        applied, call_seed = self._draw(index, seed)
        params = {"applied": False, "seed": call_seed, "pose": None, "cage_key": None, "cage": None,
                  "image_size": (image.shape[1], image.shape[0]), "grid_step": self.grid_step,
                  "map_step": self.map_step, "amplitude": self.amplitude}
        if applied:
            key, cage = self._cage_for(_float32(image), name)
            if cage is not None:
                scaled, binding = self._binding(cage, params["image_size"])
                check = {"binding": binding} if self.fold_check == "exact" else {}
                pose = _mc.random_pose(scaled, self.amplitude, seed=call_seed, **check, **self.pose_options)
                params.update(applied=True, pose=pose, cage_key=key, cage=cage)
        return self._apply(params, image, mask, masks, keypoints, bboxes, other, return_params)

    def replay(self, params, *, image=None, mask=None, masks=None, keypoints=None, bboxes=None,
               return_params=False, **other):
        """Applies exactly what a call returned in out['replay'] (its pose and cage) to these
        targets: the same pixels, points and boxes as that call gave for the same inputs."""
        if image is None:
            raise ValueError("MulticageWarp.replay: image= is required")
        image = np.asarray(image)
        size = (image.shape[1], image.shape[0])
        if params.get("applied") and tuple(params["image_size"]) != size:
            raise ValueError(f"MulticageWarp.replay: the parameters are for a {params['image_size']} "
                             f"image, this one is {size}")
        if params.get("grid_step", self.grid_step) != self.grid_step:
            raise ValueError("MulticageWarp.replay: the parameters were made with grid_step="
                             f"{params['grid_step']}, this transform has {self.grid_step}")
        if params.get("map_step", self.map_step) != self.map_step:
            raise ValueError("MulticageWarp.replay: the parameters were made with map_step="
                             f"{params['map_step']}, this transform has {self.map_step}")
        return self._apply(dict(params), image, mask, masks, keypoints, bboxes, other, return_params)

    def _apply(self, params, image, mask, masks, keypoints, bboxes, other, return_params):
        out = dict(other)
        h, w = image.shape[:2]
        work = _float32(image)
        deformer = pose = None
        if params["applied"]:
            key, cage = params["cage_key"], params["cage"]  # the cage travels with the params
            deformer = self._deformer(cage, work)
            pose = params["pose"]
        need_maps = deformer is not None and (mask is not None or masks is not None
                                              or self.border_mode != cv2.BORDER_CONSTANT)
        maps = deformer.compute_maps(pose, *self._map_buffers(w, h)) if need_maps else None
        if deformer is None:
            out["image"] = image.copy()
        elif maps is None:
            out["image"] = deformer.deform(pose, image=work)
        else:
            out["image"] = cv2.remap(work, maps[0], maps[1], cv2.INTER_LINEAR, borderMode=self.border_mode,
                                     borderValue=self._cv_border(self.border_value))
        if out["image"].dtype != image.dtype:
            out["image"] = out["image"].astype(image.dtype)  # a float64 image, warped in float32
        if mask is not None:
            out["mask"] = self._move_mask(np.asarray(mask), maps, (w, h))
        if masks is not None:
            out["masks"] = [self._move_mask(np.asarray(m), maps, (w, h)) for m in masks]
        if keypoints is not None:
            out["keypoints"], out["keypoints_visible"] = self._move_keypoints(keypoints, deformer, pose, w, h)
            self._filter_labels(out, self.keypoint_label_fields, out["keypoints_visible"], "keypoints")
        if bboxes is not None:
            out["bboxes"], out["bboxes_visible"] = self._move_boxes(bboxes, deformer, pose, w, h)
            self._filter_labels(out, self.label_fields, out["bboxes_visible"], "bboxes")
        if return_params:
            params["pose"] = None if params["pose"] is None else np.array(params["pose"], np.float32)
            out["replay"] = params
        return out

    def _filter_labels(self, out, fields, visible, what):
        """Each label field's list, one item per box (keypoint), kept where its box (keypoint) is
        kept: albumentations' label_fields."""
        keep = visible if self.remove_invisible else np.ones(len(visible), bool)
        which = "label_fields" if what == "bboxes" else "keypoint_label_fields"
        for field in fields:
            if field not in out:
                raise ValueError(f"{which}: {field}= was not passed with {what}= (one label per item of {what})")
            labels = out[field]
            if len(labels) != len(visible):
                raise ValueError(f"{which}: {field}= has {len(labels)} items for {len(visible)} {what}")
            if keep.all():
                continue  # given back as given
            if isinstance(labels, np.ndarray):
                out[field] = labels[keep]
            else:
                out[field] = [v for v, k in zip(labels, keep) if k]

    @staticmethod
    def _cv_border(value):
        return (value,) * 4 if isinstance(value, (int, float)) else tuple(value)

    def _move_mask(self, mask, maps, size):
        if mask.shape[:2] != (size[1], size[0]):
            raise ValueError(f"mask: shape {mask.shape} but the image is {size[0]}x{size[1]}")
        if maps is None:
            return mask.copy()
        channels = mask.shape[2] if mask.ndim == 3 else 1
        if mask.dtype in _REMAP_DTYPES and channels <= 4:
            return cv2.remap(mask, maps[0], maps[1], cv2.INTER_NEAREST, borderMode=self.border_mode,
                             borderValue=self._cv_border(self.mask_value))
        # dtypes cv2.remap refuses (bool, uint32, float16) or narrows (int64 to int32), and
        # masks of many channels: the same nearest pixels, found by remapping their indices.
        w, h = size
        index = cv2.remap(np.arange(w * h, dtype=np.int32).reshape(h, w), maps[0], maps[1],
                          cv2.INTER_NEAREST, borderMode=self.border_mode, borderValue=(-1,) * 4)
        out = mask.reshape(w * h, -1)[np.maximum(index, 0)].reshape(mask.shape)
        out[index < 0] = self.mask_value
        return out

    @staticmethod
    def _split(rows, width, what):
        """(N x width float64 coordinates, extra columns per row or None) of an array or a
        list of tuples whose extra columns may be anything (labels)."""
        if isinstance(rows, np.ndarray):
            a = rows.astype(np.float64).reshape(-1, rows.shape[-1]) if rows.size else np.zeros((0, width))
            if a.shape[1] < width:
                raise ValueError(f"{what}: expected N x ({width} + extra columns), got shape {rows.shape}")
            return a, None
        rows = list(rows)
        for r in rows:
            if len(r) < width:
                raise ValueError(f"{what}: every item needs {width} coordinates first, got {r!r}")
        coords = np.array([[float(v) for v in r[:width]] for r in rows], np.float64).reshape(-1, width)
        return coords, [tuple(r[width:]) for r in rows]

    @staticmethod
    def _join(rows, moved, extras, keep):
        if extras is None:
            out = moved[keep]
            return out.astype(rows.dtype if rows.dtype.kind == "f" else np.float32)
        return [tuple(m) + e for m, e, k in zip(moved.tolist(), extras, keep) if k]

    @staticmethod
    def _check_finite(coords, what, item):
        bad = ~np.isfinite(coords).all(axis=1)
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            raise ValueError(f"{what}: {item} {i} is not finite {tuple(coords[i].tolist())}")

    def _move_keypoints(self, keypoints, deformer, pose, w, h):
        fmt = self.keypoint_format
        ix, iy, ia, js = KEYPOINT_FORMATS[fmt]
        width = len(fmt)
        what = "keypoints" if fmt == "xy" else f"keypoints (keypoint_format {fmt!r})"
        k, extras = self._split(keypoints, width, what)
        self._check_finite(k[:, :width], what, "keypoint")
        xy = k[:, [ix, iy]]
        moved = k.copy()
        if deformer is not None and len(k):
            new = deformer.transform_points(pose, xy.astype(np.float32)).astype(np.float64)
            if ia is not None or js is not None:
                jac = self._local_maps(deformer, pose, xy)
                if ia is not None:
                    moved[:, ia] = self._turn_angles(k[:, ia], jac)
                if js is not None:
                    moved[:, js] = k[:, js] * np.sqrt(np.abs(np.linalg.det(jac)))
            moved[:, ix], moved[:, iy] = new[:, 0], new[:, 1]
            xy = new
        x, y = xy[:, 0], xy[:, 1]
        visible = (x >= -0.5) & (x < w - 0.5) & (y >= -0.5) & (y < h - 0.5)
        keep = visible if self.remove_invisible else np.ones(len(k), bool)
        return self._join(keypoints, moved if extras is None else moved[:, :width], extras, keep), visible

    @staticmethod
    def _local_maps(deformer, pose, xy):
        """N x 2 x 2 Jacobians of the deformation at the points: central differences of
        transform_points a fraction of a pixel either side in x and in y."""
        e = _JACOBIAN_STEP
        offsets = np.array([[e, 0], [-e, 0], [0, e], [0, -e]])
        around = (xy[:, None, :] + offsets[None]).reshape(-1, 2)
        t = deformer.transform_points(pose, around.astype(np.float32)).astype(np.float64).reshape(-1, 4, 2)
        # Columns: where a step along x and a step along y go (dT/dx, dT/dy).
        return np.stack([(t[:, 0] - t[:, 1]) / (2 * e), (t[:, 2] - t[:, 3]) / (2 * e)], axis=2)

    def _turn_angles(self, angles, jac):
        """The direction (cos a, sin a) (x right, y down) carried by the local linear map, as an
        angle in [0, 360) degrees or [0, 2 pi) radians: where an arrow drawn at the keypoint points
        after the warp (a similarity's rotation is added to it)."""
        a = np.radians(angles) if self.angle_in_degrees else angles
        d = np.einsum("nij,nj->ni", jac, np.stack([np.cos(a), np.sin(a)], axis=1))
        turned = np.mod(np.arctan2(d[:, 1], d[:, 0]), 2 * np.pi)
        if self.angle_in_degrees:
            turned = np.mod(np.degrees(turned), 360.0)
        return turned

    def _boxes_to_pixels(self, b, w, h):
        """pascal_voc pixel boxes (x_min, y_min, x_max, y_max in pixel edges) of N boxes in the
        transform's bbox_format, checked in that format's own terms."""
        fmt = self.bbox_format
        terms = f"({fmt} boxes are {BBOX_FORMATS[fmt]})"
        if fmt in ("coco", "yolo"):
            negative = (b[:, 2] < 0) | (b[:, 3] < 0)
            if negative.any():
                i = int(np.flatnonzero(negative)[0])
                side = "width" if b[i, 2] < 0 else "height"
                raise ValueError(f"bboxes: box {i} {tuple(b[i, :4].tolist())} has a negative {side} {terms}")
        else:
            inverted = (b[:, 2] < b[:, 0]) | (b[:, 3] < b[:, 1])
            if inverted.any():
                i = int(np.flatnonzero(inverted)[0])
                raise ValueError(f"bboxes: box {i} {tuple(b[i, :4].tolist())} has its maximum before its "
                                 f"minimum {terms}")
        if fmt == "coco":
            return np.stack([b[:, 0], b[:, 1], b[:, 0] + b[:, 2], b[:, 1] + b[:, 3]], axis=1)
        if fmt == "pascal_voc":
            return b[:, :4].copy()
        if fmt == "yolo":
            edges = np.stack([b[:, 0] - b[:, 2] / 2, b[:, 1] - b[:, 3] / 2,
                              b[:, 0] + b[:, 2] / 2, b[:, 1] + b[:, 3] / 2], axis=1)
        else:
            edges = b[:, :4]
        # Normalised boxes lie in the image (as albumentations requires): beyond it is a box in
        # pixels given under a normalised format's name.
        outside = ((edges < -_NORMALISED_SLACK) | (edges > 1 + _NORMALISED_SLACK)).any(axis=1)
        if outside.any():
            i = int(np.flatnonzero(outside)[0])
            raise ValueError(f"bboxes: box {i} {tuple(b[i, :4].tolist())} reaches outside the image "
                             f"(edges outside [0, 1]) {terms}; boxes in pixels are bbox_format='pascal_voc' "
                             "or 'coco'")
        return edges * np.array([w, h, w, h], np.float64)

    def _boxes_from_pixels(self, p, w, h):
        """N pascal_voc pixel boxes in the transform's bbox_format."""
        fmt = self.bbox_format
        if fmt == "pascal_voc":
            return p.copy()
        if fmt == "coco":
            return np.stack([p[:, 0], p[:, 1], p[:, 2] - p[:, 0], p[:, 3] - p[:, 1]], axis=1)
        n = p / np.array([w, h, w, h], np.float64)
        if fmt == "albumentations":
            return n
        return np.stack([(n[:, 0] + n[:, 2]) / 2, (n[:, 1] + n[:, 3]) / 2, n[:, 2] - n[:, 0], n[:, 3] - n[:, 1]],
                        axis=1)

    def _move_boxes(self, bboxes, deformer, pose, w, h):
        b, extras = self._split(bboxes, 4, "bboxes")
        self._check_finite(b[:, :4], "bboxes", "box")
        given = self._boxes_to_pixels(b, w, h)
        moved = given.copy()
        if deformer is not None and len(b):
            outlines = [box_outline(box) for box in given]
            points = deformer.transform_points(pose, np.concatenate(outlines))
            start = 0
            for i, outline in enumerate(outlines):
                p = points[start:start + len(outline)]
                start += len(outline)
                moved[i, 0:2] = p.min(axis=0) + 0.5
                moved[i, 2:4] = p.max(axis=0) + 0.5
        moved[:, 0:4:2] = np.clip(moved[:, 0:4:2], 0, w)
        moved[:, 1:4:2] = np.clip(moved[:, 1:4:2], 0, h)
        visible = (moved[:, 2] > moved[:, 0]) & (moved[:, 3] > moved[:, 1])
        keep = visible if self.remove_invisible else np.ones(len(b), bool)
        result = b.copy()
        result[:, :4] = self._boxes_from_pixels(moved, w, h)
        # A box the warp leaves where it was comes back as given, not through two conversions'
        # rounding (x + width - x is not always width in floating point).
        same = (moved == given).all(axis=1)
        result[same, :4] = b[same, :4]
        return self._join(bboxes, result if extras is None else result[:, :4], extras, keep), visible


class TorchMulticageWarp:
    """MulticageWarp for torchvision pipelines: inside a torchvision.transforms.Compose, on a
    CHW tensor (uint8 or float, 1, 3 or 4 channels) or a dict of tensors ('image', 'mask' HxW,
    'keypoints' Nx2+, 'boxes' Nx4+; a str 'name' names the image for the cage cache; the
    wrapped warp's label_fields and keypoint_label_fields, tensors or lists, are filtered with
    the boxes and keypoints; other keys pass through), giving the same type back. Boxes and
    keypoints are in the warp's bbox_format and keypoint_format.

    Its seed comes from torch's generator (torch.randint), so the usual pattern of seeding
    torch per sample (torch.manual_seed(f(index)) in Dataset.__getitem__) makes every random
    transform of the Compose, this one included, the same in any worker; index= is not
    needed. The warp itself is the wrapped MulticageWarp's (same options, same caches)."""

    def __init__(self, warp=None, **options):
        self.warp = warp if warp is not None else MulticageWarp(**options)

    def __repr__(self):
        return f"TorchMulticageWarp({self.warp!r})"

    def __call__(self, sample):
        import torch

        seed = int(torch.randint(0, 2**62, (1,)).item())
        if isinstance(sample, dict):
            image = sample["image"]
            kwargs = {"image": self._to_numpy(image)}
            if "mask" in sample:
                kwargs["mask"] = sample["mask"].numpy()
            if "keypoints" in sample:
                kwargs["keypoints"] = sample["keypoints"].numpy()
            if "boxes" in sample:
                kwargs["bboxes"] = sample["boxes"].numpy()
            if isinstance(sample.get("name"), str):
                kwargs["name"] = sample["name"]  # the cage cache's key (else the image's content)
            labels = [f for f in self.warp.label_fields + self.warp.keypoint_label_fields if f in sample]
            for field in labels:
                value = sample[field]
                kwargs[field] = value.numpy() if isinstance(value, torch.Tensor) else value
            out = self.warp(seed=seed, **kwargs)
            result = dict(sample)
            result["image"] = self._to_tensor(out["image"], image)
            if "mask" in sample:
                result["mask"] = torch.from_numpy(np.ascontiguousarray(out["mask"]))
            if "keypoints" in sample:
                result["keypoints"] = torch.from_numpy(np.ascontiguousarray(out["keypoints"]))
                result["keypoints_visible"] = torch.from_numpy(out["keypoints_visible"])
            if "boxes" in sample:
                result["boxes"] = torch.from_numpy(np.ascontiguousarray(out["bboxes"]))
                result["boxes_visible"] = torch.from_numpy(out["bboxes_visible"])
            for field in labels:
                value = out[field]
                if isinstance(value, np.ndarray):
                    value = torch.from_numpy(np.ascontiguousarray(value))
                result[field] = value
            return result
        return self._to_tensor(self.warp(image=self._to_numpy(sample), seed=seed)["image"], sample)

    @staticmethod
    def _to_numpy(tensor):
        if tensor.ndim != 3:
            raise ValueError(f"TorchMulticageWarp: expected a CHW tensor, got shape {tuple(tensor.shape)}")
        a = tensor.detach().cpu().numpy()
        return np.ascontiguousarray(a.transpose(1, 2, 0) if a.shape[0] > 1 else a[0])

    @staticmethod
    def _to_tensor(array, like):
        import torch

        a = array if array.ndim == 3 else array[:, :, None]
        return torch.from_numpy(np.ascontiguousarray(a.transpose(2, 0, 1))).to(like.dtype)

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

Conventions are the package's: images as cv2 gives them (HxW, HxWxC; uint8, uint16, float32),
points (x, y) with pixel (x, y) at its centre, so the image spans [-0.5, w - 0.5) in x; boxes
are pascal_voc (x_min, y_min, x_max, y_max) in pixel edges (the box of mask pixels x0..x1-1 is
x0..x1), as albumentations has them; columns after the first 2 (keypoints) or 4 (boxes) are
carried along unchanged (labels, angles...).

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
                  pose_options=None)

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

    The transform pickles (without its caches) for workers.
    """

    def __init__(self, amplitude=10.0, grid_step=4, *, map_step=None, p=1.0, seed=None, coordinates=None, cage=None,
                 cages=None, cage_dir=None, propose=True, protect=True, propose_options=None,
                 no_subject="default", border_mode="constant", border_value=0, mask_value=0,
                 remove_invisible=False, backend="cpu", pose_options=None, fold_check="coarse",
                 cache_size=16):
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

    def _binding(self, key, cage, size):
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

    def _deformer(self, key, cage, image):
        dkey = (_cage_digest(cage), image.shape, image.dtype.str)
        with self._lock:
            d = self._deformers.get(dkey)
            if d is not None:
                self._deformers.move_to_end(dkey)
        if d is None:
            size = (image.shape[1], image.shape[0])
            _, binding = self._binding(key, cage, size)
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
        rng = np.random.default_rng(np.random.SeedSequence([seed, 0x6d63]))
        return rng.random() < self.p, seed

    def __call__(self, *, image=None, mask=None, masks=None, keypoints=None, bboxes=None, name=None,
                 index=None, seed=None, return_params=False, **other):
        """The targets moved by one random deformation: a dict with the keys given (other keys
        are passed through unchanged), plus 'keypoints_visible' / 'bboxes_visible' (a bool per
        input keypoint / box: inside the output) when keypoints / boxes were given, and
        'replay' when return_params. name: the image's name (cage mapping, proposal cache);
        index: the sample's index (seeding, see the module's doc); seed: this call's seed."""
        if image is None:
            raise ValueError("MulticageWarp: image= is required (the deformation is drawn for its size)")
        image = np.asarray(image)
        applied, call_seed = self._draw(index, seed)
        params = {"applied": False, "seed": call_seed, "pose": None, "cage_key": None, "cage": None,
                  "image_size": (image.shape[1], image.shape[0]), "grid_step": self.grid_step,
                  "map_step": self.map_step, "amplitude": self.amplitude}
        if applied:
            key, cage = self._cage_for(image, name)
            if cage is not None:
                scaled, binding = self._binding(key, cage, params["image_size"])
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
        deformer = pose = None
        if params["applied"]:
            key, cage = params["cage_key"], params["cage"]  # the cage travels with the params
            deformer = self._deformer(key, cage, image)
            pose = params["pose"]
        need_maps = deformer is not None and (mask is not None or masks is not None
                                              or self.border_mode != cv2.BORDER_CONSTANT)
        maps = deformer.compute_maps(pose, *self._map_buffers(w, h)) if need_maps else None
        if deformer is None:
            out["image"] = image.copy()
        elif maps is None:
            out["image"] = deformer.deform(pose, image=image)
        else:
            out["image"] = cv2.remap(image, maps[0], maps[1], cv2.INTER_LINEAR, borderMode=self.border_mode,
                                     borderValue=self._cv_border(self.border_value))
        if mask is not None:
            out["mask"] = self._move_mask(np.asarray(mask), maps, (w, h))
        if masks is not None:
            out["masks"] = [self._move_mask(np.asarray(m), maps, (w, h)) for m in masks]
        if keypoints is not None:
            out["keypoints"], out["keypoints_visible"] = self._move_keypoints(keypoints, deformer, pose, w, h)
        if bboxes is not None:
            out["bboxes"], out["bboxes_visible"] = self._move_boxes(bboxes, deformer, pose, w, h)
        if return_params:
            params["pose"] = None if params["pose"] is None else np.array(params["pose"], np.float32)
            out["replay"] = params
        return out

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
        k, extras = self._split(keypoints, 2, "keypoints")
        self._check_finite(k[:, :2], "keypoints", "keypoint")
        moved = k.copy()
        if deformer is not None and len(k):
            moved[:, :2] = deformer.transform_points(pose, k[:, :2].astype(np.float32))
        x, y = moved[:, 0], moved[:, 1]
        visible = (x >= -0.5) & (x < w - 0.5) & (y >= -0.5) & (y < h - 0.5)
        keep = visible if self.remove_invisible else np.ones(len(k), bool)
        return self._join(keypoints, moved if extras is None else moved[:, :2], extras, keep), visible

    def _move_boxes(self, bboxes, deformer, pose, w, h):
        b, extras = self._split(bboxes, 4, "bboxes")
        self._check_finite(b[:, :4], "bboxes", "box")
        inverted = (b[:, 2] < b[:, 0]) | (b[:, 3] < b[:, 1])
        if inverted.any():
            i = int(np.flatnonzero(inverted)[0])
            raise ValueError(f"bboxes: box {i} {tuple(b[i, :4].tolist())} has its maximum before its "
                             "minimum (pascal_voc boxes are x_min, y_min, x_max, y_max)")
        moved = b.copy()
        if deformer is not None and len(b):
            outlines = [box_outline(box) for box in b]
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
        if extras is None:
            return self._join(bboxes, moved, None, keep), visible
        return self._join(bboxes, moved[:, :4], extras, keep), visible


class TorchMulticageWarp:
    """MulticageWarp for torchvision pipelines: inside a torchvision.transforms.Compose, on a
    CHW tensor (uint8 or float, 1, 3 or 4 channels) or a dict of tensors ('image', 'mask' HxW,
    'keypoints' Nx2+, 'boxes' Nx4+; a str 'name' names the image for the cage cache; other keys
    pass through), giving the same type back.

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
            return result
        return self._to_tensor(self.warp(image=self._to_numpy(sample), seed=seed)["image"], sample)

    @staticmethod
    def _to_numpy(tensor):
        if tensor.ndim != 3:
            raise ValueError(f"TorchMulticageWarp: expected a CHW tensor, got shape {tuple(tensor.shape)}")
        a = tensor.detach().cpu().numpy()
        if a.dtype == np.float64:
            a = a.astype(np.float32)
        return np.ascontiguousarray(a.transpose(1, 2, 0) if a.shape[0] > 1 else a[0])

    @staticmethod
    def _to_tensor(array, like):
        import torch

        a = array if array.ndim == 3 else array[:, :, None]
        return torch.from_numpy(np.ascontiguousarray(a.transpose(2, 0, 1))).to(like.dtype)

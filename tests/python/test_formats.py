"""Issue 40, item 7: boxes and keypoints as albumentations users give them. bbox_format
('pascal_voc', 'coco', 'yolo', 'albumentations') against the moved mask's box, exact round
trips, errors in the format's own terms; label_fields filtered with the boxes; keypoint angle
and scale columns carried by the local linear map; float64 images."""

import numpy as np
import pytest

import multicage as mc
from conftest import box_mask, mask_box, square

FORMATS = ("pascal_voc", "coco", "yolo", "albumentations")


@pytest.fixture()
def cage(butterfly_cage):
    return butterfly_cage


# Conversions written out here, apart from the module's, so that a wrong one there shows.
def from_voc(box, fmt, w, h):
    x0, y0, x1, y1 = (float(v) for v in box)
    return {"pascal_voc": (x0, y0, x1, y1),
            "coco": (x0, y0, x1 - x0, y1 - y0),
            "yolo": ((x0 + x1) / (2 * w), (y0 + y1) / (2 * h), (x1 - x0) / w, (y1 - y0) / h),
            "albumentations": (x0 / w, y0 / h, x1 / w, y1 / h)}[fmt]


def to_voc(box, fmt, w, h):
    a, b, c, d = (float(v) for v in box[:4])
    return np.array({"pascal_voc": (a, b, c, d),
                     "coco": (a, b, a + c, b + d),
                     "yolo": ((a - c / 2) * w, (b - d / 2) * h, (a + c / 2) * w, (b + d / 2) * h),
                     "albumentations": (a * w, b * h, c * w, d * h)}[fmt])


# --- box formats -------------------------------------------------------------------------------

@pytest.mark.parametrize("fmt", FORMATS)
def test_each_format_matches_the_moved_mask_box(butterfly, cage, fmt):
    """A box given in each format comes back, in that format, within 1 px of the box of the
    moved mask of the box, and where the pascal_voc box of the same warp goes."""
    h, w = butterfly.shape[:2]
    warp = mc.MulticageWarp(amplitude=30, grid_step=4, cage=cage, seed=5, bbox_format=fmt)
    voc = mc.MulticageWarp(amplitude=30, grid_step=4, cage=cage, seed=5)
    rng = np.random.default_rng(1)
    worst = moved_most = 0.0
    for i in range(4):
        x0, y0 = rng.integers(20, w // 2), rng.integers(20, h // 2)
        box = (x0, y0, x0 + rng.integers(30, w // 2 - 10), y0 + rng.integers(30, h // 2 - 10))
        given = from_voc(box, fmt, w, h)
        out = warp(image=butterfly, mask=box_mask((h, w), box), bboxes=np.array([given]), index=i)
        assert out["bboxes"].dtype == np.float64 and out["bboxes"].shape == (1, 4)
        got = to_voc(out["bboxes"][0], fmt, w, h)
        worst = max(worst, np.abs(got - mask_box(out["mask"])).max())
        moved_most = max(moved_most, np.abs(got - np.array(box, np.float64)).max())
        # A normalised box's pixel edges carry rounding (230.0000001): its outline is sampled a
        # point more, which moves the bounds by hundredths of a pixel.
        np.testing.assert_allclose(got, voc(image=butterfly, bboxes=[box], index=i)["bboxes"][0][:4],
                                   atol=1e-6 if fmt in ("pascal_voc", "coco") else 0.05)
        # A list of tuples with a label column gives the same box and keeps the label.
        listed = warp(image=butterfly, bboxes=[given + ("wing",)], index=i)["bboxes"][0]
        assert listed[4] == "wing"
        np.testing.assert_allclose(listed[:4], out["bboxes"][0], rtol=0, atol=1e-12)
    assert worst <= 1.0, f"{fmt} box off the moved mask's box by {worst:.2f} px"
    assert moved_most > 2.0, "the warp moves the boxes (else the comparison proves nothing)"


@pytest.mark.parametrize("fmt", FORMATS)
def test_boxes_come_back_exactly_when_not_moved(butterfly, cage, fmt):
    """Without a warp (p=0) boxes come back bit for bit as given, in every format, arrays
    (float32 and float64) and lists alike; no conversion's rounding shows."""
    h, w = butterfly.shape[:2]
    voc = [(0.1, 0.7, 200.3, 100.9), (13.0 / 3, 1.0 / 7, 492.9, 355.1), (0.0, 0.0, float(w), float(h))]
    boxes = np.array([from_voc(b, fmt, w, h) for b in voc])
    never = mc.MulticageWarp(amplitude=30, cage=cage, p=0.0, bbox_format=fmt)
    for given in (boxes, boxes.astype(np.float32), np.hstack([boxes, [[1], [2], [3]]])):
        out = never(image=butterfly, bboxes=given, index=0)["bboxes"]
        assert out.dtype == given.dtype
        assert np.array_equal(out, given)
    listed = [tuple(b) + ("label",) for b in boxes.tolist()]
    assert never(image=butterfly, bboxes=listed, index=0)["bboxes"] == listed


def test_box_errors_speak_the_format(butterfly, cage):
    def call(fmt, boxes):
        return mc.MulticageWarp(amplitude=5, cage=cage, bbox_format=fmt)(image=butterfly, bboxes=boxes, seed=1)

    # The COCO box: refused as pascal_voc (its width is below its x), taken as coco.
    with pytest.raises(ValueError, match=r"maximum before its minimum \(pascal_voc boxes"):
        call("pascal_voc", [(300, 50, 100, 100)])
    assert call("coco", [(300, 50, 100, 100)])["bboxes_visible"].tolist() == [True]
    with pytest.raises(ValueError, match=r"bboxes: box 1 \(300.0, 50.0, -100.0, 100.0\) has a negative width "
                                         r"\(coco boxes are x_min, y_min, width, height in pixels\)"):
        call("coco", [(1, 1, 5, 5), (300, 50, -100, 100)])
    with pytest.raises(ValueError, match=r"negative height \(yolo boxes are x_center"):
        call("yolo", [(0.5, 0.5, 0.2, -0.1)])
    with pytest.raises(ValueError, match=r"outside the image .*yolo boxes are x_center.*bbox_format='pascal_voc'"):
        call("yolo", [(300, 50, 100, 100)])  # pixels given as yolo
    with pytest.raises(ValueError, match=r"box 0 .*outside the image .*\(albumentations boxes"):
        call("albumentations", [(0.2, 0.2, 1.5, 0.9)])
    with pytest.raises(ValueError, match=r"maximum before its minimum \(albumentations boxes"):
        call("albumentations", [(0.5, 0.2, 0.4, 0.9)])
    with pytest.raises(ValueError, match="bboxes: box 0 is not finite"):
        call("yolo", [(np.nan, 0.5, 0.1, 0.1)])
    # Rounding of a label file's 6 decimals is no error.
    assert len(call("yolo", [(0.5, 0.5, 1.0000005, 1.0)])["bboxes"]) == 1
    with pytest.raises(ValueError, match="bbox_format: one of"):
        mc.MulticageWarp(bbox_format="xyxy")
    with pytest.raises(ValueError, match="keypoint_format: one of"):
        mc.MulticageWarp(keypoint_format="xyz")


# --- label fields ------------------------------------------------------------------------------

def test_label_fields_are_filtered_with_their_boxes_and_keypoints(butterfly, cage):
    h, w = butterfly.shape[:2]
    boxes = [(-40, -40, 30, 30), (10, 10, 40, 40), (w + 5, 20, 10, 10), (100, 120, 50, 30)]  # coco
    points = [(100.0, 100.0), (-3.0, 50.0), (300.0, 200.0)]
    kwargs = dict(image=butterfly, bboxes=boxes, classes=["off", "on", "off too", "on too"],
                  scores=np.array([0.1, 0.2, 0.3, 0.4]), keypoints=points, joints=["eye", "gone", "tip"],
                  note="kept", seed=1)
    options = dict(amplitude=10, cage=cage, bbox_format="coco", label_fields=["classes", "scores"],
                   keypoint_label_fields="joints")
    out = mc.MulticageWarp(remove_invisible=True, **options)(**kwargs)
    np.testing.assert_array_equal(out["bboxes_visible"], [False, True, False, True])
    assert out["classes"] == ["on", "on too"] and len(out["bboxes"]) == 2
    np.testing.assert_array_equal(out["scores"], [0.2, 0.4])
    np.testing.assert_array_equal(out["keypoints_visible"], [True, False, True])
    assert out["joints"] == ["eye", "tip"] and len(out["keypoints"]) == 2
    assert out["note"] == "kept"
    kept = mc.MulticageWarp(**options)(**kwargs)  # without remove_invisible: all, as given
    assert kept["classes"] == kwargs["classes"] and kept["joints"] == kwargs["joints"]
    assert len(kept["bboxes"]) == 4
    # The same through replay.
    warp = mc.MulticageWarp(remove_invisible=True, **options)
    params = warp(return_params=True, **kwargs)["replay"]
    again = warp.replay(params, **{k: v for k, v in kwargs.items() if k != "seed"})
    assert again["classes"] == ["on", "on too"] and again["joints"] == ["eye", "tip"]
    with pytest.raises(ValueError, match=r"label_fields: classes= has 3 items for 4 bboxes"):
        warp(**{**kwargs, "classes": ["a", "b", "c"]})
    with pytest.raises(ValueError, match=r"label_fields: scores= was not passed with bboxes="):
        warp(**{k: v for k, v in kwargs.items() if k != "scores"})
    with pytest.raises(ValueError, match=r"keypoint_label_fields: joints= has 2 items for 3 keypoints"):
        warp(**{**kwargs, "joints": ["a", "b"]})
    with pytest.raises(ValueError, match="keyword of the call"):
        mc.MulticageWarp(label_fields=["mask"])
    with pytest.raises(ValueError, match="both name 'labels'"):
        mc.MulticageWarp(label_fields=["labels"], keypoint_label_fields=["labels"])
    with pytest.raises(TypeError, match="label_fields"):
        mc.MulticageWarp(label_fields=[3])


def test_torch_wrapper_filters_label_fields(butterfly, cage):
    torch = pytest.importorskip("torch")
    h, w = butterfly.shape[:2]
    adapter = mc.TorchMulticageWarp(amplitude=8, cage=cage, bbox_format="albumentations", label_fields=["labels"],
                                    remove_invisible=True)
    sample = {"image": torch.from_numpy(butterfly.transpose(2, 0, 1).copy()).double(),
              "boxes": torch.tensor([[0.1, 0.1, 0.3, 0.3], [0.0, 0.0, 0.0, 0.5], [0.5, 0.5, 0.9, 0.8]]),
              "labels": torch.tensor([1, 2, 3])}
    torch.manual_seed(0)
    out = adapter(sample)
    assert out["image"].dtype == torch.float64 and out["image"].shape == sample["image"].shape
    assert out["labels"].tolist() == [1, 3] and out["boxes"].shape == (2, 4)
    assert out["boxes"].dtype == torch.float32 and float(out["boxes"].max()) <= 1.0
    # issue 41: the wrapper keeps which boxes were visible, one flag per box given
    assert out["boxes_visible"].tolist() == [True, False, True]


# --- keypoint angle and scale ------------------------------------------------------------------

SIZE = (200, 160)
ROTATION, SCALE = 25.0, 1.3


def similarity_warp():
    """A transform, its replay parameters and a pose that turns a square polygon by ROTATION
    degrees and scales it by SCALE about its centre. Bound with local mean value coordinates,
    what the polygon holds follows it alone: an exact similarity inside it."""
    w, h = SIZE
    cage = mc.Multicage(SIZE)
    cage.add_polygon(square(60, 40, 140, 120))
    cage.orient()
    cage.coordinates = "local_mean_value"
    image = np.tile(np.linspace(0, 255, w, dtype=np.float32), (h, 1))
    rest = cage.rest_pose()
    centre = rest.mean(axis=0)
    t = np.radians(ROTATION)
    rotation = np.array([[np.cos(t), -np.sin(t)], [np.sin(t), np.cos(t)]])
    pose = ((rest - centre) @ rotation.T * SCALE + centre).astype(np.float32)
    assert mc.validate_pose(cage, pose)[0]
    return cage, image, pose, lambda p: (np.asarray(p, np.float64) - centre) @ rotation.T * SCALE + centre


@pytest.mark.parametrize("fmt,degrees", [("xyas", True), ("xysa", True), ("xyas", False), ("xya", True),
                                         ("xys", True)])
def test_angle_and_scale_follow_a_similarity(fmt, degrees):
    cage, image, pose, similar = similarity_warp()
    warp = mc.MulticageWarp(amplitude=1, grid_step=2, cage=cage, keypoint_format=fmt, angle_in_degrees=degrees)
    params = dict(warp(image=image, index=0, return_params=True)["replay"], pose=pose)
    full = 360.0 if degrees else 2 * np.pi
    turn = ROTATION if degrees else np.radians(ROTATION)
    xy = np.array([[100.0, 80.0], [75.0, 55.0], [125.0, 108.0], [-20.0, 50.0]])  # the last: off the image
    angles = np.array([0.0, 350.0, -100.0, 30.0]) * (1 if degrees else np.pi / 180)
    scales = np.array([1.0, 2.5, 10.0, 4.0])
    columns = {"x": xy[:, 0], "y": xy[:, 1], "a": angles, "s": scales}
    given = np.column_stack([columns[c] for c in fmt] + [np.arange(4.0)])  # and an extra column
    out = warp.replay(params, image=image, keypoints=given)["keypoints"]
    got = {c: out[:, i] for i, c in enumerate(fmt)}
    np.testing.assert_allclose(np.column_stack([got["x"], got["y"]])[:3], similar(xy[:3]), atol=1e-3)
    np.testing.assert_array_equal(out[:, len(fmt)], np.arange(4.0))
    if "a" in fmt:
        assert ((got["a"] >= 0) & (got["a"] < full)).all()
        expected = np.mod(angles[:3] + turn, full)
        off = np.abs((got["a"][:3] - expected + full / 2) % full - full / 2)
        assert off.max() < 1e-3 * full / 360, f"angles off by {off.max()}"
        # Off the image the frame holds: the direction stays (given back in [0, 360)).
        assert abs(got["a"][3] - np.mod(angles[3], full)) < 1e-3 * full / 360
    if "s" in fmt:
        np.testing.assert_allclose(got["s"][:3], scales[:3] * SCALE, rtol=1e-4)
        assert abs(got["s"][3] - scales[3]) < 1e-4 * scales[3]
    # yx is xy with the columns swapped.
    yx = mc.MulticageWarp(amplitude=1, grid_step=2, cage=cage, keypoint_format="yx")
    swapped = yx.replay(params, image=image, keypoints=xy[:, ::-1].copy())["keypoints"]
    np.testing.assert_allclose(swapped[:3, ::-1], similar(xy[:3]), atol=1e-3)


def test_angle_and_scale_follow_a_random_warp(butterfly, cage):
    """Under a random warp an angle points where a short arrow drawn at the keypoint goes, and
    a scale changes as the area of a small square around it does (found here with a Deformer
    of the same cage, apart from the transform)."""
    h, w = butterfly.shape[:2]
    warp = mc.MulticageWarp(amplitude=30, grid_step=4, cage=cage, keypoint_format="xyas")
    ys, xs = np.mgrid[30:h - 30:37, 30:w - 30:41]
    xy = np.column_stack([xs.ravel(), ys.ravel()]).astype(np.float64) + 0.3
    angles = np.linspace(0, 720, len(xy), endpoint=False) - 180
    out = warp(image=butterfly, keypoints=np.column_stack([xy, angles, np.full(len(xy), 5.0)]), seed=4,
               return_params=True)
    d = mc.Deformer(butterfly, cage, backend="cpu", grid_step=4)
    pose = out["replay"]["pose"]
    k = out["keypoints"]
    np.testing.assert_allclose(k[:, :2], d.transform_points(pose, xy.astype(np.float32)), atol=1e-4)
    a = np.radians(angles)
    tip = d.transform_points(pose, (xy + 2.0 * np.column_stack([np.cos(a), np.sin(a)])).astype(np.float32))
    arrow = np.degrees(np.arctan2(tip[:, 1] - k[:, 1], tip[:, 0] - k[:, 0]))
    off = np.abs((k[:, 2] - arrow + 180) % 360 - 180)
    assert off.max() < 2.0, f"an angle is {off.max():.2f} degrees from its arrow"
    turned = np.abs((k[:, 2] - angles + 180) % 360 - 180)
    assert turned.max() > 2.0, "the warp turns some keypoints (else the comparison proves nothing)"
    r = 2.0
    corners = np.array([[-r, -r], [r, -r], [r, r], [-r, r]])
    quads = d.transform_points(pose, (xy[:, None, :] + corners[None]).astype(np.float32)).astype(np.float64)
    x, y = quads[..., 0], quads[..., 1]
    area = 0.5 * np.abs((x * np.roll(y, -1, 1) - np.roll(x, -1, 1) * y).sum(axis=1))
    np.testing.assert_allclose(k[:, 3], 5.0 * np.sqrt(area / (2 * r) ** 2), rtol=0.03)
    assert np.abs(k[:, 3] / 5.0 - 1).max() > 0.02, "the warp scales some keypoints"


def test_keypoint_format_rows_are_checked(butterfly, cage):
    warp = mc.MulticageWarp(amplitude=5, cage=cage, keypoint_format="xya")
    with pytest.raises(ValueError, match=r"keypoints \(keypoint_format 'xya'\): every item needs 3"):
        warp(image=butterfly, keypoints=[(1.0, 2.0)], seed=1)
    with pytest.raises(ValueError, match=r"keypoint_format 'xya'\): keypoint 0 is not finite"):
        warp(image=butterfly, keypoints=[(1.0, 2.0, np.nan)], seed=1)
    never = mc.MulticageWarp(amplitude=5, cage=cage, keypoint_format="xysa", p=0)
    rows = [(1.5, 2.5, 3.0, -400.0, "label")]
    assert never(image=butterfly, keypoints=rows, seed=1)["keypoints"] == rows, "not moved: as given"


# --- float64 images ----------------------------------------------------------------------------

def test_float64_images_warp_as_float32(butterfly, cage):
    image32 = (butterfly / 255.0).astype(np.float32)
    image64 = image32.astype(np.float64)
    warp = mc.MulticageWarp(amplitude=15, cage=cage, seed=2)
    mask = box_mask(butterfly.shape[:2], (100, 80, 300, 250))
    for extra in ({}, {"mask": mask}):  # the deformer's own path and the maps path
        out64 = warp(image=image64, index=3, **extra)
        out32 = warp(image=image32, index=3, **extra)
        assert out64["image"].dtype == np.float64 and out64["image"].shape == image64.shape
        np.testing.assert_array_equal(out64["image"], out32["image"].astype(np.float64))
        assert not np.array_equal(out64["image"], image64)
    params = warp(image=image64, index=3, return_params=True)["replay"]
    np.testing.assert_array_equal(warp.replay(params, image=image64)["image"], out64["image"])
    never = mc.MulticageWarp(amplitude=15, cage=cage, p=0)(image=image64 + 1e-12, index=0)["image"]
    assert never.dtype == np.float64 and np.array_equal(never, image64 + 1e-12), "not warped: as given"

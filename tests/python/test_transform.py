"""Issue 23: MulticageWarp, one albumentations-style transform (images bilinear, masks nearest,
keypoints flagged, boxes from the moved outline), cages given / mapped / proposed and cached,
per-sample seeding equal across worker processes, and exact replay."""

import multiprocessing
import pickle

import cv2
import numpy as np
import pytest

import multicage as mc
from conftest import SAMPLES, box_mask, mask_box


@pytest.fixture()
def cage():
    return mc.Multicage.load(str(SAMPLES / "butterfly.yml"))


# --- the targets --------------------------------------------------------------------------------

def test_call_returns_the_same_keys_moved_by_one_deformation(butterfly, cage):
    """Every target moves by the deformation the replay names: the image is the Deformer's
    bilinear output for that pose, the mask cv2.remap nearest of its maps, keypoints its
    transform_points; other keys pass through."""
    warp = mc.MulticageWarp(amplitude=15, grid_step=4, cage=cage, seed=3)
    h, w = butterfly.shape[:2]
    labels = (np.arange(h * w) % 7).reshape(h, w).astype(np.uint8)
    points = np.array([[100.0, 80.0], [250.0, 200.0], [400.0, 300.0]], np.float32)
    out = warp(image=butterfly, mask=labels, masks=[labels, labels * 2], keypoints=points,
               bboxes=[(50, 40, 200, 150, "wing")], label=17, index=0, return_params=True)
    assert set(out) == {"image", "mask", "masks", "keypoints", "keypoints_visible", "bboxes",
                        "bboxes_visible", "label", "replay"}
    assert out["label"] == 17
    params = out["replay"]
    assert params["applied"] and params["cage_key"] == "given"
    pose = params["pose"]
    assert not np.array_equal(pose, cage.rest_pose()), "a pose of amplitude 15 moves the cage"
    assert warp.map_step == 4, "map_step None: the grid step"
    d = mc.Deformer(butterfly, cage, backend="cpu", grid_step=4, map_step=4)
    mapx, mapy = d.compute_maps(pose)
    exact = mc.Deformer(butterfly, cage, backend="cpu", grid_step=4).compute_maps(pose)
    offset = np.hypot(mapx - exact[0], mapy - exact[1])
    assert 0 < offset.mean() < 0.01, "the maps of a lattice 4 px apart: off by the grid step's kind of error"
    assert out["image"].shape == butterfly.shape and out["image"].dtype == butterfly.dtype
    np.testing.assert_array_equal(out["image"], d.deform(pose))
    np.testing.assert_array_equal(out["mask"], cv2.remap(labels, mapx, mapy, cv2.INTER_NEAREST))
    np.testing.assert_array_equal(out["masks"][1], cv2.remap(labels * 2, mapx, mapy, cv2.INTER_NEAREST))
    assert set(np.unique(out["mask"])) <= set(range(7)), "nearest: no blended labels"
    np.testing.assert_allclose(out["keypoints"], d.transform_points(pose, points), atol=1e-5)
    assert out["bboxes"][0][4] == "wing"
    assert not np.array_equal(out["image"], butterfly)


def test_image_alone_equals_the_maps_path(butterfly, cage):
    """The fast path (image only: Deformer.deform(image=)) and the maps path (with a mask:
    compute_maps + cv2.remap) give the same pixels."""
    warp = mc.MulticageWarp(amplitude=12, grid_step=2, cage=cage, seed=9)
    alone = warp(image=butterfly, index=4)["image"]
    with_mask = warp(image=butterfly, mask=np.zeros(butterfly.shape[:2], np.uint8), index=4)["image"]
    np.testing.assert_array_equal(alone, with_mask)


@pytest.mark.parametrize("step", [1, 4])
def test_boxes_match_the_moved_mask_box_within_a_pixel(butterfly, cage, step):
    """A box becomes the bounds of its moved outline: within 1 px of the box of the moved mask
    of that box (remapped nearest), where the box of the four moved corners is not."""
    warp = mc.MulticageWarp(amplitude=30, grid_step=step, cage=cage, seed=5)
    h, w = butterfly.shape[:2]
    rng = np.random.default_rng(0)
    worst = worst_corners = 0.0
    for i in range(6):
        x0, y0 = rng.integers(20, w // 2), rng.integers(20, h // 2)
        box = (x0, y0, x0 + rng.integers(30, w // 2 - 10), y0 + rng.integers(30, h // 2 - 10))
        corners = np.array([[box[0], box[1]], [box[2], box[1]], [box[2], box[3]], [box[0], box[3]]],
                           np.float32) - 0.5
        out = warp(image=butterfly, mask=box_mask((h, w), box), bboxes=np.array([box], np.float32),
                   keypoints=corners, index=i)
        expected = mask_box(out["mask"])
        worst = max(worst, np.abs(out["bboxes"][0] - expected).max())
        k = out["keypoints"] + 0.5
        four = np.array([k[:, 0].min(), k[:, 1].min(), k[:, 0].max(), k[:, 1].max()])
        worst_corners = max(worst_corners, np.abs(four - expected).max())
    assert worst <= 1.0, f"box off the moved mask's box by {worst:.2f} px"
    assert worst_corners > 1.5, "the warp bends edges: four moved corners make a box too small"


def test_keypoints_outside_are_flagged_and_dropped_when_asked(butterfly, cage):
    h, w = butterfly.shape[:2]
    points = [(100.0, 100.0, "eye"), (-3.0, 50.0, "gone"), (w + 2.0, 10.0, "gone too"), (300.0, 200.0, "tip")]
    out = mc.MulticageWarp(amplitude=10, cage=cage)(image=butterfly, keypoints=points, seed=1)
    np.testing.assert_array_equal(out["keypoints_visible"], [True, False, False, True])
    assert [p[2] for p in out["keypoints"]] == ["eye", "gone", "gone too", "tip"]
    dropped = mc.MulticageWarp(amplitude=10, cage=cage, remove_invisible=True)(
        image=butterfly, keypoints=points, bboxes=[(-40, -40, -10, -10, "off"), (10, 10, 50, 50, "on")], seed=1)
    assert [p[2] for p in dropped["keypoints"]] == ["eye", "tip"]
    assert dropped["keypoints"][0][:2] == out["keypoints"][0][:2]
    assert [b[4] for b in dropped["bboxes"]] == ["on"]
    np.testing.assert_array_equal(dropped["bboxes_visible"], [False, True])


@pytest.mark.parametrize("border", ["constant", "reflect"])
def test_masks_of_any_dtype_move_as_uint8_masks_do(butterfly, cage, border):
    # bool, int64, uint32 and float16 masks (cv2.remap refuses or narrows them) and a mask of
    # 6 channels pick the same nearest pixels as a uint8 mask, and keep their dtype.
    h, w = butterfly.shape[:2]
    labels = (np.random.default_rng(3).random((h, w)) * 5).astype(np.uint8)
    labels[0, :] = 4  # a border row, so that reflect copies a known value
    warp = mc.MulticageWarp(amplitude=20, cage=cage, seed=5, border_mode=border, mask_value=0)
    reference = warp(image=butterfly, mask=labels, index=2)["mask"]
    for dtype in (bool, np.int64, np.uint32, np.float16):
        m = labels.astype(dtype) if dtype is not bool else labels > 0
        out = warp(image=butterfly, mask=m, masks=[m], index=2)
        expected = reference if dtype is not bool else reference > 0
        for moved in (out["mask"], out["masks"][0]):
            assert moved.dtype == np.dtype(dtype) and moved.shape == (h, w)
            np.testing.assert_array_equal(moved, expected.astype(dtype))
    many = warp(image=butterfly, mask=np.repeat(labels[..., None], 6, axis=2), index=2)["mask"]
    assert many.shape == (h, w, 6)
    for c in range(6):
        np.testing.assert_array_equal(many[..., c], reference)


def test_bad_boxes_and_keypoints_are_named(butterfly, cage):
    warp = mc.MulticageWarp(amplitude=10, cage=cage)
    with pytest.raises(ValueError, match=r"bboxes: box 1 \(50.0, 40.0, 10.0, 60.0\) has its maximum before"):
        warp(image=butterfly, bboxes=[(1, 1, 5, 5), (50, 40, 10, 60)], seed=1)
    with pytest.raises(ValueError, match="bboxes: box 0 is not finite"):
        warp(image=butterfly, bboxes=[(np.nan, 1, 5, 5)], seed=1)
    with pytest.raises(ValueError, match="keypoints: keypoint 1 is not finite"):
        warp(image=butterfly, keypoints=[(3.0, 4.0), (np.inf, 2.0)], seed=1)
    # A box of no width (a line) is kept: only a maximum before its minimum is refused.
    out = warp(image=butterfly, bboxes=[(20, 20, 20, 60)], seed=1)
    assert len(out["bboxes"]) == 1


def test_border_mode_and_probability(butterfly, cage):
    never = mc.MulticageWarp(amplitude=10, cage=cage, p=0.0)
    out = never(image=butterfly, keypoints=np.array([[5.0, 5.0]], np.float32), index=1, return_params=True)
    np.testing.assert_array_equal(out["image"], butterfly)
    assert not out["replay"]["applied"]
    half = mc.MulticageWarp(amplitude=10, cage=cage, p=0.5, seed=2)
    applied = [half(image=butterfly, index=i, return_params=True)["replay"]["applied"] for i in range(16)]
    assert 0 < sum(applied) < 16
    assert applied == [half(image=butterfly, index=i, return_params=True)["replay"]["applied"] for i in range(16)]
    rep = mc.MulticageWarp(amplitude=10, cage=cage, border_mode="replicate", seed=2)(image=butterfly, index=0)
    assert rep["image"].shape == butterfly.shape
    with pytest.raises(ValueError, match="border_mode"):
        mc.MulticageWarp(border_mode="mirror")
    with pytest.raises(ValueError, match="p:"):
        mc.MulticageWarp(p=2)


# --- cages --------------------------------------------------------------------------------------

def test_cages_by_name_proposed_cached_and_saved(butterfly, cage, tmp_path, monkeypatch):
    small = cv2.resize(butterfly, (butterfly.shape[1] // 2, butterfly.shape[0] // 2))
    warp = mc.MulticageWarp(amplitude=8, cages={"b.jpg": str(SAMPLES / "butterfly.yml")}, cage_dir=tmp_path, seed=0)
    named = warp(image=small, name="b.jpg", index=0, return_params=True)["replay"]
    assert named["cage_key"] == "name:b.jpg" and named["image_size"] == (small.shape[1], small.shape[0])
    proposed = warp(image=small, name="other.jpg", index=0, return_params=True)["replay"]
    assert proposed["cage_key"] == "proposed:other.jpg"
    assert (tmp_path / "other.yml").exists(), "a proposed cage is saved in cage_dir"
    # A fresh transform (another run) reads the saved cage instead of proposing again.
    import multicage.transforms as transforms
    monkeypatch.setattr(transforms._mc, "propose_multicage", lambda *a, **k: pytest.fail("proposed again"))
    again = mc.MulticageWarp(amplitude=8, cage_dir=tmp_path, seed=0)(image=small, name="other.jpg", index=0,
                                                                      return_params=True)["replay"]
    np.testing.assert_array_equal(again["pose"], proposed["pose"])


def test_binding_cache_is_bounded(butterfly, cage):
    """Bindings are reused per cage and size, and at most cache_size are kept (a dataset of
    proposed cages has one per image)."""
    warp = mc.MulticageWarp(amplitude=5, cage=cage, cache_size=2)
    sizes = [(160, 120), (200, 150), (240, 180)]
    for w, h in sizes + sizes[-1:]:
        warp(image=cv2.resize(butterfly, (w, h)), index=0)
    assert len(warp._bindings) == 2 and len(warp._deformers) == 2
    assert [key[1] for key in warp._bindings] == [(200, 150), (240, 180)]


def test_images_without_a_subject(butterfly):
    flat = np.full((90, 120, 3), 77, np.uint8)
    noise = np.random.default_rng(0).integers(0, 255, (90, 120, 3)).astype(np.uint8)
    default = mc.MulticageWarp(amplitude=6, seed=0)
    out = default(image=noise, index=0, return_params=True)
    assert out["replay"]["applied"] and out["replay"]["cage_key"] == "default:120x90"
    assert not np.array_equal(out["image"], noise), "the default cage still warps the picture"
    assert default(image=flat, index=0, return_params=True)["replay"]["applied"]
    skip = mc.MulticageWarp(amplitude=6, no_subject="skip")(image=noise, index=0, return_params=True)
    assert not skip["replay"]["applied"]
    np.testing.assert_array_equal(skip["image"], noise)
    with pytest.raises(mc.NoObjectFoundError):
        mc.MulticageWarp(no_subject="raise")(image=noise)


# --- seeding and replay -------------------------------------------------------------------------

def test_seeded_per_sample_and_replayed_exactly(butterfly, cage):
    warp = mc.MulticageWarp(amplitude=15, grid_step=4, cage=cage, seed=11)
    mask = box_mask(butterfly.shape[:2], (100, 80, 300, 250))
    a = warp(image=butterfly, mask=mask, index=7, return_params=True)
    b = warp(image=butterfly, mask=mask, index=7)
    c = warp(image=butterfly, mask=mask, index=8)
    other_seed = mc.MulticageWarp(amplitude=15, grid_step=4, cage=cage, seed=12)(image=butterfly, index=7)
    np.testing.assert_array_equal(a["image"], b["image"])
    assert not np.array_equal(a["image"], c["image"])
    assert not np.array_equal(a["image"], other_seed["image"])
    assert a["replay"]["seed"] == mc.sample_seed(11, 7)
    # The parameters travel (pickle) and re-apply exactly in a fresh transform, to new targets too.
    params = pickle.loads(pickle.dumps(a["replay"]))
    fresh = mc.MulticageWarp(amplitude=99, grid_step=4, seed=0,  # only grid_step matters
                             cage=mc.default_multicage((butterfly.shape[1], butterfly.shape[0])))
    fresh(image=butterfly, index=0)  # its own cage bound first: the replay must not take it
    r = fresh.replay(params, image=butterfly, mask=mask, keypoints=np.array([[150.0, 120.0]], np.float32))
    np.testing.assert_array_equal(r["image"], a["image"])
    np.testing.assert_array_equal(r["mask"], a["mask"])
    d = mc.Deformer(butterfly, cage, backend="cpu", grid_step=4)
    np.testing.assert_allclose(r["keypoints"], d.transform_points(params["pose"], [[150.0, 120.0]]), atol=1e-5)
    with pytest.raises(ValueError, match="grid_step"):
        mc.MulticageWarp(grid_step=2).replay(params, image=butterfly)


def warp_in_worker(job):
    """Runs in worker processes (fork and spawn): the pickled transform on sample `index`."""
    warp, image, index = job
    out = warp(image=image, keypoints=np.array([[120.0, 90.0]], np.float32), index=index)
    return out["image"], out["keypoints"]


@pytest.mark.parametrize("method", ["fork", "spawn"])
def test_workers_give_what_one_process_gives(butterfly, cage, method):
    """Samples handed to 2 worker processes, in any order, come out as in one process."""
    small = cv2.resize(butterfly, (160, 120))
    warp = mc.MulticageWarp(amplitude=8, grid_step=4, cage=cage, seed=21)
    indices = [5, 1, 4, 0, 3, 2]
    local = [warp_in_worker((warp, small, i)) for i in indices]
    with multiprocessing.get_context(method).Pool(2) as pool:
        remote = pool.map(warp_in_worker, [(warp, small, i) for i in indices], chunksize=1)
    for (li, lk), (ri, rk) in zip(local, remote):
        np.testing.assert_array_equal(li, ri)
        np.testing.assert_array_equal(lk, rk)
    assert not np.array_equal(local[0][0], local[1][0])


def test_compute_maps_writes_into_given_maps(butterfly, cage):
    """compute_maps(pose, mapx, mapy) fills the caller's arrays (the transform reuses them
    between calls): the same maps as fresh ones; wrong arrays are refused."""
    d = mc.Deformer(butterfly, cage, backend="cpu", grid_step=4)
    pose = mc.random_pose(cage, 10, seed=2)
    fresh = d.compute_maps(pose)
    h, w = butterfly.shape[:2]
    mx, my = np.full((h, w), 7, np.float32), np.full((h, w), 7, np.float32)
    got = d.compute_maps(pose, mx, my)
    assert got[0] is mx and got[1] is my
    np.testing.assert_array_equal(mx, fresh[0])
    np.testing.assert_array_equal(my, fresh[1])
    with pytest.raises(ValueError, match="mapx"):
        d.compute_maps(pose, np.zeros((h, w + 1), np.float32), my)
    with pytest.raises(ValueError, match="mapy"):
        d.compute_maps(pose, mx, np.zeros((h, w), np.float64))
    with pytest.raises(ValueError, match="both"):
        d.compute_maps(pose, mx)
    with pytest.raises(ValueError, match="twice"):
        d.compute_maps(pose, mx, mx)


@pytest.mark.parametrize("kind", ["gray_u16", "bgra_u8", "bgr_f32"])
def test_image_types_kept(butterfly, cage, kind):
    image = {"gray_u16": cv2.cvtColor(butterfly, cv2.COLOR_BGR2GRAY).astype(np.uint16) * 200,
             "bgra_u8": cv2.cvtColor(butterfly, cv2.COLOR_BGR2BGRA),
             "bgr_f32": butterfly.astype(np.float32) / 255}[kind]
    out = mc.MulticageWarp(amplitude=10, cage=cage)(image=image, mask=np.ones(image.shape[:2], bool).view(np.uint8),
                                                   seed=3)
    assert out["image"].shape == image.shape and out["image"].dtype == image.dtype
    assert not np.array_equal(out["image"], image)

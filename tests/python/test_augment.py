"""Issue 15 in Python: keypoints follow the image (transform_points), random poses from a seed
(random_pose), batches on one binding (deform(image=), deform_many, set_image)."""

import pickle

import cv2
import numpy as np
import pytest

import multicage as mc
from conftest import SAMPLES
from test_gil import check_runs_without_gil


@pytest.fixture()
def cage():
    return mc.Multicage.load(str(SAMPLES / "butterfly.yml"))


@pytest.fixture()
def deformer(butterfly, cage):
    return mc.Deformer(butterfly, cage, backend="cpu", grid_step=2)


def others(butterfly):
    return [cv2.flip(butterfly, 1), cv2.bitwise_not(butterfly), cv2.GaussianBlur(butterfly, (7, 7), 2)]


# --- keypoints ---------------------------------------------------------------------------------

def test_dots_land_where_transform_points_puts_them(cage):
    """Bright dots drawn at keypoints are found, after deforming the image at grid step 1, where
    transform_points puts the keypoints (their peaks, to a fraction of a pixel)."""
    w, h = cage.image_size
    rng = np.random.default_rng(4)
    ys, xs = np.mgrid[14:h - 14:20, 14:w - 14:20]
    points = np.stack([xs.ravel(), ys.ravel()], 1).astype(np.float32) + rng.uniform(-0.5, 0.5, (xs.size, 2))
    image = np.zeros((h, w), np.float32)
    gy, gx = np.mgrid[0:h, 0:w]
    for x, y in points:
        box = (slice(int(y) - 6, int(y) + 7), slice(int(x) - 6, int(x) + 7))
        image[box] += np.exp(-((gx[box] - x) ** 2 + (gy[box] - y) ** 2) / (2 * 1.3 ** 2))
    d = mc.Deformer(image, cage, backend="cpu", grid_step=1)
    pose = mc.random_pose(cage, 12, seed=3)
    assert np.abs(pose - cage.rest_pose()).max() > 4
    out = d.deform(pose)
    landed = d.transform_points(pose, points)
    errors = []
    for q in landed:
        cx, cy = int(round(q[0])), int(round(q[1]))
        if not (8 <= cx < w - 8 and 8 <= cy < h - 8):
            continue
        win = out[cy - 4:cy + 5, cx - 4:cx + 5]
        py_, px_ = np.unravel_index(np.argmax(win), win.shape)
        by, bx = cy - 4 + py_, cx - 4 + px_
        def fit(a, b, c):
            a, b, c = np.log(max(a, 1e-6)), np.log(max(b, 1e-6)), np.log(max(c, 1e-6))
            return 0.5 * (a - c) / (a - 2 * b + c) if a - 2 * b + c < 0 else 0.0
        peak = (bx + fit(out[by, bx - 1], out[by, bx], out[by, bx + 1]),
                by + fit(out[by - 1, bx], out[by, bx], out[by + 1, bx]))
        errors.append(np.hypot(peak[0] - q[0], peak[1] - q[1]))
    errors = np.array(errors)
    assert len(errors) > 300
    assert errors.max() < 0.5, f"worst dot {errors.max():.3f} px off"
    assert errors.mean() < 0.1


def test_transform_points_is_exact_at_cage_vertices_and_keeps_shapes(deformer, cage):
    pose = mc.random_pose(cage, 12, seed=11)
    landed = deformer.transform_points(pose, cage.rest_pose())
    assert landed.dtype == np.float32 and landed.shape == pose.shape
    assert np.abs(landed - pose).max() < 1e-3
    boxes = np.array([[[60, 60], [140, 60], [140, 120], [60, 120]],
                      [[300, 100], [380, 100], [380, 200], [300, 200]]])  # 2 boxes x 4 corners, int64
    moved = deformer.transform_points(pose, boxes)
    assert moved.shape == (2, 4, 2) and moved.dtype == np.float32
    assert np.array_equal(moved.reshape(-1, 2), deformer.transform_points(pose, boxes.reshape(-1, 2)))
    assert np.array_equal(moved.reshape(-1, 2), deformer.binding.transform_points(pose, boxes.reshape(-1, 2)))
    assert deformer.transform_points(pose, np.zeros((0, 2))).shape == (0, 2)
    rest = deformer.transform_points(cage.rest_pose(), boxes)
    assert np.abs(rest - boxes).max() < 1e-3, "the rest pose moves nothing"


def test_transform_points_bad_input(deformer, cage):
    pose = cage.rest_pose()
    with pytest.raises(ValueError, match="points"):
        deformer.transform_points(pose, [[1, 2, 3]])
    with pytest.raises(ValueError, match="not finite"):
        deformer.transform_points(pose, [[1, np.nan]])
    with pytest.raises(TypeError, match="points"):
        deformer.transform_points(pose, [["a", "b"]])
    with pytest.raises(ValueError, match="pose"):
        deformer.transform_points(pose[:3], [[1, 2]])


# --- random poses ------------------------------------------------------------------------------

def test_random_pose_is_reproducible_valid_and_fold_free(deformer, cage):
    rest = cage.rest_pose()
    a = [mc.random_pose(cage, 12, seed=s) for s in range(200)]
    b = [mc.random_pose(cage, 12, seed=s) for s in range(200)]
    assert all(np.array_equal(x, y) for x, y in zip(a, b)), "the same seed gives the same pose"
    assert not np.array_equal(a[0], a[1])
    assert not np.array_equal(mc.random_pose(cage, 12), mc.random_pose(cage, 12)), "seed=None draws anew"
    moves = []
    for pose in a:
        assert pose.shape == rest.shape and pose.dtype == np.float32
        assert mc.validate_pose(cage, pose) == (True, "")
        assert deformer.folded_triangles(pose) == 0
        moves.append(np.linalg.norm(pose - rest, axis=1).max())
    assert max(moves) <= 12 + 1e-3 and np.mean(moves) > 4


def test_random_pose_checks_the_given_deformer(butterfly, cage):
    fine = mc.Deformer(butterfly, cage, backend="cpu", grid_step=1)
    for s in range(20):
        pose = mc.random_pose(cage, 20, seed=s, deformer=fine)
        assert fine.folded_triangles(pose) == 0 and mc.validate_pose(cage, pose)[0]
    assert np.array_equal(mc.random_pose(cage, 20, seed=5, binding=fine.binding),
                          mc.random_pose(cage, 20, seed=5, deformer=fine))


def test_random_pose_bad_input(cage, deformer):
    with pytest.raises(ValueError, match="amplitude"):
        mc.random_pose(cage, -1)
    with pytest.raises(TypeError, match="seed"):
        mc.random_pose(cage, 5, seed=1.5)
    with pytest.raises(ValueError, match="not both"):
        mc.random_pose(cage, 5, binding=deformer.binding, deformer=deformer)
    with pytest.raises(ValueError, match="binding"):
        mc.random_pose(cage, 5, binding=mc.bind(cage.scaled((100, 80)), grid_step=4))
    with pytest.raises(TypeError, match="cage"):
        mc.random_pose("cage.yml", 5)
    bad = mc.Multicage((100, 100))
    bad.add_polygon(np.array([[10, 10], [90, 90], [90, 10], [10, 90]], np.float32))  # a bow tie
    with pytest.raises(mc.Error, match="randomPose"):
        mc.random_pose(bad, 5)
    ok, why = mc.validate_pose(cage, cage.rest_pose() - 400)
    assert not ok and why


# --- batches -----------------------------------------------------------------------------------

def test_deform_another_image_without_rebinding(butterfly, cage, deformer):
    pose = mc.random_pose(cage, 10, seed=1)
    for other in others(butterfly):
        fresh = mc.Deformer(other, deformer.binding, backend="cpu")
        assert np.array_equal(deformer.deform(pose, image=other), fresh.deform(pose))
    assert np.array_equal(deformer.deform(pose), mc.Deformer(butterfly, deformer.binding, backend="cpu").deform(pose)), \
        "deform(image=) leaves the deformer's own image"
    with pytest.raises(ValueError, match="shape"):
        deformer.deform(pose, image=butterfly[:, :, 0])
    with pytest.raises(ValueError, match="dtype"):
        deformer.deform(pose, image=butterfly.astype(np.float32))


def test_deform_many_equals_one_at_a_time(butterfly, cage, deformer):
    poses = [mc.random_pose(cage, 10, seed=s) for s in range(6)]
    images = (others(butterfly) * 2)[:6]
    batch = deformer.deform_many(poses, images)
    assert len(batch) == 6
    for pose, image, out in zip(poses, images, batch):
        assert np.array_equal(out, deformer.deform(pose, image=image))
    own = deformer.deform_many(np.stack(poses))  # a K x N x 2 array works too
    assert all(np.array_equal(o, deformer.deform(p)) for o, p in zip(own, poses))
    assert deformer.deform_many([]) == []
    with pytest.raises(ValueError, match="2 images for 6 poses"):
        deformer.deform_many(poses, images[:2])
    with pytest.raises(ValueError, match=r"images\[1\]"):
        deformer.deform_many(poses[:2], [images[0], images[1][:20]])
    with pytest.raises(mc.Error, match="batch item 1"):
        deformer.deform_many([poses[0], poses[1][:3]])
    with pytest.raises(TypeError, match="poses"):
        deformer.deform_many(5)


def test_deform_many_releases_the_gil(butterfly, cage):
    big = cv2.resize(butterfly, (986, 712))
    d = mc.Deformer(big, cage, backend="cpu", grid_step=1)
    poses = [mc.random_pose(cage, 10, seed=s) for s in range(3)]
    out = check_runs_without_gil(lambda: d.deform_many(poses, [big] * 3))
    assert len(out) == 3


def test_set_image_replaces_the_image_and_travels_by_pickle(butterfly, cage, deformer):
    pose = mc.random_pose(cage, 10, seed=2)
    other = others(butterfly)[0]
    deformer.set_image(other)
    expected = mc.Deformer(other, deformer.binding, backend="cpu").deform(pose)
    assert np.array_equal(deformer.deform(pose), expected)
    again = pickle.loads(pickle.dumps(deformer))
    assert np.array_equal(again.deform(pose), expected)
    with pytest.raises(ValueError, match="shape"):
        deformer.set_image(other[:50])


def test_gpu_backend_batches_and_points(butterfly, cage, gpu):
    if not gpu:
        pytest.skip("no EGL context here")
    d = mc.Deformer(butterfly, cage, backend="gpu", grid_step=2)
    pose = mc.random_pose(cage, 10, seed=8)
    other = others(butterfly)[1]
    expected = mc.Deformer(other, d.binding, backend="gpu").deform(pose)
    assert np.array_equal(d.deform(pose, image=other), expected)
    assert np.array_equal(d.deform_many([pose], [other])[0], expected)
    cpu = mc.Deformer(butterfly, d.binding, backend="cpu")
    assert np.abs(d.transform_points(pose, cage.rest_pose()) - cpu.transform_points(pose, cage.rest_pose())).max() < 1e-3
    assert np.array_equal(d.deform(pose), mc.Deformer(butterfly, d.binding, backend="gpu").deform(pose))

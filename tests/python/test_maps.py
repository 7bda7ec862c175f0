"""compute_maps + cv2.remap: a label mask deformed with INTER_NEAREST stays on the image
pixels it labelled, and the maps are the ones the CPU backend deforms with."""

import cv2
import numpy as np
import pytest

import multicage as mc

PALETTE = np.array([[0, 0, 0], [40, 200, 90], [230, 60, 20], [10, 90, 250], [250, 250, 250]], np.uint8)


def label_image(size):
    """Labels 1-4 in large blocks (0 is kept for uncovered output pixels)."""
    w, h = size
    y, x = np.mgrid[0:h, 0:w]
    labels = 1 + (x * 3 // w + 2 * (y * 2 // h)) % 4
    labels[(x - w * 0.5) ** 2 + (y - h * 0.45) ** 2 < (h * 0.2) ** 2] = 4
    return labels.astype(np.uint8)


@pytest.mark.parametrize("backend", ["cpu", "gpu"])
def test_label_mask_follows_image(gpu, butterfly_cage, backend):
    if backend == "gpu" and not gpu:
        pytest.skip("no headless EGL context here")
    labels = label_image(butterfly_cage.image_size)
    image = PALETTE[labels]
    deformer = mc.Deformer(image, butterfly_cage, backend=backend, grid_step=2)
    pose = butterfly_cage.pose("flap").vertices
    mapx, mapy = deformer.compute_maps(pose)
    h, w = labels.shape
    assert mapx.shape == (h, w) and mapy.shape == (h, w)
    assert mapx.dtype == np.float32 and mapy.dtype == np.float32

    image_out = cv2.remap(image, mapx, mapy, cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT, borderValue=0)
    labels_out = cv2.remap(labels, mapx, mapy, cv2.INTER_NEAREST, borderMode=cv2.BORDER_CONSTANT, borderValue=0)
    assert not np.array_equal(labels_out, labels), "the pose should move the labels"

    covered = (mapx > -1000) & (mapy > -1000)
    assert covered.mean() > 0.99
    assert np.all(labels_out[~covered] == 0) and np.all(image_out[~covered] == 0)

    # Where the four source pixels around the map position share one label, the deformed
    # image has exactly that label's colour and the deformed mask has that label.
    x0 = np.clip(np.floor(mapx[covered]).astype(int), 0, w - 2)
    y0 = np.clip(np.floor(mapy[covered]).astype(int), 0, h - 2)
    quad = np.stack([labels[y0, x0], labels[y0, x0 + 1], labels[y0 + 1, x0], labels[y0 + 1, x0 + 1]])
    uniform = np.all(quad == quad[0], axis=0)
    assert uniform.mean() > 0.95
    got_labels = labels_out[covered]
    got_colours = image_out[covered]
    bad = np.count_nonzero(got_labels[uniform] != quad[0][uniform])
    assert bad == 0, f"{bad} mask pixels left their image pixels"
    assert np.array_equal(got_colours[uniform], PALETTE[quad[0][uniform]])
    # Elsewhere (label edges) the mask takes one of the four labels, never another.
    assert np.all(np.any(quad == got_labels, axis=0))

    deformed = deformer.deform(pose)
    if backend == "cpu":
        # The CPU backend is exactly cv2.remap with these maps (INTER_LINEAR, border value).
        assert np.array_equal(deformed, image_out)
    else:
        # The GPU samples in its fragment shader: the same picture up to rounding.
        assert np.mean(np.abs(deformed.astype(int) - image_out.astype(int))) < 1.0


def test_maps_of_rest_pose_are_identity(butterfly, butterfly_cage):
    deformer = mc.Deformer(butterfly, butterfly_cage, backend="cpu")
    mapx, mapy = deformer.compute_maps(butterfly_cage.rest_pose())
    h, w = butterfly.shape[:2]
    y, x = np.mgrid[0:h, 0:w].astype(np.float32)
    assert np.abs(mapx - x).max() < 0.02 and np.abs(mapy - y).max() < 0.02
    assert np.array_equal(deformer.deform(butterfly_cage.vertices()), butterfly)


def test_map_step_interpolates_and_travels(butterfly_cage):
    """map_step=4: the maps found on a lattice 4 px apart and interpolated, a few thousandths
    of a pixel from those found at every pixel; the keyword pickles with the deformer, and
    values outside [1, 64] are refused."""
    import pickle
    image = PALETTE[label_image(butterfly_cage.image_size)]
    pose = mc.random_pose(butterfly_cage, 8, seed=4)
    exact = mc.Deformer(image, butterfly_cage, backend="cpu", grid_step=4)
    lattice = mc.Deformer(image, butterfly_cage, backend="cpu", grid_step=4, map_step=4)
    (ex, ey), (lx, ly) = exact.compute_maps(pose), lattice.compute_maps(pose)
    offset = np.hypot(lx - ex, ly - ey)
    assert 0 < offset.mean() < 0.01 and np.percentile(offset, 99) < 0.1
    again = pickle.loads(pickle.dumps(lattice))
    np.testing.assert_array_equal(again.deform(pose), lattice.deform(pose))
    for bad in (0, 65):
        with pytest.raises(ValueError, match="map_step"):
            mc.Deformer(image, butterfly_cage, backend="cpu", map_step=bad)

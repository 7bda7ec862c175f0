"""Content-aware resizing from Python (issue 25): resize_pose, content_aware_resize, and a
Deformer answering a resize pose in the new size."""
import numpy as np
import pytest

import multicage as mc


def _cage():
    cage = mc.Multicage((160, 120))
    cage.add_polygon(np.float32([[30, 118], [35, 60], [55, 30], [75, 60], [82, 118]]))
    cage.add_polygon(np.float32([[48, 55], [62, 55], [62, 70], [48, 70]]))
    cage.orient()
    return cage


def _image():
    rng = np.random.default_rng(3)
    return rng.integers(0, 255, (120, 160, 3), dtype=np.uint8)


def test_resize_pose_has_the_new_frame_last():
    cage = _cage()
    pose = mc.resize_pose(cage, (240, 120))
    assert pose.shape == (cage.vertex_count + 4, 2) and pose.dtype == np.float32
    np.testing.assert_array_equal(pose[-4:], [[-0.5, -0.5], [239.5, -0.5], [239.5, 119.5], [-0.5, 119.5]])
    # The same size is the rest pose.
    np.testing.assert_array_equal(mc.resize_pose(cage, (160, 120)), np.float32(cage.vertices()))


def test_deformer_answers_a_resize_pose_in_the_new_size():
    cage, image = _cage(), _image()
    d = mc.Deformer(image, cage, backend="cpu")
    pose = mc.resize_pose(cage, (240, 100), binding=d)
    assert d.folded_triangles(pose) == 0
    np.testing.assert_array_equal(pose, mc.resize_pose(cage, (240, 100), binding=d.binding))
    with pytest.raises(TypeError):
        mc.resize_pose(cage, (240, 100), binding="mine")
    assert d.deform(pose).shape == (100, 240, 3)
    mapx, mapy = d.compute_maps(pose)
    assert mapx.shape == (100, 240) and (mapx > -1).all()
    # The image's corner pixels land where the frame's scaling puts them (the frame's corners
    # are pinned to the new frame's).
    corners = np.float32([[0, 0], [159, 119]])
    moved = d.transform_points(pose, corners)
    np.testing.assert_allclose(moved, (corners + 0.5) * [240 / 160, 100 / 120] - 0.5, atol=0.01)


def test_content_aware_resize_returns_h_by_w_and_refuses_bad_sizes():
    cage, image = _cage(), _image()
    out = mc.content_aware_resize(image, (200, 120), cage=cage, backend="cpu")
    assert out.shape == (120, 200, 3) and out.dtype == np.uint8
    np.testing.assert_array_equal(mc.content_aware_resize(image, (160, 120), cage=cage), image)
    for bad in [(0, 120), (160 * 9, 120)]:
        with pytest.raises(ValueError):
            mc.content_aware_resize(image, bad, cage=cage)
    with pytest.raises(TypeError):
        mc.content_aware_resize(image, (200, 120), cage=cage, colour="red")

"""Issue 13 item 12 / issue 15 item 4: Multicage, Pose, Binding and Deformer pickle, so that
multiprocessing data loaders ('spawn' included) and distributed engines can ship them. The
round trips must give back equal objects that compute bit for bit what the originals do."""

import copy
import multiprocessing
import pickle

import numpy as np
import pytest

import multicage as mc
from conftest import square

import pickle_workers

PROTOCOLS = sorted({2, pickle.DEFAULT_PROTOCOL, pickle.HIGHEST_PROTOCOL})


def assert_same_multicage(a, b):
    assert (a.image_size, a.polygon_count, a.pose_count, a.coordinates, a.clip_frame) == \
           (b.image_size, b.polygon_count, b.pose_count, b.coordinates, b.clip_frame)
    for i in range(a.polygon_count):
        assert np.array_equal(a.polygon(i), b.polygon(i))
    for pa, pb in zip(a.poses, b.poses):
        assert pa == pb


def assert_same_binding(a, b):
    assert (a.image_size, a.grid_step, a.grid_size, a.coordinates) == (b.image_size, b.grid_step, b.grid_size,
                                                                       b.coordinates)
    assert np.array_equal(a.coefficients, b.coefficients)
    assert np.array_equal(a.rest_vertices, b.rest_vertices)
    assert (a.min_conditioning, a.worst_node) == (b.min_conditioning, b.worst_node)


@pytest.mark.parametrize("protocol", PROTOCOLS)
def test_multicage_and_pose_round_trip(butterfly_cage, protocol):
    butterfly_cage.coordinates = "harmonic"
    butterfly_cage.clip_frame = 7
    butterfly_cage.add_pose("later", butterfly_cage.rest_pose() + np.float32(0.25), time=1.5)
    back = pickle.loads(pickle.dumps(butterfly_cage, protocol))
    assert isinstance(back, mc.Multicage)
    assert_same_multicage(back, butterfly_cage)
    assert back.validate() == butterfly_cage.validate()
    pose = butterfly_cage.pose("later")
    pose_back = pickle.loads(pickle.dumps(pose, protocol))
    assert isinstance(pose_back, mc.Pose) and pose_back == pose
    assert (pose_back.name, pose_back.time) == ("later", 1.5)
    assert np.array_equal(pose_back.vertices, pose.vertices) and pose_back.vertices.dtype == np.float32
    # A copy is independent of the original.
    back.remove_polygon(0)
    assert butterfly_cage.polygon_count == 2


def test_a_multicage_pickled_before_clip_frame_loads_on_the_first_frame(butterfly_cage):
    state = butterfly_cage.__getstate__()
    assert len(state) == 6 and state[5] == 0
    old = mc.Multicage.__new__(mc.Multicage)
    old.__setstate__(state[:5])  # the five fields a pickle of an earlier version holds
    assert old.clip_frame == 0 and old.polygon_count == butterfly_cage.polygon_count


def test_an_invalid_multicage_pickles_as_it_is():
    # An editor may hold an invalid state: pickling keeps it, it does not repair or refuse it.
    cage = mc.Multicage((100, 100))
    cage.add_polygon(square(10, 10, 60, 60))
    cage.add_polygon(square(40, 40, 90, 90))
    back = pickle.loads(pickle.dumps(cage))
    assert_same_multicage(back, cage)
    assert back.validate() == cage.validate() and not back.validate()[0]


@pytest.mark.parametrize("protocol", PROTOCOLS)
def test_binding_round_trip(butterfly_cage, protocol):
    binding = mc.bind(butterfly_cage, grid_step=4)
    back = pickle.loads(pickle.dumps(binding, protocol))
    assert_same_binding(back, binding)
    pose = butterfly_cage.pose(0).vertices
    assert np.array_equal(back.apply(pose), binding.apply(pose))


@pytest.mark.parametrize("protocol", PROTOCOLS)
def test_deformer_is_re_created_from_image_binding_and_parameters(butterfly, butterfly_cage, protocol):
    deformer = mc.Deformer(butterfly, butterfly_cage, backend="cpu", grid_step=3, border_value=(1, 2, 3))
    pose = butterfly_cage.pose(0).vertices
    expected = deformer.deform(pose)
    back = pickle.loads(pickle.dumps(deformer, protocol))
    assert isinstance(back, mc.Deformer) and back is not deformer
    assert (back.backend, back.grid_step, back.image_size, back.vertex_count, back.coordinates) == \
           (deformer.backend, deformer.grid_step, deformer.image_size, deformer.vertex_count, deformer.coordinates)
    assert_same_binding(back.binding, deformer.binding)
    assert np.array_equal(back.deform(pose), expected)
    for a, b in zip(back.compute_maps(pose), deformer.compute_maps(pose)):
        assert np.array_equal(a, b)
    # border_value travelled too: a pose that uncovers pixels fills them with it
    shrink = (butterfly_cage.vertices() - 246) * np.float32(0.5) + 246
    assert np.array_equal(back.deform(shrink), deformer.deform(shrink))
    assert np.array_equal(copy.deepcopy(deformer).deform(pose), expected)


def test_deformer_of_a_scaled_cage_keeps_the_cage_coordinates(butterfly, butterfly_cage):
    import cv2
    small = cv2.resize(butterfly, (301, 217), interpolation=cv2.INTER_AREA)
    deformer = mc.Deformer(small, butterfly_cage, backend="cpu", grid_step=2)
    back = pickle.loads(pickle.dumps(deformer))
    assert back.cage_size == (493, 356) and back.image_size == (301, 217)
    pose = butterfly_cage.pose("flap").vertices
    assert np.array_equal(back.deform(pose), deformer.deform(pose))


def test_a_deformer_that_cannot_be_made_here_says_why(butterfly, butterfly_cage, gpu):
    # Forge the pickle of a GPU deformer (as one made on a GPU machine would be) and load it
    # where the GPU backend fails: a clear multicage.Error, not a crash or a silent CPU one.
    deformer = mc.Deformer(butterfly, butterfly_cage, backend="cpu", grid_step=8)
    cls, args, state = deformer.__reduce_ex__(2)[:3]
    version, image, binding, params, cage_size = state
    bad = dict(params, backend="gpu", memory_budget=-1)
    with pytest.raises(ValueError, match="memory_budget"):
        obj = cls(*args)
        obj.__setstate__((version, image, binding, bad, cage_size))
    if not gpu:
        obj = cls(*args)
        with pytest.raises(mc.Error, match=r"cannot re-create the pickled multicage.Deformer \(backend='gpu'\) "
                                           r"here: .*backend='auto' or 'cpu'"):
            obj.__setstate__((version, image, binding, dict(params, backend="gpu"), cage_size))
    with pytest.raises(ValueError, match="pickled in format 99"):
        cls(*args).__setstate__((99, image, binding, params, cage_size))


def test_round_trips_through_spawned_worker_processes(butterfly, butterfly_cage):
    """multiprocessing with the 'spawn' start method (a fresh interpreter per worker, as on
    macOS and Windows and in most data loaders) ships every object both ways."""
    deformer = mc.Deformer(butterfly, butterfly_cage, backend="cpu", grid_step=4)
    binding = mc.bind(butterfly_cage, grid_step=4)
    pose = butterfly_cage.pose(0)
    expected = deformer.deform(pose.vertices)
    context = multiprocessing.get_context("spawn")
    with context.Pool(2) as pool:
        results = pool.map(pickle_workers.deform_in_worker, [(deformer, butterfly_cage, pose, binding)] * 2)
        crossing = mc.Multicage((100, 100))
        crossing.add_polygon(square(10, 10, 60, 60))
        crossing.add_polygon(square(40, 40, 90, 90))
        with pytest.raises(mc.Error, match="cannot bind: polygon 1"):
            # the library's error in a worker travels back as multicage.Error
            pool.apply(pickle_workers.fail_in_worker, (crossing,))
    for out, from_binding, cage_back, pose_back, binding_back, deformer_back in results:
        assert np.array_equal(out, expected)
        assert np.array_equal(from_binding, expected)
        assert_same_multicage(cage_back, butterfly_cage)
        assert pose_back == pose
        assert_same_binding(binding_back, binding)
        assert np.array_equal(deformer_back.deform(pose.vertices), expected)

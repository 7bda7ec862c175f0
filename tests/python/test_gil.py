"""The GIL is released while the library works: another Python thread keeps running during
a bind, a Deformer creation, a deform and a compute_maps made in a worker thread."""

import threading
import time

import cv2
import numpy as np
import pytest

import multicage as mc

SIZE = (986, 712)  # twice the butterfly: each call takes a good fraction of a second


@pytest.fixture(scope="module")
def big(butterfly):
    return cv2.resize(butterfly, SIZE)


@pytest.fixture(scope="module")
def big_cage(big):
    return mc.Multicage.load(str(__import__("conftest").SAMPLES / "butterfly.yml")).scaled(SIZE)


def python_ticks_during(call, min_total=0.3):
    """Runs call() in a worker thread, again and again until min_total seconds have passed,
    while this thread keeps looping; returns the last result, the median duration of one call
    and the longest time this thread could not run. A call that holds the GIL stops this
    thread for a whole call; one that releases it does not. Repeating makes the check
    independent of how fast the machine is."""
    done = threading.Event()
    calls = []
    box = {}

    def worker():
        start = time.perf_counter()
        while not calls or time.perf_counter() - start < min_total:
            t0 = time.perf_counter()
            box["result"] = call()
            calls.append(time.perf_counter() - t0)
        done.set()

    ticks = [time.perf_counter()]
    thread = threading.Thread(target=worker)
    thread.start()
    while not done.is_set():
        ticks.append(time.perf_counter())
    thread.join()
    ticks.append(time.perf_counter())
    longest_stall = float(np.max(np.diff(ticks)))
    return box["result"], float(np.median(calls)), longest_stall


def check_runs_without_gil(call):
    result, duration, stall = python_ticks_during(call)
    assert duration > 0.02, f"one call takes {duration * 1e3:.1f} ms: too short to tell"
    assert stall < 0.5 * duration, (
        f"Python stood still for {stall * 1e3:.0f} ms of a {duration * 1e3:.0f} ms call: the GIL was held")
    return result


def test_bind_releases_gil(big_cage):
    binding = check_runs_without_gil(lambda: mc.bind(big_cage, grid_step=1))
    assert binding.grid_size == SIZE


def test_deformer_creation_deform_and_maps_release_gil(big, big_cage):
    deformer = check_runs_without_gil(lambda: mc.Deformer(big, big_cage, backend="cpu"))
    pose = big_cage.pose(0).vertices
    threaded = check_runs_without_gil(lambda: deformer.deform(pose))
    assert np.array_equal(threaded, deformer.deform(pose))
    mapx, mapy = check_runs_without_gil(lambda: deformer.compute_maps(pose))
    assert np.array_equal(cv2.remap(big, mapx, mapy, cv2.INTER_LINEAR), threaded)


def test_threads_sharing_a_deformer_get_serial_results(butterfly, butterfly_cage):
    """Calls on one Deformer from several threads take turns (it holds per-call state)."""
    deformer = mc.Deformer(butterfly, butterfly_cage, backend="cpu", grid_step=2)
    rest = butterfly_cage.rest_pose()
    poses = [rest + np.float32(k) for k in range(-3, 3)]
    expected = [deformer.deform(p) for p in poses]
    results = [None] * len(poses)

    def work(i):
        for _ in range(3):
            results[i] = deformer.deform(poses[i])

    threads = [threading.Thread(target=work, args=(i,)) for i in range(len(poses))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for got, want in zip(results, expected):
        assert np.array_equal(got, want)


def test_the_check_catches_a_call_that_holds_the_gil():
    # sorted() of a long range is one C call that never releases the GIL: the check sees it.
    numbers = range(2_500_000, 0, -1)
    _, duration, stall = python_ticks_during(lambda: sorted(numbers))
    assert stall > 0.8 * duration
    with pytest.raises(AssertionError, match="the GIL was held"):
        check_runs_without_gil(lambda: sorted(numbers))

"""CageTracker from Python (issue 42 item 1): a multicage follows a subject across a still scene,
a cut is reported with nothing moved, and bad frames and options are refused."""
import cv2
import numpy as np
import pytest

import multicage as mc
from conftest import DATA


def crossing_frame(background, subject, shift):
    """The subject pasted on the background with its top-left at (120, 100) + shift."""
    frame = background.copy()
    x, y = 120 + shift[0], 100 + shift[1]
    frame[y : y + subject.shape[0], x : x + subject.shape[1]] = subject
    return frame


@pytest.fixture(scope="module")
def clip():
    background = cv2.resize(cv2.imread(str(DATA / "fruits.jpg")), (640, 480))
    subject = cv2.imread(str(DATA / "messi5.jpg"))[40:200, 200:360].copy()
    cage = mc.Multicage((640, 480))
    cage.add_polygon(np.float32([[130, 110], [270, 110], [270, 250], [130, 250]]))
    cage.orient()
    return background, subject, cage


def test_a_subject_crossing_a_still_scene_is_followed(clip):
    background, subject, cage = clip
    tracker = mc.CageTracker(cage, crossing_frame(background, subject, (0, 0)))
    start = cage.vertices()[: cage.vertex_count]
    for t in range(1, 9):
        report = tracker.track(crossing_frame(background, subject, (7 * t, 3 * t)))
        assert report["state"] == "ok", report["why"]
        moved = tracker.multicage.vertices()[: cage.vertex_count]
        assert np.abs(moved - (start + [7 * t, 3 * t])).max() < 0.5, t
    # An edit drawn on the first frame (the square pulled wider) moves with it.
    edit = start + np.float32([[-10, 0], [10, 0], [10, 0], [-10, 0]])
    carried = mc.carry_pose(cage, edit, tracker.multicage)
    assert carried.shape == (4, 2) and np.abs(carried - (edit + [56, 24])).max() < 0.5
    with pytest.raises(mc.Error):
        mc.carry_pose(cage, edit[:3], tracker.multicage)


def test_a_cut_is_reported_and_nothing_moves(clip):
    background, subject, cage = clip
    tracker = mc.CageTracker(cage, crossing_frame(background, subject, (0, 0)))
    other = cv2.resize(cv2.imread(str(DATA / "building.jpg")), (640, 480))
    report = tracker.track(other)
    assert report["state"] == "cut" and "a cut" in report["why"]
    assert np.array_equal(tracker.multicage.vertices(), cage.vertices())
    tracker.reset(cage, other)
    assert tracker.track(other)["state"] == "ok"


def test_bad_frames_and_options_are_refused(clip):
    background, subject, cage = clip
    with pytest.raises(mc.Error):
        mc.CageTracker(cage, np.zeros((480, 640, 3), np.float32))
    with pytest.raises(TypeError, match="unexpected keyword 'speed'"):
        mc.CageTracker(cage, background, speed=2)
    tracker = mc.CageTracker(cage, background)
    with pytest.raises(mc.Error, match="size or type"):
        tracker.track(np.zeros((100, 100, 3), np.uint8))

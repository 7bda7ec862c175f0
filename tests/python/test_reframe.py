"""VideoReframer from Python (issue 42): a still clip comes out still, in order and of the size
asked; a 16:9 clip reframed to 9:16 is cropped to a window and its face polygon keeps its shape;
reframe() yields what push() and pop() give; bad frames and options are refused; push() runs
without the GIL."""
import cv2
import numpy as np
import pytest

import multicage as mc
from conftest import DATA, square
from test_gil import check_runs_without_gil

W, H = 256, 144  # 16:9
OUT = (90, 160)  # 9:16: more than max_warp takes, so a window is cropped


@pytest.fixture(scope="module")
def scene():
    background = cv2.resize(cv2.imread(str(DATA / "fruits.jpg")), (W, H))
    subject = cv2.resize(cv2.imread(str(DATA / "messi5.jpg"))[40:200, 200:360], (60, 80))
    return background, subject


def frame(scene, shift=0):
    """The subject pasted on the background with its top-left at (40 + shift, 40)."""
    background, subject = scene
    f = background.copy()
    f[40:120, 40 + shift : 100 + shift] = subject
    return f


def subject_cage(shift=0):
    """An outline around the subject and an inner polygon (its 'face'), at rest."""
    cage = mc.Multicage((W, H))
    cage.add_polygon(square(34 + shift, 34, 106 + shift, 126))
    cage.add_polygon(square(55 + shift, 45, 85 + shift, 75))
    cage.orient()
    return cage


def run(reframer, frames):
    """push() each frame and pop() what is ready, then finish() and pop() the rest; also checks
    that the output runs reframer.lag frames behind the input."""
    outs = []
    for k, f in enumerate(frames, 1):
        reframer.push(f)
        while (out := reframer.pop()) is not None:
            outs.append(out)
        assert len(outs) == max(0, k - reframer.lag)
    reframer.finish()
    while (out := reframer.pop()) is not None:
        outs.append(out)
    return outs


def similarity_residual(src, dst):
    """The largest distance from dst of the least-squares similarity of src onto it."""
    n = len(src)
    a = np.zeros((2 * n, 4))
    a[0::2] = np.c_[src[:, 0], -src[:, 1], np.ones(n), np.zeros(n)]
    a[1::2] = np.c_[src[:, 1], src[:, 0], np.zeros(n), np.ones(n)]
    p, *_ = np.linalg.lstsq(a, dst.reshape(-1).astype(np.float64), rcond=None)
    return np.linalg.norm((a @ p).reshape(-1, 2) - dst, axis=1).max()


def test_a_still_clip_comes_out_still_in_order_and_of_the_size_asked(scene):
    still = frame(scene)
    reframer = mc.VideoReframer(OUT, backend="cpu")  # the multicage proposed on the first frame
    assert reframer.size == OUT and reframer.lag == 12 and reframer.pop() is None
    outs = run(reframer, [still] * 20)
    assert [o["index"] for o in outs] == list(range(20))
    first = outs[0]["image"].astype(np.float64)
    for o in outs:
        assert o["image"].shape == (OUT[1], OUT[0], 3) and o["image"].dtype == np.uint8
        assert np.abs(o["image"] - first).mean() <= 1.0, o["index"]
        assert o["shot"] == 0 and o["smoothed"]
    stats = reframer.stats
    assert stats["frames_in"] == stats["frames_out"] == 20
    assert stats["proposals"] == 1 and stats["last_why"] == "the first frame"
    assert stats["cuts"] == stats["lost"] == 0
    assert all(stats[k] >= 0 for k in ("propose_ms", "track_ms", "bind_ms", "pose_ms", "deform_ms"))


def test_9_16_from_16_9_crops_a_window_and_the_face_keeps_its_shape(scene):
    cage = subject_cage()
    outs = run(mc.VideoReframer(OUT, cage=cage, backend="cpu", smoothing=2), [frame(scene)] * 6)
    assert len(outs) == 6
    for o in outs:
        x, y, w, h = o["window"]
        assert w < W - 100 and (y, h) == pytest.approx((0, H)), o["window"]  # a crop, all the height
        assert x <= 34 and x + w >= 106  # the outline is in the window, whole
        # On a still clip the window is the single frame's and the crop's multicage that of
        # the given one: reframe_window() and crop_multicage() say the same.
        assert np.allclose(o["window"], mc.reframe_window(cage, OUT), atol=1e-6)
        crop = mc.crop_multicage(cage, o["crop"])
        assert np.array_equal(crop.vertices(), o["cage"].vertices())
        # The face (the inner polygon, kept second) is posed by a similarity, scaled as the
        # window is to the output.
        rest = o["cage"]
        assert rest.polygon_count == 2
        n0, face = len(rest.polygon(0)), rest.polygon(1)
        posed = o["pose"][n0 : n0 + len(face)]
        assert o["pose"].shape == (rest.vertex_count + 4, 2) and o["pose"].dtype == np.float32
        assert similarity_residual(face, posed) < 1.0
        scale = np.linalg.norm(posed[2] - posed[0]) / np.linalg.norm(face[2] - face[0])
        assert scale == pytest.approx(OUT[1] / H, rel=0.05)


def test_reframe_yields_what_push_and_pop_give(scene):
    clip = [frame(scene, 2 * t) for t in range(14)]
    options = dict(cage=subject_cage(), backend="cpu", smoothing=3)
    popped = run(mc.VideoReframer(OUT, **options), clip)
    yielded = list(mc.VideoReframer(OUT, **options).reframe(iter(clip)))
    assert len(yielded) == len(popped) == len(clip)
    for a, b in zip(yielded, popped):
        assert np.array_equal(a, b["image"])
    # The subject moved 26 px to the right: the window followed it.
    assert popped[-1]["window"][0] > popped[0]["window"][0] + 10


@pytest.mark.parametrize("channels", [1, 4])
def test_grey_and_bgra_frames_keep_their_channels(scene, channels):
    f = frame(scene)
    f = cv2.cvtColor(f, cv2.COLOR_BGR2GRAY) if channels == 1 else cv2.cvtColor(f, cv2.COLOR_BGR2BGRA)
    out = list(mc.VideoReframer(OUT, cage=subject_cage(), backend="cpu", smoothing=0).reframe([f, f]))
    assert len(out) == 2 and out[0].shape == (OUT[1], OUT[0]) + ((4,) if channels == 4 else ())


def test_bad_frames_and_options_are_refused(scene):
    still = frame(scene)
    for size, error in (((0, 10), ValueError), ("9:16", TypeError), ((90.5, 160), TypeError)):
        with pytest.raises(error, match="size"):
            mc.VideoReframer(size)
    with pytest.raises(TypeError, match="unexpected keyword 'speed'"):
        mc.VideoReframer(OUT, speed=2)
    with pytest.raises(TypeError, match="cage"):
        mc.VideoReframer(OUT, cage="cage.yml")
    for key, value, error in (("coordinates", "bezier", ValueError), ("backend", "tpu", ValueError),
                              ("protect", "eyes", ValueError), ("protect", 1.0, TypeError),
                              ("segmenter", "magic", ValueError), ("smoothing", -1, ValueError),
                              ("smoothing", 1.5, TypeError), ("grid_step", 0, ValueError),
                              ("max_warp", "wide", TypeError), ("retry_empty_every", -3, ValueError),
                              ("min_points", "8", TypeError)):
        with pytest.raises(error, match=key):
            mc.VideoReframer(OUT, **{key: value})
    with pytest.raises(ValueError, match="segmenter_model"):
        mc.VideoReframer(OUT, segmenter="classic", segmenter_model="u2netp.onnx")

    reframer = mc.VideoReframer(OUT, cage=subject_cage(), backend="cpu", smoothing=1)
    with pytest.raises(mc.Error, match="8-bit"):
        reframer.push(still.astype(np.float32))
    with pytest.raises(TypeError, match="dtype"):
        reframer.push(still.astype(np.int8))
    with pytest.raises(ValueError, match="2 channels"):
        reframer.push(still[:, :, :2])
    with pytest.raises(ValueError, match="empty"):
        reframer.push(np.zeros((0, W, 3), np.uint8))
    with pytest.raises(TypeError, match="numpy array"):
        reframer.push(still.tolist())
    reframer.push(still)
    with pytest.raises(mc.Error, match="the first was 256x144"):
        reframer.push(cv2.resize(still, (128, 72)))
    with pytest.raises(mc.Error, match="the first was"):
        reframer.push(cv2.cvtColor(still, cv2.COLOR_BGR2GRAY))
    reframer.push(still)  # a refused frame changes nothing
    reframer.finish()
    with pytest.raises(mc.Error, match=r"after finish\(\)"):
        reframer.push(still)
    assert [o["index"] for o in iter(reframer.pop, None)] == [0, 1]
    assert reframer.stats["frames_in"] == 2

    with pytest.raises(ValueError, match="no image size"):
        mc.reframe_window(mc.Multicage(), OUT)
    with pytest.raises(ValueError, match="inside"):
        mc.crop_multicage(subject_cage(), (200, 0, 100, 144))
    with pytest.raises(TypeError, match="crop"):
        mc.crop_multicage(subject_cage(), (0, 0, 10))


def test_push_runs_without_the_gil(scene):
    # The first push proposes a multicage (the longest step): another thread runs meanwhile.
    still = frame(scene)
    check_runs_without_gil(lambda: mc.VideoReframer(OUT, backend="cpu").push(still), tries=5)

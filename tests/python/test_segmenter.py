"""Issue 39 item 7: the subject cue of a proposal is one default everywhere (segmenter='auto':
the learned subject model when one is found, else the classic segmentation), and the keywords
segmenter= and segmenter_model= pick another, validated as the CLI's --segmenter and
--segmenter-model are."""

import os

import cv2
import numpy as np
import pytest

import multicage as mc
from conftest import DATA


@pytest.fixture(scope="module")
def photo():
    image = cv2.imread(str(DATA / "messi5.jpg"), cv2.IMREAD_UNCHANGED)
    assert image is not None
    return image


@pytest.fixture(scope="module")
def model():
    """The installed subject model's path, or None (.ci/deps.sh not run)."""
    path, why = mc.segmenter_model_file(segmenter="model")
    return path or None


@pytest.fixture()
def junk(tmp_path):
    """1000 random bytes named like a model."""
    path = tmp_path / "random_bytes.onnx"
    path.write_bytes(np.random.default_rng(39).integers(0, 256, 1000, dtype=np.uint8).tobytes())
    return path


def assert_valid(cage, image):
    assert cage.validate() == (True, "")
    assert cage.polygon_count >= 1
    assert cage.image_size == (image.shape[1], image.shape[0])


def test_defaults_and_the_look_up():
    defaults = mc.propose_defaults()
    assert defaults["segmenter"] == "auto"
    assert defaults["segmenter_model"] is None
    path, why = mc.segmenter_model_file()
    assert isinstance(path, str) and isinstance(why, str) and why
    if path:
        assert why in ("MULTICAGE_SEGMENTER_MODEL", "MULTICAGE_DATA_DIR", "the build tree",
                       "the install prefix"), why
    else:
        assert "no subject model" in why, why
    assert mc.segmenter_model_file("classic") == ("", mc.segmenter_model_file("classic")[1])
    assert "classic" in mc.segmenter_model_file("classic")[1]
    # An explicit path is returned as given, existing or not (reading it is what fails).
    assert mc.segmenter_model_file(segmenter_model="/no/such/model.onnx") == (
        "/no/such/model.onnx", "ProposeParams::segmenterModel")
    import pathlib
    assert mc.segmenter_model_file("model", pathlib.Path("/x/m.onnx"))[0] == "/x/m.onnx"


@pytest.mark.parametrize("function", ["propose_multicage", "propose_segmentation"])
def test_keywords_are_validated(photo, function):
    propose = getattr(mc, function)
    with pytest.raises(ValueError, match=r"segmenter: 'bogus' is not one of 'auto', 'model', 'classic'"):
        propose(photo, segmenter="bogus")
    with pytest.raises(TypeError, match=r"segmenter: expected a name"):
        propose(photo, segmenter=1.5)
    with pytest.raises(TypeError, match=r"segmenter_model: expected a path"):
        propose(photo, segmenter_model=3)
    with pytest.raises(ValueError, match=r"segmenter_model: an empty path"):
        propose(photo, segmenter_model="")
    with pytest.raises(ValueError, match=r"segmenter_model: .* segmenter='classic', which runs no model"):
        propose(photo, segmenter="classic", segmenter_model="/x/m.onnx")
    with pytest.raises(ValueError, match=r"segmenter: 'bogus'"):
        mc.segmenter_model_file("bogus")
    with pytest.raises(ValueError, match=r"segmenter: 'bogus'"):
        mc.content_aware_resize(photo, (600, 342), segmenter="bogus")


def test_classic_and_default_both_give_valid_cages(photo, model):
    # GrabCut draws from OpenCV's random generator: seeded alike, one cue gives one cage.
    cv2.setRNGSeed(39)
    classic = mc.propose_multicage(photo, segmenter="classic")
    cv2.setRNGSeed(39)
    default = mc.propose_multicage(photo)
    assert_valid(classic, photo)
    assert_valid(default, photo)
    # The default is the model when one is installed, else the classic segmentation itself.
    cv2.setRNGSeed(39)
    same_as = mc.propose_multicage(photo, segmenter="model" if model else "classic")
    assert np.array_equal(same_as.vertices(), default.vertices())
    for mask in (mc.propose_segmentation(photo, segmenter="classic"), mc.propose_segmentation(photo)):
        assert mask.shape == photo.shape[:2] and mask.dtype == np.uint8
        assert 0 < np.count_nonzero(mask) < mask.size
    if model:
        assert_valid(mc.propose_multicage(photo, segmenter="model", segmenter_model=model), photo)
    else:
        with pytest.raises(mc.Error, match="no subject model is installed") as e:
            mc.propose_multicage(photo, segmenter="model")
        assert e.value.code == -204  # StsObjectNotFound


def test_a_bad_model_file_is_an_error_naming_it(photo, junk, tmp_path):
    # (propose_segmentation is left out: the library's proposeSegmentation() runs no model.)
    for call in (lambda: mc.propose_multicage(photo, segmenter_model=junk),
                 lambda: mc.propose_multicage(photo, segmenter="model", segmenter_model=str(junk)),
                 lambda: mc.subject_map(photo, segmenter_model=junk),
                 lambda: mc.content_aware_resize(photo, (600, 342), segmenter_model=junk, grid_step=4)):
        with pytest.raises(mc.Error, match=str(junk)) as e:
            call()
        assert e.value.code == -212  # StsParseError
    missing = tmp_path / "missing.onnx"
    with pytest.raises(mc.Error, match=str(missing)):
        mc.propose_multicage(photo, segmenter_model=missing)


def test_subject_map(photo, model):
    if not model:
        with pytest.raises(mc.Error, match="no subject model"):
            mc.subject_map(photo)
        pytest.skip("no subject model installed (.ci/deps.sh)")
    m = mc.subject_map(photo)
    assert m.shape == photo.shape[:2] and m.dtype == np.float32
    assert 0.0 <= m.min() and m.max() <= 1.0
    assert m.max() - m.min() > 0.5, "a photo of a person has a subject"
    assert np.array_equal(m, mc.subject_map(photo, segmenter_model=model))


def test_multicage_warp_passes_the_keywords_through(photo):
    warp = mc.MulticageWarp(amplitude=5, seed=1, propose_options={"segmenter": "bogus"})
    with pytest.raises(ValueError, match=r"segmenter: 'bogus'"):
        warp(image=photo)
    warp = mc.MulticageWarp(amplitude=5, seed=1, propose_options={"segmenter": "classic"})
    out = warp(image=photo)["image"]
    assert out.shape == photo.shape

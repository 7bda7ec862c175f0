"""multicage.imread (issue 22, item 3): reads what the CLI reads, and raises multicage.Error,
naming the file, where cv2.imread decodes a damaged file with a warning or returns None."""

import pathlib

import cv2
import numpy as np
import pytest

import multicage as mc
from conftest import DATA


def test_reads_as_stored_like_cv2(tmp_path):
    for name in ("butterfly.jpg", "smarties.png"):
        path = DATA / name
        image = mc.imread(str(path))
        assert np.array_equal(image, cv2.imread(str(path), cv2.IMREAD_UNCHANGED))
        assert np.array_equal(mc.imread(pathlib.Path(path)), image)  # an os.PathLike too
    gray = mc.imread(DATA / "butterfly.jpg", cv2.IMREAD_GRAYSCALE)
    assert gray.ndim == 2 and gray.dtype == np.uint8
    # 16 bits and alpha are kept (the default is cv2.IMREAD_UNCHANGED, as the CLI reads).
    deep = np.zeros((20, 30, 4), np.uint16)
    deep[..., 0] = 65535
    deep[..., 3] = 1234
    cv2.imwrite(str(tmp_path / "deep.png"), deep)
    assert np.array_equal(mc.imread(tmp_path / "deep.png"), deep)


def test_damaged_files_raise_naming_the_file(tmp_path):
    jpeg = (DATA / "butterfly.jpg").read_bytes()
    png = (DATA / "smarties.png").read_bytes()
    (tmp_path / "cut.jpg").write_bytes(jpeg[:2000])
    (tmp_path / "cut.png").write_bytes(png[:len(png) // 2])
    (tmp_path / "empty.jpg").write_bytes(b"")
    (tmp_path / "notes.png").write_text("a text file, not an image\n")
    # What cv2.imread makes of them: a half-grey picture from the cut JPEG, None from the others.
    assert cv2.imread(str(tmp_path / "cut.jpg")) is not None
    assert cv2.imread(str(tmp_path / "empty.jpg")) is None
    expected = {"cut.jpg": "the file is truncated (a JPEG ends with an end-of-image marker FF D9; this one "
                           "stops after 2000 bytes, in the middle of its data)",
                "cut.png": f"the file is truncated (a PNG ends with an IEND chunk; this one stops after "
                           f"{len(png) // 2} bytes, in the middle of its data)",
                "empty.jpg": "the file is empty",
                "notes.png": "not an image OpenCV can read",
                "missing.jpg": "no such file, or it cannot be read"}
    for name, why in expected.items():
        with pytest.raises(mc.Error) as error:
            mc.imread(tmp_path / name)
        assert str(error.value) == f"{tmp_path / name}: {why}"


def test_wrong_arguments_are_type_errors():
    with pytest.raises(TypeError, match="path: expected a str or an os.PathLike, got"):
        mc.imread(3)
    with pytest.raises(TypeError, match="flags"):
        mc.imread(str(DATA / "butterfly.jpg"), "color")

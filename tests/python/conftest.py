"""Fixtures for the Python module's tests. Run by ctest (one test per file: Python.test_api,
...), which sets PYTHONPATH to the module in the build tree and MULTICAGE_CLI to the
`multicage` tool built beside it; run by hand: PYTHONPATH=<build>/python MULTICAGE_CLI=<build>/bin/multicage
/usr/bin/python3 -m pytest -q tests/python"""

import os
import pathlib
import subprocess

import cv2
import numpy as np
import pytest

import multicage as mc

SOURCE_DIR = pathlib.Path(os.environ.get("MULTICAGE_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
SAMPLES = SOURCE_DIR / "samples"
DATA = SAMPLES / "data"


@pytest.fixture(scope="session")
def cli():
    """Runs the C++ `multicage` tool; fails the test with its stderr when it fails."""
    path = os.environ.get("MULTICAGE_CLI")
    if not path or not os.path.isfile(path):
        pytest.skip("MULTICAGE_CLI is not set to the built multicage tool")

    def run(*args):
        r = subprocess.run([path, *map(str, args)], capture_output=True, text=True, timeout=600)
        assert r.returncode == 0, f"multicage {' '.join(map(str, args))} failed:\n{r.stderr}"
        return r

    return run


@pytest.fixture(scope="session")
def gpu():
    ok, description = mc.gpu_available()
    return ok


@pytest.fixture(scope="session")
def butterfly():
    image = cv2.imread(str(DATA / "butterfly.jpg"), cv2.IMREAD_UNCHANGED)
    assert image is not None
    return image


@pytest.fixture(scope="session")
def butterfly_cage_path():
    return SAMPLES / "butterfly.yml"


@pytest.fixture()
def butterfly_cage(butterfly_cage_path):
    return mc.Multicage.load(str(butterfly_cage_path))


def box_mask(shape, box):
    """A mask of `shape` with 255 on the pascal_voc box (pixel edges)."""
    m = np.zeros(shape, np.uint8)
    x0, y0, x1, y1 = (int(v) for v in box)
    m[y0:y1, x0:x1] = 255
    return m


def mask_box(mask):
    """The pascal_voc box (pixel edges) of a mask's non-zero pixels."""
    ys, xs = np.nonzero(mask)
    return np.array([xs.min(), ys.min(), xs.max() + 1, ys.max() + 1], np.float64)


def square(x0, y0, x1, y1):
    """Corners of an axis-aligned rectangle, clockwise on screen."""
    return np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]], np.float32)

"""samples/python/augment.py: runs, writes COUNT image/mask pairs, keeps every vertex within
the bound, and deforms the mask with the image."""

import os
import subprocess
import sys

import cv2
import numpy as np

import multicage as mc
from conftest import DATA, SAMPLES

SCRIPT = SAMPLES / "python" / "augment.py"


def run(*args):
    env = dict(os.environ)
    return subprocess.run([sys.executable, str(SCRIPT), *map(str, args)], capture_output=True, text=True,
                          env=env, timeout=600)


def test_help():
    r = run("--help")
    assert r.returncode == 0 and "--bound" in r.stdout and "--mask" in r.stdout


def test_bad_input_fails_with_one_line(tmp_path):
    r = run(tmp_path / "missing.png", "-o", tmp_path / "out")
    assert r.returncode != 0 and "no such file" in r.stderr
    assert not (tmp_path / "out").exists()


def test_augments_image_and_mask_within_bound(tmp_path):
    image = cv2.imread(str(DATA / "HappyFish.jpg"))
    h, w = image.shape[:2]
    mask = np.zeros((h, w), np.uint8)
    cv2.ellipse(mask, (w // 2, h // 2), (w // 4, h // 5), 0, 0, 360, 255, -1)
    cv2.imwrite(str(tmp_path / "mask.png"), mask)
    out = tmp_path / "out"
    r = run(DATA / "HappyFish.jpg", "--mask", tmp_path / "mask.png", "-o", out, "-n", 3, "--bound", 8,
            "--seed", 5, "--backend", "cpu")
    assert r.returncode == 0, r.stderr
    for k in range(3):
        img = cv2.imread(str(out / f"HappyFish_{k:03d}.png"))
        m = cv2.imread(str(out / f"HappyFish_{k:03d}_mask.png"), cv2.IMREAD_UNCHANGED)
        assert img.shape == image.shape and m.shape == mask.shape
        assert set(np.unique(m)) <= {0, 255}, "nearest neighbour never blends labels"
        assert not np.array_equal(m, mask), "the mask should move"
        assert abs(int(np.count_nonzero(m)) - int(np.count_nonzero(mask))) < 0.2 * np.count_nonzero(mask)
    cage = mc.Multicage.load(str(out / "HappyFish_cage.yml"))
    assert cage.pose_count == 3 and cage.validate() == (True, "")
    rest = cage.rest_pose()
    for p in cage.poses:
        assert np.linalg.norm(p.vertices - rest, axis=1).max() <= 8 + 1e-3
    # The saved poses reproduce the saved masks: the mask followed the same maps as the image.
    deformer = mc.Deformer(image, cage, backend="cpu", grid_step=2)
    mapx, mapy = deformer.compute_maps(cage.pose("aug001").vertices)
    covered = mapx > -1000
    again = cv2.remap(mask, mapx, mapy, cv2.INTER_NEAREST)
    saved = cv2.imread(str(out / "HappyFish_001_mask.png"), cv2.IMREAD_UNCHANGED)
    assert np.array_equal(again[covered], saved[covered])


def test_no_object_fails_with_one_line(tmp_path):
    noise = np.random.default_rng(1).integers(0, 255, (20, 20, 3), dtype=np.uint8)
    cv2.imwrite(str(tmp_path / "noise.png"), noise)
    r = run(tmp_path / "noise.png", "-o", tmp_path / "out")
    assert r.returncode != 0 and "no object found in the image" in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1

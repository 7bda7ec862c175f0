"""samples/python/dask_augment.py (issue 15, item 5): on a 2-worker local Dask cluster over 20
small images it writes the same bytes as one process does, atomically, and a rerun skips what
is done; annotations and masks follow the images; the README's command runs as written."""

import json
import os
import re
import subprocess
import sys

import cv2
import numpy as np
import pytest

import multicage as mc
from conftest import DATA, SAMPLES, SOURCE_DIR

pytest.importorskip("dask")
pytest.importorskip("distributed")

SCRIPT = SAMPLES / "python" / "dask_augment.py"


def run(*args, cwd=None):
    r = subprocess.run([sys.executable, str(SCRIPT), *map(str, args)], capture_output=True, text=True,
                       timeout=900, cwd=cwd)
    assert r.returncode == 0, f"dask_augment.py {' '.join(map(str, args))} failed:\n{r.stdout}\n{r.stderr}"
    return r.stdout


def files(folder):
    """Every file of folder (names and bytes), temporary files included: there must be none."""
    return {name: (folder / name).read_bytes() for name in sorted(os.listdir(folder))}


@pytest.fixture(scope="module")
def images(tmp_path_factory):
    """20 small images made from the sample photos (about 160 px: resized, cropped, flipped,
    turned), three with annotations and one with its own mask."""
    folder = tmp_path_factory.mktemp("images")
    photos = sorted(p for p in os.listdir(DATA) if p.endswith((".jpg", ".png")))
    made = []
    for name in photos:
        photo = cv2.imread(str(DATA / name))
        h, w = photo.shape[:2]
        small = cv2.resize(photo, (160, round(160 * h / w)), interpolation=cv2.INTER_AREA)
        crop = cv2.resize(photo[h // 6:h - h // 6, w // 6:w - w // 6], (144, 112), interpolation=cv2.INTER_AREA)
        for suffix, image in (("small", small), ("crop", crop), ("flip", cv2.flip(small, 1)),
                              ("turn", cv2.rotate(crop, cv2.ROTATE_90_CLOCKWISE))):
            made.append((f"{os.path.splitext(name)[0]}_{suffix}", image))
    made = made[:20]
    for stem, image in made:
        cv2.imwrite(str(folder / f"{stem}.png"), image)
    assert len(made) == 20
    for stem, image in made[:3]:
        h, w = image.shape[:2]
        (folder / f"{stem}.json").write_text(json.dumps({
            "keypoints": [[w * 0.3, h * 0.4], [w * 0.6, h * 0.5], [w * 0.5, h * 0.8]],
            "boxes": [[w * 0.2, h * 0.2, w * 0.7, h * 0.6]]}))
    stem, image = made[4]
    mask = np.zeros(image.shape[:2], np.uint8)
    cv2.ellipse(mask, (image.shape[1] // 2, image.shape[0] // 2), (40, 25), 0, 0, 360, 7, -1)
    cv2.imwrite(str(folder / f"{stem}_mask.png"), mask)
    return folder, [stem for stem, _ in made]


@pytest.fixture(scope="module")
def reference(images, tmp_path_factory):
    """The single-process run: --scheduler synchronous, every OpenCV thread."""
    folder, _ = images
    out = tmp_path_factory.mktemp("single")
    text = run(folder, "-o", out, "--copies", 2, "--seed", 15, "--scheduler", "synchronous")
    assert "20 images on this process: 20 augmented" in text
    return out


def test_two_worker_cluster_writes_the_single_process_bytes(images, reference, tmp_path):
    folder, stems = images
    out = tmp_path / "cluster"
    text = run(folder, "-o", out, "--copies", 2, "--seed", 15, "--workers", 2)
    assert "a local cluster of 2 worker processes: 20 augmented, 0 skipped" in text
    expected = files(reference)
    assert len(expected) == 20 * (2 * 3 + 1), sorted(expected)  # 2 copies x (image, mask, json) + cage
    got = files(out)
    assert sorted(got) == sorted(expected)
    different = [name for name in expected if got[name] != expected[name]]
    assert not different, f"the cluster's outputs differ from one process's: {different}"

    # A rerun skips everything and rewrites nothing.
    before = {name: os.stat(out / name).st_mtime_ns for name in got}
    text = run(folder, "-o", out, "--copies", 2, "--seed", 15, "--workers", 2)
    assert "0 augmented, 20 skipped" in text
    assert {name: os.stat(out / name).st_mtime_ns for name in got} == before

    # A copy lost (an interrupted run): only it is made again, the same bytes.
    victim = stems[7]
    for name in (f"{victim}_001.png", f"{victim}_001.json"):
        (out / name).unlink()
    text = run(folder, "-o", out, "--copies", 2, "--seed", 15, "--workers", 2)
    assert f"{victim}.png: wrote 1 of 2 copies" in text and "19 skipped" in text
    assert files(out) == expected


def test_outputs_follow_the_image(images, reference):
    folder, stems = images
    # Annotations: the keypoints are where transform_points puts them for the pose used.
    stem = stems[0]
    meta = json.loads((reference / f"{stem}_001.json").read_text())
    cage = mc.Multicage.load(str(reference / f"{stem}_cage.yml"))
    assert cage.pose_count == 2 and np.allclose(cage.pose("aug001").vertices, meta["pose"])
    image = cv2.imread(str(folder / f"{stem}.png"))
    deformer = mc.Deformer(image, cage, backend="cpu", grid_step=2, map_step=2)  # MulticageWarp's
    annotations = json.loads((folder / f"{stem}.json").read_text())
    pose = np.array(meta["pose"], np.float32)
    assert np.allclose(meta["keypoints"], deformer.transform_points(pose, annotations["keypoints"]), atol=1e-4)
    assert len(meta["boxes"]) == 1 and meta["boxes"][0] != annotations["boxes"][0]
    assert np.array_equal(cv2.imread(str(reference / f"{stem}_001.png")), deformer.deform(pose))
    assert mc.validate_pose(cage, pose)[0] and deformer.folded_triangles(pose) == 0
    # The given mask: deformed with the image's maps, its labels kept.
    masked = stems[4]
    mask = cv2.imread(str(reference / f"{masked}_000_mask.png"), cv2.IMREAD_UNCHANGED)
    assert set(np.unique(mask)) == {0, 7}
    assert not np.array_equal(mask, cv2.imread(str(folder / f"{masked}_mask.png"), cv2.IMREAD_UNCHANGED))
    # Different copies and images get different poses.
    poses = [json.loads((reference / f"{s}_{k:03d}.json").read_text())["seed"] for s in stems for k in range(2)]
    assert len(set(poses)) == 40


def test_given_cage_and_bad_input(images, tmp_path):
    folder, stems = images
    out = tmp_path / "caged"
    text = run(folder, "-o", out, "--copies", 1, "--cage", SAMPLES / "butterfly.yml", "--scheduler", "synchronous")
    assert "20 augmented" in text
    cage = mc.Multicage.load(str(out / f"{stems[0]}_cage.yml"))
    assert cage.polygon_count == 2  # butterfly.yml's, scaled to the image
    r = subprocess.run([sys.executable, str(SCRIPT), str(tmp_path / "missing"), "-o", str(tmp_path / "o")],
                       capture_output=True, text=True)
    assert r.returncode != 0 and "no such folder" in r.stderr
    (tmp_path / "junk").mkdir()
    (tmp_path / "junk" / "broken.png").write_bytes(b"not a png")
    r = subprocess.run([sys.executable, str(SCRIPT), str(tmp_path / "junk"), "-o", str(tmp_path / "o2"),
                        "--scheduler", "synchronous"], capture_output=True, text=True)
    assert r.returncode == 1 and "broken.png: error" in r.stdout


def test_readme_at_scale_command_runs_as_written(tmp_path):
    text = (SOURCE_DIR / "README.md").read_text()
    section = re.search(r"^## At scale\n(.*?)^## ", text, re.S | re.M)
    assert section, "README.md has no '## At scale' section"
    commands = [line.strip() for line in section.group(1).splitlines() if "dask_augment.py" in line
                and line.strip().startswith("PYTHONPATH=")]
    assert commands, "the section shows no dask_augment.py command"
    command = commands[0]
    out = re.search(r"-o (\S+)", command).group(1)
    # As written, from the source folder; only the output goes to a fresh folder and the module
    # comes from this build (the README's build/python is where `cmake -B build` puts it).
    command = command.replace(f"-o {out}", f"-o {tmp_path / 'out'}")
    command = command.replace("PYTHONPATH=build/python", f"PYTHONPATH={os.pathsep.join(p for p in sys.path if p)}")
    command = command.replace("/usr/bin/python3", sys.executable)
    before = set(os.listdir(SOURCE_DIR))
    r = subprocess.run(command, shell=True, cwd=SOURCE_DIR, capture_output=True, text=True, timeout=900)
    assert r.returncode == 0, f"{commands[0]}\nfails as written:\n{r.stdout}\n{r.stderr}"
    assert "0 failed" in r.stdout
    assert set(os.listdir(SOURCE_DIR)) == before, "the example must not leave files in the source folder"
    assert any(name.endswith("_mask.png") for name in os.listdir(tmp_path / "out"))


def test_damaged_files_are_named_get_no_output_and_the_rest_finish(images, tmp_path):
    """Issue 22 item 3: a truncated JPEG, a zero-byte file and a text file named .png among good
    images. cv2.imread decoded the cut JPEG into a half-grey picture that the sample augmented
    and reported as done; now each damaged file is named in the summary with the reason, gets
    no output, the good images are augmented as usual, and the exit status is 1."""
    folder, stems = images
    mixed = tmp_path / "mixed"
    mixed.mkdir()
    good = stems[:3]
    for stem in good:
        (mixed / f"{stem}.png").write_bytes((folder / f"{stem}.png").read_bytes())
    (mixed / "cut.jpg").write_bytes((DATA / "butterfly.jpg").read_bytes()[:2000])  # the file
    (mixed / "empty.jpg").write_bytes(b"")
    (mixed / "notes.png").write_text("a text file, not an image\n")
    assert cv2.imread(str(mixed / "cut.jpg")) is not None  # what the sample used to read
    out = tmp_path / "out"
    r = subprocess.run([sys.executable, str(SCRIPT), str(mixed), "-o", str(out), "--copies", "2", "--seed", "3",
                        "--scheduler", "synchronous"], capture_output=True, text=True, timeout=900)
    assert r.returncode == 1, f"{r.stdout}\n{r.stderr}"
    lines = r.stdout.splitlines()
    assert lines[-1] == (f"6 images on this process: 3 augmented, 0 skipped (already done), 3 failed: "
                         f"cut.jpg, empty.jpg, notes.png; outputs in {out}")
    reasons = {"cut.jpg": "the file is truncated", "empty.jpg": "the file is empty",
               "notes.png": "not an image OpenCV can read"}
    for name, why in reasons.items():
        line = next(line for line in lines if line.startswith(f"{name}: "))
        assert line.startswith(f"{name}: error: ") and why in line and "\n" not in line, line
    for stem in good:
        assert f"{stem}.png: wrote 2 of 2 copies" in lines
    written = sorted(os.listdir(out))
    assert written == sorted(f"{stem}{suffix}" for stem in good for suffix in
                             ("_000.png", "_000_mask.png", "_000.json", "_001.png", "_001_mask.png",
                              "_001.json", "_cage.yml")), written

"""Issue 40 items 1 and 5: cage files are standard YAML and JSON that PyYAML and Python's json
read to the numbers the library holds, bit for bit; `multicage pose` writes poses a script made."""

import json
import math
import struct

import numpy as np
import pytest
import yaml

import multicage as mc
from conftest import DATA, SAMPLES


def awkward_cage():
    """Two nested polygons with coordinates that need all 9 digits of a float, tiny and huge
    exponents, negative zero, and pose names YAML would read as other types unquoted."""
    cage = mc.Multicage((640, 480))
    cage.add_polygon(np.float32([[20.1, 30.7], [600.3333, 25.5], [610, 450.125], [25, 455]]))
    cage.add_polygon(np.float32([[200, 200], [1 / 3 * 900, 201], [301, 300.0001], [199.99999, 299]]))
    cage.orient()
    rng = np.random.default_rng(1)
    for k, name in enumerate(["rest", "yes", "1.5", "null", "a: b # c", 'say "hi"', "x\\y"]):
        pose = cage.vertices()[: cage.vertex_count].astype(np.float32)
        pose += rng.normal(0, 3, pose.shape).astype(np.float32) * (k > 0)
        if k == 1:
            pose[0, 0] = np.float32(1e-7)
            pose[0, 1] = np.float32(-0.0)
        cage.add_pose(name, pose, time=[0, 0.1, 1 / 3, 1e-9, 2.5, 3, 4][k])
    return cage


def bits(values):
    return [struct.pack("<f", v) for v in np.asarray(values, np.float32).ravel()]


@pytest.mark.parametrize("ext", [".yml", ".json"])
def test_written_files_are_read_by_standard_tools_bit_for_bit(tmp_path, ext):
    cage = awkward_cage()
    path = tmp_path / ("cage" + ext)
    cage.save(str(path))
    text = path.read_text()
    data = json.loads(text) if ext == ".json" else yaml.safe_load(text)
    if ext == ".yml":
        assert text.startswith("%YAML 1.2\n---\n")
    assert data["image_size"] == [640, 480]
    assert len(data["polygons"]) == cage.polygon_count
    for i, polygon in enumerate(data["polygons"]):
        assert all(isinstance(v, (int, float)) for v in polygon), polygon
        assert bits(polygon) == bits(cage.polygon(i))
    assert [p["name"] for p in data["poses"]] == [p.name for p in cage.poses]
    for written, pose in zip(data["poses"], cage.poses):
        assert isinstance(written["name"], str)
        assert written["time"] == pose.time  # a double, also bit for bit
        assert bits(written["vertices"]) == bits(pose.vertices)
    assert math.copysign(1, data["poses"][1]["vertices"][1]) == -1  # -0.0 kept
    back = mc.Multicage.load(str(path))
    assert [p.name for p in back.poses] == [p.name for p in cage.poses]
    assert all(bits(a.vertices) == bits(b.vertices) for a, b in zip(back.poses, cage.poses))


def test_numbers_are_as_short_as_they_can_be(tmp_path):
    cage = mc.Multicage((100, 100))
    cage.add_polygon(np.float32([[10, 10], [90, 10], [90, 90], [10.5, 90]]))
    cage.add_pose("rest", cage.vertices())
    cage.save(str(tmp_path / "c.yml"))
    text = (tmp_path / "c.yml").read_text()
    assert "[10, 10, 90, 10, 90, 90, 10.5, 90]" in text, text
    assert "e+" not in text and "0000" not in text


def test_files_written_before_still_load():
    # OpenCV's own writer ("%YAML:1.0", "{:name:rest") and hand-written samples
    for path in [SAMPLES / "butterfly.yml", SAMPLES / "butterfly_flap.yml"]:
        assert mc.Multicage.load(str(path)).polygon_count >= 1


def test_a_file_edited_by_a_yaml_tool_loads(tmp_path):
    cage = awkward_cage()
    cage.save(str(tmp_path / "c.yml"))
    data = yaml.safe_load((tmp_path / "c.yml").read_text())
    data["poses"][0]["name"] = "moved"
    data["poses"][0]["vertices"][0] += 2
    (tmp_path / "edited.yml").write_text(yaml.safe_dump(data))
    (tmp_path / "edited.json").write_text(json.dumps(data))
    for name in ["edited.yml", "edited.json"]:
        back = mc.Multicage.load(str(tmp_path / name))
        assert back.pose(0).name == "moved"
        assert back.pose(0).vertices[0, 0] == np.float32(data["poses"][0]["vertices"][0])


def test_pose_command_moves_targets_in_order_and_refuses_crossings(cli, tmp_path):
    cage = mc.Multicage((400, 300))
    cage.add_polygon(np.float32([[50, 50], [350, 50], [350, 250], [50, 250]]))
    cage.add_polygon(np.float32([[150, 100], [250, 100], [250, 200], [150, 200]]))
    cage.orient()
    cage.save(str(tmp_path / "c.yml"))
    inner = cage.polygon(1)
    out = tmp_path / "posed.yml"
    r = cli("pose", tmp_path / "c.yml", "--name", "turn", "--rotate", "1", "90", "--translate", "1", "10", "-5",
            "--move-vertex", "0:2", "360", "260", "-o", out)
    assert "pose 'turn'" in r.stdout
    posed = mc.Multicage.load(str(out))
    turned = posed.pose("turn").vertices
    centre = inner.mean(axis=0)
    # 90 degrees counter-clockwise on screen (y down): (dx, dy) -> (dy, -dx), then moved
    expected = np.stack([centre[0] + (inner[:, 1] - centre[1]), centre[1] - (inner[:, 0] - centre[0])], 1)
    np.testing.assert_allclose(turned[4:], expected + [10, -5], atol=1e-3)
    np.testing.assert_allclose(turned[2], [360, 260])
    np.testing.assert_array_equal(turned[[0, 1, 3]], cage.polygon(0)[[0, 1, 3]])
    assert posed.pose("turn").time == 0  # the first keyframe at 0 s, the next one second later
    # --about and --scale of a nested target: both polygons scale about the given point; no -o:
    # into the file itself
    cli("pose", out, "--name", "small", "--about", "200", "150", "--scale", "0+", "0.5")
    assert mc.Multicage.load(str(out)).pose("small").time == 1
    small = mc.Multicage.load(str(out)).pose("small").vertices
    np.testing.assert_allclose(small, 200 + (cage.vertices()[:8] - [200, 150]) * 0.5 + [0, -50], atol=1e-3)

    import subprocess, os
    crossing = subprocess.run([os.environ["MULTICAGE_CLI"], "pose", str(out), "--name", "bad", "--translate", "1",
                               "150", "0", "-o", str(tmp_path / "bad.yml")], capture_output=True, text=True)
    assert crossing.returncode == 1 and not (tmp_path / "bad.yml").exists()
    assert "polygon" in crossing.stderr and "--allow-invalid" in crossing.stderr
    assert len(crossing.stderr.strip().splitlines()) == 1

"""Bad input fails early with an exception that says what is wrong; library errors keep the
C++ library's own message (no 'OpenCV(...) file.cpp:123' wrapping)."""

import re

import numpy as np
import pytest

import multicage as mc
from conftest import square


@pytest.fixture()
def deformer(butterfly, butterfly_cage):
    return mc.Deformer(butterfly, butterfly_cage, backend="cpu", grid_step=4)


@pytest.mark.parametrize("dtype", [np.float64, np.int8, np.int32, np.bool_, np.float16])
def test_wrong_image_dtype_is_a_type_error(butterfly, butterfly_cage, dtype):
    with pytest.raises(TypeError, match=r"image: dtype \w+ is not supported; use uint8, uint16 or float32"):
        mc.Deformer(butterfly.astype(dtype), butterfly_cage)
    with pytest.raises(TypeError, match="uint8, uint16 or float32"):
        mc.deform_image(butterfly.astype(dtype), butterfly_cage, butterfly_cage.rest_pose())


@pytest.mark.parametrize("shape,message", [
    ((356, 493, 2), r"2 channels \(shape \(356, 493, 2\)\) are not supported"),
    ((356, 493, 5), r"5 channels"),
    ((356, 493, 3, 1), r"shape \(356, 493, 3, 1\) is not an image"),
    ((493,), r"shape \(493,\) is not an image"),
    ((0, 493, 3), r"the image is empty"),
])
def test_wrong_image_shape_is_a_value_error(butterfly_cage, shape, message):
    with pytest.raises(ValueError, match=message):
        mc.Deformer(np.zeros(shape, np.uint8), butterfly_cage)


def test_not_an_array_is_a_type_error(butterfly, butterfly_cage):
    with pytest.raises(TypeError, match="expected a numpy array .* got list"):
        mc.Deformer(butterfly.tolist(), butterfly_cage)


def test_binding_of_another_size_says_what_to_do_in_python_terms(butterfly, butterfly_cage):
    # A Multicage is scaled to the image (test_cli_agreement); a Binding cannot be: the error
    # names both sizes and the Python way out, never a C++ function.
    binding = mc.bind(butterfly_cage, grid_step=8)
    with pytest.raises(ValueError, match=r"the image is 493x100 but the binding was made for 493x356; "
                                         r"pass the Multicage instead .* cage\.scaled\(\(493, 100\)\)") as e:
        mc.Deformer(butterfly[:100], binding)
    assert "::" not in str(e.value) and "Size" not in str(e.value)


def test_multicage_without_a_size_is_a_value_error(butterfly):
    with pytest.raises(ValueError, match=r"the multicage has no image size; make it with Multicage\(\(width, height\)\)"):
        mc.Deformer(butterfly, mc.Multicage())


def test_library_errors_carry_code_and_function(butterfly, butterfly_cage):
    pose = butterfly_cage.rest_pose()
    with pytest.raises(mc.Error) as e:
        mc.Deformer(butterfly, butterfly_cage, backend="cpu", grid_step=8).deform(pose[:3])
    assert isinstance(e.value, ValueError)
    assert not str(e.value).startswith("OpenCV"), "the message must be the library's, not cv::Exception::what()"
    assert e.value.code < 0 and e.value.func


def test_pose_of_the_wrong_length(deformer, butterfly_cage):
    pose = butterfly_cage.rest_pose()
    message = r"^multicage: the pose has 19 vertices; the multicage has 20 \(or 24 with the frame corners\)$"
    for call in (deformer.deform, deformer.compute_maps, deformer.folded_triangles):
        with pytest.raises(mc.Error, match=message):
            call(pose[:19])
    # vertex_count and vertex_count + 4 are both fine
    assert deformer.deform(pose).shape == deformer.deform(butterfly_cage.vertices()).shape


@pytest.mark.parametrize("value", [np.nan, np.inf])
def test_non_finite_pose_names_the_point(deformer, butterfly_cage, value):
    pose = butterfly_cage.rest_pose()
    pose[7, 1] = value
    with pytest.raises(ValueError, match=r"pose: point 7 is not finite"):
        deformer.deform(pose)
    with pytest.raises(ValueError, match=r"point 7 is not finite"):
        butterfly_cage.add_pose("bad", pose)


@pytest.mark.parametrize("pose,error,message", [
    (np.zeros((20, 3), np.float32), ValueError, r"pose: shape \(20, 3\) is not a list of points; expected Nx2"),
    (np.zeros(40, np.float32), ValueError, r"shape \(40,\)"),
    (np.array([["a", "b"]] * 20), TypeError, r"pose: dtype <U1 is not a real number type"),
])
def test_pose_of_the_wrong_shape_or_type(deformer, pose, error, message):
    with pytest.raises(error, match=message):
        deformer.deform(pose)


def test_contours_from_cv2_are_points(butterfly_cage):
    # cv2.findContours gives Nx1x2 int32: accepted as points.
    cage = mc.Multicage((100, 80))
    contour = square(10, 10, 60, 50).astype(np.int32).reshape(-1, 1, 2)
    assert cage.add_polygon(contour) == 0
    assert np.array_equal(cage.polygon(0), square(10, 10, 60, 50))


def test_invalid_multicage_reports_where():
    cage = mc.Multicage((100, 100))
    cage.add_polygon(square(10, 10, 60, 60))
    cage.add_polygon(square(40, 40, 90, 90))  # crosses polygon 0
    ok, why = cage.validate()
    assert not ok and "polygon 1" in why and "polygon 0" in why
    with pytest.raises(mc.Error, match="polygon 1"):
        cage.validate(raise_error=True)
    with pytest.raises(mc.Error, match="^multicage: cannot bind: " + re.escape(why) + "$"):
        mc.Deformer(np.zeros((100, 100), np.uint8), cage, backend="cpu")
    with pytest.raises(mc.Error, match="cannot bind"):
        mc.bind(cage)


def test_bad_parameters(butterfly, butterfly_cage):
    with pytest.raises(ValueError, match=r"backend: 'cuda' is not one of 'auto', 'cpu', 'gpu'"):
        mc.Deformer(butterfly, butterfly_cage, backend="cuda")
    with pytest.raises(ValueError, match=r"coordinates: 'wachspress' is not one of"):
        mc.Deformer(butterfly, butterfly_cage, coordinates="wachspress")
    with pytest.raises(ValueError, match="grid_step: must be >= 1"):
        mc.Deformer(butterfly, butterfly_cage, grid_step=0)
    with pytest.raises(TypeError, match="expected a multicage.Multicage or a multicage.Binding"):
        mc.Deformer(butterfly, "cage.yml")
    with pytest.raises(TypeError, match=r"unexpected keyword argument 'max_vertex'.*max_vertices"):
        mc.propose_multicage(butterfly, max_vertex=10)
    with pytest.raises(ValueError, match="method: 'magic' is not one of"):
        mc.propose_multicage(butterfly, method="magic")
    with pytest.raises(mc.Error, match="constant"):
        mc.propose_multicage(np.zeros((50, 50), np.uint8))
    with pytest.raises(TypeError, match=r"expected \(width, height\)"):
        mc.Multicage((100,))
    with pytest.raises(IndexError, match=r"polygon 7 does not exist \(there are 2 polygons\)"):
        butterfly_cage.polygon(7)
    with pytest.raises(KeyError, match="no pose named 'nope' .*flap"):
        butterfly_cage.pose("nope")


def test_library_errors_keep_their_message(tmp_path):
    with pytest.raises(mc.Error, match="^meanValueCoordinates: the polygon has 2 vertices, it needs at least 3$"):
        mc.mean_value_coordinates([[0, 0], [1, 0]], [[0.5, 0.5]])
    with pytest.raises(mc.Error, match="cannot be opened"):
        mc.Multicage.load(str(tmp_path / "missing.yml"))
    bad = tmp_path / "bad.yml"
    bad.write_text("%YAML:1.0\n---\nimage_size: [ 100, 100 ]\npolygons:\n   - [ 1, 2, 3, 4, 5, 6, 7 ]\n")
    with pytest.raises(mc.Error, match=r"polygons\[0\]"):
        mc.Multicage.load(str(bad))


# --- issue 13 item 13: errors in Python's terms -----------------------------------------------

@pytest.mark.parametrize("keyword,value,message", [
    ("margin", "5", r"margin: expected a number, got str '5'"),
    ("min_region_area", "0.01", r"min_region_area: expected a number, got str"),
    ("max_vertices", 2.5, r"max_vertices: expected an integer, got float 2.5"),
    ("max_vertices", "40", r"max_vertices: expected an integer, got str '40'"),
    ("max_depth", True, r"max_depth: expected an integer, got bool True"),
    ("protect", 1, r"protect: expected True or False, got int 1"),
    ("rect", "0 0 10 10", r"rect: expected \(x, y, width, height\), got str"),
    ("method", 2.0, r"method: expected a name or an enum value, got float 2.0"),
])
def test_propose_keywords_of_the_wrong_type_are_type_errors(butterfly, keyword, value, message):
    with pytest.raises(TypeError, match=message):
        mc.propose_multicage(butterfly, **{keyword: value})


def test_numpy_scalars_are_numbers(butterfly):
    a = mc.propose_multicage(butterfly, method="threshold", max_vertices=np.int64(30), margin=np.float32(4))
    b = mc.propose_multicage(butterfly, method="threshold", max_vertices=30, margin=4)
    assert a.vertex_count == b.vertex_count and np.array_equal(a.polygon(0), b.polygon(0))


@pytest.mark.parametrize("keyword,value,error,message", [
    ("grid_step", "4", TypeError, r"grid_step: expected an integer, got str '4'"),
    ("grid_step", 2.0, TypeError, r"grid_step: expected an integer, got float"),
    ("half_float", "yes", TypeError, r"half_float: expected True or False, got str 'yes'"),
    ("border_value", "white", TypeError, r"border_value: expected a number or up to 4 numbers"),
    ("memory_budget", "1G", TypeError, r"memory_budget: expected a number, got str '1G'"),
    ("memory_budget", -1, ValueError, r"memory_budget: expected a whole number of bytes >= 0"),
    ("coordinates", 3.5, TypeError, r"coordinates: expected a name or an enum value"),
])
def test_deformer_keywords_of_the_wrong_type_name_the_keyword(butterfly, butterfly_cage, keyword, value, error,
                                                               message):
    with pytest.raises(error, match=message):
        mc.Deformer(butterfly, butterfly_cage, backend="cpu", **{keyword: value})


@pytest.mark.parametrize("call", [
    lambda image, cage: mc.Deformer(image, cage, "cpu"),
    lambda image, cage: mc.Deformer.create(image, cage, "cpu", 4),
    lambda image, cage: mc.deform_image(image, cage, cage.rest_pose(), "cpu"),
    lambda image, cage: mc.propose_multicage(image, "threshold"),
    lambda image, cage: cage.draw(image, "thick"),
    lambda image, cage: mc.Multicage.for_image(image, 2),
    lambda image, cage: mc.Deformer(image, cage, backend="cpu", grid_step=4).deform(image),
])
def test_positional_misuse_does_not_print_the_image(butterfly, butterfly_cage, call):
    with pytest.raises((TypeError, ValueError)) as e:
        call(butterfly, butterfly_cage)
    message = str(e.value)
    assert len(message) < 1200, f"{len(message)} characters: the message shows the image"
    assert "[[" not in message and "dtype=uint8)" not in message.replace("dtype=uint8),", "")
    if isinstance(e.value, TypeError) and "incompatible" in message:
        assert "numpy.ndarray(shape=(356, 493, 3), dtype=uint8)" in message
        assert "multicage._multicage" not in message
        if "*" in message.split("Invoked with")[0]:
            assert "keyword-only: pass them as name=value" in message


def test_other_type_errors_pass_through_unchanged(butterfly_cage):
    # The rewriting touches only pybind11's argument mismatch, never the module's own messages.
    with pytest.raises(TypeError, match=r"^rest: expected a multicage.Multicage or a multicage.Binding, got str"):
        mc.Deformer(np.zeros((10, 10), np.uint8), "cage.yml")


def test_pose_vertices_are_read_only_or_assigned_whole(butterfly_cage):
    """`pose.vertices[0] = ...` must not silently do nothing: it raises; assigning a whole
    array writes through."""
    pose = butterfly_cage.pose("flap")
    before = pose.vertices.copy()
    with pytest.raises(ValueError, match="read-only"):
        pose.vertices[0] = (1, 2)
    with pytest.raises(ValueError, match="read-only"):
        pose.vertices[:, 1] -= 8
    assert np.array_equal(pose.vertices, before)
    v = pose.vertices.copy()
    v[0] = (1, 2)
    pose.vertices = v
    assert np.array_equal(pose.vertices[0], [1, 2])
    # Binding.rest_vertices and coefficients likewise; rest_pose() and polygon() are fresh arrays.
    binding = mc.bind(butterfly_cage, grid_step=16)
    with pytest.raises(ValueError, match="read-only"):
        binding.rest_vertices[0] = 0
    rest = butterfly_cage.rest_pose()
    rest[0] = 0
    assert not np.array_equal(butterfly_cage.rest_pose(), rest)


def test_propose_without_an_object_raises_as_the_cli_fails(tmp_path):
    """A 20x20 noise image: the CLI says "no object found"; Python raises NoObjectFoundError
    (a multicage.Error, so a batch can skip such images) instead of returning an empty cage."""
    noise = np.random.default_rng(1).integers(0, 255, (20, 20, 3), dtype=np.uint8)
    with pytest.raises(mc.NoObjectFoundError, match=r"^propose_multicage: no object found with method='auto'"):
        mc.propose_multicage(noise)
    assert issubclass(mc.NoObjectFoundError, mc.Error) and issubclass(mc.NoObjectFoundError, ValueError)
    # an empty mask: no object either
    with pytest.raises(mc.NoObjectFoundError, match="method='mask'"):
        mc.propose_multicage(np.zeros((50, 50), np.uint8) + np.eye(50, dtype=np.uint8), method="mask",
                             min_region_area=0.5)
    import os
    import subprocess
    cli = os.environ.get("MULTICAGE_CLI")
    if cli:
        import cv2
        cv2.imwrite(str(tmp_path / "noise.png"), noise)
        r = subprocess.run([cli, "propose", str(tmp_path / "noise.png"), "-o", str(tmp_path / "c.yml")],
                           capture_output=True, text=True)
        assert r.returncode != 0 and "no object found" in r.stderr


def test_an_image_cv2_could_not_read_says_so(butterfly_cage):
    import cv2
    missing = cv2.imread("no/such/file.jpg")
    with pytest.raises(TypeError, match=r"image: expected a numpy array, got None \(cv2.imread returns None"):
        mc.Deformer(missing, butterfly_cage)

"""The Python module and the C++ `multicage` tool give the same pixels for the same inputs:
both are the one library, so any difference is a conversion bug (dtype, channels, strides,
cage scaling, pose order)."""

import cv2
import numpy as np
import pytest

import multicage as mc


def cli_deform(cli, tmp_path, image_path, cage_path, *args):
    out = tmp_path / "cli_out.png" if not str(image_path).endswith(".tiff") else tmp_path / "cli_out.tiff"
    cli("deform", image_path, cage_path, "-o", out, *args)
    result = cv2.imread(str(out), cv2.IMREAD_UNCHANGED)
    assert result is not None
    return result


def assert_same_pixels(python, cli):
    assert python.shape == cli.shape and python.dtype == cli.dtype
    diff = np.count_nonzero(python != cli)
    assert np.array_equal(python, cli), f"{diff} values differ between the Python module and the CLI"


@pytest.mark.parametrize("backend", ["cpu", "gpu"])
def test_deform_sample_equals_cli(cli, gpu, tmp_path, butterfly, butterfly_cage, butterfly_cage_path, backend):
    if backend == "gpu" and not gpu:
        pytest.skip("no headless EGL context here")
    from conftest import DATA
    expected = cli_deform(cli, tmp_path, DATA / "butterfly.jpg", butterfly_cage_path,
                          "--pose", "flap", "--backend", backend)
    deformer = mc.Deformer(butterfly, butterfly_cage, backend=backend)
    assert deformer.backend == backend
    got = deformer.deform(butterfly_cage.pose("flap").vertices)
    assert not np.array_equal(got, butterfly), "the pose should move pixels"
    assert_same_pixels(got, expected)
    # The one-shot form and a Binding shared through bind() are the same computation.
    assert_same_pixels(mc.deform_image(butterfly, butterfly_cage, butterfly_cage.pose(0).vertices,
                                       backend=backend), expected)


def test_grid_step_and_harmonic_equal_cli(cli, tmp_path, butterfly, butterfly_cage, butterfly_cage_path):
    from conftest import DATA
    expected = cli_deform(cli, tmp_path, DATA / "butterfly.jpg", butterfly_cage_path,
                          "--backend", "cpu", "--grid-step", "3", "--coords", "harmonic")
    binding = mc.bind(butterfly_cage, coordinates="harmonic", grid_step=3)
    assert binding.grid_step == 3 and binding.coordinates == "harmonic"
    deformer = mc.Deformer(butterfly, binding, backend=mc.Backend.CPU)
    assert_same_pixels(deformer.deform(butterfly_cage.pose(0).vertices), expected)


@pytest.mark.parametrize("kind", ["bgra16", "gray8", "float32"])
def test_other_types_and_a_scaled_cage_equal_cli(cli, tmp_path, butterfly, butterfly_cage, butterfly_cage_path, kind):
    """A cage drawn for 493x356 applied to a 301x217 image: the CLI scales it, Python does
    it with Multicage.scaled; 16-bit BGRA, 8-bit gray and float BGRA images keep their type."""
    small = cv2.resize(butterfly, (301, 217), interpolation=cv2.INTER_AREA)
    if kind == "bgra16":
        alpha = np.tile(np.linspace(0, 255, 301, dtype=np.uint8), (217, 1))
        image = np.dstack([small, alpha]).astype(np.uint16) * 257
        path = tmp_path / "in.png"
    elif kind == "gray8":
        image = cv2.cvtColor(small, cv2.COLOR_BGR2GRAY)
        path = tmp_path / "in.png"
    else:
        # Four channels: OpenCV writes 3-channel float TIFF lossily (SGILOG), 1 and 4 exactly.
        image = cv2.cvtColor(small, cv2.COLOR_BGR2BGRA).astype(np.float32) / 255.0
        path = tmp_path / "in.tiff"
    assert cv2.imwrite(str(path), image)
    assert np.array_equal(cv2.imread(str(path), cv2.IMREAD_UNCHANGED), image)
    expected = cli_deform(cli, tmp_path, path, butterfly_cage_path, "--backend", "cpu", "--grid-step", "2")
    cage = butterfly_cage.scaled((301, 217))
    assert cage.image_size == (301, 217)
    got = mc.Deformer(image, cage, backend="cpu", grid_step=2).deform(cage.pose(0).vertices)
    assert got.dtype == image.dtype and got.shape == image.shape
    assert_same_pixels(got, expected)


def test_python_cage_file_and_propose_equal_cli(cli, tmp_path):
    """propose: the CLI's cage file and propose_multicage hold the same polygons; a pose added
    and saved from Python deforms the same in the CLI."""
    from conftest import DATA
    image_path = DATA / "HappyFish.jpg"
    image = cv2.imread(str(image_path), cv2.IMREAD_UNCHANGED)
    cli("propose", image_path, "-o", tmp_path / "cli_cage.yml", "--max-vertices", "40")
    from_cli = mc.Multicage.load(str(tmp_path / "cli_cage.yml"))
    cage = mc.propose_multicage(image, max_vertices=40)
    assert cage.polygon_count >= 1 and cage.validate() == (True, "")
    assert from_cli.polygon_count == cage.polygon_count
    for i in range(cage.polygon_count):
        assert np.array_equal(from_cli.polygon(i), cage.polygon(i)), f"polygon {i} differs"

    pose = cage.rest_pose()
    centre = pose[:, 0].mean()  # narrower about the middle: every polygon stays valid and nested
    pose[:, 0] = (centre + (pose[:, 0] - centre) * 0.95).astype(np.float32)
    cage.add_pose("wider", pose)
    cage.save(str(tmp_path / "py_cage.yml"))
    expected = cli_deform(cli, tmp_path, image_path, tmp_path / "py_cage.yml", "--pose", "wider", "--backend", "cpu")
    got = mc.Deformer(image, mc.Multicage.load(str(tmp_path / "py_cage.yml")), backend="cpu").deform(pose)
    assert_same_pixels(got, expected)


@pytest.mark.parametrize("size", [(301, 217), (986, 712)])
def test_a_cage_for_another_size_is_scaled_as_the_cli_scales_it(cli, tmp_path, butterfly, butterfly_cage,
                                                                butterfly_cage_path, size):
    """Issue 13 item 11: Deformer(resized_image, cage) scales the cage to the image silently,
    as `multicage deform` does, and takes poses in the cage's own coordinates (the cage file's
    poses), so the same pose name gives the same pixels in both."""
    image = cv2.resize(butterfly, size, interpolation=cv2.INTER_AREA)
    path = tmp_path / "resized.png"
    assert cv2.imwrite(str(path), image)
    expected = cli_deform(cli, tmp_path, path, butterfly_cage_path, "--pose", "flap", "--backend", "cpu",
                          "--grid-step", "2")
    deformer = mc.Deformer(image, butterfly_cage, backend="cpu", grid_step=2)
    assert deformer.image_size == size and deformer.cage_size == (493, 356)
    flap = butterfly_cage.pose("flap").vertices
    got = deformer.deform(flap)
    assert got.shape == image.shape
    assert_same_pixels(got, expected)
    # The one-shot form scales the same way; explicit scaling gives the same deformer.
    assert_same_pixels(mc.deform_image(image, butterfly_cage, flap, backend="cpu", grid_step=2), expected)
    scaled = butterfly_cage.scaled(size)
    explicit = mc.Deformer(image, scaled, backend="cpu", grid_step=2)
    assert_same_pixels(explicit.deform(scaled.pose("flap").vertices), expected)
    # Maps and fold-over counts take the pose in the same coordinates as deform.
    for got_map, explicit_map in zip(deformer.compute_maps(flap), explicit.compute_maps(scaled.pose("flap").vertices)):
        assert np.array_equal(got_map, explicit_map)
    assert deformer.folded_triangles(flap) == explicit.folded_triangles(scaled.pose("flap").vertices)
    # With the frame corners appended (vertex_count + 4 points) the pose scales the same.
    assert_same_pixels(deformer.deform(np.vstack([flap, butterfly_cage.frame()])), expected)


def test_the_cage_files_coordinates_are_followed_unless_given(cli, tmp_path, butterfly, butterfly_cage):
    """Issue 13 item 6: a cage file's `coordinates: harmonic` is followed by Deformer,
    deform_image and bind as by `multicage deform`; coordinates= overrides it."""
    from conftest import DATA
    butterfly_cage.coordinates = "harmonic"
    path = tmp_path / "harmonic.yml"
    butterfly_cage.save(str(path))
    cage = mc.Multicage.load(str(path))
    assert cage.coordinates == "harmonic"
    expected = cli_deform(cli, tmp_path, DATA / "butterfly.jpg", path, "--backend", "cpu", "--grid-step", "4")
    deformer = mc.Deformer(butterfly, cage, backend="cpu", grid_step=4)
    assert deformer.coordinates == "harmonic" and deformer.binding.coordinates == "harmonic"
    pose = cage.pose(0).vertices
    assert_same_pixels(deformer.deform(pose), expected)
    assert_same_pixels(mc.deform_image(butterfly, cage, pose, backend="cpu", grid_step=4), expected)
    assert mc.bind(cage, grid_step=8).coordinates == "harmonic"
    # The caller's choice wins, as --coords does.
    expected_mvc = cli_deform(cli, tmp_path, DATA / "butterfly.jpg", path, "--backend", "cpu", "--grid-step", "4",
                              "--coords", "mvc")
    mvc = mc.Deformer(butterfly, cage, backend="cpu", grid_step=4, coordinates="mvc")
    assert mvc.coordinates == "mvc"
    assert_same_pixels(mvc.deform(pose), expected_mvc)
    assert not np.array_equal(expected, expected_mvc)
    assert mc.bind(cage, coordinates="mvc", grid_step=8).coordinates == "mvc"
    # A Binding already holds its coordinates: asking for others is a mistake, not a rebind.
    with pytest.raises(ValueError, match="the binding holds harmonic coordinates, not mvc"):
        mc.Deformer(butterfly, mc.bind(cage, grid_step=8), coordinates="mvc")


def cli_propose_options(cli):
    """`multicage propose --help`: {option name: default shown or None}."""
    import re
    text = cli("propose", "--help").stdout
    options = {}
    for line in text.splitlines():
        m = re.match(r"\s+(?:-\w,)?--([\w-]+)(\s+\S+)?", line)
        if m:
            default = re.search(r"\S=([\w.-]+)\s*$", line)
            options[m.group(1)] = default.group(1) if default else None
    return options


def test_propose_keywords_are_the_cli_options(cli):
    """Issue 13 items 5 and 13: every `multicage propose` option is a propose_multicage keyword
    of the same name ('-' as '_', --no-X as X=False), with the same default, and the Python
    defaults are the library's own (propose_defaults())."""
    defaults = mc.propose_defaults()
    options = cli_propose_options(cli)
    assert {"max-vertices", "margin", "method"} <= set(options), options
    aliases = {"min-area": "min_region_area"}  # the CLI's older name, accepted by Python too
    for option, default in options.items():
        if option in ("help", "help-all", "output", "overlay", "jobs", "overwrite"):  # the CLI's files and datasets
            continue
        name = option.replace("-", "_")
        name = aliases.get(option, name[3:] if name.startswith("no_") else name)
        assert name in defaults, f"--{option} has no propose_multicage keyword {name!r}"
        if default is not None:
            expected = defaults[name]
            assert type(expected)(default) == expected, f"--{option} defaults to {default}, Python to {expected}"
    # protect: the CLI's flag says which way its default goes; Python's default is the same.
    if "no-protect" in options:
        assert defaults["protect"] is True
    elif "protect" in options:
        assert defaults["protect"] is False


def test_protect_gives_the_multicage_the_cli_gives(cli, tmp_path):
    """protect=True adds inner polygons (depth 2) around features inside the outline, as
    `multicage propose --protect` does; protect=False gives outlines only; no keyword gives
    the library's default. (method='threshold': 'auto' takes GrabCut here, whose result
    varies between calls in one process.)"""
    from conftest import DATA
    # messi5.jpg: the default protects faces first (issue 21), a face polygon (depth 2) with
    # its anchors (depth 3). butterfly.jpg, used before, gets none now: its salient wings are no
    # more textured than the butterfly, and the texture rule leaves them out.
    image_path = DATA / "messi5.jpg"
    image = cv2.imread(str(image_path), cv2.IMREAD_UNCHANGED)
    protected = mc.propose_multicage(image, method="threshold", protect=True)
    outline = mc.propose_multicage(image, method="threshold", protect=False)
    assert max(protected.depth(i) for i in range(protected.polygon_count)) >= 2
    assert max(outline.depth(i) for i in range(outline.polygon_count)) == 1
    assert protected.validate() == (True, "")
    default = mc.propose_multicage(image, method="threshold")
    expected = protected if mc.propose_defaults()["protect"] else outline
    assert default.polygon_count == expected.polygon_count
    assert all(np.array_equal(default.polygon(i), expected.polygon(i)) for i in range(default.polygon_count))
    options = cli_propose_options(cli)
    for flags, cage in ((("--protect", "all"), protected), (("--no-protect",), outline)):
        flag = flags[0]
        if flag[2:] in options:
            cli("propose", image_path, "-o", tmp_path / "cli.yml", "--method", "threshold", *flags)
            from_cli = mc.Multicage.load(str(tmp_path / "cli.yml"))
            assert from_cli.polygon_count == cage.polygon_count, flag
            for i in range(cage.polygon_count):
                assert np.array_equal(from_cli.polygon(i), cage.polygon(i)), f"{flag}: polygon {i} differs"
    # Every default passed explicitly is the same as no keyword at all, and min_area is
    # min_region_area under the CLI's older name.
    explicit = mc.propose_multicage(image, **dict(mc.propose_defaults(), method="threshold"))
    assert explicit.polygon_count == default.polygon_count
    assert all(np.array_equal(explicit.polygon(i), default.polygon(i)) for i in range(default.polygon_count))
    a = mc.propose_multicage(image, method="threshold", min_area=0.05, protect=False)
    b = mc.propose_multicage(image, method="threshold", min_region_area=0.05, protect=False)
    assert a.polygon_count == b.polygon_count and np.array_equal(a.polygon(0), b.polygon(0))
    with pytest.raises(TypeError, match="both min_region_area and min_area"):
        mc.propose_multicage(image, min_area=0.05, min_region_area=0.05)

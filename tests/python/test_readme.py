"""Issue 13 item 10, issue 40 item 2, issue 41 item 2: every Python example of the README and of
the docs/ pages (docs/**/*.md), and the module docstring's example, run as written, from the
source folder with the module on PYTHONPATH (as the README says), or, with MULTICAGE_README_CWD
set, from an installed prefix's share/multicage (its samples/ beside the examples' relative
paths). The pages are read from the source folder either way. Their relative links resolve."""

import os
import pathlib
import re
import subprocess
import sys

import pytest

import multicage as mc
from conftest import SOURCE_DIR

PYTHON_PAGE = "docs/python.md"  # the Python section that left the README


def pages():
    """README.md, then every markdown page under docs/, as paths relative to the source folder."""
    docs = sorted(p.relative_to(SOURCE_DIR).as_posix() for p in (SOURCE_DIR / "docs").rglob("*.md"))
    return ["README.md", *docs]


def python_blocks(page):
    """The ```python blocks of a page, each with the line its code starts on."""
    text = (SOURCE_DIR / page).read_text()
    return [(text.count("\n", 0, m.start(1)) + 1, m.group(1))
            for m in re.finditer(r"^```python\n(.*?)^```", text, re.S | re.M)]


def all_blocks():
    return [(page, number, line, code) for page in pages()
            for number, (line, code) in enumerate(python_blocks(page), 1)]


# Where the examples run: the source folder, or an installed share/multicage.
RUN_DIR = pathlib.Path(os.environ.get("MULTICAGE_README_CWD", SOURCE_DIR))


def docstring_example():
    lines = mc.__doc__.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("    import "))
    block = []
    for line in lines[start:]:
        if line and not line.startswith("    "):
            break
        block.append(line[4:])
    return "\n".join(block).strip() + "\n"


def run_as_written(code, tmp_path, name):
    # As a script of its own (a 'spawn' pool needs an importable __main__), from the source
    # folder the examples' relative paths are written for.
    script = tmp_path / name
    script.write_text(code)
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in sys.path if p))
    r = subprocess.run([sys.executable, str(script)], cwd=RUN_DIR, env=env, capture_output=True, text=True,
                       timeout=900)
    assert r.returncode == 0, f"{name} fails as written:\n{code}\n{r.stderr[-3000:]}"
    return r


def test_readme_has_python_examples():
    blocks = [code for _, code in python_blocks("README.md")]
    assert blocks, "the README has no ```python block"
    assert any("mc.Deformer" in b and "compute_maps" in b for b in blocks)
    assert python_blocks(PYTHON_PAGE), f"{PYTHON_PAGE} has no ```python block"


@pytest.mark.parametrize("page, number, line, code",
                         [pytest.param(*block, id=f"{block[0]}-block{block[1]}-line{block[2]}")
                          for block in all_blocks()])
def test_readme_python_block_runs_as_written(tmp_path, page, number, line, code):
    before = set(os.listdir(RUN_DIR))
    name = re.sub(r"\W", "_", page[:-len(".md")]) + f"_block_{number}.py"
    run_as_written(code, tmp_path, name)
    assert set(os.listdir(RUN_DIR)) == before, \
        f"{page} line {line}: the example must not leave files in the folder it runs in"


def test_module_docstring_example_runs_as_written(tmp_path):
    code = docstring_example()
    assert "Deformer" in code and "compute_maps" in code
    run_as_written(code, tmp_path, "docstring_example.py")


def test_python_docs_name_only_what_the_module_has():
    # Every mc.NAME the Python page and the README's Python section mention exists (a renamed
    # function breaks the docs here).
    readme = (SOURCE_DIR / "README.md").read_text()
    section = re.search(r"^## Python\n(.*?)^## ", readme, re.S | re.M)
    assert section, "README.md has no '## Python' section"
    for where, text in ((PYTHON_PAGE, (SOURCE_DIR / PYTHON_PAGE).read_text()), ("README.md", section.group(1))):
        for name in set(re.findall(r"\b(?:mc|multicage)\.([A-Za-z_]\w*)", text)):
            assert hasattr(mc, name), f"{where} mentions multicage.{name}, which the module does not have"


def heading_anchors(text):
    """GitHub's anchors of a page: each heading's slug (-1, -2 for repeats), and <a id="...">."""
    text = re.sub(r"^```.*?^```", "", text, flags=re.S | re.M)
    anchors, seen = set(), {}
    for heading in re.findall(r"^#{1,6} (.*)$", text, re.M):
        heading = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", heading).replace("`", "")
        slug = re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")
        anchors.add(slug if slug not in seen else f"{slug}-{seen[slug]}")
        seen[slug] = seen.get(slug, 0) + 1
    return anchors | set(re.findall(r'<a id="([^"]+)"', text))


def test_relative_links_of_the_readme_and_docs_resolve():
    # Issue 41 item 2: text moved from the README into docs/ keeps its pictures and links; every
    # relative link or image names a file that exists, and a #fragment a heading of that page.
    broken = []
    for page in pages():
        text = (SOURCE_DIR / page).read_text()
        text = re.sub(r"^```.*?^```", lambda m: "\n" * m.group(0).count("\n"), text, flags=re.S | re.M)
        text = re.sub(r"`[^`\n]*`", "", text)
        for m in re.finditer(r"!?\[[^\]]*\]\(([^)\s]+)\)", text):
            target = m.group(1)
            if re.match(r"[a-z]+:", target):
                continue
            path, _, fragment = target.partition("#")
            dest = (SOURCE_DIR / page).parent / path if path else SOURCE_DIR / page
            where = f"{page}:{text.count(chr(10), 0, m.start()) + 1}: {target}"
            if not dest.exists():
                broken.append(f"{where}: no such file")
            elif fragment and dest.suffix == ".md" and fragment not in heading_anchors(dest.read_text()):
                broken.append(f"{where}: no heading #{fragment}")
    assert not broken, "\n".join(broken)


def cpp_blocks():
    return [(page, number, line, code) for page in pages()
            for number, (line, code) in enumerate(
                [(text.count("\n", 0, m.start(1)) + 1, m.group(1))
                 for text in [(SOURCE_DIR / page).read_text()]
                 for m in re.finditer(r"^```cpp\n(.*?)^```", text, re.S | re.M)], 1)]


@pytest.mark.parametrize("page, number, line, code", cpp_blocks(),
                         ids=[f"{p}-block{n}-line{l}" for p, n, l, _ in cpp_blocks()])
def test_cpp_block_compiles_as_written(tmp_path, page, number, line, code):
    """Issue 40 item 2: a C++ example is complete: its #include and using lines, then statements
    that compile as the body of main() against the public headers (g++ -fsyntax-only)."""
    lines = code.splitlines()
    head = 0
    while head < len(lines) and (lines[head].startswith(("#include", "using ")) or not lines[head].strip()):
        head += 1
    source = "\n".join(lines[:head]) + "\nint main() {\n" + "\n".join(lines[head:]) + "\nreturn 0;\n}\n"
    (tmp_path / "block.cpp").write_text(source)
    includes = [f"-I{SOURCE_DIR / 'modules' / 'include'}", "-I/usr/include/opencv4"]
    includes += [f"-I{d}" for d in sorted((SOURCE_DIR / "modules").glob("*/include"))]
    r = subprocess.run(["g++", "-std=c++17", "-fsyntax-only", *includes, str(tmp_path / "block.cpp")],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, f"{page}, block {number} (line {line}) does not compile as written:\n{source}\n{r.stderr[-3000:]}"


def test_readme_first_run_runs_as_written(tmp_path):
    """Issue 40 item 2: the README's first run of the command line, line by line, as written
    (`multicage` being the tool built beside this module), in a folder where samples/ is the
    repository's: every command exits 0 and writes what it names."""
    cli = os.environ.get("MULTICAGE_CLI")
    if not cli or not os.path.isfile(cli):
        pytest.skip("MULTICAGE_CLI is not set to the built multicage tool")
    text = (SOURCE_DIR / "README.md").read_text()
    match = re.search(r"A first run.*?^```sh\n(.*?)^```", text, re.S | re.M)
    assert match, "README.md has no 'A first run' block"
    (tmp_path / "samples").symlink_to(SOURCE_DIR / "samples")
    commands = [line.split("#")[0].strip() for line in match.group(1).splitlines() if line.strip()]
    assert len(commands) >= 3 and all(c.startswith("multicage ") for c in commands), commands
    for command in commands:
        args = command.split()[1:]
        r = subprocess.run([os.path.abspath(cli), *args], cwd=tmp_path, capture_output=True, text=True, timeout=600)
        assert r.returncode == 0, f"`{command}` fails as written:\n{r.stderr}"
        written = args[args.index("-o") + 1]
        assert (tmp_path / written).is_file(), f"`{command}` did not write {written}"

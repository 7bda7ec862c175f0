"""Issue 13 item 10, issue 40 item 2: every Python example of the README and the module
docstring's example run as written, from the source folder with the module on PYTHONPATH (as
the README says), or, with MULTICAGE_README_CWD set, from an installed prefix's
share/multicage (its samples/ beside the README's relative paths)."""

import os
import pathlib
import re
import subprocess
import sys

import pytest

import multicage as mc
from conftest import SOURCE_DIR


def python_section():
    text = (SOURCE_DIR / "README.md").read_text()
    match = re.search(r"^## Python\n(.*?)^## ", text, re.S | re.M)
    assert match, "README.md has no '## Python' section"
    return match.group(1)


def readme_blocks():
    return re.findall(r"^```python\n(.*?)^```", (SOURCE_DIR / "README.md").read_text(), re.S | re.M)


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
    # folder the README's relative paths are written for.
    script = tmp_path / name
    script.write_text(code)
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in sys.path if p))
    r = subprocess.run([sys.executable, str(script)], cwd=RUN_DIR, env=env, capture_output=True, text=True,
                       timeout=900)
    assert r.returncode == 0, f"{name} fails as written:\n{code}\n{r.stderr[-3000:]}"
    return r


def test_readme_has_python_examples():
    blocks = readme_blocks()
    assert blocks, "the Python section has no ```python block"
    assert any("mc.Deformer" in b and "compute_maps" in b for b in blocks)


@pytest.mark.parametrize("index", range(len(readme_blocks())))
def test_readme_python_block_runs_as_written(tmp_path, index):
    before = set(os.listdir(RUN_DIR))
    run_as_written(readme_blocks()[index], tmp_path, f"readme_block_{index}.py")
    assert set(os.listdir(RUN_DIR)) == before, "the example must not leave files in the folder it runs in"


def test_module_docstring_example_runs_as_written(tmp_path):
    code = docstring_example()
    assert "Deformer" in code and "compute_maps" in code
    run_as_written(code, tmp_path, "docstring_example.py")


def test_readme_names_only_what_the_module_has():
    # Every mc.NAME the section mentions exists (a renamed function breaks the docs here).
    for name in set(re.findall(r"\b(?:mc|multicage)\.([A-Za-z_]\w*)", python_section())):
        assert hasattr(mc, name), f"README mentions multicage.{name}, which the module does not have"

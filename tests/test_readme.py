"""The README shows what the project ships (its examples run as doctests), and each of
its python blocks runs on its own, as written, from the project root; so does each of
the documentation pages in :data:`PAGES`."""

from __future__ import annotations

import importlib.util
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

import linkage_fmu

ROOT = Path(__file__).parents[1]
README = (ROOT / "README.md").read_text()
#: the documentation pages whose python blocks run as the README's
PAGES = ("README.md", "docs/joints-and-links.md")
#: (page, line in it, text) of each python block
BLOCKS = [(page, text.count("\n", 0, m.start()) + 1, m.group(1))
          for page in PAGES for text in [(ROOT / page).read_text()]
          for m in re.finditer(r"```python\n(.*?)```", text, flags=re.S)]
#: runs a doctest file, exit status 1 if an example fails
DOCTEST = ("import doctest, sys; failed, _ = doctest.testfile(sys.argv[1], "
           "module_relative=False); sys.exit(failed > 0)")


def test_the_readme_shows_the_example_files_as_they_are():
    """The description file in "Your own linkage" is examples/coupler_four_bar.toml, byte
    for byte, and every line of the engine's excerpt (its comments after ``#`` aside, and
    the ``# ...`` line) is a line of examples/engine.toml (the README's doctests load
    those files)."""
    readme = (ROOT / "README.md").read_text()
    blocks = re.findall(r"```toml\n(.*?)```", readme, flags=re.S)
    coupler = (ROOT / "examples" / "coupler_four_bar.toml").read_text()
    assert len(blocks) == 2 and coupler in blocks
    excerpt = next(b for b in blocks if b != coupler)
    engine = [line.strip() for line in
              (ROOT / "examples" / "engine.toml").read_text().splitlines()]
    for line in excerpt.splitlines():
        code = line.split(" #")[0].strip()
        if code and code != "# ...":
            assert code in engine, line


@pytest.mark.parametrize("page, line, block", BLOCKS,
                         ids=[f"line{n}" if page == "README.md" else f"{Path(page).stem}-line{n}"
                              for page, n, _ in BLOCKS])
def test_each_python_block_runs_on_its_own(page, line, block, tmp_path):
    """In a fresh interpreter from the project root, nothing from the blocks before it
    (pytest's README doctest shares one namespace over the whole file, so a block using
    ``np`` or ``mech`` of an earlier one passed there and failed for a reader): a block
    of ``>>>`` examples as a doctest, any other as a script; the block of run_fmu builds
    the FMU it runs (dist/native/FourBar.fmu, as ``linkage-fmu build --native``)."""
    if ">>>" in block:
        (tmp_path / "block.txt").write_text(block)
        command = [sys.executable, "-c", DOCTEST, str(tmp_path / "block.txt")]
    else:
        command = [sys.executable, "-c", block]
    source = str(Path(linkage_fmu.__file__).parents[1])  # the package under test
    env = {**os.environ, "MPLBACKEND": "Agg",
           "PYTHONPATH": os.pathsep.join(filter(None, [source, os.environ.get("PYTHONPATH")]))}
    run = subprocess.run(command, cwd=ROOT, env=env, capture_output=True, text=True,
                         timeout=900)
    assert run.returncode == 0, f"{page} line {line}:\n{run.stdout[-3000:]}{run.stderr[-3000:]}"


def test_every_python_block_is_found():
    """The README's ten python blocks, four of them doctests, and the one of
    docs/joints-and-links.md, a doctest: a block the pattern missed would go untested."""
    readme = [b for page, _, b in BLOCKS if page == "README.md"]
    assert len(readme) == README.count("```python") == 10
    assert sum(">>>" in b for b in readme) == 4
    joints = [b for page, _, b in BLOCKS if page == "docs/joints-and-links.md"]
    assert len(joints) == 1 and ">>>" in joints[0]


def test_the_joints_page_shows_what_info_prints():
    """Each output of ``linkage-fmu info`` pasted into docs/joints-and-links.md (the
    class III six-bar's whole, Jansen's groups) is what it prints for the example file
    as it is: the page's text against a run of the command, byte for byte (regenerate:
    python docs/make_joints_pictures.py)."""
    spec = importlib.util.spec_from_file_location("make_joints_pictures",
                                                  ROOT / "docs" / "make_joints_pictures.py")
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    page = script.PAGE.read_text()
    shown = [m.group(2) for m in script.BLOCK.finditer(page)]
    assert shown == ["examples/triad_six_bar.toml", "examples/jansen.toml"]
    assert script.pasted(page) == page, "regenerate: python docs/make_joints_pictures.py"

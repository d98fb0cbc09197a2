"""The README is short (at most 300 lines), shows what the project ships (its example
runs as a doctest) and links to pages that exist; each of its python blocks runs on its
own, as written, from the project root (tests/test_docs.py does the same for every page
of the documentation)."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

import linkage_fmu

ROOT = Path(__file__).parents[1]
README = (ROOT / "README.md").read_text()
#: a python block: its text
PYTHON = re.compile(r"```python\n(.*?)```", flags=re.S)
#: an inline link or image, ``[text](target)`` or ``![alt](target "title")``: its target
LINK = re.compile(r"\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")
#: runs a doctest file, exit status 1 if an example fails
DOCTEST = ("import doctest, sys; failed, _ = doctest.testfile(sys.argv[1], "
           "module_relative=False); sys.exit(failed > 0)")


def blocks(page: str) -> list[tuple[int, str]]:
    """(line, text) of each python block of ``page`` (a path from the project root)."""
    text = (ROOT / page).read_text()
    return [(text.count("\n", 0, m.start()) + 1, m.group(1)) for m in PYTHON.finditer(text)]


def relative_links(page: str) -> list[str]:
    """The relative targets (their ``#anchor`` aside) of the links and images of
    ``page`` (a path from the project root), outside its code."""
    text = re.sub(r"```.*?```", "", (ROOT / page).read_text(), flags=re.S)
    text = re.sub(r"`[^`\n]*`", "", text)
    targets = [link.split("#")[0] for link in LINK.findall(text)]
    return [t for t in targets if t and not re.match(r"^[a-z][a-z0-9+.-]*:|^/", t, flags=re.I)]


def broken_links(page: str) -> list[str]:
    """The relative links and images of ``page`` that name no file or folder of the
    project, resolved from the page's folder as GitHub resolves them."""
    folder = (ROOT / page).parent
    return [link for link in relative_links(page) if not (folder / link).exists()]


#: what the blocks' copy of the project leaves out: what they write (dist/: the FMUs they
#: build), what the project builds, and git's data
NOT_COPIED = {"dist", "build", ".git"}


def project_copy(folder: Path) -> Path:
    """A copy of the project root under ``folder`` (links to its files and folders,
    :data:`NOT_COPIED` aside) for a block to run in: what it reads is the project's,
    what it writes to dist/ is its own (two runs at once, or a run and a build of the
    checkout, cannot overwrite each other's FMUs)."""
    copy = folder / "project"
    copy.mkdir()
    for entry in ROOT.iterdir():
        if entry.name not in NOT_COPIED:
            (copy / entry.name).symlink_to(entry, target_is_directory=entry.is_dir())
    return copy


def run_block(page: str, line: int, block: str, folder: Path) -> None:
    """Run ``block`` in a fresh interpreter from a copy of the project root
    (:func:`project_copy`), with nothing from the blocks before it (pytest's README
    doctest shares one namespace over the whole file, so a block using ``np`` or
    ``mech`` of an earlier one passed there and failed for a reader): a block of ``>>>``
    examples as a doctest, any other as a script file (as a reader runs it: ``python
    script.py``, so that ``if __name__ == "__main__":`` and the processes a Dask cluster
    starts behave as they do for them). The environment is the reader's: no matplotlib
    backend is chosen for the block (a block that draws chooses its own: tests/test_docs.py
    checks it)."""
    if ">>>" in block:
        (folder / "block.txt").write_text(block)
        command = [sys.executable, "-c", DOCTEST, str(folder / "block.txt")]
    else:
        (folder / "block_script.py").write_text(block)
        command = [sys.executable, str(folder / "block_script.py")]
    source = str(Path(linkage_fmu.__file__).parents[1])  # the package under test
    env = {name: value for name, value in os.environ.items() if name != "MPLBACKEND"}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [source, os.environ.get("PYTHONPATH")]))
    run = subprocess.run(command, cwd=project_copy(folder), env=env, capture_output=True,
                         text=True, timeout=900)
    assert run.returncode == 0, f"{page} line {line}:\n{run.stdout[-3000:]}{run.stderr[-3000:]}"


def test_the_readme_is_at_most_300_lines():
    assert len(README.splitlines()) <= 300


@pytest.mark.parametrize("line, block", blocks("README.md"),
                         ids=[f"line{n}" for n, _ in blocks("README.md")])
def test_each_python_block_runs_on_its_own(line, block, tmp_path):
    """The first example (a doctest) and the FMU run in fmpy, which builds the FMU it
    runs (dist/native/FourBar.fmu, as ``linkage-fmu build --native four_bar``, in the
    block's copy of the project)."""
    run_block("README.md", line, block, tmp_path)


def test_the_readme_has_its_parts():
    """The two commands, unchanged (.ci/run and the test suite run the second); how to
    run the installed command; a first example of at most 20 lines, a doctest; an FMU
    run in fmpy in at most 10 lines; the two pictures."""
    assert ("python3 -m venv .venv && .venv/bin/pip install . && .venv/bin/python "
            "build_fmu.py\npython3 -m venv .venv && .venv/bin/pip install -e \".[test]\" && "
            ".venv/bin/python -m pytest\n") in README
    assert ". .venv/bin/activate" in README and ".venv/bin/linkage-fmu" in README
    (_, first), (_, fmu) = blocks("README.md")
    assert ">>>" in first and len(first.splitlines()) <= 20
    assert "fmpy" in fmu and len(fmu.splitlines()) <= 10
    pictures = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", README)
    assert pictures == ["docs/four_bar.gif", "docs/crank_shaper_forces.png"]
    assert (ROOT / pictures[1]).is_file()


def test_every_link_and_image_of_the_readme_is_a_file():
    """Each relative link and image of the README names a file of the project."""
    links = relative_links("README.md")
    assert len(links) >= 15
    assert {"docs/four_bar.gif", "docs/guide/animations.md"} <= set(links)
    assert broken_links("README.md") == []


def test_no_source_document_is_named_by_its_seed_number():
    assert not re.search(r"seed \d{3}", README, flags=re.I)

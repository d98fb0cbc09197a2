"""Every python block of every page of the documentation (docs/, mkdocs.yml's site) runs
on its own, as written, from the project root; the pages show the example files as they
are, and name their source documents for what they are."""

from __future__ import annotations

import importlib.util
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

import linkage_fmu
from test_readme import ROOT, blocks, broken_links, relative_links, run_block

DOCS = ROOT / "docs"
#: every page of the site, from the project root
PAGES = sorted(str(p.relative_to(ROOT)) for p in DOCS.rglob("*.md"))
#: (page, line in it, text) of each python block
BLOCKS = [(page, line, text) for page in PAGES for line, text in blocks(page)]


@pytest.mark.parametrize("page, line, block", BLOCKS,
                         ids=[f"{Path(page).stem}-line{n}" for page, n, _ in BLOCKS])
def test_each_python_block_runs_on_its_own(page, line, block, tmp_path):
    """A doctest block as a doctest, any other as a script. The blocks that build an
    FMU build the four-bar's native FMU (dist/native/FourBar.fmu of the block's copy of
    the project), a second's work; the Dask block sweeps 10 designs on a local cluster."""
    run_block(page, line, block, tmp_path)


def fences(page: str) -> list[tuple[int, str, str]]:
    """(line, indent, info string) of each code block's opening fence in ``page``."""
    found, inside = [], False
    for n, text in enumerate((ROOT / page).read_text().splitlines(), 1):
        fence = re.match(r"^(\s*)(?:```|~~~)\s*(\S*)", text)
        if fence and not inside:
            found.append((n, fence.group(1), fence.group(2)))
        inside ^= bool(fence)
    return found


def test_every_python_block_is_found():
    """Every code block of the README and the pages names its language, and each in
    Python (``py``, ``python3``, ``pycon``, or indented in a list) opens as the
    ```` ```python ```` at the start of a line that :func:`test_readme.blocks` finds (a
    block it missed would go untested); the pages of the user guide and getting started
    have blocks."""
    for page in ["README.md", *PAGES]:
        opened = fences(page)
        assert [n for n, _, info in opened if not info] == [], page
        python = [(n, indent, info) for n, indent, info in opened
                  if re.match(r"(?:py|python3?|pycon|ipython)\b", info, flags=re.I)]
        assert python == [(n, "", "python") for n, _ in blocks(page)], page
    pages = {page for page, _, _ in BLOCKS}
    for page in ("getting-started.md", "guide/solving.md", "guide/loads.md",
                 "guide/friction.md", "guide/motion.md", "guide/fmus.md", "guide/sweeps.md",
                 "guide/plots.md", "guide/linkages.md", "joints-and-links.md"):
        assert f"docs/{page}" in pages, page
    assert len(BLOCKS) >= 18


def test_every_block_that_draws_chooses_its_backend():
    """A block of the README or the pages that draws with matplotlib (linkage_fmu.plot,
    pyplot) chooses the file-only backend, ``matplotlib.use("Agg")``, before it imports
    them: the blocks run without one chosen for them, as a reader's do (a reader with a
    display would otherwise get windows, or wait on one)."""
    drawing = 0
    for page in ["README.md", *PAGES]:
        for line, block in blocks(page):
            code = re.sub(r"#[^\n]*", "", block)
            imports = [m.start() for m in re.finditer(
                r"^\s*(?:>>> )?(?:from linkage_fmu(?:\.plot)? import [^\n]*\bplot\b|"
                r"from linkage_fmu\.plot|import matplotlib\.pyplot|from matplotlib import pyplot)",
                code, flags=re.M)]
            if not imports:
                continue
            drawing += 1
            chosen = code.find('matplotlib.use("Agg")')
            assert 0 <= chosen < min(imports), f"{page} line {line}"
    assert drawing >= 2


def test_the_pages_show_the_example_files_as_they_are():
    """The description file on the linkages page is examples/coupler_four_bar.toml, byte
    for byte, and every line of the engine's excerpt on the loads page (its comments
    after ``#`` aside, and the ``# ...`` line) is a line of examples/engine.toml (the
    pages' doctests load those files)."""
    coupler = (ROOT / "examples" / "coupler_four_bar.toml").read_text()
    (linkages,) = re.findall(r"```toml\n(.*?)```", (DOCS / "guide" / "linkages.md").read_text(),
                             flags=re.S)
    assert linkages == coupler
    (excerpt,) = re.findall(r"```toml\n(.*?)```", (DOCS / "guide" / "loads.md").read_text(),
                            flags=re.S)
    engine = [line.strip() for line in
              (ROOT / "examples" / "engine.toml").read_text().splitlines()]
    for line in excerpt.splitlines():
        code = line.split(" #")[0].strip()
        if code and code != "# ...":
            assert code in engine, line


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


def test_no_page_names_a_source_document_by_its_seed_number():
    """The source documents are named for what they are (the scotch yoke worked
    example, ..., and "the source documents' way" in the benchmark results), never
    "seed 000" or "seed way", on the pages and on the benchmark pages the site includes
    (docs/hooks.py)."""
    results = sorted((ROOT / "benchmarks" / "results").glob("*.md"))
    assert len(results) >= 4
    for page in [ROOT / p for p in PAGES] + results:
        assert not re.search(r"seed( \d{3}| way|s' way| per angle)", page.read_text(),
                             flags=re.I), page


def test_every_link_and_image_resolves_on_github():
    """Each relative link and image of each page, and of the benchmark pages the site
    includes, names a file or folder of the project from the page's folder, as GitHub
    resolves it (docs/hooks.py maps these paths to the site's; no page links to
    anything mkdocs generates, so none is exempt)."""
    results = sorted(str(p.relative_to(ROOT))
                     for p in (ROOT / "benchmarks" / "results").glob("*.md"))
    broken = {page: broken_links(page) for page in PAGES + results}
    assert {page: links for page, links in broken.items() if links} == {}
    assert "../benchmarks/results/results.md" in relative_links("docs/performance.md")


def test_the_pages_only_mkdocs_builds_say_so_on_github():
    """The changelog (a snippet of CHANGELOG.md) and the API reference (directives),
    empty on GitHub, open with a line naming mkdocs and their source, which the site
    leaves out (docs/hooks.py)."""
    for page in ["docs/changelog.md", *(p for p in PAGES if p.startswith("docs/api/"))]:
        text = (ROOT / page).read_text()
        (note,) = re.findall(r"^> This page is built by mkdocs \(`mkdocs serve` or `mkdocs "
                             r"build`\).*$", text, flags=re.M)
        assert re.search(r"\]\(\.\./(CHANGELOG\.md|\.\./src/linkage_fmu/)", note), page


def test_every_page_is_in_the_sites_navigation():
    """Each page, and each page of the committed benchmark results (docs/hooks.py adds
    them to the site), is reached from mkdocs.yml's nav (a page outside it would be built
    but found by no reader; the strict build also refuses it)."""
    nav = (ROOT / "mkdocs.yml").read_text().split("\nnav:\n")[1]
    listed = set(re.findall(r"^\s+- (?:[^:\n]+: )?([\w/.-]+\.md)$", nav, flags=re.M))
    results = {f"benchmarks/results/{p.name}"
               for p in (ROOT / "benchmarks" / "results").glob("*.md")}
    assert listed == {str(Path(p).relative_to("docs")) for p in PAGES} | results


def test_the_flywheel_report_shown_is_what_the_command_prints(tmp_path):
    """The report on the motion page under ``linkage-fmu flywheel examples/engine.toml
    ...`` is what that command prints today, line for line."""
    page = (DOCS / "guide" / "motion.md").read_text()
    command = re.search(r"```sh\n(linkage-fmu flywheel examples/engine\.toml [^\n]*)\n```\n\n"
                        r"```text\n(.*?)```", page, flags=re.S)
    assert command is not None
    source = str(Path(linkage_fmu.__file__).parents[1])
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(
        filter(None, [source, os.environ.get("PYTHONPATH")]))}
    args = ["--omega-mean", "3000 rpm", "--Cs", "0.02"]
    assert command.group(1) == "linkage-fmu flywheel examples/engine.toml " + " ".join(
        f'"{a}"' if " " in a else a for a in args)
    run = subprocess.run([sys.executable, "-m", "linkage_fmu", "flywheel",
                          "examples/engine.toml", *args], cwd=ROOT, env=env,
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert run.stdout == command.group(2)


def test_the_docstrings_roles_become_cross_references():
    """docs/hooks.py makes a role's code an optional reference (autorefs links it where
    the site documents the object, else it stays code) to the object Sphinx would find:
    ``~`` shows the last name; a leading dot or a bare name is looked up from the
    documented object's module (Mechanism.reduced_inertia's ``.inertia.reduced_inertia``
    is linkage_fmu.inertia's, which linkage_fmu.mechanism imports); a titled role keeps
    its title. Unknown names (``float``) keep their text, no link is invented."""
    spec = importlib.util.spec_from_file_location("hooks", DOCS / "hooks.py")
    hooks = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(hooks)
    html = ('<h3 id="linkage_fmu.Mechanism.reduced_inertia" class="doc doc-heading">'
            "<p>:func:<code>.inertia.reduced_inertia</code>, "
            ":meth:<code>~linkage_fmu.Mechanism.solve</code>, :func:<code>simulate</code>, "
            ":meth:<code>Solver.solve &lt;linkage_fmu.solver.Solver.solve&gt;</code>, "
            ":class:<code>float</code>, <code>.copy()</code></p>")
    ref = '<autoref identifier="{}" optional><code>{}</code></autoref>'
    assert hooks.cross_references(html) == (
        '<h3 id="linkage_fmu.Mechanism.reduced_inertia" class="doc doc-heading"><p>'
        + ", ".join([ref.format("linkage_fmu.inertia.reduced_inertia", "inertia.reduced_inertia"),
                     ref.format("linkage_fmu.Mechanism.solve", "solve"),
                     ref.format("linkage_fmu.mechanism.Mechanism.simulate", "simulate"),
                     ref.format("linkage_fmu.solver.Solver.solve", "Solver.solve"),
                     ref.format("float", "float"), "<code>.copy()</code></p>"]))


def test_the_home_page_table_links_every_guide_page_the_readme_does():
    """The site's home and the README hold the same table of what the project does: each
    user-guide page the README's table links, the home page's links too."""
    def guide_pages(text: str, prefix: str) -> set[str]:
        rows = [line for line in text.splitlines() if line.startswith("| ")]
        return {m for row in rows for m in re.findall(rf"\]\({prefix}(guide/[\w-]+\.md)\)", row)}
    readme = guide_pages((ROOT / "README.md").read_text(), "docs/")
    assert "guide/animations.md" in readme and len(readme) >= 9
    assert readme <= guide_pages((DOCS / "index.md").read_text(), "")

"""The web report of a linkage (linkage_fmu.report): its pictures are PNG files beside
it, its numbers are the solver's, headless Chromium draws its images and its MathML, the
variants of a CSV file are each one's own report, and a bad CSV file is named by file,
row and column."""

from __future__ import annotations

import io
import math
import re
import shutil
import subprocess
from contextlib import redirect_stderr
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest

from linkage_fmu import presets
from linkage_fmu.cli import main
from linkage_fmu.errors import InputError
from linkage_fmu.report import (
    N_REVOLUTION,
    POSITIONS,
    TABLE_STEP,
    read_variants,
    revolution_extremes,
    write_report,
    write_variants,
)

pytest.importorskip("matplotlib")
PIL = pytest.importorskip("PIL.Image")

ROOT = Path(__file__).resolve().parents[1]
CHROMIUM = Path("/usr/bin/chromium")
#: the inputs of each report: the scotch yoke worked example's, the six-bar's start values
CASES = {"scotch_yoke": {"omega": 10.0, "load": 400.0}, "six_bar": {}}
#: a number shown to 6 significant figures is within this of its value, relatively
SHOWN = 5e-6


class Page(HTMLParser):
    """What a report holds: its images' sources, and each table and MathML table with a
    ``data-part`` as rows of cell texts (a cell's ``data-value`` where it has one)."""

    def __init__(self, text: str):
        super().__init__()
        self.images: list[str] = []
        self.parts: dict[str, list[list[str]]] = {}
        #: section id -> unknown -> its value as shown in the solution
        self.unknowns: dict[str, dict[str, str]] = {}
        self._part = self._section = self._unknown = self._value = None
        self._row: list[str] | None = None
        self._cell: list[str] | None = None
        self.feed(text)

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "img":
            self.images.append(a["src"])
        if tag == "section":
            self._section = a.get("id")
        if tag == "table" and "data-part" in a:
            self._part = a["data-part"] + (f":{a['data-theta']}" if "data-theta" in a else "")
            self.parts[self._part] = []
        if tag == "tr" and self._part:
            self._row = []
        if tag in ("td", "th") and self._row is not None:
            self._cell = []
        if tag == "span" and "data-value" in a and self._cell is not None:
            self._value = a["data-value"]
        if tag == "mtr" and "data-unknown" in a:
            self._unknown = a["data-unknown"]
            self.unknowns.setdefault(self._section, {})[self._unknown] = ""

    def handle_endtag(self, tag):
        if tag in ("td", "th") and self._cell is not None:
            self._row.append(self._value or "".join(self._cell).strip())
            self._cell = self._value = None
        if tag == "tr" and self._row is not None:
            self.parts[self._part].append(self._row)
            self._row = None
        if tag == "table":
            self._part = None
        if tag == "mtr" and self._unknown is not None:
            row = self.unknowns[self._section]
            row[self._unknown] = re.fullmatch(r".*?=(−?[\d.eE+-]+).*", row[self._unknown])[1]
            self._unknown = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell.append(data)
        if self._unknown is not None:
            self.unknowns[self._section][self._unknown] += data


def shown(text: str) -> float:
    """A number as the report shows it (a minus sign − as -)."""
    return float(text.replace("−", "-").strip())


def close(text: str, exact: float, scale: float = 0.0) -> bool:
    return math.isclose(shown(text), exact, rel_tol=SHOWN, abs_tol=1e-12 * max(scale, 1.0))


@pytest.fixture(scope="module")
def reports(tmp_path_factory) -> dict[str, Path]:
    out = {}
    for name, inputs in CASES.items():
        out[name] = write_report(presets.get(name), tmp_path_factory.mktemp(name), **inputs)
    return out


@pytest.mark.parametrize("name", CASES)
def test_every_picture_is_a_png_beside_the_page(reports, name):
    page = reports[name]
    assert page.name == "index.html" and page.is_file()
    text = page.read_text(encoding="utf-8")
    assert "<script" not in text.lower() and text.count("<style>") == 1
    images = Page(text).images
    assert len(images) == len(POSITIONS) + 3  # the first position's twice, effort, forces
    for src in set(images):
        assert "/" not in src and not src.startswith(("http", "data:"))
        path = page.parent / src
        assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", src
        with PIL.open(path) as im:
            im.verify()


@pytest.mark.parametrize("name", CASES)
def test_the_numbers_shown_are_the_solvers(reports, name):
    """At each position, the solution of ``A x = b`` (its balancing effort, e.g. the
    worked example's Mb 15.6699 N.m at 60 deg) and every output shown are
    ``Mechanism.solve``'s there, and the table over the cycle is too at every
    ``TABLE_STEP`` angle; each to the 6 significant figures shown (relative
    :data:`SHOWN`, or 1e-12 of the column's largest value for a value that is 0 as
    shown)."""
    mech, inputs = presets.get(name), CASES[name]
    page = Page(reports[name].read_text(encoding="utf-8"))
    effort = mech.effort.name
    for deg in POSITIONS:
        sol = mech.solve(math.radians(deg), **inputs)
        label = f"{deg:g}"
        assert close(page.unknowns[f"theta-{label}"][effort], sol[effort])
        rows = page.parts[f"outputs:{label}"][1:]
        assert len(rows) > 5
        for output, value, unit in rows:
            assert unit == mech.output_info[output][0]
            assert close(value, sol[output]), (deg, output, value, sol[output])
    if name == "scotch_yoke":
        assert page.unknowns["theta-60"][effort] == "15.6699"
    table = page.parts["cycle"]
    head, rows = table[0], table[1:]
    assert head[0] == "θ [°]" and len(rows) == round(360 / TABLE_STEP)
    names = [h.split(" [")[0] for h in head[1:]]
    assert head[1:] == [f"{n} [{mech.output_info[n][0]}]" for n in names]
    deg = np.array([shown(r[0]) for r in rows])
    sol = mech.solve(np.radians(deg), **inputs)
    for j, n in enumerate(names, 1):
        scale = float(np.max(np.abs(sol[n])))
        assert all(close(r[j], v, scale) for r, v in zip(rows, sol[n])), n


def test_the_extremes_are_those_of_a_revolution(reports):
    """The table of extremes is :func:`revolution_extremes`, whose scotch yoke peak Mb
    is the largest |Mb| of N_REVOLUTION angles (exactly), and whose pin force is the
    magnitude of its components."""
    mech = presets.get("scotch_yoke")
    ex = revolution_extremes(mech, **CASES["scotch_yoke"])
    deg = np.linspace(0.0, 360.0, N_REVOLUTION)
    sol = mech.solve(np.radians(deg), **CASES["scotch_yoke"])
    assert ex.loc["Mb", "peak"] == np.max(np.abs(sol["Mb"]))
    assert ex.loc["|F12|", "max"] == np.max(np.hypot(sol["F12x"], sol["F12y"]))
    rows = Page(reports["scotch_yoke"].read_text(encoding="utf-8")).parts["extremes"][1:]
    assert [r[0] for r in rows] == list(ex.index)
    assert all(close(r[2], ex.loc[r[0], "peak"]) for r in rows)


def test_the_equations_and_where_to_put_the_effort_are_in_the_page(reports):
    text = reports["six_bar"].read_text(encoding="utf-8")
    page = Page(text)
    # each position: the labelled A | b and the solution, and Equations.to("mathml")
    assert text.count('data-part="matrix"') == len(POSITIONS)
    assert text.count('data-part="free body"') == len(POSITIONS) * 5  # five moving links
    assert text.count('<math display="block"') > 3 * len(POSITIONS)
    places = page.parts["places"]
    assert [r[0] for r in places[1:]][:2] == ["OA", "AB"]
    assert 'data-part="recommendation"><strong>OA</strong>' in text


def test_a_linkage_driven_by_time_is_refused_and_friction_is_in_the_equations(tmp_path):
    five = presets.linkage(ROOT / "examples" / "five_bar.toml")
    with pytest.raises(InputError, match="five_bar is driven by time .*: a report takes a "
                                         "linkage driven by one crank"):
        write_report(five, tmp_path / "five")
    rough = presets.get("scotch_yoke", mu_A=0.1, r_A=0.01)
    page = write_report(rough, tmp_path / "rough", positions=[60.0], omega=10.0, load=400.0)
    text = page.read_text(encoding="utf-8")
    assert 'data-part="matrix"' in text and "Mf_A [N.m]" in text
    assert text.count('data-part="friction"') == 1  # the law of the pin A's friction


# -- in a browser ---------------------------------------------------------------------
#: marks the body with what the page drew, once it has loaded (added to a copy only)
CHECK = """<script>
window.addEventListener("load", () => {
  const images = [...document.images], maths = [...document.getElementsByTagName("math")];
  const b = document.body;
  b.dataset.images = images.length;
  b.dataset.brokenImages = images.filter(i => !i.complete || i.naturalWidth === 0).length;
  b.dataset.maths = maths.length;
  b.dataset.emptyMaths = maths.filter(m => {
    const r = m.getBoundingClientRect(); return r.width === 0 || r.height === 0; }).length;
  b.dataset.mathml = maths.filter(m => typeof MathMLElement !== "undefined" &&
    m instanceof MathMLElement).length;
  b.dataset.checked = "yes";
});
</script>"""


def chromium(*args: str, user_data: Path) -> subprocess.CompletedProcess:
    return subprocess.run(
        [str(CHROMIUM), "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
         "--no-first-run", "--disable-background-networking", "--disable-component-update",
         "--disable-sync", f"--user-data-dir={user_data}", *args],
        capture_output=True, text=True, timeout=180)


@pytest.mark.parametrize("name", CASES)
def test_chromium_draws_every_image_and_every_formula(reports, name, tmp_path):
    """Headless Chromium's screenshot of the page is not blank; in its DOM, once loaded,
    no image is broken, and every <math> is a MathMLElement of nonzero size (checked by
    a script in a copy of the page; the report has none)."""
    if not CHROMIUM.exists():
        pytest.skip(f"{CHROMIUM} is not installed (.ci/run installs it)")
    page = reports[name]
    shot = tmp_path / "screenshot.png"
    done = chromium(f"--screenshot={shot}", "--window-size=1200,3000", page.as_uri(),
                    user_data=tmp_path / "profile-1")
    assert shot.is_file(), done.stderr[-2000:]
    with PIL.open(shot) as im:
        grey = np.asarray(im.convert("L"))
    assert grey.shape == (3000, 1200)
    assert (grey < 128).mean() > 0.005 and (grey > 128).mean() > 0.5  # text on white
    shutil.copy(shot, page.parent / "screenshot.png")  # kept beside the report

    checked = page.parent / "checked.html"
    checked.write_text(page.read_text(encoding="utf-8").replace("</body>", CHECK + "</body>"),
                       encoding="utf-8")
    done = chromium("--dump-dom", "--virtual-time-budget=5000", checked.as_uri(),
                    user_data=tmp_path / "profile-2")
    body = re.search(r"<body([^>]*)>", done.stdout)
    assert body, done.stderr[-2000:]
    marks = dict(re.findall(r'data-([\w-]+)="([^"]*)"', body.group(1)))
    assert marks.get("checked") == "yes", marks
    assert int(marks["images"]) == len(Page(page.read_text(encoding="utf-8")).images)
    assert marks["broken-images"] == "0"
    assert int(marks["maths"]) > 0
    assert marks["empty-maths"] == "0" and marks["mathml"] == marks["maths"]


# -- variants ---------------------------------------------------------------------------
def test_three_variants_are_three_reports_and_an_index(tmp_path):
    """Each variant's page is its own report, and the index's peak effort is the largest
    |Mb| of that variant solved over the revolution, to 1e-9 relative (the index keeps
    it unrounded in data-value)."""
    csv = tmp_path / "designs.csv"
    csv.write_text("variant,l_AB,l_BC\nshort,0.08,0.35\nbase,0.1,0.35\nlong,0.12,0.4\n")
    mech = presets.get("four_bar")
    index = write_variants(mech, csv, tmp_path / "out", positions=[30.0], omega=10.0,
                           load=3.0)
    page = Page(index.read_text(encoding="utf-8"))
    rows = page.parts["variants"]
    assert rows[0][:3] == ["variant", "l_AB", "l_BC"] and rows[0][3] == "peak |Mb| [N.m]"
    assert [r[0] for r in rows[1:]] == ["short", "base", "long"]
    assert '<a href="short/index.html">' in index.read_text(encoding="utf-8")
    deg = np.linspace(0.0, 360.0, N_REVOLUTION)
    for row, (l_ab, l_bc) in zip(rows[1:], [(0.08, 0.35), (0.1, 0.35), (0.12, 0.4)]):
        assert (index.parent / row[0] / "index.html").is_file()
        assert shown(row[1]) == l_ab and shown(row[2]) == l_bc
        variant = presets.get("four_bar", l_AB=l_ab, l_BC=l_bc)
        peak = np.max(np.abs(variant.solve(np.radians(deg), 10.0, load=3.0)["Mb"]))
        assert math.isclose(shown(row[3]), peak, rel_tol=1e-9)
        forces = np.hypot(*(variant.solve(np.radians(deg), 10.0, load=3.0)[c]
                            for c in ("F21x", "F21y")))
        assert math.isclose(shown(row[rows[0].index("peak |F21| [N]")]), np.max(forces),
                            rel_tol=1e-9)


@pytest.mark.parametrize("text, message", [
    ("", "designs.csv: the file is empty; expected a header row"),
    ("\n\n", "designs.csv: the file is empty"),
    ("l_AB,l_BC\n", "designs.csv: no variant rows under the header"),
    ("l_AB,l_XY\n0.1,0.3\n", "designs.csv, line 1, column 2 'l_XY': four_bar has no parameter "
                             "'l_XY'; its parameters are: l_AB, l_BC"),
    ("l_AB,variant\n0.1,a\n", "designs.csv, line 1, column 2: 'variant' must be the first"),
    ("l_AB,l_AB\n0.1,0.1\n", "designs.csv, line 1, column 2 'l_AB': the column repeats "
                             "column 1"),
    ("l_AB,\n0.1,0.2\n", "designs.csv, line 1, column 2: the column has no name"),
    ("l_AB,l_BC\n0.1,0.35\n0.12,long\n", "designs.csv, row 2 (line 3), column 'l_BC': "
                                         "'long' is not a number"),
    ("l_AB,l_BC\n0.1,\n", "designs.csv, row 1 (line 2), column 'l_BC': the value is empty"),
    ("l_AB,l_BC\n0.1,nan\n", "designs.csv, row 1 (line 2), column 'l_BC': 'nan' is not a "
                             "finite number"),
    ("l_AB,l_BC\n-0.1,0.3\n", "designs.csv, row 1 (line 2), column 'l_AB': l_AB must be > 0"),
    ("l_AB,l_BC\n0.1\n", "designs.csv, row 1 (line 2): 1 values for the 2 columns"),
    ("variant,l_AB\n../up,0.1\n", "designs.csv, row 1 (line 2), column 'variant': '../up' is "
                                  "not a folder name"),
    ("variant,l_AB\na,0.1\na,0.12\n", "designs.csv, row 2 (line 3), column 'variant': 'a' "
                                      "names row 1 too"),
])
def test_a_bad_csv_file_is_named_by_file_row_and_column(tmp_path, text, message):
    csv = tmp_path / "designs.csv"
    csv.write_text(text)
    with pytest.raises(InputError) as err:
        read_variants(presets.get("four_bar"), csv)
    assert str(err.value).replace(str(csv), "designs.csv").startswith(message), str(err.value)


def test_a_variant_that_cannot_be_built_names_its_row(tmp_path):
    csv = tmp_path / "designs.csv"
    csv.write_text("variant,l_AB,l_BC,l_CD,l_AD\nok,0.1,0.35,0.3,0.4\nnone,0.1,0.1,0.1,5\n")
    with pytest.raises(ValueError, match=r"row 2 \(variant none\)|cannot be assembled"):
        write_variants(presets.get("four_bar"), csv, tmp_path / "out", positions=[30.0])


# -- the command line ------------------------------------------------------------------------
def test_the_report_command_writes_the_page_and_names_a_bad_csv(tmp_path):
    err = io.StringIO()
    with redirect_stderr(err):
        assert main(["report", "scotch_yoke", "-o", str(tmp_path / "r"), "--omega", "10",
                     "--load", "400", "--positions", "60,150"]) == 0
    assert f"wrote {tmp_path / 'r' / 'index.html'}" in err.getvalue()
    page = Page((tmp_path / "r" / "index.html").read_text(encoding="utf-8"))
    assert page.unknowns["theta-60"]["Mb"] == "15.6699"
    assert "theta-220" not in page.unknowns

    csv = tmp_path / "d.csv"
    csv.write_text("l_AB,h2\n0.1,0.08\n0.12,x\n")
    err = io.StringIO()
    with redirect_stderr(err):
        assert main(["report", "scotch_yoke", "-o", str(tmp_path / "v"), "--variants",
                     str(csv)]) == 2
    assert f"linkage-fmu: {csv}, row 2 (line 3), column 'h2': 'x' is not a number" \
        in err.getvalue()
    err = io.StringIO()
    with redirect_stderr(err):
        assert main(["report", "scotch_yoke", "-o", str(tmp_path / "w"), "--positions",
                     "1 rad"]) == 2
    assert "--positions '1 rad': degrees" in err.getvalue()

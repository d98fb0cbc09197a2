"""A linkage's kinetostatics as a web page (:func:`write_report`): its parameters, its
picture and groups, the equilibrium equations ``A x = b`` at chosen crank angles with
their solution (in MathML, which Chromium, Firefox and Safari draw with no script), a
table of every output over the cycle, the curves of the balancing effort and of the
joint forces over a revolution with their extremes, where best to put the balancing
effort (:mod:`~linkage_fmu.effort_places`); and one report per design of a CSV
file with a page comparing them (:func:`write_variants`), a class's answer key.

The page is ``DIR/index.html``, one HTML file with its stylesheet and no script; its
pictures are PNG files beside it. Drawing needs matplotlib (the ``plot`` extra:
``pip install "linkage_fmu[plot]"``), used without pyplot, so that writing a report
changes no backend and keeps no figure.

What a report takes: a linkage driven by one crank on the frame (one driven by time,
several drivers, a motor or a cylinder, is refused: its outputs are not functions of
one crank angle). With friction in its joints, the equations hold each friction at the
solution, and its law.
"""

from __future__ import annotations

import csv
import html
import math
import re
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from . import __version__, ranges
from .descriptions.assur import outline
from .drivers import one_crank
from .equations import equations
from .errors import AssemblyError, DependencyError, InputError, SingularPositionError
from .friction import outputs as friction_outputs
from .printing import number

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd

    from .mechanism import Mechanism

#: the crank angles [deg] of a report's equations by default: the scotch yoke worked
#: example's positions
POSITIONS = (60.0, 150.0, 220.0)
#: the step [deg] of the table over the cycle
TABLE_STEP = 30.0
#: the crank angles of the curves and extremes: 0, 0.5, ..., 360 deg
N_REVOLUTION = 721
#: the significant figures of the numbers shown
DIGITS = 6
_INSTALL = 'a report draws with matplotlib: pip install "linkage_fmu[plot]"'
_VARIANT = "variant"
_SAFE_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.+-]*")
_CSS = """
body { font-family: system-ui, sans-serif; margin: 2em auto; max-width: 90em;
       padding: 0 1em; color: #222; line-height: 1.4; }
h1 { font-size: 1.6em; } h2 { border-bottom: 1px solid #ccc; margin-top: 2em; }
table { border-collapse: collapse; margin: 0.8em 0; font-size: 0.9em; }
th, td { border: 1px solid #ccc; padding: 0.2em 0.6em; }
th { background: #f0f0f0; } td.num { text-align: right; font-variant-numeric: tabular-nums; }
tbody tr:nth-child(even) { background: #fafafa; }
.wide { overflow-x: auto; overflow-y: hidden; padding: 0.3em 0; }
img { max-width: 100%; height: auto; }
.pair { display: flex; flex-wrap: wrap; gap: 1.5em; align-items: flex-start; }
.pair figure { max-width: 50em; }
.note { color: #555; font-style: italic; } figure { margin: 1em 0; }
math { font-size: 1.05em; } mtd { padding: 0.15em 0.45em; }
mtd.label { text-align: left; } mtd.b { border-left: 1px solid #888; }
mtr.head mtd { border-bottom: 1px solid #888; } mn.zero { color: #aaa; }
"""


# -- the numbers --------------------------------------------------------------------
def revolution_extremes(mech: "Mechanism", omega=None, alpha=None, *loads,
                        **named) -> "pd.DataFrame":
    """The balancing effort and each joint force's magnitude over a revolution
    (:data:`N_REVOLUTION` crank angles 0..360 deg): the largest magnitude and where,
    the smallest and largest value and where.

    A joint force with x and y components (:func:`~linkage_fmu.plot.force_pairs`) is
    ``|F|``, one with a single component (a prismatic pair's normal force) its value.
    Angles where the linkage cannot be assembled are left out.

    Parameters
    ----------
    mech : Mechanism
        Driven by one crank.
    omega, alpha, *loads, **named : float, optional
        As :meth:`Mechanism.solve <linkage_fmu.Mechanism.solve>` takes them; the
        linkage's start values if not given.

    Returns
    -------
    pandas.DataFrame
        Indexed by quantity (the effort's name first, then ``|F12|``, ...): columns
        ``unit``, ``peak`` (the largest magnitude), ``peak_deg``, ``min``,
        ``min_deg``, ``max``, ``max_deg``.

    Raises
    ------
    InputError
        The linkage is driven by time, or cannot be assembled at any angle.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> yoke = presets.get("scotch_yoke")
    >>> ex = revolution_extremes(yoke, 10.0, load=400.0)
    >>> list(ex.index)
    ['Mb', '|F12|', '|F41|', 'F23y']
    >>> r = ex.loc["Mb"]                       # its peak, first reached at 193 deg
    >>> r["unit"], round(float(r["peak"]), 4), float(r["peak_deg"])
    ('N.m', 41.1667, 193.0)
    """
    inputs = _inputs(mech, omega, alpha, loads, named)
    deg = np.linspace(0.0, 360.0, N_REVOLUTION)
    return _extremes(mech, deg, _curves(mech, deg, inputs))


def _inputs(mech: "Mechanism", omega, alpha, loads: Sequence, named: dict) -> dict:
    """``{omega, alpha, <load>: value}``: those given, else the start values."""
    one_crank(mech, "a report")
    values, given = mech.inputs(omega, alpha, tuple(loads), named)
    return dict(zip(mech.input_names[1:] + tuple(given), map(float, values)))


def _solve(mech: "Mechanism", deg, inputs: dict):
    loads = {k: v for k, v in inputs.items() if k not in ("omega", "alpha")}
    return mech.solve(np.radians(np.asarray(deg, dtype=float)), inputs["omega"],
                      inputs["alpha"], **loads)


def _reactions(mech: "Mechanism") -> list[tuple[str, tuple[str, ...]]]:
    """(quantity, its output components) of each joint force: a pair's magnitude, or
    a one-component force output (from the description) as it is."""
    from .plot import force_pairs

    found = [(f"|{p.name}|", (p.x, p.y)) for p in force_pairs(mech)]
    paired = {c for _, cs in found for c in cs}
    if mech.description is not None:
        for spec in mech.description.outputs:
            components = spec.get("components", "xy")
            if spec["kind"] == "force" and len(components) == 1:
                name = spec.get(components[0], spec["name"] + components[0])
                if name in mech.output_names and name not in paired:
                    found.append((name, (name,)))
    return found


def _curves(mech: "Mechanism", deg: np.ndarray, inputs: dict) -> dict[str, np.ndarray]:
    """quantity -> its values at ``deg``: the effort, then each joint force."""
    sol = _solve(mech, deg, inputs)
    curves = {mech.effort.name: np.asarray(sol[mech.effort.name], dtype=float)}
    for name, components in _reactions(mech):
        values = [np.asarray(sol[c], dtype=float) for c in components]
        curves[name] = np.hypot(*values) if len(values) == 2 else values[0]
    return curves


def _extremes(mech: "Mechanism", deg: np.ndarray, curves: dict) -> "pd.DataFrame":
    import pandas as pd

    rows = {}
    for name, values in curves.items():
        ok = np.isfinite(values)
        if not ok.any():
            raise InputError(f"{mech.name} cannot be assembled at any of the {deg.size} "
                             f"crank angles {number(deg[0])}..{number(deg[-1])} deg")
        v, d = values[ok], deg[ok]
        k, lo, hi = int(np.argmax(np.abs(v))), int(np.argmin(v)), int(np.argmax(v))
        unit = mech.output_info[name][0] if name in mech.output_info else "N"  # |F|
        rows[name] = {"unit": unit, "peak": float(abs(v[k])), "peak_deg": float(d[k]),
                      "min": float(v[lo]), "min_deg": float(d[lo]),
                      "max": float(v[hi]), "max_deg": float(d[hi])}
    df = pd.DataFrame.from_dict(rows, orient="index")
    df.index.name = "quantity"
    return df


def _table_columns(mech: "Mechanism") -> list[str]:
    """The outputs of the table over the cycle: every one, but the friction outputs of
    a linkage whose every ``mu`` is 0 (all 0)."""
    hidden = set() if mech.friction.active else {o.name for o in friction_outputs(mech)}
    return [n for n in mech.output_names if n not in hidden]


# -- HTML -----------------------------------------------------------------------------
def _e(text) -> str:
    return html.escape(str(text), quote=True)


def _num(value: float, scale: float = 0.0) -> str:
    return "–" if not math.isfinite(value) else number(value, DIGITS, scale=scale)


def _html_table(head: Sequence[str], rows: Sequence[Sequence], numeric: Sequence[bool],
                attrs: str = "") -> str:
    """A table: ``head`` (escaped), rows of cells (escaped, or HTML if wrapped in a
    one-element tuple), right-aligned where ``numeric``."""
    out = [f"<div class=\"wide\"><table{attrs}><thead><tr>"
           + "".join(f"<th>{_e(h)}</th>" for h in head) + "</tr></thead><tbody>"]
    for row in rows:
        cells = []
        for cell, num in zip(row, numeric):
            body = cell[0] if isinstance(cell, tuple) else _e(cell)
            cells.append(f"<td class=\"num\">{body}</td>" if num else f"<td>{body}</td>")
        out.append("<tr>" + "".join(cells) + "</tr>")
    return "".join(out) + "</tbody></table></div>"


def _figure(src: str, alt: str, caption: str = "") -> str:
    cap = f"<figcaption>{_e(caption)}</figcaption>" if caption else ""
    return f"<figure><img src=\"{_e(src)}\" alt=\"{_e(alt)}\">{cap}</figure>"


def _page(title: str, body: list[str]) -> str:
    return ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
            f"<title>{_e(title)}</title><style>{_CSS}</style></head>\n<body>\n"
            + "\n".join(body) + "\n</body></html>\n")


# -- the pictures ---------------------------------------------------------------------
def _new_axes(figsize):
    """A figure of its own (no pyplot: no backend chosen, no figure kept) and its axes."""
    try:
        from matplotlib.figure import Figure
    except ImportError as err:
        raise DependencyError(_INSTALL) from err
    fig = Figure(figsize=figsize, layout="constrained")
    return fig, fig.subplots()


def _save(fig, directory: Path, name: str) -> str:
    fig.savefig(directory / name, dpi=100)
    return name


def _draw_forces(mech: "Mechanism", deg: np.ndarray, curves: dict, ax) -> None:
    from .plot.figures import degree_axis

    for name, values in list(curves.items())[1:]:
        ax.plot(deg, np.abs(values), label=name, gid=name)
    degree_axis(ax, deg)
    ax.set_ylabel("magnitude [N]")
    ax.set_title(f"{mech.name}: joint forces over a revolution", fontsize=10)
    ax.legend(fontsize=8, ncols=2)


# -- the sections ---------------------------------------------------------------------
def _intro(mech: "Mechanism", inputs: dict, heading: str) -> list[str]:
    d = mech.description
    out = [f"<h1>{_e(heading)}</h1>"]
    if d is not None and d.title:
        out.append(f"<p>{_e(d.title)}</p>")
    out.append(f"<p class=\"note\">Written by linkage_fmu {_e(__version__)}; SI units, "
               "angles in degrees; numbers to 6 significant figures.</p>")
    units = {"omega": "rad/s", "alpha": "rad/s²", **mech.input_units}
    words = {"omega": "crank speed ω", "alpha": "crank acceleration α"}
    for load in mech.loads:
        words[load.name] = load.description or f"{load.kind} on link {load.body}"
    out.append("<h2>Inputs</h2>" + _html_table(
        ("input", "value", "unit", "meaning"),
        [(k, _num(v), units.get(k, ""), words.get(k, "")) for k, v in inputs.items()],
        (False, True, False, False)))
    out.append("<h2>Parameters</h2>")
    if d is not None:
        rows = [(p.name, _parameter_text(mech.parameters[p.name]), p.unit, p.description)
                for p in d.parameter_specs()]
    else:
        rows = [(k, _parameter_text(v), "", "") for k, v in mech.parameters.items()]
    out.append(_html_table(("parameter", "value", "unit", "meaning"), rows,
                           (False, True, False, False)))
    return out


def _parameter_text(value) -> str:
    return _num(value) if isinstance(value, (int, float)) else str(value)


def _decomposition(mech: "Mechanism") -> str:
    d = mech.description
    items = []
    if d is not None:
        for cls, kind, links, joints in outline(d.groups):
            if kind == "point":
                items.append(f"point {joints[0]} on link {links[0]}")
            else:
                name = f"II ({kind})" if cls == "II" else cls
                items.append(f"{name}: link{'s' if len(links) > 1 else ''} "
                             f"{', '.join(links)}; joints {', '.join(map(str, joints))}")
        how = "decomposed from its joints and links" if d.drawn is not None else "as written"
    else:
        for grp in mech.groups:
            joints = ", ".join(j.name for j in getattr(grp, "joints", ()))
            items.append(f"{type(grp).__name__}: links {', '.join(grp.links)}"
                         + (f"; joints {joints}" if joints else ""))
        how = "as built"
    return (f"<h3>Decomposition</h3><p>The groups, in the order they are solved ({_e(how)}):"
            "</p><ol>" + "".join(f"<li>{_e(i)}</li>" for i in items) + "</ol>")


def _position(mech: "Mechanism", deg: float, inputs: dict, directory: Path,
              columns: list[str]) -> list[str]:
    label = number(deg, DIGITS)
    out = [f"<section id=\"theta-{_e(label)}\"><h3>θ = {_e(label)}°</h3>"]
    sol = _solve(mech, [deg], inputs)
    if not bool(np.asarray(sol.valid).all()):
        return out + [f"<p class=\"note\">{_e(mech.name)} cannot be assembled at θ = "
                      f"{_e(label)}°.</p></section>"]
    fig, ax = _new_axes((8.0, 6.5))
    from . import plot

    plot.linkage(mech, theta_deg=deg, **inputs, ax=ax)
    picture = _save(fig, directory, f"linkage_{label}.png")
    values = {n: float(np.asarray(sol[n]).ravel()[0]) for n in columns}
    scale = max((abs(v) for v in values.values() if math.isfinite(v)), default=0.0)
    out.append("<div class=\"pair\">" + _figure(
        picture, f"{mech.name} at θ = {label}° with its joint forces") + _html_table(
        ("output", "value", "unit"),
        [(n, _num(values[n], scale), mech.output_info[n][0]) for n in columns],
        (False, True, False), f" data-part=\"outputs\" data-theta=\"{_e(label)}\"")
        + "</div>")
    out.append("<h4>Equilibrium equations</h4>")
    loads = {k: v for k, v in inputs.items() if k not in ("omega", "alpha")}
    try:
        eq = equations(mech, math.radians(deg), inputs["omega"], inputs["alpha"], **loads)
    except (AssemblyError, SingularPositionError) as err:
        return out + [f"<p class=\"note\">{_e(err)}</p></section>"]
    out.append("<p>Each moving link's ΣFx = 0, ΣFy = 0 and ΣM = 0 about the point its group "
               "takes moments about, in SI units; the unknowns are each pair's reaction (the "
               "action of its first body on its second) and the balancing effort.</p>")
    out.append(f"<div class=\"wide symbolic\">{eq.to('mathml')}</div>")
    return out + ["</section>"]


def _cycle_table(mech: "Mechanism", inputs: dict, columns: list[str]) -> list[str]:
    deg = np.arange(0.0, 360.0, TABLE_STEP)
    sol = _solve(mech, deg, inputs)
    data = {n: np.asarray(sol[n], dtype=float).ravel() for n in columns}
    largest = {n: float(np.nanmax(np.abs(v))) if np.isfinite(v).any() else 0.0
               for n, v in data.items()}
    # a column of rounding (a shaking moment that is 0) is 0 against those of its unit
    scale = {n: max(largest[m] for m in columns if mech.output_info[m][0] ==
                    mech.output_info[n][0]) for n in columns}
    rows = [[number(d, DIGITS)] + [_num(data[n][k], scale[n]) for n in columns]
            for k, d in enumerate(deg)]
    out = [f"<h2>Over the cycle</h2><p>Every output every {number(TABLE_STEP)}°.</p>"]
    if not mech.friction.active and friction_outputs(mech):
        out.append("<p class=\"note\">The friction outputs are left out: every coefficient "
                   "of friction is 0.</p>")
    out.append(_html_table(["θ [°]"] + [f"{n} [{mech.output_info[n][0]}]" for n in columns],
                           rows, [True] * (len(columns) + 1), " data-part=\"cycle\""))
    return out


def _revolution(mech: "Mechanism", inputs: dict, directory: Path,
                deg: np.ndarray, curves: dict, extremes: "pd.DataFrame") -> list[str]:
    from . import plot

    out = ["<h2>Effort and joint forces over a revolution</h2>"]
    bad = ~np.isfinite(curves[mech.effort.name])
    if bad.any():
        out.append(f"<p class=\"note\">{_e(mech.name)} cannot be assembled at θ = "
                   f"{_e(ranges.text(ranges.runs(deg, bad)))}°: the curves have gaps there."
                   "</p>")
    fig, ax = _new_axes((8.0, 4.5))
    plot.torque(mech, theta_deg=deg, **inputs, ax=ax)
    out.append(_figure(_save(fig, directory, "effort.png"),
                       f"the balancing effort {mech.effort.name} over a revolution"))
    fig, ax = _new_axes((8.0, 4.5))
    _draw_forces(mech, deg, curves, ax)
    out.append(_figure(_save(fig, directory, "forces.png"),
                       "the joint forces' magnitudes over a revolution"))
    rows = [(name, r["unit"], _num(r["peak"]), number(r["peak_deg"], DIGITS),
             _num(r["min"]), number(r["min_deg"], DIGITS), _num(r["max"]),
             number(r["max_deg"], DIGITS)) for name, r in extremes.iterrows()]
    out.append(f"<h3>Extremes</h3><p>Over {N_REVOLUTION} crank angles 0..360°; a joint "
               "force with two components as its magnitude |F|.</p>")
    out.append(_html_table(("quantity", "unit", "max |value|", "at θ [°]", "min", "at θ [°]",
                            "max", "at θ [°]"), rows, (False, False) + (True,) * 6,
                           " data-part=\"extremes\""))
    return out


def _places(mech: "Mechanism", inputs: dict, deg: np.ndarray) -> list[str]:
    """Where to put the balancing effort (:mod:`~linkage_fmu.effort_places`), over the
    angles ``deg`` of the revolution where the linkage assembles."""
    from .effort_places import effort_places, recommend

    out = ["<h2>Where to put the balancing effort</h2>"]
    loads = {k: v for k, v in inputs.items() if k not in ("omega", "alpha")}
    try:
        table = effort_places(mech, np.radians(deg), inputs["omega"], inputs["alpha"],
                              **loads)
        best, why = recommend(table)
    except InputError as err:
        return out + [f"<p class=\"note\">Not compared: {_e(err)}</p>"]
    out.append(f"<p>Each place the effort can act at, over the {deg.size} crank angles of "
               "the revolution where the linkage assembles: its peak and RMS value, the "
               "largest reaction in any pair, and the power it supplies.</p>")
    rows = [(name, r["effort"], r["unit"], _num(r["peak"]), _num(r["rms"]),
             _num(r["peak_reaction"]), _num(r["peak_power"]), _num(r["mean_power"]),
             r["reason"]) for name, r in table.iterrows()]
    out.append(_html_table(("place", "effort", "unit", "peak", "rms", "peak reaction [N]",
                            "peak power [W]", "mean power [W]", "not possible"),
                           rows, (False,) * 3 + (True,) * 5 + (False,),
                           " data-part=\"places\""))
    out.append(f"<p data-part=\"recommendation\"><strong>{_e(best)}</strong>. "
               f"{_e(why)}</p>")
    return out


def _write(mech: "Mechanism", directory, positions: Sequence[float], inputs: dict,
           heading: str) -> tuple[Path, "pd.DataFrame"]:
    _new_axes((1.0, 1.0))  # matplotlib, or the error that says how to install it
    positions = [float(p) for p in np.atleast_1d(np.asarray(positions, dtype=float))]
    if not positions or not all(map(math.isfinite, positions)):
        raise InputError(f"positions must be finite crank angles [deg], got {positions!r}")
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    deg = np.linspace(0.0, 360.0, N_REVOLUTION)
    curves = _curves(mech, deg, inputs)
    extremes = _extremes(mech, deg, curves)
    columns = _table_columns(mech)
    body = _intro(mech, inputs, heading)
    sections = [_position(mech, p, inputs, directory, columns) for p in positions]
    body.append("<h2>The linkage</h2>")
    drawn = [p for p, section in zip(positions, sections) if "<img" in section[1]]
    if drawn:  # the first position's picture, drawn for its section
        at = number(drawn[0], DIGITS)
        body.append(_figure(f"linkage_{at}.png", f"{mech.name} at θ = {at}°",
                            f"{mech.name} at θ = {at}°, its joint forces drawn to scale "
                            "from their joints"))
    body.append(_decomposition(mech))
    body.append("<h2>Positions</h2>")
    for section in sections:
        body += section
    body += _cycle_table(mech, inputs, columns)
    body += _revolution(mech, inputs, directory, deg, curves, extremes)
    cycle = deg[:-1]  # 360 deg is 0: a cycle sampled evenly, for the mean power
    body += _places(mech, inputs, cycle[np.isfinite(curves[mech.effort.name][:-1])])
    path = directory / "index.html"
    path.write_text(_page(heading, body), encoding="utf-8")
    return path, extremes


def write_report(mech: "Mechanism", directory, positions: Sequence[float] = POSITIONS,
                 omega=None, alpha=None, *loads, **named) -> Path:
    """Write the report of ``mech`` into ``directory``: ``index.html`` and its PNG
    pictures.

    The page holds, in order: the linkage's name and title, its inputs and parameters
    (tables with units); its picture at the first position and its groups in the order
    they are solved; at each position, its picture with the joint forces, every output,
    and the equilibrium equations ``A | b`` labelled by equation and unknown with their
    solution, then each link's free body and equations as
    :meth:`Equations.to("mathml") <linkage_fmu.equations.Equations.to>` writes them
    (MathML; sympy writes those); every output every :data:`TABLE_STEP` degrees over
    the cycle; the curves of the balancing effort and of the joint forces' magnitudes
    over a revolution and a table of their extremes (:func:`revolution_extremes`);
    where to put the balancing effort (:func:`~linkage_fmu.effort_places.
    effort_places` over the revolution's angles where it assembles, and its
    :func:`~linkage_fmu.effort_places.recommend`).

    Parameters
    ----------
    mech : Mechanism
        Driven by one crank on the frame.
    directory : str or Path
        Made if missing; files of a report already there are replaced.
    positions : sequence of float, optional
        The crank angles [deg] of the equations; default :data:`POSITIONS`.
    omega, alpha, *loads, **named : float, optional
        The crank's speed [rad/s] and acceleration [rad/s2] and the loads, as
        :meth:`Mechanism.solve <linkage_fmu.Mechanism.solve>` takes them; the
        linkage's start values if not given.

    Returns
    -------
    Path
        ``directory / "index.html"``.

    Raises
    ------
    InputError
        The linkage is driven by time (several drivers, a motor, a cylinder), cannot
        be assembled at any angle, or a position is not a finite number.
    DependencyError
        matplotlib is not installed (an ``ImportError`` naming the ``plot`` extra).

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> from linkage_fmu import presets
    >>> yoke = presets.get("scotch_yoke")
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     page = write_report(yoke, tmp, omega=10.0, load=400.0)
    ...     text = page.read_text(encoding="utf-8")
    ...     pictures = sorted(p.name for p in Path(tmp).glob("*.png"))
    >>> page.name, text.count('data-part="matrix"'), "<script" in text
    ('index.html', 3, False)
    >>> pictures  # doctest: +NORMALIZE_WHITESPACE
    ['effort.png', 'forces.png', 'linkage_150.png', 'linkage_220.png',
     'linkage_60.png']
    """
    inputs = _inputs(mech, omega, alpha, loads, named)
    return _write(mech, directory, positions, inputs, f"{mech.name}: kinetostatic report")[0]


# -- variants ---------------------------------------------------------------------------
def read_variants(mech: "Mechanism", path) -> list[tuple[str, dict]]:
    """The designs of a CSV file: one row each, a column per parameter of ``mech``
    (numbers in SI; a parameter of kind ``choice`` takes its text), and an optional
    first column ``variant`` naming each (letters, digits, ``_.+-``); without it,
    ``variant_1``, ``variant_2``, ... Blank lines are skipped.

    Parameters
    ----------
    mech : Mechanism
        Built from a description (its parameters are the columns' names).
    path : str or Path

    Returns
    -------
    list of (str, dict)
        Each variant's name and its parameters (name -> value, as checked by the
        parameter: ``branch_B`` 1.0 as 1).

    Raises
    ------
    InputError
        The file is empty or has no rows, a column is not a parameter (or repeats
        one), a row has too few or too many values, a value is empty, not a number or
        out of its parameter's range, a variant's name is not a folder name or repeats
        another: the message names the file, the row (and its line) and the column.

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> from linkage_fmu import presets
    >>> bar = presets.get("four_bar")
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     f = Path(tmp) / "designs.csv"
    ...     _ = f.write_text("l_AB,l_BC\\n0.1,0.35\\n0.12,0.4\\n")
    ...     for variant in read_variants(bar, f):
    ...         print(variant)
    ...     _ = f.write_text("l_AB,l_BC\\n0.1,long\\n")
    ...     try:
    ...         read_variants(bar, f)
    ...     except InputError as err:
    ...         print(str(err).replace(str(f), "designs.csv"))
    ('variant_1', {'l_AB': 0.1, 'l_BC': 0.35})
    ('variant_2', {'l_AB': 0.12, 'l_BC': 0.4})
    designs.csv, row 1 (line 2), column 'l_BC': 'long' is not a number
    """
    if mech.description is None:
        raise InputError(f"{mech.name} was built without a description: its variants "
                         "cannot be built from their parameters")
    specs = {p.name: p for p in mech.description.parameter_specs()}
    with open(path, newline="", encoding="utf-8-sig") as f:
        reader = csv.reader(f)
        lines = [(reader.line_num, row) for row in reader if any(c.strip() for c in row)]
    if not lines:
        raise InputError(f"{path}: the file is empty; expected a header row of parameter "
                         f"names (an optional first column {_VARIANT!r}), then a row per "
                         "variant")
    header = [c.strip() for c in lines[0][1]]
    named = bool(header) and header[0] == _VARIANT
    for k, name in enumerate(header, 1):
        where = f"{path}, line {lines[0][0]}, column {k}"
        if not name:
            raise InputError(f"{where}: the column has no name")
        if name == _VARIANT and (k > 1):
            raise InputError(f"{where}: {_VARIANT!r} must be the first column")
        if name != _VARIANT and name not in specs:
            raise InputError(f"{where} {name!r}: {mech.name} has no parameter {name!r}; its "
                             f"parameters are: {', '.join(specs)}")
        if header.index(name) != k - 1:
            raise InputError(f"{where} {name!r}: the column repeats column "
                             f"{header.index(name) + 1}")
    if len(lines) < 2:
        raise InputError(f"{path}: no variant rows under the header")
    variants, seen = [], {}
    for i, (line, row) in enumerate(lines[1:], 1):
        where = f"{path}, row {i} (line {line})"
        if len(row) != len(header):
            raise InputError(f"{where}: {len(row)} values for the {len(header)} columns")
        values = {}
        for name, text in zip(header, (c.strip() for c in row)):
            if not text:
                raise InputError(f"{where}, column {name!r}: the value is empty")
            if name == _VARIANT:
                continue
            spec = specs[name]
            value = text
            if spec.kind != "choice":
                try:
                    value = float(text)
                except ValueError:
                    raise InputError(f"{where}, column {name!r}: {text!r} is not a number") \
                        from None
                if not math.isfinite(value):
                    raise InputError(f"{where}, column {name!r}: {text!r} is not a finite "
                                     "number")
            try:
                values[name] = spec.validate(value)
            except (ValueError, TypeError) as err:
                raise InputError(f"{where}, column {name!r}: {err}") from None
        label = row[0].strip() if named else f"variant_{i}"
        if not _SAFE_NAME.fullmatch(label):
            raise InputError(f"{where}, column {_VARIANT!r}: {label!r} is not a folder name "
                             "(letters, digits and _ . + -, not first)")
        if label in seen:
            raise InputError(f"{where}, column {_VARIANT!r}: {label!r} names row "
                             f"{seen[label]} too")
        seen[label] = i
        variants.append((label, values))
    return variants


def write_variants(mech: "Mechanism", path, directory, positions: Sequence[float] = POSITIONS,
                   omega=None, alpha=None, *loads, **named) -> Path:
    """Write a report (:func:`write_report`) of each design of the CSV file ``path``
    (:func:`read_variants`: ``mech`` with the row's parameters in place of its own) in
    ``directory/<variant>/``, and ``directory/index.html`` listing them: each one's
    link, parameters, the peak magnitude of its balancing effort and of each joint
    force over a revolution (:func:`revolution_extremes`; each cell's ``data-value``
    the value unrounded).

    Parameters
    ----------
    mech : Mechanism
        Built from a description; the parameters a row does not give keep its values.
    path : str or Path
        The CSV file.
    directory : str or Path
        Made if missing.
    positions, omega, alpha, *loads, **named
        As for :func:`write_report`, the same for every variant.

    Returns
    -------
    Path
        ``directory / "index.html"``.

    Raises
    ------
    InputError
        A bad CSV file (:func:`read_variants`), a variant that cannot be built (the
        message names the file and the row), or as :func:`write_report`.

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> from linkage_fmu import presets
    >>> bar = presets.get("four_bar")
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     f = Path(tmp) / "designs.csv"
    ...     _ = f.write_text("variant,l_AB\\nshort,0.08\\nlong,0.12\\n")
    ...     page = write_variants(bar, f, Path(tmp) / "out", positions=[30.0])
    ...     print(sorted(p.parent.name for p in page.parent.glob("*/index.html")))
    ['long', 'short']
    """
    variants = read_variants(mech, path)
    one_crank(mech, "a report")
    directory = Path(directory)
    rows, reactions, effort_unit = [], None, ""
    for i, (label, values) in enumerate(variants, 1):
        try:
            built = mech.description.build(**{**mech.parameters, **values})
        except (ValueError, TypeError) as err:
            raise InputError(f"{path}, row {i} (variant {label}): {err}") from None
        inputs = _inputs(built, omega, alpha, loads, named)
        heading = f"{mech.name}, {label}: kinetostatic report"
        _, ex = _write(built, directory / label, positions, inputs, heading)
        reactions = list(ex.index[1:]) if reactions is None else reactions
        effort_unit = ex.iloc[0]["unit"]
        rows.append((label, values, ex))
    names = list(dict.fromkeys(n for _, values, _ in rows for n in values))
    effort = mech.effort.name
    head = (["variant"] + names + [f"peak |{effort}| [{effort_unit}]", "at θ [°]"]
            + [f"peak {r} [N]" for r in reactions])
    table = []
    for label, values, ex in rows:
        cells = [(f"<a href=\"{_e(label)}/index.html\">{_e(label)}</a>",)]
        cells += [_parameter_text(values[n]) for n in names]
        cells.append((_valued(ex.iloc[0]["peak"]),))
        cells.append(number(ex.iloc[0]["peak_deg"], DIGITS))
        cells += [(_valued(ex.loc[r, "peak"]),) if r in ex.index else "–" for r in reactions]
        table.append(cells)
    body = [f"<h1>{_e(mech.name)}: {len(rows)} variants</h1>"]
    if mech.description.title:
        body.append(f"<p>{_e(mech.description.title)}</p>")
    body.append(f"<p>From {_e(Path(path).name)}; the parameters not given there as in every "
                f"report. Peaks over {N_REVOLUTION} crank angles 0..360°; a joint force with "
                "two components as its magnitude |F|.</p>")
    body.append(_html_table(head, table, [False] + [True] * (len(head) - 1),
                            " data-part=\"variants\""))
    index = directory / "index.html"
    index.write_text(_page(f"{mech.name}: variants", body), encoding="utf-8")
    return index


def _valued(value: float) -> str:
    """A number shown rounded, its ``data-value`` the float unrounded."""
    return f"<span data-value=\"{float(value)!r}\">{_e(_num(value))}</span>"

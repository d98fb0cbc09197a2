"""The equilibrium equations of a linkage at one state, as the source documents write
them: each moving link's free body (:mod:`~linkage_fmu.free_body`) and its ``ΣFx = 0``,
``ΣFy = 0`` and ``ΣM = 0`` about the point its group chooses (a crank's pivot, a dyad
link's outer joint), assembled into ``A x = b`` with every row and column labelled, in
SI units, and solved (:func:`equations`); written out as text, markdown, LaTeX or
MathML (:meth:`Equations.to`).

The system is the one the direct solver solves (:func:`~linkage_fmu.kinetostatics.
equilibrium_entries`, in SI units). The unknowns are each pair's two reaction
components, the action of its first body on its second (``Fx_<pair>``, ``Fy_<pair>``
for a revolute pair, ``N_<pair>``, ``M_<pair>`` for a prismatic one, as a description's
expressions name them), then each effort.
"""

from __future__ import annotations

import html
from dataclasses import dataclass, field

import numpy as np

from . import evaluation, friction, kinetostatics
from .equation_files import LANGUAGES, function_file
from .errors import InputError
from .free_body import FreeBodies, free_bodies
from .loads import wrenches
from .numerics import SCALAR
from .printing import number

#: what :meth:`Equations.to` writes
FORMATS = ("text", "markdown", "latex", "mathml", "matlab", "python")


@dataclass(frozen=True)
class Equations:
    """``A x = b`` of a linkage at one state: ``unknowns`` (column labels), ``rows``
    (row labels, ``"link 2: ΣFx"``), ``A`` and ``b`` (numpy, SI), ``state`` (each input
    -> its value), ``units`` (each unknown's), ``free_bodies``
    (:class:`~linkage_fmu.free_body.FreeBodies`, the equations symbolically);
    :attr:`solution` (unknown -> value, ``A \\ b``), :attr:`residual`, :attr:`det`
    and :attr:`cond`; :meth:`to` writes it out."""

    name: str
    unknowns: tuple
    rows: tuple
    A: np.ndarray
    b: np.ndarray
    state: dict = field(default_factory=dict)
    free_bodies: FreeBodies | None = field(default=None, repr=False)
    mech: object = field(default=None, repr=False, compare=False)
    units: tuple = ()

    @property
    def solution(self) -> dict:
        return dict(zip(self.unknowns, np.linalg.solve(self.A, self.b).tolist()))

    @property
    def residual(self) -> float:
        """``|A x - b|`` (largest entry) at the solution."""
        x = np.array(list(self.solution.values()))
        return float(np.max(np.abs(self.A @ x - self.b)))

    @property
    def det(self) -> float:
        return float(np.linalg.det(self.A))

    @property
    def cond(self) -> float:
        return float(np.linalg.cond(self.A))

    def symbolic(self) -> tuple:
        """``(A, b)`` as sympy matrices, written from the free bodies alone; at
        ``free_bodies.values`` they are :attr:`A` and :attr:`b`."""
        return self.free_bodies.matrices()

    def to(self, fmt: str = "text") -> str:
        """The system written out, in a format of :data:`FORMATS`:

        * ``"text"``: the table of every a(i, j) and b(i), as the hinged four-bar
          worked example tables them, then each link's free body and equations, the
          solution, the residual, det A and the condition number;
        * ``"markdown"``: the same, as markdown tables;
        * ``"latex"``: each link's equations (``align*``), ``A`` and ``b``
          (``bmatrix``) and the solution;
        * ``"mathml"``: the same in MathML (``<math display="block">`` elements, for a
          web page);
        * ``"matlab"``, ``"python"``: a function file of the linkage's inputs returning
          ``A \\ b`` (:func:`~linkage_fmu.equation_files.function_file`).
        """
        if fmt not in FORMATS:
            raise InputError(f"format {fmt!r}: the formats are {', '.join(FORMATS)}")
        if fmt in LANGUAGES:
            return function_file(self.mech, self.state, self.unknowns, fmt)
        return {"text": _text, "markdown": _markdown, "latex": _latex,
                "mathml": _mathml}[fmt](self)

    def title(self) -> str:
        at = ", ".join(f"{k} = {v:.6g}" for k, v in self.state.items())
        return f"{self.name} at {at}: A x = b, {len(self.rows)} equations"


def _g(v: float) -> str:
    return f"{v:.6g}"


def _by_link(eq: Equations):
    """Each link with its free body and its three equations (sympy)."""
    import sympy

    fb = eq.free_bodies
    lhs = fb.equations()
    for k, (link, actions) in enumerate(fb.actions.items()):
        yield link, actions, [sympy.Eq(e, 0) for e in lhs[3 * k:3 * k + 3]]


def _text(eq: Equations, markdown: bool = False) -> str:
    n = len(eq.unknowns)
    head = ["i", "equation"] + [f"a(i, {j + 1})" for j in range(n)] + ["b(i)"]
    table = [[str(i + 1), row] + [_g(v) for v in eq.A[i]] + [_g(eq.b[i])]
             for i, row in enumerate(eq.rows)]
    lines = [f"**{eq.title()}**" if markdown else eq.title(), ""]
    if markdown:
        lines += ["| j | " + " | ".join(str(j + 1) for j in range(n)) + " |",
                  "|---" * (n + 1) + "|",
                  "| unknown | " + " | ".join(eq.unknowns) + " |", "",
                  "| " + " | ".join(head) + " |", "|---" * len(head) + "|"]
        lines += ["| " + " | ".join(r) + " |" for r in table]
    else:
        wide = [max(len(r[c]) for r in [head] + table) for c in range(len(head))]
        lines.append("unknowns: " + ", ".join(f"x{j + 1} = {u}" for j, u in
                                               enumerate(eq.unknowns)))
        lines += ["  ".join(c.rjust(w) if k != 1 else c.ljust(w) for k, (c, w) in
                            enumerate(zip(r, wide))) for r in [head] + table]
    for link, actions, equations in _by_link(eq):
        lines += ["", f"link {link}, moments about {eq.free_bodies.about[link]}:"]
        lines += [f"  {a.what}: " + (f"({a.fx}, {a.fy})" if a.at else f"{a.m}")
                  for a in actions]
        lines += [f"  {e.lhs} = 0" for e in equations]
    if eq.free_bodies.laws:
        lines += ["", "friction, at the solution (s: the sign of the pair's motion):"]
        lines += [f"  {law.lhs} = {law.rhs} = {_g(eq.free_bodies.values[law.lhs])}"
                  for law in eq.free_bodies.laws]
    lines += ["", "solution:"] + [f"  {u} = {_g(v)}" for u, v in eq.solution.items()]
    lines.append(f"residual {eq.residual:.3g}, det A {_g(eq.det)}, cond {eq.cond:.3g}")
    return "\n".join(lines) + "\n"


def _markdown(eq: Equations) -> str:
    return _text(eq, markdown=True)


def _latex(eq: Equations) -> str:
    import sympy

    out = [f"% {eq.title()}"]
    for link, _, equations in _by_link(eq):
        about = eq.free_bodies.about[link]
        out += [f"% link {link}, moments about {about}", "\\begin{align*}"]
        out += ["  " + sympy.latex(e.lhs) + " &= 0" + (" \\\\" if k < 2 else "")
                for k, e in enumerate(equations)]
        out.append("\\end{align*}")
    if eq.free_bodies.laws:
        out += ["% friction, at the solution (s: the sign of the pair's motion)",
                "\\begin{align*}"]
        out += ["  " + sympy.latex(law.lhs) + " &= " + sympy.latex(law.rhs) + " = "
                + _g(eq.free_bodies.values[law.lhs]) + " \\\\" for law in eq.free_bodies.laws]
        out.append("\\end{align*}")
    rows = [" & ".join(_g(v) for v in r) for r in eq.A]
    out += ["\\[", "\\begin{bmatrix}", " \\\\\n".join(rows), "\\end{bmatrix}",
            "\\begin{bmatrix}", " \\\\ ".join(sympy.latex(sympy.Symbol(u))
                                             for u in eq.unknowns),
            "\\end{bmatrix} = \\begin{bmatrix}", " \\\\ ".join(_g(v) for v in eq.b),
            "\\end{bmatrix}", "\\]"]
    out += ["% solution"] + [f"% {u} = {_g(v)}" for u, v in eq.solution.items()]
    return "\n".join(out) + "\n"


def _mi(name: str) -> str:
    """A name in MathML: ``Fx_A`` as Fx with the subscript A."""
    base, sep, sub = name.partition("_")
    if sep and base and sub:
        return f"<msub><mi>{html.escape(base)}</mi><mi>{html.escape(sub)}</mi></msub>"
    return f"<mi>{html.escape(name)}</mi>"


def _mn(value: float, scale: float = 0.0) -> str:
    """A number in MathML, 0 where it is within rounding of 0 against ``scale``."""
    text = number(value, 6, scale=scale)
    if text == "0":
        return '<mn class="zero">0</mn>'
    if text.startswith("-"):
        return f"<mrow><mo>−</mo><mn>{html.escape(text[1:])}</mn></mrow>"
    return f"<mn>{html.escape(text)}</mn>"


def _mathml(eq: Equations) -> str:
    """Each link's free body and equations, ``A | b`` with its rows and columns
    labelled, the solution with its units, then the residual, det A and cond A."""
    from sympy.printing.mathml import mathml

    def sym(expr) -> str:
        return mathml(expr, printer="presentation")

    def text(s: str) -> str:
        return f"<mtext>{html.escape(s)}</mtext>"

    out = []
    for link, actions, equations in _by_link(eq):
        about = eq.free_bodies.about[link]
        rows = "".join(
            f"<mtr><mtd>{text(a.what)}</mtd><mtd>" + (
                f"<mrow><mo>(</mo>{sym(a.fx)}<mo>,</mo>{sym(a.fy)}<mo>)</mo></mrow>"
                if a.at else sym(a.m)) + "</mtd></mtr>" for a in actions)
        out.append(f"<p>link {html.escape(link)}: its free body, and its equations with the "
                   f"moments about {html.escape(about)}</p>")
        out.append(f'<math display="block" data-part="free body"><mtable>{rows}</mtable>'
                   "</math>")
        out.append('<math display="block" data-part="link equations"><mtable>' + "".join(
            f"<mtr><mtd>{sym(e)}</mtd></mtr>" for e in equations) + "</mtable></math>")
    if eq.free_bodies.laws:
        out.append("<p>the friction in the pairs, at the solution (s: the sign of the "
                   "pair's motion)</p>")
        out.append('<math display="block" data-part="friction"><mtable>' + "".join(
            f"<mtr><mtd>{sym(law)}</mtd><mtd><mo>=</mo>"
            f"{_mn(eq.free_bodies.values[law.lhs])}</mtd></mtr>"
            for law in eq.free_bodies.laws) + "</mtable></math>")
    head = '<mtr class="head"><mtd><mtext>equation</mtext></mtd>' + "".join(
        f"<mtd>{_mi(u)}</mtd>" for u in eq.unknowns) + '<mtd class="b"><mi>b</mi></mtd></mtr>'
    rows, b_scale = [], float(np.max(np.abs(eq.b)))
    for i, label in enumerate(eq.rows):
        scale = float(np.max(np.abs(eq.A[i])))
        rows.append(f'<mtr><mtd class="label">{text(label)}</mtd>'
                    + "".join(f"<mtd>{_mn(v, scale)}</mtd>" for v in eq.A[i])
                    + f'<mtd class="b">{_mn(eq.b[i], b_scale)}</mtd></mtr>')
    out.append('<math display="block" data-part="matrix"><mrow><mi>A</mi><mo>|</mo><mi>b</mi>'
               f"<mo>=</mo><mtable>{head}{''.join(rows)}</mtable></mrow></math>")
    scale = max(map(abs, eq.solution.values()))
    rows = "".join(
        f'<mtr data-unknown="{html.escape(u)}"><mtd>{_mi(u)}</mtd><mtd><mo>=</mo></mtd>'
        f'<mtd style="text-align: right">{_mn(v, scale)}</mtd><mtd class="label">'
        f"{text(unit)}</mtd></mtr>"
        for (u, v), unit in zip(eq.solution.items(), eq.units))
    out.append('<math display="block" data-part="solution"><mrow><mi>x</mi><mo>=</mo>'
               "<msup><mi>A</mi><mrow><mo>−</mo><mn>1</mn></mrow></msup><mi>b</mi><mo>:</mo>"
               f"<mtable>{rows}</mtable></mrow></math>")
    out.append(f"<p>residual max|A x − b| = {number(eq.residual, 3)}, det A = "
               f"{number(eq.det, 6)}, cond A = {number(eq.cond, 3)}</p>")
    return "\n".join(out) + "\n"


def equations(mech, theta=None, omega=None, alpha=None, *loads, **named) -> Equations:
    """The labelled system ``A x = b`` of ``mech`` at one state (its inputs as
    ``Mechanism.solve`` takes them, one value each), solved.

    Examples
    --------
    The scotch yoke worked example's eight equations at 60 deg, 10 rad/s, Fr 400 N:

    >>> import math
    >>> from linkage_fmu import presets
    >>> yoke = presets.get("scotch_yoke")
    >>> eq = equations(yoke, math.radians(60), 10.0, load=400.0)
    >>> len(eq.rows), eq.rows[:3], eq.unknowns[-1]
    (9, ('link 1: ΣFx', 'link 1: ΣFy', 'link 1: ΣM about A'), 'Mb')
    >>> round(eq.solution["Mb"], 4), round(eq.solution["Fy_B"], 4)
    (15.6699, 278.7564)
    """
    if mech.rates:
        values, given = mech.input_table.every((theta, omega, alpha, *loads), named)
    else:
        rest, given = mech.inputs(omega, alpha, loads, named)
        values = [theta, *rest]
    if any(np.ndim(v) for v in values):
        raise InputError("equations are of one state: give each input one value")
    values = [float(v) for v in values]
    state = dict(zip(mech.input_names, values))
    theta, omega, alpha, loads = evaluation.split(mech, values)
    st, omega, alpha = evaluation.at_state(mech, theta, omega, alpha, 2, SCALAR)
    every = evaluation.every_load(mech, given, loads)
    W = wrenches(mech, st, omega, alpha, every, False)
    rubbing, signs = {}, {}
    if mech.friction.active:  # each friction as its value at the solution
        sol = mech.solve(**state, **{k: named[k] for k in given})
        rubbing = {jf.joint.name: float(sol[jf.output]) for jf in mech.friction.joints}
        for jf in mech.friction.joints:
            friction.apply(mech, st, W, jf, rubbing[jf.joint.name])
        _, signs = friction.motion_signs(mech, st, omega, not (omega or alpha))
    about = {link: grp.moment_point(link) for grp in mech.groups for link in grp.links}
    n, entries, rhs = kinetostatics.equilibrium_entries(mech, st, W, about, 1.0)
    A, b = np.zeros((n, n)), np.zeros(n)
    for r, c, v in entries:
        A[r, c] += v
    for r, v in rhs:
        b[r] += v
    names = [f"{c}_{j.name}" for j in mech.joints for c in j.components]
    names += [e.name for e in mech.efforts]
    labels = []
    for body in mech.bodies:
        labels += [f"link {body.name}: ΣFx", f"link {body.name}: ΣFy",
                   f"link {body.name}: ΣM about {about[body.name]}"]
    fb = free_bodies(mech, st, omega, alpha, every, tuple(names), about, rubbing, signs)
    units = tuple("N.m" if c == "M" else "N" for j in mech.joints for c in j.components)
    units += tuple(mech.output_info[e.name][0] for e in mech.efforts)
    return Equations(mech.name, tuple(names), tuple(labels), A, b, state, fb, mech, units)

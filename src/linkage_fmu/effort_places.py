"""Where to put the balancing effort: the places a linkage's balancing effort can act at,
each with the effort it takes, the load on the bearings and the power it supplies over
the given crank angles (the six-bar coursework's task 2, for any linkage).

A place is a moment on a moving link (a couple, about its pivot) or a force on a slider
along its guide. :func:`places` builds the linkage once per place from its description;
:func:`effort_places` solves each over the crank angles and tabulates them;
:func:`recommend` picks the place whose bearings are loaded least.

Places are named

* by the values of the description's choice parameter where its ``[effort]`` is
  ``choose = PARAMETER`` (the six-bar's ``"OA"``, ``"AB"``, ``"O1B"``, ``"KD"``,
  ``"D"``), each built with that value, as :func:`linkage_fmu.presets.get` builds it;
* ``"moment on <link>"`` for a moving link whose moment no option is, its effort
  named ``Mb`` (or the description's own effort's name, where that is this moment);
  not for a slider on a guide fixed in the frame, which does not turn, so that a
  moment on it does no work and balances nothing;
* ``"force at <slider>"`` for a link in a prismatic pair with the frame (a guide fixed
  in the frame) whose force along the guide no option is, its effort named ``Pb``,
  positive along the pair's sliding direction ``t = (n_y, -n_x)`` (its normal ``n``
  turned 90 deg clockwise), acting at the pair's point. A block in the slot of a
  moving link is no slider here: a force along its guide would turn with the guide,
  and a balancing effort of a description has a direction fixed in the frame;
* ``"<effort> on <link> at <point>"`` for a description's one ``[effort]`` that is
  none of these (a force elsewhere).

Every place gets the linkage's parameters, loads and friction; the other placements
of the effort are left out of the linkage built for a place.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd

from . import ranges
from .errors import InputError
from .printing import number
from .solver import SOLVED

__all__ = ["places", "effort_places", "recommend"]

#: the names the generic places' efforts take: a moment, a force along a guide
MOMENT, FORCE = "Mb", "Pb"
#: the stem of the reaction outputs the linkage of a place reports
REACTION = "reaction_"
#: a state whose condition estimate ``cond`` is above this is near-singular: its effort
#: and reactions have lost more than about 4 of their 16 digits to rounding
ILL_CONDITIONED = 1e12
#: parallel within this (unit vectors): an option's force along a slider's guide
PARALLEL = 1e-9


def places(mech) -> dict:
    """The linkage ``mech`` built once per place of its balancing effort: place name ->
    Mechanism (the names: :mod:`linkage_fmu.effort_places`), each reporting its effort
    and the reaction of every pair.

    Raises
    ------
    InputError
        ``mech`` is driven by time (several drivers, a motor, a cylinder: each drives,
        there is no balancing effort to place), or was built without a description.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> built = places(presets.get("six_bar"))
    >>> list(built)
    ['OA', 'AB', 'O1B', 'KD', 'D']
    >>> built["D"].effort.name, built["D"].effort.body, built["D"].effort.point
    ('Pb', 'slider', 'D')
    >>> list(places(presets.get("slider_crank")))
    ['moment on 1', 'moment on 2', 'force at 3']
    """
    _placeable(mech)
    d = mech.description
    params = dict(mech.parameters)
    out: dict = {}
    choice = [w for w in d.efforts if w is not None]
    for parameter, value in choice:  # the description's own options, by their values
        out[str(value)] = _variant(mech, {}, {**params, parameter: value})
    if None in d.efforts:  # its one effort, named by where it acts
        out[_generic_name(mech, mech.effort)] = _variant(mech, {}, params)
    moments = {m.effort.body for m in out.values() if m.effort.direction is None}
    forces = [(m.effort.body, m.effort.direction) for m in out.values()
              if m.effort.direction is not None]
    sliders = _sliders(mech)
    turning = {b.name for b in mech.bodies} - {slider for slider, _, _ in sliders}
    for body in mech.bodies:
        if body.name in turning and body.name not in moments:
            out[f"moment on {body.name}"] = _variant(mech, {"name": MOMENT, "body": body.name},
                                                     params)
    for slider, point, t in sliders:
        if not any(b == slider and _along(u, t) for b, u in forces):
            spec = {"name": FORCE, "body": slider, "at": point, "direction": list(t)}
            out[f"force at {slider}"] = _variant(mech, spec, params)
    return out


def effort_places(mech, theta, omega=0.0, alpha=0.0, *loads, **named) -> pd.DataFrame:
    """The places the balancing effort of ``mech`` can act at, compared over the crank
    angles ``theta``: the effort each needs, the peak reaction in each pair, the power.

    Parameters
    ----------
    mech : Mechanism
        A linkage driven by one crank, built from a description.
    theta : array_like
        Crank angles [rad], e.g. a revolution.
    omega, alpha : float or array_like, optional
        Crank speed [rad/s] and acceleration [rad/s2] (default 0: a static scene), as
        :meth:`~linkage_fmu.mechanism.Mechanism.solve` takes them (text with a unit
        too; None: the linkage's start value).
    *loads, **named
        The loads, as ``solve`` takes them.

    Returns
    -------
    pandas.DataFrame
        Indexed by ``place`` (names: :mod:`linkage_fmu.effort_places`), one row each;
        columns: ``effort`` (the effort's output name: ``Mb``, ``Pb``), ``unit`` (N.m
        or N), ``peak`` (the largest ``|effort|``), ``rms``, ``peak_reaction`` (the
        largest reaction over every pair and angle), ``peak_<pair>`` for each pair (its
        largest reaction: ``sqrt(Fx**2 + Fy**2)`` of a revolute pair, ``|N|`` of a
        prismatic pair's normal force), ``peak_power`` and ``mean_power`` [W] (the
        largest ``|P|`` and the mean of ``P``, the power the effort supplies: ``Mb``
        times its link's angular speed, ``Pb`` times its slider's speed along it; the
        mean is over the angles given, a cycle's mean where they sample one evenly),
        and ``reason``: '' where the place balances the linkage at every angle, else
        why not and where: singular (its link does not move) or locked by friction at
        some angles, the row's numbers then NaN; or near-singular (the condition
        estimate ``cond`` above :data:`ILL_CONDITIONED` at some angle: the numbers
        are as solved, dominated by rounding at those angles). Without friction the
        power is the same at every place (the virtual power of the loads and the
        links' inertia); with it, each place's friction loss adds to it.

    Raises
    ------
    InputError
        ``mech`` driven by time or built without a description (:func:`places`),
        ``theta`` not finite numbers, or an angle where the linkage cannot be assembled
        (wherever its effort is).

    Examples
    --------
    >>> import numpy as np
    >>> from linkage_fmu import presets
    >>> theta = np.linspace(0.0, 2.0 * np.pi, 36, endpoint=False)
    >>> table = effort_places(presets.get("six_bar"), theta, load=100.0)
    >>> table[["effort", "unit", "peak", "peak_reaction"]].round(1)
                     effort unit    peak  peak_reaction
    place
    OA                   Mb  N.m    44.5          451.3
    AB                   Mb  N.m  2490.6         4235.0
    O1B                  Mb  N.m   157.8          687.4
    KD                   Mb  N.m   775.8         1018.7
    D                    Pb    N  2741.9         3068.7
    """
    _placeable(mech)
    theta = _angles(theta)
    (speed, *_), _ = mech.inputs(omega, alpha, loads, named)
    st = mech.kinematics(theta, order=1)
    if st.invalid is not None and np.any(st.invalid):
        bad = np.asarray(st.invalid, bool)
        where = ranges.text(ranges.runs(np.degrees(theta), bad), digits=6)
        raise InputError(f"{mech.name} cannot be assembled at {int(bad.sum())} of {theta.size} "
                         f"angles (theta = {where}), wherever its effort is: give angles where "
                         "it assembles (linkage_fmu.ranges.assembles)")
    speed = np.broadcast_to(np.asarray(speed, dtype=float), theta.shape)
    rows = {}
    for name, m in places(mech).items():
        sol = m.solve(theta, omega, alpha, *loads, **named)
        e = m.effort
        row = {"effort": e.name, "unit": m.output_info[e.name][0]}
        status = np.asarray(sol.status).reshape(-1)
        if np.any(status != SOLVED):
            row.update(dict.fromkeys(("peak", "rms", "peak_reaction"), np.nan))
            row.update({f"peak_{j.name}": np.nan for j in m.joints})
            row.update(peak_power=np.nan, mean_power=np.nan, reason=_unsolved(sol, status))
            rows[name] = row
            continue
        effort = np.asarray(sol[e.name], dtype=float)
        power = effort * _effort_speed(m, st) * speed
        peaks = {f"peak_{j.name}": _peak(np.asarray(sol[f"{REACTION}{j.name}"], float))
                 for j in m.joints}
        row.update(peak=_peak(effort), rms=float(np.sqrt(np.mean(effort * effort))),
                   peak_reaction=max(peaks.values()), **peaks, peak_power=_peak(power),
                   mean_power=float(np.mean(power)), reason=_ill(sol, theta))
        rows[name] = row
    table = pd.DataFrame.from_dict(rows, orient="index")
    table.index.name = "place"
    return table


def recommend(table: pd.DataFrame) -> tuple[str, str]:
    """The place of :func:`effort_places`'s ``table`` whose bearings are loaded least
    (the lowest ``peak_reaction`` of the places whose ``reason`` is '': those that
    balance the linkage at every angle; the first of equal ones), and why, in words: its
    peak reaction and the pair that takes it, and each place's peak effort and peak
    power.

    Raises
    ------
    InputError
        No place balances the linkage at every angle of the table.

    Examples
    --------
    >>> import numpy as np
    >>> from linkage_fmu import presets
    >>> theta = np.linspace(0.0, 2.0 * np.pi, 36, endpoint=False)
    >>> place, why = recommend(effort_places(presets.get("six_bar"), theta))
    >>> place
    'OA'
    >>> print(why)
    OA: the lowest peak reaction in the pairs, 359.1 N (in pair O1). Peak effort and
    peak power by place: OA 37.79 N.m, 0 W; AB 2117 N.m, 0 W; O1B 135.8 N.m, 0 W;
    KD 667.8 N.m, 0 W; D 2787 N, 0 W.
    """
    ok = table[table["reason"] == ""]
    if ok.empty:
        raise InputError("no place balances the linkage at every angle given: "
                         + "; ".join(f"{k}: {r}" for k, r in table["reason"].items()))
    best = ok["peak_reaction"].idxmin()
    pairs = [c for c in table.columns if c.startswith("peak_") and c not in
             ("peak_reaction", "peak_power")]
    pair = table.loc[best, pairs].astype(float).idxmax().removeprefix("peak_")
    each = [f"{k}: unsuitable ({r['reason']})" if r["reason"] else
            f"{k} {number(r['peak'])} {r['unit']}, {number(r['peak_power'])} W"
            for k, r in table.iterrows()]
    return best, (f"{best}: the lowest peak reaction in the pairs, "
                  f"{number(table.loc[best, 'peak_reaction'])} N (in pair {pair}). Peak "
                  f"effort and peak power by place: {'; '.join(each)}.")


def _placeable(mech) -> None:
    """Refuse a linkage whose balancing effort has no places: one driven by time, or
    one without a description to build them from."""
    if mech.rates:
        raise InputError(f"{mech.name} is driven by time (its drivers: "
                         f"{', '.join(d.name for d in mech.drivers)}): each driver applies "
                         "its own effort, so there is no balancing effort to place")
    if mech.description is None:
        raise InputError(f"{mech.name} was built without a description: the places of its "
                         "effort are built from one (build it from a Description)")


def _variant(mech, effort: dict, params: dict):
    """``mech``'s description built with ``params``, its effort ``effort`` (a spec of
    ``[effort]``; empty: the description's own), reporting the effort and each pair's
    load: ``sqrt(Fx**2 + Fy**2)`` of a pin, ``|N|`` of a prismatic pair (the
    description's own outputs left out: they may name an effort the place has not)."""
    d = mech.description.copy()
    if effort:
        d.efforts.clear()
        d.effort(effort["name"], effort["body"], effort.get("at", ""),
                 effort.get("direction"))
    d.outputs.clear()
    for j in mech.joints:  # each pair's load, as the pair reckons it (Magnitude)
        d.output("force", name=f"{REACTION}{j.name}", by=j.a, on=j.b, components=["x"],
                 magnitude=f"{REACTION}{j.name}")
    return d.build(**params)


def _sliders(mech) -> list:
    """``(link, point, t)`` of each link in a prismatic pair with the frame: the pair's
    point and its sliding direction ``t = (n_y, -n_x)``, fixed in the frame."""
    out = []
    for j in mech.joints:
        normal = j.guide(None)  # a guide fixed in the frame: the same at every state
        if normal is not None and mech.frame in (j.a, j.b):
            nx, ny = (float(v) for v in normal)
            out.append((j.b if j.a == mech.frame else j.a, j.point, (ny, -nx)))
    return out


def _generic_name(mech, e) -> str:
    """The place name of the description's one effort ``e``."""
    if e.direction is None:
        return f"moment on {e.body}"
    for slider, _, t in _sliders(mech):
        if slider == e.body and _along(e.direction, t):
            return f"force at {slider}"
    return f"{e.name} on {e.body} at {e.point}"


def _along(u: tuple, t: tuple) -> bool:
    """Whether the unit vectors ``u`` and ``t`` are parallel (either way)."""
    return abs(u[0] * t[1] - u[1] * t[0]) <= PARALLEL


def _effort_speed(m, st) -> np.ndarray:
    """The speed conjugate to the effort of ``m`` per unit crank speed: its link's
    ``dphi/dtheta`` for a moment, the velocity of its link's material point at the
    effort's point along its direction for a force."""
    e = m.effort
    w1 = np.asarray(st.w1[e.body], dtype=float)
    if e.direction is None:
        return w1
    cg = m.cg[e.body]
    (vx, vy), (px, py), (sx, sy) = st.d1[cg], st.p[e.point], st.p[cg]
    tx, ty = e.direction
    return (vx - w1 * (py - sy)) * tx + (vy + w1 * (px - sx)) * ty


def _peak(values: np.ndarray) -> float:
    return float(np.max(np.abs(values)))


def _unsolved(sol, status: np.ndarray) -> str:
    """Why a place has no outputs at some states: how many, the first reason."""
    n, total = int(np.count_nonzero(status != SOLVED)), status.size
    first = min(sol.problems.values(), key=lambda p: p.first)
    how = "singular" if first.reason.kind == "singular" else \
        "locked by friction" if first.reason.kind == "locking" else "not solved"
    at = f"all {total} angles" if n == total else f"{n} of {total} angles"
    return f"{how} at {at}: {first.reason.what or first.reason.text}"


def _ill(sol, theta: np.ndarray) -> str:
    """'' where every state is well conditioned, else where the worst one is."""
    cond = np.asarray(sol["cond"], dtype=float).reshape(-1)
    bad = cond > ILL_CONDITIONED
    if not np.any(bad):
        return ""
    k = int(np.argmax(cond))
    return (f"near-singular at {int(bad.sum())} of {cond.size} angles (cond up to "
            f"{number(cond[k], 2)} at theta = {number(np.degrees(theta[k]), 6)} deg): the "
            "effort is unbounded there, its figures are rounding")


def _angles(theta: Sequence | np.ndarray) -> np.ndarray:
    try:
        out = np.atleast_1d(np.asarray(theta, dtype=float)).reshape(-1)
    except (TypeError, ValueError):
        raise InputError(f"theta must be crank angles in rad (numbers), got {theta!r}") from None
    if out.size == 0 or not np.all(np.isfinite(out)):
        raise InputError("theta must be one or more finite crank angles in rad")
    return out

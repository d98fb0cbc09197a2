"""Adapter that runs ``kinepy`` on the ``four_bar`` and ``slider_crank`` presets of ``linkage_fmu``.

Same contract as the adapters of ``benchmarks/peers.py``: the functions return the output names
of our presets in our conventions (SI units; ``Fij`` is the force **by link i on link j**;
``Mb`` is the motor's moment on the crank, counter-clockwise positive), so a benchmark can
compare run time and error on the same linkage and states.

``kinepy`` (PyPI, pure Python + numpy; checked with 0.1.7)
    Planar mechanisms from solids and joints; the kinematics and the joint actions are solved
    in closed form group by group (Assur groups RRR, RRP, PPR, 2-RR-PP for the actions),
    vectorised with numpy over an array of input samples. It has **no velocity or
    acceleration input**: ``System.solve_dynamics(inputs, t)`` takes a *time history* of the
    piloted joint's angle, ``n`` samples ``dt = t / n`` apart, and gets every inertia force
    from the 3-point central second difference of the sampled positions (``-m (x[k+1] +
    x[k-1] - 2 x[k]) / dt**2``; the first and last samples are NaN). To get our outputs at
    arbitrary crank angles and a given ``omega``, ``alpha``, the adapter feeds it, for each
    angle, the stencil ``theta - omega h + alpha h2/2, theta, theta + omega h + alpha h2/2``
    (all the stencils one after the other in one array) with ``h = step / max(|omega|,
    sqrt|alpha|)``, and keeps the middle samples: the crank's acceleration is then exactly
    ``alpha`` and every other one is exact to O(step**2) (max relative error over a revolution
    <= 6e-7 on the four-bar, <= 1.3e-7 on the slider-crank at the default ``step = 1e-3``
    rad; smaller steps lose more to round-off in kinepy's ``arccos`` positions than they
    gain; near a toggle/assembly limit the error grows, 1e-3 there). ``extrapolate=True``
    runs a second solve at ``2 h`` and combines the two (Richardson, the reactions being
    linear in the accelerations), which removes the O(step**2) term (<= 1e-8), at twice the
    cost. ``omega = alpha = 0`` gives three equal samples: exact
    statics. Mapping:

    * units: kinepy's default unit system has **lengths in mm** (everything else SI) and is a
      module-level global; the adapter switches it to ``kinepy.units.SI`` for the call and
      restores it afterwards;
    * solids: ``Ground`` (created by ``System``), crank, coupler (or connecting rod), rocker
      (or piston); each link's local frame has its origin at our reference joint (A, B, D
      for the four-bar; O, A, B for the slider-crank) and x towards the link's other joint
      (B, C, C; A, B, along the guide), so our centre of mass ``(l, beta)`` is the local
      point ``g = (l cos beta, -l sin beta)``; ``j`` is about the centre of mass (our ``J``);
    * four-bar joints: ``add_revolute(Ground, crank, (0,0), (0,0))`` (A, piloted: its input
      is our theta), ``add_revolute(crank, coupler, (l_AB,0), (0,0))`` (B),
      ``add_revolute(coupler, rocker, (l_BC,0), (l_CD,0))`` (C),
      ``add_revolute(Ground, rocker, (l_AD,0), (0,0))`` (D);
    * slider-crank joints: ``add_revolute(Ground, crank)`` (O, piloted),
      ``add_revolute(crank, rod, (l_OA,0), (0,0))`` (A), ``add_revolute(rod, piston,
      (l_AB,0), (0,0))`` (B), ``add_prismatic(Ground, piston, a1=gamma, d1=e, a2=0, d2=0)``
      (the guide: direction gamma, offset e along its left normal; the piston is a solid of
      mass ``m3``, ``j = 0``, centre of mass at B);
    * gravity: ``add_gravity((0, -g))`` (kinepy's default is 9.8067 m/s2);
    * our ``load``: four-bar ``rocker.add_torque(Mr)``; slider-crank
      ``piston.add_force((-F cos gamma, -F sin gamma), (0, 0))`` (towards the crank);
    * assembly mode: the RRR group's sign (``System.change_signs``) is ``-branch`` for the
      four-bar as built here (its ``+1`` puts C right of B->D); the RRP group's sign is
      ``+1`` for our piston on the +gamma side of the crank. The adapter checks the side of C
      (of B) at every angle and returns NaN where it is not ours;
    * reactions: a ``RevoluteJoint(s1, s2)``'s ``force`` is the force **on s1 by s2** and its
      ``torque`` (piloted joint) the moment on s1 by s2, a ``PrismaticJoint(s1, s2)``'s
      ``normal`` is the force on s1 by s2 along the left normal of the axis, so
      ``F21 = rev_B.force``, ``F32 = rev_C.force``, ``F43 = -rev_D.force``,
      ``F14 = rev_A.force``, ``Mb = -rev_A.torque`` (four-bar) and ``F21 = rev_A.force``,
      ``F32 = rev_B.force``, ``N43 = -prismatic.normal``, ``F14 = rev_O.force``,
      ``Mb = -rev_O.torque`` (slider-crank).

    It represents every parameter of our ``four_bar`` and ``slider_crank`` presets (centre
    of mass anywhere on a link, inertias, gravity, the loads, both four-bar assembly modes,
    guide offset and direction), so :data:`KINEPY_PARAMS` are simply our defaults. What it
    cannot do: take a velocity or an acceleration (only finite differences of a uniformly
    sampled time history, whence the stencil above and its O(step**2) error); report an
    unassemblable position as an error (its ``arccos`` returns NaN with a RuntimeWarning,
    which the adapter silences: those outputs are NaN); solve the joint actions of the
    two-loop groups it can place (3-PR, PP-RR-PR, PP-PR-RP, RR-PR-RP: their dynamic solvers
    are empty stubs in 0.1.7, leaving zero forces without a warning); friction. Its
    ``arccos`` of nearly collinear vectors loses about half the digits of the positions, which
    is what limits the stencil's step.

Examples
--------
>>> import numpy as np, kinepy_peer                                   # doctest: +SKIP
>>> kinepy_peer.kinepy_version()                                      # doctest: +SKIP
'0.1.7'
>>> th = np.linspace(0.0, 2.0 * np.pi, 360, endpoint=False)           # doctest: +SKIP
>>> kinepy_peer.kinepy_four_bar(kinepy_peer.KINEPY_PARAMS, th, 10.0, 0.0, 0.0)["Mb"]  # doctest: +SKIP

Run ``python kinepy_peer.py`` for the verification against ``linkage_fmu``.
"""

from __future__ import annotations

import contextlib
import io
import math
import time
from importlib import metadata

import numpy as np

from linkage_fmu import presets
from peers import relative_errors

#: Parameters of our ``four_bar`` preset for the kinepy comparison: kinepy can represent all
#: of them (gravity, centre of mass anywhere on the link, inertia, a moment on the rocker,
#: both assembly modes), so these are our defaults, spelled out.
KINEPY_PARAMS = {
    "l_AB": 0.10, "l_BC": 0.35, "l_CD": 0.30, "l_AD": 0.40,
    "m1": 1.0, "J1": 0.0, "l_AS1": 0.0, "beta1": 0.0,
    "m2": 2.0, "J_S2": 0.02, "l_BS2": 0.175, "beta2": 0.0,
    "m3": 1.5, "J_S3": 0.012, "l_DS3": 0.15, "beta3": 0.0,
    "g": 9.81, "branch": 1,
}

#: ... and of our ``slider_crank`` preset (all representable: our defaults).
KINEPY_SLIDER_PARAMS = {
    "l_OA": 0.05, "l_AB": 0.20, "e": 0.0, "gamma": 0.0,
    "m1": 0.0, "J1": 0.0, "l_OS1": 0.0,
    "m2": 0.8, "J2": 0.004, "l_AS2": 0.06, "m3": 0.6, "g": 9.81,
}

#: Crank-angle step [rad] of the 3-point stencil fed to kinepy's finite differences
#: (measured on the four-bar: 1e-2 -> 3e-5, 3e-3 -> 3e-6, 1e-3 -> 6e-7, 3e-4 -> 2e-5,
#: 1e-4 -> 2e-4 max relative error; round-off in the positions wins below 1e-3).
KINEPY_STEP = 1e-3
#: The step with ``extrapolate=True`` (the O(step**2) term is removed; larger steps keep
#: the round-off small).
KINEPY_STEP_EXTRAPOLATED = 1e-2


# -- versions ----------------------------------------------------------------------
def kinepy_version() -> str | None:
    """Installed version of ``kinepy``, or None if it is not installed."""
    try:
        return metadata.version("kinepy")
    except metadata.PackageNotFoundError:
        return None


def _parameters(preset: str, params: dict | None = None) -> dict:
    """Our preset's full, validated parameter dict (defaults overridden by ``params``)."""
    return dict(presets.get(preset, **(params or {})).parameters)


@contextlib.contextmanager
def _si_units():
    """kinepy's global unit system set to SI (its default has mm), restored on exit."""
    import kinepy.units as ku

    saved = dict(ku.SYSTEM.dct)
    ku.set_unit_system(ku.SI)
    try:
        yield
    finally:
        ku.SYSTEM.dct.clear()
        ku.SYSTEM.dct.update(saved)


def _stencil(theta, omega, alpha, load, step):
    """Broadcast the inputs; kinepy's input samples (3 per state), the time step and loads."""
    theta, omega, alpha, load = np.broadcast_arrays(*(np.asarray(x, dtype=float)
                                                      for x in (theta, omega, alpha, load)))
    shape = theta.shape
    th, w, a, q = (x.reshape(-1) for x in (theta, omega, alpha, load))
    rate = max(float(np.max(np.abs(w), initial=0.0)),
               math.sqrt(float(np.max(np.abs(a), initial=0.0))))
    h = step / rate if rate > 0.0 else 1.0  # static scene: three equal samples
    d1, d2 = w * h, 0.5 * a * h * h
    samples = np.stack([th - d1 + d2, th, th + d1 + d2], axis=1).reshape(-1)
    return shape, samples, h, np.repeat(q, 3)


@contextlib.contextmanager
def _kinepy_session():
    """SI units, silenced arccos warnings and kinepy's compile-time printing."""
    with _si_units(), np.errstate(invalid="ignore", divide="ignore"), \
            contextlib.redirect_stdout(io.StringIO()):
        yield


def _run(builder, p, theta, omega, alpha, load, step, extrapolate):
    """Stencil, build, solve (twice with Richardson extrapolation), reshape."""
    if step is None:
        step = KINEPY_STEP_EXTRAPOLATED if extrapolate else KINEPY_STEP
    shape, samples, h, q = _stencil(theta, omega, alpha, load, step)
    with _kinepy_session():
        system, pick = builder(p, q, slice(1, None, 3))  # the middle of each stencil
        system.solve_dynamics(samples, t=h * samples.size)  # kinepy: dt = t / n
        out = pick()
        if extrapolate:
            _, samples2, _, _ = _stencil(theta, omega, alpha, load, 2.0 * step)
            system.solve_dynamics(samples2, t=2.0 * h * samples2.size)
            out2 = pick()
            out = {k: (4.0 * out[k] - out2[k]) / 3.0 for k in out}
    return {k: v.reshape(shape) for k, v in out.items()}


def _four_bar_system(p: dict, q: np.ndarray, mid: slice):
    """kinepy model of our four-bar; ``pick()`` reads our outputs at samples ``mid``."""
    import kinepy as kp

    def local_cg(dist: float, beta: float) -> tuple[float, float]:
        return (dist * math.cos(beta), -dist * math.sin(beta))

    s = kp.System()
    ground = s.ground
    crank = s.add_solid("crank", p["m1"], p["J1"], local_cg(p["l_AS1"], p["beta1"]))
    coupler = s.add_solid("coupler", p["m2"], p["J_S2"], local_cg(p["l_BS2"], p["beta2"]))
    rocker = s.add_solid("rocker", p["m3"], p["J_S3"], local_cg(p["l_DS3"], p["beta3"]))
    rev_a = s.add_revolute(ground, crank, (0.0, 0.0), (0.0, 0.0))
    rev_b = s.add_revolute(crank, coupler, (p["l_AB"], 0.0), (0.0, 0.0))
    rev_c = s.add_revolute(coupler, rocker, (p["l_BC"], 0.0), (p["l_CD"], 0.0))
    rev_d = s.add_revolute(ground, rocker, (p["l_AD"], 0.0), (0.0, 0.0))
    if p["g"]:
        s.add_gravity((0.0, -p["g"]))
    if np.any(q != 0.0):
        rocker.add_torque(q)
    s.pilot(rev_a)
    s.compile()
    s.change_signs([-int(p["branch"])])  # its +1 puts C right of B->D

    def pick() -> dict:
        out = {}
        for name, f in (("F21", rev_b.force), ("F32", rev_c.force), ("F43", -rev_d.force),
                        ("F14", rev_a.force)):
            out[name + "x"], out[name + "y"] = f[0, mid].copy(), f[1, mid].copy()
        out["Mb"] = -rev_a.torque[mid]
        # assembly mode: C left of B->D for our branch +1
        b = crank.get_point((p["l_AB"], 0.0))[:, mid]
        c = rocker.get_point((p["l_CD"], 0.0))[:, mid]
        side = (p["l_AD"] - b[0]) * (c[1] - b[1]) + b[1] * (c[0] - b[0])
        bad = ~(side * p["branch"] > 0.0)
        for v in out.values():
            v[bad] = np.nan
        return out

    return s, pick


def _slider_crank_system(p: dict, q: np.ndarray, mid: slice):
    """kinepy model of our slider-crank; ``pick()`` reads our outputs at samples ``mid``."""
    import kinepy as kp

    u = np.array([[math.cos(p["gamma"])], [math.sin(p["gamma"])]])
    s = kp.System()
    ground = s.ground
    crank = s.add_solid("crank", p["m1"], p["J1"], (p["l_OS1"], 0.0))
    rod = s.add_solid("rod", p["m2"], p["J2"], (p["l_AS2"], 0.0))
    piston = s.add_solid("piston", p["m3"], 0.0, (0.0, 0.0))
    rev_o = s.add_revolute(ground, crank, (0.0, 0.0), (0.0, 0.0))
    rev_a = s.add_revolute(crank, rod, (p["l_OA"], 0.0), (0.0, 0.0))
    rev_b = s.add_revolute(rod, piston, (p["l_AB"], 0.0), (0.0, 0.0))
    guide = s.add_prismatic(ground, piston, p["gamma"], p["e"], 0.0, 0.0)
    if p["g"]:
        s.add_gravity((0.0, -p["g"]))
    if np.any(q != 0.0):
        piston.add_force(-u * q, (0.0, 0.0))  # (2, n): along the guide, towards the crank
    s.pilot(rev_o)
    s.compile()
    s.change_signs([1])  # piston on the +gamma side of the crank

    def pick() -> dict:
        out = {}
        for name, f in (("F21", rev_a.force), ("F32", rev_b.force)):
            out[name + "x"], out[name + "y"] = f[0, mid].copy(), f[1, mid].copy()
        out["N43"] = -guide.normal[mid]
        out["F14x"], out["F14y"] = rev_o.force[0, mid].copy(), rev_o.force[1, mid].copy()
        out["Mb"] = -rev_o.torque[mid]
        a = crank.get_point((p["l_OA"], 0.0))[:, mid]
        b = piston.get_point((0.0, 0.0))[:, mid]
        bad = ~(np.sum((b - a) * u, axis=0) > 0.0)
        for v in out.values():
            v[bad] = np.nan
        return out

    return s, pick


_SYSTEMS = {"four_bar": _four_bar_system, "slider_crank": _slider_crank_system}


# -- kinepy ------------------------------------------------------------------------
def kinepy_four_bar(params: dict, theta: np.ndarray, omega: float, alpha: float,
                    load: float, *, step: float | None = None,
                    extrapolate: bool = False) -> dict[str, np.ndarray]:
    """Our ``four_bar`` outputs computed by ``kinepy``, all angles in one vectorised solve.

    Parameters
    ----------
    params : dict
        Parameters of our ``four_bar`` preset (missing ones take our defaults), e.g.
        :data:`KINEPY_PARAMS`.
    theta : ndarray
        Crank angles [rad], any shape.
    omega, alpha : float or ndarray
        Crank speed [rad/s] and acceleration [rad/s2] (broadcast with ``theta``).
    load : float or ndarray
        Moment Mr on the rocker [N.m], counter-clockwise positive.
    step : float, optional
        Crank-angle step [rad] of the finite-difference stencil (default
        :data:`KINEPY_STEP`, or :data:`KINEPY_STEP_EXTRAPOLATED` with ``extrapolate``).
    extrapolate : bool
        Second solve at twice the step and Richardson extrapolation.

    Returns
    -------
    dict of str to ndarray
        ``F21x, F21y, F32x, F32y, F43x, F43y, F14x, F14y, Mb`` with the broadcast shape of
        the inputs (NaN where the linkage cannot be assembled).
    """
    p = _parameters("four_bar", params)
    out = _run(_four_bar_system, p, theta, omega, alpha, load, step, extrapolate)
    return {k: out[k] for k in presets.get("four_bar").output_names if k in out}


def kinepy_slider_crank(params: dict, theta: np.ndarray, omega: float, alpha: float,
                        load: float, *, step: float | None = None,
                        extrapolate: bool = False) -> dict[str, np.ndarray]:
    """Our ``slider_crank`` outputs computed by ``kinepy``, all angles in one solve.

    Parameters
    ----------
    params : dict
        Parameters of our ``slider_crank`` preset (missing ones take our defaults), e.g.
        :data:`KINEPY_SLIDER_PARAMS`.
    theta : ndarray
        Crank angles [rad], any shape.
    omega, alpha : float or ndarray
        Crank speed [rad/s] and acceleration [rad/s2].
    load : float or ndarray
        Force on the piston along the guide, towards the crank [N].
    step, extrapolate
        As in :func:`kinepy_four_bar`.

    Returns
    -------
    dict of str to ndarray
        ``F21x, F21y, F32x, F32y, N43, F14x, F14y, Mb`` (NaN where it cannot be assembled).
    """
    p = _parameters("slider_crank", params)
    out = _run(_slider_crank_system, p, theta, omega, alpha, load, step, extrapolate)
    return {k: out[k] for k in presets.get("slider_crank").output_names if k in out}


def kinepy_history(preset: str, params: dict, theta: np.ndarray, dt: float,
                   load: float = 0.0) -> dict[str, np.ndarray]:
    """kinepy as its authors use it: one time history of the crank angle, no stencil.

    ``theta[k]`` is the crank angle at time ``k * dt``; speeds and accelerations are kinepy's
    central differences of neighbouring samples, so the first and last outputs are NaN and
    the others carry an O(dt**2) error (for a constant speed, about ``(omega dt)**2 / 12``
    relative).

    Parameters
    ----------
    preset : {'four_bar', 'slider_crank'}
    params : dict
        Parameters of that preset (missing ones take our defaults).
    theta : ndarray
        Crank angles [rad], 1-D, equally spaced in time.
    dt : float
        Time between samples [s].
    load : float or ndarray
        Our preset's load.

    Returns
    -------
    dict of str to ndarray
        Our preset's outputs at every sample.
    """
    p = _parameters(preset, params)
    th = np.array(theta, dtype=float).reshape(-1)
    q = np.broadcast_to(np.asarray(load, dtype=float), th.shape)
    with _kinepy_session():
        system, pick = _SYSTEMS[preset](p, q, slice(None))
        system.solve_dynamics(th, t=dt * th.size)
        out = pick()
    return {k: out[k] for k in presets.get(preset).output_names if k in out}


# -- verification ------------------------------------------------------------------
def _best(f, repeat: int = 5) -> float:
    """Best of ``repeat`` wall times of ``f()`` [s]."""
    best = math.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        f()
        best = min(best, time.perf_counter() - t0)
    return best


def _main() -> None:
    import os

    print(f"kinepy {kinepy_version()}, numpy {np.__version__}, on {os.cpu_count()} CPUs")
    theta = np.linspace(0.0, 2.0 * math.pi, 360, endpoint=False)
    cases = [
        ("four_bar", kinepy_four_bar, KINEPY_PARAMS, "defaults", 10.0, 0.0, 0.0),
        ("four_bar", kinepy_four_bar, KINEPY_PARAMS, "defaults, Mr 3", 10.0, 0.0, 3.0),
        ("four_bar", kinepy_four_bar, KINEPY_PARAMS, "defaults, alpha 25, Mr 3", 10.0, 25.0,
         3.0),
        ("four_bar", kinepy_four_bar,
         dict(KINEPY_PARAMS, l_AS1=0.03, beta1=0.4, J1=0.001, beta2=-0.3, beta3=0.5,
              branch=-1), "CG off axis, J1, branch -1, alpha 25, Mr 3", -7.0, 25.0, 3.0),
        ("four_bar", kinepy_four_bar, KINEPY_PARAMS, "static (omega = alpha = 0), Mr 3", 0.0,
         0.0, 3.0),
        ("slider_crank", kinepy_slider_crank, KINEPY_SLIDER_PARAMS, "defaults", 10.0, 0.0,
         0.0),
        ("slider_crank", kinepy_slider_crank, KINEPY_SLIDER_PARAMS, "defaults, F 50", 10.0,
         0.0, 50.0),
        ("slider_crank", kinepy_slider_crank, KINEPY_SLIDER_PARAMS, "alpha 25, F 50", 10.0,
         25.0, 50.0),
        ("slider_crank", kinepy_slider_crank,
         dict(KINEPY_SLIDER_PARAMS, e=0.02, gamma=0.5, m1=0.3, J1=1e-4, l_OS1=0.01),
         "e 0.02, gamma 0.5, crank mass, alpha 25, F 50", -7.0, 25.0, 50.0),
    ]
    kinepy_four_bar(KINEPY_PARAMS, theta[:2], 10.0, 0.0, 0.0)  # imports
    for preset, fn, params, label, w, a, load in cases:
        ours = presets.get(preset, **params).solve(theta, w, a, load=load)
        for extra in (False, True):
            err = relative_errors(ours, fn(params, theta, w, a, load, extrapolate=extra))
            worst = max(err, key=lambda k: (np.nan_to_num(err[k], nan=np.inf)))
            print(f"{preset:12s} [{label}]{' richardson' if extra else ''}: max rel err "
                  f"{err[worst]:.1e} ({worst}); " + " ".join(f"{k} {v:.1e}"
                                                            for k, v in err.items()))

    # native use: one uniformly sampled revolution, no stencil (end samples are NaN)
    n = 360
    dth = 2.0 * math.pi / n
    th = dth * np.arange(-1, n + 1)  # 0 .. 2 pi (exclusive) plus one sample either side
    for preset, params, load in (("four_bar", KINEPY_PARAMS, 3.0),
                                 ("slider_crank", KINEPY_SLIDER_PARAMS, 50.0)):
        ours = presets.get(preset, **params).solve(th[1:-1], 10.0, 0.0, load=load)
        native = kinepy_history(preset, params, th, dth / 10.0, load)
        err = relative_errors(ours, {k: v[1:-1] for k, v in native.items()})
        worst = max(err, key=err.get)
        print(f"{preset:12s} [history: {n + 2} samples 1 deg apart at omega 10, Mr/F "
              f"{load:g}]: max rel err {err[worst]:.1e} ({worst}); "
              + " ".join(f"{k} {v:.1e}" for k, v in err.items()))

    # timings, best of 5, same run
    print("timings, best of 5 [us/angle]:")
    for preset, fn, params, load in (("four_bar", kinepy_four_bar, KINEPY_PARAMS, 3.0),
                                     ("slider_crank", kinepy_slider_crank,
                                      KINEPY_SLIDER_PARAMS, 50.0)):
        mech = presets.get(preset, **params)
        for n in (360, 100_000):
            th = np.linspace(0.0, 2.0 * math.pi, n, endpoint=False)
            t_k = _best(lambda: fn(params, th, 10.0, 0.0, load))
            t_kr = _best(lambda: fn(params, th, 10.0, 0.0, load, extrapolate=True))
            t_o = _best(lambda: mech.solve(th, 10.0, 0.0, load=load))
            line = (f"  {preset:12s} n={n:6d}: kinepy {1e6 * t_k / n:9.2f}, kinepy+richardson "
                    f"{1e6 * t_kr / n:9.2f}, linkage_fmu vector {1e6 * t_o / n:7.3f}")
            if n == 360:
                ths = [float(x) for x in th]
                mech.solve(ths[0], 10.0, 0.0, load=load)  # kernel build / warm-up
                t_s = _best(lambda: [mech.solve(x, 10.0, 0.0, load=load) for x in ths])
                line += f", linkage_fmu scalar loop {1e6 * t_s / n:7.2f}"
            print(line)
        # kinepy's own solve alone (model built and compiled once, stencil ready)
        p = _parameters(preset, params)
        for n in (360, 100_000):
            th = np.linspace(0.0, 2.0 * math.pi, n, endpoint=False)
            _, samples, h, q = _stencil(th, 10.0, 0.0, load, KINEPY_STEP)
            with _kinepy_session():
                system, pick = _SYSTEMS[preset](p, q, slice(1, None, 3))
                t_s = _best(lambda: (system.solve_dynamics(samples, t=h * samples.size),
                                     pick()))
            print(f"  {preset:12s} n={n:6d}: kinepy solve_dynamics + read only "
                  f"{1e6 * t_s / n:9.2f}")
        t_b = _best(lambda: fn(params, theta[:1], 10.0, 0.0, load))
        print(f"  {preset:12s} kinepy one call with 1 angle (build + compile + solve): "
              f"{1e3 * t_b:.2f} ms")


if __name__ == "__main__":
    _main()

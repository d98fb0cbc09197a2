"""Adapters that run two peer libraries on the presets of ``linkage_fmu``.

Both adapters return the output names of our presets in our conventions (SI units; ``Fij``
is the force **by link i on link j**; ``Mb`` is the motor's moment on the crank,
counter-clockwise positive), so a benchmark can compare run time and error on the same
linkage and states.

``fourbarhinge`` (PyPI, pure Python)
    Kinetostatics of one four-bar state per call (Newton-Euler, 9x9 linear system). It has
    no vectorised entry point, so :func:`fourbarhinge_four_bar` loops over the angles.
    Mapping (its ``BarId``: GROUND 0, INPUT 1, COUPLER 2, OUTPUT 3 = our frame 4, crank 1,
    coupler 2, rocker 3; its joints A, B, C, D are ours):

    * frame: ``position_ground = (0, 0)``, ``theta_ground = 0`` (D on +x); its input,
      coupler and output angles are our theta, angle of B->C and angle of D->C;
    * a bar's local frame has its origin at A, B or D and x towards B, C or C, so our centre
      of mass ``(l, beta)`` is the local point ``(l cos beta, -l sin beta)``;
    * ``inertia`` is about the centre of mass (our ``J``); gravity ``(0, -g)``;
    * our ``load`` Mr is an ``ExternalForce`` on OUTPUT with ``torque = Mr``;
    * its ``branch`` is the sign of the acos term measured from the line D->B, so
      ``branch_fbh = -branch`` (our +1 puts C left of B->D);
    * the effort is ``Actuator(bar=INPUT)`` (pure torque), its value is our ``Mb``;
    * reactions: ``R_A`` = ground on INPUT, ``R_B`` = INPUT on COUPLER, ``R_C`` = COUPLER on
      OUTPUT, ``R_D`` = ground on OUTPUT, hence ``F14 = -R_A``, ``F21 = -R_B``,
      ``F32 = -R_C``, ``F43 = R_D``.

    It represents every parameter of our ``four_bar`` preset; :data:`FOURBARHINGE_PARAMS`
    is therefore simply our defaults.  What it cannot do: positions that cannot be
    assembled (it clips ``acos`` and returns a false, silently mirrored/closed position
    without error - the adapter checks the closure error and returns NaN there).

``exudyn`` (PyPI, C++ multibody code)
    :func:`exudyn_run` builds the ``four_bar`` or ``slider_crank`` preset (our default
    parameters) as a planar multibody model: ``RigidBody2D`` links with their nodes at the
    centres of mass, ``RevoluteJoint2D`` pins, the piston a ``MassPoint2D`` held on its
    guide by a coordinate constraint, gravity as a force at each centre of mass, and the
    crank speed prescribed by a velocity-level ``CoordinateConstraint`` on the crank angle
    (exact for the trapezoidal rule: the crank angle stays ``omega * t`` to round-off). It
    integrates one revolution with ``TrapezoidalIndex2`` (implicit, second order) and reads
    the Lagrange multipliers of the joints through sensors at every step. Only the
    ``four_bar`` and ``slider_crank`` presets with our default parameters (``gamma = 0``).

Examples
--------
>>> from benchmarks import peers                                      # doctest: +SKIP
>>> peers.available()                                                 # doctest: +SKIP
{'fourbarhinge': '0.1.2', 'exudyn': '1.13.6'}

Run ``python benchmarks/peers.py`` for the verification against ``linkage_fmu``.
"""

from __future__ import annotations

import math
import time
from importlib import metadata

import numpy as np

from linkage_fmu import presets

#: Parameters of our ``four_bar`` preset for the fourbarhinge comparison. fourbarhinge can
#: represent all of them (gravity, centre of mass anywhere on the link, inertia, a moment on
#: the rocker, both assembly modes), so these are our defaults, spelled out.
FOURBARHINGE_PARAMS = {
    "l_AB": 0.10, "l_BC": 0.35, "l_CD": 0.30, "l_AD": 0.40,
    "m1": 1.0, "J1": 0.0, "l_AS1": 0.0, "beta1": 0.0,
    "m2": 2.0, "J_S2": 0.02, "l_BS2": 0.175, "beta2": 0.0,
    "m3": 1.5, "J_S3": 0.012, "l_DS3": 0.15, "beta3": 0.0,
    "g": 9.81, "branch": 1,
}

#: Newton tolerances of :func:`exudyn_run` (exudyn's default relative 1e-8 stalls the error
#: at about 1e-4 beyond ~20000 steps per revolution of the four-bar).
EXUDYN_NEWTON_RELTOL = 1e-10
EXUDYN_NEWTON_ABSTOL = 1e-12


# -- versions ----------------------------------------------------------------------
def _version(dist: str) -> str | None:
    try:
        return metadata.version(dist)
    except metadata.PackageNotFoundError:
        return None


def fourbarhinge_version() -> str | None:
    """Installed version of ``fourbarhinge``, or None if it is not installed."""
    return _version("fourbarhinge")


def exudyn_version() -> str | None:
    """Installed version of ``exudyn``, or None if it is not installed."""
    return _version("exudyn")


def available() -> dict[str, str | None]:
    """Each peer's installed version, or None where it is missing.

    Returns
    -------
    dict
        ``{"fourbarhinge": version or None, "exudyn": version or None}``.
    """
    return {"fourbarhinge": fourbarhinge_version(), "exudyn": exudyn_version()}


def _parameters(preset: str, params: dict | None = None) -> dict:
    """Our preset's full, validated parameter dict (defaults overridden by ``params``)."""
    return dict(presets.get(preset, **(params or {})).parameters)


# -- fourbarhinge ------------------------------------------------------------------
def fourbarhinge_four_bar(params: dict, theta: np.ndarray, omega: float, alpha: float,
                          load: float) -> dict[str, np.ndarray]:
    """Our ``four_bar`` outputs computed by ``fourbarhinge``, one state at a time.

    Parameters
    ----------
    params : dict
        Parameters of our ``four_bar`` preset (missing ones take our defaults), e.g.
        :data:`FOURBARHINGE_PARAMS`.
    theta : ndarray
        Crank angles [rad], any shape.
    omega, alpha : float
        Crank speed [rad/s] and acceleration [rad/s2].
    load : float
        Moment Mr on the rocker [N.m], counter-clockwise positive.

    Returns
    -------
    dict of str to ndarray
        ``F21x, F21y, F32x, F32y, F43x, F43y, F14x, F14y, Mb`` with the shape of ``theta``
        (NaN where fourbarhinge's position does not close, i.e. cannot be assembled).
    """
    from fourbarhinge import (
        Actuator,
        Bar,
        BarId,
        ExternalForce,
        FourBarDynamics,
        FourBarGeometry,
        FourBarKinematics,
        FourBarReactions,
        Point,
    )

    p = _parameters("four_bar", params)

    def bar(length: float, mass: float = 0.0, inertia: float = 0.0, dist: float = 0.0,
            beta: float = 0.0) -> Bar:
        # our centre of mass: at `dist` from the bar's first joint, direction angle - beta
        return Bar(length=length, mass=mass, inertia=inertia,
                   center_of_mass=Point(x=dist * math.cos(beta), y=-dist * math.sin(beta)))

    geometry = FourBarGeometry(
        position_ground=Point(x=0.0, y=0.0),
        bar={BarId.GROUND: bar(p["l_AD"]),
             BarId.INPUT: bar(p["l_AB"], p["m1"], p["J1"], p["l_AS1"], p["beta1"]),
             BarId.COUPLER: bar(p["l_BC"], p["m2"], p["J_S2"], p["l_BS2"], p["beta2"]),
             BarId.OUTPUT: bar(p["l_CD"], p["m3"], p["J_S3"], p["l_DS3"], p["beta3"])})
    kin = FourBarKinematics(geometry, theta_ground=0.0)
    rocker_moment = ExternalForce(bar=BarId.OUTPUT, point=Point(x=0.0, y=0.0),
                                  torque=float(load))
    dyn = FourBarDynamics(kin, external_forces=[rocker_moment], gravity=(0.0, -p["g"]))
    reactions = FourBarReactions(dyn)
    motor = Actuator(bar=BarId.INPUT)  # pure torque on the crank
    branch = -int(p["branch"])
    tol = 1e-9 * max(p["l_AB"], p["l_BC"], p["l_CD"], p["l_AD"])

    theta = np.asarray(theta, dtype=float)
    flat = theta.reshape(-1)
    out = np.full((flat.size, 9), np.nan)
    for k, th in enumerate(flat):
        kin.solve_configuration(float(th), branch=branch)
        if kin.get_closure_error() > tol:
            continue  # not assemblable: fourbarhinge clipped acos
        try:
            kin.solve_theta_dot(float(omega))
            kin.solve_theta_ddot(float(alpha))
            res = reactions.solve(motor)
        except (RuntimeError, np.linalg.LinAlgError):
            continue  # singular (toggle) position
        r = res.reactions
        out[k] = (-r["B"][0], -r["B"][1], -r["C"][0], -r["C"][1], r["D"][0], r["D"][1],
                  -r["A"][0], -r["A"][1], res.actuator_value)
    # the order of the columns above: the source documents' outputs (the shaking ones are not)
    names = [n for n in presets.get("four_bar").output_names if not n.startswith(("shake_", "Mf_", "Ff_"))
             and n not in ("P_loss", "eta")]
    return {name: out[:, i].reshape(theta.shape) for i, name in enumerate(names)}


# -- exudyn ------------------------------------------------------------------------
def _rot(phi: float, v: np.ndarray) -> np.ndarray:
    """``v`` rotated counter-clockwise by ``phi``."""
    c, s = math.cos(phi), math.sin(phi)
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])


def _cross(w: float, r: np.ndarray) -> np.ndarray:
    """Velocity ``w k x r`` of a point at ``r`` from the pivot of a link turning at ``w``."""
    return np.array([-w * r[1], w * r[0]])


def _four_bar_start(p: dict, theta: float, omega: float) -> dict:
    """Positions, link angles and velocities of the four-bar at ``theta``.

    Own closed form, independent of linkage_fmu: joints ``A, B, C, D -> (x, y)`` and
    links ``'1', '2', '3' -> (S, phi, v_S, w)`` (centre of mass, link angle, their rates).
    """
    a, b, c = p["l_AB"], p["l_BC"], p["l_CD"]
    A, D = np.zeros(2), np.array([p["l_AD"], 0.0])
    B = a * np.array([math.cos(theta), math.sin(theta)])
    vB = _cross(omega, B)
    dv = D - B
    d2 = float(dv @ dv)
    hd2 = ((b + c) ** 2 - d2) * (d2 - (b - c) ** 2)
    if hd2 < 0.0:
        raise ValueError(f"four_bar cannot be assembled at theta = {theta}")
    f = (b * b - c * c + d2) / (2.0 * d2)
    h = p["branch"] * math.sqrt(hd2) / (2.0 * d2)
    C = B + f * dv + h * np.array([-dv[1], dv[0]])  # branch +1: C left of B->D
    phi2 = math.atan2(C[1] - B[1], C[0] - B[0])
    phi3 = math.atan2(C[1] - D[1], C[0] - D[0])
    # vB + w2 k x (C - B) = w3 k x (C - D)
    M = np.column_stack([_cross(1.0, C - B), -_cross(1.0, C - D)])
    w2, w3 = np.linalg.solve(M, -vB)
    S1 = A + _rot(theta - p["beta1"], np.array([p["l_AS1"], 0.0]))
    S2 = B + _rot(phi2 - p["beta2"], np.array([p["l_BS2"], 0.0]))
    S3 = D + _rot(phi3 - p["beta3"], np.array([p["l_DS3"], 0.0]))
    return {"A": A, "B": B, "C": C, "D": D,
            "1": (S1, theta, _cross(omega, S1 - A), omega),
            "2": (S2, phi2, vB + _cross(w2, S2 - B), w2),
            "3": (S3, phi3, _cross(w3, S3 - D), w3)}


def _slider_crank_start(p: dict, theta: float, omega: float) -> dict:
    """Positions and velocities of the slider-crank (guide along +x, offset e) at ``theta``.

    Same layout as :func:`_four_bar_start`; link ``'3'`` is the piston at B.
    """
    if p["gamma"] != 0.0:
        raise NotImplementedError("exudyn model: only a guide along +x (gamma = 0)")
    r, L, e = p["l_OA"], p["l_AB"], p["e"]
    pivot = np.zeros(2)
    A = r * np.array([math.cos(theta), math.sin(theta)])
    vA = _cross(omega, A)
    dy = e - A[1]
    if abs(dy) > L:
        raise ValueError(f"slider_crank cannot be assembled at theta = {theta}")
    B = np.array([A[0] + math.sqrt(L * L - dy * dy), e])
    phi2 = math.atan2(B[1] - A[1], B[0] - A[0])
    w2 = -vA[1] / (B[0] - A[0])  # vB_y = 0
    vB = vA + _cross(w2, B - A)
    S1 = pivot + _rot(theta, np.array([p["l_OS1"], 0.0]))
    S2 = A + _rot(phi2, np.array([p["l_AS2"], 0.0]))
    return {"O": pivot, "A": A, "B": B,
            "1": (S1, theta, _cross(omega, S1 - pivot), omega),
            "2": (S2, phi2, vA + _cross(w2, S2 - A), w2),
            "3": (B, 0.0, vB, 0.0)}


def exudyn_run(preset: str, steps_per_rev: int, omega: float = 10.0,
               load: float = 0.0) -> tuple[np.ndarray, dict[str, np.ndarray], dict]:
    """Simulate one crank revolution of a preset in exudyn at constant ``omega``.

    The crank starts at theta = 0 and is driven exactly: a ``CoordinateConstraint`` on its
    angle coordinate prescribes the speed ``omega`` (velocity level; the trapezoidal rule
    integrates a constant speed exactly, so the crank angle is ``omega * t`` to round-off,
    reported as ``crank_drift_rad``). The other links start with consistent positions and
    velocities. Solver: exudyn's ``TrapezoidalIndex2`` (implicit Newmark trapezoidal rule,
    constraints reduced to index 2), ``steps_per_rev`` constant steps, Newton tolerances
    :data:`EXUDYN_NEWTON_RELTOL`, :data:`EXUDYN_NEWTON_ABSTOL`.

    Parameters
    ----------
    preset : {'four_bar', 'slider_crank'}
        Our preset, with its default parameters (g = 9.81 along -y).
    steps_per_rev : int
        Number of time steps for one revolution (>= 1).
    omega : float
        Crank speed [rad/s], nonzero.
    load : float
        Our preset's load: Mr on the rocker [N.m] or the piston force towards the crank [N].

    Returns
    -------
    theta : ndarray
        Crank angles of the ``steps_per_rev + 1`` samples, read from the crank's node: 0
        (the initial state, whose reactions come from exudyn's initial-acceleration solve)
        and the end of every step, up to ``2*pi*sign(omega)``.
    outputs : dict of str to ndarray
        Our preset's outputs at those angles (compare with
        ``presets.get(preset).solve(theta, omega, 0.0, load)``).
    timings : dict
        ``setup_s`` (building and assembling the model), ``solve_s`` (``SolveDynamic``),
        ``post_s`` (reading the sensors, converting), and ``crank_drift_rad`` (max deviation
        of the simulated crank angle from ``omega * t``).
    """
    import exudyn as exu
    from exudyn import itemInterface as ei

    if preset not in ("four_bar", "slider_crank"):
        raise ValueError(f"exudyn_run: no model for preset {preset!r}")
    omega = float(omega)
    steps = int(steps_per_rev)
    if omega == 0.0 or steps < 1:
        raise ValueError("exudyn_run needs omega != 0 and steps_per_rev >= 1")

    t0 = time.perf_counter()
    p = _parameters(preset)
    g = p["g"]
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    ground = mbs.AddObject(ei.ObjectGround(referencePosition=[0.0, 0.0, 0.0]))
    ground_node = mbs.AddNode(ei.NodePointGround(referenceCoordinates=[0.0, 0.0, 0.0]))
    ground_coord = mbs.AddMarker(ei.MarkerNodeCoordinate(nodeNumber=ground_node, coordinate=0))

    if preset == "four_bar":
        start = _four_bar_start(p, 0.0, omega)
        inertia = {"1": (p["m1"], p["J1"]), "2": (p["m2"], p["J_S2"]),
                   "3": (p["m3"], p["J_S3"])}
        ends = {"1": ("A", "B"), "2": ("B", "C"), "3": ("D", "C")}
    else:
        start = _slider_crank_start(p, 0.0, omega)
        inertia = {"1": (p["m1"], p["J1"]), "2": (p["m2"], p["J2"])}
        ends = {"1": ("O", "A"), "2": ("A", "B")}

    # links: node at the centre of mass, reference angle = link angle at theta = 0, so the
    # crank's angle coordinate (a displacement from its reference 0) is theta itself
    nodes, bodies, pins = {}, {}, {}
    for name, (mass, J) in inertia.items():
        S, phi, vS, w = start[name]
        nodes[name] = mbs.AddNode(ei.NodeRigidBody2D(
            referenceCoordinates=[S[0], S[1], phi], initialVelocities=[vS[0], vS[1], w]))
        bodies[name] = mbs.AddObject(ei.ObjectRigidBody2D(mass=mass, inertia=J,
                                                          nodeNumber=nodes[name]))
        for pt in ends[name]:  # joint markers in the body frame (origin S, x along link)
            local = _rot(-phi, start[pt] - S)
            pins[name, pt] = mbs.AddMarker(ei.MarkerBodyPosition(
                bodyNumber=bodies[name], localPosition=[local[0], local[1], 0.0]))
        if mass and g:
            cg = mbs.AddMarker(ei.MarkerBodyPosition(bodyNumber=bodies[name],
                                                     localPosition=[0.0, 0.0, 0.0]))
            mbs.AddLoad(ei.LoadForceVector(markerNumber=cg, loadVector=[0.0, -mass * g, 0.0]))

    def frame_pin(pt: str) -> int:
        return mbs.AddMarker(ei.MarkerBodyPosition(
            bodyNumber=ground, localPosition=[start[pt][0], start[pt][1], 0.0]))

    # In exudyn's DYNAMIC solvers the output Force of RevoluteJoint2D([m0, m1]) is the force
    # on the marker-0 body by the marker-1 body, and that of CoordinateConstraint([m0, m1])
    # is minus the generalized force on the marker-1 coordinate (the static solver reports
    # the opposite signs). Keys below name what Force is in our notation.
    joints = {}
    if preset == "four_bar":
        joints["F14"] = (frame_pin("A"), pins["1", "A"])
        joints["F21"] = (pins["1", "B"], pins["2", "B"])
        joints["F32"] = (pins["2", "C"], pins["3", "C"])
        joints["F34"] = (frame_pin("D"), pins["3", "D"])
        if load:
            rocker = mbs.AddMarker(ei.MarkerBodyRigid(bodyNumber=bodies["3"]))
            mbs.AddLoad(ei.LoadTorqueVector(markerNumber=rocker,
                                            loadVector=[0.0, 0.0, float(load)]))
    else:  # piston: a mass point at B; guide along +x at y = e (gamma = 0)
        B, _, vB, _ = start["3"]
        piston_node = mbs.AddNode(ei.NodePoint2D(referenceCoordinates=[B[0], B[1]],
                                                 initialVelocities=[vB[0], vB[1]]))
        piston = mbs.AddObject(ei.ObjectMassPoint2D(mass=p["m3"], nodeNumber=piston_node))
        piston_pin = mbs.AddMarker(ei.MarkerBodyPosition(bodyNumber=piston,
                                                         localPosition=[0.0, 0.0, 0.0]))
        if p["m3"] and g:
            mbs.AddLoad(ei.LoadForceVector(markerNumber=piston_pin,
                                           loadVector=[0.0, -p["m3"] * g, 0.0]))
        if load:  # along the guide, towards the crank (-x)
            mbs.AddLoad(ei.LoadForceVector(markerNumber=piston_pin,
                                           loadVector=[-float(load), 0.0, 0.0]))
        joints["F14"] = (frame_pin("O"), pins["1", "O"])
        joints["F21"] = (pins["1", "A"], pins["2", "A"])
        joints["F32"] = (pins["2", "B"], piston_pin)
    objects = {k: mbs.AddObject(ei.RevoluteJoint2D(markerNumbers=list(m)))
               for k, m in joints.items()}
    if preset == "slider_crank":  # piston y displacement = 0; Force = -N43
        piston_y = mbs.AddMarker(ei.MarkerNodeCoordinate(nodeNumber=piston_node, coordinate=1))
        objects["-N43"] = mbs.AddObject(ei.CoordinateConstraint(
            markerNumbers=[ground_coord, piston_y]))
    # motor: crank angle rate = omega (index-2 solvers use only the velocity-level offset,
    # so a position-level offsetUserFunction omega*t would be ignored; this form needs no
    # Python callback); Force = -Mb
    crank_angle = mbs.AddMarker(ei.MarkerNodeCoordinate(nodeNumber=nodes["1"], coordinate=2))
    objects["-Mb"] = mbs.AddObject(ei.CoordinateConstraint(
        markerNumbers=[ground_coord, crank_angle], velocityLevel=True, offset=omega))

    sensors = {k: mbs.AddSensor(ei.SensorObject(
        objectNumber=o, storeInternal=True, writeToFile=False,
        outputVariableType=exu.OutputVariableType.Force)) for k, o in objects.items()}
    crank_sensor = mbs.AddSensor(ei.SensorNode(
        nodeNumber=nodes["1"], storeInternal=True, writeToFile=False,
        outputVariableType=exu.OutputVariableType.Coordinates))
    mbs.Assemble()

    period = 2.0 * math.pi / abs(omega)
    ss = exu.SimulationSettings()
    ti = ss.timeIntegration
    ti.numberOfSteps = steps
    ti.endTime = period
    ti.verboseMode = 0
    ti.solverType = exu.DynamicSolverType.TrapezoidalIndex2
    ti.generalizedAlpha.computeInitialAccelerations = True
    ti.newton.relativeTolerance = EXUDYN_NEWTON_RELTOL
    ti.newton.absoluteTolerance = EXUDYN_NEWTON_ABSTOL
    ss.solution.file.write = False
    ss.solution.sensors.writePeriod = 0.5 * period / steps  # record every step
    ss.show.computationTime = False
    ss.show.statistics = False
    t1 = time.perf_counter()
    ok = mbs.SolveDynamic(ss)
    t2 = time.perf_counter()
    if not ok:
        raise RuntimeError(f"exudyn: SolveDynamic failed ({preset}, {steps} steps)")

    F = {k: np.asarray(mbs.GetSensorStoredData(s)) for k, s in sensors.items()}
    crank = np.asarray(mbs.GetSensorStoredData(crank_sensor))  # t, x, y, phi
    if crank.shape[0] != steps + 1:
        raise RuntimeError(f"exudyn: expected {steps + 1} samples, got {crank.shape[0]}")
    theta = np.ascontiguousarray(crank[:, 3])
    out = {
        "F21x": F["F21"][:, 1], "F21y": F["F21"][:, 2],
        "F32x": F["F32"][:, 1], "F32y": F["F32"][:, 2],
        "F14x": F["F14"][:, 1], "F14y": F["F14"][:, 2],
        "Mb": -F["-Mb"][:, 1],
    }
    if preset == "four_bar":
        out["F43x"], out["F43y"] = -F["F34"][:, 1], -F["F34"][:, 2]
    else:
        out["N43"] = -F["-N43"][:, 1]
    out = {k: np.ascontiguousarray(out[k]) for k in presets.get(preset).output_names
           if k in out}
    drift = float(np.max(np.abs(theta - omega * crank[:, 0])))
    t3 = time.perf_counter()
    return theta, out, {"setup_s": t1 - t0, "solve_s": t2 - t1, "post_s": t3 - t2,
                        "crank_drift_rad": drift}


# -- verification ------------------------------------------------------------------
def relative_errors(reference: dict, other: dict) -> dict[str, float]:
    """Max abs difference / max abs reference value of each output of ``other``."""
    out = {}
    for k, v in other.items():
        ref = np.asarray(reference[k], dtype=float)
        scale = float(np.max(np.abs(ref)))
        diff = float(np.max(np.abs(np.asarray(v, dtype=float) - ref)))
        out[k] = diff / scale if scale else diff
    return out


def _main() -> None:
    import os

    print("peers:", available(), f"on {os.cpu_count()} CPUs")
    if fourbarhinge_version():
        theta = np.linspace(0.0, 2.0 * math.pi, 360, endpoint=False)
        fourbarhinge_four_bar(FOURBARHINGE_PARAMS, theta[:2], 10.0, 0.0, 0.0)  # imports
        cases = [("defaults, omega 10", FOURBARHINGE_PARAMS, 10.0, 0.0, 0.0),
                 ("CG off axis, J1, branch -1, omega -7, alpha 25, Mr 3",
                  dict(FOURBARHINGE_PARAMS, l_AS1=0.03, beta1=0.4, J1=0.001, beta2=-0.3,
                       beta3=0.5, branch=-1), -7.0, 25.0, 3.0)]
        for label, params, w, a, load in cases:
            t0 = time.perf_counter()
            theirs = fourbarhinge_four_bar(params, theta, w, a, load)
            t1 = time.perf_counter()
            ours = presets.get("four_bar", **params).solve(theta, w, a, load)
            t2 = time.perf_counter()
            err = relative_errors(ours, theirs)
            worst = max(err, key=err.get)
            print(f"fourbarhinge [{label}]: max rel err {err[worst]:.1e} ({worst}); "
                  f"{1e6 * (t1 - t0) / theta.size:.0f} us/angle (linkage_fmu "
                  f"{1e6 * (t2 - t1) / theta.size:.2f} us/angle)")
    if exudyn_version():
        exudyn_run("four_bar", 4)  # imports
        for preset, load in (("four_bar", 0.0), ("slider_crank", 0.0), ("four_bar", 2.0),
                             ("slider_crank", 50.0)):
            for n in ((90, 360, 1440, 5760, 23040) if not load else (360, 1440)):
                theta, theirs, tm = exudyn_run(preset, n, 10.0, load)
                ours = presets.get(preset).solve(theta, 10.0, 0.0, load)
                err = relative_errors(ours, theirs)
                worst = max(err, key=err.get)
                print(f"exudyn {preset:12s} load {load:4g} {n:6d} steps: max rel err "
                      f"{err[worst]:.1e} ({worst}), Mb {err['Mb']:.1e}; setup "
                      f"{tm['setup_s'] * 1e3:.1f} ms, solve {tm['solve_s'] * 1e3:.1f} ms = "
                      f"{1e6 * tm['solve_s'] / n:.1f} us/step; crank drift "
                      f"{tm['crank_drift_rad']:.0e} rad")


if __name__ == "__main__":
    _main()

"""A motor driving a crank press, as a co-simulation that libcosim runs, and the same
motion from ``Mechanism.simulate``.

- The press: the ``slider_crank`` preset standing upright (the guide at ``gamma = -90
  deg``: the ram below the crank), a heavier ram, pins of given radii with friction, and a
  pressing force on the ram over its downward stroke, a load over the cycle:
  ``F_work = F_press * max(0, -sin(theta - gamma))**2`` towards the crank (zero on the
  return stroke, peak ``F_press`` half-way down). Its drive FMU
  (``build_native_fmu(..., drive=True)``) integrates the crank's angle and speed under
  the moment ``tau`` on the crank.
- The motor: ``motor.py``'s FMU, the line ``tau = T_stall * (1 - omega / omega_noload)``
  referred to the crank; its rotor's inertia (referred to the crank, ``J_ROTOR``) turns
  with the crank and is given to the press as an inertia on the crank: the drive FMU's
  ``J1`` (the crank's centre of mass is on its axis here), ``simulate``'s ``flywheel``.
- The system: ``OspSystemStructure.xml`` (:func:`system_structure`) connects the press's
  ``omega`` to the motor's input and the motor's ``tau`` to the press's input; libcosim's
  fixed-step algorithm exchanges them at every communication step ``h``. The motor's
  torque is held over a step, so the coupling error falls like ``h``.

The pins and the guide have Coulomb friction (:data:`FRICTION`): the drive FMU finds the
crank's acceleration from ``tau = Mb(theta, omega, alpha)`` with it, as ``simulate`` does,
and reports the friction's power ``P_loss``. :func:`stroke` turns a motion into the figures
a motor is sized by: the energy and the friction loss of a stroke, the torque's rms and peak.

Every number of the system is here, once: :data:`PRESS`, :data:`MOTOR`, :data:`J_ROTOR`,
:data:`PINS` and :data:`FRICTION`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from linkage_fmu import presets
from linkage_fmu.fmi import build_native_fmu

import motor

#: the press (the slider_crank preset's parameters that differ from its defaults)
PRESS = {"gamma": -math.pi / 2, "m3": 5.0, "F_press": 2000.0}
#: the motor's line referred to the crank: stall torque [N m], no-load speed [rad/s]
MOTOR = {"T_stall": 210.0, "omega_noload": 7.0}
#: the motor rotor's (with its gearbox's) moment of inertia referred to the crank [kg m2]
J_ROTOR = 20.0
#: the radii of the press's pins [m]
PINS = {"r_O": 0.02, "r_A": 0.015, "r_B": 0.01}
#: the coefficients of friction of the press's pins and guide
FRICTION = {"mu_O": 0.1, "mu_A": 0.1, "mu_B": 0.1, "mu_guide": 0.1}
#: the press starts at rest, the ram at its top dead centre
START = {"theta0": math.pi / 2, "omega0": 0.0}
#: the drive FMU's integrator tolerance (relative and absolute) within each step
TOLERANCE = 1e-10
#: ``simulate``'s tolerances, the reference the co-simulation is compared with
REFERENCE_TOLERANCE = 1e-12
PRESS_FMU, MOTOR_FMU = "PressDrive.fmu", f"{motor.MODEL}.fmu"


def description():
    """The press's description: the ``slider_crank`` preset, named ``press`` (model
    ``Press``), with the parameter ``F_press`` and the pressing force ``F_work`` on the
    ram over its downward stroke."""
    d = presets.preset("slider_crank").copy()
    d.name, d.model, d.title = "press", "Press", "Crank press: an upright slider-crank"
    d.parameter("F_press", PRESS["F_press"], "force", "peak pressing force on the ram, "
                "half-way down its working (downward) stroke")
    d.load("F_work", body="3", kind="force", at="B",
           direction=["-cos(gamma)", "-sin(gamma)"],
           value="F_press * max(0, -sin(theta - gamma))**2",
           description="pressing force on the ram over its working stroke, towards the crank")
    return d.check()


def parameters() -> dict:
    """The press's parameters that differ from the preset's (the crank's ``J1`` without
    the rotor): :data:`PRESS`, :data:`PINS` and :data:`FRICTION`."""
    return {**PRESS, **PINS, **FRICTION}


def drive_parameters(start: dict | None = None) -> dict:
    """The press's drive FMU's parameters: :func:`parameters` with the rotor's inertia in
    ``J1``, the start ``theta0``, ``omega0`` (default :data:`START`) and the integrator's
    tolerance."""
    p = parameters()
    J1 = p.get("J1", presets.preset("slider_crank").parameters["J1"]["default"])
    return {**p, "J1": float(J1) + J_ROTOR, **(start or START), "tolerance": TOLERANCE}


def build(out: str | Path) -> Path:
    """Build both FMUs into the folder ``out``: the press's drive FMU, its parameters'
    defaults the press's (:func:`drive_parameters`; the system structure sets each again),
    and the motor's."""
    out = Path(out)
    d = description()
    defaults = {k: v for k, v in drive_parameters().items() if k in d.parameters}
    build_native_fmu(d, out, drive=True, **defaults)
    motor.build_motor_fmu(out)
    return out


def _values(values: dict) -> str:
    return "".join(f'\n                <InitialValue variable={quoteattr(name)}>'
                   f'<Real value="{float(v)!r}"/></InitialValue>' for name, v in values.items())


def system_structure(h: float, start: dict | None = None) -> str:
    """``OspSystemStructure.xml`` of the system, its FMUs beside it, communication step
    ``h`` [s] (a whole number of libcosim's nanoseconds), from ``start`` (default
    :data:`START`).

    Examples
    --------
    >>> xml = system_structure(1e-4)
    >>> "<BaseStepSize>0.0001</BaseStepSize>" in xml, xml.count("<VariableConnection>")
    (True, 2)
    """
    if not (h > 0.0 and math.isfinite(h)) or abs(h * 1e9 - round(h * 1e9)) > 1e-6 * h * 1e9:
        raise ValueError(f"h must be a positive whole number of nanoseconds [s], got {h!r}")
    connections = [("press", "omega", "motor", "omega"), ("motor", "tau", "press", "tau")]
    return f"""<?xml version="1.0" encoding="utf-8"?>
<!-- The crank press of linkage_fmu's examples/press: written by press.py -->
<OspSystemStructure xmlns="http://opensimulationplatform.com/MSMI/OSPSystemStructure" version="0.1">
    <StartTime>0.0</StartTime>
    <BaseStepSize>{h!r}</BaseStepSize>
    <Algorithm>fixedStep</Algorithm>
    <Simulators>
        <Simulator name="press" source="{PRESS_FMU}">
            <InitialValues>{_values(drive_parameters(start))}
            </InitialValues>
        </Simulator>
        <Simulator name="motor" source="{MOTOR_FMU}">
            <InitialValues>{_values(MOTOR)}
            </InitialValues>
        </Simulator>
    </Simulators>
    <Connections>{"".join(f'''
        <VariableConnection>
            <Variable simulator="{a}" name="{x}"/>
            <Variable simulator="{b}" name="{y}"/>
        </VariableConnection>''' for a, x, b, y in connections)}
    </Connections>
</OspSystemStructure>
"""


def check_parameters(folder: str | Path, start: dict | None = None) -> None:
    """Initialise each FMU in ``folder`` with the system's parameters through fmpy, and
    raise a ValueError with the FMU's own message where one refuses them (a parameter out
    of its range, a linkage that cannot be assembled at ``theta0``). libcosim would abort
    the whole process there: it throws from a worker thread on an FMU's Error."""
    import fmpy

    for name, values in ((PRESS_FMU, drive_parameters(start)), (MOTOR_FMU, MOTOR)):
        said = []
        try:
            fmpy.simulate_fmu(str(Path(folder) / name), stop_time=1e-6, step_size=1e-6,
                              start_values=values, output=[],
                              logger=lambda *args: said.append(args[-1].decode()))
        except Exception as err:
            why = "; ".join(said) or str(err)
            raise ValueError(f"{name} refuses the system's parameters: {why}") from None


@dataclass
class Run:
    """A co-simulated motion of the press, sampled: the times [s], the communication step
    ``h`` [s] and, at each time, every output recorded (:data:`RECORDED`; the motor's as
    ``motor.NAME``)."""

    t: np.ndarray
    h: float
    values: dict

    def __getitem__(self, name: str) -> np.ndarray:
        return self.values[name]


#: the outputs the co-simulation records
RECORDED = {"press": ("theta", "omega", "alpha", "Mb", "P_loss"),
            "motor": ("tau", "P")}


def sample_times(h: float, t_end: float, every: float) -> np.ndarray:
    """The times a co-simulation is sampled at: every ``every`` seconds (rounded to whole
    steps ``h``, at least one) after 0, to ``t_end``.

    Examples
    --------
    >>> sample_times(1e-3, 0.01, 2.5e-3).round(12).tolist()
    [0.002, 0.004, 0.006, 0.008, 0.01]
    """
    n = max(1, round(every / h))
    return np.arange(n, round(t_end / h) + 1, n) * h


def cosimulate(folder: str | Path, h: float, t_end: float, every: float = 1e-3,
               start: dict | None = None) -> Run:
    """Run the system in libcosim from 0 to ``t_end`` at the communication step ``h``
    from ``start`` (``theta0``, ``omega0``; default :data:`START`):
    write its ``OspSystemStructure.xml`` into ``folder`` (beside the FMUs :func:`build`
    made there), load it and sample :data:`RECORDED` at :func:`sample_times`.

    Raises
    ------
    RuntimeError
        libcosim cannot load the system or a step fails (its message).
    """
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy._internal import get_last_error_message

    log_output_level(CosimLogLevel.ERROR)

    folder = Path(folder)
    check_parameters(folder, start)
    (folder / "OspSystemStructure.xml").write_text(system_structure(h, start))
    execution = CosimExecution.from_osp_config_file(str(folder / "OspSystemStructure.xml"))
    observer = CosimObserver.create_last_value()
    execution.add_observer(observer)
    index = {s.name.decode(): s.index for s in execution.slave_infos()}
    refs = {name: {v.name.decode(): v.reference for v in execution.slave_variables(index[name])}
            for name in RECORDED}
    t = sample_times(h, t_end, every)
    h_ns = round(h * 1e9)
    rows = []
    for k in np.rint(t / h).astype(np.int64):
        if not execution.simulate_until(int(k) * h_ns):
            raise RuntimeError(f"libcosim stopped at t = {execution.status().current_time * 1e-9} "
                               f"s: {get_last_error_message()}")
        rows.append([v for name, names in RECORDED.items()
                     for v in observer.last_real_values(index[name],
                                                        [refs[name][n] for n in names])])
    values = np.array(rows, dtype=float)
    names = [f"{n}" if owner == "press" else f"motor.{n}"
             for owner, ns in RECORDED.items() for n in ns]
    return Run(t, h, {n: values[:, j] for j, n in enumerate(names)})


def motor_torque(t: float, theta: float, omega: float) -> float:
    """The motor's line referred to the crank, ``simulate``'s ``tau(t, theta, omega)``:
    the same law the motor FMU computes.

    Examples
    --------
    >>> motor_torque(0.0, 0.0, 0.0), motor_torque(0.0, 0.0, MOTOR["omega_noload"])
    (210.0, 0.0)
    """
    return MOTOR["T_stall"] * (1.0 - omega / MOTOR["omega_noload"])


def simulate(t: np.ndarray, start: dict | None = None):
    """The reference: ``Mechanism.simulate`` of the press under :func:`motor_torque` with
    the rotor as a flywheel on the crank, from ``start`` (default :data:`START`) at time
    0, at the times ``t`` (after 0)."""
    mech = description().build(**parameters())
    start = start or START
    run = mech.simulate(motor_torque, np.concatenate([[0.0], t]), theta0=start["theta0"],
                        omega0=start["omega0"], flywheel=J_ROTOR, rtol=REFERENCE_TOLERANCE,
                        atol=REFERENCE_TOLERANCE)
    return run.iloc[1:]


def coupling_error(run: Run, reference) -> float:
    """The largest difference of the crank speed between ``run`` and ``reference`` (a
    DataFrame at the same times), relative to the largest speed of the reference.

    Examples
    --------
    >>> import pandas as pd
    >>> run = Run(np.array([0.1, 0.2]), 0.1, {"omega": np.array([1.0, 2.002])})
    >>> round(coupling_error(run, pd.DataFrame({"omega": [1.0, 2.0]})), 12)
    0.001
    """
    omega = reference["omega"].to_numpy()
    return float(np.max(np.abs(run["omega"] - omega)) / np.max(np.abs(omega)))


def stroke(t, theta, omega, tau, P_loss, theta_top: float = START["theta0"]) -> dict:
    """The figures a motor is sized by, over the last whole revolution of a sampled motion
    (one stroke: the crank from the top dead centre ``theta_top`` to the next; the crank
    turning forwards, ``theta`` not wrapped).

    Returns a dict: ``period`` [s] and the times ``t_start``, ``t_stop`` [s] of the
    revolution; ``omega_mean`` [rad/s]; ``tau_rms``, ``tau_max``, ``tau_min`` [N m] (the
    motor's torque: its rms sets the motor's heating, its peak the torque it must give);
    ``E_motor`` and ``E_loss`` [J] (the motor's work on the crank and the friction's
    loss over the stroke), ``P_motor_mean`` and ``P_loss_mean`` [W] (each over the
    period), ``P_loss_max`` [W]. Integrals are trapezoidal over the samples, the ends of
    the revolution interpolated linearly.

    Raises
    ------
    ValueError
        The motion holds no whole revolution from a top dead centre.

    Examples
    --------
    A crank at 2 pi rad/s under 10 N m, losing 4 W: one revolution a second.

    >>> t = np.linspace(0.0, 2.5, 251)
    >>> s = stroke(t, np.pi / 2 + 2 * np.pi * t, np.full(251, 2 * np.pi), np.full(251, 10.0),
    ...            np.full(251, 4.0))
    >>> [round(s[k], 9) for k in ("t_start", "period", "tau_rms", "E_loss", "P_loss_mean")]
    [1.0, 1.0, 10.0, 4.0, 4.0]
    """
    from scipy.integrate import cumulative_trapezoid

    t, theta, omega, tau, P_loss = (np.asarray(x, dtype=float)
                                    for x in (t, theta, omega, tau, P_loss))
    turns = np.floor((theta - theta_top) / (2.0 * np.pi) + 1e-12)
    k = np.flatnonzero(np.diff(turns) > 0)
    if len(k) < 2:
        raise ValueError("the motion holds no whole revolution from one top dead centre to "
                         "the next: run it longer")

    def crossing(i: int) -> float:
        top = theta_top + 2.0 * np.pi * turns[i + 1]
        return float(np.interp(top, theta[i:i + 2], t[i:i + 2]))

    t0, t1 = crossing(k[-2]), crossing(k[-1])
    period = t1 - t0

    def over(y):
        cumulative = cumulative_trapezoid(y, t, initial=0.0)
        return float(np.interp(t1, t, cumulative) - np.interp(t0, t, cumulative))

    inside = (t >= t0) & (t <= t1)
    E_motor, E_loss = over(tau * omega), over(P_loss)
    return {"t_start": t0, "t_stop": t1, "period": period, "omega_mean": 2.0 * np.pi / period,
            "tau_rms": float(np.sqrt(over(tau ** 2) / period)),
            "tau_max": float(np.max(tau[inside])), "tau_min": float(np.min(tau[inside])),
            "E_motor": E_motor, "E_loss": E_loss, "P_motor_mean": E_motor / period,
            "P_loss_mean": E_loss / period, "P_loss_max": float(np.max(P_loss[inside]))}

"""Directional derivatives: the kernels' forward mode (``Kernel.tangent``) and the native
FMUs' ``fmi2GetDirectionalDerivative`` / ``fmi3GetDirectionalDerivative`` over it.

References: central differences of the outputs themselves (step h = 1e-6 of the input's
scale: truncation h**2 ~ 1e-12 and rounding eps/h ~ 1e-10 relative, so 1e-7 of each
output's scale holds with room); ``J_red``, which dMb/dalpha equals exactly (the balancing
moment is affine in the crank acceleration, Mb = J alpha + ...); and, for a motor coupled
to the inverse FMU through the algebraic loop alpha -> Mb -> alpha, the library's own
integration of the same motion (:meth:`Mechanism.simulate`).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave
from fmpy.fmi3 import FMU3Slave

from conftest import IDS, VARIANTS
from fmu_cache import build_native_fmu
from linkage_fmu import presets
from linkage_fmu.fmi import writers
from test_loads import ROWS, engine

#: states (theta, omega, alpha) the kernels are differentiated at, moving and at rest
STATES = [(0.7, 12.0, 3.0), (2.9, -4.0, 0.0), (4.4, 0.0, 0.0)]


def gas():
    """The slider-crank driven against a gas force from a 720-degree table of bar."""
    return engine(table=ROWS, period_deg=720.0, table_unit="bar", scale="pi * (86 mm)**2 / 4")


def central(f, x: np.ndarray, j: int) -> np.ndarray:
    """Central difference of ``f`` in input ``j`` with a step of 1e-6 of its scale."""
    h = 1e-6 * max(1.0, abs(x[j]))
    e = np.zeros_like(x)
    e[j] = h
    return (np.asarray(f(x + e)) - np.asarray(f(x - e))) / (2.0 * h)


def scales(k, x) -> np.ndarray:
    """Each output's magnitude at ``x``, at least 1 per unit of input."""
    return np.maximum(np.abs(np.asarray(k(*x))), 1.0)


@pytest.mark.parametrize("name, params", VARIANTS, ids=IDS)
def test_the_kernel_tangent_against_central_differences_and_J_red(name, params):
    mech = presets.get(name, **params)
    k = mech.solver.kernel()
    tangent = k.tangent()
    n = k.n_inputs
    checked = 0
    for theta, omega, alpha in STATES:
        x = np.array([theta, omega, alpha] + [35.0] * (n - 3))
        if k(*x) is None:  # cannot be assembled there (a rocker's dead zone)
            assert isinstance(tangent(x, np.ones(n)), int)
            continue
        for j in range(n):
            y, dy = tangent(x, np.eye(n)[j])
            np.testing.assert_array_equal(y, k(*x))  # the values are the kernel's, bit for bit
            fd = central(lambda z: k(*z), x, j)
            np.testing.assert_allclose(dy, fd, rtol=0, atol=1e-7 * scales(k, x).max())
        # Mb = J alpha + Mb(alpha = 0): dMb/dalpha is J_red (an effort on the crank), or
        # J_red over the effort's own rate (a six-bar driven elsewhere: power balance)
        _, dy = tangent(x, np.eye(n)[2])
        y = k(*x)
        effort = dy[k.index[mech.effort.name]]
        if mech.effort_on_crank:
            assert effort == pytest.approx(y[k.index["J_red"]], rel=1e-13)
        # dJ_red/dtheta is dJ_red's own value: two routes to one number
        _, dy = tangent(x, np.eye(n)[0])
        assert dy[k.index["J_red"]] == pytest.approx(y[k.index["dJ_red"]], rel=1e-12,
                                                     abs=1e-14 * y[k.index["J_red"]])
        checked += 1
    assert checked >= 2


def test_a_table_load_is_differentiated_through_its_spline():
    """A gas force from a 720-degree table: the spline's derivative, exact, where the
    load over the cycle enters the torque."""
    mech = gas().build()
    k = mech.solver.kernel()
    tangent = k.tangent()
    for theta in (0.3, 1.9, 5.2, 9.0):
        x = np.array([theta, 180.0, 20.0])
        y, dy = tangent(x, np.array([1.0, 0.0, 0.0]))
        fd = central(lambda z: k(*z), x, 0)
        np.testing.assert_allclose(dy, fd, rtol=0, atol=1e-7 * scales(k, x).max())


# -- the native FMUs ------------------------------------------------------------------------
@pytest.fixture(scope="module")
def fmus(tmp_path_factory):
    """Native FMUs, FMI 2.0 and 3.0, of the four-bar and the slider-crank with a gas-force
    table (its spline's derivative in C)."""
    out = tmp_path_factory.mktemp("derivatives")
    made = {}
    for label, source in (("four_bar", "four_bar"), ("gas", gas())):
        for version in (2, 3):
            made[label, version] = build_native_fmu(source, out / f"{label}{version}",
                                                    fmi_version=version)
    return made


class Slave:
    """An instance of a native FMU in initialisation-free step mode, by variable name."""

    def __init__(self, path, version: int):
        md = read_model_description(str(path))
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        self.outputs = [v.name for v in md.modelVariables if v.causality == "output"]
        self.inputs = [v.name for v in md.modelVariables if v.causality == "input"]
        cls = FMU2Slave if version == 2 else FMU3Slave
        self.fmu = cls(guid=md.guid, modelIdentifier=md.coSimulation.modelIdentifier,
                       unzipDirectory=extract(str(path)))
        self.version = version
        self.fmu.instantiate()
        if version == 2:
            self.fmu.setupExperiment(startTime=0.0)
        self.fmu.enterInitializationMode()
        self.fmu.exitInitializationMode()

    def set(self, **values) -> None:
        refs = [self.vr[n] for n in values]
        if self.version == 2:
            self.fmu.setReal(refs, list(values.values()))
        else:
            self.fmu.setFloat64(refs, list(values.values()))

    def get(self, names) -> np.ndarray:
        refs = [self.vr[n] for n in names]
        return np.array(self.fmu.getReal(refs) if self.version == 2 else
                        self.fmu.getFloat64(refs))

    def derivative(self, unknowns, knowns, seed) -> np.ndarray:
        return np.array(self.fmu.getDirectionalDerivative(
            [self.vr[n] for n in unknowns], [self.vr[n] for n in knowns], list(seed)))

    def free(self) -> None:
        self.fmu.terminate()
        self.fmu.freeInstance()


@pytest.mark.parametrize("version", (2, 3))
@pytest.mark.parametrize("label", ("four_bar", "gas"))
def test_fmu_derivatives_are_the_kernel_tangent_and_central_differences(fmus, label, version):
    """Every output along each input alone and along a mixed direction: the kernel's
    tangent (the same generated C: 1e-15 relative), central differences of the FMU's own
    outputs (1e-7 of the outputs' scale), and dMb/dalpha = J_red."""
    path = fmus[label, version]
    # the FMU's own kernel: friction solved whatever its mu (they are FMU parameters)
    mech = (presets.preset("four_bar") if label == "four_bar" else gas()).fmu_build()
    tangent = mech.solver.kernel().tangent()
    s = Slave(path, version)
    assert s.inputs == list(mech.input_names)
    try:
        for theta, omega, alpha in STATES[:2]:
            x = np.array([theta, omega, alpha] + [25.0] * (len(s.inputs) - 3))
            s.set(**dict(zip(s.inputs, x)))
            y = s.get(s.outputs)
            scale = np.maximum(np.abs(y), 1.0).max()
            directions = [*np.eye(len(x)), np.linspace(0.3, -0.7, len(x))]
            for d in directions:
                got = s.derivative(s.outputs, s.inputs, d)
                _, want = tangent(x, d)
                np.testing.assert_allclose(got, want, rtol=1e-15, atol=1e-300)

                def outputs(z):
                    s.set(**dict(zip(s.inputs, z)))
                    return s.get(s.outputs)

                h = 1e-6
                fd = (outputs(x + h * d) - outputs(x - h * d)) / (2 * h)
                s.set(**dict(zip(s.inputs, x)))
                np.testing.assert_allclose(got, fd, rtol=0, atol=1e-7 * scale)
            # a subset of unknowns and knowns, in any order
            got = s.derivative(["J_red", "Mb"], ["alpha"], [1.0])
            assert got[0] == 0.0  # a function of theta alone
            assert got[1] == pytest.approx(s.get(["J_red"])[0], rel=1e-13)
    finally:
        s.free()


@pytest.mark.parametrize("version", (2, 3))
def test_bad_directional_derivative_calls_are_errors_naming_the_variable(fmus, version):
    """An unknown that is not an output, a known that is not an input, a seed that is not
    finite: Error, and the instance goes on. Inputs that cannot be assembled: NaN with
    a Warning, like a read of the outputs."""
    s = Slave(fmus["four_bar", version], version)
    messages = []
    try:
        s.set(theta=0.5, omega=3.0, alpha=0.0, load=0.0)
        for unknowns, knowns, seed in ((["theta"], ["alpha"], [1.0]),
                                       (["Mb"], ["Mb"], [1.0]),
                                       (["Mb"], ["l_AB"], [1.0]),
                                       (["Mb"], ["alpha"], [math.nan])):
            with pytest.raises(FMICallException) as err:
                s.derivative(unknowns, knowns, seed)
            messages.append(str(err.value))
        assert s.derivative(["Mb"], ["alpha"], [2.0])[0] == pytest.approx(
            2.0 * s.get(["J_red"])[0], rel=1e-14)
    finally:
        s.free()
    assert all("Error" in m or "3" in m for m in messages)


def test_a_pose_that_cannot_be_assembled_gives_nan_derivatives_with_a_warning(tmp_path):
    fmu = build_native_fmu("four_bar", tmp_path, l_AB=0.3)
    s = Slave(fmu, 2)
    try:
        s.set(theta=3.1, omega=3.0)
        refs = [s.vr["Mb"]]
        from fmpy.fmi2 import fmi2Real, fmi2ValueReference
        dv = (fmi2Real * 1)()
        status = s.fmu.fmi2GetDirectionalDerivative(
            s.fmu.component, (fmi2ValueReference * 1)(*refs), 1,
            (fmi2ValueReference * 1)(s.vr["alpha"]), 1, (fmi2Real * 1)(1.0), dv)
        assert status == 1 and math.isnan(dv[0])  # fmi2Warning
    finally:
        s.free()


@pytest.mark.parametrize("version, attribute", ((2, 'providesDirectionalDerivative="'),
                                                (3, 'providesDirectionalDerivatives="')))
def test_only_the_native_fmus_say_they_provide_them(version, attribute):
    mech = presets.get("four_bar")
    for flavour, value in (("native", "true"), ("pythonfmu", "false")):
        xml = writers.model_description(mech, flavour, version, "{0}").decode()
        assert xml.count(attribute) == 1 and f'{attribute}{value}"' in xml


# -- a master that closes the loop motor -> alpha -> inverse FMU -> Mb ----------------------
def test_a_motor_coupled_by_newton_on_the_loop_reproduces_the_library_motion(fmus):
    """A motor with the characteristic tau = tau0 (1 - omega / omega0) drives the
    four-bar through the inverse FMU: each evaluation solves r(alpha) = tau(omega) -
    Mb(theta, omega, alpha) = 0 by Newton with dr/dalpha = -dMb/dalpha from the FMU's
    directional derivative (Mb is affine in alpha: one iteration, then r is rounding).
    A classical RK4 in the master over 0.25 s (h = 0.5 ms) matches Mechanism.simulate on
    the same motor (DOP853, rtol 1e-11) to RK4's own error (measured: 1.6e-11 relative in
    theta, 2.1e-9 in omega)."""
    tau0, omega0 = 6.0, 40.0
    s = Slave(fmus["four_bar", 2], 2)
    iterations = []

    def alpha_of(theta, omega):
        alpha = 0.0
        for it in range(1, 6):
            s.set(theta=theta, omega=omega, alpha=alpha, load=0.0)
            r = tau0 * (1.0 - omega / omega0) - s.get(["Mb"])[0]
            if abs(r) <= 1e-12 * tau0:
                iterations.append(it - 1)
                return alpha
            alpha += r / s.derivative(["Mb"], ["alpha"], [1.0])[0]
        raise AssertionError(f"Newton did not converge at theta = {theta}")

    def f(y):
        return np.array([y[1], alpha_of(*y)])

    h, steps = 5e-4, 500
    y = np.array([0.3, 2.0])
    try:
        for _ in range(steps):
            k1 = f(y)
            k2 = f(y + h / 2 * k1)
            k3 = f(y + h / 2 * k2)
            k4 = f(y + h * k3)
            y = y + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    finally:
        s.free()
    assert max(iterations) <= 2 and np.mean(iterations) <= 1.01
    run = presets.get("four_bar").simulate(lambda t, th, w: tau0 * (1.0 - w / omega0),
                                           [0.0, h * steps], theta0=0.3, omega0=2.0,
                                           rtol=1e-11, load=0.0)
    assert y[0] == pytest.approx(run["theta"].iloc[-1], rel=2e-10)
    assert y[1] == pytest.approx(run["omega"].iloc[-1], rel=2e-8)
    assert y[1] > 10.0  # the motor did spin the linkage up


def test_a_state_deserialized_but_not_set_leaves_the_derivatives_alone(tmp_path):
    """Deserializing a state checks its parameter set with the kernels' parameter step,
    and leaves the instance's own in force: the derivatives after it are those before
    (a state of another l_AB, taken from a second instance, deserialized, never set)."""
    fmu = build_native_fmu("slotted_lever", tmp_path)
    a, b = Slave(fmu, 2), Slave(fmu, 2)
    try:
        u = dict(theta=2.3, omega=-6.0, alpha=5.0, load=40.0)
        a.set(**u)
        before = a.derivative(["Mb"], ["alpha"], [1.0])
        b.fmu.terminate()
        b.fmu.reset()
        b.fmu.setReal([b.vr["l_AB"]], [0.08])
        b.fmu.enterInitializationMode()
        b.fmu.exitInitializationMode()
        other = b.fmu.serializeFMUstate(b.fmu.getFMUstate())
        a.fmu.deSerializeFMUstate(other)  # a new state of a's, not set
        assert a.derivative(["Mb"], ["alpha"], [1.0])[0] == before[0]
        assert before[0] == pytest.approx(a.get(["J_red"])[0], rel=1e-14)
    finally:
        a.free()
        b.free()


@pytest.mark.parametrize("name", presets.names())
def test_the_kernel_tangent_with_friction_against_central_differences(name):
    """Friction in every pair (mu 0.15, pins of 0.02 of the length scale), the kernel's
    tangent through its Newton steps on the friction values: central differences of the
    kernel's outputs (1e-7 of the outputs' scale), at two moving states."""
    base = presets.get(name)
    d = presets.preset(name)
    params = {spec["mu"]: 0.15 for spec in d.friction.values()}
    params.update({spec["radius"]: 0.02 * base.length_scale for spec in d.friction.values()
                   if "radius" in spec})
    mech = presets.get(name, **params)
    k = mech.solver.kernel()
    tangent = k.tangent()
    n = k.n_inputs
    for theta, omega, alpha in STATES[:2]:
        x = np.array([theta, omega, alpha] + [35.0] * (n - 3))
        if k(*x) is None:
            continue
        for j in range(n):
            y, dy = tangent(x, np.eye(n)[j])
            np.testing.assert_array_equal(y, k(*x))
            fd = central(lambda z: k(*z), x, j)
            np.testing.assert_allclose(dy, fd, rtol=0, atol=1e-7 * scales(k, x).max(),
                                       err_msg=f"{name}: input {j}")

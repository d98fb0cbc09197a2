"""Random triad six-bars (a class III group) and the checks of the assembly mode the
library follows on them, against the reference of :mod:`arclength`.

A design is the triad six-bar of :mod:`arclength` drawn in a random pose; every other
one is drawn again within 1e-7 to 1e-3 rad of a limit position of its crank, on either
assembly mode that meets there. :func:`triad` is the linkage in group form with every
drawn coordinate a parameter, so that one kernel (and one FMU) serves every design.
``tests/test_closure.py`` runs 160 designs of 25 states each, and the native FMU at 200
of them; as a script, the same checks at any size, the native FMU at every state, from a
fresh host process, with the inputs a fuzz adds (NaN, infinities, huge angles)::

    python tests/triads.py --designs 800 [--seed 1] [--fmu]

It prints what it counted and fails (exit 1) on the first state answered on another
mode, refused within reach, or answered differently by the FMU.
"""

from __future__ import annotations

import argparse
import math
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import arclength
from linkage_fmu import Description

#: the drawn coordinates of the triad six-bar, as parameters: one kernel, and one FMU,
#: for every design
COORDINATES = ("r", "th0", "cx", "cy", "dx", "dy", "ex", "ey", "fx", "fy", "gx", "gy")
#: the states compared are static, under gravity and a torque on the plate
GRAVITY, TORQUE = 9.81, 5.0
#: link -> (the joint its centre of mass is at, its mass in kg): at rest the balancing
#: moment is ``g sum(m dy/dtheta) - T dphi5/dtheta`` (virtual work)
MASSES = {"3": ("E", 0.5), "4": ("F", 0.4), "6": ("G", 0.3), "5": ("E", 1.2)}
#: the links of the group: three rods and the plate
LINKS = {"3": ["B", "E"], "4": ["C", "F"], "6": ["D", "G"], "5": ["E", "F", "G"]}
#: the documented reach of the continuation: a state on the drawn assembly mode farther
#: than this from a limit position (rad of the crank angle) is solved
REACH = 1e-9


def triad(design: arclength.Design) -> Description:
    """The triad six-bar in group form, every drawn coordinate a parameter (its defaults
    ``design``'s)."""
    value = coordinates(design)
    d = Description("triad", model="Triad", frame="0", gravity=GRAVITY)
    for name in COORDINATES:
        kind = {"r": "length", "th0": "angle"}.get(name, "coordinate")
        d.parameter(name, value[name], kind, f"the drawn pose's {name}")
    d = (d.point("A", 0, 0).point("C", "cx", "cy").point("D", "dx", "dy")
         .group("crank", link="1", pivot="A", tip="B", length="r")
         .group("closure", links=LINKS,
                pose={"B": ["r * cos(th0)", "r * sin(th0)"], "C": ["cx", "cy"],
                      "D": ["dx", "dy"], "E": ["ex", "ey"], "F": ["fx", "fy"],
                      "G": ["gx", "gy"]}, theta="th0")
         .body("1", mass=0.0, inertia=0.0, cg={"from": "A"}))
    for link, (at, mass) in MASSES.items():
        d.body(link, mass=mass, inertia=0.0, cg={"from": at})
    return (d.load("T", body="5", kind="moment", description="a torque on the plate")
            .effort("Mb", body="1").output("effort", name="Mb"))


def coordinates(design: arclength.Design) -> dict:
    """The parameters of :func:`triad` that draw ``design``."""
    return dict(zip(COORDINATES, map(float, (design.r, design.theta0, *design.C, *design.D,
                                             *design.pose["E"], *design.pose["F"],
                                             *design.pose["G"]))))


def random_design(rng) -> tuple:
    """A triad six-bar drawn at a random crank angle: a plate of three points around a
    random centre, one rod from the crank tip, two from frame pivots, each of random
    length and direction; with its reference :class:`~arclength.Branch`."""
    while True:
        r, theta0 = rng.uniform(0.03, 0.08), rng.uniform(-math.pi, math.pi)
        B = r * np.array([math.cos(theta0), math.sin(theta0)])
        centre, size, turn = rng.uniform([-0.1, 0.15], [0.1, 0.3]), rng.uniform(0.04, 0.1), \
            rng.uniform(0.0, 2 * math.pi)
        plate = [centre + size * np.array([math.cos(a), math.sin(a)]) for a in
                 turn + 2 * math.pi * np.arange(3) / 3 + rng.uniform(-0.4, 0.4, 3)]
        rods = [rng.uniform(0.12, 0.3) * np.array([math.cos(a), math.sin(a)])
                for a in rng.uniform(0.0, 2 * math.pi, 2)]
        if np.linalg.norm(B - plate[0]) < 0.05:
            continue
        design = arclength.Design(r, theta0, tuple(plate[1] + rods[0]),
                                  tuple(plate[2] + rods[1]),
                                  dict(zip("EFG", map(tuple, plate))))
        try:
            return design, arclength.Branch(design)
        except RuntimeError:  # the reference cannot follow it: another
            continue


def redrawn(design: arclength.Design, theta: float, x: np.ndarray) -> arclength.Design:
    """``design`` drawn again at the crank angle ``theta`` with its plate at ``x``."""
    return arclength.Design(design.r, theta, design.C, design.D,
                            {"E": tuple(x[0:2]), "F": tuple(x[2:4]), "G": tuple(x[4:6])})


def near_a_limit(rng) -> tuple:
    """A random design whose crank cannot turn fully, drawn again within 1e-7 to 1e-3
    rad of one of its limit positions, on either assembly mode that meets there."""
    while True:
        design, branch = random_design(rng)
        limits = [(way, at) for way, at in zip((1.0, -1.0), branch.limits) if at is not None]
        if not limits:
            continue
        way, at = limits[rng.integers(len(limits))]
        eps = 10.0 ** rng.uniform(-7.0, -3.0)
        x = branch.at(at - way * eps) if rng.uniform() < 0.5 else branch.beyond(way, eps)
        drawn = redrawn(design, at - way * eps, x)
        try:
            return drawn, arclength.Branch(drawn)
        except RuntimeError:
            continue


def states(rng, design, branch, n: int = 25) -> list:
    """``n`` crank angles: 13 anywhere, then up to 6 within 1e-11 to 1e-3 rad of each
    limit (both sides), the rest within 1e-3 rad of the drawn angle; none half a turn
    away (where the shorter way round is undefined)."""
    thetas = list(rng.uniform(-math.pi, math.pi, 13))
    for at in branch.limits:
        if at is not None:
            side = np.where(rng.uniform(size=6) < 0.5, -1.0, 1.0)
            thetas += list(at + side * 10.0 ** rng.uniform(-11.0, -3.0, 6))
    thetas += list(design.theta0 + rng.uniform(-1e-3, 1e-3, n))
    return [float(t) for t in thetas[:n] if abs(branch.delta(t)) < math.pi - 1e-6]


def designs(n: int = 160, seed: int = 20261202) -> list:
    """``n`` random designs, every other one drawn near a limit position, each with its
    states: ``(design, branch, thetas)``."""
    rng = np.random.default_rng(seed)
    out = []
    for k in range(n):
        design, branch = (near_a_limit if k % 2 else random_design)(rng)
        out.append((design, branch, states(rng, design, branch)))
    return out


def reference_outputs(branch, theta: float) -> tuple[float, float]:
    """``(Mb, gamma_E)`` at rest from the reference's position and its rates: virtual
    work, and the angle at E between E -> B and E -> F."""
    x = branch.at(theta)
    rate = branch.rates(theta, x)
    P = {"E": x[0:2], "F": x[2:4], "G": x[4:6]}
    dP = {"E": rate[0:2], "F": rate[2:4], "G": rate[4:6]}
    u, du = P["F"] - P["E"], dP["F"] - dP["E"]
    turn = (u[0] * du[1] - u[1] * du[0]) / (u @ u)
    Mb = GRAVITY * sum(m * dP[at][1] for at, m in MASSES.values()) - TORQUE * turn
    a = branch.d.B(theta) - P["E"]
    return Mb, math.atan2(abs(a[0] * u[1] - a[1] * u[0]), a @ u)


def kernel_at(kernel, design):
    """The compiled kernel and the Python one at ``design``'s coordinates: each returns
    the outputs' tuple, or the code of the guard that fails (:attr:`Kernel.reasons`)."""
    from linkage_fmu.kernels import compiled

    frozen = kernel.prepare(*coordinates(design).values())
    assert frozen is not None, kernel.parameter_problem(*coordinates(design).values())
    return (compiled.scalar_kernel(kernel._module, frozen, kernel.checked),
            kernel.make(*frozen))


def judge(kernel, design, branch, theta: float) -> tuple[str, tuple | int]:
    """The kernel's answer at ``theta`` and what it is: 'reached' (solved as the reference
    has it), 'past' (refused past a limit, for a reason of kind 'assembly') or 'near'
    (within :data:`REACH` of a limit: either); AssertionError for anything else: the
    transmission angle at E within 1e-9 rad of the reference's (the position), Mb within
    1e-6 of max(1, |Mb|) N.m, near a limit (where Mb grows without bound and both solves
    lose digits) within 1e-13 over the distance to it more."""
    fast, _ = kernel_at(kernel, design)
    margin, r = branch.margin(theta), fast(theta, 0.0, 0.0, TORQUE)
    where = f"theta = {theta!r} ({margin:.3g} rad short of a limit), drawn {design}"
    if margin > REACH:
        assert type(r) is tuple, f"{where}: refused"
        Mb, gamma = reference_outputs(branch, theta)
        assert abs(r[kernel.index["gamma_E"]] - gamma) <= 1e-9, where
        assert abs(r[kernel.index["Mb"]] - Mb) <= (1e-6 + 1e-13 / margin) * max(1.0, abs(Mb)), \
            where
        return "reached", r
    if margin < -REACH:
        assert type(r) is int, f"{where}: answered past the limit"
        assert kernel.reasons[r - 1].kind == "assembly", where
        return "past", r
    return "near", r


def close(values, r: tuple, kernel) -> bool:
    """Whether the FMU's Mb and gamma_E (``values``) are the kernel's answer ``r``: to
    1e-12 of max(1, |value|), and where the state is ill-conditioned, to its rounding
    (1e-15 of the condition number ``cond`` more: the FMU's C orders some operations
    otherwise than the library's kernel)."""
    rounding = 1e-12 + 1e-15 * r[kernel.index["cond"]]
    return all(abs(got - r[kernel.index[name]]) <= rounding * max(1.0, abs(r[kernel.index[name]]))
               for got, name in zip(values, ("Mb", "gamma_E")))


def fmu_ops(refs: dict, runs: list) -> list:
    """The host's operations (tests/fmu_raw_host.py) that set each design's coordinates
    on a fresh instance and step it through its angles (``runs``: ``(design, thetas)``),
    reading Mb and gamma_E after each step."""
    reads = [refs[n] for n in ("Mb", "gamma_E")]
    inputs = [refs[n] for n in ("theta", "omega", "alpha", "T")]
    ops = []
    for k, (design, thetas) in enumerate(runs):
        name = f"design{k}"
        ops += [[name, "new", "Triad"], [name, "setup", 0.0, None], [name, "enter"],
                [name, "setReal", [refs[n] for n in COORDINATES],
                 list(coordinates(design).values())], [name, "exit"]]
        for i, theta in enumerate(thetas):
            ops += [[name, "setReal", inputs, [theta, 0.0, 0.0, TORQUE]],
                    [name, "doStep", 0.01 * i, 0.01], [name, "getReal", reads]]
        ops.append([name, "free"])
    return ops


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--designs", type=int, default=160)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--fmu", action="store_true",
                        help="also the native FMU at every state, with fuzzed inputs")
    args = parser.parse_args(argv)
    t0 = time.perf_counter()
    made = designs(args.designs, args.seed)
    kernel = triad(made[0][0]).build().kernel(static=True)
    if not kernel.compile():
        print("no C compiler: the compiled kernel is what is checked")
        return 1
    counts = {"reached": 0, "past": 0, "near": 0}
    for design, branch, thetas in made:
        for theta in thetas:
            counts[judge(kernel, design, branch, theta)[0]] += 1
    print(f"{args.designs} designs, {sum(counts.values())} states: {counts} "
          f"({time.perf_counter() - t0:.0f} s)")
    if args.fmu:
        from fmpy import read_model_description

        import fmu_cache
        from test_fmu_protocol import DISCARD, FATAL, OK, raw

        with tempfile.TemporaryDirectory() as tmp:
            source = Path(tmp) / "triad.toml"
            source.write_text(triad(made[0][0]).to_toml())
            fmu = fmu_cache.build_native_fmu(str(source), Path(tmp) / "dist")
            refs = {v.name: v.valueReference
                    for v in read_model_description(str(fmu)).modelVariables}
            rng = np.random.default_rng(args.seed + 1)
            bad = (math.nan, math.inf, -math.inf, 1e300, -1e300, 1e17)
            runs = [(design, [float(rng.choice(bad)) if rng.uniform() < 0.1 else t
                              for t in thetas]) for design, _, thetas in made]
            ops = fmu_ops(refs, runs)
            out = raw(fmu.parent, ops, Path(tmp), models=("Triad",))
        statuses = [status for status, _ in out["results"]]
        tally = {s: statuses.count(s) for s in set(statuses)}
        print(f"native FMU: {len(ops)} calls, statuses {tally} (0 OK, 1 Warning, "
              f"2 Discard, 3 Error, 4 Fatal)")
        assert FATAL not in statuses
        steps = iter(i for i, op in enumerate(ops) if op[1] == "doStep")
        for design, fuzzed in runs:
            fast, _ = kernel_at(kernel, design)
            for theta in fuzzed:
                i = next(steps)
                status, values = out["results"][i][0], out["results"][i + 1][1]
                r = fast(theta, 0.0, 0.0, TORQUE) if math.isfinite(theta) else None
                if type(r) is tuple:
                    assert status == OK, (design, theta, status)
                    assert close(values, r, kernel), (design, theta, values)
                else:
                    assert status == DISCARD or not math.isfinite(theta) and status != OK, \
                        (design, theta, status)
        print(f"every doStep as the library ({time.perf_counter() - t0:.0f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())

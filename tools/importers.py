"""Which importers run the linkage FMUs, and how well: every importer present, on every
FMU of both flavours and FMI versions, compared with the direct solver; the table of
``benchmarks/results/importers.md`` is filled only from these runs.

    python tools/importers.py --build [--dist DIR]       # build the FMUs first
    python tools/importers.py [--dist DIR] [--fmusim EXE] [--fmusim-fixed EXE]
                              [--fmucheck EXE] [--out FILE | --results]

Run it with ``PYTHONPATH=<checkout>/src``. The FMUs are ``DIR/fmi{2,3}/{pythonfmu,native}/
<Model>.fmu`` (default ``DIR``: ``dist/importers``), one per preset of
``linkage_fmu.presets.names()`` and per description file in ``examples/``, each with the
FMI cross-check files ``<Model>_in.csv``, ``_ref.csv``, ``_ref.opt`` beside it
(``write_crosscheck``: the inputs over a revolution with speed and loads varying, and the
direct solver at each row's own inputs). ``--build`` makes them: pythonfmu FMUs for this
machine, native FMUs for every platform (``platforms="all"``, zig).

The importers (each skipped, and its rows saying "not available", when absent):

- fmpy: ``linkage-fmu check`` in a fresh process (``build_fmu.check_in_fresh_process``:
  step by step, each row the outputs of its own inputs, every output within each
  output's largest magnitude, plus fmpy's validation of the modelDescription);
- libcosim (libcosimpy): the job, host process and observer of ``tests/test_libcosim.py``
  (an override manipulator sets row k's inputs, ``step()`` runs t_k -> t_k + h, the
  last value observer then holds row k's outputs);
- fmusim (Reference-FMUs, C; ``--fmusim`` or ``$FMUSIM``) and the FMU Compliance Checker
  (``--fmucheck`` or ``$FMUCHECK``): both read ``<Model>_in.csv`` (step ``StepSize`` and
  stop ``StopTime`` of ``<Model>_ref.opt``) and sample the outputs *after* each step.
  Pairing: their row at t_{k+1} holds the outputs of the inputs they applied at t_k, so
  it is compared with ``_ref.csv`` row k; their first row (t_0, after initialization)
  with row 0. The inputs are recorded too (fmusim ``--output-variable``, fmuCheck
  ``-f``): a row's inputs, read back from the FMU, must be input row k's (the column
  "notes" gives the largest difference where it is not zero);
- fmusim's save/restore: a run to the middle of the revolution writes
  ``--final-fmu-state-file``; a second run from there (``--start-time``,
  ``--initial-fmu-state-file``) must give as its first row the first run's last, step on
  to the end, and equal the direct solver and the uninterrupted run. With
  ``--fmusim-fixed`` (``$FMUSIM_FIXED``) the flow runs once more with a fmusim whose
  FMU-state release is fixed: fmusim 0.0.39 (the last C fmusim, Reference-FMUs
  ``fmusim/FMIUtil.c``) calls ``fmi2FreeFMUstate(S, FMUState)`` /
  ``fmi3FreeFMUState(S, FMUState)`` after saving and after restoring, passing the state
  where its address is due; the FMUs recognise their state given so and free it with a
  Warning (before, they answered Error and fmusim stopped with exit status 3). The fix
  passes ``&FMUState``, and the FMUs answer OK;
- the project's C host ``tests/c_host/host.c`` (compiled and run as
  ``tests/test_platforms.py`` does): this machine's binary natively (pythonfmu FMUs in the
  README's environment), the x86_64 Windows DLL under wine, the aarch64 Linux library
  (FMI 3.0) under qemu-user. The host sets theta = 2 pi k / 72, omega = 10, alpha = 0,
  load = 5 at valueReferences 0..3, steps and reads; so it runs the FMUs whose inputs are
  exactly those four.

Writes ``build/benchmarks/importers.md`` (``--out FILE`` another file; ``--results``
the committed ``benchmarks/results/importers.md``), and ``importers.csv`` beside it:
one line per FMU and importer.
"""

from __future__ import annotations

import argparse
import csv
import os
import shutil
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET
import zipfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests")]  # build_fmu.py and the tests' helpers

from linkage_fmu import presets  # noqa: E402
from linkage_fmu.fmi import fmu_linkage  # noqa: E402
from linkage_fmu.fmi.check import compare  # noqa: E402

VERSIONS = (2, 3)
FLAVOURS = ("pythonfmu", "native")
EXAMPLES = sorted((ROOT / "examples").glob("*.toml"))
HOST_INPUTS = ["theta", "omega", "alpha", "load"]
LINUX, WINDOWS, AARCH64 = "x86_64-linux", "x86_64-windows (wine)", "aarch64-linux (qemu)"


@dataclass
class Restore:
    """fmusim's save/restore flow on one FMU: ``ok``, ``message`` (why not), the
    restored run's ``error`` vs the direct solver and its largest ``difference`` from
    the uninterrupted run (relative, as the errors)."""

    ok: bool
    message: str = ""
    error: float | None = None
    difference: float | None = None


@dataclass
class Outcome:
    """One importer's run of one FMU: ``status`` ok / refused / failed / not run,
    ``message`` why, ``error`` worst relative error vs the direct solver (and where),
    ``state`` the save/restore outcome per fmusim (:class:`Restore`), ``notes``;
    ``echo`` how far the inputs read back lie from the input rows and ``applied`` the
    error against the direct solver at the inputs read back (relative, as ``error``);
    ``floor`` the largest absolute error of outputs left out of ``error`` because
    their reference is zero but for rounding."""

    status: str
    message: str = ""
    error: float | None = None
    where: str = ""
    state: dict = field(default_factory=dict)
    notes: list = field(default_factory=list)
    echo: float | None = None
    applied: float | None = None
    floor: float | None = None


def build(dist: Path) -> None:
    from linkage_fmu.fmi import build_fmu, build_native_fmu, write_crosscheck

    for source in (*presets.names(), *map(str, EXAMPLES)):
        for version in VERSIONS:
            for flavour in FLAVOURS:
                out = dist / f"fmi{version}" / flavour
                fmu = (build_native_fmu(source, out, version, platforms="all")
                       if flavour == "native" else build_fmu(source, out, version))
                write_crosscheck(out, fmu_linkage(fmu))
                print(f"built {fmu}", file=sys.stderr)


def models(dist: Path) -> list[str]:
    names = {p.stem for p in (dist / "fmi2" / "native").glob("*.fmu")}
    order = [presets.preset(n).model for n in presets.names()]
    return [m for m in order if m in names] + sorted(names - set(order))


def number(text: str) -> float:
    """A CSV cell as a float; NaN for a string (fmuCheck -f prints string parameters)."""
    try:
        return float(text)
    except ValueError:
        return float("nan")


def read_table(path: Path) -> dict[str, np.ndarray]:
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header = [h.strip().strip('"') for h in rows[0]]
    values = np.array([[number(x) for x in r] for r in rows[1:] if r], dtype=float)
    return {h: values[:, j] for j, h in enumerate(header)}


def crosscheck(fmu: Path) -> tuple[dict, dict, float, float]:
    """The FMU's ``_in.csv`` and ``_ref.csv`` columns, step size and stop time."""
    stem = fmu.with_suffix("")
    opt = dict(line.split(",", 1) for line in
               Path(f"{stem}_ref.opt").read_text().splitlines() if line)
    return (read_table(Path(f"{stem}_in.csv")), read_table(Path(f"{stem}_ref.csv")),
            float(opt["StepSize"]), float(opt["StopTime"]))


def names_of(fmu: Path) -> tuple[list[str], list[str]]:
    """The FMU's input and output names, in valueReference order."""
    with zipfile.ZipFile(fmu) as archive:
        root = ET.fromstring(archive.read("modelDescription.xml"))
    variables = (root.iter("ScalarVariable") if root.get("fmiVersion") == "2.0"
                 else list(root.find("ModelVariables")))
    by = sorted(variables, key=lambda v: int(v.get("valueReference")))
    return ([v.get("name") for v in by if v.get("causality") == "input"],
            [v.get("name") for v in by if v.get("causality") == "output"])


def sampled_after_step(table: dict, inputs: dict, ref: dict, outputs: list[str],
                       input_names: list[str], mech=None, first: int = 0) -> Outcome:
    """An importer's table (fmusim, fmuCheck) against the reference: its row j >= 1
    holds the outputs of input row ``first + j - 1``; row 0 those of row 0 when the run
    starts at the beginning (initialization), else of row ``first - 1`` (a run from a
    restored state: the outputs of the saved run's last step)."""
    n = len(table["time"])
    rows = np.r_[max(first - 1, 0), first + np.arange(n - 1)]
    if rows[-1] >= len(ref["time"]):
        return Outcome("failed", f"{n} rows, more than the {len(ref['time'])} of the inputs")
    missing = [o for o in outputs if o not in table]
    if missing:
        return Outcome("failed", f"outputs missing from its table: {missing}")
    err, where = compare({o: table[o] for o in outputs}, {o: ref[o][rows] for o in outputs},
                         outputs)
    out = Outcome("ok", error=err, where=where)
    if input_names and all(i in table for i in input_names):
        out.echo = max(float(np.max(np.abs(table[i] - inputs[i][rows])) /
                             max(float(np.max(np.abs(inputs[i]))), 1e-300))
                       for i in input_names)
        if out.echo > 0:
            applied = mech.solve(*(table[i] for i in input_names), method="direct")
            out.applied = compare({o: table[o] for o in outputs}, applied, outputs)[0]
    return out


def last_line(text: str) -> str:
    lines = [ln.strip() for ln in text.splitlines() if ln.strip()]
    return lines[-1][:200] if lines else ""


# -- the importers ---------------------------------------------------------------------

def run_fmpy(fmu: Path) -> Outcome:
    from build_fmu import check_in_fresh_process

    result = check_in_fresh_process(fmu.resolve())
    if "crashed" in " ".join(result["validate"]):
        return Outcome("failed", last_line(result["validate"][0]))
    out = Outcome("ok", error=result["max_rel_error"], where=result["worst_output"])
    if result["validate"]:
        out.notes.append("fmpy validate: " + "; ".join(result["validate"]))
    if result.get("mismatched"):
        out.notes.append(f"{result['mismatched']} rows disagree with the solver on assembly")
    return out


def run_libcosim(fmus: list[Path], work: Path) -> list[Outcome]:
    try:
        from test_libcosim import cosim, job, observed
    except Exception as err:  # noqa: BLE001  (pytest skip or import error)
        return [Outcome("not available", f"libcosimpy: {err}")] * len(fmus)
    from linkage_fmu.fmi.check import reference

    jobs = [job(f) for f in fmus]
    try:
        results = cosim([j for j, _, _ in jobs], work)
    except AssertionError as err:
        return [Outcome("failed", last_line(str(err)))] * len(fmus)
    outcomes = []
    for (_, mech, u), result in zip(jobs, results):
        if "error" in result:
            message = result["error"].replace(str(fmus[len(outcomes)]), "<FMU>")
            outcomes.append(Outcome("refused", last_line(message)))
            continue
        if not all(result["ok"]):
            outcomes.append(Outcome("failed", next(e for e in result["errors"] if e)))
            continue
        names = list(mech.output_names + mech.diagnostic_names)
        err, where = compare(observed(result), reference(mech, u), names)
        outcomes.append(Outcome("ok", error=err, where=where))
    return outcomes


def fmusim_command(exe: str, fmu: Path, h: float, names: list[str], out: Path,
                   *options: str) -> list[str]:
    stem = fmu.with_suffix("")
    recorded = [a for n in names for a in ("--output-variable", n)]
    return [exe, "--interface-type", "cs", "--input-file", f"{stem}_in.csv",
            "--output-interval", repr(h), *recorded, *options, "--output-file", str(out),
            str(fmu)]


def run_fmusim(exe: str, fmu: Path, env: dict, work: Path) -> Outcome:
    inputs, ref, h, stop = crosscheck(fmu)
    input_names, outputs = names_of(fmu)
    out = work / f"{fmu.stem}.csv"
    run = subprocess.run(fmusim_command(exe, fmu, h, input_names + outputs, out,
                                        "--stop-time", repr(stop)),
                         env=env, capture_output=True, text=True, timeout=600)
    if run.returncode != 0 or not out.is_file():
        return Outcome("failed" if out.is_file() else "refused",
                       f"exit {run.returncode}: {last_line(run.stdout + run.stderr)}")
    result = sampled_after_step(read_table(out), inputs, ref, outputs, input_names,
                                fmu_linkage(fmu))
    n = len(read_table(out)["time"])
    if n != len(ref["time"]):
        result.notes.append(f"{n} rows for {len(ref['time'])} input rows")
    return result


def save_and_restore(exe: str, fmu: Path, env: dict, work: Path) -> Restore:
    """fmusim's flow: run to the middle saving the FMU state, run on from it."""
    inputs, ref, h, stop = crosscheck(fmu)
    input_names, outputs = names_of(fmu)
    mid = (len(ref["time"]) - 1) // 2
    t1 = float(inputs["time"][mid])
    state, first, second = work / f"{fmu.stem}.state", work / "first.csv", work / "second.csv"
    for p in (state, first, second):
        p.unlink(missing_ok=True)
    run1 = subprocess.run(fmusim_command(exe, fmu, h, outputs, first, "--stop-time", repr(t1),
                                         "--final-fmu-state-file", str(state)),
                          env=env, capture_output=True, text=True, timeout=600)
    said = []
    if run1.returncode != 0:
        said.append(f"save run: exit {run1.returncode}: `{last_line(run1.stdout + run1.stderr)}`"
                    + (" (its state file written)" if state.is_file() else ""))
    if not state.is_file():
        return Restore(False, "; ".join(said) or "no state file written")
    run2 = subprocess.run(fmusim_command(exe, fmu, h, outputs, second, "--start-time", repr(t1),
                                         "--stop-time", repr(stop),
                                         "--initial-fmu-state-file", str(state)),
                          env=env, capture_output=True, text=True, timeout=600)
    if run2.returncode != 0 or not second.is_file() or not first.is_file():
        said.append(f"restore run: exit {run2.returncode}: "
                    f"`{last_line(run2.stdout + run2.stderr)}`")
        return Restore(False, "; ".join(said))
    a, b = read_table(first), read_table(second)
    steps = len(b["time"]) - 1
    same_first = all(a[o][-1] == b[o][0] for o in outputs)
    times = np.allclose(b["time"], inputs["time"][mid:mid + len(b["time"])], rtol=0, atol=1e-12)
    result = sampled_after_step(b, inputs, ref, outputs, [], first=mid)
    full = read_table(work / f"{fmu.stem}.csv")
    difference = compare({o: b[o] for o in outputs},
                         {o: full[o][mid:mid + len(b["time"])] for o in outputs}, outputs)[0]
    if not same_first:
        said.append("its first row is not the saved run's last")
    if not times or steps != len(ref["time"]) - 1 - mid:
        said.append(f"{steps} steps from t = {t1!r}, not {len(ref['time']) - 1 - mid}")
    if result.status != "ok":
        said.append(result.message)
    return Restore(not said, "; ".join(said), result.error, difference)


def run_fmucheck(exe: str, fmu: Path, env: dict, work: Path) -> Outcome:
    inputs, ref, h, stop = crosscheck(fmu)
    input_names, outputs = names_of(fmu)
    out, log = work / f"{fmu.stem}.csv", work / f"{fmu.stem}.log"
    stem = fmu.with_suffix("")
    run = subprocess.run([exe, "-k", "cs", "-n", "0", "-h", repr(h), "-s", repr(stop),
                          "-i", f"{stem}_in.csv", "-f", "-l", "3", "-e", str(log),
                          "-o", str(out), str(fmu)],
                         env=env, capture_output=True, text=True, timeout=600)
    text = (log.read_text() if log.is_file() else "") + run.stdout + run.stderr
    fatal = [ln for ln in text.splitlines() if "[FATAL]" in ln or "[ERROR]" in ln]
    if run.returncode != 0 or not out.is_file() or out.stat().st_size == 0:
        return Outcome("refused", f"exit {run.returncode}: "
                       f"{' / '.join(f.strip() for f in fatal[-2:]) or last_line(text)}")
    table = read_table(out)
    n = len(table["time"])
    extra = n - len(ref["time"])
    if extra > 0:  # a last, tiny step where the summed time falls short of the stop time
        table = {k: v[:len(ref["time"])] for k, v in table.items()}
    result = sampled_after_step(table, inputs, ref, outputs, input_names, fmu_linkage(fmu))
    if extra:
        result.notes.append(f"{n} rows for {len(ref['time'])} input rows")
    warnings = [ln for ln in text.splitlines() if "[WARNING]" in ln]
    if warnings or fatal:
        result.notes.append(f"{len(warnings)} warnings, {len(fatal)} errors in its log: "
                            + " / ".join(x.strip()[:120] for x in (fatal + warnings)[:2]))
    return result


# -- the C host ------------------------------------------------------------------------

def host_table_error(stdout: str, fmu: Path, outputs: dict) -> tuple[float, str]:
    from test_platforms import LOAD, OMEGA, STEPS

    table = np.loadtxt(stdout.splitlines(), delimiter=",", ndmin=2)
    if table.shape != (STEPS, 1 + len(outputs)):
        raise ValueError(f"the host printed a {table.shape} table")
    mech = fmu_linkage(fmu)
    expected = mech.solve(table[:, 0], OMEGA, 0.0, LOAD, method="direct")
    got = {n: table[:, j] for j, n in enumerate(outputs, start=1)}
    scale = {n: float(np.max(np.abs(expected[n]))) for n in outputs}
    zero = [n for n in outputs if scale[n] < 1e-12 * max(scale.values())]
    err, where = compare(got, expected, [n for n in outputs if n not in zero])
    floor = max((float(np.max(np.abs(got[n] - expected[n]))) for n in zero), default=None)
    return err, where, floor


def run_c_host(fmu: Path, version: int, platform: str, prefix: list[str], exe: Path,
               env: dict, work: Path) -> Outcome:
    from test_platforms import LOAD, OMEGA, STEPS, host_arguments, windows_arguments

    input_names, _ = names_of(fmu)
    if input_names != HOST_INPUTS:
        return Outcome("not run", f"the host sets {', '.join(HOST_INPUTS)}; inputs "
                       f"{', '.join(input_names)}")
    folder = work / f"{fmu.stem}{version}"
    shutil.rmtree(folder, ignore_errors=True)
    with zipfile.ZipFile(fmu) as archive:
        archive.extractall(folder)
    arguments, outputs = (windows_arguments if platform == WINDOWS else host_arguments)(
        folder, version)
    run = subprocess.run([*prefix, str(exe), *arguments, str(STEPS), repr(OMEGA), repr(LOAD),
                          *map(str, outputs.values())], env=env, capture_output=True,
                         text=True, timeout=600)
    if run.returncode != 0:
        return Outcome("failed", f"exit {run.returncode}: {last_line(run.stderr)}")
    err, where, floor = host_table_error(run.stdout, fmu, outputs)
    return Outcome("ok", error=err, where=where, floor=floor)


def host_platforms(work: Path) -> dict[str, tuple]:
    """platform -> (command prefix, host executable, environment), or a reason string."""
    from test_c_host import compile_host
    from test_platforms import AARCH64_SYSROOT, qemu_aarch64, wine

    from linkage_fmu.ccompiler import find_cross_compiler
    from linkage_fmu.fmi.platforms import PLATFORMS

    found: dict[str, tuple | str] = {}
    (work / "linux").mkdir(parents=True, exist_ok=True)
    found[LINUX] = ([], compile_host(work / "linux"), {"PATH": "/usr/bin:/bin"})
    zig = find_cross_compiler() is not None
    loader = wine()
    if not zig or loader is None:
        found[WINDOWS] = "not available: needs zig and wine"
    else:
        (work / "windows").mkdir(exist_ok=True)
        env = {**os.environ, "WINEPREFIX": str(work / "wineprefix"), "WINEDEBUG": "-all",
               "WINEDLLOVERRIDES": "mscoree,mshtml="}
        found[WINDOWS] = ([loader], compile_host(work / "windows",
                                                 PLATFORMS["x86_64-windows"].zig), env)
    qemu = qemu_aarch64()
    if not zig or qemu is None:
        found[AARCH64] = "not available: needs zig, qemu-user and the aarch64 sysroot"
    else:
        (work / "aarch64").mkdir(exist_ok=True)
        found[AARCH64] = ([qemu, "-L", str(AARCH64_SYSROOT)],
                          compile_host(work / "aarch64", PLATFORMS["aarch64-linux"].zig),
                          {"PATH": "/usr/bin:/bin"})
    return found


# -- the table -------------------------------------------------------------------------

def summarize(outcomes: dict[str, Outcome], total: int) -> tuple[str, str, str, str]:
    """The table's cells of one importer x flavour x FMI version x platform."""
    ran = {m: o for m, o in outcomes.items() if o.status not in ("not run", "not available")}
    ok = {m: o for m, o in ran.items() if o.status == "ok"}
    if not ran:
        reasons = sorted({o.message for o in outcomes.values()})
        return f"{next(iter(outcomes.values())).status}: {'; '.join(reasons)}", "", "", ""
    if not ok:
        messages = sorted({o.message for o in ran.values()})
        runs = f"{next(iter(ran.values())).status} ({len(ran)}/{total}): " + "; ".join(
            f"`{m}`" for m in messages)
    else:
        runs = f"ok ({len(ok)}/{total})"
        bad = {m: o for m, o in ran.items() if o.status != "ok"}
        if bad:
            runs += "; " + "; ".join(f"{m}: {o.status}: `{o.message}`" for m, o in bad.items())
    worst = max(ok.items(), key=lambda mo: mo[1].error, default=None)
    error = f"{worst[1].error:.1e} ({worst[0]}.{worst[1].where})" if worst else ""
    state = []
    for name in dict.fromkeys(k for o in ok.values() for k in o.state):
        flows = {m: o.state[name] for m, o in ok.items() if name in o.state}
        good = [r for r in flows.values() if r.ok]
        text = f"{name}: {'ok' if len(good) == len(flows) else 'FAILED'} ({len(good)}/{len(flows)})"
        if good:
            text += (f", restored runs within {max(r.error for r in good):.1e} of the direct "
                     f"solver and {max(r.difference for r in good):.1e} of the uninterrupted run")
        failed = sorted({r.message for r in flows.values() if not r.ok})
        if failed:
            text += ": " + "; ".join(failed)
        state.append(text)
    notes = []
    echoes = [o.echo for o in ok.values() if o.echo is not None]
    if echoes and max(echoes) > 0:
        applied = max(o.applied for o in ok.values() if o.applied is not None)
        notes.append(f"inputs read back from the FMU differ from the input rows by up to "
                     f"{max(echoes):.1e} (the importer's input times drift); against the "
                     f"direct solver at the inputs read back: {applied:.1e}")
    elif echoes:
        notes.append("inputs read back from the FMU equal the input rows exactly")
    floors = {m: o.floor for m, o in ok.items() if o.floor is not None}
    if floors:
        notes.append("outputs zero but for rounding left out of the relative error (absolute "
                     f"error up to {max(floors.values()):.1e}; {', '.join(floors)})")
    notes += sorted({n for o in ran.values() for n in o.notes})
    not_run = [m for m, o in outcomes.items() if o.status in ("not run", "not available")]
    if not_run:
        notes.append(f"not run for {', '.join(not_run)}: {outcomes[not_run[0]].message}")
    return runs, error, "<br>".join(state), "<br>".join(notes)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--dist", type=Path, default=ROOT / "dist" / "importers")
    parser.add_argument("--build", action="store_true", help="build the FMUs first")
    parser.add_argument("--fmusim", default=os.environ.get("FMUSIM"))
    parser.add_argument("--fmusim-fixed", default=os.environ.get("FMUSIM_FIXED"))
    parser.add_argument("--fmucheck", default=os.environ.get("FMUCHECK"))
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--out", type=Path, default=ROOT / "build" / "benchmarks" / "importers.md",
                       help="the table to write (default: build/benchmarks/importers.md)")
    where.add_argument("--results", action="store_true",
                       help="write the committed benchmarks/results/importers.md")
    args = parser.parse_args(argv)
    if args.results:
        args.out = ROOT / "benchmarks" / "results" / "importers.md"
    if args.build:
        build(args.dist)
    from test_c_host import readme_environment

    dist = args.dist.resolve()
    names = models(dist)
    python_env = {"PATH": "/usr/local/bin:/usr/bin:/bin", **readme_environment()}
    clean_env = {"PATH": "/usr/local/bin:/usr/bin:/bin"}
    rows: list[tuple] = []
    lines: list[dict] = []
    work_root = Path(tempfile.mkdtemp(prefix="linkage_fmu_importers_"))
    hosts = host_platforms(work_root / "host")

    def record(importer, flavour, version, platform, outcomes):
        for model, o in outcomes.items():
            lines.append({"importer": importer, "flavour": flavour, "fmi": version,
                          "platform": platform, "model": model, "status": o.status,
                          "message": o.message, "max_rel_error": o.error,
                          "worst_output": o.where, "inputs_read_back": o.echo,
                          "error_at_inputs_read_back": o.applied, "zero_output_abs_error": o.floor,
                          "save_restore": " | ".join(
                              f"{k}: " + (f"ok, error {r.error:.2e}, {r.difference:.2e} from the "
                                          "uninterrupted run" if r.ok else r.message)
                              for k, r in o.state.items()),
                          "notes": " | ".join(o.notes)})
        rows.append((importer, flavour, f"{version}.0", platform,
                     *summarize(outcomes, len(outcomes))))
        print(f"{importer} {flavour} FMI {version} {platform}: {rows[-1][4]} {rows[-1][5]}",
              file=sys.stderr)

    try:
        for version in VERSIONS:
            for flavour in FLAVOURS:
                folder = dist / f"fmi{version}" / flavour
                fmus = {m: folder / f"{m}.fmu" for m in names}
                env = python_env if flavour == "pythonfmu" else clean_env
                work = work_root / f"fmi{version}-{flavour}"
                work.mkdir(parents=True)

                record("fmpy", flavour, version, LINUX,
                       {m: run_fmpy(f) for m, f in fmus.items()})
                record("libcosim (libcosimpy)", flavour, version, LINUX,
                       dict(zip(fmus, run_libcosim(list(fmus.values()), work / "cosim"))))
                if args.fmusim:
                    outcomes = {}
                    (work / "fmusim").mkdir()
                    for m, f in fmus.items():
                        o = outcomes[m] = run_fmusim(args.fmusim, f, env, work / "fmusim")
                        if o.status == "ok":
                            o.state["fmusim"] = save_and_restore(args.fmusim, f, env,
                                                                 work / "fmusim")
                            if args.fmusim_fixed:
                                o.state["fmusim, FMU state release fixed"] = save_and_restore(
                                    args.fmusim_fixed, f, env, work / "fmusim")
                    record("fmusim", flavour, version, LINUX, outcomes)
                else:
                    record("fmusim", flavour, version, LINUX,
                           {m: Outcome("not available", "no fmusim given") for m in fmus})
                if args.fmucheck:
                    (work / "fmucheck").mkdir()
                    record("FMU Compliance Checker", flavour, version, LINUX,
                           {m: run_fmucheck(args.fmucheck, f, env, work / "fmucheck")
                            for m, f in fmus.items()})
                else:
                    record("FMU Compliance Checker", flavour, version, LINUX,
                           {m: Outcome("not available", "no fmuCheck given") for m in fmus})

                for platform, found in hosts.items():
                    if flavour == "pythonfmu" and platform != LINUX:
                        outcomes = {m: Outcome("not run", "a pythonfmu FMU carries only the "
                                               "binary of the machine that built it")
                                    for m in fmus}
                    elif platform == AARCH64 and version == 2:
                        outcomes = {m: Outcome("not run", "FMI 2.0 names no aarch64 Linux "
                                               "platform") for m in fmus}
                    elif isinstance(found, str):
                        outcomes = {m: Outcome("not available", found) for m in fmus}
                    else:
                        prefix, exe, host_env = found
                        if flavour == "pythonfmu":
                            host_env = env
                        outcomes = {m: run_c_host(f, version, platform, prefix, exe,
                                                  host_env, work / "host") for m, f in
                                    fmus.items()}
                    record("C host (tests/c_host)", flavour, version, platform, outcomes)
    finally:
        found = hosts.get(WINDOWS)
        if isinstance(found, tuple):
            server = Path(found[0][0]).with_name("wineserver")
            if server.is_file():
                subprocess.run([str(server), "-k"], env=found[2], capture_output=True,
                               timeout=60)
        shutil.rmtree(work_root, ignore_errors=True)

    versions = [versions_line("fmusim", args.fmusim, "--version"),
                versions_line("fmusim, FMU state release fixed", args.fmusim_fixed, "--version"),
                versions_line("FMU Compliance Checker", args.fmucheck, "-v")]
    write_results(args.out, rows, lines, names, [v for v in versions if v])
    return 0


def versions_line(name: str, exe: str | None, flag: str) -> str:
    if not exe:
        return ""
    run = subprocess.run([exe, flag], capture_output=True, text=True, timeout=60)
    return f"{name}: `{last_line(run.stdout + run.stderr)}`"


def write_results(out: Path, rows: list[tuple], lines: list[dict], names: list[str],
                  versions: list[str]) -> None:
    header = ["importer", "flavour", "FMI", "platform", "runs?", "worst error vs direct",
              "state save/restore", "notes"]
    text = ["# Importers: which run the FMUs, and how well\n",
            f"Written by `tools/importers.py` from its runs of the {len(names)} FMUs of each "
            f"flavour and FMI version ({', '.join(names)}); each cell is from a run, or says "
            "why there was none. Errors: the largest difference from the direct solver "
            "over the run, relative to each output's largest magnitude (model.output of "
            "the worst). Per-FMU lines: `importers.csv`. How each importer is driven and "
            "how its rows are paired with the inputs: the docstring of "
            "`tools/importers.py`.\n", "Importers: " + "; ".join(versions) + ".\n",
            "| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    text += ["| " + " | ".join(str(c).replace("|", "\\|") for c in row) + " |" for row in rows]
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text("\n".join(text) + "\n")
    with open(out.with_suffix(".csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(lines[0]))
        writer.writeheader()
        writer.writerows(lines)


if __name__ == "__main__":
    sys.exit(main())

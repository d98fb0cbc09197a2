"""Build both FMUs of every shipped preset and example, then check each with fmpy.

    python build_fmu.py [--preset NAME | --linkage FILE] [--out DIR] [--no-check]
                        [--platforms all|LIST|host]

The linkages are the presets and the description files in ``examples/`` (the coupler
four-bar, the engine driven by its indicator diagram over 720 degrees, and, written as
joints and links, Jansen's and Klann's legs, the six-bar with a class III group, and
the linkages driven by several actuators: the five-bar robot, the dump body and the
excavator arm, whose check moves each driver about its start).

``DIR/<Model>.fmu`` (default ``dist``) is the pythonfmu FMU, built by
``linkage_fmu.fmi.build_fmu``: it bundles the installed ``linkage_fmu`` package, the
linkage's description file and a small slave script; its binary is the project's FMI
framework (``linkage_fmu/fmi/framework.c`` under ``fmi2.c``) in front of pythonfmu's
wrapper. ``DIR/native/<Model>.fmu`` is the native FMU, built by
``linkage_fmu.fmi.build_native_fmu``: the linkage's traced kernels in C behind the same
framework, no Python needed by the importing tool. Both are compiled with the system C
compiler; the native one also for win64 and darwin64 (universal: x86_64 and arm64) with
zig where the ``cross`` extra is installed (``--platforms`` chooses: ``host``, ``all`` or
names, as ``linkage-fmu build --native --platforms``). The check validates the
modelDescription (``fmpy validate``), runs a revolution with time-varying speed and
loads through fmpy (two revolutions for the engine's 720 degree cycle), compares every
output with the direct solver (within 1e-9 for the pythonfmu FMU and 1e-12 for the
native one), and writes the FMI cross-check files next to the FMU. One line per FMU;
the exit status is 1 if any check fails.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

#: flavour -> its folder under --out (the check's tolerance of each flavour:
#: linkage_fmu.fmi.check.TOLERANCE)
FLAVOURS = {"pythonfmu": ".", "native": "native"}


#: the example description files built besides the presets
EXAMPLES = sorted((Path(__file__).parent / "examples").glob("*.toml"))


def check_in_fresh_process(fmu: Path) -> dict:
    """Run ``linkage-fmu check`` on ``fmu`` in a new process outside the source tree:
    FMUs are never loaded into the process that built them."""
    with tempfile.TemporaryDirectory(prefix="linkage_fmu_check_") as cwd:
        run = subprocess.run([sys.executable, "-m", "linkage_fmu.cli", "check", "--json",
                              str(fmu)], cwd=cwd, capture_output=True, text=True)
    try:
        return json.loads(run.stdout.splitlines()[-1])
    except (IndexError, ValueError):
        return {"validate": [f"check crashed (exit {run.returncode}): {run.stderr[-2000:]}"],
                "max_rel_error": float("nan"), "worst_output": "", "steps": 0, "seconds": 0.0,
                "tolerance": float("nan"), "passed": False}


def native_platforms(spec: str | None) -> str | None:
    """The ``platforms`` of the native FMUs for ``--platforms spec``, saying on stderr
    which they are when ``spec`` is not given: all where zig's compiler is installed,
    else this machine's (None)."""
    from linkage_fmu.ccompiler import find_cross_compiler
    from linkage_fmu.fmi.platforms import folders, select

    if spec == "host":
        return None
    if spec is not None:
        return spec
    if find_cross_compiler() is None:
        print("build_fmu.py: native FMUs for this machine only (for win64 and darwin64 too: "
              'pip install "linkage-fmu[cross]")', file=sys.stderr)
        return None
    print(f"build_fmu.py: native FMUs for {', '.join(folders(select('all', 2), 2))} "
          "(zig for all but this machine)", file=sys.stderr)
    return "all"


def main(argv: list[str] | None = None) -> int:
    from linkage_fmu import presets
    from linkage_fmu.ccompiler import CompilerError
    from linkage_fmu.fmi import build_fmu, build_native_fmu, write_crosscheck

    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--preset", choices=presets.names(), action="append", default=[],
                        help="build only this preset (repeatable; default: all presets and "
                             "examples)")
    parser.add_argument("--linkage", type=Path, action="append", default=[],
                        help="build this description file (repeatable)")
    parser.add_argument("--out", type=Path, default=Path("dist"), help="output folder")
    parser.add_argument("--no-check", action="store_true", help="build without checking")
    parser.add_argument("--platforms", default=None, metavar="all|LIST|host",
                        help="the native FMUs' platforms (default: all where zig is installed, "
                             "the cross extra; else this machine's)")
    args = parser.parse_args(argv)
    platforms = native_platforms(args.platforms)

    failed = False
    chosen = [*args.preset, *map(str, args.linkage)] or [*presets.names(), *map(str, EXAMPLES)]
    total, start = len(chosen) * len(FLAVOURS), time.perf_counter()
    jobs = [(source, flavour) for source in chosen for flavour in FLAVOURS]
    for k, (source, flavour) in enumerate(jobs, 1):
        out = args.out / FLAVOURS[flavour]
        # the progress, on stderr: a native FMU for several platforms takes a while
        print(f"build_fmu.py [{k}/{total}, {time.perf_counter() - start:.0f} s]: the "
              f"{flavour} FMU of {source}", file=sys.stderr, flush=True)
        try:
            if flavour == "native":
                fmu = build_native_fmu(source, out, platforms=platforms)
            else:
                fmu = build_fmu(source, out)
        except (CompilerError, ValueError, OSError) as err:
            print(f"build_fmu.py: cannot build the {flavour} FMU of {source}: {err}",
                  file=sys.stderr)
            return 2
        if args.no_check:
            print(f"{fmu}: built")
            continue
        result = check_in_fresh_process(fmu.resolve())
        write_crosscheck(out, presets.linkage(source))
        ok = result["passed"]  # validated, within its flavour's tolerance, no mismatch
        failed |= not ok
        print(f"{fmu}: {'ok' if ok else 'FAILED'}: max relative error "
              f"{result['max_rel_error']:.2e} ({result['worst_output']}) over "
              f"{result['steps']} steps in {result['seconds']:.3f} s (tolerance "
              f"{result['tolerance']:g}); fmpy validate: "
              f"{'; '.join(result['validate']) or 'no problems'}")
    print(f"build_fmu.py: {total} FMUs in {time.perf_counter() - start:.0f} s",
          file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())

"""build_fmu.py: with zig's compiler and no system C compiler, a build whose compiler
warns is built (it was reported as a failure "with exit status 0"), its warning logged,
not shown."""

from __future__ import annotations

import importlib.util
import stat
import sys
import zipfile
from pathlib import Path

import pytest

from linkage_fmu import ccompiler

ROOT = Path(__file__).parents[1]


@pytest.mark.skipif(ccompiler.find_cross_compiler() is None,
                    reason="zig's C compiler not installed")
def test_zig_and_no_system_compiler_build_through_warnings(tmp_path, monkeypatch, caplog):
    """CC names no compiler, so every binary is zig's; zig's compiler is wrapped so that
    it also says a warning on stderr after compiling (zig itself warns on some hosts:
    Python.h redefining _XOPEN_SOURCE). Both FMUs of the scotch yoke are built (status
    0), each with its linux64 binary, and the warning is logged (INFO), not shown."""
    monkeypatch.setenv("CC", "no-such-c-compiler")
    zig = ccompiler.find_cross_compiler()
    wrapper = tmp_path / "zigcc"
    wrapper.write_text(f"#!{sys.executable}\n"
                       "import subprocess, sys\n"
                       f"status = subprocess.run({zig!r} + sys.argv[1:]).returncode\n"
                       "sys.stderr.write('x.c:1:1: warning: a warning of the wrapper\\n')\n"
                       "sys.exit(status)\n")
    wrapper.chmod(wrapper.stat().st_mode | stat.S_IXUSR)
    monkeypatch.setattr(ccompiler, "find_cross_compiler", lambda: [str(wrapper)])
    spec = importlib.util.spec_from_file_location("build_fmu", ROOT / "build_fmu.py")
    build_fmu = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(build_fmu)
    with caplog.at_level("INFO", logger="linkage_fmu.ccompiler"):
        status = build_fmu.main(["--preset", "scotch_yoke", "--out", str(tmp_path / "dist"),
                                 "--no-check", "--platforms", "host"])
    assert status == 0
    assert any("a warning of the wrapper" in r.getMessage() for r in caplog.records)
    for fmu in (tmp_path / "dist" / "ScotchYoke.fmu",
                tmp_path / "dist" / "native" / "ScotchYoke.fmu"):
        with zipfile.ZipFile(fmu) as archive:
            assert "binaries/linux64/ScotchYoke.so" in archive.namelist(), fmu

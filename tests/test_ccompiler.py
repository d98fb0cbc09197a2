"""The C compilers (``linkage_fmu.ccompiler``): a compilation fails on a non-zero exit
status or a missing library, never on warnings alone (with zig and no system compiler,
every warning used to fail the build "with exit status 0"); a compiler's output is shown
where it fails, and only logged where it succeeds."""

from __future__ import annotations

import ctypes
import stat
import sys
from pathlib import Path

import pytest

from linkage_fmu.ccompiler import (
    CompilerError,
    compile_shared,
    find_cross_compiler,
)

#: C that compiles and warns under -Wall -Wextra (an unused variable and parameter)
WARNS = "int twice(int x, int unused) { int spare; return 2 * x; }\n"


def fake_compiler(tmp_path: Path, status: int, writes: bool) -> Path:
    """A compiler that says "warning: ..." on stderr, writes the ``-o`` file (or not)
    and exits with ``status``."""
    script = tmp_path / "fakecc"
    script.write_text(
        f"#!{sys.executable}\n"
        "import sys\n"
        "out = sys.argv[sys.argv.index('-o') + 1]\n"
        "sys.stderr.write('k.c:1:5: warning: unused variable spare\\n')\n"
        f"if {writes}:\n"
        "    open(out, 'wb').write(b'library')\n"
        f"sys.exit({status})\n")
    script.chmod(script.stat().st_mode | stat.S_IXUSR)
    return script


def test_a_warning_is_logged_not_shown_and_not_a_failure(tmp_path, monkeypatch, capfd,
                                                         caplog):
    """Exit 0 with a library written: the library; the compiler's words go to the logger
    ``linkage_fmu.ccompiler`` at INFO, and nothing is written to stderr nor warned."""
    import warnings

    monkeypatch.setenv("CC", str(fake_compiler(tmp_path, 0, True)))
    source = tmp_path / "k.c"
    source.write_text(WARNS)
    with warnings.catch_warnings(), caplog.at_level("INFO", logger="linkage_fmu.ccompiler"):
        warnings.simplefilter("error")
        out = compile_shared([source], tmp_path / "k.so")
    assert out.read_bytes() == b"library"
    assert capfd.readouterr().err == ""
    (record,) = caplog.records
    assert record.levelname == "INFO" and "unused variable spare" in record.getMessage()


@pytest.mark.parametrize("status, writes, message", [
    (1, True, "failed with exit status 1"),
    (0, False, "exited with status 0 but wrote no k.so"),
])
def test_a_failure_is_an_error_with_the_compilers_output(tmp_path, monkeypatch, status,
                                                         writes, message):
    monkeypatch.setenv("CC", str(fake_compiler(tmp_path, status, writes)))
    source = tmp_path / "k.c"
    source.write_text(WARNS)
    with pytest.raises(CompilerError, match=message) as info:
        compile_shared([source], tmp_path / "k.so")
    assert "unused variable spare" in str(info.value)


@pytest.mark.skipif(find_cross_compiler() is None, reason="zig's C compiler not installed")
@pytest.mark.skipif(sys.platform != "linux" or ctypes.sizeof(ctypes.c_void_p) != 8,
                    reason="loads the library built for x86_64-linux")
def test_zig_builds_a_source_that_warns(tmp_path, caplog):
    """zig's compiler (the path taken without a system compiler) warns on WARNS and
    builds it: the library loads and twice(21, 0) is 42."""
    import platform

    if platform.machine() != "x86_64":
        pytest.skip("loads the library built for x86_64-linux")
    source = tmp_path / "k.c"
    source.write_text(WARNS)
    with caplog.at_level("INFO", logger="linkage_fmu.ccompiler"):
        out = compile_shared([source], tmp_path / "k.so", flags=("-O2", "-fPIC"),
                             target="x86_64-linux-gnu")
    assert ctypes.CDLL(str(out)).twice(21, 0) == 42
    assert any("unused" in r.getMessage() for r in caplog.records)

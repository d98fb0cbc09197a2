"""The C compilers: the system's, and zig's for other platforms (the ``cross`` extra);
asked to build shared libraries.

A compilation's output is shown only where it fails (in the :class:`CompilerError`'s
message). What a compiler says while it succeeds (its warnings) goes to the logger
``linkage_fmu.ccompiler`` at level INFO, which Python shows only where logging is set up
to (``logging.basicConfig(level=logging.INFO)``): a kernel compiled on first use, or an
FMU built, prints nothing of the compiler's.

Examples
--------
>>> import shutil
>>> cc = find_compiler()
>>> cc is None or shutil.which(cc) is not None
True
>>> zig = find_cross_compiler()
>>> zig is None or zig[-1] == "cc"
True
"""

from __future__ import annotations

import importlib.util
import logging
import os
import shutil
import subprocess
import sys
from collections.abc import Sequence
from pathlib import Path

from .errors import LinkageFmuError

#: compilers tried in order when ``CC`` is not set
CANDIDATES = ("cc", "gcc", "clang")


#: where a successful compilation's output (the compiler's warnings) goes
LOG = logging.getLogger(__name__)


class CompilerError(LinkageFmuError, RuntimeError):
    """No C compiler, or a compilation failed (the message holds its output)."""


def find_compiler() -> str | None:
    """Path of the C compiler: ``$CC`` if set, else the first of :data:`CANDIDATES`."""
    chosen = os.environ.get("CC")
    if chosen:
        return shutil.which(chosen)
    for name in CANDIDATES:
        path = shutil.which(name)
        if path:
            return path
    return None


def require_compiler(purpose: str) -> str:
    """Path of the C compiler, or a :class:`CompilerError` saying what needs one and how
    to get one.

    Examples
    --------
    >>> import os
    >>> saved = os.environ.get("CC")
    >>> os.environ["CC"] = "no-such-compiler-xyz"
    >>> try:
    ...     require_compiler("the FMU framework")
    ... except CompilerError as err:
    ...     print(str(err).split(";")[0])
    ... finally:
    ...     _ = os.environ.pop("CC") if saved is None else os.environ.update(CC=saved)
    the FMU framework needs a C compiler and none was found (CC = 'no-such-compiler-xyz')
    """
    path = find_compiler()
    if path is None:
        raise CompilerError(
            f"{purpose} needs a C compiler and none was found (CC = "
            f"{os.environ.get('CC', '')!r}); install one (Debian/Ubuntu: apt-get install gcc) "
            "or point the CC environment variable at it")
    return path


def find_cross_compiler() -> list[str] | None:
    """The command of zig's C compiler, which builds for other platforms than this one:
    ``python -m ziglang cc`` where the ``ziglang`` package is installed (the ``cross``
    extra: ``pip install "linkage-fmu[cross]"``), else ``zig cc`` where zig is on
    ``PATH``; None without either."""
    if importlib.util.find_spec("ziglang") is not None:
        return [sys.executable, "-m", "ziglang", "cc"]
    zig = shutil.which("zig")
    return [zig, "cc"] if zig else None


def require_cross_compiler(purpose: str) -> list[str]:
    """The command of zig's C compiler, or a :class:`CompilerError` saying what needs it
    and how to get it.

    Examples
    --------
    >>> try:
    ...     command = require_cross_compiler("building FourBar.dll for x86_64-windows")
    ... except CompilerError as err:
    ...     assert "linkage-fmu[cross]" in str(err)
    """
    command = find_cross_compiler()
    if command is None:
        raise CompilerError(
            f"{purpose} needs zig's C compiler, and neither the ziglang package nor zig on "
            "PATH was found; install the cross extra: pip install \"linkage-fmu[cross]\"")
    return command


def compile_shared(sources: Sequence[Path], output: Path, include: Sequence[Path] = (),
                   defines: Sequence[str] = (), flags: Sequence[str] = ("-O2",),
                   libraries: Sequence[str] = (), target: str | None = None) -> Path:
    """Compile C ``sources`` into the shared library ``output``: for this machine with the
    system compiler (``target`` None), or for zig's ``target`` (``x86_64-windows-gnu``,
    ...) with zig's compiler, where ``flags`` say what position-independent code the
    target needs (``-fPIC``).

    Raises
    ------
    CompilerError
        No compiler, or the compiler failed: a non-zero exit status, or no ``output``
        (its output is in the message).

    Notes
    -----
    A compiler that succeeds and writes to its error stream (warnings) has built the
    library: what it wrote is logged to :data:`LOG` at level INFO, not shown.
    """
    if target is None:
        compiler = [require_compiler(f"building {output.name}"), "-fPIC"]
    else:
        compiler = [*require_cross_compiler(f"building {output.name} for {target}"),
                    "-target", target]
    command = [*compiler, "-shared", "-std=c99", "-Wall", "-Wextra", *flags,
               *(f"-I{p}" for p in include), *(f"-D{d}" for d in defines),
               "-o", str(output), *map(str, sources), *(f"-l{lib}" for lib in libraries)]
    run = subprocess.run(command, capture_output=True, text=True)
    if run.returncode != 0:
        raise CompilerError(f"{' '.join(command)}\nfailed with exit status {run.returncode}:\n"
                            f"{run.stderr}")
    if not output.is_file():
        raise CompilerError(f"{' '.join(command)}\nexited with status 0 but wrote no "
                            f"{output.name}:\n{run.stderr}")
    if run.stderr.strip():
        LOG.info("%s was built, with warnings from the compiler:\n%s", output.name,
                 run.stderr.strip())
    return output

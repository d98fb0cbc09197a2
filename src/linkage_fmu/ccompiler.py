"""The system C compiler: found once, and asked to build shared libraries.

Examples
--------
>>> import shutil
>>> cc = find_compiler()
>>> cc is None or shutil.which(cc) is not None
True
"""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path
from typing import Sequence

#: compilers tried in order when ``CC`` is not set
CANDIDATES = ("cc", "gcc", "clang")


class CompilerError(RuntimeError):
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


def compile_shared(sources: Sequence[Path], output: Path, include: Sequence[Path] = (),
                   defines: Sequence[str] = (), flags: Sequence[str] = ("-O2",),
                   libraries: Sequence[str] = ()) -> Path:
    """Compile C ``sources`` into the shared library ``output``.

    Raises
    ------
    CompilerError
        No compiler, or the compiler failed (its output is in the message).
    """
    cc = require_compiler(f"building {output.name}")
    command = [cc, "-shared", "-fPIC", "-std=c99", "-Wall", "-Wextra", *flags,
               *(f"-I{p}" for p in include), *(f"-D{d}" for d in defines),
               "-o", str(output), *map(str, sources), *(f"-l{lib}" for lib in libraries)]
    run = subprocess.run(command, capture_output=True, text=True)
    if run.returncode != 0 or run.stderr.strip():
        raise CompilerError(f"{' '.join(command)}\nfailed with exit status {run.returncode}:\n"
                            f"{run.stderr}")
    return output

"""Compiled kernels: the C source of a trace, built once and cached on disk.

Arrays call a shared library through ctypes (one call for many states); one state calls
a small CPython extension module (``pykernel.c`` around the kernel: a call costs a
fraction of a microsecond, ctypes several). Each is keyed by the hash of its source, the compiler
and the flags, and kept in the user's cache folder (``$LINKAGE_FMU_CACHE``, else
``$XDG_CACHE_HOME/linkage_fmu`` or ``~/.cache/linkage_fmu``), never in the package. Where
no C compiler is found, :func:`load` returns None after one warning, and the caller keeps
its numpy path.
"""

from __future__ import annotations

import ctypes
import functools
import hashlib
import importlib.util
import os
import sys
import sysconfig
import tempfile
import warnings
from collections.abc import Callable
from pathlib import Path

import numpy as np

from ..ccompiler import CompilerError, compile_shared, find_compiler
from ..errors import InputError

#: flags of every build: IEEE operations as written (no contraction into FMA), no errno
FLAGS = ("-O2", "-ffp-contract=off", "-fno-math-errno")
_NO_UNDEFINED = "-Wl,--no-undefined"  # a missing vector function fails the link, not a call
#: builds of an array kernel, fastest first: vector loops on two threads with glibc's
#: vector sin, cos and atan2 (glibc >= 2.35), with its vector sin and cos only (AVX2
#: clones: its scalar atan2 is slow from AVX-512 code), with vector loops of scalar
#: calls, then one state after the other (with threads, then without)
ARRAY_OPTIONS = (
    (("-fopenmp", "-DLK_SIMD=1", "-DLK_MVEC_SINCOS=1", "-DLK_MVEC_ATAN2=1", _NO_UNDEFINED),
     ["mvec", "m"]),
    (("-fopenmp", "-DLK_SIMD=1", "-DLK_MVEC_SINCOS=1",
      '-DLK_TARGETS="default","arch=x86-64-v3"', _NO_UNDEFINED), ["mvec", "m"]),
    (("-fopenmp", "-DLK_SIMD=1"), ["m"]),
    (("-fopenmp",), ["m"]),
    ((), ["m"]),
)
#: compiled kernels kept in the cache folder; the least recently used go beyond this
#: (one file per plan of a linkage's structure: the parameters are kernel arguments)
CACHE_FILES = 1000


def cache_folder() -> Path:
    """Where compiled kernels are kept."""
    root = os.environ.get("LINKAGE_FMU_CACHE")
    if root:
        return Path(root)
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "linkage_fmu"


@functools.lru_cache(maxsize=1)
def _no_compiler_warning() -> None:
    warnings.warn("no C compiler found (cc, gcc, clang or $CC): array solves use numpy, "
                  "about 10x slower per state", RuntimeWarning, stacklevel=3)


@functools.cache
def warn_once(message: str) -> None:
    warnings.warn(message, RuntimeWarning, stacklevel=4)


@functools.cache
def _library(path: str):
    return ctypes.CDLL(path)


def build(source: str) -> Path | None:
    """The cached shared library of ``source``, compiled on first use; None without a
    compiler (after one warning)."""
    cc = find_compiler()
    if cc is None:
        _no_compiler_warning()
        return None
    key = hashlib.sha256("\0".join([source, cc, *FLAGS, *map(repr, ARRAY_OPTIONS)])
                         .encode()).hexdigest()[:24]
    target = cache_folder() / f"kernel-{key}.so"
    if target.is_file():
        return _used(target)
    target.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="linkage_fmu_kernel_") as tmp:
        c = Path(tmp) / "kernel.c"
        c.write_text(source)
        last = None
        for flags, libraries in ARRAY_OPTIONS:  # the fastest this system builds and loads
            try:
                compile_shared([c], Path(tmp) / "k.so", flags=(*FLAGS, *flags),
                               libraries=libraries)
                ctypes.CDLL(str(Path(tmp) / "k.so"))
                break
            except (CompilerError, OSError) as err:
                last = err
        else:
            raise CompilerError(f"no build of the array kernel succeeded: {last}")
        os.replace(Path(tmp) / "k.so", target)  # atomic: another process may race us
    _trim(target.parent)
    return target


def _used(path: Path) -> Path:
    """Mark a cached kernel as just used (its modification time orders the trimming)."""
    try:
        os.utime(path)
    except OSError:  # another process trimmed it: it is still loadable if loaded
        pass
    return path


def _trim(folder: Path, keep: int | None = None) -> None:
    """Remove the least recently used compiled kernels beyond ``keep`` (CACHE_FILES)."""
    keep = CACHE_FILES if keep is None else keep
    files = []
    for pattern in ("kernel-*.so", "_linkage_kernel_*.so"):
        for f in folder.glob(pattern):
            try:
                files.append((f.stat().st_mtime, f))
            except OSError:
                pass
    files.sort(reverse=True)
    for _, f in files[keep:]:
        try:
            f.unlink()  # a process that has it loaded keeps its mapping
        except OSError:
            pass


class ArrayKernel:
    """A compiled plan over arrays, with the parameter step's values ``frozen``:
    ``kernel(inputs, n)`` with ``inputs`` a list of float64 arrays of ``n`` entries or
    of one (broadcast) returns the outputs (a list of arrays) and the mask of states
    that passed every guard."""

    def __init__(self, path: Path, prefix: str, n_outputs: int, frozen=()):
        lib = _library(str(path))
        self._array = getattr(lib, f"{prefix}_array")
        self._array.restype = None
        self._array.argtypes = [ctypes.c_size_t, ctypes.c_void_p, ctypes.POINTER(ctypes.c_void_p),
                                ctypes.POINTER(ctypes.c_size_t), ctypes.POINTER(ctypes.c_void_p),
                                ctypes.c_void_p]
        self.n_outputs = n_outputs
        self.path = path
        self.frozen = np.array(frozen, dtype=np.float64).reshape(-1)
        self._q = np.concatenate([self.frozen, [0.0]])  # never an empty buffer

    def __call__(self, inputs: list, n: int, out: list | np.ndarray | None = None,
                 frozen=None):
        """The outputs and the mask; ``out``, if given, where the outputs go: a list of
        contiguous float64 arrays of ``n`` entries, or a float64 array of shape
        (outputs, ``n``) whose rows are contiguous and apart (returned as it is: its rows'
        addresses are one step apart, no per-array look-up); ``frozen``: another parameter
        set's values of the parameter step (:meth:`Kernel.prepare
        <linkage_fmu.kernels.Kernel>`)."""
        q = self._q if frozen is None else np.ascontiguousarray(
            np.append(np.asarray(frozen, dtype=np.float64), 0.0))
        if q.size != self._q.size:
            raise InputError(f"frozen has {q.size - 1} values, the kernel takes {self._q.size - 1}")
        arrays = [np.ascontiguousarray(a, dtype=np.float64) for a in inputs]
        x = (ctypes.c_void_p * len(arrays))(*(_address(a) for a in arrays))
        step = (ctypes.c_size_t * len(arrays))(*(0 if a.size == 1 else 1 for a in arrays))
        if out is None:  # one block, its rows the outputs
            block = np.empty((max(self.n_outputs, 1), n))
            y, out = _rows(block), list(block[:self.n_outputs])
        elif isinstance(out, np.ndarray):
            if (out.dtype != np.float64 or out.shape != (self.n_outputs, n)
                    or (n > 1 and out.strides[1] != 8) or (n and out.strides[0] < 8 * n)):
                raise InputError(f"out must be a float64 array of shape ({self.n_outputs}, "
                                 f"{n}) with contiguous rows apart, got {out.dtype} "
                                 f"{out.shape} with strides {out.strides}")
            y = _rows(out)
        else:
            y = (ctypes.c_void_p * max(len(out), 1))(*(_address(a) for a in out))
        ok = np.empty(n, dtype=np.uint8)
        self._array(n, _address(q), x, step, y, _address(ok))
        return out, ok.view(bool)


class SummaryKernel:
    """The compiled reductions ``<prefix>_summary`` of the shared library at ``path``
    (see :func:`~linkage_fmu.kernels.c_source.c_source`): calling it with a matrix of
    parameter sets and the inputs of ``n`` states returns one row per parameter set,
    ``width`` values each."""

    def __init__(self, path: Path, prefix: str, n_parameters: int, width: int):
        self._summary = getattr(_library(str(path)), f"{prefix}_summary")
        self._summary.restype = None
        self._summary.argtypes = [ctypes.c_size_t, ctypes.c_void_p, ctypes.c_size_t,
                                  ctypes.POINTER(ctypes.c_void_p),
                                  ctypes.POINTER(ctypes.c_size_t), ctypes.c_void_p,
                                  ctypes.c_int]
        self.n_parameters, self.width, self.path = n_parameters, width, path

    def __call__(self, parameters, inputs: list, n: int, threads: int = 1) -> np.ndarray:
        """The rows of the parameter sets ``parameters`` (an array of shape (sets,
        ``n_parameters``)) over the states ``inputs`` (float64 arrays of ``n`` entries
        or of one, broadcast), the sets shared between ``threads`` threads (the array
        kernel's OpenMP threads: a second set of threads would compete with theirs,
        which wait spinning after each call)."""
        p = np.ascontiguousarray(parameters, dtype=np.float64)
        if p.ndim != 2 or p.shape[1] != self.n_parameters:
            raise InputError(f"parameters must have shape (sets, {self.n_parameters}), got "
                             f"{p.shape}")
        if isinstance(threads, bool) or not isinstance(threads, int) or threads < 1:
            raise InputError(f"threads must be a positive integer, got {threads!r}")
        arrays = [np.ascontiguousarray(a, dtype=np.float64).reshape(-1) for a in inputs]
        for k, a in enumerate(arrays):
            if a.size not in (1, n):
                raise InputError(f"input {k} has {a.size} values, not 1 or {n}")
        x = (ctypes.c_void_p * max(len(arrays), 1))(*(_address(a) for a in arrays))
        step = (ctypes.c_size_t * max(len(arrays), 1))(*(0 if a.size == 1 else 1
                                                         for a in arrays))
        sets = p.shape[0]
        p = np.concatenate([p.reshape(-1), [0.0]])  # never an empty buffer
        out = np.empty((sets, self.width))
        self._summary(sets, _address(p), n, x, step, _address(out), min(threads, max(sets, 1)))
        return out


class TangentKernel:
    """The compiled forward-mode kernel ``<prefix>_tangent`` of the shared library at
    ``path``: calling it with the inputs and a direction of the inputs returns the
    outputs and their derivatives along it, or the code of the guard that fails."""

    def __init__(self, path: Path, prefix: str, n_inputs: int, n_outputs: int, frozen=()):
        self._tangent = getattr(_library(str(path)), f"{prefix}_tangent")
        self._tangent.restype = ctypes.c_int
        self._tangent.argtypes = [ctypes.c_void_p] * 5
        self.n_inputs, self.n_outputs = n_inputs, n_outputs
        self._q = np.concatenate([np.array(frozen, dtype=np.float64).reshape(-1), [0.0]])

    def __call__(self, x, dx) -> tuple | int:
        """``(y, dy)`` as arrays at the state ``x`` along ``dx`` (each ``n_inputs``
        floats), or the failed guard's code."""
        x = np.ascontiguousarray(x, dtype=np.float64)
        dx = np.ascontiguousarray(dx, dtype=np.float64)
        if x.shape != (self.n_inputs,) or dx.shape != (self.n_inputs,):
            raise InputError(f"x and dx must have {self.n_inputs} values each, got "
                             f"{x.shape} and {dx.shape}")
        y, dy = np.empty(self.n_outputs + 1), np.empty(self.n_outputs + 1)
        code = self._tangent(_address(self._q), _address(x), _address(dx), _address(y),
                             _address(dy))
        return code if code else (y[:-1], dy[:-1])


def _rows(block: np.ndarray):
    """The addresses of the rows of a 2-D array, as a C array of pointers."""
    base, step = _address(block), block.strides[0]
    k = max(block.shape[0], 1)
    return (ctypes.c_void_p * k)(*range(base, base + k * step, step)) if step else \
        (ctypes.c_void_p * k)(*([base] * k))


def _address(a: np.ndarray) -> int:
    # the array interface, not ndarray.ctypes, which builds a ctypes object per access
    return a.__array_interface__["data"][0]


def build_module(source: str):
    """The extension module (``pykernel.c`` around the generated ``source``) of a
    one-state kernel, compiled on first use and cached; None without a compiler (after
    one warning).

    Raises
    ------
    CompilerError
        The compiler failed (for example, no ``Python.h`` on this system).
    """
    cc = find_compiler()
    if cc is None:
        _no_compiler_warning()
        return None
    template = (Path(__file__).with_name("pykernel.c")).read_text()
    include = sysconfig.get_paths()["include"]
    key = hashlib.sha256("\0".join([source, template, cc, include, sys.version, *FLAGS])
                         .encode()).hexdigest()[:24]
    name = f"_linkage_kernel_{key}"
    target = cache_folder() / f"{name}{sysconfig.get_config_var('EXT_SUFFIX') or '.so'}"
    if target.is_file():
        _used(target)
    else:
        target.parent.mkdir(parents=True, exist_ok=True)
        if not (Path(include) / "Python.h").is_file():
            raise CompilerError(f"no Python.h in {include}: install this Python's development "
                                "headers (e.g. python3-dev) for compiled one-state kernels")
        with tempfile.TemporaryDirectory(prefix="linkage_fmu_kernel_") as tmp:
            (Path(tmp) / "kernel.c").write_text(source)
            (Path(tmp) / "pykernel.c").write_text(template)
            compile_shared([Path(tmp) / "pykernel.c"], Path(tmp) / "m.so",
                           include=[Path(tmp), Path(include)],
                           defines=[f"MODULE_INIT=PyInit_{name}"], flags=FLAGS,
                           libraries=["m"])
            os.replace(Path(tmp) / "m.so", target)  # atomic: another process may race us
        _trim(target.parent)
    return _load_module(name, str(target))


@functools.cache
def _load_module(name: str, path: str):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def scalar_kernel(module, frozen, checked, result: tuple = ()) -> Callable:
    """The compiled one-state kernel of ``module`` with the parameter step's values
    ``frozen``: ``kernel(theta, omega, alpha, *loads)`` returns the outputs as a tuple,
    or None where it does not take the state (an input that is not a finite float, a
    guard fails, or an output at a position in ``checked`` is not finite).

    With ``result = (cls, slots, values)`` it returns, where it takes the state, an
    instance of the class ``cls`` instead, made without calling its ``__init__``: the
    slot ``slots[0]`` holds the outputs unboxed (a read-only sequence of floats, one
    allocation where a tuple takes one per output; copied and pickled as a tuple) and
    ``slots[k]`` holds ``values[k - 1]`` (``pykernel.c``)."""
    flags = bytearray(module.n_outputs)
    for i in checked:
        flags[i] = 1
    return module.bind(np.asarray(frozen, dtype=np.float64).tobytes() + bytes(flags),
                       *result)

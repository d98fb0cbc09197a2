"""FMUs of any linkage: the variable table, one FMI 2.0 framework in C with two backends
(pythonfmu's wrapper running the Python slave, or the linkage's native C kernels),
building, and checking with fmpy against the direct solver."""

from .build import build_fmu
from .check import check_fmu, fmu_linkage, write_crosscheck
from .native import build_native_fmu

__all__ = ["build_fmu", "build_native_fmu", "check_fmu", "fmu_linkage", "write_crosscheck"]

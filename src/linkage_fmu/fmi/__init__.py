"""FMUs of any linkage: one variable table, one writer per generated artefact, one FMI
framework in C (FMI 2.0 and 3.0 adapters) with two backends (pythonfmu's wrapper running
the Python slave, or the linkage's native C kernels), building, running and checking with
fmpy against the direct solver."""

from .build import build_fmu, build_native_fmu
from .check import check_fmu, write_crosscheck
from .run import fmu_linkage, run_fmu

__all__ = ["build_fmu", "build_native_fmu", "check_fmu", "fmu_linkage", "run_fmu",
           "write_crosscheck"]

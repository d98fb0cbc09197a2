"""FMUs of any linkage: the variable table, the pythonfmu slave and the C guard in front
of its wrapper, building, and checking with fmpy against the direct solver."""

from .build import build_fmu
from .check import check_fmu, fmu_linkage, write_crosscheck

__all__ = ["build_fmu", "check_fmu", "fmu_linkage", "write_crosscheck"]

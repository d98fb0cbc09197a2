"""Linkages as data: description files, their expressions, and building a Mechanism."""

from ..expressions import Expression
from .description import Description, DescriptionError

__all__ = ["Description", "DescriptionError", "Expression"]

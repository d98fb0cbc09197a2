"""Linkages as data: description files, their expressions, and building a Mechanism."""

from .description import Description, DescriptionError
from ..expressions import Expression

__all__ = ["Description", "DescriptionError", "Expression"]

"""The base class of the force elements and the checks they share (kept apart so that the
element families in several modules can all build on it without importing each other)."""

from __future__ import annotations

from typing import Any

from duhamel._protocols import Model
from duhamel._validate import dof_index, finite_float

__all__ = ["Element", "nonneg", "pair", "positive"]


class Element:
    """Base class of the elements."""

    #: Whether the element carries internal variables (a hysteretic element): the
    #: integrator commits them once per accepted step.
    _path_dependent: bool = False

    def _validate(self, system: Model) -> None:  # pragma: no cover - abstract
        raise NotImplementedError

    def _spec(self) -> tuple:  # pragma: no cover - abstract
        raise NotImplementedError


def nonneg(value: Any, name: str) -> float:
    """`value` as a finite float >= 0, or ValueError naming `name`."""
    v = finite_float(value, name)
    if v < 0:
        raise ValueError(f"`{name}` must be >= 0, got {v}")
    return v


def positive(value: Any, name: str) -> float:
    """`value` as a finite float > 0, or ValueError naming `name`."""
    v = finite_float(value, name)
    if v <= 0:
        raise ValueError(f"`{name}` must be > 0, got {v}")
    return v


def pair(i: int, j: int | None, system: Model) -> None:
    """Checks the dofs `i` and `j` (None: ground) of a two-node element."""
    dof_index(i, "i", system.n_dof)
    if j is not None:
        dof_index(j, "j", system.n_dof)
        if j == i:
            raise ValueError(f"`j` must differ from `i` (both {i}); use j=None for ground")

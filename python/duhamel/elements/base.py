"""The base class of the force elements and the checks they share (kept apart so that the
element families in several modules can all build on it without importing each other)."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel._engine.protocols import Model
from duhamel._engine.specs import element as core_element
from duhamel._engine.validate import dof_index, finite_float

__all__ = [
    "Deformation",
    "Element",
    "TwoAxis",
    "nonneg",
    "pair",
    "pair_stiffness",
    "positive",
]


class Element:
    """Base class of the elements."""

    #: Whether the element carries internal variables (a hysteretic element): the
    #: integrator commits them once per accepted step.
    _path_dependent: bool = False

    def _validate(self, system: Model) -> None:  # pragma: no cover - abstract
        raise NotImplementedError

    def _spec(self) -> tuple:  # pragma: no cover - abstract
        raise NotImplementedError

    def _passive(self) -> bool:
        """Whether the element only stores or dissipates the work done on it (a spring with
        a potential bounded below by 0, a hysteretic or viscous device, a stop): the growth
        guard of `duhamel.Semianalytic` then bounds the response's energy by what the loads
        supply. False unless an element says so (a Python element, a journal bearing, a
        rub with friction on a spinning shaft can supply energy)."""
        return False

    def _linear(self) -> tuple[tuple[int, ...], NDArray[np.float64]] | None:
        """The element's linear stiffness part ``(dofs, k0)``: the local matrix ``k0``
        (positive semidefinite, at the global `dofs`) that the linear background takes over
        (``Semianalytic(linear_parts="background")``), or None when it has none."""
        return None

    def _tangent_bound(self) -> tuple[float, float] | None:
        """Bounds ``(k, c)`` on the norms of the element's tangent stiffness and damping
        matrices as a pseudo-force over any state it can reach, for the substep rule of the
        static-correction coordinates (``duhamel._engine.correction``); None (the default)
        when the tangent has no bound (a cubic or higher term, a Python function, a device
        whose bound is not known)."""
        return None

    def _directions(self) -> list[tuple[int, int | None]]:
        """The directions the element's force acts along, each ``(i, j)``: the deformation
        ``x_i - x_j`` (``j`` None: ``x_i`` alone). By default each of its dofs alone (the
        dofs of its core element)."""
        return [(int(d), None) for d in core_element(self._spec()).dofs]

    def _remainder_spec(self) -> tuple:
        """The core spec of the element without its linear part (what stays a
        pseudo-force); by default the element minus ``k0 x``."""
        linear = self._linear()
        assert linear is not None
        k0 = linear[1]
        return ("shifted", self._spec(), k0, np.zeros_like(k0))


class Deformation:
    """Mixin of the elements that act on one deformation ``x_i - x_j`` (``j`` None: to the
    ground): their fields ``i`` and ``j`` say which."""

    i: int
    j: int | None

    def _validate(self, system: Model) -> None:
        pair(self.i, self.j, system)

    def _directions(self) -> list[tuple[int, int | None]]:
        return [(int(self.i), None if self.j is None else int(self.j))]


class TwoAxis:
    """Mixin of the elements that act on the two transverse dofs ``dof_x``, ``dof_y`` of one
    node (contacts, bearings, isolators)."""

    dof_x: int
    dof_y: int

    def _validate(self, system: Model) -> None:
        dof_index(self.dof_x, "dof_x", system.n_dof)
        dof_index(self.dof_y, "dof_y", system.n_dof)
        if self.dof_x == self.dof_y:
            raise ValueError(f"`dof_y` must differ from `dof_x` (both {self.dof_x})")


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


def pair_stiffness(i: int, j: int | None, k: float) -> tuple[tuple[int, ...], NDArray[np.float64]]:
    """The dofs and local stiffness matrix of a spring `k` from `i` to `j` (None: ground)."""
    if j is None:
        return (int(i),), np.array([[k]])
    return (int(i), int(j)), np.array([[k, -k], [-k, k]])

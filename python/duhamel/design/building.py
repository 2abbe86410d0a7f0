"""An isolated building as a design study sees it (:class:`Building`): the model, its levels
from the base level up, the storey heights, the directions of the ground motion and the
isolators; the seismic weights ASCE 7-22 chapter 17 asks for follow from the mass."""

from __future__ import annotations

from collections.abc import Sequence
from functools import cached_property
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.validate import as_float_array, dof_index
from duhamel.constants import STANDARD_GRAVITY
from duhamel.participation import direction_vector

__all__ = ["Building"]


def _levels(levels: Any, n_dof: int, name: str) -> tuple[tuple[int, ...], ...]:
    """Each level as a tuple of dofs (one per column line), checked."""
    if levels is None or isinstance(levels, str) or len(levels) < 2:
        raise ValueError(f"`{name}` must list the base level and at least one floor above it")
    out = []
    for k, level in enumerate(levels):
        group = [level] if np.ndim(level) == 0 else list(np.asarray(level).ravel())
        if not group:
            raise ValueError(f"`{name}[{k}]` lists no dof")
        out.append(tuple(dof_index(d, f"{name}[{k}]", n_dof) for d in group))
    return tuple(out)


class Building:
    """An isolated building for :class:`~duhamel.design.Study` and
    :func:`~duhamel.design.asce7.isolated_elf`.

    Parameters
    ----------
    system : duhamel.System
        The model without ground motion (its isolators among its elements).
    levels : sequence
        Along x, from the base level (the first level above the isolation interface) to
        the roof: each level's dof, or its dofs (one per column line, the same number on
        every level).
    heights : sequence of float
        The storey heights above the base level (m), ``len(levels) - 1`` of them.
    x : array_like or str, optional
        The influence vector of the x direction over the dofs, or a dof label (``"ux"``
        for a model imported from OpenSees). Default: ones on the dofs of `levels`.
    y, levels_y : optional
        The same for the y direction of a 3-D model.
    isolators : sequence of int, optional
        Which of ``system.elements`` are the isolation system (default: all).
    name : str, optional
        For the report.
    g : float, optional
        The acceleration of gravity that turns masses into weights (standard gravity).

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> from duhamel.design import Building
    >>> m = np.diag([2e5, 1e5, 1e5])  # base level and two floors, kg
    >>> k = 1e8 * np.array([[1.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    >>> s = duhamel.System(m, k, zeta=0.03)
    >>> s = s.add(duhamel.elements.FrictionPendulum(0, radius=2.0, mu=0.05, weight=4e5 * 9.80665))
    >>> b = Building(s, levels=[0, 1, 2], heights=[3.5, 3.5])
    >>> round(b.weight / 9.80665), round(b.weight_above / 9.80665)
    (400000, 200000)
    """

    def __init__(
        self,
        system: Any,
        levels: Sequence[Any],
        heights: ArrayLike,
        *,
        x: ArrayLike | str | None = None,
        y: ArrayLike | str | None = None,
        levels_y: Sequence[Any] | None = None,
        isolators: Sequence[int] | None = None,
        name: str = "isolated building",
        g: float = STANDARD_GRAVITY,
    ) -> None:
        n = int(system.n_dof)
        self.system = system
        self.levels = _levels(levels, n, "levels")
        h = as_float_array(heights, "heights", ndim=1)
        if h.size != len(self.levels) - 1 or not np.all(np.isfinite(h)) or np.any(h <= 0):
            raise ValueError(
                f"`heights` must be {len(self.levels) - 1} positive storey heights (one per "
                f"storey above the base level), got {h.tolist()}"
            )
        self.heights = h
        lines = {len(level) for level in self.levels}
        if len(lines - {1}) > 1:
            raise ValueError("`levels`: every level must list the same number of column lines")
        self.levels_y = None if levels_y is None else _levels(levels_y, n, "levels_y")
        if (y is None) != (self.levels_y is None):
            raise ValueError("a 3-D building needs both `y` and `levels_y`")
        if self.levels_y is not None and len(self.levels_y) != len(self.levels):
            raise ValueError("`levels_y` must list as many levels as `levels`")
        labels = getattr(system, "dof_labels", None)
        if x is None:
            rx = np.zeros(n)
            rx[[d for level in self.levels for d in level]] = 1.0
        else:
            rx = direction_vector(x, n, labels)
        self.x = rx
        self.y = None if y is None else direction_vector(y, n, labels)
        count = len(system.elements)
        chosen = list(range(count)) if isolators is None else list(isolators)
        self.isolators = tuple(dof_index(i, "isolators", count) for i in chosen)
        if not self.isolators:
            raise ValueError("`isolators`: the building has no isolator (no element chosen)")
        self.name = str(name)
        self.g = float(g)

    def __repr__(self) -> str:
        kind = "3-D" if self.is_3d else "2-D"
        return (
            f"Building({self.name!r}, {kind}, {len(self.levels)} levels, "
            f"{len(self.isolators)} isolators, W = {self.weight:.6g} N)"
        )

    @property
    def is_3d(self) -> bool:
        """Whether the building has a y direction too."""
        return self.y is not None

    @property
    def isolator_elements(self) -> list[Any]:
        """The isolators, as elements of the system."""
        return [self.system.elements[i] for i in self.isolators]

    def _mr(self, r: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.asarray(self.system.M @ r, dtype=np.float64).ravel()

    @cached_property
    def weight(self) -> float:
        """``W``, the seismic weight above the isolation interface: ``g r^T M r`` along x."""
        return self.g * float(self.x @ self._mr(self.x))

    @cached_property
    def level_weights(self) -> NDArray[np.float64]:
        """Each level's weight along x, ``g`` times the mass ``M r`` on its dofs; for a model
        whose masses sit on the level dofs (lumped), they add up to :attr:`weight`."""
        mr = self._mr(self.x)
        return self.g * np.array([mr[list(level)].sum() for level in self.levels])

    @cached_property
    def weight_above(self) -> float:
        """``W_s``, the weight above the base level: :attr:`weight` less the base level's."""
        return self.weight - float(self.level_weights[0])

    @property
    def elevations(self) -> NDArray[np.float64]:
        """Each level's height above the base level (m), 0 for the base level."""
        return np.concatenate([[0.0], np.cumsum(self.heights)])

    def directions(self) -> list[tuple[str, NDArray[np.float64], tuple[tuple[int, ...], ...]]]:
        """``(name, influence vector, levels)`` per direction: x, and y for a 3-D model."""
        out = [("x", self.x, self.levels)]
        if self.y is not None and self.levels_y is not None:
            out.append(("y", self.y, self.levels_y))
        return out

"""Geometric (P-Delta) stiffness of gravity loads: linear, so it is part of the stiffness.

A storey (or a leaning column) of height ``h`` carrying the compressive gravity load ``P``
softens the lateral stiffness by ``P / h`` between its top and bottom dofs: the overturning
moment ``P (x_i - x_j)`` of the displaced load is a lateral force ``P / h (x_i - x_j)`` that
pushes further. Being linear, it is added to the linear stiffness exactly, ``K - K_g``
(:meth:`duhamel.System.add_geometric_stiffness`), never stepped as a pseudo-force: the modes,
the exact modal step and the direct integrators all see it.
"""

from __future__ import annotations

from dataclasses import KW_ONLY, dataclass

import numpy as np
from numpy.typing import NDArray

from duhamel._engine.spellings import old_spellings
from duhamel._engine.validate import dof_index, finite_float

__all__ = ["PDelta"]


@old_spellings(positional=("i", "j", "P", "height"), defaults={"P": 0.0, "height": 1.0})
@dataclass(frozen=True)
class PDelta:
    """The P-Delta (leaning-column) stiffness of a storey: ``-P / height`` between dofs `i`
    and `j` (or `i` and the ground when `j` is None): ``PDelta(i, j=None, *, P, height)``.

    Parameters
    ----------
    i, j : int, int or None
        The lateral dofs at the top and the bottom of the storey (`j` None: fixed base).
    P : float
        The gravity load the storey carries, > 0 in compression (a tension ``P < 0``
        stiffens).
    height : float
        The storey height, > 0.

    Added with :meth:`duhamel.System.add`, it becomes part of the system's stiffness (its
    geometric stiffness ``K_g = P / height (e_i - e_j)(e_i - e_j)^T`` is subtracted, see
    :meth:`duhamel.System.add_geometric_stiffness`).

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> storey = duhamel.System(np.eye(1), [[100.0]])
    >>> storey = storey.add(duhamel.elements.PDelta(0, None, P=300.0, height=10.0))
    >>> storey.K.tolist()
    [[70.0]]
    """

    i: int
    j: int | None = None
    _: KW_ONLY
    P: float
    height: float

    def __post_init__(self) -> None:
        finite_float(self.P, "P")
        h = finite_float(self.height, "height")
        if h <= 0:
            raise ValueError(f"`height` must be > 0, got {h}")

    def matrix(self, n_dof: int) -> NDArray[np.float64]:
        """The geometric stiffness ``K_g`` (dense, ``n_dof x n_dof``) this storey subtracts."""
        i = dof_index(self.i, "i", n_dof)
        e = np.zeros(n_dof)
        e[i] = 1.0
        if self.j is not None:
            j = dof_index(self.j, "j", n_dof)
            if j == i:
                raise ValueError(f"`j` must differ from `i` (both {i})")
            e[j] = -1.0
        return float(self.P) / float(self.height) * np.outer(e, e)

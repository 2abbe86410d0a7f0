"""What the rotor's loads and plots need of a rotor and of a Campbell diagram.

:class:`~duhamel.rotor.Rotor` satisfies :class:`RotorModel` and :class:`DofNumbering`,
:class:`~duhamel.rotor.Campbell` satisfies :class:`CampbellData`. The loads and plots are
annotated with these protocols, so they need not import the modules that define the rotor
and the Campbell diagram (which import them): the dependency runs one way only.
"""

from __future__ import annotations

from typing import Any, Protocol

import numpy as np
from numpy.typing import NDArray

__all__ = ["CampbellData", "DofNumbering", "HasMass", "RotorModel"]


class DofNumbering(Protocol):
    """A model whose degrees of freedom are numbered by node and direction."""

    def dof(self, node: int, direction: str | int) -> int:
        """Global index of a node's degree of freedom (``"x"``, ``"y"``, ...)."""
        ...


class HasMass(Protocol):
    """Global matrices with (at least) a mass matrix ``M``."""

    @property
    def M(self) -> NDArray[np.float64]:
        """Mass matrix, ``(n_dof, n_dof)``."""
        ...


class RotorModel(DofNumbering, Protocol):
    """A rotor as its loads see it: the dof numbering, the size and the mass matrix.

    Examples
    --------
    >>> from duhamel.rotor import STEEL, Rotor, Shaft
    >>> from duhamel.rotor._protocols import RotorModel
    >>> def last_y(rotor: RotorModel) -> tuple[int, int]:
    ...     return rotor.dof(1, "y"), rotor.n_dof
    >>> last_y(Rotor([Shaft(1.0, 0.05, material=STEEL)]))
    (5, 8)
    """

    @property
    def n_dof(self) -> int:
        """Number of degrees of freedom."""
        ...

    def matrices(self, speed: float = 0.0) -> HasMass:
        """Global matrices at spin speed `speed` (rad/s)."""
        ...


class CampbellData(Protocol):
    """Frequencies against speed with their whirl, as :func:`~duhamel.rotor.plot_campbell`
    draws them."""

    @property
    def speeds(self) -> NDArray[np.float64]:
        """Spin speeds (rad/s), shape ``(n_speeds,)``."""
        ...

    @property
    def frequencies(self) -> NDArray[np.float64]:
        """Damped natural frequencies (rad/s), shape ``(n_speeds, n_columns)``."""
        ...

    @property
    def whirl(self) -> NDArray[Any]:
        """Whirl labels (``"forward"``, ...), shape ``(n_speeds, n_columns)``."""
        ...

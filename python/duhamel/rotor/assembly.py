"""Generic assembly: every component's local matrices scattered to the global dofs.

A rotor component (:class:`~duhamel.rotor.Shaft`, :class:`~duhamel.rotor.Disk`,
:class:`~duhamel.rotor.Bearing`, or anything else with the same five methods, see
:class:`Component`) owns its matrices ``M, K(speed), C(speed), G`` on its local dofs and
names those dofs in :meth:`Component.dof_mapping`, as ROSS's elements do. The rotor places
each component at a node (:class:`Placed`) and :func:`assemble` loops over them.

The rotor keeps two groups apart, because its damping and the engine's couplings treat them
differently: the *structure* (shafts, disks: symmetric, speed-independent) and the
*supports* (bearings: possibly non-symmetric, possibly tabulated against the speed).
:class:`Assembly` holds both, the speed-independent supports assembled once.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Literal, NamedTuple, Protocol

import numpy as np
from numpy.typing import NDArray

from duhamel.rotor.dofs import global_dofs

__all__ = ["Assembly", "Component", "Placed", "RotorMatrices", "assemble"]

MatrixName = Literal["M", "K", "C", "G"]


class RotorMatrices(NamedTuple):
    """The rotor's matrices: ``M x'' + (C + speed G) x' + K x = f``.

    ``K`` includes the full bearing stiffness (cross-coupled terms too), ``C`` the structural
    damping (Rayleigh or modal) and the full bearing damping; ``G`` is the gyroscopic matrix
    per unit speed (skew-symmetric).
    """

    M: NDArray[np.float64]
    K: NDArray[np.float64]
    C: NDArray[np.float64]
    G: NDArray[np.float64]


class Component(Protocol):
    """What the assembly needs of a rotor component: its local matrices and dof names."""

    def dof_mapping(self) -> dict[str, int]:
        """Local dof labels (``"x_0"``, ``"theta_y_1"``) and their local indices."""
        ...

    def M(self) -> NDArray[np.float64]:
        """Local mass matrix."""
        ...

    def K(self, speed: float = 0.0) -> NDArray[np.float64]:
        """Local stiffness matrix at spin speed `speed` (rad/s)."""
        ...

    def C(self, speed: float = 0.0) -> NDArray[np.float64]:
        """Local damping matrix at spin speed `speed` (rad/s)."""
        ...

    def G(self) -> NDArray[np.float64]:
        """Local gyroscopic matrix per unit speed."""
        ...


@dataclass(frozen=True, eq=False)
class Placed:
    """A component placed on the rotor: `dofs` are the global indices of its local dofs.

    Examples
    --------
    >>> from duhamel.rotor import Bearing
    >>> Placed.at(Bearing(2, 1e6, 1e6), first_node=2).dofs.tolist()
    [8, 9]
    """

    component: Component
    dofs: NDArray[np.intp]

    @classmethod
    def at(cls, component: Component, first_node: int) -> Placed:
        """`component` with its local node 0 at rotor node `first_node`."""
        return cls(component, global_dofs(component.dof_mapping(), first_node))

    def local(self, name: MatrixName, speed: float = 0.0) -> NDArray[np.float64]:
        """The component's matrix `name` (``"M"``, ``"K"``, ``"C"`` or ``"G"``)."""
        c = self.component
        if name == "M":
            return c.M()
        if name == "G":
            return c.G()
        return c.K(speed) if name == "K" else c.C(speed)


def assemble(
    placed: Iterable[Placed],
    n_dof: int,
    name: MatrixName,
    speed: float = 0.0,
    *,
    out: NDArray[np.float64] | None = None,
) -> NDArray[np.float64]:
    """The global matrix `name`: each component's local matrix added at its dofs, in order.

    Parameters
    ----------
    placed : iterable of Placed
        The components and their global dofs.
    n_dof : int
        Size of the global matrix.
    name : {"M", "K", "C", "G"}
        Which matrix.
    speed : float
        Spin speed (rad/s) for ``K`` and ``C``.
    out : ndarray, optional
        Keyword only. Add into this ``(n_dof, n_dof)`` array instead of zeros (in place).

    Returns
    -------
    ndarray, shape (n_dof, n_dof)

    Examples
    --------
    >>> from duhamel.rotor import Bearing
    >>> from duhamel.rotor.assembly import Placed, assemble
    >>> b = Bearing(1, kxx=1e6, kyy=2e6, kxy=5e4)
    >>> K = assemble([Placed.at(b, b.node)], n_dof=8, name="K")
    >>> K[4:6, 4:6].tolist()
    [[1000000.0, 50000.0], [0.0, 2000000.0]]
    """
    target = np.zeros((n_dof, n_dof)) if out is None else out
    for p in placed:
        target[np.ix_(p.dofs, p.dofs)] += p.local(name, speed)
    return target


def _speed_dependent(p: Placed) -> bool:
    return bool(getattr(p.component, "is_speed_dependent", False))


class Assembly:
    """A rotor's global matrices, assembled once: the structure's ``M``, ``K``, ``G`` and the
    supports' ``K``, ``C`` (those that depend on the speed at each call of
    :meth:`supports_at`). Arrays are read-only.

    Parameters
    ----------
    structure : sequence of Placed
        Shafts and disks (their ``C`` is not used: structural damping is the rotor's).
    supports : sequence of Placed
        Bearings (their ``M``, ``G`` are not used).
    n_dof : int
        Number of global dofs.

    Examples
    --------
    >>> from duhamel.rotor import STEEL, Bearing, Shaft
    >>> from duhamel.rotor.assembly import Assembly, Placed
    >>> a = Assembly([Placed.at(Shaft(0.5, 0.05, material=STEEL), 0)],
    ...              [Placed.at(Bearing(0, 1e7, 1e7), 0)], n_dof=8)
    >>> a.M.shape, float(a.supports_at(0.0)[0][0, 0])
    ((8, 8), 10000000.0)
    """

    def __init__(self, structure: Sequence[Placed], supports: Sequence[Placed], n_dof: int):
        self.n_dof = n_dof
        self.M = assemble(structure, n_dof, "M")
        self.K_structure = assemble(structure, n_dof, "K")
        self.G = assemble(structure, n_dof, "G")
        constant = [p for p in supports if not _speed_dependent(p)]
        #: The supports whose coefficients depend on the spin speed.
        self.varying: tuple[Placed, ...] = tuple(p for p in supports if _speed_dependent(p))
        self.K_support = assemble(constant, n_dof, "K")
        self.C_support = assemble(constant, n_dof, "C")
        for a in (self.M, self.K_structure, self.G, self.K_support, self.C_support):
            a.setflags(write=False)

    def supports_at(self, speed: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The supports' full stiffness and damping ``(K_b, C_b)`` at `speed` (rad/s): the
        constant part (read-only) when no support depends on the speed."""
        if not self.varying:
            return self.K_support, self.C_support
        kb = assemble(self.varying, self.n_dof, "K", speed, out=self.K_support.copy())
        cb = assemble(self.varying, self.n_dof, "C", speed, out=self.C_support.copy())
        return kb, cb

    def k_sym(self, kb: NDArray[np.float64]) -> NDArray[np.float64]:
        """``K_sym``: the structure's stiffness plus the symmetric part of `kb`."""
        return self.K_structure + (kb + kb.T) / 2.0

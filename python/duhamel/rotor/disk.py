"""A rigid disk: its mass and gyroscopic matrices on its node's four degrees of freedom."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from duhamel._engine.validate import nonneg_float, positive_float
from duhamel.rotor.dofs import DIRECTIONS, local_dof_mapping, node_index
from duhamel.rotor.material import Material

__all__ = ["Disk"]


@dataclass(frozen=True)
class Disk:
    """A rigid disk at a node: mass `mass` (kg), polar and diametral moments of inertia `Ip`,
    `Id` (kg m^2) about its centre of mass, which sits on the shaft axis at the node.

    On the node's ``(x, y, theta_x, theta_y)`` the disk adds ``M_d = diag(m, m, Id, Id)`` and
    the gyroscopic matrix ``G_d`` with ``G_d[theta_x, theta_y] = Ip = -G_d[theta_y, theta_x]``
    (Friswell et al. 2010, chapter 5): ``Id theta_x'' + speed Ip theta_y' = M_x`` and
    ``Id theta_y'' - speed Ip theta_x' = M_y``.

    Examples
    --------
    >>> from duhamel.rotor import Disk
    >>> disk = Disk(node=2, mass=20.0, Ip=0.2, Id=0.1)
    >>> disk.matrices()[1][2:, 2:].tolist()
    [[0.0, 0.2], [-0.2, 0.0]]

    As every rotor component, it owns its matrices on its local dofs (:meth:`dof_mapping`),
    which the rotor scatters to the node's global dofs:

    >>> list(disk.dof_mapping()), disk.M().diagonal().tolist(), bool(disk.K().any())
    (['x_0', 'y_0', 'theta_x_0', 'theta_y_0'], [20.0, 20.0, 0.1, 0.1], False)
    """

    node: int
    mass: float
    Ip: float
    Id: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "node", node_index(self.node))
        object.__setattr__(self, "mass", positive_float(self.mass, "mass"))
        object.__setattr__(self, "Ip", nonneg_float(self.Ip, "Ip"))
        object.__setattr__(self, "Id", nonneg_float(self.Id, "Id"))

    @classmethod
    def from_geometry(
        cls,
        node: int,
        width: float,
        outer_diameter: float,
        inner_diameter: float,
        material: Material,
    ) -> Disk:
        """A uniform annular disk (a short hollow cylinder) of the given width (axial length).

        ``m = rho pi (Do^2 - Di^2) w / 4``, ``Ip = m (Do^2 + Di^2) / 8``,
        ``Id = Ip / 2 + m w^2 / 12``.

        Examples
        --------
        >>> from duhamel.rotor import STEEL, Disk
        >>> d = Disk.from_geometry(2, width=0.07, outer_diameter=0.28, inner_diameter=0.05,
        ...                        material=STEEL)
        >>> round(d.mass, 3), round(d.Ip, 5), round(d.Id, 5)
        (32.59, 0.32956, 0.17809)
        """
        w = positive_float(width, "width")
        do = positive_float(outer_diameter, "outer_diameter")
        di = nonneg_float(inner_diameter, "inner_diameter")
        if di >= do:
            raise ValueError(
                f"`inner_diameter` must be below `outer_diameter` = {do:g}, got {di:g}"
            )
        if not isinstance(material, Material):
            raise TypeError(f"`material` must be a Material, got {type(material).__name__}")
        m = material.rho * np.pi * (do**2 - di**2) * w / 4.0
        ip = m * (do**2 + di**2) / 8.0
        return cls(node, float(m), float(ip), float(ip / 2.0 + m * w**2 / 12.0))

    def matrices(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The 4 x 4 mass and gyroscopic matrices on the node's ``(x, y, theta_x, theta_y)``."""
        M = np.diag([self.mass, self.mass, self.Id, self.Id])
        G = np.zeros((4, 4))
        G[2, 3], G[3, 2] = self.Ip, -self.Ip
        return M, G

    # ------------------------------------------------------------------ as a rotor component
    def dof_mapping(self) -> dict[str, int]:
        """Local dofs ``x_0, y_0, theta_x_0, theta_y_0`` (local node 0 is :attr:`node`)."""
        return local_dof_mapping(1, tuple(DIRECTIONS))

    def M(self) -> NDArray[np.float64]:
        """Mass matrix ``diag(m, m, Id, Id)`` on :meth:`dof_mapping`."""
        return self.matrices()[0]

    def K(self, speed: float = 0.0) -> NDArray[np.float64]:
        """Stiffness on :meth:`dof_mapping`: none (a rigid disk), zeros."""
        return np.zeros((4, 4))

    def C(self, speed: float = 0.0) -> NDArray[np.float64]:
        """Damping on :meth:`dof_mapping`: none, zeros."""
        return np.zeros((4, 4))

    def G(self) -> NDArray[np.float64]:
        """Gyroscopic matrix per unit speed on :meth:`dof_mapping` (skew-symmetric)."""
        return self.matrices()[1]

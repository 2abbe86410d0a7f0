"""Rigid disks and bearings (linear stiffness and damping, optional cubic law and rub)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel._validate import finite_float, nonneg_float, positive_float
from duhamel.rotor.material import Material

__all__ = ["Bearing", "Disk"]


def _node(value: Any) -> int:
    if isinstance(value, bool | np.bool_) or not isinstance(value, int | np.integer):
        raise TypeError(f"`node` must be an integer, got {type(value).__name__}")
    if value < 0:
        raise ValueError(f"`node` must be >= 0, got {value}")
    return int(value)


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
    >>> Disk(node=2, mass=20.0, Ip=0.2, Id=0.1).matrices()[1][2:, 2:].tolist()
    [[0.0, 0.2], [-0.2, 0.0]]
    """

    node: int
    mass: float
    Ip: float
    Id: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "node", _node(self.node))
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


def _contact(value: Any) -> tuple[float, float, float] | None:
    if value is None:
        return None
    try:
        parts = tuple(value)
    except TypeError:
        raise TypeError(
            "`contact` must be (clearance, stiffness) or (clearance, stiffness, friction), "
            f"got {type(value).__name__}"
        ) from None
    if len(parts) not in (2, 3):
        raise ValueError(
            "`contact` must be (clearance, stiffness) or (clearance, stiffness, friction), "
            f"got {len(parts)} values"
        )
    clearance = nonneg_float(parts[0], "contact clearance")
    stiffness = positive_float(parts[1], "contact stiffness")
    friction = nonneg_float(parts[2], "contact friction") if len(parts) == 3 else 0.0
    return clearance, stiffness, friction


@dataclass(frozen=True)
class Bearing:
    """A bearing (or seal, or stator) acting on a node's translations ``(x, y)``.

    The linear force on the shaft is ``-[[kxx, kxy], [kyx, kyy]] (x, y) - [[cxx, cxy],
    [cyx, cyy]] (x', y')`` (N/m, N s/m): ``kxy`` is the force in x per unit y displacement,
    as the paper's ``k12``. Cross-coupled terms need not be symmetric (``kxy = -kyx`` is the
    destabilising cross-coupling of fluid films and seals).

    Optional nonlinear parts, added as :mod:`duhamel.elements`:

    * the paper's cubic law (its section 4.4), ``r_i = k_ii x_i beta (x_i / x_stat)^2`` on
      ``i = x, y``: a ``Cubic(dof, k3 = k_ii beta / x_stat^2)`` on each translation.
      ``x_stat`` (m) is a reference deflection; with ``x_stat=None`` the rotor uses the
      magnitude of the bearing's vertical static deflection under its own weight in the linear
      model (``g = 9.81`` m/s^2, weight along ``-y``), as the paper does.
    * ``contact = (clearance, stiffness[, friction])``: a radial rub
      (:class:`duhamel.elements.Contact`) of the node against a stator with that radial
      clearance (m), contact stiffness (N/m) and Coulomb friction coefficient.

    Parameters
    ----------
    node : int
        The rotor node.
    kxx, kyy : float
        Direct stiffnesses, ``>= 0``.
    kxy, kyx : float
        Cross-coupled stiffnesses.
    cxx, cyy : float
        Direct damping, ``>= 0``.
    cxy, cyx : float
        Cross-coupled damping.
    beta : float
        Cubic-law coefficient (0: linear).
    x_stat : float, optional
        Reference deflection of the cubic law, ``> 0``.
    contact : tuple, optional
        ``(clearance, stiffness)`` or ``(clearance, stiffness, friction)``.

    Examples
    --------
    >>> from duhamel.rotor import Bearing
    >>> b = Bearing(0, kxx=1e9, kyy=1e9, kxy=1e7, kyx=-1e7, beta=0.1, x_stat=2e-5)
    >>> b.stiffness.tolist()
    [[1000000000.0, 10000000.0], [-10000000.0, 1000000000.0]]
    >>> [e.k3 for e in b.elements(dof_x=0, dof_y=1, x_stat=b.x_stat)]
    [2.4999999999999997e+17, 2.4999999999999997e+17]
    """

    node: int
    kxx: float
    kyy: float
    kxy: float = 0.0
    kyx: float = 0.0
    cxx: float = 0.0
    cyy: float = 0.0
    cxy: float = 0.0
    cyx: float = 0.0
    beta: float = 0.0
    x_stat: float | None = None
    contact: tuple[float, float, float] | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "node", _node(self.node))
        for name in ("kxx", "kyy", "cxx", "cyy"):
            object.__setattr__(self, name, nonneg_float(getattr(self, name), name))
        for name in ("kxy", "kyx", "cxy", "cyx", "beta"):
            object.__setattr__(self, name, finite_float(getattr(self, name), name))
        if self.x_stat is not None:
            object.__setattr__(self, "x_stat", positive_float(self.x_stat, "x_stat"))
        object.__setattr__(self, "contact", _contact(self.contact))

    @property
    def stiffness(self) -> NDArray[np.float64]:
        """``[[kxx, kxy], [kyx, kyy]]``."""
        return np.array([[self.kxx, self.kxy], [self.kyx, self.kyy]])

    @property
    def damping(self) -> NDArray[np.float64]:
        """``[[cxx, cxy], [cyx, cyy]]``."""
        return np.array([[self.cxx, self.cxy], [self.cyx, self.cyy]])

    @property
    def is_nonlinear(self) -> bool:
        """Whether the bearing has a cubic law or a rub contact."""
        return self.beta != 0.0 or self.contact is not None

    def elements(self, dof_x: int, dof_y: int, x_stat: float | None = None) -> list[Any]:
        """The nonlinear parts as :mod:`duhamel.elements` on the global dofs `dof_x`, `dof_y`.

        Parameters
        ----------
        dof_x, dof_y : int
            Global indices of the node's x and y translations.
        x_stat : float, optional
            Reference deflection of the cubic law (default: the bearing's own `x_stat`);
            needed when ``beta != 0``.

        Returns
        -------
        list
            ``Cubic`` elements on x and y (when ``beta != 0``) and a ``Contact`` (when
            `contact` is given).
        """
        from duhamel.elements import Contact, Cubic

        out: list[Any] = []
        if self.beta != 0.0:
            ref = self.x_stat if x_stat is None else positive_float(x_stat, "x_stat")
            if ref is None:
                raise ValueError(f"the cubic law of the bearing at node {self.node} needs `x_stat`")
            out.append(Cubic(dof_x, self.kxx * self.beta / ref**2))
            out.append(Cubic(dof_y, self.kyy * self.beta / ref**2))
        if self.contact is not None:
            clearance, stiffness, friction = self.contact
            out.append(Contact(dof_x, dof_y, clearance, stiffness, friction))
        return out

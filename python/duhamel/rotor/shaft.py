"""Timoshenko shaft element (rotary inertia, shear deformation, gyroscopic matrix).

Element degrees of freedom (Friswell et al. 2010, chapter 5)::

    q_e = [x1, y1, theta_x1, theta_y1, x2, y2, theta_x2, theta_y2]

with right-handed rotations about the fixed x and y axes, so that in pure bending
``theta_y = dx/dz`` and ``theta_x = -dy/dz``. In each bending plane the element is the
*interdependent interpolation* Timoshenko element (the shape functions are the exact static
solutions of an end-loaded Timoshenko beam; Friswell et al. 2010, chapter 5; Przemieniecki
1968), with the shear parameter ``Phi = 12 E I / (kappa G A L^2)``. The matrices are integrated
exactly (four-point Gauss-Legendre rule on polynomials of degree <= 6).
"""

from __future__ import annotations

from dataclasses import KW_ONLY, dataclass
from functools import cached_property

import numpy as np
from numpy.typing import NDArray

from duhamel._engine.validate import finite_float, positive_float
from duhamel.rotor.dofs import DIRECTIONS, local_dof_mapping
from duhamel.rotor.material import Material

__all__ = ["Shaft", "cowper_shear_coefficient"]

_GAUSS_X, _GAUSS_W = np.polynomial.legendre.leggauss(4)
#: Local planar dofs [w1, phi1, w2, phi2] in the x-z plane: (x1, theta_y1, x2, theta_y2).
_XZ = np.zeros((4, 8))
_XZ[[0, 1, 2, 3], [0, 3, 4, 7]] = 1.0
#: ... and in the y-z plane, where the section rotation dy/dz - shear is -theta_x.
_YZ = np.zeros((4, 8))
_YZ[[0, 1, 2, 3], [1, 2, 5, 6]] = [1.0, -1.0, 1.0, -1.0]


def cowper_shear_coefficient(nu: float, diameter_ratio: float = 0.0) -> float:
    """Cowper's (1966) shear coefficient of a hollow circular section.

    ``kappa = 6 (1 + nu) (1 + m^2)^2 / [(7 + 6 nu)(1 + m^2)^2 + (20 + 12 nu) m^2]`` with
    ``m = d_inner / d_outer``; for a solid section ``6 (1 + nu) / (7 + 6 nu)`` (0.886 for
    ``nu = 0.3``). This is the coefficient Friswell et al. (2010) use.
    (Cowper, J. Appl. Mech. 33 (1966) 335-340.)

    Parameters
    ----------
    nu : float
        Poisson's ratio.
    diameter_ratio : float
        Inner over outer diameter, in ``[0, 1)``.

    Returns
    -------
    float
        The shear coefficient ``kappa``.

    Examples
    --------
    >>> from duhamel.rotor import cowper_shear_coefficient
    >>> round(cowper_shear_coefficient(0.3), 6)
    0.886364
    >>> round(cowper_shear_coefficient(0.3, 0.5), 4)
    0.6202
    """
    m2 = diameter_ratio**2
    return (
        6.0
        * (1.0 + nu)
        * (1.0 + m2) ** 2
        / ((7.0 + 6.0 * nu) * (1.0 + m2) ** 2 + (20.0 + 12.0 * nu) * m2)
    )


def _planar_shapes(L: float, phi: float, xi: float) -> tuple[NDArray[np.float64], ...]:
    """Shape functions of the planar Timoshenko element at ``xi = z / L``.

    Returns the rows ``w``, ``dw/dz``, ``phi`` (section rotation) and ``d phi/dz`` on the local
    dofs ``[w1, phi1, w2, phi2]``. The shear strain ``dw/dz - phi`` is constant,
    ``Phi / ((1 + Phi) L) * [-1, -L/2, 1, -L/2]``.
    """
    d = 1.0 + phi
    w = (1.0 / d) * np.array(
        [
            1.0 - 3.0 * xi**2 + 2.0 * xi**3 + phi * (1.0 - xi),
            L * (xi - 2.0 * xi**2 + xi**3 + 0.5 * phi * (xi - xi**2)),
            3.0 * xi**2 - 2.0 * xi**3 + phi * xi,
            L * (-(xi**2) + xi**3 - 0.5 * phi * (xi - xi**2)),
        ]
    )
    dw = (1.0 / d) * np.array(
        [
            (-6.0 * xi + 6.0 * xi**2 - phi) / L,
            1.0 - 4.0 * xi + 3.0 * xi**2 + 0.5 * phi * (1.0 - 2.0 * xi),
            (6.0 * xi - 6.0 * xi**2 + phi) / L,
            -2.0 * xi + 3.0 * xi**2 - 0.5 * phi * (1.0 - 2.0 * xi),
        ]
    )
    rot = (1.0 / d) * np.array(
        [
            6.0 * (xi**2 - xi) / L,
            1.0 - 4.0 * xi + 3.0 * xi**2 + phi * (1.0 - xi),
            -6.0 * (xi**2 - xi) / L,
            -2.0 * xi + 3.0 * xi**2 + phi * xi,
        ]
    )
    drot = (1.0 / (d * L)) * np.array(
        [
            6.0 * (2.0 * xi - 1.0) / L,
            -4.0 + 6.0 * xi - phi,
            -6.0 * (2.0 * xi - 1.0) / L,
            -2.0 + 6.0 * xi + phi,
        ]
    )
    return w, dw, rot, drot


@dataclass(frozen=True)
class Shaft:
    """A uniform (hollow) circular shaft element of length `L` between two nodes.

    Shafts are listed in order along the rotor axis: shaft ``i`` joins nodes ``i`` and
    ``i + 1`` (see :class:`~duhamel.rotor.Rotor`).

    Parameters
    ----------
    L : float
        Length (m), ``> 0``.
    outer_diameter : float
        Outer diameter (m), ``> 0``.
    inner_diameter : float
        Inner (bore) diameter (m), ``0 <= inner_diameter < outer_diameter``.
    material : Material
        Keyword only.
    shear_coefficient : float, optional
        Keyword only. Default: Cowper's coefficient of the hollow circular section
        (:func:`cowper_shear_coefficient`). Hutchinson's (2001) value for a solid circle is
        ``6 (1 + nu)^2 / (7 + 12 nu + 4 nu^2)`` (0.925 for ``nu = 0.3`` against Cowper's
        0.886).
    shear_deformation : bool
        Keyword only. False gives ``Phi = 0`` (no shear deformation).
    rotary_inertia : bool
        Keyword only. False drops the rotary inertia and with it the gyroscopic matrix. With
        ``shear_deformation=False`` too, the element is the Euler-Bernoulli (Hermite cubic)
        beam element.

    Examples
    --------
    >>> from duhamel.rotor import STEEL, Shaft
    >>> shaft = Shaft(0.25, 0.05, material=STEEL)
    >>> round(shaft.mass, 4), round(shaft.kappa, 4), round(shaft.phi, 5)
    (3.8337, 0.8864, 0.088)
    >>> M, K, G = shaft.matrices()
    >>> M.shape, bool((G + G.T == 0).all())
    ((8, 8), True)

    As every rotor component, it owns its matrices on its local dofs (:meth:`dof_mapping`;
    local node 0 is the rotor node the shaft starts at):

    >>> list(shaft.dof_mapping())[3:5], bool((shaft.K() == K).all())
    (['theta_y_0', 'x_1'], True)
    """

    L: float
    outer_diameter: float
    inner_diameter: float = 0.0
    _: KW_ONLY
    material: Material
    shear_coefficient: float | None = None
    shear_deformation: bool = True
    rotary_inertia: bool = True

    def __post_init__(self) -> None:
        object.__setattr__(self, "L", positive_float(self.L, "L"))
        do = positive_float(self.outer_diameter, "outer_diameter")
        di = finite_float(self.inner_diameter, "inner_diameter")
        if not 0.0 <= di < do:
            raise ValueError(
                f"`inner_diameter` must be in [0, outer_diameter) = [0, {do:g}), got {di!r}"
            )
        object.__setattr__(self, "outer_diameter", do)
        object.__setattr__(self, "inner_diameter", di)
        if not isinstance(self.material, Material):
            raise TypeError(
                f"`material` must be a duhamel.rotor.Material, got {type(self.material).__name__}"
            )
        if self.shear_coefficient is not None:
            object.__setattr__(
                self,
                "shear_coefficient",
                positive_float(self.shear_coefficient, "shear_coefficient"),
            )
        for name in ("shear_deformation", "rotary_inertia"):
            if not isinstance(getattr(self, name), bool | np.bool_):
                raise TypeError(f"`{name}` must be a bool, got {getattr(self, name)!r}")
        # A geometry whose matrices over- or underflow (L = 1e300 m, 1e-300 m) is refused
        # here, with its parameters named, not later as an OverflowError in the assembly.
        try:
            with np.errstate(over="raise", divide="raise", invalid="raise"):
                finite = all(np.all(np.isfinite(m)) for m in self._element)
        except (ArithmeticError, FloatingPointError):
            finite = False
        if not finite:
            raise ValueError(
                f"`L` = {self.L:g} m with `outer_diameter` = {do:g} m gives non-finite element "
                "matrices (the stiffness scales as 1/L^3, the mass as L): use a length and a "
                "diameter of a physical shaft, in metres"
            )

    # ------------------------------------------------------------------ section properties
    @property
    def area(self) -> float:
        """Cross-section area ``A = pi (do^2 - di^2) / 4`` (m^2)."""
        return float(np.pi * (self.outer_diameter**2 - self.inner_diameter**2) / 4.0)

    @property
    def second_moment(self) -> float:
        """Diametral second moment of area ``I = pi (do^4 - di^4) / 64`` (m^4); the polar
        moment is ``2 I``."""
        return float(np.pi * (self.outer_diameter**4 - self.inner_diameter**4) / 64.0)

    @property
    def mass(self) -> float:
        """Mass ``rho A L`` (kg)."""
        return self.material.rho * self.area * self.L

    @property
    def kappa(self) -> float:
        """Shear coefficient (given, or Cowper's)."""
        if self.shear_coefficient is not None:
            return float(self.shear_coefficient)
        nu = self.material.nu
        assert nu is not None
        return cowper_shear_coefficient(nu, self.inner_diameter / self.outer_diameter)

    @property
    def phi(self) -> float:
        """Shear parameter ``Phi = 12 E I / (kappa G A L^2)`` (0 without shear deformation)."""
        if not self.shear_deformation:
            return 0.0
        G = self.material.G
        assert G is not None
        return (
            12.0 * self.material.E * self.second_moment / (self.kappa * G * self.area * self.L**2)
        )

    # ------------------------------------------------------------------ element matrices
    @cached_property
    def _planar(self) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """Planar mass, stiffness and rotary-inertia integral ``R = int N_phi^T N_phi dz``."""
        L, phi = self.L, self.phi
        EI, rho = self.material.E * self.second_moment, self.material.rho
        kga = 0.0
        if self.shear_deformation:
            G = self.material.G
            assert G is not None
            kga = self.kappa * G * self.area
        mt, k, r = np.zeros((4, 4)), np.zeros((4, 4)), np.zeros((4, 4))
        for x, wq in zip(_GAUSS_X, _GAUSS_W, strict=True):
            xi, wz = 0.5 * (x + 1.0), 0.5 * wq * L
            w, dw, rot, drot = _planar_shapes(L, phi, xi)
            gamma = dw - rot
            mt += wz * rho * self.area * np.outer(w, w)
            r += wz * np.outer(rot, rot)
            k += wz * (EI * np.outer(drot, drot) + kga * np.outer(gamma, gamma))
        return mt, k, r

    def matrices(self) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """The 8 x 8 element mass, stiffness and gyroscopic matrices ``(M, K, G)``.

        On ``q_e = [x1, y1, theta_x1, theta_y1, x2, y2, theta_x2, theta_y2]``, with the
        equation of motion ``M q'' + speed G q' + K q = f``:

        * ``M = sum_p T_p^T (rho A int N_w^T N_w dz + rho I int N_phi^T N_phi dz) T_p``,
        * ``K = sum_p T_p^T (EI int N_phi'^T N_phi' dz + kappa G A int g^T g dz) T_p`` with
          the shear strain ``g = N_w' - N_phi``,
        * ``G = 2 rho I int (N_tx^T N_ty - N_ty^T N_tx) dz`` (skew-symmetric),

        where ``p`` runs over the two bending planes, ``T_p`` picks the plane's
        ``(w1, phi1, w2, phi2)`` = ``(x1, theta_y1, x2, theta_y2)`` and
        ``(y1, -theta_x1, y2, -theta_x2)``, and ``N_tx = -N_phi T_yz``, ``N_ty = N_phi T_xz``
        interpolate ``theta_x`` and ``theta_y``.

        Returns
        -------
        M, K, G : ndarray, shape (8, 8)
            Symmetric, symmetric, skew-symmetric.
        """
        mt, k, r = self._planar
        rho_i = self.material.rho * self.second_moment if self.rotary_inertia else 0.0
        mp = mt + rho_i * r
        M = _XZ.T @ mp @ _XZ + _YZ.T @ mp @ _YZ
        K = _XZ.T @ k @ _XZ + _YZ.T @ k @ _YZ
        # theta_x = -N_phi T_yz q, theta_y = N_phi T_xz q
        cross = -(_YZ.T @ r @ _XZ)  # int N_tx^T N_ty dz
        G = 2.0 * rho_i * (cross - cross.T)
        return (M + M.T) / 2.0, (K + K.T) / 2.0, G

    # ------------------------------------------------------------------ as a rotor component
    @cached_property
    def _element(self) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """:meth:`matrices`, computed once and read-only (what the rotor assembles)."""
        out = self.matrices()
        for a in out:
            a.setflags(write=False)
        return out

    def dof_mapping(self) -> dict[str, int]:
        """Local dofs ``x_0, y_0, theta_x_0, theta_y_0, x_1, ..., theta_y_1`` (the order of
        :meth:`matrices`; local node 0 is the node the shaft starts at)."""
        return local_dof_mapping(2, tuple(DIRECTIONS))

    def M(self) -> NDArray[np.float64]:
        """Mass matrix on :meth:`dof_mapping` (read-only; :meth:`matrices` for a copy)."""
        return self._element[0]

    def K(self, speed: float = 0.0) -> NDArray[np.float64]:
        """Stiffness matrix on :meth:`dof_mapping` (read-only; it does not depend on the
        speed)."""
        return self._element[1]

    def C(self, speed: float = 0.0) -> NDArray[np.float64]:
        """Damping on :meth:`dof_mapping`: none of its own (the rotor's structural damping is
        Rayleigh or modal), zeros."""
        return np.zeros((8, 8))

    def G(self) -> NDArray[np.float64]:
        """Gyroscopic matrix per unit speed on :meth:`dof_mapping` (read-only)."""
        return self._element[2]

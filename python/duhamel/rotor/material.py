"""Isotropic linear-elastic shaft and disk materials."""

from __future__ import annotations

import math
from dataclasses import dataclass

from duhamel._engine.validate import finite_float, positive_float

__all__ = ["STEEL", "Material"]

#: Relative mismatch above which a `G` and a `nu` given together are inconsistent.
_CONSISTENCY_RTOL = 1e-9


@dataclass(frozen=True)
class Material:
    """An isotropic material: Young's modulus `E` (Pa), density `rho` (kg/m^3), shear modulus.

    Give the shear modulus `G` (Pa) or Poisson's ratio `nu`; the other follows from
    ``G = E / (2 (1 + nu))``. Both may be given if they agree. Poisson's ratio is also needed
    by the shear coefficient of :class:`~duhamel.rotor.Shaft`.

    Parameters
    ----------
    E : float
        Young's modulus, ``> 0``.
    rho : float
        Density, ``>= 0``. A massless shaft (``rho = 0``) is allowed for eigenvalue analyses
        (Jeffcott-type models); a time integration needs mass at every degree of freedom.
    G : float, optional
        Shear modulus, ``> 0``.
    nu : float, optional
        Poisson's ratio, in ``(-1, 0.5)``.

    Examples
    --------
    >>> from duhamel.rotor import Material
    >>> steel = Material(E=211e9, rho=7810.0, nu=0.3)
    >>> round(steel.G / 1e9, 3)
    81.154
    >>> Material(E=2e11, rho=7800.0, G=8e10).nu
    0.25
    """

    E: float
    rho: float
    G: float | None = None
    nu: float | None = None

    def __post_init__(self) -> None:
        E = positive_float(self.E, "E")
        rho = finite_float(self.rho, "rho")
        if rho < 0.0:
            raise ValueError(f"`rho` must be >= 0, got {rho!r}")
        if self.G is None and self.nu is None:
            raise ValueError("give the shear modulus `G` or Poisson's ratio `nu` of the material")
        nu = None if self.nu is None else finite_float(self.nu, "nu")
        if nu is not None and not -1.0 < nu < 0.5:
            raise ValueError(f"`nu` must be in (-1, 0.5), got {nu!r}")
        if self.G is None:
            assert nu is not None
            G = E / (2.0 * (1.0 + nu))
        else:
            G = positive_float(self.G, "G")
            implied = E / (2.0 * G) - 1.0
            if nu is None:
                if not -1.0 < implied < 0.5:
                    raise ValueError(
                        f"`E` = {E:g} and `G` = {G:g} imply Poisson's ratio {implied:.6g}, "
                        "outside (-1, 0.5)"
                    )
                nu = implied
            elif not math.isclose(G, E / (2.0 * (1.0 + nu)), rel_tol=_CONSISTENCY_RTOL):
                raise ValueError(
                    f"`G` = {G:g} and `nu` = {nu:g} disagree: E / (2 (1 + nu)) = "
                    f"{E / (2.0 * (1.0 + nu)):g}; give only one of them"
                )
        object.__setattr__(self, "E", E)
        object.__setattr__(self, "rho", rho)
        object.__setattr__(self, "G", float(G))
        object.__setattr__(self, "nu", float(nu))


#: Structural steel as in Friswell et al. (2010): E = 211 GPa, rho = 7810 kg/m^3, nu = 0.3.
STEEL = Material(E=211e9, rho=7810.0, nu=0.3)

"""The short plain journal bearing (Ocvirk's short-bearing pressure field, Gumbel's half-film
cavitation): a nonlinear force of the journal's position and velocity, in Rust with exact
tangents, and its closed-form static and linearised coefficients.

The element (:class:`JournalElement`, on two dofs) and the rotor component
(:class:`ShortJournalBearing`, at a node). The force, with ``h = c - x cos(theta) - y
sin(theta)`` and ``g = (x' + omega y / 2) cos(theta) + (y' - omega x / 2) sin(theta)``, is
``r = R mu L^3 int_{g > 0} g / h^3 (cos(theta), sin(theta)) dtheta`` (the restoring force; the
film pushes the journal with ``-r``); see ``crates/duhamel-core/src/elements/journal.rs``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._core import JournalElement
from duhamel._engine.validate import positive_float as positive
from duhamel.rotor.dofs import node_index

__all__ = ["JournalElement", "ShortJournalBearing", "ocvirk_coefficients"]


def ocvirk_coefficients(
    eccentricity: float, speed: float, radius: float, length: float, clearance: float,
    viscosity: float,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:  # fmt: skip
    """Closed-form static force and linearised coefficients of the short bearing with the
    half (pi) film, for a journal at rest displaced by ``eccentricity * clearance`` along +x,
    spinning at `speed` (> 0): ``(r, K, C)`` in (x, y), from the Booker integrals
    ``int_0^pi sin cos / (1 - e cos)^3 = 2e / (1 - e^2)^2``, ``int_0^pi sin^2 / (1 - e cos)^3
    = pi / (2 (1 - e^2)^(3/2))``, ``int_0^pi cos^2 / (1 - e cos)^3 = pi (1 + 2e^2) / (2 (1 -
    e^2)^(5/2))``. The tangents of a rotationally symmetric bearing rotate with the journal's
    angle: for another direction, rotate ``r``, ``K`` and ``C``.

    Examples
    --------
    >>> import numpy as np
    >>> from duhamel.rotor.journal import JournalElement, ocvirk_coefficients
    >>> r, K, C = ocvirk_coefficients(0.5, 300.0, 0.025, 0.02, 5e-5, 0.02)
    >>> e = JournalElement((0, 1), radius=0.025, length=0.02, clearance=5e-5, viscosity=0.02,
    ...                    speed=300.0)
    >>> r2, K2, C2 = e.evaluate([2.5e-5, 0])
    >>> bool(np.allclose(K, K2, rtol=1e-10) and np.allclose(C, C2, rtol=1e-10))
    True
    """
    e, w = float(eccentricity), float(speed)
    if not 0.0 < e < 1.0:
        raise ValueError(f"`eccentricity` must be in (0, 1), got {eccentricity}")
    q = 1.0 - e * e
    s = radius * viscosity * length**3 / clearance**3  # int over length, per h^3 in units of c
    j_sc, j_ss, j_cc = 2 * e / q**2, np.pi / (2 * q**1.5), np.pi * (1 + 2 * e * e) / (2 * q**2.5)
    c = clearance
    # restoring force: radial (x) and tangential (y)
    f_r = s * c * (w / 2) * e * j_sc
    f_t = -s * c * (w / 2) * e * j_ss
    # d/de of the radial and tangential forces (per unit x = c de)
    dj_sc = 2 * (1 + 3 * e * e) / q**3
    dj_ss = 3 * np.pi * e / (2 * q**2.5)
    k_rr = s * (w / 2) * (j_sc + e * dj_sc)
    k_tr = -s * (w / 2) * (j_ss + e * dj_ss)
    # a tangential displacement (y = e c dphi) turns the force with the journal
    k_rt, k_tt = -f_t / (e * c), f_r / (e * c)
    # velocities: g = e' cos(psi) - e (w/2 - phi') sin(psi), over the film psi in (-pi, 0)
    c_rr, c_rt = s * j_cc, -s * j_sc
    c_tr, c_tt = -s * j_sc, s * j_ss
    r = np.array([f_r, f_t])
    K = np.array([[k_rr, k_rt], [k_tr, k_tt]])
    C = np.array([[c_rr, c_rt], [c_tr, c_tt]])
    return r, K, C


@dataclass(frozen=True)
class ShortJournalBearing:
    """A short plain journal bearing at a rotor node: Ocvirk's short-bearing film with
    Gumbel's half-film cavitation, a nonlinear force of the node's ``(x, y)`` and their
    velocities at the rotor's spin speed (see :mod:`duhamel.rotor.journal`).

    Given among a :class:`~duhamel.rotor.Rotor`'s ``bearings``: its transient systems carry it
    as a :class:`JournalElement` (following a run-up's speed law), :meth:`Rotor.static_equilibrium`
    finds the journal positions under gravity, and the rotor's linear analyses (matrices,
    modes, Campbell diagram, unbalance response) use its stiffness and damping linearised at
    that equilibrium (the exact tangents of the force).

    Parameters
    ----------
    node : int
        The rotor node of the journal.
    diameter, length, clearance : float
        Journal diameter, bearing length (``L / D`` small: the short-bearing theory) and
        radial clearance (m).
    viscosity : float
        Dynamic viscosity of the lubricant (Pa s).

    Examples
    --------
    >>> from duhamel.rotor import ShortJournalBearing
    >>> b = ShortJournalBearing(0, diameter=0.05, length=0.02, clearance=5e-5, viscosity=0.02)
    >>> b.element(dof_x=0, dof_y=1, speed=300.0).radius
    0.025
    """

    node: int
    diameter: float
    length: float
    clearance: float
    viscosity: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "node", node_index(self.node))
        for name in ("diameter", "length", "clearance", "viscosity"):
            object.__setattr__(self, name, positive(getattr(self, name), name))

    @property
    def radius(self) -> float:
        """Journal radius (m)."""
        return self.diameter / 2.0

    def element(
        self, dof_x: int, dof_y: int, speed: Any, *, k0: Any = None, c0: Any = None
    ) -> JournalElement:
        """The force element on the global dofs of the node's ``x`` and ``y``, the journal
        spinning at `speed` (rad/s or a speed law), minus ``k0 x + c0 x'`` if given."""
        return JournalElement(
            (dof_x, dof_y), radius=self.radius, length=self.length, clearance=self.clearance,
            viscosity=self.viscosity, speed=speed, k0=k0, c0=c0,
        )  # fmt: skip

    def coefficients(
        self, position: ArrayLike, speed: float
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Stiffness and damping ``(K, C)`` (2 x 2, ``[[xx, xy], [yx, yy]]``) linearised at
        the journal `position` (m, at rest) and constant `speed`: the force's exact
        tangents.

        Examples
        --------
        >>> from duhamel.rotor import ShortJournalBearing
        >>> b = ShortJournalBearing(0, 0.05, 0.02, 5e-5, 0.02)
        >>> K, C = b.coefficients([1e-5, -2e-5], speed=300.0)
        >>> K.shape, bool(C[0, 0] > 0)
        ((2, 2), True)
        """
        _, K, C = self.element(0, 1, speed).evaluate(position)
        return K, C

    def sommerfeld(self, load: float, speed: float) -> float:
        """Sommerfeld number ``S = mu N L D / W (R / c)^2`` (``N`` in rev/s) for a `load` W
        (N) at `speed` (rad/s).

        Examples
        --------
        >>> from duhamel.rotor import ShortJournalBearing
        >>> round(ShortJournalBearing(0, 0.05, 0.02, 5e-5, 0.02).sommerfeld(100.0, 300.0), 4)
        2.3873
        """
        n = speed / (2 * np.pi)
        return (
            self.viscosity
            * n
            * self.length
            * self.diameter
            / load
            * (self.radius / self.clearance) ** 2
        )

"""The orbits of section 4.4 (Figs. 10 to 13): every case of the cubic law and the mass
variation, from rest, scaled by the static deflection."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

import duhamel
from duhamel.paper._common import Array, Claim, fmt
from duhamel.paper.rotor_model import (
    BETAS,
    CONSIDERABLE,
    COUPLING,
    DT,
    POSITIONS,
    SPEED,
    T_END,
    XIS,
    _planar,
    _rayleigh,
    _relative_error,
    paper_rotor,
    paper_system,
    static_scale,
)

__all__ = ["RotorOrbits", "rotor_orbits"]


@dataclass(frozen=True, eq=False)
class RotorOrbits:
    """Figs. 10-13: the orbits of the journal centres and the disk centres.

    Attributes
    ----------
    t : ndarray, shape (n_t,)
    orbits : dict of (beta, xi) to ndarray, shape (n_t, 4, 2)
        ``(x, y) / x_stat`` at the :data:`POSITIONS`, each scaled by its own static
        deflection under the weight (``beta = 0``).
    x_stat : ndarray, shape (4,)
        Those deflections (m).
    frequencies : ndarray
        Damped natural frequencies at 1500 rpm (rad/s), linear rotor.
    rayleigh : (float, float)
        The Rayleigh coefficients ``(alpha, beta)``.
    eccentricity, form : str
        As :func:`paper_system`.
    dt, t_end : float
    seconds : float
        Time for all runs (solve calls).
    """

    t: Array
    orbits: dict[tuple[float, float], Array]
    x_stat: Array
    frequencies: Array
    rayleigh: tuple[float, float]
    eccentricity: str
    form: str
    dt: float
    t_end: float
    seconds: float

    @property
    def betas(self) -> list[float]:
        """The ``beta`` values computed, ascending."""
        return sorted({b for b, _ in self.orbits})

    @property
    def xis(self) -> list[float]:
        """The ``xi`` values computed, ascending."""
        return sorted({x for _, x in self.orbits})

    def radius(self, beta: float, xi: float) -> Array:
        """Largest distance from the rest position at each position (units of ``x_stat``)."""
        return np.linalg.norm(self.orbits[(beta, xi)], axis=2).max(axis=0)

    def mass_influence(self, beta: float, xi: float) -> Array:
        """Per position: the largest change of the motion from ``xi = 0`` over the run,
        ``max_t |r_xi - r_0|``, over the orbit's size ``max_t |r_0|``."""
        return _relative_error(self.orbits[(beta, xi)], self.orbits[(beta, 0.0)])

    def claims(self) -> list[Claim]:
        """Statements of section 4.4 about Figs. 10-13, with our numbers."""
        labels = [p[0] for p in POSITIONS]
        b_lo, b_hi = self.betas[0], self.betas[-1]
        x_hi = self.xis[-1]
        r0, r1 = self.radius(b_lo, 0.0), self.radius(b_hi, 0.0)
        out = [
            Claim(
                "the model: 20 dofs, four rotating beam elements, three rotor elements; "
                "bearings (1e9, 1e7 N/m) at dofs 1, 2, 13, 14",
                "section 4.4, Fig. 9",
                "5 nodes; dofs 1, 2, 13, 14 = x, y of nodes 0 and 3; disks at nodes 1, 2, 4; "
                "critical speeds at 1500 rpm "
                + ", ".join(f"{w:.0f}" for w in self.frequencies[:4])
                + " rad/s; x_stat "
                + ", ".join(
                    f"{lab} {1e6 * s:.2f} um" for lab, s in zip(labels, self.x_stat, strict=True)
                )
                + f"; Rayleigh alpha {self.rayleigh[0]:.3g} 1/s, beta {self.rayleigh[1]:.3g} s",
                None,
                "geometry ours (the paper gives none): docs/paper.md",
            ),
            Claim(
                f"Figs. 10-11: the effect of the nonlinear restoring force (beta = {b_lo:g} "
                f"and {b_hi:g}) on the journal motion",
                "Figs. 10, 11",
                "largest orbit radius / x_stat, beta "
                f"{b_lo:g} -> {b_hi:g}: "
                + ", ".join(
                    f"{lab} {fmt(a)} -> {fmt(b)}" for lab, a, b in zip(labels, r0, r1, strict=True)
                ),
                None,
                "the cubic law stiffens the bearings: the journal orbits shrink and turn "
                "square (x and y laws are separate); the disks hardly notice",
            ),
        ]
        for beta in self.betas:
            if x_hi == 0.0:
                break
            change = self.mass_influence(beta, x_hi)
            envelope = np.abs(self.radius(beta, x_hi) / self.radius(beta, 0.0) - 1.0)
            out.append(
                Claim(
                    f"the variable mass considerably influences the motion of the rotor "
                    f"(beta = {beta:g}, xi = {x_hi:g} against xi = 0)",
                    "section 4.4, Figs. 10-13",
                    "largest change of the motion / orbit size: "
                    + ", ".join(
                        f"{lab} {100 * c:.1f} %" for lab, c in zip(labels, change, strict=True)
                    )
                    + "; of the largest radius: "
                    + ", ".join(f"{100 * e:.1f} %" for e in envelope),
                    bool(change.max() >= CONSIDERABLE),
                    f"holds = some position changes by >= {100 * CONSIDERABLE:.0f} % of its "
                    "orbit; the effect grows with (Omega / omega_1)^2 = "
                    f"{(SPEED / self.frequencies[0]) ** 2:.2f} here",
                )
            )
        return out


def rotor_orbits(
    betas: Sequence[float] = BETAS,
    xis: Sequence[float] = XIS,
    *,
    t_end: float = T_END,
    dt: float = DT,
    eccentricity: str = "rotating",
    form: str = "acceleration",
) -> RotorOrbits:
    """Data of Figs. 10-13: every ``(beta, xi)`` run with the full semi-analytic model.

    Parameters
    ----------
    betas, xis : sequence of float
        Cubic-law parameters and mass variations (``xi = 0`` is always computed: the other
        values are compared with it).
    t_end, dt : float
        Run length and step (s).
    eccentricity, form : str
        See :func:`paper_system`.

    Returns
    -------
    RotorOrbits

    Examples
    --------
    >>> from duhamel.paper.rotor import rotor_orbits
    >>> data = rotor_orbits(betas=(0.0,), xis=(0.0,), t_end=0.01)
    >>> data.orbits[(0.0, 0.0)].shape
    (101, 4, 2)
    """
    nodes = [n for _, n in POSITIONS]
    scale = static_scale()[nodes]
    xi_values = sorted({0.0, *map(float, xis)})
    orbits: dict[tuple[float, float], Array] = {}
    seconds = 0.0
    t = np.empty(0)
    for beta in map(float, betas):
        for xi in xi_values:
            system = paper_system(beta, xi, eccentricity=eccentricity, form=form)
            sol = duhamel.solve(system, duhamel.Semianalytic(coupling=COUPLING), t_end=t_end, dt=dt)
            seconds += sol.stats.total_time
            t = sol.t
            orbits[(beta, xi)] = _planar(sol.x, nodes) / scale[None, :, None]
    return RotorOrbits(
        t=t,
        orbits=orbits,
        x_stat=scale,
        frequencies=paper_rotor(0.0).natural_frequencies(SPEED),
        rayleigh=_rayleigh(),
        eccentricity=eccentricity,
        form=form,
        dt=float(dt),
        t_end=float(t_end),
        seconds=seconds,
    )

"""API 684 / API 617 Level I stability screening: the log decrement of the first forward mode
against an applied cross-coupled stiffness, its zero crossing (the stability threshold
``Q_0``) and the anticipated cross-coupling ``Q_A``.

``Q_A`` is the Wachel formula of API 617 (8th ed., 2014) and API RP 684 (2nd ed., 2005),
written here in consistent SI units: per stage (impeller or blade row)

    q_A = B T / (D H) * (rho_d / rho_s),    T = P / Omega (the stage torque, N m),

with ``P`` the stage's rated power (W), ``Omega`` the speed (rad/s), ``D`` the impeller (or
blade) diameter and ``H`` the minimum of the diffuser and impeller discharge width (or the
effective blade height) (m), ``rho_d / rho_s`` the discharge-to-suction density ratio
(centrifugal machines only), ``B = 3`` for centrifugal compressors and ``B = 1.5`` for
axial-flow machines; ``Q_A`` (N/m) is the sum over the stages. The standards print it in
engineering units, ``q_A = HP B C / (D H N) (rho_d / rho_s)`` with ``N`` in rpm and ``C`` the
unit constant (63 in US units), which is the same torque ``HP C / N`` over ``D H``.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.validate import as_float_array, finite_float, positive_float

__all__ = [
    "Level1Stability",
    "Stage",
    "ThresholdWarning",
    "anticipated_cross_coupling",
    "level1_stability",
]


class ThresholdWarning(UserWarning):
    """Level I: the log decrement does not reach zero within `q_range`, so the stability
    threshold ``Q_0`` (and ``Q_0 / Q_A``) is not known (NaN): extend `q_range`."""


#: API 617 / 684 Level I: Level II is required when ``Q_0 / Q_A < 2`` or when the log
#: decrement at ``Q_A`` is below 0.1.
RATIO_LIMIT = 2.0
LOG_DEC_LIMIT = 0.1
_B = {"centrifugal": 3.0, "axial": 1.5}


@dataclass(frozen=True)
class Stage:
    """One impeller (or blade row) for :func:`anticipated_cross_coupling`.

    Attributes
    ----------
    power : float
        Rated power of the stage (W).
    diameter : float
        Impeller (blade) diameter ``D`` (m).
    width : float
        ``H``: the minimum of the diffuser and impeller discharge width (the effective
        blade height of an axial stage) (m).
    density_ratio : float
        Discharge-to-suction density ``rho_d / rho_s`` (1 for axial machines).
    """

    power: float
    diameter: float
    width: float
    density_ratio: float = 1.0


def anticipated_cross_coupling(
    stages: Sequence[Stage], speed: float, machine: str = "centrifugal"
) -> float:
    """API 617 / 684 anticipated cross-coupling ``Q_A`` (N/m), the sum over `stages` of
    ``B P / (speed D H) (rho_d / rho_s)`` (``B = 3`` centrifugal, ``1.5`` axial; the density
    ratio is used for centrifugal machines only). See the module docstring.

    Examples
    --------
    One 1 MW impeller, 0.4 m diameter, 20 mm discharge width, density ratio 1.5, at 1000 rad/s:

    >>> from duhamel.rotor.stability import Stage, anticipated_cross_coupling
    >>> round(anticipated_cross_coupling([Stage(1e6, 0.4, 0.02, 1.5)], 1000.0))
    562500
    """
    if machine not in _B:
        raise ValueError(f"`machine` must be 'centrifugal' or 'axial', got {machine!r}")
    w = positive_float(speed, "speed")
    total = 0.0
    for stage in stages:
        if not isinstance(stage, Stage):
            raise TypeError(f"`stages` must hold Stage, got {type(stage).__name__}")
        p = positive_float(stage.power, "power")
        d = positive_float(stage.diameter, "diameter")
        h = positive_float(stage.width, "width")
        ratio = positive_float(stage.density_ratio, "density_ratio")
        total += _B[machine] * p / (w * d * h) * (ratio if machine == "centrifugal" else 1.0)
    return total


@dataclass(frozen=True, eq=False)
class Level1Stability:
    """Result of :meth:`Rotor.level1_stability <duhamel.rotor.Rotor.level1_stability>`.

    Attributes
    ----------
    speed : float
        rad/s.
    location : tuple of int
        Nodes where the cross-coupling is applied (``q`` split equally among them).
    q : ndarray
        Applied cross-coupled stiffnesses (N/m): ``k_xy = q``, ``k_yx = -q``.
    log_dec : ndarray
        Log decrement of the first forward mode at each ``q`` (followed by its shape from
        the first ``q``).
    frequency : ndarray
        Its damped natural frequency (rad/s).
    threshold : float
        ``Q_0``: the ``q`` where the log decrement reaches zero (refined by Brent's method on
        the eigenproblem to 1e-12 relative), NaN if it does not within `q`.
    q_a : float
        The anticipated cross-coupling ``Q_A`` (N/m), NaN if not given.
    log_dec_at_q_a : float
        The first forward mode's log decrement at ``Q_A`` (NaN without it).
    """

    speed: float
    location: tuple[int, ...]
    q: NDArray[np.float64]
    log_dec: NDArray[np.float64]
    frequency: NDArray[np.float64]
    threshold: float
    q_a: float
    log_dec_at_q_a: float

    @property
    def ratio(self) -> float:
        """``Q_0 / Q_A`` (NaN without either)."""
        return self.threshold / self.q_a if self.q_a > 0 else np.nan

    @property
    def requires_level2(self) -> bool:
        """API 617: ``Q_0 / Q_A < 2`` or log decrement at ``Q_A`` below 0.1 (False when
        ``Q_A`` is not known; a threshold not reached within `q` counts as above it)."""
        if not np.isfinite(self.q_a):
            return False
        ratio = np.inf if np.isnan(self.threshold) else self.ratio
        return bool(ratio < RATIO_LIMIT or self.log_dec_at_q_a < LOG_DEC_LIMIT)

    def plot(self, ax: Any = None) -> Any:
        """Log decrement against applied cross-coupling, as API 684 draws it: the curve,
        ``Q_A`` and ``Q_0`` marked, the 0.1 limit; returns the Axes."""
        import matplotlib.pyplot as plt

        ax = ax if ax is not None else plt.subplots()[1]
        ax.plot(self.q, self.log_dec, "o-", label="first forward mode")
        ax.axhline(0.0, color="k", lw=0.8)
        ax.axhline(LOG_DEC_LIMIT, color="tab:red", ls=":", label="log dec 0.1")
        if np.isfinite(self.threshold):
            label = f"Q_0 = {self.threshold:.4g} N/m"
            ax.axvline(self.threshold, color="tab:gray", ls="--", label=label)
        if np.isfinite(self.q_a):
            ax.axvline(self.q_a, color="tab:green", ls="--", label=f"Q_A = {self.q_a:.4g} N/m")
        ax.set_xlabel("applied cross-coupled stiffness q (N/m)")
        ax.set_ylabel("log decrement")
        ax.set_title(f"Level I stability at {self.speed:g} rad/s")
        ax.legend()
        return ax


def _first_forward(modes: Any) -> int:
    """Index of the lowest mode that is not backward whirl (forward, or mixed/planar once the
    cross-coupling makes the orbits elliptical)."""
    for j in range(modes.n_modes):
        if modes.whirl[j] != "backward":
            return j
    raise ValueError(f"no forward mode at {modes.speed:g} rad/s")


def _follow(modes: Any, shape: NDArray[np.complex128]) -> int:
    """Index of the mode of `modes` whose shape is closest (MAC) to `shape`."""
    return int(np.argmax(modes.mac_with(shape)))


def level1_stability(
    modes_with: Callable[[float], Any],
    speed: float,
    location: tuple[int, ...],
    q_range: ArrayLike,
    q_a: float | None,
) -> Level1Stability:
    """The Level I curve from `modes_with(q)` (the modes with cross-coupling ``q``).

    The first forward mode at the first ``q`` is followed along `q_range` by its shape (the
    largest MAC with the previous ``q``'s), so that a mode that becomes oscillatory as ``q``
    grows (or a whirl label that changes) does not replace it.
    """
    qs = as_float_array(q_range, "q_range", ndim=1)
    if qs.size < 2 or np.any(np.diff(qs) <= 0.0) or qs[0] < 0.0:
        raise ValueError("`q_range` must be at least two increasing stiffnesses >= 0 (N/m)")
    qa = np.nan if q_a is None else positive_float(q_a, "q_a")
    shapes = []
    dec = np.empty(qs.size)
    freq = np.empty(qs.size)
    for i, q in enumerate(qs):
        m = modes_with(float(q))
        j = _first_forward(m) if i == 0 else _follow(m, shapes[-1])
        shapes.append(m.shapes[:, j])
        dec[i], freq[i] = float(m.log_dec[j]), float(m.frequencies[j])

    def along(q: float, shape: NDArray[np.complex128]) -> float:
        m = modes_with(q)
        return float(m.log_dec[_follow(m, shape)])

    threshold = np.nan
    crossing = np.flatnonzero((dec[:-1] > 0.0) & (dec[1:] <= 0.0))
    if dec[0] <= 0.0:
        threshold = float(qs[0])
    elif crossing.size:
        from scipy.optimize import brentq

        c = int(crossing[0])
        a, b = float(qs[c]), float(qs[c + 1])
        threshold = float(
            brentq(along, a, b, args=(shapes[c],), xtol=1e-12 * max(b, 1.0), rtol=1e-14)
        )
    if not np.isfinite(threshold):
        import warnings

        warnings.warn(
            f"Level I at {speed:g} rad/s: the log decrement of the first forward mode stays "
            f"positive up to q = {qs[-1]:.4g} N/m (last value {dec[-1]:.4g}); the threshold "
            "Q_0 is not within `q_range` (NaN): extend `q_range`",
            ThresholdWarning,
            stacklevel=3,
        )
    at_qa = np.nan
    if np.isfinite(qa):  # followed from the nearest q of the range
        at_qa = along(qa, shapes[int(np.argmin(np.abs(qs - qa)))])
    w = finite_float(speed, "speed")
    return Level1Stability(w, location, qs, dec, freq, threshold, qa, at_qa)

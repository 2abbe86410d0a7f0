"""Time-varying mass ``M(t) = M mu(t)`` for a scalar law ``mu``.

Attach a law with :meth:`duhamel.System.set_mass_law`. The integrator treats the change of
mass as a modal pseudo-force; by default it eliminates the acceleration with the equation of
motion (``Semianalytic(mass_treatment="eliminate")``), the alternative estimates it as
``(v1 - v0)/dt`` (``"estimate"``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel import _core
from duhamel._engine.validate import as_float_array, finite_float

__all__ = ["MU_FLOOR", "Exponential", "Harmonic", "MassLaw", "Tabulated"]


#: The smallest value a mass law may take relative to its largest over a run: below it the
#: equation of motion divided by the mass overflows.
MU_FLOOR = 1e-8


class MassLaw:
    """Base class of the mass laws ``mu(t)``."""

    def _law(self) -> _core.MassLaw:  # pragma: no cover - abstract
        """The law as the core evaluates it."""
        raise NotImplementedError

    def __call__(self, t: ArrayLike) -> NDArray[np.float64]:  # pragma: no cover - abstract
        raise NotImplementedError


@dataclass(frozen=True)
class Exponential(MassLaw):
    """``mu(t) = scale * exp(rate * t)`` (the paper's decaying pendulum: ``rate = -a omega``).

    Examples
    --------
    >>> import duhamel
    >>> law = duhamel.mass.Exponential(rate=-0.1)
    >>> float(law(10.0))
    0.36787944117144233
    """

    rate: float
    scale: float = 1.0

    def __post_init__(self) -> None:
        finite_float(self.rate, "rate")
        if finite_float(self.scale, "scale") <= 0.0:
            raise ValueError(f"`scale` must be positive, got {self.scale}")

    def _law(self) -> _core.MassLaw:
        return _core.MassLaw.exponential(float(self.rate), float(self.scale))

    def __call__(self, t: ArrayLike) -> NDArray[np.float64]:
        return self.scale * np.exp(self.rate * np.asarray(t, dtype=float))


@dataclass(frozen=True)
class Harmonic(MassLaw):
    """``mu(t) = 1 + amplitude * sin(frequency * t)`` (the rotor's ``M0 [1 + xi sin(nu t)]``).

    Examples
    --------
    >>> import duhamel
    >>> law = duhamel.mass.Harmonic(amplitude=0.1, frequency=157.0)
    """

    amplitude: float
    frequency: float

    def __post_init__(self) -> None:
        if abs(finite_float(self.amplitude, "amplitude")) >= 1.0:
            raise ValueError(
                f"`amplitude` must be below 1 in magnitude (the mass would reach zero), "
                f"got {self.amplitude}"
            )
        finite_float(self.frequency, "frequency")

    def _law(self) -> _core.MassLaw:
        return _core.MassLaw.harmonic(float(self.amplitude), float(self.frequency))

    def __call__(self, t: ArrayLike) -> NDArray[np.float64]:
        return 1.0 + self.amplitude * np.sin(self.frequency * np.asarray(t, dtype=float))


@dataclass(frozen=True, eq=False)
class Tabulated(MassLaw):
    """``mu`` linear between samples ``(t, mu)``, held constant outside them; must stay above
    :data:`MU_FLOOR` times its largest value (every mass law must, over a run).

    Examples
    --------
    >>> import duhamel
    >>> law = duhamel.mass.Tabulated(t=[0.0, 1.0, 2.0], mu=[1.0, 0.8, 0.8])
    >>> float(law(0.5))
    0.9
    """

    t: NDArray[np.float64]
    mu: NDArray[np.float64]

    def __post_init__(self) -> None:
        ts = as_float_array(self.t, "t", ndim=1)
        mu = as_float_array(self.mu, "mu", ndim=1)
        if ts.size < 2 or mu.shape != ts.shape:
            raise ValueError(
                f"`mu` needs one value per `t` (at least two), got {mu.size} and {ts.size}"
            )
        if np.any(np.diff(ts) <= 0):
            raise ValueError("`t` must be strictly increasing")
        if np.any(mu <= 0):
            i = int(np.argmax(mu <= 0))
            raise ValueError(f"`mu` must stay positive; mu[{i}] = {mu[i]} at t = {ts[i]}")
        if mu.min() < MU_FLOOR * mu.max():
            i = int(np.argmin(mu))
            raise ValueError(
                f"`mu` must stay above {MU_FLOOR:g} of its largest value ({mu.max():g}); "
                f"mu[{i}] = {mu[i]:g} at t = {ts[i]:g} would make the divided equation of "
                "motion overflow"
            )
        object.__setattr__(self, "t", ts)
        object.__setattr__(self, "mu", mu)

    def _law(self) -> _core.MassLaw:
        return _core.MassLaw.table(
            np.ascontiguousarray(self.t, dtype=np.float64),
            np.ascontiguousarray(self.mu, dtype=np.float64),
        )

    def __call__(self, t: ArrayLike) -> NDArray[np.float64]:
        return np.interp(np.asarray(t, dtype=float), self.t, self.mu)


@dataclass(frozen=True)
class _Attached:
    """A law attached to a system, with how it enters the equation of motion."""

    law: MassLaw
    form: str
    scale_stiffness: bool

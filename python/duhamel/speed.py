"""Spin-speed laws ``omega(t)`` of a rotor (rad/s): what drives an
:class:`~duhamel.loads.Unbalance` load and a time-scaled
:class:`~duhamel.elements.LinearCoupling` (the gyroscopic ``omega(t) G`` of a run-up).

Every law gives the speed ``omega(t)``, the angular acceleration ``domega(t)`` and the
rotation angle ``theta(t) = integral_0^t omega``, in closed form, evaluated by the same Rust
code the time loop uses. Before ``t = 0`` a law keeps its initial speed. The laws are also
available as ``duhamel.loads.ConstantSpeed`` and ``duhamel.loads.LinearRunUp``.

Examples
--------
>>> import duhamel
>>> run_up = duhamel.speed.LinearRunUp(omega0=0.0, omega1=150.0, t1=2.0)
>>> float(run_up.omega(1.0)), float(run_up.domega(1.0)), float(run_up.theta(2.0))
(75.0, 75.0, 150.0)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel import _core
from duhamel._engine.validate import finite_float

__all__ = ["ConstantSpeed", "LinearRunUp", "SpeedLaw", "as_speed_law"]


class SpeedLaw:
    """Base class of the speed laws."""

    def _law(self) -> _core.SpeedLaw:  # pragma: no cover - abstract
        """The law as the core evaluates it."""
        raise NotImplementedError

    def constant_value(self) -> float | None:  # pragma: no cover - abstract
        """The speed when it does not change with time, else None."""
        raise NotImplementedError

    def _to_value(self) -> str:
        """The law as the core's data (JSON text): how an element's speed parameter holds it."""
        return self._law()._to_value()

    def _eval(self, t: ArrayLike, which: int) -> Any:
        ts = np.asarray(t, dtype=np.float64)
        flat = np.ascontiguousarray(np.atleast_1d(ts).ravel())
        out = self._law().evaluate(flat)[which].reshape(ts.shape)
        if not np.all(np.isfinite(out)):
            bad = float(np.atleast_1d(ts).ravel()[~np.isfinite(np.atleast_1d(out).ravel())][0])
            what = ("omega", "domega", "theta")[which]
            raise ValueError(f"the speed law's {what} overflows the double range at `t` = {bad!r}")
        return out[()] if ts.ndim == 0 else out

    def omega(self, t: ArrayLike) -> NDArray[np.float64]:
        """The speed ``omega(t)`` (rad/s); a float array of the shape of `t`."""
        return self._eval(t, 0)

    def domega(self, t: ArrayLike) -> NDArray[np.float64]:
        """The angular acceleration ``omega'(t)`` (rad/s^2); right-continuous where it jumps."""
        return self._eval(t, 1)

    def theta(self, t: ArrayLike) -> NDArray[np.float64]:
        """The rotation angle ``theta(t) = integral_0^t omega(s) ds`` (rad), exact."""
        return self._eval(t, 2)

    def __call__(self, t: ArrayLike) -> NDArray[np.float64]:
        """The speed ``omega(t)``, as :meth:`omega`."""
        return self.omega(t)


@dataclass(frozen=True, init=False, repr=False)
class ConstantSpeed(SpeedLaw):
    """``omega(t) = omega`` (rad/s); the speed is the attribute ``value`` (``omega`` is the
    method every law has).

    Examples
    --------
    >>> import duhamel
    >>> law = duhamel.speed.ConstantSpeed(157.0)
    >>> law.value, float(law.theta(0.5))
    (157.0, 78.5)
    """

    value: float

    def __init__(self, omega: float) -> None:
        object.__setattr__(self, "value", finite_float(omega, "omega"))

    def __repr__(self) -> str:
        return f"ConstantSpeed(omega={self.value!r})"

    def _law(self) -> _core.SpeedLaw:
        return _core.SpeedLaw.constant(self.value)

    def constant_value(self) -> float | None:
        return self.value


@dataclass(frozen=True)
class LinearRunUp(SpeedLaw):
    """Linear run-up (or run-down) from ``omega0`` at ``t = 0`` to ``omega1`` at ``t1``,
    constant ``omega1`` after: ``theta = omega0 t + (omega1 - omega0) t^2 / (2 t1)`` up to
    ``t1``.

    The angular acceleration jumps to zero at ``t1``; an :class:`~duhamel.loads.Unbalance`
    load jumps there by ``m_e (omega1 - omega0)/t1``, which :class:`~duhamel.Semianalytic`
    integrates exactly wherever ``t1`` falls (direct integrators see loads at grid times
    only: put ``t1`` on the step grid for them).

    Examples
    --------
    >>> import duhamel
    >>> law = duhamel.speed.LinearRunUp(omega0=10.0, omega1=30.0, t1=4.0)
    >>> float(law.omega(2.0)), float(law.omega(9.0))
    (20.0, 30.0)
    """

    omega0: float
    omega1: float
    t1: float

    def __post_init__(self) -> None:
        for name in ("omega0", "omega1", "t1"):
            object.__setattr__(self, name, finite_float(getattr(self, name), name))
        if self.t1 <= 0.0:
            raise ValueError(f"`t1` must be positive (the end of the run-up), got {self.t1!r}")

    def _law(self) -> _core.SpeedLaw:
        return _core.SpeedLaw.run_up(self.omega0, self.omega1, self.t1)

    def constant_value(self) -> float | None:
        return self.omega0 if self.omega0 == self.omega1 else None


def as_speed_law(value: Any, name: str) -> SpeedLaw:
    """`value` as a speed law: a law as it is, a real number as :class:`ConstantSpeed`."""
    if isinstance(value, SpeedLaw):
        return value
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        raise TypeError(
            f"`{name}` must be a number (a constant speed, rad/s) or a speed law "
            f"(duhamel.speed.ConstantSpeed, LinearRunUp), got {type(value).__name__}"
        )
    return ConstantSpeed(finite_float(value, name))

"""What every integrator shares: the Newton settings and their checks."""

from __future__ import annotations

import numbers
from typing import Any

import numpy as np

from duhamel._engine.validate import finite_float, positive_int

__all__ = [
    "MAX_ITER",
    "DirectIntegrator",
    "Integrator",
    "newton_options",
    "real",
    "tolerance_options",
]


class Integrator:
    """Base class of the integrators passed to :func:`duhamel.solve`: small frozen
    configuration objects, checked when made.

    Attributes
    ----------
    tol : float
        Newton's relative tolerance for implicit step equations.
    max_iter : int
        Newton iterations per step before the run stops with a :class:`duhamel.SolverError`.
    """

    tol: float
    max_iter: int


#: Most Newton iterations per step an integrator accepts.
MAX_ITER = 10_000


def real(value: object, name: str, lo: float | None = None, hi: float | None = None) -> float:
    """`value` (any Python or numpy real) as a finite float in ``[lo, hi]``; errors name
    the parameter."""
    out = finite_float(value, name)
    if (lo is not None and out < lo) or (hi is not None and out > hi):
        lo_s = "-inf" if lo is None else f"{lo:g}"
        hi_s = "inf" if hi is None else f"{hi:g}"
        raise ValueError(f"`{name}` must be in [{lo_s}, {hi_s}], got {out!r}")
    return out


def tolerance_options(integrator: Any) -> None:
    """Checks a direct integrator's steps-by-tolerance options: `rtol` None or a number in
    (0, 1), `atol` a finite number >= 0, `subdivisions` an integer in [1, 20]; stores
    `rtol` and `atol` as floats."""
    rtol = integrator.rtol
    if rtol is not None:
        rtol = finite_float(rtol, "rtol")
        if not 0.0 < rtol < 1.0:
            raise ValueError(f"`rtol` must be a number in (0, 1) (or None), got {rtol}")
        object.__setattr__(integrator, "rtol", rtol)
    atol = finite_float(integrator.atol, "atol")
    if atol < 0.0:
        raise ValueError(f"`atol` must be >= 0, got {atol}")
    object.__setattr__(integrator, "atol", atol)
    positive_int(integrator.subdivisions, "subdivisions", 20)


def newton_options(tol: object, max_iter: object) -> None:
    """Checks Newton's `tol` (a number in (0, 1)) and `max_iter` (a positive integer, at
    most :data:`MAX_ITER`); numpy scalars are accepted."""
    if not 0.0 < finite_float(tol, "tol") < 1.0:
        raise ValueError(f"`tol` must be a number in (0, 1), got {tol!r}")
    if isinstance(max_iter, bool | np.bool_) or not isinstance(max_iter, numbers.Integral):
        raise ValueError(f"`max_iter` must be a positive integer, got {max_iter!r}")
    positive_int(max_iter, "max_iter", MAX_ITER)


class DirectIntegrator(Integrator):
    """Base class of the direct integrators, which step the physical equations of motion
    ``M(t) x'' + C x' + K x + r(x, x', t) = f(t)`` (no modal transformation).

    See docs/direct.md. :func:`duhamel.solve` returns a :class:`~duhamel.Solution` whose
    ``modal`` is None for them. Path-dependent elements (hysteresis, a ``Callable`` with
    ``state``) are evaluated from their committed internal variables at every Newton
    iteration and committed once per accepted step, at its end state.
    """

    #: The internal variables of path-dependent elements are committed once per step.
    _commits_state = True

    def _method(self) -> Any:  # pragma: no cover - abstract
        """The method as the core takes it (a ``_core.Method``)."""
        raise NotImplementedError

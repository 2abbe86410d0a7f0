"""Convergence of an integrator on a problem with a known solution: the observed order."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.validate import as_float_array, positive_float
from duhamel.prepared import solve
from duhamel.system import System

__all__ = ["Convergence", "ReferenceProblem", "convergence_order"]

Array = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class ReferenceProblem:
    """A run compared with a reference: ``problem(integrator, dt)`` returns the error.

    Calls ``duhamel.solve(system, integrator, t_end=t_end, dt=dt, x0=x0, v0=v0)`` (with the
    system's loads) and compares the displacements with ``reference(sol.t)``.

    Parameters
    ----------
    system : System
        The model, with its loads and elements.
    t_end : float
        End time; choose a common multiple of the steps so that every run ends at `t_end`.
    reference : callable
        ``reference(t)`` with ``t`` of shape ``(n_t,)`` returns the exact displacements,
        shape ``(n_t, n_dof)`` (or ``(n_t,)`` for one degree of freedom).
    x0, v0 : array_like, optional
        Initial state (zero by default).
    measure : {"max", "final"}
        The largest absolute displacement error over all saved times and dofs, or over the
        dofs at the last time.

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> from duhamel.analysis import ReferenceProblem
    >>> oscillator = duhamel.System([[1.0]], [[1.0]])
    >>> free = ReferenceProblem(oscillator, 2 * np.pi, np.cos, x0=[1.0])
    >>> free(duhamel.Semianalytic(), 0.1) < 1e-13    # exact for a linear background
    True
    """

    system: System
    t_end: float
    reference: Callable[[Array], ArrayLike]
    x0: ArrayLike | None = None
    v0: ArrayLike | None = None
    measure: Literal["max", "final"] = "max"

    def __post_init__(self) -> None:
        if not isinstance(self.system, System):
            raise TypeError(f"`system` must be a duhamel.System, got {type(self.system).__name__}")
        object.__setattr__(self, "t_end", positive_float(self.t_end, "t_end"))
        if not callable(self.reference):
            raise TypeError(f"`reference` must be callable, got {type(self.reference).__name__}")
        if self.measure not in ("max", "final"):
            raise ValueError(f"`measure` must be 'max' or 'final', got {self.measure!r}")

    def __call__(self, integrator: Any, dt: float) -> float:
        sol = solve(self.system, integrator, t_end=self.t_end, dt=dt, x0=self.x0, v0=self.v0)
        ref = np.asarray(self.reference(sol.t), dtype=np.float64).reshape(sol.x.shape)
        diff = np.abs(sol.x - ref)
        return float(diff.max() if self.measure == "max" else diff[-1].max())


@dataclass(frozen=True)
class Convergence:
    """Result of :func:`convergence_order`.

    Attributes
    ----------
    dts, errors : ndarray, shape (k,)
        Steps (as given) and the errors the problem returned.
    order : float
        Least-squares slope of ``log(error)`` against ``log(dt)``.
    orders : ndarray, shape (k - 1,)
        Slopes between consecutive steps.
    """

    dts: Array
    errors: Array
    order: float
    orders: Array


def convergence_order(
    problem: Callable[[Any, float], float], integrator: Any, dts: ArrayLike
) -> Convergence:
    """Measured order of convergence: the slope of the error against the step.

    Parameters
    ----------
    problem : callable
        ``problem(integrator, dt) -> error`` (a positive float), for instance a
        :class:`ReferenceProblem`, or any function that runs the integrator and compares
        with a reference of its own.
    integrator : object
        Passed to `problem` unchanged.
    dts : array_like, shape (k,)
        At least two distinct positive steps.

    Returns
    -------
    Convergence

    Raises
    ------
    ValueError
        Bad `dts`, or `problem` returned an error that is not a positive finite number
        (e.g. zero for an integrator that is exact on the problem: no order exists).

    Examples
    --------
    Damping as a pseudo-force (scheme b, second order) against the exact damped oscillator:

    >>> import numpy as np, duhamel
    >>> from duhamel.analysis import ReferenceProblem, convergence_order
    >>> w, z = 1.0, 0.1
    >>> oscillator = duhamel.System([[1.0]], [[w * w]]).add(duhamel.elements.Damper(0, c=2 * z * w))
    >>> wd = w * np.sqrt(1 - z * z)
    >>> exact = lambda t: np.exp(-z * w * t) * (np.cos(wd * t) + z * w / wd * np.sin(wd * t))
    >>> problem = ReferenceProblem(oscillator, 10.0, exact, x0=[1.0])
    >>> result = convergence_order(problem, duhamel.Semianalytic(scheme="b"), [0.1, 0.05, 0.025])
    >>> round(result.order, 2)
    2.0
    """
    if not callable(problem):
        raise TypeError(f"`problem` must be callable, got {type(problem).__name__}")
    steps = as_float_array(dts, "dts", ndim=1)
    if steps.size < 2:
        raise ValueError(f"`dts` must contain at least two steps, got {steps.size}")
    if np.any(steps <= 0.0):
        raise ValueError("`dts` must be positive")
    if np.unique(steps).size != steps.size:
        raise ValueError("`dts` must be distinct")
    errors = np.empty(steps.size)
    for i, dt in enumerate(steps):
        err = problem(integrator, float(dt))
        try:
            errors[i] = float(err)
        except (TypeError, ValueError):
            raise TypeError(
                f"`problem` must return a number, got {type(err).__name__} at dt = {dt:g}"
            ) from None
        if not (np.isfinite(errors[i]) and errors[i] > 0.0):
            raise ValueError(
                f"`problem` returned error {errors[i]!r} at dt = {dt:g}: an order needs "
                "positive finite errors (zero means the integrator is exact on the problem)"
            )
    ld, le = np.log(steps), np.log(errors)
    order = float(np.polyfit(ld, le, 1)[0])
    return Convergence(dts=steps, errors=errors, order=order, orders=np.diff(le) / np.diff(ld))

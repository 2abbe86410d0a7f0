"""The cubic Hermite time element on the physical equations."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from duhamel import _core
from duhamel.integrators.base import DirectIntegrator, newton_options, tolerance_options

__all__ = ["CubicHermite"]


@dataclass(frozen=True)
class CubicHermite(DirectIntegrator):
    """A time finite element with a C1 cubic Hermite trial function: fourth order.

    Over each step the displacement is the cubic through ``(x0, v0)`` and ``(x1, v1)``; the
    residual of the equation of motion along it is made orthogonal to ``{1, t}``
    (``points``-point Gauss-Legendre quadrature), which gives ``2 n`` equations for
    ``(x1, v1)``, solved by Newton with the elements' tangents at every Gauss point. It stands
    for the "cubic Hermitian" comparison scheme of Holl, Belyaev and Irschik, whose exact
    form is not available to us: a reconstruction (docs/direct.md). Saved accelerations come
    from the equation of motion at the saved states.

    Parameters
    ----------
    points : int
        Gauss points per step, 2 to 8. Three integrate the linear terms exactly; more matter
        only for strongly nonlinear forces (docs/direct.md).
    tol : float
        Newton: relative size of the last update of ``(x1, dt v1)``.
    max_iter : int
        Newton iterations per step.
    rtol, atol, subdivisions : float or None, float, int
        Steps chosen by tolerance, as for :class:`duhamel.Newmark` (fourth order: the
        returned run's error is about a fifteenth of its ``stats.error_estimate``).

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> sys = duhamel.System(np.eye(1), np.eye(1))
    >>> sol = duhamel.solve(sys, duhamel.CubicHermite(), t_end=2 * np.pi,
    ...                     dt=2 * np.pi / 20, x0=[1.0])
    >>> bool(abs(sol.x[-1, 0] - 1.0) < 1e-4)     # 20 steps per period, fourth order
    True
    """

    points: int = 3
    tol: float = 1e-10
    max_iter: int = 25
    rtol: float | None = None
    atol: float = 0.0
    subdivisions: int = 4

    def __post_init__(self) -> None:
        p = self.points
        if isinstance(p, bool) or not isinstance(p, int) or not 2 <= p <= 8:
            raise ValueError(f"`points` must be an integer from 2 to 8, got {p!r}")
        newton_options(self.tol, self.max_iter)
        tolerance_options(self)

    def _method(self) -> Any:
        return _core.Method.hermite(int(self.points))

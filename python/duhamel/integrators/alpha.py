"""The generalized-alpha family on the physical equations: one engine, different
coefficients (Newmark, HHT, Chung-Hulbert, central difference)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from duhamel import _core
from duhamel.integrators.base import DirectIntegrator, newton_options, real, tolerance_options

__all__ = ["HHT", "CentralDifference", "GeneralizedAlpha", "Newmark"]


class _AlphaFamily(DirectIntegrator):
    """A member of the generalized-alpha family (Chung and Hulbert 1993)."""

    @property
    def coefficients(self) -> dict[str, float]:
        """``alpha_m``, ``alpha_f``, ``gamma``, ``beta`` in Chung and Hulbert's convention:
        inertia weighted ``(1 - alpha_m)`` at the end of the step and ``alpha_m`` at its
        start, forces and loads ``(1 - alpha_f)`` and ``alpha_f``."""
        am, af, gamma, beta = self._params()
        return {"alpha_m": am, "alpha_f": af, "gamma": gamma, "beta": beta}

    def _params(self) -> tuple[float, float, float, float]:  # pragma: no cover - abstract
        raise NotImplementedError

    def _method(self) -> Any:
        return _core.Method.alpha(*self._params())


@dataclass(frozen=True)
class Newmark(_AlphaFamily):
    """Newmark's method on the physical equations (implicit for ``beta > 0``).

    ``x1 = x0 + dt v0 + dt^2 ((1/2 - beta) a0 + beta a1)``,
    ``v1 = v0 + dt ((1 - gamma) a0 + gamma a1)``, with the equation of motion enforced at the
    end of the step. The default ``gamma = 1/2, beta = 1/4`` is the average acceleration
    (trapezoidal) rule: second order, unconditionally stable, no numerical damping (spectral
    radius 1 for any step). Unconditional stability needs ``2 beta >= gamma >= 1/2``;
    ``gamma > 1/2`` damps but is first order. For the explicit ``beta = 0`` use
    :class:`CentralDifference`, which checks the stability limit.

    Parameters
    ----------
    gamma, beta : float
        Newmark's parameters, ``>= 0``.
    tol : float
        Newton: relative size of the last update of the end acceleration (measured against
        ``max(|a1|, |v1|/dt, |x1|/dt^2)``).
    max_iter : int
        Newton iterations per step before the run stops with a :class:`duhamel.SolverError`.
    rtol, atol, subdivisions : float or None, float, int
        Steps chosen by tolerance (every member of the family): with `rtol`, the run is
        repeated in steps of ``dt / 2**k``, ``k = 1, 2, ...``, until two successive runs
        differ by at most ``atol + rtol * peak`` at the saved dofs' displacements (their
        difference bounds the finer run's error for a method of order 1 or more once the
        steps resolve the response); the finer run is returned, the saved instants the
        user's, its ``stats.error_estimate`` that difference over the peak and
        ``stats.substeps`` ``2**k``. ``k`` stops at `subdivisions` (default 4): a run still
        above raises :class:`duhamel.SolverError` with ``reason="tolerance"``. Default
        None (the run at `dt`), `atol` 0.

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> sys = duhamel.System(np.eye(1), np.eye(1))
    >>> sol = duhamel.solve(sys, duhamel.Newmark(), t_end=2 * np.pi, dt=2 * np.pi / 10,
    ...                     x0=[1.0])
    >>> theta = 2 * np.arctan(np.pi / 10)   # phase per step: tan(theta/2) = omega dt / 2
    >>> bool(np.allclose(sol.x[:, 0], np.cos(theta * np.arange(11)), rtol=0, atol=1e-14))
    True
    >>> duhamel.Newmark(gamma=0.6, beta=0.3025).coefficients["gamma"]
    0.6
    """

    gamma: float = 0.5
    beta: float = 0.25
    tol: float = 1e-10
    max_iter: int = 25
    rtol: float | None = None
    atol: float = 0.0
    subdivisions: int = 4

    def __post_init__(self) -> None:
        real(self.gamma, "gamma", 0.0)
        real(self.beta, "beta", 0.0)
        newton_options(self.tol, self.max_iter)
        tolerance_options(self)

    def _params(self) -> tuple[float, float, float, float]:
        return (0.0, 0.0, float(self.gamma), float(self.beta))


@dataclass(frozen=True)
class HHT(_AlphaFamily):
    """The Hilber-Hughes-Taylor alpha method (1977), ``-1/3 <= alpha <= 0``.

    Forces and loads are weighted ``(1 + alpha)`` at the end of the step and ``-alpha`` at
    its start, with ``gamma = (1 - 2 alpha)/2`` and ``beta = (1 - alpha)^2/4``: second order,
    unconditionally stable, with numerical damping of the high frequencies: the spectral
    radius tends to ``(1 + alpha)/(1 - alpha)`` as ``dt/T`` grows. ``alpha = 0`` is the
    average acceleration rule. In Chung and Hulbert's notation ``alpha_m = 0``,
    ``alpha_f = -alpha``.

    Parameters
    ----------
    alpha : float
        In ``[-1/3, 0]``.
    tol, max_iter, rtol, atol, subdivisions
        As for :class:`Newmark`.

    Examples
    --------
    >>> import duhamel
    >>> hht = duhamel.HHT(-0.1)
    >>> round(hht.coefficients["gamma"], 12), round(hht.coefficients["beta"], 12)
    (0.6, 0.3025)
    """

    alpha: float
    tol: float = 1e-10
    max_iter: int = 25
    rtol: float | None = None
    atol: float = 0.0
    subdivisions: int = 4

    def __post_init__(self) -> None:
        real(self.alpha, "alpha", -1.0 / 3.0, 0.0)
        newton_options(self.tol, self.max_iter)
        tolerance_options(self)

    def _params(self) -> tuple[float, float, float, float]:
        a = float(self.alpha)
        return (0.0, -a, 0.5 - a, (1.0 - a) ** 2 / 4.0)


@dataclass(frozen=True)
class GeneralizedAlpha(_AlphaFamily):
    """The generalized-alpha method of Chung and Hulbert (1993), ``0 <= rho_inf <= 1``.

    ``alpha_m = (2 rho_inf - 1)/(rho_inf + 1)``, ``alpha_f = rho_inf/(rho_inf + 1)``,
    ``gamma = 1/2 - alpha_m + alpha_f``, ``beta = (1 - alpha_m + alpha_f)^2/4``: second
    order, unconditionally stable, with the spectral radius tending to `rho_inf` as ``dt/T``
    grows (``rho_inf = 1``: no numerical damping; ``0``: the highest frequencies are
    annihilated in one step), and the least low-frequency damping for that high-frequency
    damping.

    Parameters
    ----------
    rho_inf : float
        Spectral radius at infinite ``dt/T``, in ``[0, 1]``.
    tol, max_iter, rtol, atol, subdivisions
        As for :class:`Newmark`.

    Examples
    --------
    >>> import duhamel
    >>> c = duhamel.GeneralizedAlpha(0.5).coefficients
    >>> [round(c[k], 12) for k in ("alpha_m", "alpha_f", "gamma", "beta")]
    [0.0, 0.333333333333, 0.833333333333, 0.444444444444]
    """

    rho_inf: float
    tol: float = 1e-10
    max_iter: int = 25
    rtol: float | None = None
    atol: float = 0.0
    subdivisions: int = 4

    def __post_init__(self) -> None:
        real(self.rho_inf, "rho_inf", 0.0, 1.0)
        newton_options(self.tol, self.max_iter)
        tolerance_options(self)

    def _params(self) -> tuple[float, float, float, float]:
        r = float(self.rho_inf)
        am = (2.0 * r - 1.0) / (r + 1.0)
        af = r / (r + 1.0)
        return (am, af, 0.5 - am + af, (1.0 - am + af) ** 2 / 4.0)


@dataclass(frozen=True)
class CentralDifference(_AlphaFamily):
    """The central difference method: explicit, second order, stable for
    ``dt <= 2/omega_max``.

    Run as Newmark with ``gamma = 1/2``, ``beta = 0``: the displacement update is explicit and
    the step equation involves only ``M`` (and, with damping or velocity-dependent elements,
    ``C`` and the elements' velocity tangents, since the end velocity is implicit), so no
    stiffness matrix is ever factorised. In that form viscous damping does not lower the
    stability limit ``2/omega_max``.

    :func:`duhamel.solve` refuses a step above the limit with a ``ValueError`` that gives
    ``dt``, the highest natural frequency and the limit. ``omega_max`` is computed from the
    stiffness (with the elements' tangent stiffness at the initial state) and the mass (at its
    smallest value over the run when a mass law is attached); a nonlinear response that stiffens
    later can still exceed it, and then stops with a :class:`duhamel.SolverError`.

    Parameters
    ----------
    allow_unstable : bool
        Run even above the stability limit (the response then grows without bound).
    tol, max_iter
        As for :class:`Newmark` (Newton on the end velocity with velocity-dependent elements).
    rtol, atol, subdivisions
        As for :class:`Newmark` (each finer run must also keep within the stability limit).

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> sys = duhamel.System(np.eye(1), np.array([[100.0]]))      # omega = 10 rad/s
    >>> duhamel.solve(sys, duhamel.CentralDifference(), t_end=1.0, dt=0.25, x0=[1.0])
    Traceback (most recent call last):
    ...
    ValueError: `dt` = 0.25 exceeds the stability limit of the central difference method, \
2/omega_max = 0.2 (highest natural frequency omega_max = 10 rad/s); reduce `dt` or pass \
CentralDifference(allow_unstable=True)
    """

    allow_unstable: bool = False
    tol: float = 1e-10
    max_iter: int = 25
    rtol: float | None = None
    atol: float = 0.0
    subdivisions: int = 4

    def __post_init__(self) -> None:
        if not isinstance(self.allow_unstable, bool):
            raise TypeError(f"`allow_unstable` must be a bool, got {self.allow_unstable!r}")
        newton_options(self.tol, self.max_iter)
        tolerance_options(self)

    def _params(self) -> tuple[float, float, float, float]:
        return (0.0, 0.0, 0.5, 0.0)

"""Time integrators: small configuration objects passed to :func:`duhamel.solve`."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from duhamel import _core

__all__ = [
    "HHT",
    "CentralDifference",
    "CubicHermite",
    "DirectIntegrator",
    "GeneralizedAlpha",
    "Newmark",
    "Semianalytic",
]

_CHOICES = {
    "scheme": ("a", "b", "c"),
    "quadrature": ("trapezoid", "parabolic", "exact"),
    "mass_treatment": ("eliminate", "estimate"),
    "solver": ("auto", "newton"),
    "coupling": ("auto", "exact", "pseudo-force"),
}


@dataclass(frozen=True)
class Semianalytic:
    """The semi-analytic (Duhamel, "BEM in time") integrator of Holl, Belyaev and Irschik.

    Every modal oscillator of the linear background system is advanced with its exact
    transition and load-transfer matrices, so a linear time-invariant system is integrated
    exactly (to round-off) whatever the step, for loads that are polynomials of degree <= 2
    in time within each step. Linear couplings of the modes (non-classical damping,
    gyroscopic and cross-coupled terms) are integrated exactly too, in the first-order
    modes of the coupled system (see `coupling`). Everything else — element forces,
    time-varying mass, couplings that follow a time-varying speed — enters as a modal
    pseudo-force whose evolution over the step is approximated.

    Parameters
    ----------
    modes : int, optional
        Keep only the lowest `modes` modes (modal reduction). Default: all modes.
    scheme : {"a", "b", "c"}
        State inside the step for evaluating pseudo-forces (the paper's eq. 20): "a" constant
        velocity ``(v0 + v1)/2``; "b" displacement linear from ``x0`` to ``x1``, velocity
        ``(x1 - x0)/dt`` — unconditionally stable, the default; "c" the parabola through
        ``x0`` (slope ``v0``) and ``x1``.
    quadrature : {"trapezoid", "parabolic", "exact"}
        How the pseudo-force along that state is integrated against ``A(dt - tau)``: linear
        between its start and end values; the parabola through start, middle and end; or
        the cubic through four values, exact for polynomial forces of degree <= 3 along
        schemes "a" and "b". The default "trapezoid" is the most accurate in our
        measurements (docs/nonlinear.md: 5x smaller errors on the paper's Duffing case).
    tol : float
        Relative tolerance of the Newton updates.
    max_iter : int
        Newton iterations per step before the run stops with a :class:`duhamel.SolverError`.
    mass_treatment : {"eliminate", "estimate"}
        Time-varying mass: divide the equation of motion by the mass law (no acceleration
        needed; the default, more accurate) or estimate the acceleration as ``(v1 - v0)/dt``.
    solver : {"auto", "newton"}
        "auto" solves a single-mode step with polynomial forces of degree <= 3 in closed form
        (the cubic of the paper); "newton" always iterates.
    coupling : {"auto", "exact", "pseudo-force"}
        Modal couplings — non-classical damping, gyroscopic and cross-coupled
        (circulatory) terms, i.e. constant :class:`duhamel.elements.LinearCoupling`
        elements and a damping matrix that the modes do not diagonalise. "exact" integrates
        the coupled linear background exactly in its first-order (complex) modes
        (docs/coupled.md): a linear system is then exact like an uncoupled one, and with
        nonlinear elements only the element forces are pseudo-forces (scheme "b",
        "trapezoid" quadrature). "pseudo-force" treats the couplings as the paper does, as
        pseudo-forces (second order in ``dt``). "auto" (default) is "exact" where it
        applies and the first-order eigenvectors are well conditioned (condition number
        <= 1e4), "pseudo-force" otherwise (a mass law, couplings scaled by a time-varying
        speed law, another scheme or quadrature with elements, a nearly defective system).
        ``solve`` raises ValueError when "exact" cannot be honoured.

    Examples
    --------
    >>> import duhamel
    >>> duhamel.Semianalytic()
    Semianalytic(modes=None, scheme='b', quadrature='trapezoid', tol=1e-10, max_iter=25, \
mass_treatment='eliminate', solver='auto', coupling='auto')
    >>> duhamel.Semianalytic(modes=5, quadrature="exact").quadrature
    'exact'
    """

    modes: int | None = None
    scheme: str = "b"
    quadrature: str = "trapezoid"
    tol: float = 1e-10
    max_iter: int = 25
    mass_treatment: str = "eliminate"
    solver: str = "auto"
    coupling: str = "auto"

    def __post_init__(self) -> None:
        m = self.modes
        if m is not None and (isinstance(m, bool) or not isinstance(m, int) or m < 1):
            raise ValueError(f"`modes` must be a positive integer or None, got {m!r}")
        for name, allowed in _CHOICES.items():
            value = getattr(self, name)
            if value not in allowed:
                raise ValueError(f"`{name}` must be one of {allowed}, got {value!r}")
        tol = self.tol
        if isinstance(tol, bool) or not isinstance(tol, int | float) or not (0 < tol < 1):
            raise ValueError(f"`tol` must be a number in (0, 1), got {tol!r}")
        if math.isnan(tol):  # pragma: no cover - excluded above
            raise ValueError("`tol` must not be NaN")
        it = self.max_iter
        if isinstance(it, bool) or not isinstance(it, int) or it < 1:
            raise ValueError(f"`max_iter` must be a positive integer, got {it!r}")

    def _options(self) -> tuple[str, str, float, int, str]:
        return (self.scheme, self.quadrature, float(self.tol), int(self.max_iter), self.solver)


# --------------------------------------------------------------------------------------------
# Direct integrators: the reference methods, on the physical equations
# --------------------------------------------------------------------------------------------


def _real(value: object, name: str, lo: float | None = None, hi: float | None = None) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise TypeError(f"`{name}` must be a real number, got {type(value).__name__}")
    out = float(value)
    if not math.isfinite(out):
        raise ValueError(f"`{name}` must be finite, got {out!r}")
    if (lo is not None and out < lo) or (hi is not None and out > hi):
        lo_s = "-inf" if lo is None else f"{lo:g}"
        hi_s = "inf" if hi is None else f"{hi:g}"
        raise ValueError(f"`{name}` must be in [{lo_s}, {hi_s}], got {out!r}")
    return out


def _newton_options(tol: object, max_iter: object) -> None:
    if isinstance(tol, bool) or not isinstance(tol, int | float) or not (0 < tol < 1):
        raise ValueError(f"`tol` must be a number in (0, 1), got {tol!r}")
    if isinstance(max_iter, bool) or not isinstance(max_iter, int) or max_iter < 1:
        raise ValueError(f"`max_iter` must be a positive integer, got {max_iter!r}")


class DirectIntegrator:
    """Base class of the direct integrators, which step the physical equations of motion
    ``M(t) x'' + C x' + K x + r(x, x', t) = f(t)`` (no modal transformation).

    See docs/direct.md. :func:`duhamel.solve` returns a :class:`~duhamel.Solution` whose
    ``modal`` is None for them.
    """

    tol: float
    max_iter: int

    def _method(self) -> Any:  # pragma: no cover - abstract
        """The method as the core takes it (a ``_core.Method``)."""
        raise NotImplementedError


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

    def __post_init__(self) -> None:
        _real(self.gamma, "gamma", 0.0)
        _real(self.beta, "beta", 0.0)
        _newton_options(self.tol, self.max_iter)

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
    tol, max_iter
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

    def __post_init__(self) -> None:
        _real(self.alpha, "alpha", -1.0 / 3.0, 0.0)
        _newton_options(self.tol, self.max_iter)

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
    tol, max_iter
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

    def __post_init__(self) -> None:
        _real(self.rho_inf, "rho_inf", 0.0, 1.0)
        _newton_options(self.tol, self.max_iter)

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

    def __post_init__(self) -> None:
        if not isinstance(self.allow_unstable, bool):
            raise TypeError(f"`allow_unstable` must be a bool, got {self.allow_unstable!r}")
        _newton_options(self.tol, self.max_iter)

    def _params(self) -> tuple[float, float, float, float]:
        return (0.0, 0.0, 0.5, 0.0)


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

    def __post_init__(self) -> None:
        p = self.points
        if isinstance(p, bool) or not isinstance(p, int) or not 2 <= p <= 8:
            raise ValueError(f"`points` must be an integer from 2 to 8, got {p!r}")
        _newton_options(self.tol, self.max_iter)

    def _method(self) -> Any:
        return _core.Method.hermite(int(self.points))

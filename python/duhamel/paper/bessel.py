"""Figs. 5-8: free vibration with an exponentially varying mass (section 4.3).

``(m x')' + m0 omega^2 x = 0`` with the mass ratio ``m / m0 = K exp(-2 a omega t)`` (eq. 41),
whose exact solution is in Bessel functions of order one (eq. 44,
:func:`duhamel.exact.bessel_mass`). The paper's "c = a = 1/20" means ``a = 1/20`` and
``chi = a sqrt(K) = 1/20``, so ``K = 1`` (NOTES.md section 3); ``x0 = 1``, ``x0' = 0``. The
paper gives no time span: we use ``omega t`` in ``[0, 20]``, over which the mass falls to
``exp(-2) = 13.5 %`` and the instantaneous frequency rises to ``e omega``.

The semi-analytic runs use the momentum form of the mass law, a constant stiffness and the
default treatment (scheme (b), trapezoid, mass change eliminated; docs/mass.md).
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

import duhamel
from duhamel import exact
from duhamel.paper._common import OMEGA, PERIOD, Array, Claim, fit_order, fmt, local_orders

__all__ = ["BesselData", "Fig8Data", "bessel_system", "fig8", "figs5to7"]

A = 1.0 / 20.0
K = 1.0
X0, V0 = 1.0, 0.0
T_END = 20.0 / OMEGA


def bessel_system(a: float = A, K: float = K) -> duhamel.System:
    """``(m x')' + m0 omega^2 x = 0`` with ``m = m0 K exp(-2 a omega t)`` (``m0 = 1``).

    Parameters
    ----------
    a, K : float
        Decay rate and initial mass ratio (the paper: 1/20 and 1).

    Returns
    -------
    System

    Examples
    --------
    >>> from duhamel.paper.bessel import bessel_system
    >>> bessel_system().mass_law.law
    Exponential(rate=-0.1, scale=1.0)
    """
    system = duhamel.System([[1.0]], [[OMEGA**2]])
    return system.set_mass_law(
        duhamel.mass.Exponential(rate=-2.0 * a * OMEGA, scale=K),
        form="momentum",
        scale_stiffness=False,
    )


def _solve(steps_per_period: int, t_end: float, integrator: object = None) -> duhamel.Solution:
    return duhamel.solve(
        bessel_system(),
        integrator if integrator is not None else duhamel.Semianalytic(),
        t_end=t_end,
        dt=PERIOD / steps_per_period,
        x0=[X0],
        v0=[V0],
    )


@dataclass(frozen=True, eq=False)
class BesselData:
    """Figs. 5-7: mass ratio, displacement and velocity, phase plane.

    Attributes
    ----------
    t : ndarray
        A fine grid of ``[0, t_end]`` for the exact curves.
    mass_ratio : ndarray
        ``m(t) / m0 = K exp(-2 a omega t)`` on `t` (Fig. 5).
    x, v : ndarray
        Eq. 44 on `t`: ``x / x0`` and ``x' / (x0 omega)`` (Figs. 6, 7).
    t_num, x_num, v_num : ndarray
        The semi-analytic run at ``omega dt = 2 pi / steps_per_period``, normalised alike.
    steps_per_period : int
    ode_deviation : float
        Largest difference between eq. 44 and a DOP853 solution (rtol 1e-13) of the
        equation of motion, relative to ``max |x|``: eq. 44 checked independently.
    """

    t: Array
    mass_ratio: Array
    x: Array
    v: Array
    t_num: Array
    x_num: Array
    v_num: Array
    steps_per_period: int
    ode_deviation: float

    @property
    def max_error(self) -> float:
        """Largest displacement error of the semi-analytic run, ``max |x - x_exact| / x0``."""
        ref = exact.bessel_mass(self.t_num, A, K, OMEGA, X0, V0)[0]
        return float(np.abs(self.x_num - ref / X0).max())

    def claims(self) -> list[Claim]:
        """The paper's statements about Figs. 5-7, with our numbers."""
        return [
            Claim(
                "eq. 44 (Bessel J1, Y1) is the exact free vibration for m/m0 = K exp(-2 a omega t)",
                "eqs. 41-44, Figs. 5-7",
                f"eq. 44 vs DOP853 (rtol 1e-13): {fmt(self.ode_deviation, 2)} of max |x|",
                self.ode_deviation < 1e-9,
                "with the abbreviation c = a sqrt(K); a = 1/20, K = 1 (NOTES.md section 3)",
            ),
            Claim(
                "the mass decays, the vibration stiffens and its amplitude changes",
                "Figs. 5-7",
                f"m/m0 from 1 to {self.mass_ratio[-1]:.3f}; max |x|/x0 {np.abs(self.x).max():.3f}, "
                f"max |x'|/(x0 omega) {np.abs(self.v).max():.3f} over omega t in "
                f"[0, {OMEGA * self.t[-1]:g}]",
                None,
                "the paper gives no time span",
            ),
            Claim(
                f"semi-analytic run drawn in Figs. 6, 7 (omega dt = 2 pi/{self.steps_per_period})",
                "(not stated)",
                f"max |x - x_exact| / x0 = {fmt(self.max_error)}",
                None,
            ),
        ]


def figs5to7(steps_per_period: int = 40, t_end: float = T_END, n_fine: int = 801) -> BesselData:
    """Data of Figs. 5-7: the exact solution (eq. 44) and a semi-analytic run.

    Parameters
    ----------
    steps_per_period : int
        Step of the semi-analytic run drawn with the exact curves.
    t_end : float
        End of the time span (``omega t = 20`` by default).
    n_fine : int
        Points of the grid of the exact curves.

    Returns
    -------
    BesselData

    Examples
    --------
    >>> from duhamel.paper import figs5to7
    >>> data = figs5to7()
    >>> round(float(data.mass_ratio[-1]), 4), round(data.max_error, 3)
    (0.1353, 0.143)
    """
    t = np.linspace(0.0, t_end, int(n_fine))
    x, v = exact.bessel_mass(t, A, K, OMEGA, X0, V0)

    def rhs(s: float, y: Array) -> list[float]:
        mu = K * np.exp(-2.0 * A * OMEGA * s)  # (mu x')' + omega^2 x = 0
        return [y[1], 2.0 * A * OMEGA * y[1] - OMEGA**2 * y[0] / mu]

    ode = solve_ivp(rhs, (0.0, t_end), [X0, V0], method="DOP853", rtol=1e-13, atol=1e-15, t_eval=t)
    deviation = float(np.abs(ode.y[0] - x).max() / np.abs(x).max())
    sol = _solve(steps_per_period, t_end)
    return BesselData(
        t=t,
        mass_ratio=K * np.exp(-2.0 * A * OMEGA * t),
        x=x / X0,
        v=v / (X0 * OMEGA),
        t_num=sol.t,
        x_num=sol.x[:, 0] / X0,
        v_num=sol.v[:, 0] / (X0 * OMEGA),
        steps_per_period=int(steps_per_period),
        ode_deviation=deviation,
    )


@dataclass(frozen=True, eq=False)
class Fig8Data:
    """Fig. 8: solutions for several steps and the measured order of convergence.

    Attributes
    ----------
    steps : tuple of int
        Steps per period ``T = 2 pi / omega`` (``dt = T / n``).
    solutions : dict of int to (ndarray, ndarray)
        ``(t, x / x0)`` of the semi-analytic run per step count.
    errors : dict of int to float
        ``max |x - x_exact| / x0`` per step count (semi-analytic, default).
    newmark_errors : dict of int to float
        The same for Newmark (1/2, 1/4), for comparison.
    order_steps : tuple of int
        The step counts over which :attr:`order` is fitted (the asymptotic range).
    t, x : ndarray
        The exact solution on a fine grid.
    """

    steps: tuple[int, ...]
    solutions: dict[int, tuple[Array, Array]]
    errors: dict[int, float]
    newmark_errors: dict[int, float]
    order_steps: tuple[int, ...]
    t: Array
    x: Array

    @property
    def order(self) -> float:
        """Least-squares slope of ``log(error)`` against ``log(dt)`` over `order_steps`."""
        return fit_order(
            [1.0 / n for n in self.order_steps], [self.errors[n] for n in self.order_steps]
        )

    @property
    def newmark_order(self) -> float:
        """The same slope for Newmark."""
        return fit_order(
            [1.0 / n for n in self.order_steps], [self.newmark_errors[n] for n in self.order_steps]
        )

    def claims(self) -> list[Claim]:
        """The paper's statements about Fig. 8, with our numbers."""
        errs = [self.errors[n] for n in self.steps]
        orders = local_orders(self.steps, errs)
        span = f"T/{self.order_steps[0]}..T/{self.order_steps[-1]}"
        return [
            Claim(
                "the convergence of the present method is of order two (halving dt divides "
                "the error by 4)",
                "Fig. 8, section 4.3",
                f"order {self.order:.3f} ({span}); local orders "
                + ", ".join(f"{q:.2f}" for q in orders),
                abs(self.order - 2.0) < 0.1,
                "holds = fitted order within 0.1 of 2",
            ),
            Claim(
                "the solutions converge as the step is reduced",
                "Fig. 8",
                "max |x - x_exact| / x0 "
                + ", ".join(f"{fmt(e)} (T/{n})" for n, e in zip(self.steps, errs, strict=True)),
                all(b < a for a, b in itertools.pairwise(errs)),
            ),
            Claim(
                "Newmark on the same case, for comparison",
                "(not in the paper)",
                "max |x - x_exact| / x0 "
                + ", ".join(f"{fmt(self.newmark_errors[n])} (T/{n})" for n in self.steps)
                + f"; order {self.newmark_order:.3f}",
                None,
            ),
        ]


def fig8(
    steps: tuple[int, ...] = (10, 20, 40, 80, 160, 320),
    order_steps: tuple[int, ...] | None = None,
    t_end: float = T_END,
) -> Fig8Data:
    """Data of Fig. 8: the Bessel-mass case for several steps, and the measured order.

    Parameters
    ----------
    steps : tuple of int
        Steps per period, increasing.
    order_steps : tuple of int, optional
        Where to fit the order; default: the last four of `steps` (from ``T/10`` the first
        halvings are pre-asymptotic, docs/mass.md).
    t_end : float
        End of the run.

    Returns
    -------
    Fig8Data

    Examples
    --------
    >>> from duhamel.paper import fig8
    >>> data = fig8(steps=(40, 80, 160))
    >>> round(data.order, 1)
    2.0
    """
    steps = tuple(int(n) for n in steps)
    order_steps = tuple(order_steps) if order_steps is not None else steps[-4:]
    solutions, errors, nm_errors = {}, {}, {}
    for n in steps:
        sol = _solve(n, t_end)
        ref = exact.bessel_mass(sol.t, A, K, OMEGA, X0, V0)[0]
        solutions[n] = (sol.t, sol.x[:, 0] / X0)
        errors[n] = float(np.abs(sol.x[:, 0] - ref).max() / X0)
        nm = _solve(n, t_end, duhamel.Newmark(gamma=0.5, beta=0.25))
        nm_errors[n] = float(np.abs(nm.x[:, 0] - ref).max() / X0)
    t = np.linspace(0.0, t_end, 801)
    x = exact.bessel_mass(t, A, K, OMEGA, X0, V0)[0] / X0
    return Fig8Data(steps, solutions, errors, nm_errors, order_steps, t, x)

"""Fig. 3 and the CPU-time ratio: free vibration of the undamped Duffing oscillator.

The paper's section 4.1: ``X'' + omega^2 X + b X^3 = 0`` with ``b X0^2 = 4 omega^2``,
``X0' = 0``, stepped with ``omega dt = 2 pi / 100`` (scheme (b), the step equation a cubic in
``X1`` solved in closed form). Fig. 3 plots the error in the phase plane, normalised
displacement error against normalised velocity error, for the present method, Newmark's
method and Argyris' cubic Hermitian method. The reference is the Jacobi ``cn`` solution
(:func:`duhamel.exact.duffing`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import duhamel
from duhamel import exact
from duhamel.paper._common import OMEGA, PERIOD, Array, Claim, fmt

__all__ = ["CpuData", "DuffingRun", "Fig3Data", "cpu_ratios", "duffing_system", "fig3"]

#: ``b X0^2 = 4 omega^2`` with ``X0 = 1``.
X0 = 1.0
B = 4.0 * OMEGA**2 / X0**2

#: The methods of Fig. 3, in plotting order.
METHODS: dict[str, object] = {
    "semi-analytic (b), trapezoid (default)": duhamel.Semianalytic(),
    "semi-analytic (b), parabolic (paper)": duhamel.Semianalytic(quadrature="parabolic"),
    "Newmark (1/2, 1/4)": duhamel.Newmark(gamma=0.5, beta=0.25),
    "cubic Hermite": duhamel.CubicHermite(),
}
DEFAULT, PARABOLIC, NEWMARK, HERMITE = METHODS


def duffing_system() -> duhamel.System:
    """The paper's Duffing oscillator, ``x'' + omega^2 x + b x^3 = 0`` (``b x0^2 = 4 omega^2``).

    Returns
    -------
    System

    Examples
    --------
    >>> from duhamel.paper.duffing import duffing_system
    >>> duffing_system()
    System(n_dof=1, damping='none', loads=0, elements=1)
    """
    system = duhamel.System(np.eye(1), OMEGA**2 * np.eye(1))
    return system.add(duhamel.elements.Cubic(0, k3=B))


@dataclass(frozen=True, eq=False)
class DuffingRun:
    """One method's run: times and the normalised errors of Fig. 3.

    Attributes
    ----------
    t : ndarray
        Times.
    eps : ndarray
        ``(w_calc - w_exact) / w0``.
    sigma : ndarray
        ``(w'_calc - w'_exact) / (w0 omega)``.
    stats : SolveStats
        The run's cost (steps solved in closed form, Newton iterations).
    """

    t: Array
    eps: Array
    sigma: Array
    stats: duhamel.SolveStats

    @property
    def max_eps(self) -> float:
        """Largest displacement error ``max |eps|``."""
        return float(np.abs(self.eps).max())

    @property
    def max_sigma(self) -> float:
        """Largest velocity error ``max |sigma|``."""
        return float(np.abs(self.sigma).max())


@dataclass(frozen=True, eq=False)
class Fig3Data:
    """Fig. 3: error phase planes of the Duffing oscillator.

    Attributes
    ----------
    runs : dict of str to DuffingRun
        Per method (keys of ``METHODS``).
    dt : float
        The step (``omega dt = 2 pi / steps_per_period``).
    periods : float
        Length of the run in background periods ``2 pi / omega``.
    """

    runs: dict[str, DuffingRun]
    dt: float
    periods: float

    def claims(self) -> list[Claim]:
        """The paper's accuracy statements about Fig. 3, with our numbers."""
        e = {k: r.max_eps for k, r in self.runs.items()}
        steps = self.runs[DEFAULT].stats
        return [
            Claim(
                "the present method is more accurate than Newmark (default trapezoid quadrature)",
                "Fig. 3, section 4.1: 'the present method is more accurate'",
                f"max |eps| {fmt(e[DEFAULT])} vs Newmark {fmt(e[NEWMARK])}",
                e[DEFAULT] < e[NEWMARK],
                "NOTES.md section 2: 0.035 vs 0.105",
            ),
            Claim(
                "the present method is more accurate than Newmark (the paper's parabolic "
                "load interpolation of the pseudo-force)",
                "as above",
                f"max |eps| {fmt(e[PARABOLIC])} vs Newmark {fmt(e[NEWMARK])}",
                e[PARABOLIC] < e[NEWMARK],
                "NOTES.md section 2: 0.166 vs 0.105; the claim depends on the quadrature",
            ),
            Claim(
                "the present method is more accurate than the cubic Hermitian method",
                "Fig. 3 (Argyris [25])",
                f"max |eps| {fmt(e[DEFAULT])} vs cubic Hermite {fmt(e[HERMITE])}",
                e[DEFAULT] < e[HERMITE],
                "our cubic Hermite element is a fourth-order reconstruction (reference [25] "
                "is not available); NOTES.md: 7e-5",
            ),
            Claim(
                "each step is a cubic in X1, solved without iteration",
                "section 4.1",
                f"{steps.closed_form_steps} of {steps.steps} steps in closed form, "
                f"{steps.newton_iterations} Newton iterations",
                steps.closed_form_steps == steps.steps and steps.newton_iterations == 0,
            ),
        ]


def _run(integrator: object, t_end: float, dt: float) -> DuffingRun:
    sol = duhamel.solve(duffing_system(), integrator, t_end=t_end, dt=dt, x0=[X0])
    w, v = exact.duffing(sol.t, OMEGA, B, X0)
    return DuffingRun(sol.t, (sol.x[:, 0] - w) / X0, (sol.v[:, 0] - v) / (X0 * OMEGA), sol.stats)


def fig3(periods: float = 10.0, steps_per_period: int = 100) -> Fig3Data:
    """Data of Fig. 3: the Duffing oscillator's error phase plane for four methods.

    Parameters
    ----------
    periods : float
        Run length in background periods ``2 pi / omega`` (NOTES.md: 10, i.e. 1000 steps).
    steps_per_period : int
        ``omega dt = 2 pi / steps_per_period`` (the paper: 100).

    Returns
    -------
    Fig3Data

    Examples
    --------
    >>> from duhamel.paper import fig3
    >>> data = fig3()
    >>> {k: round(r.max_eps, 4) for k, r in data.runs.items()}  # doctest: +NORMALIZE_WHITESPACE
    {'semi-analytic (b), trapezoid (default)': 0.0348,
     'semi-analytic (b), parabolic (paper)': 0.1656,
     'Newmark (1/2, 1/4)': 0.1052,
     'cubic Hermite': 0.0001}
    """
    dt = PERIOD / steps_per_period
    t_end = periods * PERIOD
    runs = {name: _run(integrator, t_end, dt) for name, integrator in METHODS.items()}
    return Fig3Data(runs, dt, float(periods))


@dataclass(frozen=True, eq=False)
class CpuData:
    """Time-loop cost on the Duffing case, each method against Newmark, measured together.

    Attributes
    ----------
    seconds_per_step : dict of str to ndarray
        Per method, the loop time per step (``stats.wall_time / steps``) of every repeat.
    steps : int
        Steps per run.
    repeats : int
        Runs per method, interleaved (method 1, method 2, ..., method 1, ...).
    """

    seconds_per_step: dict[str, Array]
    steps: int
    repeats: int

    def best(self, name: str) -> float:
        """Fastest loop time per step of `name` over the repeats (seconds)."""
        return float(np.min(self.seconds_per_step[name]))

    def median(self, name: str) -> float:
        """Median loop time per step of `name` over the repeats (seconds)."""
        return float(np.median(self.seconds_per_step[name]))

    def ratio(self, name: str, reference: str = NEWMARK, *, statistic: str = "best") -> float:
        """Loop time of `name` over that of `reference` (Newmark by default).

        `statistic` is ``"best"`` (fastest repeat of each, the least disturbed by other
        processes) or ``"median"``.
        """
        pick = self.best if statistic == "best" else self.median
        return pick(name) / pick(reference)

    def claims(self) -> list[Claim]:
        """The paper's CPU-time statement, with our ratio."""
        ns = {k: 1e9 * self.best(k) for k in self.seconds_per_step}
        r, r_med = self.ratio(DEFAULT), self.ratio(DEFAULT, statistic="median")
        out = [
            Claim(
                "the CPU time of the present method was smaller than Newmark's by a factor "
                "of 1/2 (Duffing, omega dt = 2 pi/100)",
                "section 4.1: factor 1/2",
                f"{ns[DEFAULT]:.0f} ns vs {ns[NEWMARK]:.0f} ns per step: ratio {r:.2f} "
                f"(median of the repeats: {r_med:.2f})",
                r <= 0.6,
                f"best of {self.repeats} interleaved runs of {self.steps} steps each, time "
                "loop only, both in the same Rust engine; holds = ratio <= 0.6",
            )
        ]
        for name, what in (
            (NEWTON, "the same method with Newton iterations instead of the closed-form cubic"),
            (HERMITE, "cubic Hermite against Newmark"),
        ):
            if name in ns:
                out.append(
                    Claim(
                        what,
                        "(not in the paper)",
                        f"{ns[name]:.0f} ns per step: ratio {self.ratio(name):.2f}",
                        None,
                    )
                )
        return out


NEWTON = "semi-analytic (b), Newton"


def cpu_ratios(repeats: int = 5, periods: float = 1000.0, steps_per_period: int = 100) -> CpuData:
    """Loop time per step of the semi-analytic method and of Newmark on the Duffing case.

    The runs of the methods are interleaved (one of each, `repeats` times) so that both
    see the same machine load; the time is the Rust loop's own clock
    (:attr:`duhamel.SolveStats.wall_time`, every step saved), without the Python set-up.
    The run is long (1e5 steps by default) so that the fixed cost of a run (allocating the
    output) does not count; the paper's 1000 steps take about 0.2 ms.

    Parameters
    ----------
    repeats : int
        Runs per method.
    periods : float
        Run length in background periods.
    steps_per_period : int
        ``omega dt = 2 pi / steps_per_period`` (the paper: 100).

    Returns
    -------
    CpuData

    Examples
    --------
    >>> from duhamel.paper import cpu_ratios
    >>> data = cpu_ratios(repeats=2, periods=10)
    >>> data.steps, sorted(data.seconds_per_step)[0]
    (1000, 'Newmark (1/2, 1/4)')
    >>> 0.0 < data.ratio("semi-analytic (b), trapezoid (default)") < 2.0
    True
    """
    methods = {
        DEFAULT: METHODS[DEFAULT],
        NEWMARK: METHODS[NEWMARK],
        NEWTON: duhamel.Semianalytic(solver="newton"),
        HERMITE: METHODS[HERMITE],
    }
    dt = PERIOD / steps_per_period
    t_end = periods * PERIOD
    system = duffing_system()
    times: dict[str, list[float]] = {k: [] for k in methods}
    steps = 0
    for _ in range(int(repeats)):
        for name, integrator in methods.items():
            sol = duhamel.solve(system, integrator, t_end=t_end, dt=dt, x0=[X0])
            steps = sol.stats.steps
            times[name].append(sol.stats.wall_time / steps)
    return CpuData({k: np.array(v) for k, v in times.items()}, steps, int(repeats))

"""Table 1 of section 4.4: modal reduction (CPU time, error against the full model) and
Newmark at the same accuracy."""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

import duhamel
from duhamel.paper._common import Array, Claim, fit_order, fmt
from duhamel.paper.rotor_model import (
    COUPLING,
    DT,
    PAPER_CPU,
    POSITIONS,
    SMALL,
    T_END,
    _planar,
    _relative_error,
    paper_system,
    static_scale,
)

__all__ = ["Table1Data", "table1"]


@dataclass(frozen=True, eq=False)
class Table1Data:
    """Table 1: modal reduction (CPU time, error against the full model) and Newmark.

    Attributes
    ----------
    modes : tuple of int
        Retained modes, the first the full model (20).
    seconds : dict of int to ndarray
        Loop time (:attr:`duhamel.SolveStats.wall_time`, s) of every repeat per mode count.
    newmark_seconds : ndarray
        Loop time of ``duhamel.Newmark()`` at the same step, every repeat.
    errors : dict of int to ndarray, shape (4,)
        Per position (:data:`POSITIONS`), ``max_t |r_m - r_full| / max_t |r_full|`` of the
        paper's case (``beta``, ``xi``).
    linear_errors : dict of int to ndarray, shape (4,)
        The same for the linear rotor (``beta = 0``, ``xi = 0``).
    accuracy : dict of str to float
        Largest error over the positions against a converged run (the full semi-analytic
        model at ``dt / refine``), in units of the orbit size: ``"semi-analytic"`` and
        ``"Newmark"`` at ``dt``, ``"Newmark dt/k"`` at the finer steps tried.
    newmark_equal : tuple of (int, float, bool)
        The smallest ``k`` for which Newmark at ``dt / k`` is as accurate as the
        semi-analytic method at ``dt``, its loop time (s), and whether it was reached (else
        the largest ``k`` tried).
    beta, xi, dt, t_end : float
    steps : int
    repeats : int
    refine : int
    """

    modes: tuple[int, ...]
    seconds: dict[int, Array]
    newmark_seconds: Array
    errors: dict[int, Array]
    linear_errors: dict[int, Array]
    accuracy: dict[str, float]
    newmark_equal: tuple[int, float, bool]
    beta: float
    xi: float
    dt: float
    t_end: float
    steps: int
    repeats: int
    refine: int
    corrected: dict[int, tuple[int, Array]] = field(default_factory=dict)

    @property
    def full(self) -> int:
        """The full model's number of modes."""
        return self.modes[0]

    def relative_cpu(self, m: int) -> float:
        """Best loop time with `m` modes over the full model's, in %."""
        return 100.0 * float(self.seconds[m].min() / self.seconds[self.full].min())

    @property
    def newmark_ratio(self) -> float:
        """Best Newmark loop time over the full semi-analytic model's, same step."""
        return float(self.newmark_seconds.min() / self.seconds[self.full].min())

    def cost_exponent(self) -> float:
        """Slope of log(best loop time) against log(modes) over every mode count."""
        return fit_order(self.modes, [self.seconds[m].min() for m in self.modes])

    def claims(self) -> list[Claim]:
        """Table 1 and the statements of section 4.4 and the conclusion about it."""
        bearings, disks = slice(0, 2), slice(2, 4)
        out = []
        for m in self.modes:
            e, lin = self.errors[m], self.linear_errors[m]
            paper = f"{PAPER_CPU[m]:.0f} %" if m in PAPER_CPU else "-"
            out.append(
                Claim(
                    f"Table 1: {m} modal coordinates",
                    f"relative CPU time {paper}",
                    f"relative loop time {self.relative_cpu(m):.0f} % "
                    f"({1e6 * self.seconds[m].min() / self.steps:.1f} us per step); "
                    f"error bearings {100 * e[bearings].max():.1f} %, disks "
                    f"{100 * e[disks].max():.1f} % (linear rotor: "
                    f"{100 * lin[bearings].max():.1f} %, {100 * lin[disks].max():.1f} %)",
                    None,
                    "error = max_t |r_m - r_full| / max_t |r_full| per position",
                )
            )
        reduced = [m for m in self.modes if m != self.full]
        ours = "/".join(f"{self.relative_cpu(m):.0f}" for m in self.modes)
        theirs = "/".join(f"{PAPER_CPU.get(m, float('nan')):.0f}" for m in self.modes)
        near = all(
            abs(self.relative_cpu(m) - PAPER_CPU[m]) <= 10.0 for m in self.modes if m in PAPER_CPU
        )
        five = [m for m in self.modes if m >= 5 and m != self.full]
        worst_five = max((float(self.errors[m].max()) for m in five), default=0.0)
        acc = self.accuracy
        k, t_eq, reached = self.newmark_equal
        out += [
            Claim(
                "relative CPU time 100/85/60/36/27 % for 20/15/10/5/3 modal coordinates",
                "Table 1",
                f"{ours} % (cost ~ modes^{self.cost_exponent():.2f})",
                near,
                "holds = every value within 10 percentage points; the loop time falls "
                + (
                    "monotonically"
                    if all(
                        self.seconds[a].min() > self.seconds[b].min()
                        for a, b in itertools.pairwise(self.modes)
                    )
                    else "but not monotonically"
                )
                + f" with fewer modes; paper {theirs} %",
            ),
            Claim(
                "modal reduction gives only small errors with at least five generalized "
                "coordinates",
                "section 4.4",
                "largest error with "
                + ", ".join(f"{m}: {100 * self.errors[m].max():.1f} %" for m in five)
                + " modes",
                worst_five <= SMALL,
                f"holds = <= {100 * SMALL:.0f} % of the orbit at every position; beta = "
                f"{self.beta:g}, xi = {self.xi:g}. Linear rotor: "
                + ", ".join(f"{m}: {100 * self.linear_errors[m].max():.1f} %" for m in five),
            ),
            Claim(
                "the higher errors occur at the bearings",
                "section 4.4",
                ", ".join(
                    f"{m}: {100 * self.errors[m][bearings].max():.1f} vs "
                    f"{100 * self.errors[m][disks].max():.1f} %"
                    for m in reduced
                ),
                all(self.errors[m][bearings].max() > self.errors[m][disks].max() for m in reduced),
                "bearings vs disks, largest error of each; holds = at every reduced model",
            ),
            *self._correction_claims(),
            Claim(
                "Newmark takes about two times the computation time of the present method "
                "without modal reduction",
                "section 4.4",
                f"Newmark / semi-analytic (full) = {self.newmark_ratio:.2f} "
                f"({1e6 * self.newmark_seconds.min() / self.steps:.1f} vs "
                f"{1e6 * self.seconds[self.full].min() / self.steps:.1f} us per step)",
                bool(1.5 <= self.newmark_ratio <= 2.5),
                f"same step dt = {fmt(self.dt)} s, {self.steps} steps, best of "
                f"{self.repeats} interleaved runs, time loop only, one Rust engine; holds = "
                "ratio in [1.5, 2.5]",
            ),
            Claim(
                "at the same time step the error against a converged solution is smaller "
                "than Newmark's",
                "section 5",
                f"semi-analytic {fmt(acc['semi-analytic'])} vs Newmark {fmt(acc['Newmark'])} "
                "of the orbit size",
                acc["semi-analytic"] < acc["Newmark"],
                f"converged: the full semi-analytic model at dt/{self.refine}",
            ),
            Claim(
                "(not in the paper) cost at equal accuracy",
                "-",
                ("Newmark needs" if reached else "Newmark, not yet as accurate, at")
                + f" dt/{k} ({fmt(acc[f'Newmark dt/{k}'])}) to match the "
                f"semi-analytic method at dt: loop time {1e3 * t_eq:.1f} ms vs "
                f"{1e3 * self.seconds[self.full].min():.1f} ms, ratio "
                f"{t_eq / self.seconds[self.full].min():.2f}",
                None,
                "Newmark at dt/k, k = 1, 2, 3, ... until its error is at most the "
                "semi-analytic one",
            ),
        ]
        return out

    def _correction_claims(self) -> list[Claim]:
        if not self.corrected:
            return []
        bearings, disks = slice(0, 2), slice(2, 4)
        rows = ", ".join(
            f"{m} modes ({n} coordinates): {100 * e[bearings].max():.1f} / "
            f"{100 * e[disks].max():.1f} %"
            for m, (n, e) in self.corrected.items()
        )
        five = [e for m, (_, e) in self.corrected.items() if m >= 5]
        return [
            Claim(
                "(not in the paper) modal reduction with static correction",
                "-",
                f"largest error at bearings / disks: {rows}",
                bool(five) and max(float(e.max()) for e in five) <= SMALL,
                "Semianalytic(modes=m, static_correction=True): the modes plus the static "
                "responses to the bearing forces and the load patterns (docs/nonlinear.md); "
                f"holds = <= {100 * SMALL:.0f} % of the orbit from 5 modes on",
            )
        ]


def table1(
    modes: Sequence[int] = (20, 15, 10, 5, 3),
    *,
    beta: float = 0.1,
    xi: float = 0.1,
    t_end: float = T_END,
    dt: float = DT,
    repeats: int = 7,
    refine: int = 16,
    max_newmark_refine: int = 8,
) -> Table1Data:
    """Data of Table 1: modal reduction and Newmark on the paper's case.

    The runs of the mode counts and of Newmark are interleaved (one of each, `repeats`
    times) so that they see the same machine load; the time is the Rust loop's own clock
    (:attr:`duhamel.SolveStats.wall_time`, every step saved). Errors are against the full
    model at the same step (reduction) or against it at ``dt / refine`` (accuracy).

    Parameters
    ----------
    modes : sequence of int
        Retained modes; the first is the full model (20).
    beta, xi : float
        The case (the paper's: cubic bearings and variable mass).
    t_end, dt : float
        Run length and step (s).
    repeats : int
        Timed runs per method.
    refine : int
        The converged reference uses ``dt / refine``.
    max_newmark_refine : int
        Largest ``k`` tried for Newmark at ``dt / k`` (equal accuracy).

    Returns
    -------
    Table1Data

    Examples
    --------
    >>> from duhamel.paper.rotor import table1
    >>> data = table1(modes=(20, 10), t_end=0.02, repeats=1, refine=2)
    >>> data.errors[20].tolist()
    [0.0, 0.0, 0.0, 0.0]
    """
    modes = tuple(int(m) for m in modes)
    nodes = [n for _, n in POSITIONS]
    scale = static_scale()[nodes][None, :, None]
    system = paper_system(beta, xi)
    linear = paper_system(0.0, 0.0)
    kw = {"t_end": t_end, "dt": dt}
    seconds: dict[int, list[float]] = {m: [] for m in modes}
    newmark: list[float] = []
    runs: dict[int, Array] = {}
    steps = 0
    for _ in range(int(repeats)):
        for m in modes:
            # The paper's modal truncation (no static correction, our default when reduced).
            plain = duhamel.Semianalytic(modes=m, coupling=COUPLING, static_correction=False)
            sol = duhamel.solve(system, plain, **kw)
            seconds[m].append(sol.stats.wall_time)
            runs[m] = _planar(sol.x, nodes) / scale
            steps = sol.stats.steps
        sol = duhamel.solve(system, duhamel.Newmark(), **kw)
        newmark.append(sol.stats.wall_time)
        newmark_run = _planar(sol.x, nodes) / scale
    full = runs[modes[0]]
    errors = {m: _relative_error(runs[m], full) for m in modes}
    corrected = {}
    for m in modes[1:]:
        enriched = duhamel.Semianalytic(modes=m, coupling=COUPLING, static_correction=True)
        sol = duhamel.solve(system, enriched, **kw)
        corrected[m] = (sol.stats.modes, _relative_error(_planar(sol.x, nodes) / scale, full))
    truncated = {
        m: duhamel.Semianalytic(modes=m, coupling=COUPLING, static_correction=False) for m in modes
    }
    linear_runs = {
        m: _planar(duhamel.solve(linear, truncated[m], **kw).x, nodes) / scale for m in modes
    }
    linear_errors = {m: _relative_error(linear_runs[m], linear_runs[modes[0]]) for m in modes}
    fine = duhamel.solve(
        system, duhamel.Semianalytic(coupling=COUPLING), t_end=t_end, dt=dt / refine
    )
    ref = _planar(fine.x[::refine], nodes) / scale
    accuracy = {
        "semi-analytic": float(_relative_error(full, ref).max()),
        "Newmark": float(_relative_error(newmark_run, ref).max()),
    }
    accuracy["Newmark dt/1"] = accuracy["Newmark"]
    equal = (1, float(min(newmark)), accuracy["Newmark"] <= accuracy["semi-analytic"])
    k = 1
    while not equal[2] and k < int(max_newmark_refine):
        k += 1
        sol = duhamel.solve(system, duhamel.Newmark(), t_end=t_end, dt=dt / k)
        err = float(_relative_error(_planar(sol.x[::k], nodes) / scale, ref).max())
        accuracy[f"Newmark dt/{k}"] = err
        equal = (k, sol.stats.wall_time, err <= accuracy["semi-analytic"])
    return Table1Data(
        modes=modes,
        seconds={m: np.array(v) for m, v in seconds.items()},
        newmark_seconds=np.array(newmark),
        errors=errors,
        linear_errors=linear_errors,
        accuracy=accuracy,
        newmark_equal=equal,
        beta=float(beta),
        xi=float(xi),
        dt=float(dt),
        t_end=float(t_end),
        steps=int(steps),
        repeats=int(repeats),
        refine=int(refine),
        corrected=corrected,
    )

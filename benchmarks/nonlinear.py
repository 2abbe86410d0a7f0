"""Nonlinear duhamel benchmarks: wall time and nanoseconds per step (imported by ``run.py``).

Two models, each timed in one run on one machine (best of `repeats` cold calls):

* **Duffing oscillator** ``x'' + x + 4 x^3 = 0``, ``x(0) = 1``, ``x'(0) = 0`` (the paper's case
  ``b x0^2 = 4 omega^2``), ``omega dt = 2 pi / 100``, 1e6 steps. duhamel's default
  ``Semianalytic()`` solves every step of this single-mode polynomial problem in closed form
  (the root of the step's cubic); it is timed saving every step, every 100th step and only
  the final state, and with ``solver="newton"`` for comparison. Accuracy is the largest
  displacement error against the exact ``cn`` solution (:func:`duhamel.exact.duffing`) over
  the first 1000 steps (10 periods of the linear background, about 20 of the nonlinear
  oscillation) and over the whole run. ``scipy.integrate.solve_ivp`` (DOP853) on the same
  ODE is the outside reference: its ``rtol`` is the loosest of a grid that is at least as
  accurate as duhamel over the first 1000 steps, and it is timed over the same time span
  with output at the same instants (on a shorter span, scaled, if that would be too slow).
* **20-dof chain** (fixed-free, unit masses, springs 1e4 N/m, zeta = 0.02) with four cubic
  springs to ground ``Cubic(dof, k3)`` at dofs 4, 9, 14, 19, under ``50 N sin(12 t)`` at the
  tip, 1e5 steps of 1 ms, tip displacement saved every step: 5 retained modes against the
  full 20-mode model (Newton steps, the general path), with the 5-vs-20 tip difference.
  ``k3 = 1e6 N/m^3`` stiffens the chain enough to move its first resonance (7.66 rad/s)
  past the forcing frequency, so the steady response is in phase with the load instead of
  opposite to it; with a stiffer ``k3 = 5e6`` the 5-mode model settles on a different
  periodic response than the 20-mode one (tip difference about 100 % of the amplitude),
  which would make the truncation comparison meaningless.

Times are ``Solution.stats.wall_time`` (the time loop, with the allocation and filling of
the modal history) divided by the steps; ``total_time`` adds modal analysis and recovery.
"""

from __future__ import annotations

import gc
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace

import numpy as np
import scipy.integrate
from numpy.typing import NDArray

import duhamel
from duhamel.exact import duffing, duffing_period

TARGET_NS = 100.0  # ns per step, single-dof Duffing (issue acceptance)


# ------------------------------------------------------------------------------- the models
@dataclass(frozen=True)
class NonlinearSetup:
    """Sizes and parameters of the nonlinear benchmark problems."""

    # Duffing x'' + omega^2 x + b x^3 = 0
    omega: float = 1.0
    b: float = 4.0
    x0: float = 1.0
    duffing_steps: int = 1_000_000
    steps_per_period: int = 100  # of the linear background: omega dt = 2 pi / 100
    accuracy_steps: int = 1000  # the "short" accuracy window
    sparse_every: int = 100
    rtol_per_decade: int = 8  # grid of the DOP853 rtol search
    rtol_range: tuple[float, float] = (1e-8, 1e-2)
    # 20-dof chain
    n_dof: int = 20
    k: float = 1e4  # N/m
    zeta: float = 0.02
    k3: float = 1e6  # N/m^3
    cubic_dofs: tuple[int, ...] = (4, 9, 14, 19)
    tip_amplitude: float = 50.0  # N
    tip_omega: float = 12.0  # rad/s
    modes: int = 5
    chain_dt: float = 1e-3
    chain_steps: int = 100_000
    steady_fraction: float = 0.1  # last 10 % of the run: the steady state
    repeats: int = 3

    @property
    def dt(self) -> float:
        return 2.0 * math.pi / (self.steps_per_period * self.omega)

    @property
    def tip(self) -> int:
        return self.n_dof - 1


QUICK = NonlinearSetup(duffing_steps=20_000, chain_steps=2000, repeats=1)


def duffing_system(s: NonlinearSetup) -> duhamel.System:
    system = duhamel.System(np.eye(1), np.array([[s.omega**2]]))
    system.add(duhamel.elements.Cubic(0, k3=s.b))
    return system


def chain_system(s: NonlinearSetup, *, cubic: bool = True) -> duhamel.System:
    """The fixed-free chain (dof 0 tied to the ground) with its springs and tip load."""
    n = s.n_dof
    K = np.zeros((n, n))
    for i in range(n):  # spring i joins node i - 1 (the ground for i = 0) to node i
        K[i, i] += s.k
        if i > 0:
            K[i - 1, i - 1] += s.k
            K[i - 1, i] -= s.k
            K[i, i - 1] -= s.k
    system = duhamel.System(np.eye(n), K, zeta=s.zeta)
    if cubic:
        for dof in s.cubic_dofs:
            system.add(duhamel.elements.Cubic(dof, k3=s.k3))
    system.add_load(duhamel.loads.Harmonic(s.tip, amplitude=s.tip_amplitude, omega=s.tip_omega))
    return system


# ------------------------------------------------------------------------------- results
@dataclass
class NRow:
    """One timed nonlinear case."""

    name: str
    steps: int
    loop_time: float  # seconds in the time loop (scaled to `steps` when timed on fewer)
    total_time: float
    newton_per_step: float = float("nan")
    note: str = ""
    err_short: float = float("nan")  # Duffing: max |x - exact| / x0, first accuracy_steps
    err_all: float = float("nan")  # Duffing: over the whole run
    period_err: float = float("nan")  # Duffing: mean period / exact period - 1
    energy_err: float = float("nan")  # Duffing: energy at the end / initial energy - 1

    @property
    def ns_per_step(self) -> float:
        return 1e9 * self.loop_time / self.steps

    @property
    def total_ns_per_step(self) -> float:
        return 1e9 * self.total_time / self.steps


@dataclass
class NonlinearResults:
    setup: NonlinearSetup
    duffing_rows: list[NRow] = field(default_factory=list)
    chain_rows: list[NRow] = field(default_factory=list)
    primary: NRow | None = None  # Duffing, closed form, every step
    kernel: NRow | None = None  # Duffing, closed form, final state only
    ivp: NRow | None = None
    ivp_rtol: float = float("nan")
    ivp_atol: float = float("nan")
    ivp_steps: int = 0  # duhamel-step equivalents actually timed
    period_exact: float = float("nan")
    chain_amplitude: float = float("nan")  # 20-mode tip amplitude (max |x|)
    chain_steady_amplitude: float = float("nan")
    linear_steady_amplitude: float = float("nan")  # same chain without the cubic springs
    diff_all: float = float("nan")  # 5 vs 20 modes, max |dx| / max |x_20|
    diff_steady: float = float("nan")  # the same over the steady part
    diff_dt: float = float("nan")  # 20 modes, dt vs dt/4, max |dx| / max |x_20|
    phase_lag: float = float("nan")  # steady tip response behind the load, degrees
    linear_phase_lag: float = float("nan")  # the same without the cubic springs
    newton_diff: float = float("nan")  # Duffing, max |x_newton - x_closed| / x0
    omega_chain: tuple[float, float] = (float("nan"), float("nan"))


# ------------------------------------------------------------------------------- helpers
def mean_period(t: NDArray[np.float64], x: NDArray[np.float64]) -> float:
    """Mean period from the upward zero crossings (linear interpolation between samples)."""
    i = np.nonzero((x[:-1] < 0.0) & (x[1:] >= 0.0))[0]
    if i.size < 2:
        return float("nan")
    tc = t[i] - x[i] * (t[i + 1] - t[i]) / (x[i + 1] - x[i])
    return float((tc[-1] - tc[0]) / (i.size - 1))


def energy(s: NonlinearSetup, x: float, v: float) -> float:
    """Energy per unit mass of the Duffing oscillator (a constant of its exact motion)."""
    return 0.5 * v * v + 0.5 * s.omega**2 * x * x + 0.25 * s.b * x**4


def phase_lag(t: NDArray[np.float64], x: NDArray[np.float64], omega: float) -> float:
    """Lag (degrees, in (-180, 180]) of the fundamental of `x` behind ``sin(omega t)``.

    Least-squares fit ``x = a sin(omega t) + b cos(omega t) + c = A sin(omega t - lag) + c``.
    """
    basis = np.stack([np.sin(omega * t), np.cos(omega * t), np.ones_like(t)], axis=1)
    (a, b, _), *_ = np.linalg.lstsq(basis, x, rcond=None)
    lag = -math.degrees(math.atan2(b, a))
    return lag + 360.0 if lag <= -180.0 else lag


def duffing_errors(
    s: NonlinearSetup,
    t: NDArray[np.float64],
    x: NDArray[np.float64],
    v: NDArray[np.float64],
    every_step: bool,
) -> tuple[float, float, float, float]:
    """(short-window error, whole-run error, mean period error, end energy error).

    The displacement errors are relative to ``|x0|``; period and energy errors are
    relative to the exact values; the period needs every step saved (else NaN).
    """
    exact, _ = duffing(t, s.omega, s.b, s.x0)
    err = np.abs(x - exact) / abs(s.x0)
    short = t <= s.accuracy_steps * s.dt * (1.0 + 1e-12)
    period = duffing_period(s.omega, s.b, s.x0)
    energy_err = energy(s, float(x[-1]), float(v[-1])) / energy(s, s.x0, 0.0) - 1.0
    return (
        float(err[short].max()),
        float(err.max()),
        mean_period(t, x) / period - 1.0 if every_step else float("nan"),
        energy_err,
    )


def best_of(
    repeats: int, make: Callable[[], duhamel.System], **kwargs: object
) -> tuple[duhamel.Solution, float]:
    """Best of `repeats` cold `duhamel.solve` calls: (fastest loop's solution, best total)."""
    best: duhamel.Solution | None = None
    best_total = float("inf")
    for _ in range(repeats):
        system = make()
        gc.collect()
        sol = duhamel.solve(system, **kwargs)  # type: ignore[arg-type]
        if best is None or sol.stats.wall_time < best.stats.wall_time:
            best = sol
        best_total = min(best_total, sol.stats.total_time)
        del sol
    assert best is not None
    return best, best_total


# ------------------------------------------------------------------------------- Duffing
def duffing_solve(s: NonlinearSetup, solver: str, save_every: int) -> duhamel.Solution:
    """One cold call on a fresh Duffing system, checked for its step count and path."""
    n = s.duffing_steps
    gc.collect()
    sol = duhamel.solve(
        duffing_system(s),
        duhamel.Semianalytic(solver=solver),
        t_end=n * s.dt,
        dt=s.dt,
        x0=[s.x0],
        save_every=save_every,
    )
    st = sol.stats
    if st.steps != n:
        raise RuntimeError(f"duhamel took {st.steps} steps, not {n}")
    if solver == "auto" and st.closed_form_steps != n:
        raise RuntimeError(f"only {st.closed_form_steps} of {n} steps took the closed form")
    return sol


def duffing_cases(
    s: NonlinearSetup, cases: list[tuple[str, str, int, str]], log: Callable[[str], None]
) -> tuple[list[NRow], NDArray[np.float64]]:
    """Times the duhamel Duffing cases ``(name, solver, save_every, note)``, round-robin.

    Each repeat runs every case once, so that a change in the machine's load affects all
    cases alike; loop and total times are minimised separately over the repeats. The
    results are deterministic: errors come from the first repeat. Also returns the
    displacement history of the first case saved at every step (for cross-checks).
    """
    n = s.duffing_steps
    rows: list[NRow] = []
    x_ref = np.empty(0)
    for rep in range(s.repeats):
        log(f"nonlinear: Duffing, duhamel cases, repeat {rep + 1} of {s.repeats} ...")
        for k, (name, solver, every, note) in enumerate(cases):
            sol = duffing_solve(s, solver, every)
            st = sol.stats
            if rep == 0:
                row = NRow(name, n, st.wall_time, st.total_time, st.newton_iterations / n, note)
                if every < n:
                    x, v = sol.x[:, 0], sol.v[:, 0]
                    errs = duffing_errors(s, sol.t, x, v, every_step=every == 1)
                    row.err_short, row.err_all, row.period_err, row.energy_err = errs
                if every == 1 and x_ref.size == 0:
                    x_ref = np.array(sol.x[:, 0])
                rows.append(row)
            else:
                row = rows[k]
                row.loop_time = min(row.loop_time, st.wall_time)
                row.total_time = min(row.total_time, st.total_time)
            del sol
    return rows, x_ref


def _rhs(omega2: float, b: float) -> Callable[[float, NDArray[np.float64]], tuple[float, float]]:
    def rhs(_t: float, y: NDArray[np.float64]) -> tuple[float, float]:
        x = y[0]
        return (y[1], -omega2 * x - b * x * x * x)

    return rhs


def run_ivp(
    s: NonlinearSetup, n_steps: int, rtol: float, atol: float
) -> tuple[float, NDArray[np.float64], NDArray[np.float64], int]:
    """DOP853 over `n_steps` duhamel steps, output at the step instants.

    Returns (seconds in ``solve_ivp``, t, y = (x, v) history, right-hand side calls).
    """
    t = np.arange(n_steps + 1) * s.dt
    rhs = _rhs(s.omega**2, s.b)
    gc.collect()
    start = time.perf_counter()
    res = scipy.integrate.solve_ivp(
        rhs, (0.0, float(t[-1])), [s.x0, 0.0], method="DOP853", rtol=rtol, atol=atol, t_eval=t
    )
    elapsed = time.perf_counter() - start
    if not res.success:
        raise RuntimeError(f"solve_ivp failed: {res.message}")
    return elapsed, res.t, res.y, int(res.nfev)


def ivp_tolerance(s: NonlinearSetup, target: float) -> tuple[float, float, float]:
    """The loosest rtol of the grid whose short-window error is <= `target`.

    Returns (rtol, atol, its short-window error); ``atol = 1e-3 rtol |x0|`` so that the
    relative tolerance governs. DOP853's error is not monotone in rtol at loose tolerances,
    hence a grid scan from loose to tight rather than a bisection.
    """
    lo, hi = s.rtol_range
    k_max = round(s.rtol_per_decade * math.log10(hi / lo))
    for k in range(k_max + 1):
        rtol = hi * 10.0 ** (-k / s.rtol_per_decade)
        atol = 1e-3 * rtol * abs(s.x0)
        _, t, y, _ = run_ivp(s, s.accuracy_steps, rtol, atol)
        err = duffing_errors(s, t, y[0], y[1], every_step=False)[0]
        if err <= target:
            return rtol, atol, err
    raise RuntimeError(f"no rtol >= {lo:g} reaches the error {target:.3g}")


def ivp_case(
    s: NonlinearSetup, target: float, max_seconds: float, log: Callable[[str], None]
) -> tuple[NRow, float, float, int]:
    """Times DOP853 at the matched tolerance; (row, rtol, atol, duhamel-steps timed)."""
    rtol, atol, _ = ivp_tolerance(s, target)
    log(f"  DOP853 rtol = {rtol:.3g} (atol {atol:.3g})")
    n = s.duffing_steps
    probe = min(n, 20_000)
    probe_time, *_ = run_ivp(s, probe, rtol, atol)
    projected = probe_time * n / probe
    n_run = n
    if projected > max_seconds:
        n_run = max(probe, int(n * 0.5 * max_seconds / projected))
    one_run = projected * n_run / n
    repeats = s.repeats if one_run * s.repeats <= max_seconds else 1
    best = float("inf")
    nfev = 0
    for _ in range(repeats):
        elapsed, t, y, nfev = run_ivp(s, n_run, rtol, atol)
        best = min(best, elapsed)
    scale = n / n_run
    note = (
        f"rtol={rtol:.3g}, atol={atol:.3g}; output at every duhamel step (t_eval); "
        f"{nfev} RHS calls; best of {repeats}"
    )
    if n_run < n:
        note += f"; timed on {n_run} steps' span and scaled x{scale:.3g}"
    row = NRow("scipy solve_ivp DOP853 (matched error)", n, best * scale, best * scale, note=note)
    errs = duffing_errors(s, t, y[0], y[1], every_step=True)
    row.err_short, row.err_all, row.period_err, row.energy_err = errs
    return row, rtol, atol, n_run


# ------------------------------------------------------------------------------- chain
def chain_case(s: NonlinearSetup, name: str, modes: int | None) -> tuple[NRow, NDArray[np.float64]]:
    n = s.chain_steps
    sol, total = best_of(
        s.repeats,
        lambda: chain_system(s),
        integrator=duhamel.Semianalytic(modes=modes),
        t_end=n * s.chain_dt,
        dt=s.chain_dt,
        dofs=[s.tip],
    )
    st = sol.stats
    if st.steps != n:
        raise RuntimeError(f"duhamel took {st.steps} steps, not {n}")
    row = NRow(
        name,
        n,
        st.wall_time,
        total,
        st.newton_iterations / n,
        note=f"{st.modes} modes",
    )
    return row, np.array(sol.x[:, 0])


def run_nonlinear(
    s: NonlinearSetup, ivp_max_seconds: float, log: Callable[[str], None]
) -> NonlinearResults:
    res = NonlinearResults(setup=s, period_exact=duffing_period(s.omega, s.b, s.x0))
    n = s.duffing_steps

    names = {
        "primary": "duhamel, closed form (default), every step",
        "kernel": "duhamel, closed form, final state only",
        "newton": 'duhamel, solver="newton", every step',
    }
    cases = [
        (names["primary"], "auto", 1, ""),
        (f"duhamel, closed form, every {s.sparse_every}th step", "auto", s.sparse_every, ""),
        (names["kernel"], "auto", n, "save_every=n_steps: the stepping kernel alone"),
        (names["newton"], "newton", 1, ""),
    ]
    rows, x_closed = duffing_cases(s, cases, log)
    res.duffing_rows += rows
    by_name = {r.name: r for r in rows}
    primary = res.primary = by_name[names["primary"]]
    res.kernel = by_name[names["kernel"]]
    sol = duffing_solve(s, "newton", 1)
    res.newton_diff = float(np.abs(sol.x[:, 0] - x_closed).max()) / abs(s.x0)
    del sol

    log("nonlinear: Duffing, scipy solve_ivp DOP853 ...")
    row, res.ivp_rtol, res.ivp_atol, res.ivp_steps = ivp_case(
        s, primary.err_short, ivp_max_seconds, log
    )
    res.ivp = row
    res.duffing_rows.append(row)

    log(f"nonlinear: chain, {s.modes} modes ...")
    basis = chain_system(s).modal(None)
    res.omega_chain = (float(basis.omega[0]), float(basis.omega[-1]))
    row5, x5 = chain_case(s, f"duhamel, {s.modes} modes, tip saved every step", s.modes)
    res.chain_rows.append(row5)
    log(f"nonlinear: chain, all {s.n_dof} modes ...")
    row20, x20 = chain_case(s, f"duhamel, all {s.n_dof} modes, tip saved every step", None)
    res.chain_rows.append(row20)

    steady = slice(round((1.0 - s.steady_fraction) * x20.size), None)
    amp = float(np.abs(x20).max())
    res.chain_amplitude = amp
    res.chain_steady_amplitude = float(np.abs(x20[steady]).max())
    res.diff_all = float(np.abs(x5 - x20).max()) / amp
    res.diff_steady = float(np.abs(x5 - x20)[steady].max()) / amp

    log("nonlinear: chain reference runs (dt/4; no cubic springs) ...")
    fine = replace(s, chain_dt=s.chain_dt / 4, chain_steps=4 * s.chain_steps)
    sol = duhamel.solve(
        chain_system(fine),
        duhamel.Semianalytic(),
        t_end=fine.chain_steps * fine.chain_dt,
        dt=fine.chain_dt,
        dofs=[s.tip],
        save_every=4,
    )
    x_fine = np.array(sol.x[:, 0])
    if x_fine.size != x20.size:
        raise RuntimeError("the dt/4 reference run is not on the benchmark's time grid")
    res.diff_dt = float(np.abs(x20 - x_fine).max()) / amp
    lin = duhamel.solve(
        chain_system(s, cubic=False),
        duhamel.Semianalytic(),
        t_end=s.chain_steps * s.chain_dt,
        dt=s.chain_dt,
        dofs=[s.tip],
    )
    res.linear_steady_amplitude = float(np.abs(lin.x[steady, 0]).max())
    t = np.arange(x20.size) * s.chain_dt
    res.phase_lag = phase_lag(t[steady], x20[steady], s.tip_omega)
    res.linear_phase_lag = phase_lag(t[steady], np.asarray(lin.x[steady, 0]), s.tip_omega)
    return res


# ------------------------------------------------------------------------------- reporting
def _g(x: float, digits: int = 3) -> str:
    return "n/a" if math.isnan(x) else f"{x:.{digits}g}"


def _coef(c: float) -> str:
    """A coefficient in front of a term: empty for 1."""
    return "" if c == 1.0 else f"{c:g} "


def duffing_table(res: NonlinearResults) -> list[str]:
    assert res.primary is not None
    ref = res.primary.loop_time
    lines = [
        "| case | ns/step (loop) | loop time [s] | total time [s] | loop time / closed form "
        "| Newton iterations/step | notes |",
        "|---|---:|---:|---:|---:|---:|---|",
    ]
    for r in res.duffing_rows:
        lines.append(
            f"| {r.name} | {r.ns_per_step:.4g} | {r.loop_time:.4g} | {r.total_time:.4g} | "
            f"{r.loop_time / ref:.3g} | {_g(r.newton_per_step)} | {r.note} |"
        )
    return lines


def duffing_accuracy_table(res: NonlinearResults) -> list[str]:
    s = res.setup
    lines = [
        f"| case | max error, first {s.accuracy_steps} steps | max error, whole run "
        "| mean period error | energy error at the end |",
        "|---|---:|---:|---:|---:|",
    ]
    for r in res.duffing_rows:
        if math.isnan(r.err_short):
            continue
        lines.append(
            f"| {r.name} | {_g(r.err_short)} | {_g(r.err_all)} | {_g(r.period_err)} | "
            f"{_g(r.energy_err)} |"
        )
    return lines


def chain_table(res: NonlinearResults) -> list[str]:
    lines = [
        "| case | ns/step (loop) | loop time [s] | total time [s] | Newton iterations/step "
        "| notes |",
        "|---|---:|---:|---:|---:|---|",
    ]
    for r in res.chain_rows:
        lines.append(
            f"| {r.name} | {r.ns_per_step:.4g} | {r.loop_time:.4g} | {r.total_time:.4g} | "
            f"{_g(r.newton_per_step)} | {r.note} |"
        )
    return lines


def nonlinear_verdict(res: NonlinearResults) -> str:
    p, k = res.primary, res.kernel
    assert p is not None
    met = "MET" if p.ns_per_step < TARGET_NS else "NOT MET"
    text = (
        f"**Target (< {TARGET_NS:g} ns per step, single-dof Duffing): {met}** - "
        f"{p.ns_per_step:.0f} ns/step (default closed-form solver, every step saved, loop "
        f"time, best of {res.setup.repeats})."
    )
    if k is not None:
        text += (
            f" The stepping kernel alone (final state only) takes {k.ns_per_step:.0f} ns/step "
            f"({'under' if k.ns_per_step < TARGET_NS else 'over'} the target)."
        )
    return text


def nonlinear_findings(res: NonlinearResults) -> list[str]:
    by_name = {r.name: r for r in res.duffing_rows}
    p, k = res.primary, res.kernel
    assert p is not None
    lines: list[str] = []
    if k is not None:
        extra = p.ns_per_step - k.ns_per_step
        if extra > 0:
            lines.append(
                f"* Output cost: saving every step adds {extra:.0f} ns/step to the loop "
                f"({100 * extra / p.ns_per_step:.0f} % of it) compared with the final state "
                "only."
            )
        else:
            lines.append(
                "* Output cost: not measurable in this run (saving every step was "
                f"{-extra:.0f} ns/step faster than the final state only: timing noise)."
            )
    newton = by_name.get('duhamel, solver="newton", every step')
    if newton is not None:
        lines.append(
            f'* `solver="newton"` takes {newton.ns_per_step:.0f} ns/step '
            f"({newton.newton_per_step:.2g} iterations/step), "
            f"{newton.loop_time / p.loop_time:.2g}x the closed form; the two histories differ "
            f"by at most {res.newton_diff:.2g} x0 (Newton tolerance 1e-10)."
        )
    if res.ivp is not None:
        r = res.ivp
        lines.append(
            f"* DOP853 at the matched error needs {r.ns_per_step:.0f} ns per duhamel step "
            f"(loop time {r.loop_time:.3g} s vs {p.loop_time:.3g} s): duhamel is "
            f"{r.loop_time / p.loop_time:.3g}x faster in loop time and "
            f"{r.total_time / p.total_time:.3g}x in total time."
        )
    if res.ivp is not None and not math.isnan(p.period_err):
        r = res.ivp
        lines.append(
            f"* Over the whole run ({res.setup.duffing_steps} steps, "
            f"{res.setup.duffing_steps * res.setup.dt / res.period_exact:.3g} periods) the max "
            f"error is {p.err_all:.3g} x0 for duhamel and {r.err_all:.3g} x0 for DOP853 (2 x0 "
            "means the phase is lost entirely); the drifts behind it: duhamel's mean period "
            f"is off by {p.period_err:.2g} (relative) and its energy by {p.energy_err:.2g} at "
            f"the end, DOP853's by {r.period_err:.2g} and {r.energy_err:.2g}."
        )
    rows = res.chain_rows
    if len(rows) == 2:
        r5, r20 = rows
        lines.append(
            f"* Chain: {res.setup.modes} modes take {r5.ns_per_step:.0f} ns/step, the full "
            f"model {r20.ns_per_step:.0f} ns/step ({r20.loop_time / r5.loop_time:.3g}x); the "
            f"{res.setup.modes}-mode tip response differs from the 20-mode one by "
            f"{100 * res.diff_all:.3g} % of the tip amplitude over the whole run "
            f"({100 * res.diff_steady:.3g} % in the steady state)."
        )
    return lines


def nonlinear_markdown(res: NonlinearResults) -> list[str]:
    s = res.setup
    assert res.primary is not None
    lines = [
        "## Nonlinear benchmarks",
        "",
        "### What this measures",
        "",
        f"* **Duffing oscillator** `x'' + {_coef(s.omega**2)}x + {_coef(s.b)}x^3 = 0`, "
        f"`x(0) = {s.x0:g}`, "
        f"`x'(0) = 0`, {s.duffing_steps} steps of dt = 2 pi / {s.steps_per_period} = "
        f"{s.dt:.6g} s (t_end = {s.duffing_steps * s.dt:.6g} s; the exact period is "
        f"{res.period_exact:.6g} s, {res.period_exact / s.dt:.4g} steps). duhamel's default "
        "`Semianalytic()` (scheme b, trapezoid) solves each step of this single-mode cubic "
        "problem in closed form; it is timed saving every step, every "
        f'{s.sparse_every}th step and only the final state, and with `solver="newton"`. '
        f"**ns/step** = loop time / steps; duhamel rows are the best of {s.repeats} cold "
        "call(s) (loop and total minimised separately), run round-robin (each repeat "
        "runs every case once) so that a change in the machine's load affects all alike.",
        "* **scipy.integrate.solve_ivp, DOP853**, on the same ODE (Python right-hand side, "
        "output at every duhamel step through `t_eval`): `rtol` is the loosest of "
        f"{s.rtol_per_decade} values per decade from {s.rtol_range[1]:g} down whose max error "
        f"over the first {s.accuracy_steps} steps is at most duhamel's "
        f"(`atol = 1e-3 rtol x0`); it is then timed over the same span "
        f"({res.ivp_steps} duhamel steps' worth), its ns/step is per duhamel step "
        "(its own steps are longer and fewer). Its loop and total time are the `solve_ivp` call.",
        f"* **20-dof chain**: fixed-free, unit masses, springs {s.k:g} N/m, zeta = {s.zeta:g} "
        f"(omega = {res.omega_chain[0]:.4g} ... {res.omega_chain[1]:.4g} rad/s), cubic springs "
        f"`Cubic(dof, {s.k3:g})` at dofs {', '.join(map(str, s.cubic_dofs))}, "
        f"{s.tip_amplitude:g} N * sin({s.tip_omega:g} t) at the tip (dof {s.tip}), "
        f"{s.chain_steps} steps of dt = {s.chain_dt:g} s, tip displacement saved every step; "
        f"`Semianalytic(modes={s.modes})` against all {s.n_dof} modes (Newton on every step). "
        "The cubic springs matter: the steady tip amplitude is "
        f"{100 * res.chain_steady_amplitude:.3g} cm against "
        f"{100 * res.linear_steady_amplitude:.3g} cm without them, and its fundamental lags "
        f"the load by {res.phase_lag:.0f} deg against {res.linear_phase_lag:.0f} deg without "
        "them (the linear chain is driven above its first resonance, the stiffened one "
        "below it). "
        "(With the stiffer k3 = 5e6 the 5-mode model settles on a different periodic "
        "response than the 20-mode one, so that truncation comparison would be meaningless.)",
        "",
        "### Duffing oscillator, 1 dof",
        "",
    ]
    lines += duffing_table(res)
    lines += ["", nonlinear_verdict(res), ""]
    lines += [
        "Accuracy against the exact `cn` solution (`duhamel.exact.duffing`), max |x - x_exact| "
        "/ x0 at the saved instants; the mean period from the upward zero crossings of the "
        "run relative to the exact period (every step saved), and the energy "
        "`v^2/2 + omega^2 x^2/2 + b x^4/4` at the last step relative to the initial one:",
        "",
    ]
    lines += duffing_accuracy_table(res)
    lines += [
        "",
        f"### 20-dof chain, 4 cubic springs, {s.modes} of {s.n_dof} modes",
        "",
    ]
    lines += chain_table(res)
    lines += [
        "",
        "| comparison | max abs difference / max abs 20-mode tip displacement |",
        "|---|---:|",
        f"| {s.modes} modes vs {s.n_dof} modes, tip, whole run | {res.diff_all:.3g} |",
        f"| {s.modes} modes vs {s.n_dof} modes, tip, last {100 * s.steady_fraction:g} % "
        f"(steady state) | {res.diff_steady:.3g} |",
        f"| {s.n_dof} modes, dt vs dt/4, tip, whole run | {res.diff_dt:.3g} |",
        "",
        f"20-mode tip amplitude: {100 * res.chain_amplitude:.3g} cm (whole run), "
        f"{100 * res.chain_steady_amplitude:.3g} cm (steady state).",
        "",
    ]
    lines += nonlinear_findings(res)
    return lines


def print_nonlinear(res: NonlinearResults) -> None:
    print()
    for line in duffing_table(res):
        print(line)
    print()
    print(nonlinear_verdict(res))
    print()
    for line in duffing_accuracy_table(res):
        print(line)
    print()
    for line in chain_table(res):
        print(line)
    print()
    print(f"chain tip, {res.setup.modes} vs 20 modes (whole run):  {res.diff_all:.3g}")
    print(f"chain tip, {res.setup.modes} vs 20 modes (steady):     {res.diff_steady:.3g}")
    print(f"chain tip, 20 modes, dt vs dt/4:        {res.diff_dt:.3g}")
    print(
        f"chain tip phase lag (steady): {res.phase_lag:.0f} deg, "
        f"without cubic springs {res.linear_phase_lag:.0f} deg"
    )
    print(f"Duffing, Newton vs closed form: max |dx| / x0 = {res.newton_diff:.2g}")
    print(
        f"chain tip amplitude (steady): {res.chain_steady_amplitude:.4g} m, "
        f"without cubic springs {res.linear_steady_amplitude:.4g} m"
    )

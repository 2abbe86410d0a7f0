"""Work-precision benchmark: maximum error against CPU time (imported by ``run.py``).

Two nonlinear problems, every method run in one process on one machine, so that the time
ratios are measured in one run:

* **Duffing oscillator** ``x'' + x + 4 x^3 = 0``, ``x(0) = 1``, ``x'(0) = 0``, over ten periods
  of the linear background (``t_end = 20 pi``); error = ``max |x - x_exact| / x0`` at every
  saved instant against the exact ``cn`` solution (:func:`duhamel.exact.duffing`).
* **20-dof chain** of ``nonlinear.py`` (fixed-free, unit masses, springs 1e4 N/m, zeta = 0.02,
  ``Cubic(dof, 1e6)`` at dofs 4, 9, 14, 19, ``50 N sin(12 t)`` at the tip), ``t_end = 10 s``
  from rest; error = ``max |x_tip - x_ref|`` over the instants ``k * 0.02 s`` (common to every
  step size), divided by ``max |x_ref|``. The reference is ``CubicHermite`` at a very small
  step, cross-checked by the next larger step and by DOP853 at ``rtol = 1e-12``.

Methods: ``Semianalytic`` (scheme b) with each quadrature (trapezoid, parabolic, exact; on
the chain also with 5 of the 20 modes), ``Newmark()``, ``HHT(-0.1)``,
``GeneralizedAlpha(0.8)``, ``CubicHermite()``, all through ``duhamel.solve`` on the same
``System``, and ``scipy.integrate.solve_ivp`` (DOP853; Radau with the analytic Jacobian) on
the first-order form of the same equations, with a numpy right-hand side.

Every duhamel method runs at a base list of steps; a method whose error is still above
``extend_to`` (1e-6) at the smallest base step is run at halved steps until it gets there,
its error stops falling (modal truncation, round-off), or a smallest step is reached — so
that the time to reach 1e-6 is interpolated rather than extrapolated. solve_ivp runs a
fixed list of ``rtol``.

Times: duhamel's *loop time* is ``stats.wall_time`` (the Rust time loop on one thread, every
step saved), its *total time* ``stats.total_time`` (the whole ``solve`` call on a fresh
``System``); solve_ivp's loop and total time are both the ``solve_ivp`` call. Each case is
timed as the minimum over runs: a first pass runs every case once (and measures the
errors, which are deterministic); ``repeats - 1`` further round-robin passes run every
case again, short cases several times in a row (so that each batch lasts about
``batch_seconds``), cases longer than ``single_seconds`` not at all.
"""

from __future__ import annotations

import gc
import math
import os
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import nonlinear  # benchmarks/nonlinear.py: the chain model
import numpy as np
import scipy.integrate
from numpy.typing import NDArray

import duhamel
from duhamel.exact import duffing

THRESHOLDS = (1e-3, 1e-6)  # the summary's error levels
REFERENCE_METHOD = "Semianalytic (trapezoid)"  # ratios are relative to this method
CHAIN = nonlinear.NonlinearSetup()  # the 20-dof chain of the nonlinear section


# ------------------------------------------------------------------------------- set-up
@dataclass(frozen=True)
class PrecisionSetup:
    """Sizes of the work-precision runs."""

    # Duffing x'' + omega^2 x + b x^3 = 0
    omega: float = 1.0
    b: float = 4.0
    x0: float = 1.0
    periods: int = 10  # of the linear background: t_end = periods * 2 pi / omega
    duffing_n: tuple[int, ...] = (25, 50, 100, 200, 400, 800)  # dt = 2 pi / (n omega)
    duffing_max_n: int = 51_200  # smallest step of the extension
    duffing_eval_n: int = 100  # solve_ivp output instants per background period
    duffing_rtols: tuple[float, ...] = tuple(10.0**-k for k in range(3, 13))
    # 20-dof chain (the model of nonlinear.py)
    chain: nonlinear.NonlinearSetup = CHAIN
    chain_t_end: float = 10.0
    chain_dt0: float = 0.02  # dt = chain_dt0 / 2^j; errors compared at multiples of dt0
    chain_levels: int = 7  # base list: j = 0 ... chain_levels - 1
    chain_max_level: int = 10  # smallest step of the extension
    chain_ref_level: int = 9  # the CubicHermite reference run
    chain_dop_rtols: tuple[float, ...] = tuple(10.0**-k for k in range(3, 13))
    chain_radau_rtols: tuple[float, ...] = tuple(10.0**-k for k in range(3, 10))
    modes: int = 5  # the truncated Semianalytic variant on the chain
    # step extension and timing
    extend_to: float = 1e-6
    plateau: float = 0.9  # stop extending when a halving leaves > 90 % of the error
    repeats: int = 3
    batch_seconds: float = 0.02
    single_seconds: float = 2.0

    @property
    def duffing_t_end(self) -> float:
        return self.periods * 2.0 * math.pi / self.omega


QUICK = PrecisionSetup(
    duffing_n=(25, 50, 100),
    duffing_max_n=400,
    duffing_rtols=(1e-3, 1e-6),
    chain_t_end=1.0,
    chain_levels=3,
    chain_max_level=4,
    chain_ref_level=6,
    chain_dop_rtols=(1e-3, 1e-6),
    chain_radau_rtols=(1e-3,),
    repeats=1,
)


# ------------------------------------------------------------------------------- results
@dataclass
class RunResult:
    """One call: times, the response at the instants where the error is measured, cost."""

    loop_time: float
    total_time: float
    t: NDArray[np.float64]
    x: NDArray[np.float64]
    steps: int  # duhamel steps, or solve_ivp right-hand side calls
    newton_per_step: float = float("nan")
    note: str = ""


@dataclass
class Point:
    """One (method, step or rtol) case of the work-precision table."""

    param: float  # dt [s] or rtol
    label: str  # how the table shows it
    error: float = float("nan")
    loop_time: float = float("nan")
    total_time: float = float("nan")
    steps: int = 0
    newton_per_step: float = float("nan")
    runs: int = 0
    note: str = ""
    failed: str = ""  # why the run stopped early (empty: it completed)
    extended: bool = False  # beyond the base list of steps


@dataclass
class Method:
    """A method and its runner ``run(param) -> RunResult``."""

    name: str
    kind: str  # "duhamel" or "ivp"
    params: list[float]
    labels: list[str]
    run: Callable[[float], RunResult]
    min_param: float = 0.0  # smallest step of the extension (duhamel)
    label_of: Callable[[float], str] = str
    points: list[Point] = field(default_factory=list)
    note: str = ""


@dataclass
class Problem:
    name: str
    methods: list[Method] = field(default_factory=list)
    ref_note: list[str] = field(default_factory=list)
    amplitude: float = float("nan")  # chain: max |x_ref|, the error's scale
    omega_max: float = float("nan")  # chain: highest natural frequency of the linear part


@dataclass
class PrecisionResults:
    setup: PrecisionSetup
    duffing: Problem
    chain: Problem
    figure: str = ""
    load_before: tuple[float, float, float] = (float("nan"),) * 3
    load_after: tuple[float, float, float] = (float("nan"),) * 3
    seconds: float = float("nan")


# ------------------------------------------------------------------------------- runners
def duhamel_run(
    make: Callable[[], duhamel.System],
    integrator: object,
    t_end: float,
    dt: float,
    x0: list[float] | None,
    dof: int,
    stride: int = 1,
) -> RunResult:
    """One cold ``duhamel.solve`` call (fresh System), every step saved, one dof recovered."""
    system = make()
    sol = duhamel.solve(
        system,
        integrator,  # type: ignore[arg-type]
        t_end=t_end,
        dt=dt,
        x0=x0,
        dofs=[dof],
        threads=1,
    )
    st = sol.stats
    expected = math.floor(t_end / dt * (1.0 + 1e-12) + 1e-9)
    if st.steps != expected:
        raise RuntimeError(f"duhamel took {st.steps} steps, not {expected}")
    note = ""
    if st.closed_form_steps:
        note = "closed form" if st.closed_form_steps == st.steps else "partly closed form"
    return RunResult(
        st.wall_time,
        st.total_time,
        np.asarray(sol.t[::stride]),
        np.asarray(sol.x[::stride, 0]),
        st.steps,
        st.newton_iterations / st.steps,
        note,
    )


def ivp_run(
    rhs: Callable[[float, NDArray[np.float64]], object],
    jac: Callable[[float, NDArray[np.float64]], NDArray[np.float64]] | None,
    z0: NDArray[np.float64],
    t_eval: NDArray[np.float64],
    method: str,
    rtol: float,
    atol: float,
    out: int,
) -> RunResult:
    """One ``solve_ivp`` call; the time is the call, the output component `out` at t_eval."""
    kwargs = {"jac": jac} if (jac is not None and method == "Radau") else {}
    start = time.perf_counter()
    res = scipy.integrate.solve_ivp(
        rhs,
        (0.0, float(t_eval[-1])),
        z0,
        method=method,
        rtol=rtol,
        atol=atol,
        t_eval=t_eval,
        **kwargs,
    )
    elapsed = time.perf_counter() - start
    if not res.success:
        raise RuntimeError(f"solve_ivp ({method}, rtol={rtol:g}) failed: {res.message}")
    note = f"atol={atol:.2g}; {res.nfev} RHS calls"
    if method == "Radau":
        note += f", {res.njev} Jacobians, {res.nlu} LU"
    return RunResult(elapsed, elapsed, res.t, res.y[out], int(res.nfev), note=note)


# ------------------------------------------------------------------------------- measuring
def loadavg() -> tuple[float, float, float]:
    try:
        return os.getloadavg()
    except OSError:  # pragma: no cover - not on Unix
        return (float("nan"),) * 3


def _first_pass(
    method: Method,
    error: Callable[[RunResult], float],
    s: PrecisionSetup,
    log: Callable[[str], None],
) -> None:
    """Runs the base list (and the extension for duhamel methods) once, with errors."""

    def one(param: float, label: str, extended: bool) -> Point:
        p = Point(param, label, extended=extended)
        gc.collect()
        try:
            r = method.run(param)
        except duhamel.SolverError as err:
            p.failed = f"diverged at t = {err.time:.4g} s (SolverError, reason={err.reason})"
            return p
        p.error, p.loop_time, p.total_time = error(r), r.loop_time, r.total_time
        p.steps, p.newton_per_step, p.note, p.runs = r.steps, r.newton_per_step, r.note, 1
        return p

    log(f"  {method.name} ...")
    for param, label in zip(method.params, method.labels, strict=True):
        method.points.append(one(param, label, False))
    if method.kind != "duhamel":
        return
    while True:
        ok = [p for p in method.points if not p.failed]
        last = method.points[-1]
        if last.failed or not ok or last.error <= s.extend_to:
            break
        if len(ok) >= 2 and ok[-1].error > s.plateau * ok[-2].error:
            break  # no longer converging: a floor (truncation, round-off)
        dt = last.param / 2.0
        if dt < method.min_param * (1.0 - 1e-9):
            break
        method.points.append(one(dt, method.label_of(dt), True))


def _repeat_pass(methods: Sequence[Method], s: PrecisionSetup) -> None:
    """One round-robin pass: every short-enough case again, in batches; keeps the minima."""
    for method in methods:
        for p in method.points:
            if p.failed or p.loop_time > s.single_seconds:
                continue
            batch = max(1, min(50, math.ceil(s.batch_seconds / max(p.total_time, 1e-6))))
            gc.collect()
            for _ in range(batch):
                r = method.run(p.param)
                p.loop_time = min(p.loop_time, r.loop_time)
                p.total_time = min(p.total_time, r.total_time)
            p.runs += batch


def measure(
    problem: Problem,
    error: Callable[[RunResult], float],
    s: PrecisionSetup,
    log: Callable[[str], None],
) -> None:
    for method in problem.methods:
        _first_pass(method, error, s, log)
    for rep in range(1, s.repeats):
        log(f"  timing pass {rep + 1} of {s.repeats} ...")
        _repeat_pass(problem.methods, s)


# ------------------------------------------------------------------------------- Duffing
def _duffing_label(s: PrecisionSetup) -> Callable[[float], str]:
    def label(dt: float) -> str:
        return f"2 pi/{round(2.0 * math.pi / (s.omega * dt))}"

    return label


def duffing_problem(s: PrecisionSetup) -> tuple[Problem, Callable[[RunResult], float]]:
    def make() -> duhamel.System:
        system = duhamel.System(np.eye(1), np.array([[s.omega**2]]))
        return system.add(duhamel.elements.Cubic(0, k3=s.b))

    t_end = s.duffing_t_end
    label = _duffing_label(s)
    dts = [2.0 * math.pi / (s.omega * n) for n in s.duffing_n]
    min_dt = 2.0 * math.pi / (s.omega * s.duffing_max_n)

    def direct(integrator: object) -> Callable[[float], RunResult]:
        return lambda dt: duhamel_run(make, integrator, t_end, dt, [s.x0], 0)

    integrators: list[tuple[str, object]] = [
        ("Semianalytic (trapezoid)", duhamel.Semianalytic(quadrature="trapezoid")),
        ("Semianalytic (parabolic)", duhamel.Semianalytic(quadrature="parabolic")),
        ("Semianalytic (exact)", duhamel.Semianalytic(quadrature="exact")),
        ("Newmark (average acceleration)", duhamel.Newmark()),
        ("HHT(alpha=-0.1)", duhamel.HHT(alpha=-0.1)),
        ("GeneralizedAlpha(rho_inf=0.8)", duhamel.GeneralizedAlpha(rho_inf=0.8)),
        ("CubicHermite", duhamel.CubicHermite()),
    ]
    problem = Problem("Duffing")
    for name, integ in integrators:
        problem.methods.append(
            Method(
                name,
                "duhamel",
                list(dts),
                [label(dt) for dt in dts],
                direct(integ),
                min_param=min_dt,
                label_of=label,
            )
        )

    omega2, b = s.omega**2, s.b

    def rhs(_t: float, y: NDArray[np.float64]) -> tuple[float, float]:
        x = y[0]
        return (y[1], -omega2 * x - b * x * x * x)

    def jac(_t: float, y: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.array([[0.0, 1.0], [-omega2 - 3.0 * b * y[0] * y[0], 0.0]])

    n_eval = s.periods * s.duffing_eval_n
    t_eval = np.linspace(0.0, t_end, n_eval + 1)
    z0 = np.array([s.x0, 0.0])

    def ivp(method: str) -> Callable[[float], RunResult]:
        return lambda rtol: ivp_run(
            rhs, jac, z0, t_eval, method, rtol, 1e-3 * rtol * abs(s.x0), out=0
        )

    for method in ("DOP853", "Radau"):
        problem.methods.append(
            Method(
                f"solve_ivp {method}",
                "ivp",
                list(s.duffing_rtols),
                [f"{r:.0e}" for r in s.duffing_rtols],
                ivp(method),
                note="analytic Jacobian" if method == "Radau" else "",
            )
        )

    def error(r: RunResult) -> float:
        exact, _ = duffing(r.t, s.omega, s.b, s.x0)
        return float(np.max(np.abs(r.x - exact)) / abs(s.x0))

    return problem, error


# ------------------------------------------------------------------------------- chain
def _chain_label(s: PrecisionSetup) -> Callable[[float], str]:
    def label(dt: float) -> str:
        j = round(math.log2(s.chain_dt0 / dt))
        return f"{dt:.4g}" if j == 0 else f"{dt:.4g} (dt0/{2**j})"

    return label


def chain_first_order(
    s: PrecisionSetup,
) -> tuple[
    Callable[[float, NDArray[np.float64]], NDArray[np.float64]],
    Callable[[float, NDArray[np.float64]], NDArray[np.float64]],
]:
    """``z' = (v, M^-1 (f - C v - K x - r(x)))`` of the same physical system, and its Jacobian.

    M and K are the duhamel System's; C is the modal damping matrix the direct integrators
    build from ``zeta``, ``M Phi diag(2 zeta omega) Phi^T M`` with all modes.
    """
    c = s.chain
    system = nonlinear.chain_system(c)
    M, K = np.asarray(system.M, dtype=float), np.asarray(system.K, dtype=float)
    basis = system.modal(None)
    C = M @ basis.phi @ np.diag(basis.c) @ basis.phi.T @ M
    n = system.n_dof
    Minv = np.linalg.inv(M)
    k3 = np.zeros(n)
    k3[list(c.cubic_dofs)] = c.k3
    f = np.zeros(n)
    f[c.tip] = c.tip_amplitude
    MK, MC, Mk3, Mf = Minv @ K, Minv @ C, Minv * k3[None, :], Minv @ f
    w = c.tip_omega
    J0 = np.block([[np.zeros((n, n)), np.eye(n)], [-MK, -MC]])

    def rhs(t: float, z: NDArray[np.float64]) -> NDArray[np.float64]:
        x, v = z[:n], z[n:]
        return np.concatenate((v, Mf * math.sin(w * t) - MK @ x - MC @ v - Mk3 @ (x * x * x)))

    def jac(_t: float, z: NDArray[np.float64]) -> NDArray[np.float64]:
        J = J0.copy()
        J[n:, :n] -= Mk3 * (3.0 * z[:n] ** 2)[None, :]
        return J

    return rhs, jac


def chain_problem(
    s: PrecisionSetup, log: Callable[[str], None]
) -> tuple[Problem, Callable[[RunResult], float]]:
    c = s.chain
    t_end = s.chain_t_end
    label = _chain_label(s)
    n_grid = round(t_end / s.chain_dt0)
    t_grid = np.arange(n_grid + 1) * s.chain_dt0

    def make() -> duhamel.System:
        return nonlinear.chain_system(c)

    def direct(integrator: object) -> Callable[[float], RunResult]:
        def run(dt: float) -> RunResult:
            stride = round(s.chain_dt0 / dt)
            r = duhamel_run(make, integrator, t_end, dt, None, c.tip, stride)
            if r.t.size != t_grid.size or not np.allclose(r.t, t_grid, atol=1e-9):
                raise RuntimeError("a chain run is not on the comparison grid")
            return r

        return run

    problem = Problem("Chain")
    # The reference: CubicHermite at a very small step, and the next larger step.
    log(f"  reference: CubicHermite, dt = dt0/{2**s.chain_ref_level} ...")
    ref_dt = s.chain_dt0 / 2**s.chain_ref_level
    gc.collect()
    ref = direct(duhamel.CubicHermite())(ref_dt)
    half = direct(duhamel.CubicHermite())(2.0 * ref_dt)
    x_ref = ref.x
    amp = float(np.max(np.abs(x_ref)))
    problem.amplitude = amp
    problem.omega_max = float(make().modal(None).omega[-1])
    problem.ref_note.append(
        f"Reference: `CubicHermite()` at dt = {ref_dt:.4g} s ({ref.steps} steps, "
        f"{ref.loop_time:.3g} s); against the same at twice the step: "
        f"{np.max(np.abs(half.x - x_ref)) / amp:.2g} of the tip amplitude "
        f"({100 * amp:.4g} cm)"
    )

    dts = [s.chain_dt0 / 2**j for j in range(s.chain_levels)]
    min_dt = s.chain_dt0 / 2**s.chain_max_level
    integrators: list[tuple[str, object, str]] = [
        ("Semianalytic (trapezoid)", duhamel.Semianalytic(quadrature="trapezoid"), ""),
        ("Semianalytic (parabolic)", duhamel.Semianalytic(quadrature="parabolic"), ""),
        ("Semianalytic (exact)", duhamel.Semianalytic(quadrature="exact"), ""),
        (
            f"Semianalytic (trapezoid, {s.modes} modes)",
            duhamel.Semianalytic(modes=s.modes),
            f"{s.modes} of {c.n_dof} modes: the error includes the modal truncation",
        ),
        ("Newmark (average acceleration)", duhamel.Newmark(), ""),
        ("HHT(alpha=-0.1)", duhamel.HHT(alpha=-0.1), ""),
        ("GeneralizedAlpha(rho_inf=0.8)", duhamel.GeneralizedAlpha(rho_inf=0.8), ""),
        ("CubicHermite", duhamel.CubicHermite(), ""),
    ]
    for name, integ, note in integrators:
        problem.methods.append(
            Method(
                name,
                "duhamel",
                list(dts),
                [label(dt) for dt in dts],
                direct(integ),
                min_param=min_dt,
                label_of=label,
                note=note,
            )
        )

    rhs, jac = chain_first_order(s)
    z0 = np.zeros(2 * c.n_dof)

    def ivp(method: str) -> Callable[[float], RunResult]:
        return lambda rtol: ivp_run(
            rhs, jac, z0, t_grid, method, rtol, 1e-3 * rtol * amp, out=c.tip
        )

    for method, rtols in (("DOP853", s.chain_dop_rtols), ("Radau", s.chain_radau_rtols)):
        problem.methods.append(
            Method(
                f"solve_ivp {method}",
                "ivp",
                list(rtols),
                [f"{r:.0e}" for r in rtols],
                ivp(method),
                note="analytic Jacobian" if method == "Radau" else "",
            )
        )

    def error(r: RunResult) -> float:
        return float(np.max(np.abs(r.x - x_ref)) / amp)

    return problem, error


# ------------------------------------------------------------------------------- the run
def run_precision(
    s: PrecisionSetup, log: Callable[[str], None], figure: str | None = None
) -> PrecisionResults:
    start = time.perf_counter()
    load_before = loadavg()
    log("work-precision: Duffing ...")
    duff, duff_error = duffing_problem(s)
    measure(duff, duff_error, s, log)
    log("work-precision: 20-dof chain ...")
    chain, chain_error = chain_problem(s, log)
    measure(chain, chain_error, s, log)
    dop = next(m for m in chain.methods if m.name == "solve_ivp DOP853")
    tight = min((p for p in dop.points if not p.failed), key=lambda p: p.param)
    chain.ref_note.append(
        f"Cross-check: solve_ivp DOP853 at rtol = {tight.param:.0e} differs from the reference "
        f"by {tight.error:.2g} of the tip amplitude"
    )
    res = PrecisionResults(s, duff, chain, load_before=load_before)
    res.load_after = loadavg()
    res.seconds = time.perf_counter() - start
    if figure:
        write_figure(res, figure)
        res.figure = figure
    return res


# ------------------------------------------------------------------------------- summary
@dataclass(frozen=True)
class Reach:
    """Time to reach an error level: interpolated (`=`), a bound (`<=`), or not reached."""

    value: float
    kind: str  # "=", "<=", "none"


def time_to_reach(points: Sequence[Point], target: float, attr: str) -> Reach:
    """Log-log interpolation of time against error between the two measured points that
    bracket `target`, taking the points in order of decreasing step (rtol): the first point
    at or below `target` and the one before it. A first point already below gives a bound."""
    ok = [p for p in points if not p.failed and math.isfinite(p.error)]
    for i, p in enumerate(ok):
        if p.error <= target:
            t1 = getattr(p, attr)
            if i == 0:
                return Reach(t1, "<=")
            q = ok[i - 1]
            t0 = getattr(q, attr)
            if p.error <= 0.0 or q.error == p.error:
                return Reach(t1, "<=")
            frac = math.log(target / q.error) / math.log(p.error / q.error)
            return Reach(math.exp(math.log(t0) + frac * math.log(t1 / t0)), "=")
    return Reach(float("nan"), "none")


def _fmt_reach(r: Reach) -> str:
    if r.kind == "none":
        return "not reached"
    return f"{r.value:.3g}" if r.kind == "=" else f"<= {r.value:.3g}"


def _fmt_ratio(r: Reach, ref: Reach) -> str:
    if r.kind == "none" or ref.kind == "none":
        return "n/a"
    x = r.value / ref.value
    if r.kind == "=" and ref.kind == "=":
        return f"{x:.3g}"
    if r.kind == "<=" and ref.kind == "=":
        return f"<= {x:.3g}"
    if r.kind == "=" and ref.kind == "<=":
        return f">= {x:.3g}"
    return "n/a"


def summary(problem: Problem) -> list[tuple[str, list[Reach]]]:
    """Per method: reaches for (loop, t1), (loop, t2), (total, t1), (total, t2)."""
    rows = []
    for m in problem.methods:
        reaches = [
            time_to_reach(m.points, target, attr)
            for attr in ("loop_time", "total_time")
            for target in THRESHOLDS
        ]
        rows.append((m.name, reaches))
    return rows


def summary_table(problem: Problem) -> list[str]:
    rows = summary(problem)
    ref = dict(rows)[REFERENCE_METHOD]
    t1, t2 = (f"{t:.0e}" for t in THRESHOLDS)
    lines = [
        f"| method | loop time to {t1} [s] | x SA-trap | loop time to {t2} [s] | x SA-trap "
        f"| total time to {t1} [s] | x SA-trap | total time to {t2} [s] | x SA-trap |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for name, reaches in rows:
        cells = []
        for r, rr in zip(reaches, ref, strict=True):
            cells += [_fmt_reach(r), _fmt_ratio(r, rr)]
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    return lines


def method_table(m: Method) -> list[str]:
    if m.kind == "duhamel":
        lines = [
            "| dt [s] | steps | max error | loop time [s] | total time [s] | Newton it./step "
            "| runs (best of) | notes |",
            "|---|---:|---:|---:|---:|---:|---:|---|",
        ]
        for p in m.points:
            if p.failed:
                lines.append(f"| {p.label} |  | unstable |  |  |  |  | {p.failed} |")
                continue
            note = "; ".join(x for x in (p.note, "extended range" if p.extended else "") if x)
            lines.append(
                f"| {p.label} | {p.steps} | {p.error:.3g} | {p.loop_time:.4g} | "
                f"{p.total_time:.4g} | {p.newton_per_step:.3g} | {p.runs} | {note} |"
            )
        return lines
    lines = [
        "| rtol | max error | time [s] | runs (best of) | notes |",
        "|---|---:|---:|---:|---|",
    ]
    for p in m.points:
        lines.append(f"| {p.label} | {p.error:.3g} | {p.loop_time:.4g} | {p.runs} | {p.note} |")
    return lines


def fastest(problem: Problem) -> list[str]:
    """Computed statements: the fastest method (loop time) at each error level."""
    rows = summary(problem)
    ref = dict(rows)[REFERENCE_METHOD]
    out = []
    for k, target in enumerate(THRESHOLDS):
        exact = sorted(
            ((r[k].value, name) for name, r in rows if r[k].kind == "="), key=lambda x: x[0]
        )
        bounds = [f"{name} <= {r[k].value:.3g} s" for name, r in rows if r[k].kind == "<="]
        if not exact:
            continue
        text = f"error <= {target:.0e}: fastest by interpolated loop time: " + "; ".join(
            f"{name} {value:.3g} s" for value, name in exact[:3]
        )
        if ref[k].kind == "=":
            text += f" (SA-trap {ref[k].value:.3g} s)"
        if bounds:
            text += "; already below at the largest stable step (loosest rtol) tried: "
            text += "; ".join(bounds)
        missing = [name for name, r in rows if r[k].kind == "none"]
        if missing:
            text += f"; not reached: {'; '.join(missing)}"
        out.append(f"* {problem.name}, {text}.")
    return out


def write_figure(res: PrecisionResults, path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.0, 4.8), dpi=100)
    markers = "os^vD<>ph*"
    for k, m in enumerate(res.duffing.methods):
        pts = [p for p in m.points if not p.failed]
        style = "--" if m.kind == "ivp" else "-"
        ax.loglog(
            [p.loop_time for p in pts],
            [max(p.error, 1e-16) for p in pts],
            style,
            marker=markers[k % len(markers)],
            markersize=4,
            linewidth=1.2,
            label=m.name,
        )
    for target in THRESHOLDS:
        ax.axhline(target, color="0.6", linewidth=0.6, linestyle=":")
    ax.set_xlabel("time [s] (duhamel: Rust loop time, one thread; solve_ivp: the call)")
    ax.set_ylabel("max |x - x_exact| / x0")
    ax.set_title("Duffing x'' + x + 4x^3 = 0, x0 = 1, t_end = 20 pi: work-precision")
    ax.grid(True, which="major", linewidth=0.4, alpha=0.5)
    ax.legend(fontsize=7, loc="lower left")
    fig.tight_layout()
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path)
    plt.close(fig)


# ------------------------------------------------------------------------------- reporting
def precision_markdown(res: PrecisionResults, figure_link: str | None = None) -> list[str]:
    s, c = res.setup, res.setup.chain
    duff_rtols = f"{max(s.duffing_rtols):.0e} ... {min(s.duffing_rtols):.0e}"
    lines = [
        "## Work-precision: Duffing oscillator and a 20-dof chain with cubic springs",
        "",
        "### What this measures",
        "",
        "Maximum error against CPU time for every method, all measured in this one run "
        f"(section time {res.seconds:.0f} s; 1-min load average before {res.load_before[0]:.2f}"
        f", after {res.load_after[0]:.2f}).",
        "",
        f"* **Duffing** `x'' + x + {s.b:g} x^3 = 0`, `x0 = {s.x0:g}`, `v0 = 0`, over "
        f"{s.periods} periods of the background (t_end = {s.duffing_t_end:.6g} s); error = "
        "max |x - x_exact| / x0 at every step (exact `cn` solution, "
        "`duhamel.exact.duffing`); solve_ivp's error at "
        f"{s.duffing_eval_n} instants per background period (`t_eval`, its dense output).",
        f"* **20-dof chain** (the model of the nonlinear section: springs {c.k:g} N/m, "
        f"zeta = {c.zeta:g}, `Cubic(dof, {c.k3:g})` at dofs "
        f"{', '.join(map(str, c.cubic_dofs))}, {c.tip_amplitude:g} N sin({c.tip_omega:g} t) "
        f"at the tip) from rest, t_end = {s.chain_t_end:g} s; error = max |x_tip - x_ref| at "
        f"the instants k x {s.chain_dt0:g} s (common to every dt), divided by max |x_ref| "
        f"= {100 * res.chain.amplitude:.4g} cm; omega_max = {res.chain.omega_max:.4g} rad/s "
        f"(omega_max dt = {res.chain.omega_max * s.chain_dt0:.3g} at dt = {s.chain_dt0:g} s: "
        "above pi, outside CubicHermite's recommended range, see docs/direct.md). "
        f"The same `System(M, K, zeta={c.zeta:g})` "
        "for every duhamel method: Semianalytic uses the modal damping directly, the direct "
        "integrators build `C = M Phi diag(2 zeta omega) Phi^T M` from all modes "
        "(docs/direct.md), solve_ivp gets that same C in first-order form "
        "`z' = (v, M^-1 (f - C v - K x - r(x)))` (numpy right-hand side). "
        + ". ".join(res.chain.ref_note)
        + ".",
        "* **Methods**: `Semianalytic()` (scheme b) with each quadrature (and on the chain with "
        f"{s.modes} of {c.n_dof} modes: its error includes the modal truncation, so it "
        "levels off), `Newmark()`, `HHT(alpha=-0.1)`, `GeneralizedAlpha(rho_inf=0.8)`, "
        "`CubicHermite()`, all through `duhamel.solve` (every step saved, one dof "
        "recovered, `threads=1`), and `scipy.integrate.solve_ivp` DOP853 and Radau (analytic "
        f"Jacobian) at `rtol` = {duff_rtols} (Duffing; chain: DOP853 "
        f"{max(s.chain_dop_rtols):.0e} ... {min(s.chain_dop_rtols):.0e}, Radau "
        f"{max(s.chain_radau_rtols):.0e} ... {min(s.chain_radau_rtols):.0e}), "
        "`atol = 1e-3 rtol x_scale` (x0, or the chain's tip amplitude).",
        "* **Steps**: Duffing dt = 2 pi/{"
        + ", ".join(map(str, s.duffing_n))
        + "}; chain dt = "
        + f"{s.chain_dt0:g} s / 2^j, j = 0 ... {s.chain_levels - 1}. A duhamel method still "
        f"above {s.extend_to:g} at the smallest of these is run at halved steps until it is "
        f"below (down to 2 pi/{s.duffing_max_n}, resp. {s.chain_dt0:g}/{2**s.chain_max_level}),"
        " or until a halving leaves more than "
        f"{100 * s.plateau:.0f} % of the error (a floor); such rows say 'extended range'.",
        "* **Times** (wall clock of single-threaded code, i.e. CPU time on an otherwise idle "
        "core): duhamel's *loop time* is `stats.wall_time` (the Rust time loop, one "
        "thread), its *total time* `stats.total_time` (the whole `solve` call on a fresh "
        "System: modal analysis or damping matrix, loop, recovery); solve_ivp's time is the "
        "call (Python right-hand side: not the same language, an outside reference). Each "
        f"time is the minimum over the runs counted in 'runs': one first pass, then "
        f"{s.repeats - 1} round-robin pass(es) that rerun every case (short ones up to 50 "
        f"times in a row, about {s.batch_seconds:g} s per batch); cases longer than "
        f"{s.single_seconds:g} s run once.",
        "* **Summary**: the time to reach max error <= "
        + " and <= ".join(f"{t:.0e}" for t in THRESHOLDS)
        + " is **interpolated log-log** between the two measured points that bracket the "
        "level (in order of decreasing dt or rtol: the first point at or below it and the one "
        "before); '<= t' means the largest stable step (loosest rtol) tried is already below the "
        "level, 'not reached' that no measured point is. 'x SA-trap' = that time / "
        "Semianalytic (trapezoid)'s.",
        "",
    ]
    for problem, title in (
        (res.duffing, "Duffing oscillator"),
        (res.chain, f"20-dof chain, 4 cubic springs, t_end = {s.chain_t_end:g} s"),
    ):
        lines += [f"### {title}", "", "Summary:", ""]
        lines += summary_table(problem)
        lines += [""]
        if problem is res.duffing and figure_link:
            lines += [f"![work-precision, Duffing]({figure_link})", ""]
        for m in problem.methods:
            head = f"#### {problem.name}: {m.name}"
            if m.note:
                head += f" ({m.note})"
            lines += [head, ""]
            lines += method_table(m)
            lines += [""]
    lines += ["### Fastest per error level (computed from the tables)", ""]
    lines += fastest(res.duffing) + fastest(res.chain)
    return lines


def print_precision(res: PrecisionResults) -> None:
    for problem in (res.duffing, res.chain):
        print()
        print(f"work-precision, {problem.name}:")
        for line in summary_table(problem):
            print(line)
        for m in problem.methods:
            print(f"-- {m.name}")
            for p in m.points:
                if p.failed:
                    print(f"   {p.label:>20}  {p.failed}")
                else:
                    print(
                        f"   {p.label:>20}  err {p.error:9.3g}  loop {p.loop_time:9.4g} s  "
                        f"total {p.total_time:9.4g} s  runs {p.runs}"
                    )
    for line in fastest(res.duffing) + fastest(res.chain):
        print(line)


if __name__ == "__main__":  # the section alone: python benchmarks/precision.py [--quick]
    import sys

    def _log(msg: str) -> None:
        print(msg, file=sys.stderr, flush=True)

    print_precision(run_precision(QUICK if "--quick" in sys.argv else PrecisionSetup(), _log))

"""duhamel benchmarks: a linear 100-mode system (mode-steps/s) and nonlinear cases (ns/step).

The model is a fixed-free chain of 100 unit masses joined by springs ``k = 1e6 N/m`` with 2 %
modal damping (natural frequencies 2.5 Hz ... 318 Hz), loaded by a harmonic force at the free
tip and a step force at mid-chain, and integrated over 1e5 steps of ``dt = 1 ms`` with all 100
modes. In one run on one machine it times:

* ``duhamel.solve`` with the ``Semianalytic`` integrator on one thread and on all cores, and
  with different amounts of output (one dof or all dofs, every step or every 10th, or only
  the final state, which isolates the stepping kernel);
* a pure-numpy loop of the same exact modal recurrence (the same ``A``, ``B`` from
  ``duhamel.oscillator.transfer_matrices`` and the same parabolic load basis), which is both
  a speed baseline and a cross-check: it must agree with duhamel to 1e-10 relative;
* ``scipy.signal.lsim`` on the same system in physical first-order form (200 states, the
  100-dof load vector as input, linear interpolation of the input between samples).

Throughput is reported as mode-steps per second (modes x steps / seconds).

The nonlinear section (``nonlinear.py``, run after the linear one) times a single-dof
Duffing oscillator over 1e6 steps (closed-form steps, Newton steps, and
``scipy.integrate.solve_ivp`` with DOP853 at a matched error) and a 20-dof chain with four
cubic springs over 1e5 steps (5 retained modes and all 20), in nanoseconds per step.

The work-precision section (``precision.py``, run last) measures the maximum error against
CPU time of every integrator (Semianalytic with each quadrature, Newmark, HHT,
generalized-alpha, CubicHermite) and of ``scipy.integrate.solve_ivp`` (DOP853, Radau) at
several step sizes or tolerances, on the Duffing oscillator over ten periods and on the
20-dof chain with cubic springs over 10 s, with the time each method needs to reach an
error of 1e-3 and 1e-6 (log-log interpolation). Usage::

    python benchmarks/run.py                          # print the tables
    python benchmarks/run.py --write BENCHMARKS.md    # also write the markdown report
    python benchmarks/run.py --quick                  # smoke test, a few seconds

OpenBLAS/OpenMP worker threads are limited to one (unless the environment already sets
them) before numpy is imported: on a machine with few cores, idle BLAS workers spin after
each numpy product and steal CPU time from duhamel's time loop, which would make its
timings depend on what numpy did just before.
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import datetime  # noqa: E402
import gc  # noqa: E402
import platform  # noqa: E402
import shlex  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402
from dataclasses import dataclass, field  # noqa: E402
from pathlib import Path  # noqa: E402

import nonlinear  # noqa: E402  (benchmarks/nonlinear.py, next to this script)
import numpy as np  # noqa: E402
import precision  # noqa: E402  (benchmarks/precision.py)
import scipy  # noqa: E402
import scipy.signal  # noqa: E402
from numpy.typing import NDArray  # noqa: E402

import duhamel  # noqa: E402
from duhamel.oscillator import transfer_matrices  # noqa: E402

TARGET = 2e8  # mode-steps per second on one core, few dofs saved (issue acceptance)
AGREEMENT_RTOL = 1e-10  # numpy loop vs duhamel, relative to the largest modal coordinate
FIGURE = "docs/figures/work_precision_duffing.png"  # relative to the repository root


# ------------------------------------------------------------------------------- the model
@dataclass(frozen=True)
class Setup:
    """Size and parameters of the benchmark problem."""

    n_dof: int = 100
    k: float = 1e6  # N/m, every spring
    m: float = 1.0  # kg, every mass
    zeta: float = 0.02
    dt: float = 1e-3
    n_steps: int = 100_000
    tip_amplitude: float = 1e3  # N
    tip_omega: float = 2.0 * np.pi * 2.0  # rad/s (2 Hz, near the first mode at 2.5 Hz)
    step_amplitude: float = 5e2  # N
    repeats: int = 5

    @property
    def tip(self) -> int:
        return self.n_dof - 1

    @property
    def mid(self) -> int:
        return self.n_dof // 2 - 1

    @property
    def t_end(self) -> float:
        return self.n_steps * self.dt


def chain(setup: Setup) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Mass and stiffness of a fixed-free spring-mass chain (dof 0 is tied to the ground)."""
    n, k = setup.n_dof, setup.k
    K = np.zeros((n, n))
    for i in range(n):  # spring i joins node i - 1 (the ground for i = 0) to node i
        K[i, i] += k
        if i > 0:
            K[i - 1, i - 1] += k
            K[i - 1, i] -= k
            K[i, i - 1] -= k
    return setup.m * np.eye(n), K


def make_system(setup: Setup) -> duhamel.System:
    """A fresh model with its two loads (fresh, so no modal analysis is cached)."""
    M, K = chain(setup)
    system = duhamel.System(M, K, zeta=setup.zeta)
    system.add_load(
        duhamel.loads.Harmonic(setup.tip, amplitude=setup.tip_amplitude, omega=setup.tip_omega)
    )
    system.add_load(duhamel.loads.Step(setup.mid, amplitude=setup.step_amplitude, t0=0.0))
    return system


# ------------------------------------------------------------------------------- results
@dataclass
class Row:
    """One timed case."""

    name: str
    modes: int
    steps: int
    loop_time: float  # seconds in the time loop
    total_time: float  # seconds for the whole call (set-up and output included)
    note: str = ""
    timed_steps: int = 0  # steps actually run when the time was scaled from a shorter run

    @property
    def rate(self) -> float:
        return self.modes * self.steps / self.loop_time

    @property
    def total_rate(self) -> float:
        return self.modes * self.steps / self.total_time


@dataclass
class Results:
    """Everything the report needs."""

    setup: Setup
    quick: bool
    rows: list[Row] = field(default_factory=list)
    primary: Row | None = None
    kernel: Row | None = None
    numpy_diff: float = float("nan")
    numpy_tip_diff: float = float("nan")
    lsim_diff: float = float("nan")
    lsim_steps: int = 0
    ref_diff_duhamel: float = float("nan")
    ref_diff_lsim: float = float("nan")
    omega_min: float = float("nan")
    omega_max: float = float("nan")
    load_before: tuple[float, float, float] = (float("nan"),) * 3
    load_after: tuple[float, float, float] = (float("nan"),) * 3


# ------------------------------------------------------------------------------- duhamel
def time_duhamel(
    setup: Setup,
    name: str,
    *,
    threads: int | None,
    dofs: list[int] | None,
    save_every: int,
) -> tuple[Row, duhamel.Solution]:
    """Best of `setup.repeats` cold calls (fresh System each time, so modal analysis counts)."""
    best: duhamel.Solution | None = None
    best_total = float("inf")
    for _ in range(setup.repeats):
        system = make_system(setup)
        gc.collect()
        start = time.perf_counter()
        sol = duhamel.solve(
            system,
            duhamel.Semianalytic(modes=None),
            t_end=setup.t_end,
            dt=setup.dt,
            save_every=save_every,
            dofs=dofs,
            threads=threads,
        )
        # Accelerations are computed on first access: the total time includes them, as it
        # did when they were computed inside `solve`.
        _ = sol.a
        total = time.perf_counter() - start
        if sol.stats.steps != setup.n_steps:
            raise RuntimeError(f"duhamel took {sol.stats.steps} steps, not {setup.n_steps}")
        if best is None or sol.stats.wall_time < best.stats.wall_time:
            best = sol
        best_total = min(best_total, total)
        del sol
    assert best is not None
    row = Row(name, best.stats.modes, best.stats.steps, best.stats.wall_time, best_total)
    return row, best


# ------------------------------------------------------------------------------- numpy loop
def load_basis(setup: Setup, n_steps: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Per-step load basis ``(p0, Dp, DDp)`` of the harmonic and of the step time functions.

    Same definition as the Rust core: the parabola through the values at ``t_n``,
    ``t_n + dt/2`` and ``t_n + dt`` with ``t_n = n dt``; a step with ``t0 = 0`` is held at 1.
    """
    t = np.arange(n_steps) * setup.dt
    s0 = np.sin(setup.tip_omega * t)
    sm = np.sin(setup.tip_omega * (t + 0.5 * setup.dt))
    s1 = np.sin(setup.tip_omega * (t + setup.dt))
    harmonic = np.stack([s0, s1 - s0, sm - 0.5 * (s0 + s1)], axis=1)
    step = np.zeros((n_steps, 3))
    step[:, 0] = (t >= 0.0).astype(np.float64)
    return harmonic, step


def numpy_loop(
    setup: Setup, system: duhamel.System
) -> tuple[Row, NDArray[np.float64], NDArray[np.float64]]:
    """The exact modal recurrence in a Python loop over steps, numpy-vectorised over modes.

    Returns the timing row, the modal displacement history ``q`` (n_steps + 1, n_modes) and
    the modal velocity history.
    """
    started = time.perf_counter()
    basis = system.modal(None)
    n = basis.n_modes
    A, B = transfer_matrices(basis.omega, basis.zeta, setup.dt)  # (n, 2, 2), (n, 2, 3)
    f_tip = np.zeros(system.n_dof)
    f_tip[setup.tip] = setup.tip_amplitude
    f_mid = np.zeros(system.n_dof)
    f_mid[setup.mid] = setup.step_amplitude
    patterns = [basis.phi.T @ f_tip, basis.phi.T @ f_mid]  # modal loads, in add_load order
    # G[:, r, 3 l + j] = pattern_l * B[:, r, j]: the response of the state row r to the
    # basis entry j of load l, so the load term of a step is G @ u with u the stacked bases.
    G = np.concatenate([B * p[:, None, None] for p in patterns], axis=2)
    Gx, Gv = np.ascontiguousarray(G[:, 0, :]), np.ascontiguousarray(G[:, 1, :])
    a11, a12 = A[:, 0, 0].copy(), A[:, 0, 1].copy()
    a21, a22 = A[:, 1, 0].copy(), A[:, 1, 1].copy()

    loop_start = time.perf_counter()
    harmonic, step = load_basis(setup, setup.n_steps)
    U = np.concatenate([harmonic, step], axis=1)  # (n_steps, 6), loads in system order
    q = np.empty((setup.n_steps + 1, n))
    v = np.empty((setup.n_steps + 1, n))
    x = np.zeros(n)
    xd = np.zeros(n)
    q[0], v[0] = x, xd
    for s in range(setup.n_steps):
        u = U[s]
        x, xd = a11 * x + a12 * xd + Gx @ u, a21 * x + a22 * xd + Gv @ u
        q[s + 1] = x
        v[s + 1] = xd
    end = time.perf_counter()
    row = Row(
        "pure-numpy loop, same recurrence",
        n,
        setup.n_steps,
        end - loop_start,
        end - started,
        note="Python loop over steps, numpy over modes; saves q, v every step",
    )
    return row, q, v


# ------------------------------------------------------------------------------- lsim
def state_space(
    setup: Setup, system: duhamel.System
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Physical first-order form ``z = (x, x')``, input the whole load vector, output the tip.

    The damping matrix is the classical one with the modal damping of duhamel:
    ``C = M Phi diag(c) Phi^T M``.
    """
    basis = system.modal(None)
    M, K = np.asarray(system.M), np.asarray(system.K)
    phi = basis.phi
    C = M @ phi @ np.diag(basis.c) @ phi.T @ M
    n = system.n_dof
    Minv = np.linalg.inv(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-Minv @ K, -Minv @ C]])
    Bm = np.vstack([np.zeros((n, n)), Minv])
    Cm = np.zeros((1, 2 * n))
    Cm[0, setup.tip] = 1.0
    return A, Bm, Cm, np.zeros((1, n))


def run_lsim(
    setup: Setup, system: duhamel.System, n_steps: int
) -> tuple[float, float, NDArray[np.float64]]:
    """``scipy.signal.lsim`` over `n_steps` steps: (lsim seconds, total seconds, tip history)."""
    started = time.perf_counter()
    A, Bm, Cm, D = state_space(setup, system)
    t = np.arange(n_steps + 1) * setup.dt
    U = np.zeros((n_steps + 1, system.n_dof))
    for load in system.loads:
        U += load.evaluate(system, t)
    gc.collect()
    call = time.perf_counter()
    _, y, _ = scipy.signal.lsim((A, Bm, Cm, D), U, t, interp=True)
    end = time.perf_counter()
    return end - call, end - started, np.asarray(y).reshape(-1)


def lsim_case(
    setup: Setup, system: duhamel.System, max_seconds: float
) -> tuple[Row, NDArray[np.float64]]:
    """Times lsim on the full run, or on a shorter run scaled up when it would be too slow."""
    probe = min(setup.n_steps, 2000)
    probe_time, _, _ = run_lsim(setup, system, probe)
    projected = probe_time * setup.n_steps / probe
    n_run = setup.n_steps
    if projected > max_seconds:
        n_run = max(probe, int(setup.n_steps * 0.5 * max_seconds / projected))
    # Best of `repeats` runs while that fits the time budget, else a single run.
    one_run = projected * n_run / setup.n_steps
    repeats = setup.repeats if one_run * setup.repeats <= max_seconds else 1
    loop, total, y = run_lsim(setup, system, n_run)
    for _ in range(repeats - 1):
        loop_i, total_i, _ = run_lsim(setup, system, n_run)
        loop, total = min(loop, loop_i), min(total, total_i)
    scale = setup.n_steps / n_run
    note = f"physical form, 200 states, 100 inputs, FOH input; best of {repeats}"
    if n_run < setup.n_steps:
        note += f"; timed on {n_run} steps and scaled x{scale:.3g}"
    row = Row(
        "scipy.signal.lsim",
        system.n_dof,
        setup.n_steps,
        loop * scale,
        total * scale,
        note=note,
        timed_steps=n_run,
    )
    return row, y


# ------------------------------------------------------------------------------- the run
def loadavg() -> tuple[float, float, float]:
    """System load averages (1, 5, 15 min), NaN where unavailable."""
    try:
        return os.getloadavg()
    except OSError:  # pragma: no cover - not on Unix
        return (float("nan"),) * 3


def rel_max(a: NDArray[np.float64], b: NDArray[np.float64]) -> float:
    """``max |a - b| / max |b|``."""
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))


def run(setup: Setup, quick: bool, lsim_max_seconds: float, log: Callable[[str], None]) -> Results:
    """Runs every case and the cross-checks."""
    res = Results(setup=setup, quick=quick, load_before=loadavg())
    basis = make_system(setup).modal(None)
    res.omega_min, res.omega_max = float(basis.omega[0]), float(basis.omega[-1])
    n = setup.n_steps
    tip = [setup.tip]

    log("duhamel, threads=1, dofs=[tip], save_every=1 ...")
    primary, sol = time_duhamel(setup, "", threads=1, dofs=tip, save_every=1)
    primary.name = "duhamel, 1 thread, dofs=[tip], every step"
    res.primary = primary
    res.rows.append(primary)
    q_duhamel = np.array(sol.modal.q)
    x_duhamel = np.array(sol.x[:, 0])
    del sol

    cases: list[tuple[str, int | None, list[int] | None, int, str]] = [
        ("duhamel, all cores, dofs=[tip], every step", None, tip, 1, ""),
        ("duhamel, 1 thread, all dofs, every step", 1, None, 1, "x, v, a of 100 dofs"),
        ("duhamel, 1 thread, dofs=[tip], every 10th step", 1, tip, 10, ""),
        (
            "duhamel, 1 thread, final state only",
            1,
            tip,
            n,
            "save_every=n_steps: the stepping kernel alone",
        ),
        ("duhamel, all cores, final state only", None, tip, n, "save_every=n_steps"),
    ]
    for name, threads, dofs, every, note in cases:
        log(f"{name} ...")
        row, sol = time_duhamel(setup, name, threads=threads, dofs=dofs, save_every=every)
        row.note = note
        res.rows.append(row)
        if every == n and threads == 1:
            res.kernel = row
        del sol

    log("pure-numpy loop ...")
    row, q_np, _ = numpy_loop(setup, make_system(setup))
    for _ in range(setup.repeats - 1):
        again, _, _ = numpy_loop(setup, make_system(setup))
        row.loop_time = min(row.loop_time, again.loop_time)
        row.total_time = min(row.total_time, again.total_time)
    row.note += f"; best of {setup.repeats}"
    res.rows.append(row)
    res.numpy_diff = rel_max(q_np, q_duhamel)
    tip_np = q_np @ basis.phi[setup.tip, :]
    res.numpy_tip_diff = rel_max(tip_np, x_duhamel)
    log(f"  numpy loop vs duhamel: max |dq| / max |q| = {res.numpy_diff:.3e}")
    if not res.numpy_diff < AGREEMENT_RTOL:
        raise RuntimeError(
            f"the numpy loop disagrees with duhamel: relative difference {res.numpy_diff:.3e} "
            f">= {AGREEMENT_RTOL:g}"
        )

    log("scipy.signal.lsim ...")
    row, y = lsim_case(setup, make_system(setup), lsim_max_seconds)
    res.rows.append(row)
    res.lsim_steps = row.timed_steps
    res.lsim_diff = rel_max(y, x_duhamel[: y.size])

    log("reference: duhamel with dt/10 ...")
    fine = Setup(**{**setup.__dict__, "dt": setup.dt / 10, "n_steps": n * 10, "repeats": 1})
    _, ref = time_duhamel(fine, "", threads=None, dofs=tip, save_every=10)
    x_ref = np.array(ref.x[:, 0])
    if x_ref.size != x_duhamel.size:
        raise RuntimeError("the reference run is not on the benchmark's time grid")
    res.ref_diff_duhamel = rel_max(x_duhamel, x_ref)
    res.ref_diff_lsim = rel_max(y, x_ref[: y.size])
    res.load_after = loadavg()
    return res


# ------------------------------------------------------------------------------- reporting
def cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def git_revision() -> str:
    try:
        rev = subprocess.run(
            ["git", "rev-parse", "--short", "HEAD"],
            capture_output=True,
            text=True,
            check=True,
            cwd=Path(__file__).resolve().parent,
        ).stdout.strip()
        dirty = subprocess.run(
            ["git", "status", "--porcelain", "--untracked-files=no"],
            capture_output=True,
            text=True,
            check=True,
            cwd=Path(__file__).resolve().parent,
        ).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"
    return f"{rev} (uncommitted changes)" if dirty else rev


def machine_info(res: Results) -> list[tuple[str, str]]:
    try:
        usable = len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not on Linux
        usable = os.cpu_count() or 0
    blas = f"OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS', '')}"
    load = f"before {res.load_before[0]:.2f}, after {res.load_after[0]:.2f}"
    return [
        ("date (UTC)", datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M")),
        ("platform", platform.platform()),
        ("CPU", cpu_model()),
        ("cores", f"{os.cpu_count()} logical, {usable} usable by this process"),
        ("Python", platform.python_version()),
        ("numpy / scipy", f"{np.__version__} / {scipy.__version__}"),
        ("duhamel", f"{duhamel.__version__} (git {git_revision()})"),
        ("BLAS threads", blas),
        ("1-min load average", f"{load} (other processes share the machine if >> 1)"),
    ]


def fmt_rate(x: float) -> str:
    return f"{x:.3g}"


def fmt_time(x: float) -> str:
    return f"{x:.4g}"


def table(res: Results) -> list[str]:
    assert res.primary is not None
    ref = res.primary.loop_time
    lines = [
        "| case | mode-steps/s (loop) | loop time [s] | total time [s] "
        "| loop time / duhamel 1-thread | notes |",
        "|---|---:|---:|---:|---:|---|",
    ]
    for r in res.rows:
        lines.append(
            f"| {r.name} | {fmt_rate(r.rate)} | {fmt_time(r.loop_time)} | "
            f"{fmt_time(r.total_time)} | {r.loop_time / ref:.3g} | {r.note} |"
        )
    return lines


def verdict(res: Results) -> str:
    assert res.primary is not None
    rate = res.primary.rate
    met = "MET" if rate >= TARGET else "NOT MET"
    text = (
        f"**Target (>= {TARGET:.0e} mode-steps/s on one core, few dofs saved): {met}** - "
        f"{rate:.3g} mode-steps/s (duhamel, 1 thread, dofs=[tip], every step saved, "
        f"loop time)."
    )
    if res.kernel is not None:
        text += (
            f" The stepping kernel alone (final state only) runs at {res.kernel.rate:.3g} "
            f"mode-steps/s ({'above' if res.kernel.rate >= TARGET else 'below'} the target)."
        )
    return text


def findings(res: Results) -> list[str]:
    """Observations computed from this run's numbers."""
    by_name = {r.name: r for r in res.rows}
    p, k = res.primary, res.kernel
    assert p is not None
    lines: list[str] = []
    if k is not None:
        extra = p.loop_time - k.loop_time
        lines.append(
            f"* Output cost: saving the modal history at every step adds {extra:.3g} s to the "
            f"loop ({100 * extra / p.loop_time:.0f} % of it) compared with keeping only the "
            "final state, whatever `dofs` is."
        )
    every10 = by_name.get("duhamel, 1 thread, dofs=[tip], every 10th step")
    if every10 is not None:
        lines.append(
            f"* Saving every 10th step: {every10.rate:.3g} mode-steps/s "
            f"({p.loop_time / every10.loop_time:.2g}x the every-step rate)."
        )
    alldofs = by_name.get("duhamel, 1 thread, all dofs, every step")
    if alldofs is not None:
        lines.append(
            f"* All 100 dofs instead of one: total time {alldofs.total_time:.3g} s vs "
            f"{p.total_time:.3g} s (the back-transformation to x, v, a is done in numpy after "
            "the loop)."
        )
    allcores = by_name.get("duhamel, all cores, dofs=[tip], every step")
    if allcores is not None:
        lines.append(
            f"* All cores vs one thread (every step saved): loop time "
            f"{allcores.loop_time:.3g} s vs {p.loop_time:.3g} s "
            f"(speed-up {p.loop_time / allcores.loop_time:.3g}x)."
        )
    numpy_row = by_name.get("pure-numpy loop, same recurrence")
    lsim_row = by_name.get("scipy.signal.lsim")
    if numpy_row is not None and lsim_row is not None:
        lines.append(
            f"* duhamel (1 thread, every step) is {numpy_row.loop_time / p.loop_time:.3g}x "
            f"faster than the pure-numpy loop and {lsim_row.loop_time / p.loop_time:.3g}x "
            "faster than lsim in loop time "
            f"({numpy_row.total_time / p.total_time:.3g}x and "
            f"{lsim_row.total_time / p.total_time:.3g}x in total time)."
        )
    return lines


def markdown(
    res: Results,
    command: str,
    nl: nonlinear.NonlinearResults | None = None,
    wp: precision.PrecisionResults | None = None,
    figure_link: str | None = None,
) -> str:
    s = res.setup
    assert res.primary is not None
    n_saved = s.n_steps + 1
    history_mb = 2 * s.n_dof * n_saved * 8 / 1e6
    out: list[str] = ["# Benchmarks", ""]
    if res.quick:
        out += [
            "> **QUICK smoke-test run (`--quick`): sizes are reduced, numbers are not "
            "representative.**",
            "",
        ]
    out += [
        "Generated by `benchmarks/run.py`; re-run it to refresh. Command:",
        "",
        "```sh",
        command,
        "```",
        "",
        "## Machine",
        "",
        "| | |",
        "|---|---|",
    ]
    out += [f"| {k} | {v} |" for k, v in machine_info(res)]
    out += [
        "",
        "## What this measures",
        "",
        f"A linear {s.n_dof}-dof fixed-free spring-mass chain (masses {s.m:g} kg, springs "
        f"{s.k:g} N/m, modal damping zeta = {s.zeta:g}; omega = {res.omega_min:.4g} ... "
        f"{res.omega_max:.4g} rad/s, so omega_max * dt = {res.omega_max * s.dt:.3g}) is "
        f"integrated with all {s.n_dof} modes over {s.n_steps} steps of dt = {s.dt:g} s, "
        f"under {s.tip_amplitude:g} N * sin({s.tip_omega:.4g} t) at the tip (dof {s.tip}) and "
        f"a {s.step_amplitude:g} N step at dof {s.mid}. Throughput is "
        "**mode-steps per second** = modes x steps / seconds (for the numpy loop and lsim "
        f"with the same {s.n_dof} modes and steps, i.e. an equivalent rate). "
        "For duhamel the *loop time* is "
        "`Solution.stats.wall_time` (the Rust time loop, GIL released, including the "
        "allocation and filling of the modal history); the *total time* is "
        "`stats.total_time` (the whole `solve` call on a fresh `System`: modal analysis, "
        "load projection, loop, back-transformation to the requested dofs). duhamel rows are "
        f"the best of {s.repeats} run(s) (loop and total minimised separately), as are the "
        "numpy and lsim rows (see their notes).",
        "",
        "* **pure-numpy loop**: the same exact recurrence `y_{n+1} = A y_n + B (p0, Dp, DDp)` "
        "with `A`, `B` from `duhamel.oscillator.transfer_matrices`, the same parabolic load "
        "basis (sin at the start, middle and end of each step, evaluated vectorised before "
        "the loop), a Python `for` loop over steps and numpy over the modes, storing `q` and "
        "`v` every step. Its loop time includes the load basis; its total time adds modal "
        "patterns and transfer matrices. It doubles as a cross-check of the Rust loop.",
        "* **scipy.signal.lsim**: the same system in physical first-order form (200 states, "
        "`C = M Phi diag(2 zeta omega) Phi^T M`), input the 100-dof load vector sampled at "
        "the step times, output the tip displacement. lsim interpolates the input linearly "
        "between samples (first-order hold), duhamel uses the parabola through start, middle "
        "and end of each step, so the two differ by the load representation; both are "
        "compared with a duhamel run at dt/10 as reference. Its loop time is the `lsim` call "
        "(matrix exponential + its Python loop), its total time adds building the matrices "
        "and sampling the input.",
        f"* duhamel's time loop always stores the full modal history (q and v of every mode "
        f"at every saved step: {history_mb:.0f} MB here when every step is saved; modal "
        "accelerations follow from the modal equations and are recovered afterwards); "
        "`dofs` only selects the back-transformation done afterwards with numpy (in total "
        "time), so the output rows show what saving costs.",
        "",
        "## Results",
        "",
    ]
    out += table(res)
    out += ["", verdict(res), ""]
    out += findings(res)
    out += [
        "",
        "## Accuracy",
        "",
        "| comparison | max abs difference / max abs value |",
        "|---|---:|",
        f"| pure-numpy loop vs duhamel, all modal coordinates q | {res.numpy_diff:.2e} "
        f"(required < {AGREEMENT_RTOL:g}) |",
        f"| pure-numpy loop vs duhamel, tip displacement | {res.numpy_tip_diff:.2e} |",
        f"| lsim vs duhamel, tip displacement ({res.lsim_steps} steps) | {res.lsim_diff:.2e} |",
        f"| duhamel (dt) vs duhamel (dt/10), tip displacement | {res.ref_diff_duhamel:.2e} |",
        f"| lsim (dt) vs duhamel (dt/10), tip displacement | {res.ref_diff_lsim:.2e} |",
        "",
    ]
    if nl is not None:
        out += [*nonlinear.nonlinear_markdown(nl), ""]
    if wp is not None:
        out += [*precision.precision_markdown(wp, figure_link), ""]
    return "\n".join(out)


def print_report(res: Results) -> None:
    print()
    for line in table(res):
        print(line)
    print()
    print(verdict(res))
    print()
    print(f"numpy loop vs duhamel (q):           {res.numpy_diff:.2e}")
    print(f"numpy loop vs duhamel (tip x):       {res.numpy_tip_diff:.2e}")
    print(f"lsim vs duhamel (tip x):             {res.lsim_diff:.2e}")
    print(f"duhamel(dt) vs duhamel(dt/10) (tip): {res.ref_diff_duhamel:.2e}")
    print(f"lsim(dt) vs duhamel(dt/10) (tip):    {res.ref_diff_lsim:.2e}")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--write", metavar="FILE", help="write the markdown report to FILE")
    parser.add_argument(
        "--quick", action="store_true", help="small smoke-test size (a few seconds)"
    )
    parser.add_argument("--steps", type=int, default=None, help="override the number of steps")
    parser.add_argument("--repeats", type=int, default=None, help="duhamel repeats (best of)")
    parser.add_argument(
        "--lsim-max-seconds",
        type=float,
        default=60.0,
        help="if lsim would take longer on all steps, time it on fewer steps and scale",
    )
    parser.add_argument(
        "--ivp-max-seconds",
        type=float,
        default=120.0,
        help="if solve_ivp (Duffing) would take longer on the whole span, time it on a "
        "shorter span and scale",
    )
    parser.add_argument(
        "--nonlinear-repeats",
        type=int,
        default=None,
        help="repeats (best of) of the nonlinear cases (default 3)",
    )
    parser.add_argument(
        "--precision-repeats",
        type=int,
        default=None,
        help="timing passes of the work-precision section (default 3)",
    )
    parser.add_argument(
        "--figure",
        metavar="PNG",
        default=None,
        help="write the Duffing work-precision plot to PNG (default with --write and without "
        "--quick: docs/figures/work_precision_duffing.png; 'none' for no plot)",
    )
    parser.add_argument(
        "--no-precision", action="store_true", help="skip the work-precision section"
    )
    args = parser.parse_args(argv)

    setup = Setup(n_steps=2000, repeats=1) if args.quick else Setup()
    if args.steps is not None:
        setup = Setup(**{**setup.__dict__, "n_steps": args.steps})
    if args.repeats is not None:
        setup = Setup(**{**setup.__dict__, "repeats": args.repeats})

    def log(msg: str) -> None:
        print(msg, file=sys.stderr, flush=True)

    nl_setup = nonlinear.QUICK if args.quick else nonlinear.NonlinearSetup()
    if args.nonlinear_repeats is not None:
        nl_setup = nonlinear.NonlinearSetup(
            **{**nl_setup.__dict__, "repeats": args.nonlinear_repeats}
        )

    wp_setup = precision.QUICK if args.quick else precision.PrecisionSetup()
    if args.precision_repeats is not None:
        wp_setup = precision.PrecisionSetup(
            **{**wp_setup.__dict__, "repeats": args.precision_repeats}
        )
    figure = args.figure
    if figure is None and args.write and not args.quick:
        figure = str(Path(__file__).resolve().parent.parent / FIGURE)
    if figure is not None and figure.lower() == "none":
        figure = None

    res = run(setup, args.quick, args.lsim_max_seconds, log)
    nl = nonlinear.run_nonlinear(nl_setup, args.ivp_max_seconds, log)
    wp = None if args.no_precision else precision.run_precision(wp_setup, log, figure)
    res.load_after = loadavg()
    print_report(res)
    nonlinear.print_nonlinear(nl)
    if wp is not None:
        precision.print_precision(wp)
    if args.write:
        command = shlex.join(getattr(sys, "orig_argv", [sys.executable, *sys.argv]))
        link = None
        if wp is not None and wp.figure:
            link = os.path.relpath(wp.figure, Path(args.write).resolve().parent)
        Path(args.write).write_text(markdown(res, command, nl, wp, link))
        log(f"wrote {args.write}")
        if wp is not None and wp.figure:
            log(f"wrote {wp.figure}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

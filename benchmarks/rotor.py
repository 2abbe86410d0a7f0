"""ROSS's example rotor: duhamel against ROSS's own ``run_time_response``, in one run.

The model is ``ross.rotor_example()`` (6 Timoshenko shaft elements of 0.25 m x 50 mm, two
steel disks at nodes 2 and 4, bearings kxx = 1e6, kyy = 0.8e6 N/m at nodes 0 and 6, no
damping), turned into a duhamel System by :func:`duhamel.rotor.from_ross` at 500 rad/s (28
lateral dofs). ROSS runs on exactly the same matrices: its own ``convert_6dof_to_4dof`` of the
same rotor (checked equal to ``from_ross``'s), and, for reference, on its default 6-dof model
(42 dofs, the axial and torsional ones included) as a ROSS user would call it.

**Linear case.** An unbalance ``m_e = 1e-3 kg m`` at the disk of node 2, switched on at
``t = 0`` from rest, 1e5 steps of ``dt = 0.1 ms`` (10 s, 796 revolutions). ROSS gets the force
array ``F`` sampled at the steps; duhamel the harmonic unbalance load. Timed: duhamel
``Semianalytic`` (all 28 modes, and 12 modes) both with its default ``coupling="auto"`` (the
gyroscopic terms integrated exactly in the first-order modes; also on one thread) and with
``coupling="pseudo-force"`` (the paper's route), duhamel ``Newmark``, ROSS ``run_time_response``
with ``method="default"`` (``scipy.signal.lsim`` on the first-order system) and
``method="newmark"`` (its Python-level Newmark loop, numba-compiled step; compiled before
timing). Error: the largest difference over all translational dofs and all steps against the
exact solution, divided by the largest translation; the exact solution is the harmonic
particular solution plus the free vibration, from the eigen-decomposition of the first-order
system, cross-checked by ``scipy.linalg.expm`` of the system augmented with the forcing
oscillator. The speed targets of issue 6 are judged at equal or better accuracy: each duhamel
method is rerun at ``dt/k`` (saving every ``k``-th step) with the smallest ``k`` that makes it
at least as accurate as the ROSS path, and timed over the same 10 s.

**Rub.** The same rotor and unbalance, plus a ``duhamel.elements.Contact`` at the disk of
node 2 (radial clearance 80 um, stiffness 5e7 N/m, friction 0.1): the disk rubs from the
first revolution. duhamel (``Semianalytic`` with all 28 modes, 20 and 12: the contact force a
pseudo-force on the exactly integrated gyroscopic background; ``Newmark``, implicit) is
compared with the lagged-force Newmark that ROSS uses for nonlinear forces: ROSS's
own ``run_time_response(method="newmark", add_to_RHS=...)`` evaluates the extra force at the
state of the previous step (the same contact law, written in Python), and a numpy
implementation of the same lagged scheme with a consistent initial acceleration (ROSS starts
from zero acceleration) isolates the effect of the lag. Error over the first 0.05 s (4
revolutions; the undamped rub is chaotic, so that over longer spans every method drifts from
every other, the references included): the largest distance of the disk centre from the
reference, divided by the largest radial displacement of the reference; the reference is
``Semianalytic`` at ``dt = 25 us / 16``, cross-checked by ``Newmark`` at the same step, at
``dt`` = 0.1, 0.05 and 0.025 ms. Timed over 1e5 steps (a method that diverges there is
timed on its window run).

Usage::

    python benchmarks/rotor.py                                # print the tables
    python benchmarks/rotor.py --append BENCHMARKS.md         # as a section of BENCHMARKS.md
    python benchmarks/rotor.py --quick                        # smoke test, a few seconds

Needs ROSS (``pip install duhamel[ross]``; ``make test`` installs it). OpenBLAS/OpenMP worker
threads are limited to one before numpy is imported, as in ``run.py``.
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import contextlib  # noqa: E402
import datetime  # noqa: E402
import gc  # noqa: E402
import io  # noqa: E402
import math  # noqa: E402
import platform  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402
from collections.abc import Callable  # noqa: E402
from dataclasses import dataclass, field  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402
import scipy  # noqa: E402
import scipy.linalg  # noqa: E402
from numpy.typing import NDArray  # noqa: E402

import duhamel  # noqa: E402
from duhamel.rotor import from_ross  # noqa: E402

NEWMARK_TARGET = 50.0  # issue 6: at least 50x faster than ROSS's Newmark path ...
LSIM_TARGET = 10.0  # ... and 10x faster than its lsim path, at equal or better accuracy
RUB_TARGET = 10.0  # rub: an error at least 10x smaller than the lagged-force Newmark
MAX_REFINE = 64  # largest dt/k tried to match an accuracy
WARM_UP = 4  # untimed duhamel calls before the linear timings (see `linear`)
EXACT_28 = "duhamel Semianalytic, 28 modes (exact coupling)"
EXACT_28_1T = "duhamel Semianalytic, 28 modes (exact coupling), one thread"
EXACT_RED = "duhamel Semianalytic, 12 modes (exact coupling)"
PSEUDO_28 = "duhamel Semianalytic, 28 modes, pseudo-force, tol=0.5"
PSEUDO_RED = "duhamel Semianalytic, 12 modes, pseudo-force, tol=0.5"


# ------------------------------------------------------------------------------- set-up
@dataclass(frozen=True)
class Setup:
    speed: float = 500.0  # rad/s
    m_e: float = 1e-3  # kg m
    node: int = 2  # the disk carrying the unbalance (and the rub)
    dt: float = 1e-4
    n_steps: int = 100_000
    modes: int = 12  # reduced Semianalytic
    repeats: int = 3
    clearance: float = 8e-5
    contact_stiffness: float = 5e7
    friction: float = 0.1
    rub_modes: int = 20  # reduced Semianalytic for the rub (12 miss the contact's high modes)
    rub_window: float = 0.05  # s, accuracy window of the rub (4 revolutions)
    rub_steps: tuple[float, ...] = (1e-4, 5e-5, 2.5e-5)
    rub_ref_factor: int = 16

    @property
    def t_end(self) -> float:
        return self.n_steps * self.dt


def import_ross() -> Any:
    with warnings.catch_warnings(), contextlib.redirect_stdout(io.StringIO()):
        warnings.simplefilter("ignore")  # ROSS's ccp dependency warns about REFPROP
        try:
            import ross
        except ImportError:
            sys.exit("benchmarks/rotor.py needs ROSS: pip install 'duhamel[ross]' (or make test)")
    return ross


def quiet(fn: Callable[..., Any], *args: Any, **kwargs: Any) -> Any:
    """Call a ROSS function without its prints ("Running direct method")."""
    with contextlib.redirect_stdout(io.StringIO()):
        return fn(*args, **kwargs)


class Model:
    """ROSS's example rotor, its 4-dof conversion and the duhamel model."""

    def __init__(self, ross: Any, setup: Setup) -> None:
        from ross.utils import convert_6dof_to_4dof

        self.setup = setup
        self.ross6 = ross.rotor_example()
        self.ross4 = convert_6dof_to_4dof(self.ross6)
        model = from_ross(self.ross6, setup.speed)
        self.dofs = model.dofs
        self.M, self.K, self.C, self.G = model.matrices
        w = setup.speed
        same = all(
            np.array_equal(a, b)
            for a, b in zip(
                model.matrices,
                (self.ross4.M(w), self.ross4.K(w), self.ross4.C(w), self.ross4.G()),
                strict=True,
            )
        )
        if not same:
            raise RuntimeError("from_ross's matrices differ from ROSS's convert_6dof_to_4dof")
        self.ix, self.iy = self.dofs(setup.node, "x"), self.dofs(setup.node, "y")
        self.trans = np.array(
            [i for i, s in enumerate(self.dofs.labels) if s.split("_")[0] in ("x", "y")]
        )

    def system(self, rub: bool = False) -> duhamel.System:
        s = self.setup
        system, dofs, _ = from_ross(self.ross6, s.speed)
        system.add_load(dofs.unbalance(s.node, s.m_e, s.speed))
        if rub:
            system.add(self.contact())
        return system

    def contact(self) -> duhamel.elements.Contact:
        s = self.setup
        return duhamel.elements.Contact(
            (self.ix, self.iy),
            clearance=s.clearance,
            stiffness=s.contact_stiffness,
            friction=s.friction,
        )

    def force(self, t: NDArray[np.float64], n_dof: int, index: NDArray[np.intp]) -> NDArray:
        """ROSS's force array of the unbalance on `n_dof` dofs (x, y at `index`)."""
        s = self.setup
        F = np.zeros((t.size, n_dof))
        F[:, index[self.ix]] = s.m_e * s.speed**2 * np.cos(s.speed * t)
        F[:, index[self.iy]] = s.m_e * s.speed**2 * np.sin(s.speed * t)
        return F


# ------------------------------------------------------------------------------- exact reference
class Exact:
    """Exact response to the unbalance from rest: ``z = Re(z_p e^{i W t}) + V e^{L t} c``."""

    def __init__(self, model: Model) -> None:
        M, K, C, G, w = model.M, model.K, model.C, model.G, model.setup.speed
        n = M.shape[0]
        self.n = n
        self.A = np.block(
            [
                [np.zeros((n, n)), np.eye(n)],
                [-np.linalg.solve(M, K), -np.linalg.solve(M, C + w * G)],
            ]
        )
        fc = np.zeros(n, dtype=complex)
        amp = model.setup.m_e * w**2
        fc[model.ix], fc[model.iy] = amp, -1j * amp  # cos(W t), sin(W t) = Re(-i e^{i W t})
        self.b = np.concatenate([np.zeros(n), np.linalg.solve(M, fc)])
        self.zp = np.linalg.solve(1j * w * np.eye(2 * n) - self.A, self.b)
        self.lam, self.V = np.linalg.eig(self.A)
        self.c = np.linalg.solve(self.V, -self.zp.real.astype(complex))
        self.w = w

    def displacements(self, t: NDArray[np.float64], rows: NDArray[np.intp]) -> NDArray:
        out = np.empty((t.size, rows.size))
        for a in range(0, t.size, 20_000):
            tt = t[a : a + 20_000]
            free = (self.V[rows] @ (self.c[:, None] * np.exp(self.lam[:, None] * tt))).real
            forced = (self.zp[rows, None] * np.exp(1j * self.w * tt)).real
            out[a : a + tt.size] = (free + forced).T
        return out

    def expm_check(self, t: NDArray[np.float64], rows: NDArray[np.intp]) -> float:
        """Largest difference to ``expm`` of the system augmented with the forcing oscillator
        ``(cos W t, sin W t)``, at the times `t`, relative to the largest value."""
        n2 = 2 * self.n
        aug = np.zeros((n2 + 2, n2 + 2))
        aug[:n2, :n2] = self.A
        aug[:n2, n2] = self.b.real  # times cos(W t)
        aug[:n2, n2 + 1] = -self.b.imag  # b = b_r + i b_i: Re(b e^{iWt}) = b_r cos - b_i sin
        aug[n2, n2 + 1], aug[n2 + 1, n2] = -self.w, self.w
        z0 = np.zeros(n2 + 2)
        z0[n2] = 1.0
        ref = np.array([(scipy.linalg.expm(aug * tk) @ z0)[rows] for tk in t])
        ours = self.displacements(t, rows)
        return float(np.abs(ours - ref).max() / np.abs(ref).max())


# ------------------------------------------------------------------------------- results
@dataclass
class Row:
    name: str
    steps: int
    total: float  # s, the whole call
    loop: float | None = None  # s, duhamel's time loop
    error: float = float("nan")
    error_early: float = float("nan")  # over the first 0.2 s
    note: str = ""

    @property
    def us_per_step(self) -> float:
        return 1e6 * self.total / self.steps


@dataclass
class Matched:
    method: str
    against: str
    target_error: float
    k: int | None
    error: float
    total: float
    ross_total: float

    @property
    def speedup(self) -> float:
        return self.ross_total / self.total if self.k else float("nan")


@dataclass
class RubRow:
    name: str
    errors: dict[float, float]
    us_per_step: float = float("nan")
    note: str = ""


@dataclass
class Results:
    setup: Setup
    quick: bool
    versions: dict[str, str] = field(default_factory=dict)
    rows: list[Row] = field(default_factory=list)
    matched: list[Matched] = field(default_factory=list)
    rub: list[RubRow] = field(default_factory=list)
    exact_check: float = float("nan")
    rub_ref_check: float = float("nan")
    rub_peak: float = float("nan")
    omega_max: float = float("nan")
    load: tuple[float, float] = (float("nan"), float("nan"))


def loadavg() -> float:
    try:
        return os.getloadavg()[0]
    except OSError:  # pragma: no cover
        return float("nan")


# ------------------------------------------------------------------------------- linear case
def run_duhamel(
    model: Model,
    integrator: Any,
    dt: float,
    n_steps: int,
    repeats: int,
    save_every: int = 1,
    threads: int | None = None,
) -> tuple[duhamel.Solution, float]:
    """Best of `repeats` cold calls (fresh System: the modal analysis counts)."""
    best: duhamel.Solution | None = None
    best_total = math.inf
    for _ in range(repeats):
        system = model.system()
        gc.collect()
        started = time.perf_counter()
        sol = duhamel.solve(
            system, integrator, t_end=n_steps * dt, dt=dt, save_every=save_every, threads=threads
        )
        total = time.perf_counter() - started
        if sol.stats.steps != n_steps:
            raise RuntimeError(f"duhamel took {sol.stats.steps} steps, not {n_steps}")
        if total < best_total:
            best, best_total = sol, total
    assert best is not None
    return best, best_total


def run_ross(
    rotor: Any, speed: float, F: NDArray, t: NDArray, method: str, repeats: int, **kw: Any
) -> tuple[NDArray, float]:
    best, out = math.inf, None
    for _ in range(repeats):
        gc.collect()
        started = time.perf_counter()
        res = quiet(rotor.run_time_response, speed, F, t, method=method, **kw)
        best = min(best, time.perf_counter() - started)
        out = res.yout
    assert out is not None
    return out, best


def linear(model: Model, res: Results, log: Callable[[str], None]) -> None:
    s = model.setup
    t = np.arange(s.n_steps + 1) * s.dt
    exact = Exact(model)
    rows = model.trans
    X = exact.displacements(t, rows)
    res.exact_check = exact.expm_check(t[:: max(1, s.n_steps // 10)], rows)
    res.omega_max = float(np.abs(exact.lam).max())
    scale = float(np.abs(X).max())
    early = round(0.2 / s.dt) + 1
    log(f"exact reference: expm cross-check {res.exact_check:.1e}; peak {scale * 1e6:.1f} um")

    def errors(x: NDArray) -> tuple[float, float]:
        d = np.abs(x[:, rows] - X).max(axis=1) / scale
        return float(d.max()), float(d[:early].max())

    # The first calls of a fresh process that allocate ~100 MB histories run 2-3x slower
    # (the kernel assembling transparent huge pages, measured); untimed warm-up calls, as
    # ROSS's numba step is compiled before it is timed.
    for _ in range(WARM_UP):
        run_duhamel(model, duhamel.Semianalytic(), s.dt, s.n_steps, 1)

    cases: list[tuple[str, Any, str, int | None]] = [
        (EXACT_28, duhamel.Semianalytic(), "default; stepping and output on two threads", None),
        (EXACT_28_1T, duhamel.Semianalytic(), "threads=1", 1),
        (EXACT_RED, duhamel.Semianalytic(modes=s.modes), "", None),
        (
            PSEUDO_28,
            duhamel.Semianalytic(tol=0.5, coupling="pseudo-force"),
            "the paper's route; linear step: one Newton iteration suffices",
            None,
        ),
        (
            PSEUDO_RED,
            duhamel.Semianalytic(modes=s.modes, tol=0.5, coupling="pseudo-force"),
            "",
            None,
        ),
        ("duhamel Newmark", duhamel.Newmark(), "average acceleration", None),
    ]
    for name, integrator, note, threads in cases:
        sol, total = run_duhamel(model, integrator, s.dt, s.n_steps, s.repeats, threads=threads)
        if sol.stats.coupling == "exact":
            # x, v are computed in the call; a (which ROSS does not return) on first access
            started = time.perf_counter()
            _ = sol.a
            lazy = time.perf_counter() - started
            note = "; ".join(
                filter(None, [note, f"`a` on first access: {lazy * 1e3:.0f} ms more, not timed"])
            )
        e, e0 = errors(sol.x)
        res.rows.append(Row(name, s.n_steps, total, sol.stats.wall_time, e, e0, note))
        log(f"{name}: {1e6 * total / s.n_steps:.2f} us/step, error {e:.2e} (0.2 s: {e0:.2e})")

    ross_repeats = min(s.repeats, 2)
    w = s.speed
    F4 = model.force(t, model.ross4.ndof, np.arange(model.dofs.n_dof))
    F6 = model.force(t, model.ross6.ndof, model.dofs.ross_index)
    # compile ROSS's numba Newmark step before timing it
    quiet(model.ross4.run_time_response, w, F4[:50], t[:50], method="newmark")
    quiet(model.ross6.run_time_response, w, F6[:50], t[:50], method="newmark")
    for name, rotor, F, method, pick in (
        ("ROSS lsim (default), same 28-dof matrices", model.ross4, F4, "default", None),
        ("ROSS Newmark, same 28-dof matrices", model.ross4, F4, "newmark", None),
        ("ROSS lsim (default), its 42-dof model", model.ross6, F6, "default", model.dofs),
        ("ROSS Newmark, its 42-dof model", model.ross6, F6, "newmark", model.dofs),
    ):
        y, total = run_ross(rotor, w, F, t, method, ross_repeats)
        x = pick.from_ross(y) if pick is not None else y
        e, e0 = errors(x)
        note = (
            "starts from zero acceleration"
            if method == "newmark"
            else "input linear between samples"
        )
        res.rows.append(Row(name, s.n_steps, total, None, e, e0, note))
        log(f"{name}: {1e6 * total / s.n_steps:.2f} us/step, error {e:.2e} (0.2 s: {e0:.2e})")

    # equal accuracy: refine duhamel until it is at least as accurate as each ROSS path
    by_name = {r.name: r for r in res.rows}
    for against in (
        "ROSS Newmark, same 28-dof matrices",
        "ROSS lsim (default), same 28-dof matrices",
    ):
        ross_row = by_name[against]
        for method, integrator, threads in (
            (EXACT_28, duhamel.Semianalytic(), None),
            (EXACT_28_1T, duhamel.Semianalytic(), 1),
            (EXACT_RED, duhamel.Semianalytic(modes=s.modes), None),
            (PSEUDO_28, duhamel.Semianalytic(tol=0.5, coupling="pseudo-force"), None),
            (
                PSEUDO_RED,
                duhamel.Semianalytic(modes=s.modes, tol=0.5, coupling="pseudo-force"),
                None,
            ),
            ("duhamel Newmark", duhamel.Newmark(), None),
        ):
            base = by_name[method]
            k, err, total = 1, base.error, base.total
            while err > ross_row.error:
                nxt = max(k + 1, math.ceil(k * math.sqrt(err / ross_row.error) * 1.05))
                if nxt > MAX_REFINE:
                    k = 0
                    break
                sol, total_k = run_duhamel(
                    model,
                    integrator,
                    s.dt / nxt,
                    s.n_steps * nxt,
                    1,
                    save_every=nxt,
                    threads=threads,
                )
                new_err, _ = errors(sol.x)
                stalled = new_err > 0.9 * err  # no longer falling: an error floor
                k, err, total = nxt, new_err, total_k
                if stalled:  # (modal truncation)
                    k = 0
                    break
            res.matched.append(
                Matched(method, against, ross_row.error, k or None, err, total, ross_row.total)
            )
            log(
                f"matched {method} vs {against}: k = {k or 'none'}, error {err:.2e}, "
                f"{total:.3g} s vs {ross_row.total:.3g} s"
            )


# ------------------------------------------------------------------------------- rub
def contact_force(el: duhamel.elements.Contact, x: float, y: float, vx: float, vy: float):
    """duhamel's Contact law (crates/duhamel-core/src/elements/contact.rs) in Python: the
    restoring force on the shaft centre."""
    rho = math.hypot(x, y)
    if rho < 1e-300:
        return 0.0, 0.0
    eps = el.smoothing
    z = (rho - el.clearance) / eps
    fn = el.stiffness * eps * (max(z, 0.0) + math.log1p(math.exp(-abs(z))))
    vt = (x * vy - y * vx) / rho
    ft = el.friction * fn * math.tanh(vt / el.velocity_smoothing)
    nx, ny = x / rho, y / rho
    return fn * nx - ft * ny, fn * ny + ft * nx


def lagged_newmark(model: Model, dt: float, n_steps: int) -> tuple[NDArray, float]:
    """Average-acceleration Newmark with the contact force of the previous step (ROSS's
    scheme for extra forces), starting from the consistent acceleration."""
    s, el = model.setup, model.contact()
    M, K, D = model.M, model.K, model.C + s.speed * model.G
    n = M.shape[0]
    t = np.arange(n_steps + 1) * dt
    F = model.force(t, n, np.arange(n))
    started = time.perf_counter()
    lu = scipy.linalg.lu_factor(M + 0.5 * dt * D + 0.25 * dt * dt * K)
    x, v = np.zeros(n), np.zeros(n)
    a = np.linalg.solve(M, F[0])
    out = np.empty((n_steps + 1, 2))
    out[0] = 0.0
    ix, iy = model.ix, model.iy
    for k in range(1, n_steps + 1):
        rx, ry = contact_force(el, float(x[ix]), float(x[iy]), float(v[ix]), float(v[iy]))
        xp = x + dt * v + 0.25 * dt * dt * a
        vp = v + 0.5 * dt * a
        rhs = F[k] - D @ vp - K @ xp
        rhs[ix] -= rx
        rhs[iy] -= ry
        a = scipy.linalg.lu_solve(lu, rhs, check_finite=False)
        v = vp + 0.5 * dt * a
        x = xp + 0.25 * dt * dt * a
        out[k] = x[ix], x[iy]
        if not math.isfinite(out[k, 0]) or abs(out[k, 0]) > 1.0:  # blown up (1 m)
            out[k:] = np.nan
            break
    return out, time.perf_counter() - started


def ross_lagged(model: Model, dt: float, n_steps: int) -> tuple[NDArray | None, float]:
    """ROSS's Newmark with the contact force through `add_to_RHS` (previous step's state)."""
    s, el, rotor = model.setup, model.contact(), model.ross4
    ix, iy = model.ix, model.iy
    t = np.arange(n_steps + 1) * dt
    F = model.force(t, rotor.ndof, np.arange(rotor.ndof))

    def extra(step: int, time_step: float = 0.0, disp_resp=None, velc_resp=None, accl_resp=None):
        out = np.zeros(rotor.ndof)
        p, v = disp_resp, velc_resp
        rx, ry = contact_force(el, float(p[ix]), float(p[iy]), float(v[ix]), float(v[iy]))
        out[ix], out[iy] = -rx, -ry
        return out

    started = time.perf_counter()
    try:
        y = quiet(rotor.run_time_response, s.speed, F, t, method="newmark", add_to_RHS=extra).yout
    except Warning:  # ROSS's Newton loop gives up when the response blows up
        return None, time.perf_counter() - started
    return y[:, [ix, iy]], time.perf_counter() - started


def rub(model: Model, res: Results, log: Callable[[str], None]) -> None:
    s = model.setup
    ix, iy = model.ix, model.iy
    ref_dt = min(s.rub_steps) / s.rub_ref_factor
    n_ref = round(s.rub_window / ref_dt)

    def solve(integrator: Any, dt: float, n: int) -> tuple[NDArray, float]:
        system = model.system(rub=True)
        started = time.perf_counter()
        sol = duhamel.solve(system, integrator, t_end=n * dt, dt=dt)
        return sol.x[:, [ix, iy]], time.perf_counter() - started

    ref, _ = solve(duhamel.Semianalytic(), ref_dt, n_ref)
    check, _ = solve(duhamel.Newmark(), ref_dt, n_ref)
    peak = float(np.hypot(ref[:, 0], ref[:, 1]).max())
    res.rub_peak = peak
    res.rub_ref_check = float(np.hypot(*(check - ref).T).max() / peak)
    log(
        f"rub reference: peak {peak * 1e6:.1f} um, Newmark at the same step {res.rub_ref_check:.1e}"
    )

    def error(xy: NDArray | None, dt: float) -> float:
        if xy is None or not np.all(np.isfinite(xy)):
            return float("inf")
        k = round(dt / ref_dt)
        r = ref[::k][: xy.shape[0]]
        return float(np.hypot(*(xy[: r.shape[0]] - r).T).max() / peak)

    methods: list[tuple[str, Callable[[float, int], tuple[NDArray | None, float]], str]] = [
        ("duhamel Semianalytic, 28 modes", lambda dt, n: solve(duhamel.Semianalytic(), dt, n), ""),
        (
            f"duhamel Semianalytic, {s.rub_modes} modes",
            lambda dt, n: solve(duhamel.Semianalytic(modes=s.rub_modes), dt, n),
            "",
        ),
        (
            f"duhamel Semianalytic, {s.modes} modes",
            lambda dt, n: solve(duhamel.Semianalytic(modes=s.modes), dt, n),
            "modal truncation dominates",
        ),
        ("duhamel Newmark (implicit contact)", lambda dt, n: solve(duhamel.Newmark(), dt, n), ""),
        (
            "ROSS Newmark, lagged contact force (add_to_RHS)",
            lambda dt, n: ross_lagged(model, dt, n),
            "ROSS's default for extra forces; starts from zero acceleration",
        ),
        (
            "lagged-force Newmark (numpy, this script)",
            lambda dt, n: lagged_newmark(model, dt, n),
            "same lag, consistent initial acceleration",
        ),
    ]
    zeros = np.zeros((50, model.ross4.ndof))  # compile ROSS's numba step (if not yet)
    quiet(model.ross4.run_time_response, s.speed, zeros, np.arange(50) * s.dt, method="newmark")
    for name, fn, note in methods:
        errs, window_time = {}, math.nan
        for dt in s.rub_steps:
            n = round(s.rub_window / dt)
            xy, elapsed = fn(dt, n)
            errs[dt] = error(xy, dt)
            if dt == s.dt:
                window_time = 1e6 * elapsed / n
        xy, elapsed = fn(s.dt, s.n_steps)  # timing over the full run
        if xy is not None and bool(np.all(np.isfinite(xy))):
            row = RubRow(name, errs, 1e6 * elapsed / s.n_steps, note)
        else:
            why = f"diverged within the {s.t_end:g} s run (time per step from the window run)"
            row = RubRow(name, errs, window_time, f"{note}; {why}" if note else why)
        res.rub.append(row)
        shown = ", ".join(f"{dt:g}: {e:.2e}" for dt, e in errs.items())
        log(f"rub {name}: {row.us_per_step:.1f} us/step; errors {shown}")


# ------------------------------------------------------------------------------- report
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
            ["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True, check=True
        ).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"
    return rev


def verdict(ok: bool) -> str:
    return "**met**" if ok else "**not met**"


def report(res: Results) -> str:
    s = res.setup
    by_name = {r.name: r for r in res.rows}
    kind = "quick smoke run" if res.quick else "full run"
    span = f"{s.t_end:g} s"
    lines = [
        "# Rotor benchmark: ROSS's example rotor, duhamel vs ROSS",
        "",
        f"Generated by `python benchmarks/rotor.py` ({kind}); see the script's docstring for "
        "the set-up. One run, one machine:",
        "",
        "| | |",
        "|---|---|",
        f"| date (UTC) | {datetime.datetime.now(datetime.UTC).strftime('%Y-%m-%d %H:%M')} |",
        f"| machine | {cpu_model()}, {os.cpu_count()} logical cores, {platform.platform()} |",
        f"| Python / numpy / scipy | {platform.python_version()} / {np.__version__} / "
        f"{scipy.__version__} |",
        f"| ROSS | {res.versions.get('ross', '?')} |",
        f"| duhamel | {duhamel.__version__} (git {git_revision()}) |",
        f"| 1-min load average | before {res.load[0]:.2f}, after {res.load[1]:.2f} |",
        "",
        "## Linear: unbalance response",
        "",
        f"`ross.rotor_example()` at {s.speed:g} rad/s (28 lateral dofs; natural frequencies "
        f"up to {res.omega_max:.3g} rad/s, so `omega_max dt` = {res.omega_max * s.dt:.2g}), "
        f"unbalance {s.m_e:g} kg m at node {s.node} from rest, {s.n_steps} steps of "
        f"{s.dt * 1e3:g} ms. Error: largest translational difference from the exact solution "
        f"(expm cross-check {res.exact_check:.0e}) over all {s.n_steps} steps, and over the "
        "first 0.2 s, relative to the largest translation. Times: the whole call, best of "
        f"{s.repeats} (duhamel) or {min(s.repeats, 2)} (ROSS), after {WARM_UP} untimed "
        "duhamel calls (the first calls of a process that allocate ~100 MB of history run 2-3x "
        "slower while the kernel assembles huge pages) and ROSS's numba compilation.",
        "",
        f"| method | us/step | total [s] | duhamel loop [s] | error, {span} | error, 0.2 s "
        "| notes |",
        "|---|---:|---:|---:|---:|---:|---|",
    ]
    for r in res.rows:
        loop = f"{r.loop:.3g}" if r.loop is not None else ""
        lines.append(
            f"| {r.name} | {r.us_per_step:.2f} | {r.total:.3g} | {loop} | {r.error:.2e} "
            f"| {r.error_early:.2e} | {r.note} |"
        )
    lines += [
        "",
        "At equal or better accuracy: each duhamel method rerun at `dt/k` (the smallest `k` "
        "found, by the second-order rate, that reaches the ROSS path's error over "
        f"{span}; `k` up to {MAX_REFINE}), timed over the same {span}.",
        "",
        "| duhamel method | vs ROSS path | ROSS error | k | duhamel error | duhamel [s] "
        "| ROSS [s] | speed-up |",
        "|---|---|---:|---:|---:|---:|---:|---:|",
    ]
    for m in res.matched:
        k = str(m.k) if m.k else f"none <= {MAX_REFINE}"
        speedup = f"{m.speedup:.2f}x" if m.k else "—"
        lines.append(
            f"| {m.method} | {m.against} | {m.target_error:.2e} | {k} | {m.error:.2e} "
            f"| {m.total:.3g} | {m.ross_total:.3g} | {speedup} |"
        )
    best: dict[str, float] = {}
    for m in res.matched:
        if m.k:
            best[m.against] = max(best.get(m.against, 0.0), m.speedup)
    nm = best.get("ROSS Newmark, same 28-dof matrices", float("nan"))
    ls = best.get("ROSS lsim (default), same 28-dof matrices", float("nan"))
    exact = by_name[EXACT_28]
    same_dt_nm = by_name["ROSS Newmark, same 28-dof matrices"].total / exact.total
    same_dt_ls = by_name["ROSS lsim (default), same 28-dof matrices"].total / exact.total
    lines += [
        "",
        f"* Target >= {NEWMARK_TARGET:g}x faster than ROSS's Newmark path at equal or better "
        f"accuracy: best {nm:.2f}x — {verdict(nm >= NEWMARK_TARGET)}.",
        f"* Target >= {LSIM_TARGET:g}x faster than ROSS's lsim path at equal or better accuracy: "
        f"best {ls:.2f}x — {verdict(ls >= LSIM_TARGET)}.",
        f"* At the same step, the default Semianalytic (all 28 modes, exact coupling, error "
        f"{exact.error:.1e}) vs ROSS: {same_dt_nm:.1f}x the speed of its Newmark, "
        f"{same_dt_ls:.1f}x that of its lsim. Its time includes the modal analysis, the "
        "first-order eigen-decomposition and `x`, `v` of all 28 dofs at every step (ROSS "
        "returns displacements and states); the accelerations are computed when first "
        "accessed (the notes give that time).",
        "",
        "## Rub at the disk",
        "",
        f"Contact at node {s.node}: clearance {s.clearance * 1e6:g} um, stiffness "
        f"{s.contact_stiffness:g} N/m, friction {s.friction:g}; same unbalance. Error over the "
        f"first {s.rub_window:g} s: largest distance of the disk centre from the reference "
        f"(Semianalytic at dt = {min(s.rub_steps) / s.rub_ref_factor:.3g} s; Newmark at that "
        f"step differs by {res.rub_ref_check:.1e}), relative to the reference's largest "
        f"radial displacement ({res.rub_peak * 1e6:.1f} um). Time per step over "
        f"{s.n_steps} steps of {s.dt * 1e3:g} ms (whole call).",
        "",
        "| method | us/step | "
        + " | ".join(f"error, dt = {dt * 1e3:g} ms" for dt in s.rub_steps)
        + " | notes |",
        "|---|---:|" + "---:|" * len(s.rub_steps) + "---|",
    ]
    for r in res.rub:
        errs = " | ".join("diverged" if math.isinf(e) else f"{e:.2e}" for e in r.errors.values())
        lines.append(f"| {r.name} | {r.us_per_step:.1f} | {errs} | {r.note.strip('; ')} |")
    rub_rows = {r.name: r for r in res.rub}
    sa = rub_rows["duhamel Semianalytic, 28 modes"].errors[s.dt]
    lag_ross = rub_rows["ROSS Newmark, lagged contact force (add_to_RHS)"].errors[s.dt]
    lag_np = rub_rows["lagged-force Newmark (numpy, this script)"].errors[s.dt]
    ratio_ross, ratio_np = lag_ross / sa, lag_np / sa
    lines += [
        "",
        f"* Target: error at least {RUB_TARGET:g}x smaller than ROSS's lagged-force Newmark at "
        f"the same step (dt = {s.dt * 1e3:g} ms): {ratio_ross:.3g}x — "
        f"{verdict(ratio_ross >= RUB_TARGET)} (against the lagged scheme with a consistent "
        f"start: {ratio_np:.3g}x).",
        "",
    ]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--write", metavar="MD", help="write the markdown report here")
    parser.add_argument(
        "--append",
        metavar="MD",
        help="append the report as a section of this file (make bench: BENCHMARKS.md)",
    )
    parser.add_argument("--quick", action="store_true", help="smoke test: 2000 steps")
    parser.add_argument("--steps", type=int, default=None)
    parser.add_argument("--repeats", type=int, default=None)
    args = parser.parse_args(argv)
    setup = Setup()
    if args.quick:
        setup = Setup(n_steps=2000, repeats=1, rub_window=0.02, rub_ref_factor=4)
    if args.steps:
        setup = Setup(**{**setup.__dict__, "n_steps": args.steps})
    if args.repeats:
        setup = Setup(**{**setup.__dict__, "repeats": args.repeats})
    ross = import_ross()
    res = Results(setup=setup, quick=args.quick, versions={"ross": ross.__version__})
    res.load = (loadavg(), float("nan"))

    def log(msg: str) -> None:
        print(msg, flush=True)

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        model = Model(ross, setup)
        linear(model, res, log)
        rub(model, res, log)
    res.load = (res.load[0], loadavg())
    text = report(res)
    print()
    print(text)
    if args.write:
        Path(args.write).write_text(text)
        print(f"wrote {args.write}")
    if args.append:
        section = text.replace("# Rotor benchmark", "## Rotor benchmark", 1)
        with Path(args.append).open("a") as f:
            f.write("\n\n" + section + "\n")
        print(f"appended to {args.append}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

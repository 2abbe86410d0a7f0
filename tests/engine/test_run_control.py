"""Runs that can be interrupted, watched and continued, on every route.

* Every failure names the step the engine could not complete, on every route (uncoupled,
  first-order, pseudo-force, direct) and for every kind (divergence, Newton, callback).
* Ctrl-C (a real SIGINT, in a subprocess) stops a long run within 0.5 s with the history
  computed so far.
* ``progress`` reports between blocks; ``t0`` continues a run from its last state, and two
  chained runs give what one run gives, to round-off.
"""

from __future__ import annotations

import itertools
import json
import signal
import subprocess
import sys
import textwrap

import numpy as np
import pytest
from _callbacks import callback_failure

import duhamel
from duhamel import elements as E
from duhamel import loads as L

# --------------------------------------------------------------------------------------------
# Models, one per route
# --------------------------------------------------------------------------------------------

K3 = 2e4 * (np.diag([2.0, 2.0, 1.0]) - np.diag([1.0, 1.0], 1) - np.diag([1.0, 1.0], -1))
GYRO = np.array([[0.0, 30.0, 0.0], [-30.0, 0.0, 0.0], [0.0, 0.0, 0.0]])

ROUTES = {
    "uncoupled": (lambda s: s, duhamel.Semianalytic()),
    "first-order": (lambda s: s.add(E.LinearCoupling(C=GYRO)), duhamel.Semianalytic()),
    "pseudo-force": (
        lambda s: s.add(E.LinearCoupling(C=GYRO)),
        duhamel.Semianalytic(coupling="pseudo-force"),
    ),
    "direct": (lambda s: s, duhamel.Newmark()),
}


def chain(route: str, zeta: float = 0.02) -> tuple[duhamel.System, object]:
    make, integrator = ROUTES[route]
    system = make(duhamel.System(np.eye(3), K3, zeta=zeta))
    return system, integrator


def route_of(sol: duhamel.Solution) -> str:
    if sol.modal is None:
        return "direct"
    return {None: "uncoupled", "exact": "first-order", "pseudo-force": "pseudo-force"}[
        sol.stats.coupling
    ]


@pytest.mark.parametrize("route", list(ROUTES))
def test_models_take_their_route(route):
    system, integrator = chain(route)
    sol = duhamel.solve(system, integrator, t_end=0.1, dt=0.01, x0=[1e-3, 0, 0])
    assert route_of(sol) == route


# --------------------------------------------------------------------------------------------
# The failing step, from the engine, on every route and for every kind
# --------------------------------------------------------------------------------------------

T0, DT = 0.25, 0.01


@pytest.mark.parametrize("route", list(ROUTES))
def test_divergence_names_its_step(route):
    # Negative damping: the state overflows; the error names the step whose end state is
    # not finite, and the partial history ends on the step before it.
    system, integrator = chain(route, zeta=-0.5)
    if route == "direct":
        system = duhamel.System(np.eye(3), K3, C=-0.5 * np.sqrt(2e4) * np.eye(3))
    with pytest.raises(duhamel.SolverError) as info:
        duhamel.solve(system, integrator, t0=T0, t_end=T0 + 1e4, dt=DT, x0=[1e-3, 0, 0])
    err = info.value
    assert err.reason == "nonfinite"
    assert isinstance(err.step, int) and err.step > 100
    assert err.time == pytest.approx(T0 + err.step * DT, rel=1e-12)
    part = err.partial
    assert part.stats.steps == err.step - 1
    assert part.t[-1] <= T0 + (err.step - 1) * DT + 1e-9
    assert np.all(np.isfinite(part.x)) and np.all(np.isfinite(part.v))
    assert f"(step {err.step})" in str(err)


NEWTON_ROUTES = {
    "first-order": duhamel.Semianalytic(max_iter=1),
    "pseudo-force": duhamel.Semianalytic(
        coupling="pseudo-force", max_iter=1, solver="newton", subdivisions=0
    ),
    "direct": duhamel.Newmark(max_iter=1),
}


@pytest.mark.parametrize("route", list(NEWTON_ROUTES))
def test_newton_failure_names_its_step(route):
    # At rest until a step load at t = T0 + 5.5 dt: the cubic spring is idle (every step
    # equation converges at once) until the sixth step, which one Newton iteration cannot
    # solve.
    system = duhamel.System(np.eye(3), K3, zeta=0.02)
    system.add(E.LinearCoupling(C=GYRO)).add(E.Spring(2, None, k=0.0, k3=1e12))
    system.add_load(L.Step(2, amplitude=1e3, t0=T0 + 5.5 * DT))
    with pytest.raises(duhamel.SolverError) as info:
        duhamel.solve(system, NEWTON_ROUTES[route], t0=T0, t_end=T0 + 1.0, dt=DT)
    err = info.value
    assert err.reason == "convergence"
    assert err.step == 6
    assert err.time == pytest.approx(T0 + 6 * DT, rel=1e-12)
    assert err.partial.t[-1] == pytest.approx(T0 + 5 * DT, rel=1e-12)
    assert err.partial.stats.steps == 5


CALLBACKS = [(r, "load") for r in ROUTES] + [
    # an element takes the uncoupled model off its route: the other three
    (r, "element")
    for r in ROUTES
    if r != "uncoupled"
]


@pytest.mark.parametrize(("route", "source"), CALLBACKS)
def test_callback_exception_names_its_step(route, source):
    # The function raises from t = T0 + 0.4 on (first asked for at grid point 40): step 40
    # is the first that needs it; the user's exception comes back with the step noted and
    # the states before it kept.
    def broken(*args):
        t = args[-1]
        if t > T0 + 0.395:
            raise ZeroDivisionError("sensor failed")
        return np.zeros(3 if source == "load" else 1)

    system, integrator = chain(route)
    if source == "load":
        system.add_load(L.Callable(broken))
    else:
        system.add(E.Callable([0], broken))
    with callback_failure(ZeroDivisionError, "sensor failed") as info:
        duhamel.solve(system, integrator, t0=T0, t_end=T0 + 1.0, dt=DT, x0=[1e-3, 0, 0])
    assert info.value.step == 40 and "(step 40)" in str(info.value)
    part = info.value.partial
    assert part.t[-1] == pytest.approx(T0 + 39 * DT, rel=1e-12)
    assert part.stats.steps == 39


# --------------------------------------------------------------------------------------------
# Ctrl-C: a real SIGINT in a subprocess
# --------------------------------------------------------------------------------------------

SIGINT_SCRIPT = textwrap.dedent(
    """
    import json, os, signal, sys, threading, time
    # Ctrl-C raises KeyboardInterrupt here however the test run was launched: a background
    # job of a non-interactive shell (`make test &`) starts with SIGINT ignored, and a child
    # inherits that disposition (Python installs its handler only over the default one).
    signal.signal(signal.SIGINT, signal.default_int_handler)
    import numpy as np
    import duhamel
    from duhamel import elements as E, loads as L

    route = sys.argv[1]
    n = 100 if route == "uncoupled" else 12
    k = 1e4 * (2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1))
    system = duhamel.System(np.eye(n), k, zeta=0.02)
    system.add_load(L.Harmonic(n - 1, 1.0, 30.0))
    integrator = duhamel.Semianalytic()
    if route == "first-order":
        g = np.zeros((n, n)); g[0, 1], g[1, 0] = 5.0, -5.0
        system.add(E.LinearCoupling(C=g))
    elif route == "pseudo-force":
        system.add(E.Cubic(n - 1, 1e6))
    elif route == "direct":
        integrator = duhamel.Newmark()
    # Sized to take about 20 s on the development machine.
    steps = {"uncoupled": 1.5e8, "first-order": 2.2e8, "pseudo-force": 1e7, "direct": 2e7}[route]
    sent = {}

    def interrupt():
        sent["t"] = time.perf_counter()
        os.kill(os.getpid(), signal.SIGINT)

    threading.Timer(1.0, interrupt).start()
    start = time.perf_counter()
    try:
        duhamel.solve(system, integrator, t_end=steps * 1e-4, dt=1e-4, save_every=10_000,
                      dofs=[n - 1])
        out = {"raised": None}
    except KeyboardInterrupt as exc:
        now = time.perf_counter()
        part = exc.partial
        out = {
            "raised": type(exc).__name__,
            "after_signal": now - sent["t"],
            "total": now - start,
            "rows": int(part.t.size),
            "t_last": float(part.t[-1]),
            "finite": bool(np.all(np.isfinite(part.x))),
            "steps": int(part.stats.steps),
        }
    print(json.dumps(out))
    """
)


def _ignore_sigint() -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)


@pytest.mark.parametrize("route", list(ROUTES))
def test_ctrl_c_stops_a_long_run_with_its_history(route, ignored=False):
    proc = subprocess.run(
        [sys.executable, "-c", SIGINT_SCRIPT, route],
        capture_output=True,
        text=True,
        timeout=120,
        preexec_fn=_ignore_sigint if ignored else None,
    )
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout.strip().splitlines()[-1])
    print(f"\n{route}: {out}")
    assert out["raised"] == "KeyboardInterrupt"
    assert out["after_signal"] < 0.5
    assert out["total"] < 5.0
    assert out["rows"] >= 1 and out["finite"]
    # The history kept reaches the step the run stopped at (every 10,000th step is saved:
    # every 1.0 of simulated time).
    reached = out["steps"] * 1e-4
    assert reached - 1.0 - 1e-9 <= out["t_last"] <= reached + 1e-9


def test_ctrl_c_reaches_a_child_started_with_sigint_ignored():
    """A test run launched as a background job (`make test &` in a non-interactive shell)
    starts with SIGINT ignored and its children inherit that: the child scripts install
    Python's handler themselves (issue 38; before, the signal never arrived)."""
    test_ctrl_c_stops_a_long_run_with_its_history("uncoupled", ignored=True)


# --------------------------------------------------------------------------------------------
# progress
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("route", list(ROUTES))
def test_progress_reports_between_blocks(route):
    system, integrator = chain(route)
    system.add_load(L.Harmonic(2, amplitude=1.0, omega=30.0))
    calls = []
    n_steps = 5000
    duhamel.solve(
        system,
        integrator,
        t0=1.0,
        t_end=1.0 + n_steps * 1e-3,
        dt=1e-3,
        progress=lambda step, total, t: calls.append((step, total, t)),
    )
    steps = [c[0] for c in calls]
    assert steps[0] == 0 and steps[-1] == n_steps
    assert all(b >= a for a, b in itertools.pairwise(steps))
    assert all(c[1] == n_steps for c in calls)
    assert all(c[2] == pytest.approx(1.0 + c[0] * 1e-3) for c in calls)
    # Between blocks, not per step.
    assert len(calls) < n_steps / 10


def test_progress_bar_and_bad_progress():
    system, integrator = chain("uncoupled")
    sol = duhamel.solve(system, integrator, t_end=1.0, dt=1e-3, progress=True)
    assert sol.t.size == 1001
    with pytest.raises(TypeError, match="`progress`"):
        duhamel.solve(system, integrator, t_end=1.0, dt=1e-3, progress="yes")


def test_an_exception_in_progress_stops_the_run_with_its_history():
    system, integrator = chain("uncoupled")

    def progress(step, total, t):
        if step > 100:
            raise RuntimeError("enough")

    with pytest.raises(RuntimeError, match="enough") as info:
        duhamel.solve(system, integrator, t_end=100.0, dt=1e-3, progress=progress)
    part = info.value.partial
    assert 100 < part.stats.steps < 100_000
    assert part.t[-1] == pytest.approx(part.stats.steps * 1e-3)


# --------------------------------------------------------------------------------------------
# t0: two chained runs equal one run, to round-off
# --------------------------------------------------------------------------------------------

CHAIN_ROUTES = {
    **ROUTES,
    "pseudo-force (cubic)": (
        lambda s: s.add(E.Spring(2, None, k=0.0, k3=1e9)),
        duhamel.Semianalytic(),
    ),
    "direct (Hermite)": (lambda s: s, duhamel.CubicHermite()),
    "direct (Newmark, cubic)": (
        lambda s: s.add(E.Spring(2, None, k=0.0, k3=1e9)),
        duhamel.Newmark(tol=1e-14),
    ),
}


@pytest.mark.parametrize("route", list(CHAIN_ROUTES))
def test_two_chained_runs_equal_one(route):
    make, integrator = CHAIN_ROUTES[route]
    system = make(duhamel.System(np.eye(3), K3, zeta=0.02))
    system.add_load(L.Harmonic(2, amplitude=50.0, omega=30.0)).add_load(
        L.Step(1, amplitude=20.0, t0=0.3123)
    )
    run = dict(dt=1e-3)
    x0 = np.array([1e-3, 0.0, -2e-3])
    one = duhamel.solve(system, integrator, t0=0.1, t_end=0.7, x0=x0, **run)
    first = duhamel.solve(system, integrator, t0=0.1, t_end=0.4, x0=x0, **run)
    second = duhamel.solve(
        system, integrator, t0=first.t[-1], t_end=0.7, x0=first.x[-1], v0=first.v[-1], **run
    )
    assert one.t[0] == 0.1 and second.t[0] == pytest.approx(0.4, abs=1e-15)
    np.testing.assert_allclose(second.t, one.t[300:], rtol=0, atol=1e-15)
    scale = np.abs(one.x).max()
    err = np.abs(second.x - one.x[300:]).max() / scale
    print(f"\n{route}: chained vs one run, max |dx| / max |x| = {err:.1e}")
    assert err < 1e-11
    assert np.abs(second.a - one.a[300:]).max() / np.abs(one.a).max() < 1e-9


def test_loads_keep_their_absolute_time():
    # A run from t0 sees the loads a run from 0 sees at the same times.
    system, integrator = chain("uncoupled")
    system.add_load(L.Step(2, amplitude=1.0, t0=2.05))
    late = duhamel.solve(system, integrator, t0=2.0, t_end=2.2, dt=0.01)
    assert np.all(late.x[:5] == 0.0) and np.abs(late.x[-1]).max() > 0.0
    assert late.modal.p[5, :].any() and not late.modal.p[4, :].any()


def test_t0_is_checked():
    system, integrator = chain("uncoupled")
    with pytest.raises(ValueError, match="`t_end`"):
        duhamel.solve(system, integrator, t0=1.0, t_end=1.0, dt=0.1)
    with pytest.raises(ValueError, match="`t0`"):
        duhamel.solve(system, integrator, t0=float("nan"), t_end=1.0, dt=0.1)

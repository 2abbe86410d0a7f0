"""Events located inside the steps: against closed forms and an independent matrix
exponential on the linear routes, consistently as dt shrinks on a Gap (nonlinear)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import expm
from scipy.optimize import brentq

import duhamel
from duhamel import events

W, Z, F = 2.0 * np.pi, 0.05, 3.0
WD = W * np.sqrt(1.0 - Z**2)


def _step_response(t: float) -> tuple[float, float]:
    """x, v of m=1, k=W^2, zeta=Z under the step F from rest at t=0 (closed form)."""
    e = np.exp(-Z * W * t)
    x = F / W**2 * (1.0 - e * (np.cos(WD * t) + Z * W / WD * np.sin(WD * t)))
    v = F / W**2 * e * (W**2 / WD) * np.sin(WD * t)
    return x, v


def _sdof() -> duhamel.System:
    return duhamel.System(np.eye(1), W**2 * np.eye(1), zeta=Z)


@pytest.mark.parametrize("dt", [0.05, 0.0137])
def test_step_load_first_crossing_and_terminal_state(dt: float) -> None:
    system = _sdof()
    system.add_load(duhamel.loads.Step(dof=0, amplitude=F))
    level = 1.5 * F / W**2  # reached on the first overshoot
    t_ref = brentq(lambda t: _step_response(t)[0] - level, 0.0, np.pi / WD, xtol=1e-15)
    ev = events.threshold(0, level, direction=1, terminal=True, name="up")
    sol = duhamel.solve(system, duhamel.Semianalytic(), t_end=3.0, dt=dt, events=[ev])
    (occ,) = sol.events
    assert occ.name == "up" and occ.index == 0 and occ.terminal
    assert abs(occ.time - t_ref) < 1e-10
    assert sol.t[-1] == occ.time and np.all(np.diff(sol.t) > 0)
    x_ref, v_ref = _step_response(occ.time)
    assert abs(sol.x[-1, 0] - x_ref) <= 1e-12 * abs(x_ref)
    assert abs(sol.v[-1, 0] - v_ref) <= 1e-12 * abs(v_ref)
    np.testing.assert_array_equal(sol.x[-1], occ.x)
    assert sol.modal.q.shape[0] == sol.t.size == sol.x.shape[0] == sol.a.shape[0]
    # Without `terminal` every crossing of the level, both ways, in time order.
    both = events.threshold(0, level)
    full = duhamel.solve(system, duhamel.Semianalytic(), t_end=3.0, dt=dt, events=[both])
    times = [o.time for o in full.events]
    assert len(times) >= 2 and times == sorted(times) and abs(times[0] - t_ref) < 1e-10
    t2 = brentq(lambda t: _step_response(t)[0] - level, t_ref + 1e-6, np.pi / WD + 0.3)
    assert abs(times[1] - t2) < 1e-10


def _exact_record(tr: np.ndarray, fr: np.ndarray, t: float) -> np.ndarray:
    """State (x, v) at `t` under the piecewise-linear force (tr, fr), by the matrix
    exponential of the system augmented with the force and its slope on each segment."""
    a = np.array([[0.0, 1.0, 0.0, 0.0], [-(W**2), -2 * Z * W, 1.0, 0.0],
                  [0.0, 0.0, 0.0, 1.0], [0.0, 0.0, 0.0, 0.0]])  # fmt: skip
    y = np.zeros(2)
    k = 0
    while tr[k + 1] < t:
        slope = (fr[k + 1] - fr[k]) / (tr[k + 1] - tr[k])
        y = (expm(a * (tr[k + 1] - tr[k])) @ np.array([*y, fr[k], slope]))[:2]
        k += 1
    slope = (fr[k + 1] - fr[k]) / (tr[k + 1] - tr[k])
    return (expm(a * (t - tr[k])) @ np.array([*y, fr[k], slope]))[:2]


def test_record_first_crossing_against_the_matrix_exponential() -> None:
    rng = np.random.default_rng(7)
    dt = 0.02
    tr = np.arange(0.0, 2.0 + dt / 2, dt)
    fr = 20.0 * rng.standard_normal(tr.size)
    system = _sdof()
    system.add_load(duhamel.loads.Tabulated(0, t=tr, values=fr))
    sol = duhamel.solve(system, duhamel.Semianalytic(), t_end=2.0, dt=dt, dense=True)
    level = 0.6 * np.abs(sol.x[:, 0]).max()
    rows = np.flatnonzero(np.abs(sol.x[:, 0]) >= level)
    n = rows[0] - 1  # the step of the first crossing of |x| = level
    sign = np.sign(sol.x[rows[0], 0])
    t_ref = brentq(lambda t: sign * _exact_record(tr, fr, t)[0] - level, sol.t[n],
                   sol.t[n + 1], xtol=1e-15)  # fmt: skip
    ev = events.drift(0, None, level, direction=1, terminal=True)
    stop = duhamel.solve(system, duhamel.Semianalytic(), t_end=2.0, dt=dt, events=[ev])
    assert abs(stop.t[-1] - t_ref) < 1e-10
    state = _exact_record(tr, fr, stop.t[-1])
    np.testing.assert_allclose([stop.x[-1, 0], stop.v[-1, 0]], state, rtol=1e-12)


def test_python_events_plain_and_vectorized_agree() -> None:
    system = _sdof()
    sol = duhamel.solve(system, duhamel.Semianalytic(), t_end=2.0, dt=0.03, x0=[1.0],
                        events=[duhamel.Event(lambda t, x, v: v[0], direction=1),
                                duhamel.Event(lambda t, x, v: v[:, 0], direction=1,
                                              vectorized=True, name="vec")])  # fmt: skip
    plain = [o.time for o in sol.events if o.index == 0]
    vec = [o.time for o in sol.events if o.index == 1]
    # Minima of a free decay: v = 0 going up at t = k * 2 pi / WD.
    minima = np.pi / WD * (2 * np.arange(1, len(plain) + 1) - 1)
    np.testing.assert_allclose(plain, minima, rtol=0, atol=1e-10)
    np.testing.assert_allclose(plain, vec, rtol=0, atol=1e-12)
    with pytest.raises(ValueError, match="direction"):
        duhamel.Event(lambda t, x, v: 0.0, direction=2)
    with pytest.raises(ValueError, match="dof"):
        duhamel.solve(system, duhamel.Semianalytic(), t_end=1.0, dt=0.1,
                      events=[events.threshold(3, 0.0)])  # fmt: skip


def _gap_closings(dt: float) -> list[float]:
    """The instants the stop closes (deformation reaching -gap from above) of a mass bouncing
    between a stop and its spring, under a step load."""
    system = duhamel.System(np.eye(1), W**2 * np.eye(1), zeta=0.02)
    system.add(duhamel.elements.Gap(0, None, gap=0.05, k=4.0 * W**2))
    system.add_load(duhamel.loads.Harmonic(dof=0, amplitude=-8.0, omega=5.0))
    ev = events.element(0, "deformation", -0.05, direction=-1)
    sol = duhamel.solve(system, duhamel.Semianalytic(), t_end=3.0, dt=dt, events=[ev])
    return [o.time for o in sol.events]


def test_gap_closing_located_consistently_as_dt_shrinks() -> None:
    """The closings after the first contact depend on the nonlinear steps: against a run at
    a 64 times smaller step they converge at about the scheme's second order (the contact's
    kink inside a step makes the error irregular; the least-squares slope is measured)."""
    steps = np.array([0.004, 0.002, 0.001, 0.0005])
    ref = np.array(_gap_closings(0.0000625))
    assert ref.size >= 3
    errors = np.array([np.abs(np.array(_gap_closings(dt))[:3] - ref[:3]) for dt in steps])
    assert np.all(np.diff(errors, axis=0) < 0), errors  # every closing, every halving
    for j in (1, 2):  # the closings after a contact
        slope = np.polyfit(np.log(steps), np.log(errors[:, j]), 1)[0]
        assert slope > 1.6, (j, errors[:, j], slope)


def _stopping_model(route: str) -> duhamel.System:
    m, k = 1e5 * np.eye(2), 4e7 * np.array([[1.0, -1.0], [-1.0, 1.0]])
    if route == "first-order":
        s = duhamel.System(m, k, np.array([[3e5, -1e5], [-1e5, 2e4]]))
    else:
        s = duhamel.System(m, k, zeta=0.05)
    if route == "elements":
        s.add(duhamel.elements.Bilinear(0, None, k=4e7, fy=1.2e6, alpha=0.05))
    t = np.arange(0.0, 40.0, 0.01)
    ramp = np.sin(3 * t) * np.minimum(t / 20.0, 1.0) * 5.0
    return s.add_load(duhamel.loads.Tabulated(1, t=t, values=1e5 * ramp))


@pytest.mark.parametrize("route", ["uncoupled", "first-order", "elements"])
def test_terminal_event_stops_the_work(route: str) -> None:
    """A terminal event stops the run itself: the steps after it are not taken (the run's
    stats count far fewer than a full run's), and what is returned equals, bit for bit, the
    rows, events and located state of the same run with the event not terminal."""
    prep = duhamel.prepare(_stopping_model(route), duhamel.Semianalytic(), dt=0.002)
    assert prep.route == {"elements": "pseudo-force"}.get(route, route)
    level = 0.6 * np.abs(prep.run(t_end=40.0).x[:, 1]).max()  # reached as the load grows
    watch = [events.threshold(1, level), events.threshold(0, 0.3 * level)]
    full = prep.run(t_end=40.0, events=watch)
    assert full.stats.steps == 20000
    crossing = next(o for o in full.events if o.index == 0)
    assert 5.0 < crossing.time < 30.0  # not in the run's first chunk, nor its last
    stop = [events.threshold(1, level, terminal=True), watch[1]]
    sol = prep.run(t_end=40.0, events=stop, dense=True)
    assert sol.stats.steps < crossing.time / 0.002 + 20000 / 16
    assert sol.stats.steps < 0.8 * full.stats.steps
    n = sol.t.size - 1
    assert sol.t[n] == crossing.time
    for name in ("t", "x", "v", "a"):
        np.testing.assert_array_equal(getattr(sol, name)[:n], getattr(full, name)[:n])
    np.testing.assert_array_equal(sol.x[n], crossing.x)
    np.testing.assert_array_equal(sol.v[n], crossing.v)
    kept = [(o.index, o.time) for o in full.events if o.time <= crossing.time]
    assert [(o.index, o.time) for o in sol.events] == kept
    for mine, theirs in zip(sol.elements, full.elements, strict=True):
        np.testing.assert_array_equal(mine.force[:n], theirs.force[:n])
    inside = 0.5 * (sol.t[n - 2] + sol.t[n - 1])
    again = prep.run(t_end=40.0, events=watch, dense=True)
    inside = 0.5 * (sol.t[n - 2] + sol.t[n - 1])
    np.testing.assert_array_equal(sol.at(inside)[0], again.at(inside)[0])

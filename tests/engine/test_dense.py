"""Dense output: the response between the steps (``t_eval``, ``Solution.at``), exact on the
linear routes against scipy.signal.lsim (first-order hold), of the scheme's order on a
nonlinear model against solve_ivp."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import signal
from scipy.integrate import solve_ivp
from scipy.linalg import eigh

import duhamel

DT = 0.02


def _record(t_end: float, seed: int = 3) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, t_end + DT / 2, DT)
    return t, rng.standard_normal(t.size)


def _frame(c: np.ndarray | None = None) -> duhamel.System:
    m = np.diag([1.0, 1.5])
    k = np.array([[300.0, -120.0], [-120.0, 120.0]])
    return duhamel.System(m, k, zeta=0.03) if c is None else duhamel.System(m, k, c)


def matrices(system: duhamel.System, zeta: float = 0.03) -> tuple[np.ndarray, ...]:
    """M, C, K; C of modal damping `zeta` when the system has none."""
    m, k = np.asarray(system.M, dtype=float), np.asarray(system.K, dtype=float)
    if system.C is not None:
        return m, np.asarray(system.C, dtype=float), k
    w2, phi = eigh(k, m)
    c = m @ phi @ np.diag(2.0 * zeta * np.sqrt(w2)) @ phi.T @ m
    return m, c, k


def _lsim(system: duhamel.System, f: np.ndarray, tr: np.ndarray, fr: np.ndarray,
          t_fine: np.ndarray) -> np.ndarray:  # fmt: skip
    """lsim (linear interpolation of the input between its samples) on `t_fine`."""
    m, c, k = matrices(system)
    n = m.shape[0]
    minv = np.linalg.inv(m)
    a = np.block([[np.zeros((n, n)), np.eye(n)], [-minv @ k, -minv @ c]])
    b = np.concatenate([np.zeros((n, 1)), minv @ f[:, None]])
    sys = signal.StateSpace(a, b, np.eye(2 * n), np.zeros((2 * n, 1)))
    u = np.interp(t_fine, tr, fr)
    _, _, y = signal.lsim(sys, u, t_fine, interp=True)
    return y


@pytest.mark.parametrize("route", ["uncoupled", "first-order"])
def test_t_eval_equals_lsim_off_grid(route: str) -> None:
    """t_eval at instants inside the steps equals lsim (first-order hold) to 1e-12 of the
    response's size, on both linear routes."""
    c = None if route == "uncoupled" else np.array([[3.0, -1.0], [-1.0, 0.5]])
    system = _frame(c)
    f = np.array([0.0, 1.0])
    tr, fr = _record(2.0)
    system.add_load(duhamel.loads.Tabulated(1, t=tr, values=fr))
    fine = 8
    t_fine = np.arange(0.0, 2.0 * fine / DT + 0.5) * (DT / fine)
    y = _lsim(system, f, tr, fr, t_fine)
    pick = np.arange(3, t_fine.size - 1, 5)  # mostly off the run's grid
    pick = pick[pick % fine != 0]
    sol = duhamel.solve(system, duhamel.Semianalytic(), t_end=2.0, dt=DT, t_eval=t_fine[pick])
    prep = duhamel.prepare(system, duhamel.Semianalytic(), dt=DT)
    assert prep.route == route
    scale = np.abs(y).max(axis=0)
    assert np.abs(sol.x - y[pick, :2]).max() <= 1e-12 * scale[:2].max()
    assert np.abs(sol.v - y[pick, 2:]).max() <= 1e-12 * scale[2:].max()
    np.testing.assert_array_equal(sol.t, t_fine[pick])
    # The accelerations there are the equations of motion's.
    m, cc, k = matrices(system)
    load = np.outer(np.interp(sol.t, tr, fr), f)
    a_ref = np.linalg.solve(m, (load - sol.x @ k.T - sol.v @ cc.T).T).T
    assert np.abs(sol.a - a_ref).max() <= 1e-9 * np.abs(a_ref).max()


def test_at_matches_t_eval_and_grid() -> None:
    system = _frame()
    system.add_load(duhamel.loads.Step(dof=1, amplitude=2.0))
    sol = duhamel.solve(system, duhamel.Semianalytic(), t_end=1.0, dt=DT, dense=True)
    x, v = sol.at(sol.t[7])
    np.testing.assert_array_equal(v, sol.v[7])
    np.testing.assert_array_equal(x, sol.x[7])
    times = np.array([0.011, 0.5, 0.733])
    xs, vs = sol.at(times)
    other = duhamel.solve(system, duhamel.Semianalytic(), t_end=1.0, dt=DT, t_eval=times)
    np.testing.assert_array_equal(xs, other.x)
    np.testing.assert_array_equal(vs, other.v)
    plain = duhamel.solve(system, duhamel.Semianalytic(), t_end=1.0, dt=DT)
    with pytest.raises(ValueError, match="dense=True"):
        plain.at(0.5)
    with pytest.raises(ValueError, match="within the run"):
        sol.at(1.5)


def test_bad_input_names_the_parameter() -> None:
    system = _frame()
    with pytest.raises(ValueError, match="save_every"):
        duhamel.solve(system, duhamel.Semianalytic(), t_end=1.0, dt=DT, dense=True,
                      save_every=2)  # fmt: skip
    with pytest.raises(ValueError, match="t_eval"):
        duhamel.solve(system, duhamel.Semianalytic(), t_end=1.0, dt=DT, t_eval=[0.5, 2.0])
    with pytest.raises(ValueError, match="t_eval"):
        duhamel.solve(system, duhamel.Semianalytic(), t_end=1.0, dt=DT, t_eval=[0.5, 0.2])
    with pytest.raises(TypeError, match="events"):
        duhamel.solve(system, duhamel.Semianalytic(), t_end=1.0, dt=DT, events=[1.0])


def _duffing(t: float, y: np.ndarray) -> list[float]:
    return [y[1], np.cos(3.0 * t) - 0.2 * y[1] - 25.0 * y[0] - 40.0 * y[0] ** 3]


def test_nonlinear_interpolant_converges_at_the_schemes_order() -> None:
    """A Duffing oscillator: the response at instants inside the steps (never on any of the
    grids) converges at the pseudo-force scheme's order 2 as dt halves."""
    times = np.array([0.1234, 0.777, 1.3579, 1.9])
    ref = solve_ivp(_duffing, (0.0, 2.0), [0.05, 0.0], rtol=1e-12, atol=1e-14,
                    dense_output=True).sol(times)[0]  # fmt: skip
    errors = []
    steps = [0.02, 0.01, 0.005, 0.0025]
    for dt in steps:
        system = duhamel.System(np.eye(1), 25.0 * np.eye(1), 0.2 * np.eye(1))
        system.add(duhamel.elements.Cubic(0, k3=40.0))
        system.add_load(duhamel.loads.Harmonic(dof=0, amplitude=1.0, omega=3.0, phase=np.pi / 2))
        sol = duhamel.solve(system, duhamel.Semianalytic(), t_end=2.0, dt=dt, x0=[0.05],
                            t_eval=times)  # fmt: skip
        errors.append(np.abs(sol.x[:, 0] - ref).max())
    slopes = np.diff(np.log(errors)) / np.diff(np.log(steps))
    assert np.all(slopes > 1.8), (errors, slopes)

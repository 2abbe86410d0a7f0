"""Automatic step subdivision of the semi-analytic integrator (issue 13).

A step whose equation does not converge is retried in halves, down to
``dt / 2**subdivisions``. Checked: a run that stops without it completes with it, reports
what it did, and agrees with an independent reference (solve_ivp at tight tolerance) as
well as the run that converges without help; bad values are refused. (The substeps' load
restriction is unit-tested in the core, `pseudo/subdivide.rs`.)
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import duhamel
from duhamel import elements as E
from duhamel import loads as L

M = np.diag([2.0, 1.0])
K = np.array([[401.0, -400.0], [-400.0, 400.0]])
FY = 0.1 * 9.81 * 3.0
V_EPS = 1e-4
T_REC = np.linspace(0.0, 4.0, 801)
A_REC = 4.0 * np.sin(2 * np.pi * 1.3 * T_REC) * np.exp(-0.1 * T_REC)


def friction(x, v, t):
    return np.array([FY * np.tanh(v[0] / V_EPS)])


def friction_system() -> duhamel.System:
    """An isolated 2-dof structure with a smoothed Coulomb friction isolator (a stiff law:
    its tangent is FY / V_EPS = 3e4 times the isolator's linear stiffness)."""
    s = duhamel.System(M, K, zeta=0.02)
    s.add(E.Callable([0], friction))
    s.add_load(L.BaseAcceleration(np.ones(2), t=T_REC, values=A_REC))
    return s


def reference(t_out: np.ndarray) -> np.ndarray:
    """solve_ivp (Radau, rtol 1e-11) of the same equations, with the same modal damping."""
    basis = duhamel.System(M, K, zeta=0.02).modal()
    phi, w, zeta = basis.phi, np.sqrt(basis.omega2), 0.02
    c = M @ phi @ np.diag(2 * zeta * w) @ phi.T @ M

    def rhs(t, y):
        x, v = y[:2], y[2:]
        ag = np.interp(t, T_REC, A_REC)
        f = -M @ np.ones(2) * ag - c @ v - K @ x
        f[0] -= FY * np.tanh(v[0] / V_EPS)
        return np.concatenate([v, np.linalg.solve(M, f)])

    sol = solve_ivp(
        rhs,
        (0, t_out[-1]),
        np.zeros(4),
        method="Radau",
        rtol=1e-11,
        atol=1e-13,
        t_eval=t_out,
        max_step=2.5e-3,
    )
    assert sol.success
    return sol.y[:2].T


def test_a_run_that_stops_completes_in_halves() -> None:
    stopping = duhamel.Semianalytic(max_iter=4, subdivisions=0)
    with pytest.raises(duhamel.SolverError) as err:
        duhamel.solve(friction_system(), stopping, t_end=4.0, dt=0.01)
    assert err.value.reason == "convergence"
    helped = duhamel.solve(
        friction_system(), duhamel.Semianalytic(max_iter=4, subdivisions=8), t_end=4.0, dt=0.01
    )
    assert helped.stats.subdivided_steps > 0
    assert 1 <= helped.stats.subdivision_depth <= 8
    plain = duhamel.solve(friction_system(), duhamel.Semianalytic(), t_end=4.0, dt=0.01)
    assert plain.stats.subdivided_steps == 0 and plain.stats.subdivision_depth == 0
    ref = reference(helped.t)
    peak = np.abs(ref).max()
    err_helped = np.abs(helped.x - ref).max() / peak
    err_plain = np.abs(plain.x - ref).max() / peak
    # both second-order accurate at dt = 0.01 against the converged reference; the
    # subdivided steps are, if anything, more accurate
    assert err_plain < 2e-2
    assert err_helped < 2e-2
    assert err_helped <= 1.5 * err_plain


@pytest.mark.parametrize("bad", [-1, 31, 2.5, True, "4"])
def test_bad_subdivisions_are_refused(bad: object) -> None:
    with pytest.raises((ValueError, TypeError), match="subdivisions"):
        duhamel.Semianalytic(subdivisions=bad)  # type: ignore[arg-type]


def test_linear_runs_never_subdivide() -> None:
    s = duhamel.System(M, K, zeta=0.02)
    s.add(E.Spring(0, None, k=50.0))
    s.add_load(L.BaseAcceleration(np.ones(2), t=T_REC, values=A_REC))
    sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=1.0, dt=0.01)
    assert sol.stats.subdivided_steps == 0

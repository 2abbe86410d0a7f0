"""A Python `Callable` element with internal variables (issue 13: users' own hysteresis).

The elastoplastic element of the docstring under a harmonic force, against an independent
fine-step integration with the same return mapping (velocity Verlet, dt = 1e-5 s); errors
fall with the step; the committed force history obeys the yield limit and closes loops
that dissipate energy; protocol errors name what is wrong.
"""

from __future__ import annotations

import numpy as np
import pytest

import duhamel
from duhamel import elements as E
from duhamel import loads as L

K_EL, FY, M, K_FRAME, ZETA = 100.0, 1.0, 1.0, 10.0, 0.02
AMP, W = 3.0, 2.0


def _return_map(x: float, plastic: float) -> tuple[float, float]:
    trial = K_EL * (x - plastic)
    if abs(trial) > FY:
        plastic = x - np.sign(trial) * FY / K_EL
        trial = np.sign(trial) * FY
    return trial, plastic


def epp(x, v, t, state):
    force, plastic = _return_map(x[0], state[1])
    return np.array([force]), np.array([x[0], plastic])


def epp_jacobian(x, v, t, state):
    trial = K_EL * (x[0] - state[1])
    return np.array([[0.0 if abs(trial) > FY else K_EL]]), np.zeros((1, 1))


def system(jacobian: bool = True) -> duhamel.System:
    s = duhamel.System(np.array([[M]]), np.array([[K_FRAME]]), zeta=ZETA)
    s.add(E.Callable([0], epp, jacobian=epp_jacobian if jacobian else None, state=[0.0, 0.0]))
    s.add_load(L.Harmonic(0, amplitude=AMP, omega=W))
    return s


def reference(t_end: float, dt: float) -> np.ndarray:
    """Velocity Verlet with the same return mapping (independent of duhamel)."""
    c = 2 * ZETA * np.sqrt(K_FRAME / M) * M
    x = v = plastic = 0.0
    r, plastic = _return_map(x, plastic)
    a = (-c * v - K_FRAME * x - r) / M
    out = [x]
    for i in range(round(t_end / dt)):
        x += dt * v + 0.5 * dt * dt * a
        r, plastic = _return_map(x, plastic)
        vh = v + 0.5 * dt * a
        a = (AMP * np.sin(W * (i + 1) * dt) - c * vh - K_FRAME * x - r) / M
        v = vh + 0.5 * dt * a
        out.append(x)
    return np.array(out)


@pytest.fixture(scope="module")
def fine() -> np.ndarray:
    return reference(6.0, 1e-5)


def test_elastoplastic_callable_converges_to_the_reference(fine: np.ndarray) -> None:
    errors = []
    for dt in (0.02, 0.01, 0.005):
        sol = duhamel.solve(system(), duhamel.Semianalytic(), t_end=6.0, dt=dt)
        ref = fine[:: round(dt / 1e-5)]
        errors.append(np.abs(sol.x[:, 0] - ref).max() / np.abs(ref).max())
    assert errors[-1] < 2e-4
    # the error falls with the step (at least first order through the yield kinks)
    assert errors[1] < 0.6 * errors[0] and errors[2] < 0.6 * errors[1]


def test_committed_forces_obey_the_yield_limit_and_dissipate() -> None:
    sol = duhamel.solve(system(), duhamel.Semianalytic(), t_end=6.0, dt=0.005)
    el = sol.elements[0]
    assert np.abs(el.force).max() <= FY * (1 + 1e-12)
    assert np.abs(el.force).max() > 0.999 * FY  # it yields
    # work done by the element over the run (trapezoid): positive (it dissipates)
    work = np.sum(0.5 * (el.axial_force[1:] + el.axial_force[:-1]) * np.diff(el.deformation))
    stored = 0.5 * el.axial_force[-1] ** 2 / K_EL
    assert work - stored > 0.1


def test_finite_difference_tangents_work_too(fine: np.ndarray) -> None:
    a = duhamel.solve(system(jacobian=False), duhamel.Semianalytic(), t_end=6.0, dt=0.005)
    b = duhamel.solve(system(), duhamel.Semianalytic(), t_end=6.0, dt=0.005)
    assert np.abs(a.x - b.x).max() <= 1e-6 * np.abs(b.x).max()


def test_protocol_errors_are_clear() -> None:
    s = duhamel.System(np.eye(1), np.eye(1), zeta=0.02)
    s.add(E.Callable([0], lambda x, v, t, state: np.array([x[0]]), state=[0.0]))
    with pytest.raises(duhamel.SolverError, match=r"expected a pair \(r, state\)") as err:
        duhamel.solve(s, duhamel.Semianalytic(), t_end=0.1, dt=0.01, x0=[0.1])
    assert err.value.reason == "callback"
    with pytest.raises(ValueError, match="`state`"):
        E.Callable([0], epp, state=[])
    with pytest.raises(ValueError, match="`state`"):
        E.Callable([0], epp, state=[np.nan])


def test_direct_integrators_commit_the_callable_state() -> None:
    """Newmark commits the Python element's state once per step like the semi-analytic
    integrator: it approaches the independent Verlet reference as the step falls."""
    ref = reference(4.0, 1e-5)
    peak = np.abs(ref).max()
    errors = []
    for dt in (4e-3, 2e-3, 1e-3):
        sol = duhamel.solve(system(), duhamel.Newmark(), t_end=4.0, dt=dt)
        errors.append(np.abs(sol.x[:, 0] - ref[:: round(dt / 1e-5)]).max() / peak)
    assert errors[-1] < 2e-3 and errors[0] > 2.5 * errors[-1], errors

"""Path-dependent elements on the direct integrators (issue 13): internal variables evaluated
from the committed ones at every Newton iteration and committed once per accepted step.
Checked against the semi-analytic integrator (an independent route: modal background,
pseudo-forces, its own commit path) at a fine step, with the convergence order measured,
and a Python ``Callable`` with state equal to the built-in element it re-implements."""

from __future__ import annotations

import numpy as np
import pytest

import duhamel
from duhamel import elements as E
from duhamel import loads as L

T_END = 4.0


def sdof(element: duhamel.elements.Element) -> duhamel.System:
    """A 2-dof frame (T1 about 1 s) with a device between the floors, under a base motion."""
    M = np.diag([2.0, 1.0])
    K = 40.0 * np.array([[2.0, -1.0], [-1.0, 1.0]])
    s = duhamel.System(M, K, zeta=0.02).add(element)
    t = np.linspace(0.0, T_END, 801)
    s.add_load(
        L.BaseAcceleration(np.ones(2), t=t, values=8.0 * np.sin(5.0 * t) * np.minimum(t, 1.0))
    )
    return s


ELEMENTS = {
    "bilinear": E.Bilinear(1, 0, k=60.0, fy=1.5, alpha=0.05),
    "bouc-wen": E.BoucWen(1, 0, k=60.0, fy=1.5, alpha=0.05, n=2.0),
}


def reference(element) -> duhamel.Solution:
    dt = T_END / (800 * 2**6)
    return duhamel.solve(sdof(element), duhamel.Semianalytic(), t_end=T_END, dt=dt)


@pytest.mark.parametrize("name", sorted(ELEMENTS))
@pytest.mark.parametrize(
    "integrator", [duhamel.Newmark(), duhamel.CubicHermite()], ids=["newmark", "hermite"]
)
def test_converges_to_the_semianalytic_run(name: str, integrator) -> None:
    element = ELEMENTS[name]
    ref = reference(element)
    every = 2**6
    xr = ref.x[::every]
    peak = np.abs(xr).max()
    errors = []
    dts = [T_END / 800 / 2**j for j in range(4)]
    for j, dt in enumerate(dts):
        sol = duhamel.solve(sdof(element), integrator, t_end=T_END, dt=dt, save_every=2**j)
        errors.append(np.abs(sol.x - xr).max() / peak)
    rel = ref.elements[0].deformation
    assert np.abs(rel).max() > 3 * 1.5 / 60.0  # the device yields (ductility > 3)
    slope = np.polyfit(np.log(dts), np.log(errors), 1)[0]
    assert errors[-1] < 2e-3, errors
    assert slope > 1.7, (slope, errors)  # second order (up to the kinks of the hysteresis)


def test_python_callable_with_state_equals_bilinear() -> None:
    """An elastic-perfectly-plastic law written in Python with the documented state protocol
    gives the built-in Bilinear's run (alpha = 0) on Newmark, to round-off."""
    k, fy = 60.0, 1.5

    def epp(x, v, t, state):
        plastic = state[0]
        u = x[1] - x[0]
        trial = k * (u - plastic)
        if abs(trial) > fy:
            plastic = u - np.sign(trial) * fy / k
            trial = np.sign(trial) * fy
        return np.array([-trial, trial]), np.array([plastic])

    def jacobian(x, v, t, state):
        u = x[1] - x[0]
        kt = k if abs(k * (u - state[0])) <= fy else 0.0
        return kt * np.array([[1.0, -1.0], [-1.0, 1.0]]), np.zeros((2, 2))

    mine = E.Callable([0, 1], epp, jacobian=jacobian, state=[0.0])
    kw = {"t_end": T_END, "dt": 0.005}
    a = duhamel.solve(sdof(mine), duhamel.Newmark(), **kw)
    b = duhamel.solve(sdof(E.Bilinear(1, 0, k=k, fy=fy, alpha=0.0)), duhamel.Newmark(), **kw)
    assert np.abs(b.x[:, 1] - b.x[:, 0]).max() > 3 * fy / k
    np.testing.assert_allclose(a.x, b.x, rtol=0, atol=1e-10 * np.abs(b.x).max())

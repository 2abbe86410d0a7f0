"""Elements built in duhamel in a loaded state (issue 36): ``Bilinear(...,
initial_deformation, initial_force)`` and ``FrictionPendulum(..., initial_axial_force)``
with its vertical dof. The model's ``x = 0`` is then the loaded state (a gravity state
whose loads the model does not carry) and the element adds its change from it.

References: the return mapping written out here (closed form), and the same physical model
run from its undeformed configuration with the load that holds the state (the total
formulation): ``x_total = x0 + x`` within the integrators' tolerance.
"""

from __future__ import annotations

import numpy as np
import pytest

import duhamel
from duhamel import elements as E

K, FY, ALPHA = 100.0, 1.0, 0.1


def _mapping(uc: float, fc: float, u: float) -> float:
    """The bilinear kinematic band's return mapping (the docs' formula)."""
    trial = fc + K * (u - uc)
    line, band = ALPHA * K * u, (1 - ALPHA) * FY
    return min(max(trial, line - band), line + band)


def test_drive_from_a_yielded_and_unloaded_state_equals_the_return_mapping() -> None:
    # loaded to 0.05 (yielded), unloaded to 0.03: OpenSees' state after a gravity analysis
    f1 = _mapping(0.0, 0.0, 0.05)
    f0 = _mapping(0.05, f1, 0.03)
    hinge = E.Bilinear(0, k=K, fy=FY, alpha=ALPHA, initial_deformation=0.03, initial_force=f0)
    path = np.array([0.0, 0.01, 0.04, -0.02, -0.09, 0.03])
    got = E.drive(hinge, path).force
    uc, fc, want = 0.03, f0, []
    for x in path:
        fc, uc = _mapping(uc, fc, 0.03 + x), 0.03 + x
        want.append(fc - f0)
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-12)


def test_the_default_initial_force_is_the_backbone() -> None:
    hinge = E.Bilinear(0, k=K, fy=FY, alpha=ALPHA, initial_deformation=0.05)
    f0 = _mapping(0.0, 0.0, 0.05)
    got = E.drive(hinge, np.array([0.0, -0.01]))
    np.testing.assert_allclose(got.force, [0.0, _mapping(0.05, f0, 0.04) - f0], atol=1e-12)


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"initial_deformation": 0.0, "initial_force": 2.0}, "initial_force"),
        ({"initial_deformation": float("nan")}, "initial_deformation"),
        ({"initial_force": float("inf")}, "initial_force"),
    ],
)
def test_a_state_the_element_cannot_reach_is_refused_naming_it(kwargs: dict, name: str) -> None:
    with pytest.raises(ValueError, match=f"`{name}`"):
        E.Bilinear(0, k=K, fy=FY, alpha=ALPHA, **kwargs)


def test_gravity_state_run_equals_the_total_formulation() -> None:
    """Two dofs: a mass on a spring and a Bilinear, a static load P holding it yielded.
    The incremental model (the Bilinear at its loaded state, no P) equals the total model
    (the virgin Bilinear, P as a constant load, started from the static state x0)."""
    m, ks, p = np.diag([1.0, 2.0]), np.array([[30.0, -10.0], [-10.0, 10.0]]), 1.6
    # the static state under p at dof 1: spring + bilinear (yielded: on the upper line)
    uy = FY / K
    # solve (K x)_0 + B(x0_0) = 0, (K x)_1 = p with B on the upper line alpha k u + (1-a) fy
    a = ks + np.diag([ALPHA * K, 0.0])
    x0 = np.linalg.solve(a, [-(1 - ALPHA) * FY, p])
    assert x0[0] > uy  # yielded at the static state
    f0 = ALPHA * K * x0[0] + (1 - ALPHA) * FY
    t = np.linspace(0.0, 3.0, 301)
    ag = 2.0 * np.sin(2 * np.pi * 1.3 * t) * np.exp(-t)
    runs = []
    for total in (False, True):
        s = duhamel.System(m, ks, rayleigh=(0.1, 0.0))
        if total:
            s.add(E.Bilinear(0, k=K, fy=FY, alpha=ALPHA))
            s.add_load(duhamel.loads.Step(dof=1, amplitude=p))
        else:
            s.add(E.Bilinear(0, k=K, fy=FY, alpha=ALPHA, initial_deformation=x0[0],
                             initial_force=f0))  # fmt: skip
        s.add_load(duhamel.loads.BaseAcceleration(np.ones(2), t, ag))
        kw = {"x0": x0} if total else {}
        sol = duhamel.solve(s, duhamel.Newmark(), t_end=3.0, dt=1e-3, save_every=10, **kw)
        runs.append(sol.x if total else x0 + sol.x)
    np.testing.assert_allclose(runs[0], runs[1], rtol=0, atol=1e-9 * np.abs(runs[1]).max())
    assert np.ptp(runs[1][:, 0]) > 2 * uy  # it yields again along the record


def test_pendulum_initial_axial_force_is_the_weight_held() -> None:
    """A mass on a friction pendulum with its vertical dof: the model at its static state
    with ``initial_axial_force = W`` equals the model that carries the weight as a load and
    starts from ``u_z = -W / k_v``."""
    mass, kv, w = 1e4, 5e8, 1e4 * 9.81
    t = np.linspace(0.0, 3.0, 301)
    ag = 3.0 * np.sin(2 * np.pi * 0.8 * t) * np.exp(-0.5 * t)
    runs = []
    for total in (False, True):
        s = duhamel.System(mass * np.eye(2), np.zeros((2, 2)))
        extra = {} if total else {"initial_axial_force": w}
        s.add(E.FrictionPendulum((0, None, 1), radius=2.0, mu=0.06, weight=w,
                                 vertical_stiffness=kv, **extra))  # fmt: skip
        s.add_load(duhamel.loads.BaseAcceleration([1.0, 0.0], t, ag))
        s.add_load(duhamel.loads.BaseAcceleration([0.0, 1.0], t, 0.4 * ag))
        x0 = np.array([0.0, -w / kv])
        if total:
            s.add_load(duhamel.loads.Step(dof=1, amplitude=-w))
        kw = {"x0": x0} if total else {}
        sol = duhamel.solve(s, duhamel.Newmark(), t_end=3.0, dt=2e-4, save_every=50, **kw)
        runs.append(sol.x if total else x0 + sol.x)
    np.testing.assert_allclose(runs[0], runs[1], rtol=0, atol=1e-7 * np.abs(runs[1][:, 0]).max())
    assert np.abs(runs[1][:, 0]).max() > 0.01  # it slides

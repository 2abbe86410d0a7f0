"""One mode stepped on scalars against the dense modal Newton, bit for bit.

With one mode and a pseudo-force of elements only (a one-dof device, one kept mode of a
larger frame), the step equation is solved by a scalar copy of the modal Newton
(``pseudo/newton/one.rs``: the same operations in the same order, no per-step vectors);
``solver="modal-newton"`` keeps the dense reference. Both must give the same numbers, not
merely close ones: every scheme and quadrature, devices with and without internal
variables or velocity dependence, a stop stiff enough to subdivide its steps, and the
stored histories of the elements.
"""

from __future__ import annotations

import numpy as np
import pytest

import duhamel
from duhamel import elements as E
from duhamel import loads as L

DEVICES = {
    "bilinear": lambda: E.Bilinear(0, None, k=1e4, fy=60.0, alpha=0.05),
    "gap": lambda: E.Gap(0, None, gap=0.004, k=3e4),
    "viscous-damper": lambda: E.ViscousDamper(0, None, c=200.0, exponent=0.4),
    "friction-pendulum": lambda: E.FrictionPendulum((0, None), radius=2.0, mu=0.05, weight=98.0),
    "bouc-wen": lambda: E.BoucWen(0, None, k=1e4, fy=60.0, alpha=0.1, n=2.0),
    "cubic-spring-newton": lambda: E.Spring(0, None, k=0.0, k3=1e9),
}


def _one_dof(element: E.Element) -> duhamel.System:
    s = duhamel.System(10.0 * np.eye(1), 1e4 * np.eye(1), zeta=0.05)
    t = np.linspace(0.0, 3.0, 601)
    s.add_load(L.BaseAcceleration(np.ones(1), t=t, values=30.0 * np.sin(7.0 * t) * np.sin(1.3 * t)))
    return s.add(element)


def _same(a: duhamel.Solution, b: duhamel.Solution) -> None:
    for name in ("t", "x", "v", "a"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
    np.testing.assert_array_equal(a.modal.pseudo_force, b.modal.pseudo_force)
    for ea, eb in zip(a.elements, b.elements, strict=True):
        np.testing.assert_array_equal(ea.force, eb.force)
    assert a.stats.newton_iterations == b.stats.newton_iterations
    assert a.stats.subdivided_steps == b.stats.subdivided_steps


def _pair(system, dt=0.005, **options):
    fast = duhamel.solve(system(), duhamel.Semianalytic(**options), t_end=3.0, dt=dt)
    options["solver"] = "modal-newton"
    dense = duhamel.solve(system(), duhamel.Semianalytic(**options), t_end=3.0, dt=dt)
    return fast, dense


@pytest.mark.parametrize("device", sorted(DEVICES))
def test_devices_match_the_dense_modal_newton(device):
    # a cubic spring alone would take the closed form: "newton" keeps it on Newton
    options = {"solver": "newton"} if device == "cubic-spring-newton" else {}
    fast, dense = _pair(lambda: _one_dof(DEVICES[device]()), **options)
    assert fast.stats.newton_iterations > fast.stats.steps  # the device is nonlinear here
    _same(fast, dense)


@pytest.mark.parametrize("scheme", ["a", "b", "c"])
@pytest.mark.parametrize("quadrature", ["trapezoid", "parabolic", "exact"])
def test_every_scheme_and_quadrature(scheme, quadrature):
    fast, dense = _pair(
        lambda: _one_dof(DEVICES["bilinear"]()), scheme=scheme, quadrature=quadrature
    )
    _same(fast, dense)


def test_a_stop_that_subdivides_its_steps():
    fast, dense = _pair(lambda: _one_dof(E.Gap(0, None, gap=0.002, k=1e8)), dt=0.01)
    assert fast.stats.subdivided_steps > 0
    _same(fast, dense)


def test_one_kept_mode_of_a_frame():
    def frame():
        s = duhamel.System(np.diag([2.0, 1.0]), [[2e3, -1e3], [-1e3, 1e3]], zeta=0.03)
        return s.add(E.Bilinear(0, 1, k=3e3, fy=5.0, alpha=0.1))

    x0 = [0.004, 0.01]
    runs = []
    for solver in ("auto", "modal-newton"):
        integrator = duhamel.Semianalytic(modes=1, static_correction=False, solver=solver)
        runs.append(duhamel.solve(frame(), integrator, t_end=2.0, dt=0.01, x0=x0))
    assert runs[0].stats.modes == 1
    _same(*runs)


def test_a_stiff_bilinear_that_subdivides_its_steps():
    # a hysteretic device dominating its background: steps the stiffness watch rejects are
    # taken in substeps that commit the device several times; the next step must not take
    # the rejected trial's end force as its start (one.rs keeps the last end's force only
    # across exactly one commit)
    fast, dense = _pair(lambda: _one_dof(E.Bilinear(0, None, k=2e6, fy=400.0, alpha=0.02)), dt=0.01)
    assert fast.stats.subdivided_steps > 0
    _same(fast, dense)

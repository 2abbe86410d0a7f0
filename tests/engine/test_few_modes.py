"""Two and three modes stepped on fixed-size arrays against the dense modal Newton, bit for bit.

With two or three modes, a pseudo-force of elements only and an element space as large as
the modes (a bidirectional bearing under a rigid mass, with or without its vertical dof; a
two-storey shear building with a device in each storey), the step equation is solved by a
fixed-size copy of the modal Newton (``pseudo/newton/few.rs``: the same operations in the
same order); ``solver="modal-newton"`` keeps the dense reference. Both must give the same
numbers, not merely close ones: every scheme and quadrature, devices with and without
internal variables or velocity dependence, a stop stiff enough to subdivide its steps, and
the stored histories of the elements.
"""

from __future__ import annotations

import numpy as np
import pytest

import duhamel
from duhamel import elements as E
from duhamel import loads as L

T = np.linspace(0.0, 3.0, 601)
ACC = 30.0 * np.sin(7.0 * T) * np.sin(1.3 * T)


def _rigid_mass(element: E.Element, n: int = 2) -> duhamel.System:
    """A rigid mass on a bearing, excited along x and (less) along y."""
    s = duhamel.System(10.0 * np.eye(n), np.zeros((n, n)))
    s.add_load(L.BaseAcceleration(np.eye(n)[0], t=T, values=ACC))
    s.add_load(L.BaseAcceleration(np.eye(n)[1], t=T, values=0.6 * np.roll(ACC, 80)))
    return s.add(element)


def _two_storeys(*elements: E.Element) -> duhamel.System:
    """A two-storey shear building (5 % modal damping) with a device in each storey."""
    k = 1e4
    K = k * np.array([[2.0, -1.0], [-1.0, 1.0]])
    s = duhamel.System(10.0 * np.eye(2), K, zeta=0.05)
    s.add_load(L.BaseAcceleration(np.ones(2), t=T, values=ACC))
    for e in elements:
        s.add(e)
    return s


DEVICES = {
    "friction-pendulum": lambda: _rigid_mass(
        E.FrictionPendulum((0, 1), radius=2.0, mu=0.05, weight=98.0)
    ),
    "friction-pendulum-velocity": lambda: _rigid_mass(
        E.FrictionPendulum((0, 1), radius=2.0, mu=0.08, mu_slow=0.04, rate=20.0, weight=98.0)
    ),
    "lead-rubber-bearing": lambda: _rigid_mass(E.LeadRubberBearing((0, 1), k=4e3, fy=40.0)),
    "bilinear-storeys": lambda: _two_storeys(
        E.Bilinear(0, None, k=1e4, fy=60.0, alpha=0.05),
        E.Bilinear(1, 0, k=5e3, fy=40.0, alpha=0.1),
    ),
    "viscous-storeys": lambda: _two_storeys(
        E.ViscousDamper(0, None, c=200.0, exponent=0.4),
        E.ViscousDamper(1, 0, c=150.0, exponent=0.5),
    ),
    "bouc-wen-storeys": lambda: _two_storeys(
        E.BoucWen(0, None, k=1e4, fy=60.0, alpha=0.1, n=2.0),
        E.Spring(1, 0, k=0.0, k3=1e9),
    ),
}


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
    fast, dense = _pair(DEVICES[device])
    assert fast.stats.modes == 2
    assert fast.stats.newton_iterations > fast.stats.steps  # the devices are nonlinear here
    _same(fast, dense)


@pytest.mark.parametrize("scheme", ["a", "b", "c"])
@pytest.mark.parametrize("quadrature", ["trapezoid", "parabolic", "exact"])
def test_every_scheme_and_quadrature(scheme, quadrature):
    fast, dense = _pair(DEVICES["bilinear-storeys"], scheme=scheme, quadrature=quadrature)
    _same(fast, dense)
    fast, dense = _pair(DEVICES["friction-pendulum"], scheme=scheme, quadrature=quadrature)
    _same(fast, dense)


def test_a_stop_that_subdivides_its_steps():
    def stopped():
        return _two_storeys(E.Gap(0, None, gap=0.002, k=1e8), E.Bilinear(1, 0, k=5e3, fy=40.0))

    fast, dense = _pair(stopped, dt=0.01)
    assert fast.stats.subdivided_steps > 0
    _same(fast, dense)


def test_three_modes_a_bearing_with_its_vertical_dof():
    def bearing():
        s = duhamel.System(10.0 * np.eye(3), np.zeros((3, 3)))
        s.add(
            E.FrictionPendulum((0, 1, 2), radius=2.0, mu=0.05, weight=98.0, vertical_stiffness=1e6)
        )
        s.add_load(L.BaseAcceleration(np.eye(3)[0], t=T, values=0.2 * ACC))
        s.add_load(L.BaseAcceleration(np.eye(3)[1], t=T, values=0.1 * np.roll(ACC, 80)))
        s.add_load(L.Step(2, amplitude=-98.0))
        return s

    x0 = np.array([0.0, 0.0, -98.0 / 1e6])
    fast = duhamel.solve(bearing(), duhamel.Semianalytic(), t_end=3.0, dt=0.005, x0=x0)
    dense = duhamel.solve(
        bearing(), duhamel.Semianalytic(solver="modal-newton"), t_end=3.0, dt=0.005, x0=x0
    )
    assert fast.stats.modes == 3
    assert fast.stats.newton_iterations > fast.stats.steps
    _same(fast, dense)

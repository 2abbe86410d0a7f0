"""The energy balance accumulated in the core during the run (``solve(..., energy=True)``,
issue 27): it closes on a frame with a Bilinear brace, a viscous damper and a friction
pendulum and converges with dt; it does not depend on `save_every` or `dofs`; each element's
work is the loop integral of its own force-deformation history; the absolute and relative
inputs differ by the kinetic-energy terms; it equals the after-run balance where their
formulas are the same."""

from __future__ import annotations

import numpy as np
import pytest

import duhamel
from duhamel import elements as E
from duhamel import loads as L
from duhamel.results.energy import energy_balance

T_REC = np.arange(0.0, 7.0, 0.01)
A_REC = 3.0 * np.sin(2 * np.pi * 1.1 * T_REC) * np.exp(-0.3 * T_REC) * np.minimum(T_REC, 1.0)


def frame() -> duhamel.System:
    """A 2-storey frame (x: dofs 2, 3) on a mat (x 0, y 1) on a friction pendulum, a Bilinear
    brace in the first storey and a viscous damper in the second, under a record."""
    m = np.diag([3e5, 3e5, 2e5, 2e5])
    k = np.zeros((4, 4))
    for a, b, ks in ((0, 2, 3e8), (2, 3, 3e8)):
        k[np.ix_([a, b], [a, b])] += ks * np.array([[1.0, -1.0], [-1.0, 1.0]])
    s = duhamel.System(m, k, rayleigh=(0.0, 0.003))
    s.add(E.FrictionPendulum((0, 1), radius=2.0, mu=0.04, weight=1e6 * 9.81))
    s.add(E.Bilinear(2, 0, k=1e8, fy=1.5e5, alpha=0.05))
    s.add(E.ViscousDamper(3, 2, c=1e6, exponent=0.5))
    s.add_load(L.BaseAcceleration(np.array([1.0, 0.0, 1.0, 1.0]), t=T_REC, values=2.0 * A_REC))
    return s


def run(dt: float, **kw: object) -> duhamel.Solution:
    return duhamel.solve(frame(), duhamel.Semianalytic(), t_end=6.0, dt=dt, energy=True, **kw)


FIELDS = ("kinetic", "kinetic_absolute", "strain", "damping", "elements", "hysteretic")
FIELDS += ("input", "input_absolute", "error")


def test_balance_closes_and_converges_with_dt() -> None:
    dts = [0.004, 0.002, 0.001, 0.0005]
    ends = []
    for dt in dts:
        e = run(dt, save_every=max(1, round(0.02 / dt))).energy
        assert e.hysteretic[-1] > 0.3 * e.input[-1]  # the devices take most of the input
        ends.append(abs(e.error[-1]) / e.input[-1])
    # measured: 5.8e-5, 2.9e-5, 7.3e-6, 1.8e-6 (slope 1.7 over all, 2.0 over the finest
    # three: the second order of the trapezoids once the stick-slip events are resolved)
    slope = np.polyfit(np.log(dts), np.log(ends), 1)[0]
    fine = np.polyfit(np.log(dts[1:]), np.log(ends[1:]), 1)[0]
    assert slope > 1.5 and fine > 1.8, (ends, slope, fine)
    assert max(ends) <= 1e-4, ends


def test_save_every_and_dofs_do_not_change_the_energy() -> None:
    every = run(0.002).energy
    for kw in ({"save_every": 10}, {"save_every": 7, "dofs": [3]}):
        sparse = run(0.002, **kw).energy
        step = int(kw["save_every"])  # type: ignore[call-overload]
        n = every.t[::step].size
        np.testing.assert_array_equal(sparse.t[:n], every.t[::step])
        for name in FIELDS:
            a, b = getattr(sparse, name)[:n], getattr(every, name)[::step]
            scale = np.abs(getattr(every, name)).max()
            np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 * scale, err_msg=name)
        # the last instant (always kept) too
        for name in FIELDS:
            a, b = getattr(sparse, name)[-1], getattr(every, name)[-1]
            scale = np.abs(getattr(every, name)).max()
            np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 * scale, err_msg=name)


def test_element_work_is_the_loop_integral_of_its_history() -> None:
    sol = run(0.002)
    e = sol.energy
    for k, history in enumerate(sol.elements):
        u, f = np.asarray(history.x), np.asarray(history.force)
        if isinstance(history.element, E.FrictionPendulum):  # both directions
            loop = np.trapezoid(f[:, 0], u[:, 0]) + np.trapezoid(f[:, 1], u[:, 1])
        else:  # a two-node element: its force against its deformation
            loop = np.trapezoid(f[:, 0], u[:, 0] - u[:, 1])
        assert loop > 0
        np.testing.assert_allclose(e.elements[-1, k], loop, rtol=1e-12)
    # the damper stores nothing and dissipates int F v dt (to the quadrature's order)
    damper = sol.elements[2]
    fv = damper.force[:, 0] * (damper.v[:, 0] - damper.v[:, 1])
    np.testing.assert_allclose(e.elements[-1, 2], np.trapezoid(fv, sol.t), rtol=1e-3)
    np.testing.assert_array_equal(e.element_stored[:, 2], 0.0)


def test_absolute_and_relative_inputs_differ_by_the_kinetic_terms() -> None:
    gaps, dts = [], [0.002, 0.001, 0.0005]
    for dt in dts:
        e = run(dt, save_every=max(1, round(0.04 / dt))).energy
        gap = (e.input_absolute - e.input) - (e.kinetic_absolute - e.kinetic)
        gaps.append(np.abs(gap).max() / np.abs(e.input).max())
        # the difference itself is not small: the terms are the ground's
        assert np.abs(e.kinetic_absolute - e.kinetic).max() > 0.1 * np.abs(e.input).max()
    slope = np.polyfit(np.log(dts), np.log(gaps), 1)[0]
    # measured: 4.3e-5, 1.1e-5, 2.7e-6
    assert slope > 1.8 and gaps[-1] < 1e-5, (gaps, slope)


def test_equals_the_after_run_balance_where_the_formulas_agree() -> None:
    # dt divides the record's sampling: the ground velocity's integrals agree exactly
    sol = run(0.002)
    core, after = sol.energy, energy_balance(sol, sol._structure())
    for name in ("kinetic", "kinetic_absolute", "strain", "damping", "elements", "input"):
        a, b = getattr(core, name), getattr(after, name)
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 * np.abs(b).max(), err_msg=name)
    # the absolute input: a Stieltjes trapezoid in the core, the trapezoid of the absolute
    # accelerations after the run: both second order
    gap = np.abs(core.input_absolute - after.input_absolute).max()
    assert gap < 1e-4 * np.abs(after.input_absolute).max()


def test_a_free_oscillator_with_an_element_and_other_loads() -> None:
    # no base excitation: a Duffing spring, a dashpot and a harmonic force
    s = duhamel.System(np.eye(2), np.array([[2.0, -1.0], [-1.0, 1.0]]), zeta=0.02)
    s.add(E.Spring(1, None, k=0.5, k3=2.0))
    s.add_load(L.Harmonic(dof=0, amplitude=0.3, omega=1.3))
    errors = []
    for dt in (0.02, 0.01, 0.005):
        sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=20.0, dt=dt, energy=True, x0=[1, 0])
        e = sol.energy
        errors.append(np.abs(e.error).max() / (e.kinetic[0] + e.strain[0]))
        np.testing.assert_array_equal(e.input_absolute, e.input)
    slope = np.polyfit(np.log([0.02, 0.01, 0.005]), np.log(errors), 1)[0]
    assert 1.9 < slope < 2.1, (errors, slope)


def test_the_uncoupled_route_accumulates_stepwise() -> None:
    # a linear frame (no elements): stepped one step at a time when energy is asked for
    m = np.diag([2e5, 2e5, 1.5e5])
    k = 4e8 * np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    s = duhamel.System(m, k, rayleigh=(0.3, 0.002))
    s.add_load(L.BaseAcceleration(np.ones(3), t=T_REC, values=A_REC))
    plain = duhamel.solve(s, duhamel.Semianalytic(), t_end=6.0, dt=0.005)
    assert duhamel.prepare(s, duhamel.Semianalytic(), dt=0.005).route == "uncoupled"
    sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=6.0, dt=0.005, energy=True)
    assert sol._energy_run is not None
    np.testing.assert_allclose(sol.x, plain.x, rtol=0, atol=1e-13 * np.abs(plain.x).max())
    core, after = sol.energy, plain.energy
    for name in ("kinetic", "kinetic_absolute", "strain", "damping", "input"):
        a, b = getattr(core, name), getattr(after, name)
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 * np.abs(b).max(), err_msg=name)
    sparse = duhamel.solve(
        s, duhamel.Semianalytic(), t_end=6.0, dt=0.005, energy=True, save_every=10, dofs=[2]
    ).energy
    for name in FIELDS:
        if name in ("elements", "hysteretic"):  # no element: empty, zeros
            continue
        scale = np.abs(getattr(core, "input" if name == "error" else name)).max()
        a, b = getattr(sparse, name), getattr(core, name)[::10]
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 * scale, err_msg=name)
    ends = []
    dts = [0.01, 0.005, 0.0025]
    for dt in dts:
        e = duhamel.solve(s, duhamel.Semianalytic(), t_end=6.0, dt=dt, energy=True, save_every=20)
        ends.append(abs(e.energy.error[-1]) / e.energy.input[-1])
    slope = np.polyfit(np.log(dts), np.log(ends), 1)[0]
    assert 1.9 < slope < 2.1 and ends[1] < 2e-4, (ends, slope)  # measured 1.1e-4 at 5 ms


def test_the_direct_integrators_accumulate_it_too() -> None:
    ends, dts = [], [0.004, 0.002, 0.001]
    for dt in dts:
        plain = duhamel.solve(frame(), duhamel.Newmark(), t_end=6.0, dt=dt)
        sol = duhamel.solve(frame(), duhamel.Newmark(), t_end=6.0, dt=dt, energy=True)
        np.testing.assert_array_equal(sol.x, plain.x)  # the tap changes nothing
        e = sol.energy
        assert e.hysteretic[-1] > 0.3 * e.input[-1]
        ends.append(abs(e.error[-1]) / e.input[-1])
    # measured: 1.6e-4, 3.9e-5, 9.7e-6 (slope 2.0)
    slope = np.polyfit(np.log(dts), np.log(ends), 1)[0]
    assert slope > 1.9 and ends[1] <= 1e-4, (ends, slope)
    sparse = duhamel.solve(
        frame(), duhamel.Newmark(), t_end=6.0, dt=0.001, energy=True, save_every=10, dofs=[3]
    ).energy
    for name in FIELDS:
        scale = np.abs(getattr(e, "input" if name == "error" else name)).max()
        a, b = getattr(sparse, name), getattr(e, name)[::10]
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 * scale, err_msg=name)
    # against the semi-analytic run: the same physics, to the integrators' accuracy
    semi = run(0.001).energy
    for name in ("input", "damping", "hysteretic"):
        a, b = getattr(e, name)[-1], getattr(semi, name)[-1]
        assert abs(a - b) < 2e-3 * abs(semi.input[-1]), (name, a, b)
    np.testing.assert_allclose(e.elements[-1], semi.elements[-1], rtol=2e-3)


def test_the_first_order_route_accumulates_it_without_elements() -> None:
    # non-classical damping (a dashpot at the base): the exact first-order modes
    m = np.diag([2e5, 2e5, 1.5e5])
    k = 4e8 * np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    c = 2e6 * np.diag([1.0, 0.0, 0.0]) + 0.002 * k
    s = duhamel.System(m, k, C=c)
    s.add_load(L.BaseAcceleration(np.ones(3), t=T_REC, values=A_REC))
    assert duhamel.prepare(s, duhamel.Semianalytic(), dt=0.005).route == "first-order"
    plain = duhamel.solve(s, duhamel.Semianalytic(), t_end=6.0, dt=0.005)
    sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=6.0, dt=0.005, energy=True)
    assert sol._energy_run is not None
    np.testing.assert_array_equal(sol.x, plain.x)
    core, after = sol.energy, plain.energy
    for name in ("kinetic", "kinetic_absolute", "strain", "damping", "input"):
        a, b = getattr(core, name), getattr(after, name)
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 * np.abs(b).max(), err_msg=name)
    sparse = duhamel.solve(
        s, duhamel.Semianalytic(), t_end=6.0, dt=0.005, energy=True, save_every=10, dofs=[2]
    ).energy
    for name in ("kinetic", "strain", "damping", "input", "input_absolute", "error"):
        scale = np.abs(core.input).max()
        a, b = getattr(sparse, name), getattr(core, name)[::10]
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 * scale, err_msg=name)
    ends, dts = [], [0.01, 0.005, 0.0025]
    for dt in dts:
        e = duhamel.solve(s, duhamel.Semianalytic(), t_end=6.0, dt=dt, energy=True, save_every=20)
        ends.append(abs(e.energy.error[-1]) / e.energy.input[-1])
    slope = np.polyfit(np.log(dts), np.log(ends), 1)[0]
    assert 1.9 < slope < 2.1, (ends, slope)  # measured 4.4e-4, 1.1e-4, 2.7e-5


def test_requests_the_route_cannot_serve_are_refused() -> None:
    # a coupled system (non-classical damping) with an element: the first-order route with
    # its corrector, whose balance is computed after the run
    s = duhamel.System(np.eye(2), np.diag([1.0, 4.0]), C=np.array([[0.1, 0.05], [0.05, 0.0]]))
    s.add(E.Spring(1, None, k=0.1, k3=0.01))
    assert duhamel.prepare(s, duhamel.Semianalytic(), dt=0.1).route == "first-order"
    with pytest.raises(ValueError, match=r"`energy`.*save_every=1"):
        duhamel.solve(s, duhamel.Semianalytic(), t_end=1.0, dt=0.1, energy=True, save_every=2)
    with pytest.raises(TypeError, match="`energy`"):
        duhamel.solve(s, duhamel.Semianalytic(), t_end=1.0, dt=0.1, energy="yes")
    # every step kept: the after-run balance serves it
    sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=10.0, dt=0.01, energy=True, x0=[1.0, 0.0])
    assert sol._energy_run is None
    e = sol.energy
    assert abs(e.kinetic[-1] + e.strain[-1] + e.damping[-1] - 0.5) < 1e-5


def test_a_streamed_run_and_its_resume_give_the_same_energy(tmp_path) -> None:
    pytest.importorskip("zarr")
    from duhamel.store import Store, resume

    ref = run(0.002).energy
    # segments of 1024 rows: the integrals continue across three segments
    stored = run(0.002, store=Store(tmp_path / "a.zarr", segment_bytes=1)).energy
    sparse = run(0.002, save_every=10, dofs=[3], store=Store(tmp_path / "b.zarr", modal=False))
    for name in FIELDS:
        # (the error is a difference of the energies: its round-off is theirs)
        scale = np.abs(getattr(ref, "input" if name == "error" else name)).max()
        a, b = getattr(stored, name), getattr(ref, name)
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 * scale, err_msg=name)
        a, b = getattr(sparse.energy, name), getattr(ref, name)[::10]
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 * scale, err_msg=name)

    def stop(step: int, total: int, t: float) -> None:
        if step > 1500:
            raise RuntimeError("stop here")

    path = tmp_path / "c.zarr"
    with pytest.raises(RuntimeError, match="stop here"):
        run(0.002, store=Store(path, segment_bytes=1), progress=stop)
    resumed = resume(path).energy
    for name in FIELDS:
        np.testing.assert_array_equal(getattr(resumed, name), getattr(stored, name), err_msg=name)

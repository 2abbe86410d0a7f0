"""Prepared runs (issue 22): ``prepare(...).run(...)`` is ``solve(...)`` bit for bit on every
route, a run's own loads replace the system's, a Prepared is a snapshot of the system, bad
input is refused by name, and systems that share their matrices share their set-up without
changing a bit."""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

import duhamel
from duhamel import elements as E
from duhamel import loads as L

N = 6
K = 1e4 * (2 * np.eye(N) - np.eye(N, k=1) - np.eye(N, k=-1))
K[-1, -1] = 1e4
T = np.linspace(0.0, 3.0, 601)
RECORD = np.sin(7.0 * T) * np.exp(-0.5 * T)


def model(route: str) -> duhamel.System:
    s = duhamel.System(np.eye(N), K, zeta=0.03)
    s.add_load(L.BaseAcceleration(np.ones(N), t=T, values=RECORD))
    if route == "first-order":
        g = np.zeros((N, N))
        g[0, 1], g[1, 0] = 3.0, -3.0
        s.add(E.LinearCoupling(C=g))
    elif route == "pseudo-force":
        s.add(E.Bilinear(0, None, k=5e3, fy=0.01, alpha=0.05))
    return s


ROUTES = ["uncoupled", "first-order", "pseudo-force", "direct"]


def integrator(route: str) -> duhamel.Semianalytic | duhamel.Newmark:
    return duhamel.Newmark() if route == "direct" else duhamel.Semianalytic()


@pytest.mark.parametrize("route", ROUTES)
def test_prepared_run_is_solve_bit_for_bit(route: str) -> None:
    s = model(route)
    kw = {"t_end": 2.0, "save_every": 3, "dofs": [0, N - 1], "x0": 1e-3 * np.arange(N)}
    expected = duhamel.solve(model(route), integrator(route), dt=0.01, **kw)
    prepared = duhamel.prepare(s, integrator(route), dt=0.01)
    assert prepared.route == ("direct" if route == "direct" else route)
    for _ in range(2):  # a second run of the same Prepared too
        sol = prepared.run(**kw)
        np.testing.assert_array_equal(sol.t, expected.t)
        np.testing.assert_array_equal(sol.x, expected.x)
        np.testing.assert_array_equal(sol.v, expected.v)
        np.testing.assert_array_equal(sol.a, expected.a)


@pytest.mark.parametrize("route", ROUTES)
def test_a_runs_loads_replace_the_systems(route: str) -> None:
    prepared = duhamel.prepare(model(route), integrator(route), dt=0.01)
    other = L.BaseAcceleration(np.ones(N), t=T, values=2.0 * RECORD[::-1])
    sol = prepared.run(t_end=2.0, loads=[other])
    reference = model(route)
    reference.loads.clear()
    reference.add_load(other)
    expected = duhamel.solve(reference, integrator(route), t_end=2.0, dt=0.01)
    np.testing.assert_array_equal(sol.x, expected.x)
    np.testing.assert_array_equal(sol.a_absolute, expected.a_absolute)
    # and the system's own loads come back on the next run
    again = prepared.run(t_end=2.0)
    own = duhamel.solve(model(route), integrator(route), t_end=2.0, dt=0.01)
    np.testing.assert_array_equal(again.x, own.x)
    # solve takes a run's loads as Prepared.run does (issue 35), bit for bit
    solved = duhamel.solve(model(route), integrator(route), t_end=2.0, dt=0.01, loads=[other])
    np.testing.assert_array_equal(solved.x, sol.x)
    np.testing.assert_array_equal(solved.a_absolute, sol.a_absolute)


def test_a_prepared_is_a_snapshot_of_the_system() -> None:
    s = model("uncoupled")
    integ = duhamel.Semianalytic()
    prepared = duhamel.prepare(s, integ, dt=0.01)
    before = prepared.run(t_end=1.0)
    assert prepared.matches(s, integ, 0.01)
    s.add_load(L.Step(N - 1, amplitude=1e3))
    assert not prepared.matches(s, integ, 0.01)
    after = prepared.run(t_end=1.0)
    np.testing.assert_array_equal(after.x, before.x)
    assert not prepared.matches(s, integ, 0.02)
    assert not prepared.matches(s, duhamel.Semianalytic(modes=2), 0.01)


def test_bad_input_is_refused_by_name() -> None:
    s = model("uncoupled")
    with pytest.raises(TypeError, match="`system`"):
        duhamel.prepare("not a system", duhamel.Semianalytic(), dt=0.1)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="`integrator`"):
        duhamel.prepare(s, "newmark", dt=0.1)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="`dt`"):
        duhamel.prepare(s, duhamel.Semianalytic(), dt=-0.1)
    prepared = duhamel.prepare(s, duhamel.Semianalytic(), dt=0.1)
    with pytest.raises(TypeError, match="`loads` must be a list"):
        prepared.run(t_end=1.0, loads=L.Step(0, amplitude=1.0))  # type: ignore[arg-type]
    with pytest.raises(TypeError, match=r"`loads\[0\]`"):
        prepared.run(t_end=1.0, loads=[1.0])  # type: ignore[list-item]
    with pytest.raises(ValueError, match="`dof`") as err:
        prepared.run(t_end=1.0, loads=[L.Step(N + 3, amplitude=1.0)])
    assert any("loads[0]" in note for note in err.value.__notes__)
    with pytest.raises(ValueError, match="`t_end`"):
        prepared.run(t_end=0.0)
    with pytest.raises(ValueError, match="`x0`"):
        prepared.run(t_end=1.0, x0=[1.0])


def test_runs_in_threads_on_one_prepared_are_the_runs_one_at_a_time() -> None:
    prepared = duhamel.prepare(model("pseudo-force"), duhamel.Semianalytic(), dt=0.01)
    scales = [0.5, 1.0, 1.5, 2.0, 2.5, 3.0]
    cases = [[L.BaseAcceleration(np.ones(N), t=T, values=s * RECORD)] for s in scales]
    alone = [prepared.run(t_end=2.0, loads=c).x for c in cases]
    with ThreadPoolExecutor(max_workers=3) as pool:
        together = list(pool.map(lambda c: prepared.run(t_end=2.0, loads=c).x, cases))
    for a, b in zip(alone, together, strict=True):
        np.testing.assert_array_equal(a, b)
    # a yielding element: the response is not proportional to the record
    assert not np.allclose(alone[-1], 6.0 * alone[0])


def test_systems_with_the_same_matrices_share_their_set_up_bit_for_bit() -> None:
    # Distinct matrices from every other test, so what is shared is made here.
    k = K * (1.0 + 1e-7)
    first = duhamel.System(np.eye(N), k, zeta=0.02)
    b3, b_all = first.modal(3), first.modal(None)  # 3 modes first, then grown to all
    second = duhamel.System(np.eye(N), k, zeta=0.02)
    # The second system's first analysis (all modes) is its own, not the first's grown one:
    # what a fresh system computes never depends on what other systems did. The reference
    # is computed without anything shared.
    from duhamel._engine.basis import _checked_modal

    reference = _checked_modal(duhamel.System(np.eye(N), k, zeta=0.02), N)
    np.testing.assert_array_equal(second.modal(None).phi, reference.phi)
    np.testing.assert_array_equal(second.modal(None).omega2, reference.omega2)
    third = duhamel.System(np.eye(N), k, zeta=0.02)
    np.testing.assert_array_equal(third.modal(3).phi, b3.phi)
    assert b_all.n_modes == N
    # a different damping gives its own modal damping on the same modes
    other = duhamel.System(np.eye(N), k, zeta=0.07)
    np.testing.assert_array_equal(other.modal(3).phi, b3.phi)
    np.testing.assert_allclose(other.modal(3).zeta, 0.07)

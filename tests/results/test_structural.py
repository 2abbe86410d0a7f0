"""Structural outputs (issue 13): element histories, absolute accelerations, drifts."""

from __future__ import annotations

import numpy as np
import pytest

import duhamel
from duhamel import elements as E
from duhamel import loads as L

T_REC = np.linspace(0.0, 3.0, 601)
A_REC = 3.0 * np.sin(2 * np.pi * 1.7 * T_REC) * np.exp(-0.3 * T_REC)


def chain(n: int = 4, k: float = 400.0) -> tuple[np.ndarray, np.ndarray]:
    K = k * (2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1))
    K[-1, -1] = k
    return np.eye(n), K


@pytest.mark.parametrize("solver", ["auto", "modal-newton"])
def test_element_histories_are_the_elements_forces(solver: str) -> None:
    M, K = chain()
    s = duhamel.System(M, K, zeta=0.03)
    s.add(E.Cubic(0, k3=2e5))
    s.add(E.Spring(1, 3, k=50.0, k3=1e4))
    s.add(E.Damper(2, None, c=1.5))
    s.add(E.LinearCoupling(K=0.1 * K))  # a coupling, not a force element: not listed
    s.add_load(L.BaseAcceleration(np.ones(4), t=T_REC, values=A_REC))
    sol = duhamel.solve(s, duhamel.Semianalytic(solver=solver), t_end=2.0, dt=0.005)
    assert len(sol.elements) == 3
    cubic, spring, damper = sol.elements
    assert cubic.element is s.elements[0]
    # the element states are the physical response at their dofs
    np.testing.assert_allclose(cubic.x[:, 0], sol.x[:, 0], rtol=0, atol=1e-12)
    np.testing.assert_allclose(spring.x, sol.x[:, [1, 3]], rtol=0, atol=1e-12)
    np.testing.assert_allclose(damper.v[:, 0], sol.v[:, 2], rtol=0, atol=1e-12)
    # and the forces their constitutive laws
    np.testing.assert_allclose(cubic.force[:, 0], 2e5 * sol.x[:, 0] ** 3, rtol=1e-12, atol=0)
    d = sol.x[:, 1] - sol.x[:, 3]
    np.testing.assert_allclose(spring.deformation, d, rtol=0, atol=1e-12)
    np.testing.assert_allclose(spring.axial_force, 50.0 * d + 1e4 * d**3, rtol=1e-11, atol=1e-14)
    np.testing.assert_allclose(spring.force[:, 1], -spring.force[:, 0], rtol=0, atol=0)
    np.testing.assert_allclose(damper.axial_force, 1.5 * sol.v[:, 2], rtol=1e-12, atol=1e-15)
    assert cubic.t is not None and cubic.t.shape == sol.t.shape


def test_element_histories_plot() -> None:
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    s = duhamel.System(np.eye(1), 40.0 * np.eye(1), zeta=0.05).add(E.Cubic(0, k3=1e3))
    sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=1.0, dt=0.01, x0=[0.2])
    ax = sol.elements[0].plot()
    x, y = ax.lines[0].get_data()
    np.testing.assert_allclose(y, 1e3 * np.asarray(x) ** 3, rtol=1e-12)


def test_partial_run_keeps_element_rows_of_the_kept_steps() -> None:
    M, K = chain()
    s = duhamel.System(M, K, zeta=0.03).add(E.Cubic(0, k3=1e9))
    s.add_load(L.BaseAcceleration(np.ones(4), t=T_REC, values=30 * A_REC))
    with pytest.raises(duhamel.SolverError) as err:
        duhamel.solve(s, duhamel.Semianalytic(max_iter=1, subdivisions=0), t_end=2.0, dt=0.01)
    part = err.value.partial
    assert part.elements and part.elements[0].x.shape[0] == part.t.size
    np.testing.assert_allclose(part.elements[0].x[:, 0], part.x[:, 0], rtol=0, atol=1e-12)


def test_absolute_acceleration_is_the_equation_of_motion() -> None:
    """m (x'' + a_g) + c x' + k x + r(x) = 0: the absolute acceleration of an SDOF is
    -(c v + k x + r) / m, whatever the record."""
    m, k, zeta = 2.0, 800.0, 0.04
    c = 2 * zeta * np.sqrt(k * m)
    s = duhamel.System(np.array([[m]]), np.array([[k]]), zeta=zeta).add(E.Cubic(0, k3=5e4))
    s.add_load(L.BaseAcceleration(np.ones(1), t=T_REC, values=A_REC))
    sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=2.5, dt=0.005)
    want = -(c * sol.v[:, 0] + k * sol.x[:, 0] + 5e4 * sol.x[:, 0] ** 3) / m
    scale = np.abs(want).max()
    np.testing.assert_allclose(sol.a_absolute[:, 0], want, rtol=0, atol=1e-9 * scale)
    # without support excitation the absolute acceleration is the relative one
    free = duhamel.solve(
        duhamel.System(np.eye(1), np.eye(1)),
        duhamel.Semianalytic(),
        t_end=1.0,
        dt=0.1,
        x0=[1.0],
    )
    np.testing.assert_array_equal(free.a_absolute, free.a)


def test_drifts() -> None:
    M, K = chain()
    s = duhamel.System(M, K, zeta=0.03)
    s.add_load(L.BaseAcceleration(np.ones(4), t=T_REC, values=A_REC))
    sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=1.0, dt=0.01)
    d = sol.drifts([0, 1, 2, 3])
    np.testing.assert_array_equal(d[:, 0], sol.x[:, 0])
    np.testing.assert_array_equal(d[:, 2], sol.x[:, 2] - sol.x[:, 1])
    ratios = sol.drifts([0, 1, 2, 3], heights=[4.0, 3.0, 3.0, 3.0])
    np.testing.assert_allclose(ratios[:, 0], sol.x[:, 0] / 4.0)
    part = duhamel.solve(s, duhamel.Semianalytic(), t_end=1.0, dt=0.01, dofs=[0, 2])
    with pytest.raises(ValueError, match="`floors`: dof 1"):
        part.drifts([0, 1, 2])
    with pytest.raises(ValueError, match="`heights`"):
        sol.drifts([0, 1], heights=[3.0, -1.0])
    with pytest.raises(TypeError, match="`floors`"):
        sol.drifts([0.5])  # type: ignore[list-item]

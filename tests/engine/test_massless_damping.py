"""Damping at massless dofs (issue 36): a massless dof that the damping matrix reaches obeys
a first-order equation, not the static relation. Against closed forms (the exponential
relaxation of a dashpot and spring) and against the exact first-order system
(``scipy.signal.lsim`` of the descriptor equations, exact for piecewise-linear loads), with
convergence orders measured as slopes; a hinged frame against Newmark on the full
singular-mass model; what ``damping_summary`` says; refusals.
"""

from __future__ import annotations

import numpy as np
import pytest
from _frames import moment_frame
from scipy.signal import lsim

import duhamel

# a dof with mass (uncoupled) and a massless dof on a spring k and a dashpot c
K_S, C_S, F = 400.0, 40.0, 3.0
TAU = C_S / K_S


def _relaxation(**damping: object) -> duhamel.System:
    M = np.diag([2.0, 0.0])
    K = np.diag([50.0, K_S])
    return duhamel.System(M, K, **damping).add_load(duhamel.loads.Step(1, amplitude=F))  # type: ignore[arg-type]


@pytest.mark.parametrize(
    "damping",
    [dict(C=np.diag([0.3, C_S])), dict(rayleigh=(0.5, TAU))],
    ids=["matrix", "rayleigh"],
)
def test_massless_dashpot_and_spring_relax_exactly(damping: dict) -> None:
    """``c x' + k x = F``: ``x = F/k (1 - exp(-t k/c))``, ``x' = F/c exp(-t k/c)``, to
    round-off at a step of 0.4 time constants (the quasi-static treatment gave ``F/k`` at
    once)."""
    system = _relaxation(**damping)
    summary = system.damping_summary().massless
    assert "first-order" in summary
    for dt in (0.04, 0.013):
        sol = duhamel.solve(system, duhamel.Semianalytic(), t_end=1.0, dt=dt)
        x = F / K_S * (1 - np.exp(-sol.t / TAU))
        v = F / C_S * np.exp(-sol.t / TAU)
        assert np.abs(sol.x[:, 1] - x).max() <= 1e-13 * F / K_S
        assert np.abs(sol.v[1:, 1] - v[1:]).max() <= 1e-12 * F / C_S
        assert np.abs(sol.x[:, 0]).max() == 0.0
    # Newmark converges to it at second order (its start velocity F/c from the equation)
    errors = []
    steps = (0.02, 0.01, 0.005)
    for dt in steps:
        sol = duhamel.solve(system, duhamel.Newmark(), t_end=1.0, dt=dt)
        assert sol.v[0, 1] == pytest.approx(F / C_S, rel=1e-12)
        errors.append(np.abs(sol.x[:, 1] - F / K_S * (1 - np.exp(-sol.t / TAU))).max())
    slopes = np.diff(np.log(errors)) / np.diff(np.log(steps))
    assert np.all(slopes > 1.9), slopes


# three dofs, two with mass, a general damping matrix reaching the massless one
M3 = np.diag([1.0, 2.0, 0.0])
K3 = np.array([[30.0, -10.0, 5.0], [-10.0, 20.0, -4.0], [5.0, -4.0, 12.0]])
C3 = np.array([[0.3, -0.1, 0.05], [-0.1, 0.2, -0.06], [0.05, -0.06, 0.4]])
T3 = np.linspace(0.0, 4.0, 4001)
F3 = np.sin(3 * T3) + 0.5 * np.cos(7 * T3)


def _descriptor(C: np.ndarray, dof: int, t: np.ndarray) -> np.ndarray:
    """The exact response of ``M x'' + C x' + K x = e_dof f(t)`` with the massless dof 2
    first-order: the state ``(x0, x1, v0, v1, x2)``, ``x2' = (f_2 - K_2 x - C_2m v) / C_22``
    substituted in the mass rows; ``lsim`` (exact for a load piecewise linear between the
    instants `t`, a subset of the table's ``T3``) on the table's instants, kept at `t`."""
    e = np.eye(3)[dof]
    A, B = np.zeros((5, 5)), np.zeros((5, 1))
    A[0, 2] = A[1, 3] = 1.0
    row = np.zeros(5)
    row[[0, 1, 4]] = -K3[2]
    row[[2, 3]] = -C[2, :2]
    row, b2 = row / C[2, 2], e[2] / C[2, 2]
    A[4], B[4, 0] = row, b2
    for i in range(2):
        r = np.zeros(5)
        r[[0, 1, 4]] = -K3[i]
        r[[2, 3]] -= C[i, :2]
        A[2 + i] = (r - C[i, 2] * row) / M3[i, i]
        B[2 + i, 0] = (e[i] - C[i, 2] * b2) / M3[i, i]
    out = lsim((A, B, np.eye(5), np.zeros((5, 1))), F3, T3)[2][:, [0, 1, 4]]
    return out[np.round(t / (T3[1] - T3[0])).astype(int)]


@pytest.mark.parametrize("dof", [0, 2], ids=["load at a mass", "load at the massless dof"])
def test_coupled_massless_damping_converges_to_the_first_order_system(dof: int) -> None:
    """A damping matrix coupling the massless dof to the modes: Semianalytic (the coupling
    a pseudo-force) and Newmark converge to the exact first-order system at second order
    (Newmark too at the massless dof: it starts from the velocity of its first-order
    equation; from rest there, it converged at first order)."""
    system = duhamel.System(M3, K3, C=C3).add_load(duhamel.loads.Tabulated(dof, t=T3, values=F3))
    steps = (0.02, 0.01, 0.005)
    found = {}
    for integrator in (duhamel.Semianalytic(), duhamel.Newmark()):
        errors = []
        for dt in steps:
            sol = duhamel.solve(system, integrator, t_end=3.9, dt=dt)
            ref = _descriptor(C3, dof, sol.t)
            errors.append(np.abs(sol.x - ref).max() / np.abs(ref).max())
        slopes = np.diff(np.log(errors)) / np.diff(np.log(steps))
        assert np.all(slopes > 1.8), (type(integrator).__name__, errors, slopes)
        found[type(integrator).__name__] = errors
    # measured: Semianalytic 1.4e-5 / 4.5e-6, Newmark 3.4e-4 / 1.8e-4 at dt = 0.005
    assert found["Semianalytic"][-1] < 0.1 * found["Newmark"][-1]


def test_rayleigh_at_massless_dofs_is_exact_on_the_linear_route() -> None:
    """Rayleigh damping ``alpha M + beta K``: the massless dof relaxes with ``beta``, uncoupled
    from the modes; the linear route integrates it exactly (a load at the massless dof)."""
    alpha, beta = 0.2, 0.03
    C = alpha * M3 + beta * K3
    system = duhamel.System(M3, K3, rayleigh=(alpha, beta))
    system.add_load(duhamel.loads.Tabulated(2, t=T3, values=F3))  # linear within each step
    sol = duhamel.solve(system, duhamel.Semianalytic(), t_end=3.9, dt=T3[1] - T3[0])
    ref = _descriptor(C, 2, sol.t)
    assert np.abs(sol.x - ref).max() <= 1e-10 * np.abs(ref).max()
    assert "beta K" in system.damping_summary().massless


@pytest.mark.parametrize("form", ["rayleigh", "matrix"])
def test_hinge_at_a_damped_massless_rotation_against_newmark(form: str) -> None:
    """A Bilinear hinge at a massless base rotation of a frame with Rayleigh damping (as
    coefficients: uncoupled; as a matrix on the FNA background K plus the hinge: coupled to
    the modes) against Newmark on the full singular-mass model at dt/64, to 1e-4 of the
    peak. The static treatment of the massless dofs missed by 3e-4 with these
    coefficients."""
    M, K, sway = moment_frame(3, 2)
    s = np.flatnonzero(np.diag(M) == 0)
    dt = 0.01
    t = np.arange(0.0, 3.0, dt)
    ag = 6.0 * np.sin(2 * np.pi * 1.2 * t) * np.exp(-0.2 * t)
    r = np.zeros(M.shape[0])
    r[sway] = 1.0
    damping = {"rayleigh": (0.3, 0.002)} if form == "rayleigh" else {"C": 0.3 * M + 0.002 * K}
    system = duhamel.System(M, K, **damping)  # type: ignore[arg-type]
    system.add_load(duhamel.loads.BaseAcceleration(r, t=t, values=ag))
    hinge = duhamel.elements.Bilinear(int(s[0]), None, k=5e7, fy=2e5, alpha=0.02)
    system.add(hinge)
    ref = duhamel.solve(system, duhamel.Newmark(), t_end=2.9, dt=dt / 64, save_every=64)
    assert np.abs(ref.x[:, hinge.i]).max() * hinge.k > 1.5 * hinge.fy  # it yields
    sol = duhamel.solve(system, duhamel.Semianalytic(), t_end=2.9, dt=dt / 4, save_every=4)
    assert np.abs(sol.x - ref.x).max() <= 1e-4 * np.abs(ref.x).max()
    assert sol.stats.coupling == (None if form == "rayleigh" else "pseudo-force")


def test_element_at_a_damped_massless_dof_converges_to_it_in_the_stiffness() -> None:
    """A linear Spring at a damped massless dof, stepped as a pseudo-force, converges at
    second order to the same spring written into K (the exact linear route)."""
    M, K, _ = moment_frame(3, 1)
    s = np.flatnonzero(np.diag(M) == 0)
    t = np.arange(0.0, 2.0, 0.01)
    moment = duhamel.loads.Tabulated(int(s[1]), t=t, values=4e4 * np.sin(5.0 * t))
    k = 3e7
    stiff = K.copy()
    stiff[s[1], s[1]] += k
    C = 0.4 * M + 0.003 * K  # the same matrix in both
    exact = duhamel.System(M, stiff, C=C).add_load(moment)
    ref = duhamel.solve(exact, duhamel.Newmark(), t_end=1.9, dt=0.01 / 256, save_every=256)
    spring = duhamel.System(M, K, C=C).add_load(moment)
    spring.add(duhamel.elements.Spring(int(s[1]), None, k=k))
    integrator = duhamel.Semianalytic(linear_parts="pseudo-force")
    errors = []
    for sub in (2, 4, 8):
        sol = duhamel.solve(spring, integrator, t_end=1.9, dt=0.01 / sub, save_every=sub)
        errors.append(np.abs(sol.x - ref.x).max() / np.abs(ref.x).max())
    slopes = -np.diff(np.log(errors)) / np.log(2.0)
    assert np.all(slopes > 1.8), (errors, slopes)


def test_damping_summary_of_massless_dofs() -> None:
    M, K, _ = moment_frame(2, 1)
    assert "static" in duhamel.System(M, K, zeta=0.05).damping_summary().massless
    assert (
        "beta = 0.002 s" in duhamel.System(M, K, rayleigh=(0.3, 0.002)).damping_summary().massless
    )
    summary = duhamel.System(M, K, C=0.3 * M + 0.002 * K).damping_summary()
    assert "damped by C" in summary.massless and "massless dofs: " in str(summary)
    # the massless dofs' relaxation, coupled by C = alpha M + beta K on the modes of K,
    # leaves the modal ratios (alpha / omega + beta omega) / 2
    basis = duhamel.System(M, K).modal()
    np.testing.assert_allclose(
        summary.zeta, (0.3 / basis.omega + 0.002 * basis.omega) / 2, rtol=1e-6
    )
    assert duhamel.System(np.eye(2), np.eye(2)).damping_summary().massless == ""


def test_refusals() -> None:
    M, K, _ = moment_frame(2, 1)
    s = np.flatnonzero(np.diag(M) == 0)
    hinge = duhamel.elements.Spring(int(s[0]), None, k=1e7)
    negative = duhamel.System(M, K, rayleigh=(0.3, -0.001)).add(hinge)
    with pytest.raises(ValueError, match=r"`rayleigh`: beta = .* < 0"):
        duhamel.solve(negative, duhamel.Semianalytic(), t_end=0.1, dt=0.01)
    C = 0.002 * K
    C[s[0], s[0]] -= 0.004 * K[s[0], s[0]]
    with pytest.raises(ValueError, match="`C` is negative at the massless dofs"):
        duhamel.System(M, K, C=C).damping_summary()
    law = duhamel.System(M, K, rayleigh=(0.3, 0.001)).add(hinge)
    law.set_mass_law(duhamel.mass.Exponential(rate=-0.1))
    with pytest.raises(ValueError, match="mass law"):
        duhamel.solve(law, duhamel.Semianalytic(), t_end=0.1, dt=0.01)
    damped = duhamel.System(M, K, rayleigh=(0.3, 0.001)).add(hinge)
    with pytest.raises(ValueError, match="`coupling`='exact' is not taken"):
        duhamel.solve(
            duhamel.System(M, K, C=0.3 * M + 0.001 * K).add(hinge),
            duhamel.Semianalytic(coupling="exact"),
            t_end=0.1,
            dt=0.01,
        )
    # Rayleigh: only the driven massless directions are coordinates; a run's own load or an
    # initial state in another direction is refused (its first-order motion is not held)
    prepared = duhamel.prepare(damped, duhamel.Semianalytic(), dt=0.01)
    with pytest.raises(ValueError, match="`loads`: Step acts at damped massless dofs"):
        prepared.run(t_end=0.1, loads=[duhamel.loads.Step(int(s[1]), amplitude=1e3)])
    x0 = np.zeros(M.shape[0])
    x0[s[1]] = 1e-3
    with pytest.raises(ValueError, match="`x0` moves the massless dofs"):
        prepared.run(t_end=0.1, x0=x0)
    # a load in the held direction runs
    assert (
        prepared.run(t_end=0.1, loads=[duhamel.loads.Step(int(s[0]), amplitude=1e3)]).x.shape[0]
        == 11
    )


def test_streamed_run_with_damping_at_massless_dofs_refused(tmp_path) -> None:
    pytest.importorskip("zarr")
    M, K, sway = moment_frame(2, 1)
    C = 0.3 * M + 0.002 * K
    C[np.ix_(sway, sway)] *= 1.5  # non-proportional: the massless dofs couple to the modes
    system = duhamel.System(M, K, C=C).add_load(duhamel.loads.Step(int(sway[0]), amplitude=1e3))
    with pytest.raises(ValueError, match=r"`store`.*damping matrix `C` that reaches"):
        duhamel.solve(
            system, duhamel.Semianalytic(), t_end=0.1, dt=0.01, store=str(tmp_path / "r.zarr")
        )

"""Newton in the space of the elements' dofs against the dense modal Newton.

The step equation of the pseudo-force route can be solved on all modal coordinates
(``solver="modal-newton"``, the reference) or, when the elements act on fewer dofs than
there are modes, in those dofs (``solver="newton"`` and ``"auto"``). Both solve the same
equation: on random small systems with every element type, every scheme, with and without
a mass law, their histories agree to 1e-12 of the response.
"""

from __future__ import annotations

import numpy as np
import pytest

import duhamel
from duhamel import elements as E
from duhamel import loads as L
from duhamel import mass

N = 12


def _random_system(seed: int, element_kind: str) -> duhamel.System:
    rng = np.random.default_rng(seed)
    a = rng.standard_normal((N, N))
    m = np.eye(N) + 0.1 * (a @ a.T) / N
    links = 1e3 * (1.0 + rng.random(N))
    k = np.diag(links + np.r_[links[1:], 0.0]) - np.diag(links[1:], 1) - np.diag(links[1:], -1)
    system = duhamel.System(m, k, rayleigh=(0.5, 1e-4))
    system.add_load(L.Harmonic(N - 1, amplitude=50.0, omega=25.0))
    system.add_load(L.Step(3, amplitude=20.0))
    dofs = rng.choice(N, size=3, replace=False).tolist()
    if element_kind == "cubic":
        for d in dofs:
            system.add(E.Cubic(d, k3=1e7 * (1.0 + rng.random())))
    elif element_kind == "polynomial":
        system.add(E.Polynomial(dofs[0], coefficients=[0.0, 200.0, 3e4, 1e7]))
    elif element_kind == "spring":
        system.add(E.Spring(dofs[0], dofs[1], k=300.0, k3=5e7))
        system.add(E.Spring(dofs[2], None, k=100.0, k3=1e7))
    elif element_kind == "damper":
        system.add(E.Damper(dofs[0], dofs[1], c=3.0))
        system.add(E.Cubic(dofs[2], k3=1e7))
    elif element_kind == "contact":
        system.add(E.Contact((dofs[0], dofs[1]), clearance=0.01, stiffness=1e5, friction=0.1))
    elif element_kind == "bilinear":
        # one hysteretic element on one dof: the lean element-space step (issue 42)
        system.add(E.Bilinear(dofs[0], k=500.0, fy=2.0, alpha=0.1))
    elif element_kind == "callable":

        def fn(x, v, t):
            return np.array([2e7 * x[0] ** 3 + 0.5 * v[0], 1e7 * x[1] ** 3])

        def jac(x, v, t):
            return np.diag([6e7 * x[0] ** 2, 3e7 * x[1] ** 2]), np.diag([0.5, 0.0])

        system.add(E.Callable(dofs[:2], fn, jacobian=jac))
    return system


KINDS = ["cubic", "polynomial", "spring", "damper", "contact", "callable", "bilinear"]


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("scheme", ["a", "b", "c"])
@pytest.mark.parametrize("law", [None, "acceleration", "momentum", "scaled"])
def test_element_space_newton_equals_the_modal_newton(kind, scheme, law):
    seed = KINDS.index(kind) * 7 + ord(scheme)
    system = _random_system(seed, kind)
    if law is not None:
        system.set_mass_law(
            mass.Harmonic(0.15, 40.0),
            form="momentum" if law == "momentum" else "acceleration",
            scale_stiffness=law == "scaled",
        )
    run = {"t_end": 0.4, "dt": 2e-3, "x0": np.full(N, 1e-3)}
    quadrature = "parabolic" if scheme == "c" else "trapezoid"
    out = {}
    for solver in ("newton", "modal-newton"):
        integ = duhamel.Semianalytic(
            modes=8, scheme=scheme, quadrature=quadrature, solver=solver, tol=1e-14
        )
        out[solver] = duhamel.solve(system, integ, **run)
    local, dense = out["newton"], out["modal-newton"]
    peak = np.abs(dense.x).max()
    err = max(np.abs(local.x - dense.x).max(), np.abs(local.v - dense.v).max() * run["dt"])
    assert err <= 1e-12 * peak, f"{kind}/{scheme}/{law}: {err / peak:.2e}"
    assert np.abs(local.a - dense.a).max() <= 1e-10 * np.abs(dense.a).max()


@pytest.mark.parametrize("scale", ["constant", "run-up"])
@pytest.mark.parametrize("law", [None, "acceleration"])
def test_couplings_are_solved_with_the_elements(scale, law):
    # LinearCoupling pseudo-forces (gyroscopic and circulatory terms, constant or following
    # a run-up) are linear: solved once per step (or once per run), with the elements'
    # Newton in their dofs. Same answer as the modal Newton.
    system = _random_system(3, "spring")
    g = np.zeros((N, N))
    g[0, 1], g[1, 0], g[4, 6], g[6, 4] = 2.0, -2.0, 1.0, -1.0
    kc = np.zeros((N, N))
    kc[2, 3], kc[3, 2] = 50.0, -50.0
    speed = None if scale == "constant" else duhamel.speed.LinearRunUp(10.0, 60.0, 0.3)
    system.add(E.LinearCoupling(K=kc, C=g, scale=speed))
    if law is not None:
        system.set_mass_law(mass.Harmonic(0.15, 40.0))
    run = {"t_end": 0.3, "dt": 2e-3, "x0": np.full(N, 1e-3)}
    out = {}
    for solver in ("newton", "modal-newton"):
        integ = duhamel.Semianalytic(modes=8, coupling="pseudo-force", solver=solver, tol=1e-14)
        out[solver] = duhamel.solve(system, integ, **run)
    local, dense = out["newton"], out["modal-newton"]
    assert local.stats.coupling == "pseudo-force"
    peak = np.abs(dense.x).max()
    assert np.abs(local.x - dense.x).max() <= 1e-12 * peak


def test_estimated_mass_keeps_the_modal_newton():
    # The estimated-mass treatment couples q1 and v1 through the acceleration estimate: the
    # step stays on the modal Newton (the same path whatever the solver).
    system = _random_system(5, "cubic").set_mass_law(mass.Harmonic(0.15, 40.0))
    run = {"t_end": 0.2, "dt": 2e-3, "x0": np.full(N, 1e-3)}
    a = duhamel.solve(system, duhamel.Semianalytic(modes=8, mass_treatment="estimate"), **run)
    b = duhamel.solve(
        system,
        duhamel.Semianalytic(modes=8, mass_treatment="estimate", solver="modal-newton"),
        **run,
    )
    assert np.array_equal(a.x, b.x)


def test_the_papers_rotor_is_solved_in_its_bearing_dofs():
    # Table 1's case (beta = 0.1, xi = 0.1): gyroscopic and bearing couplings as
    # pseudo-forces, the mass law, four cubic bearing springs.
    from duhamel.paper.rotor import paper_system

    system = paper_system(0.1, 0.1)
    out = {}
    for solver in ("auto", "modal-newton"):
        integ = duhamel.Semianalytic(coupling="pseudo-force", solver=solver, tol=1e-13)
        out[solver] = duhamel.solve(system, integ, t_end=0.05, dt=1e-4)
    peak = np.abs(out["modal-newton"].x).max()
    assert np.abs(out["auto"].x - out["modal-newton"].x).max() <= 1e-11 * peak


def test_solver_choice_is_validated():
    with pytest.raises(ValueError, match=r"`solver` must be one of"):
        duhamel.Semianalytic(solver="dense")


@pytest.mark.parametrize("n_dofs", [1, 2, 3, 4, 5, 6, 7])
@pytest.mark.parametrize("law", ["acceleration", "momentum", "scaled"])
@pytest.mark.parametrize("scheme", ["a", "b", "c"])
def test_mass_law_with_constant_couplings_at_any_element_dof_count(n_dofs, law, scheme):
    # Under a mass law with constant couplings the element-space step's matrix is rebuilt
    # every step from per-node parts formed once, and its G_i with the element dof count
    # fixed at compile time (1, 2, 3, 4, 6, 8) or not (5, 7): the same answer as the modal
    # Newton for every count, form, scheme and two- or three-node rule.
    rng = np.random.default_rng(100 + n_dofs)
    system = _random_system(n_dofs, "none")
    for d in rng.choice(N, size=n_dofs, replace=False).tolist():
        system.add(E.Cubic(d, k3=1e7 * (1.0 + rng.random())))
    g = np.zeros((N, N))
    g[0, 1], g[1, 0], g[4, 6], g[6, 4] = 2.0, -2.0, 1.0, -1.0
    kc = np.zeros((N, N))
    kc[2, 3], kc[3, 2] = 50.0, -50.0
    system.add(E.LinearCoupling(K=kc, C=g))
    system.set_mass_law(
        mass.Harmonic(0.15, 40.0),
        form="momentum" if law == "momentum" else "acceleration",
        scale_stiffness=law == "scaled",
    )
    run = {"t_end": 0.3, "dt": 2e-3, "x0": np.full(N, 1e-3)}
    quadrature = "parabolic" if scheme == "c" else "trapezoid"
    out = {}
    for solver in ("newton", "modal-newton"):
        integ = duhamel.Semianalytic(
            modes=8,
            scheme=scheme,
            quadrature=quadrature,
            coupling="pseudo-force",
            solver=solver,
            tol=1e-14,
        )
        out[solver] = duhamel.solve(system, integ, **run)
    local, dense = out["newton"], out["modal-newton"]
    peak = np.abs(dense.x).max()
    err = max(np.abs(local.x - dense.x).max(), np.abs(local.v - dense.v).max() * run["dt"])
    assert err <= 1e-12 * peak, f"{n_dofs} dofs/{law}/{scheme}: {err / peak:.2e}"


def _chain(n: int = 8) -> duhamel.System:
    links = np.full(n, 1e4)
    k = np.diag(links + np.r_[links[1:], 0.0]) - np.diag(links[1:], 1) - np.diag(links[1:], -1)
    system = duhamel.System(np.eye(n), k, zeta=0.02)
    return system.add_load(L.Harmonic(n - 1, amplitude=300.0, omega=9.0))


@pytest.mark.parametrize("scheme", ["a", "b", "c"])
def test_saved_element_records_are_the_forces_at_the_saved_states(scheme):
    # The element-space step keeps its evaluation of the start state for that state's
    # record (issue 23): the saved displacement must be the structure's at that dof and
    # the force the element's there: a cubic spring by its formula, and a bilinear spring
    # by the return mapping replayed over the saved displacements (each step committed at
    # the saved end state), independent of the engine.
    # (a hardening ratio whose yield the watch does not subdivide: a substep commits too)
    k3, (kb, fy, alpha) = 2e9, (3e3, 4.0, 0.3)
    one = _chain().add(E.Cubic(2, k3=k3))
    two = _chain().add(E.Cubic(2, k3=k3)).add(E.Bilinear(5, k=kb, fy=fy, alpha=alpha))
    # the bilinear spring alone: the lean step, which commits its end node's trial
    # variables and reuses that force at the next start (issue 42)
    alone = _chain().add(E.Bilinear(5, k=kb, fy=fy, alpha=alpha))
    for system in (one, two, alone):
        if system is alone:
            sol = duhamel.solve(system, duhamel.Semianalytic(scheme=scheme), t_end=1.0, dt=2e-3)
            _check_bilinear_record(sol.elements[0], sol.x[:, 5], kb, fy, alpha)
            continue
        sol = duhamel.solve(system, duhamel.Semianalytic(scheme=scheme), t_end=1.0, dt=2e-3)
        cubic = sol.elements[0]
        x = cubic.x[:, 0]
        peak_x = np.abs(sol.x[:, 2]).max()
        np.testing.assert_allclose(x, sol.x[:, 2], rtol=0, atol=1e-13 * peak_x)
        np.testing.assert_allclose(cubic.force[:, 0], k3 * x**3, rtol=1e-12, atol=0)
        if system is two:
            assert sol.stats.subdivided_steps == 0
            _check_bilinear_record(sol.elements[1], sol.x[:, 5], kb, fy, alpha)


def _check_bilinear_record(bil, x, kb, fy, alpha):
    # the saved displacements are the structure's, and the forces the return mapping's
    # replayed over them (each step committed at its saved end state)
    u = bil.x[:, 0]
    np.testing.assert_allclose(u, x, rtol=0, atol=1e-13 * np.abs(x).max())
    force = np.zeros_like(u)
    u_c, f_c = 0.0, 0.0
    for i, ui in enumerate(u):
        trial = f_c + kb * (ui - u_c)
        line, band = alpha * kb * ui, (1 - alpha) * fy
        force[i] = min(max(trial, line - band), line + band)
        u_c, f_c = ui, force[i]
    assert np.abs(force).max() >= fy  # it yields
    np.testing.assert_allclose(bil.force[:, 0], force, rtol=0, atol=1e-12 * fy)


def test_saving_every_step_changes_no_result_of_a_subdivided_run():
    # The stiffness watch reuses the converged end state's tangents; a saved state's
    # record in between must not change what it decides (issue 23): a stop stiff enough to
    # subdivide, saved every step or every fifth, takes the same substeps to the same bits.
    system = _chain().add(E.Gap(7, None, gap=0.02, k=1e8))
    runs = [
        duhamel.solve(system, duhamel.Semianalytic(), t_end=1.0, dt=2e-3, save_every=every)
        for every in (1, 5)
    ]
    assert runs[0].stats.subdivided_steps > 0
    assert runs[0].stats.subdivided_steps == runs[1].stats.subdivided_steps
    assert runs[0].stats.newton_iterations == runs[1].stats.newton_iterations
    np.testing.assert_array_equal(runs[0].x[::5], runs[1].x)
    np.testing.assert_array_equal(runs[0].elements[0].force[::5], runs[1].elements[0].force)

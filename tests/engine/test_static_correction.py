"""Static correction of reduced bases (issue 12): the modes enriched with the static
responses to the elements' deformation forces and the load patterns. Checked against the
full model (every mode) and on properties: still uncoupled exact oscillators, exact for a
static load, converging as modes grow, dependent vectors dropped."""

from __future__ import annotations

import numpy as np
import pytest
from _models import grounded_chain

import duhamel
from duhamel import elements as E
from duhamel import loads as L
from duhamel._engine.correction import corrected

N = 60
SPRINGS = (15, 30, 45)


def chain(n: int = N, k: float = 1e6) -> np.ndarray:
    return grounded_chain(n, k)


T = np.linspace(0.0, 1.0, 1001)
AG = 3.0 * np.sin(2 * np.pi * 5 * T) * np.minimum(T / 0.5, 1.0)


def building(**damping) -> duhamel.System:
    """A chain with three stiff cubic springs (five times its links) under a base motion."""
    s = duhamel.System(np.eye(N), chain(), **damping)
    for d in SPRINGS:
        s.add(E.Spring(d, k=5e6, k3=5e13))
    s.add_load(L.BaseAcceleration(np.ones(N), t=T, values=AG))
    return s


@pytest.mark.parametrize("damping", [{"rayleigh": (0.5, 1e-4)}, {"zeta": 0.02}])
def test_the_spring_response_with_few_modes(damping) -> None:
    full = duhamel.solve(building(**damping), duhamel.Semianalytic(), t_end=1.0, dt=1e-3)
    ref = full.x[:, SPRINGS]
    errors = {}
    for correct in (False, True):
        sol = duhamel.solve(
            building(**damping),
            duhamel.Semianalytic(modes=5, static_correction=correct),
            t_end=1.0,
            dt=1e-3,
        )
        errors[correct] = np.abs(sol.x[:, SPRINGS] - ref).max() / np.abs(ref).max()
        if correct:
            # + one vector per spring and the load pattern's, less those already in the
            # span (under modal damping the springs stay pseudo-forces: the uniform base
            # load of this chain excites its first mode only)
            assert 5 + len(SPRINGS) <= sol.stats.modes <= 5 + len(SPRINGS) + 1
    print(f"\n{damping}: error at the springs with 5 modes {errors}")
    assert errors[False] > 0.3  # free-interface modes miss the local response...
    assert errors[True] < 1e-3  # ...the static responses carry it


def test_default_is_on_for_reduced_runs_with_elements() -> None:
    s = building(rayleigh=(0.5, 1e-4))
    default = duhamel.solve(s, duhamel.Semianalytic(modes=5), t_end=0.1, dt=1e-3)
    on = duhamel.solve(s, duhamel.Semianalytic(modes=5, static_correction=True), t_end=0.1, dt=1e-3)
    assert np.array_equal(default.x, on.x) and default.stats.modes == 9
    linear = duhamel.System(np.eye(N), chain(), zeta=0.02)
    linear.add_load(L.Step(10, amplitude=1.0))
    plain = duhamel.solve(linear, duhamel.Semianalytic(modes=5), t_end=0.1, dt=1e-3)
    assert plain.stats.modes == 5  # a linear run keeps its modal truncation


def test_exact_for_a_static_load() -> None:
    """Start at the static response of a step load: the exact solution stays there. The
    corrected basis holds K^-1 p, so the reduced run does too (to round-off); plain modes
    do not."""
    K = chain()
    p = np.zeros(N)
    p[37] = 5e3
    x_static = np.linalg.solve(K, p)
    out = {}
    for correct in (False, True):
        s = duhamel.System(np.eye(N), K, zeta=0.05)
        s.add_load(L.Step(37, amplitude=5e3))
        sol = duhamel.solve(
            s,
            duhamel.Semianalytic(modes=4, static_correction=correct),
            t_end=0.5,
            dt=0.01,
            x0=x_static,
        )
        out[correct] = np.abs(sol.x - x_static).max() / np.abs(x_static).max()
    print(f"\nstatic load, 4 modes: {out}")
    assert out[True] < 1e-13
    assert out[False] > 1e-2


def test_converges_to_the_full_model_as_modes_grow() -> None:
    full = duhamel.solve(building(rayleigh=(0.5, 1e-4)), duhamel.Semianalytic(), t_end=1.0, dt=1e-3)
    ref = full.x[:, SPRINGS]
    errors = []
    for m in (3, 10, 30, 50):
        sol = duhamel.solve(
            building(rayleigh=(0.5, 1e-4)),
            duhamel.Semianalytic(modes=m, static_correction=True),
            t_end=1.0,
            dt=1e-3,
        )
        errors.append(np.abs(sol.x[:, SPRINGS] - ref).max() / np.abs(ref).max())
    print(f"\nerrors at the springs, 3/10/30/50 modes + correction: {errors}")
    assert errors[-1] < errors[0] / 10
    assert errors[-1] < 1e-6


def test_the_enriched_basis_is_modal() -> None:
    """M-orthonormal, K diagonal on it (uncoupled oscillators), Ritz values the Rayleigh
    quotients; a load pattern already in the modes' span adds nothing."""
    s = building(rayleigh=(0.5, 1e-4))
    run = duhamel.Semianalytic(modes=6)
    from duhamel._engine.background import background

    system = background(s, run.linear_parts).system
    basis = corrected(system, system.modal(6))
    phi = basis.phi
    assert np.abs(phi.T @ phi - np.eye(phi.shape[1])).max() < 1e-12
    k = phi.T @ system.K @ phi
    assert np.abs(k - np.diag(basis.omega2)).max() < 1e-8 * basis.omega2.max()
    assert np.all(np.diff(basis.omega2) >= 0)
    # Every dof loaded: the correction vectors span what is left; none beyond n_dof.
    small = duhamel.System(np.eye(4), chain(4), zeta=0.02)
    for d in range(4):
        small.add(E.Cubic(d, k3=1.0))
    b = corrected(small, small.modal(2))
    assert b.n_modes == 4
    assert np.abs(b.phi.T @ b.phi - np.eye(4)).max() < 1e-12


def test_free_free_model() -> None:
    """Rigid-body modes (singular K): the static responses are taken off them; the run is
    finite and the correction still helps at the spring (a harmonic load switched on at
    t = 0 also rings the lightly damped truncated modes, which no static vector holds)."""
    K = chain(20, 1e4)
    K[0, 0] -= 1e4  # free at both ends
    model = duhamel.System(np.eye(20), K, rayleigh=(0.2, 0.0)).add(E.Spring(3, 9, k=1e5, k3=1e9))
    model.add_load(L.Harmonic(12, amplitude=10.0, omega=3.0))
    full = duhamel.solve(model, duhamel.Semianalytic(), t_end=2.0, dt=2e-3)
    errors = {}
    for correct in (False, True):
        sol = duhamel.solve(
            model, duhamel.Semianalytic(modes=4, static_correction=correct), t_end=2.0, dt=2e-3
        )
        assert np.all(np.isfinite(sol.x))
        d, d_ref = sol.x[:, 3] - sol.x[:, 9], full.x[:, 3] - full.x[:, 9]
        errors[correct] = np.abs(d - d_ref).max() / np.abs(d_ref).max()
    print(f"\nfree-free, spring deformation with 4 modes: {errors}")
    assert errors[True] < errors[False] / 5


@pytest.mark.parametrize("mscale", [1e-300, 1.0])
def test_static_responses_that_overflow_are_dropped_not_raised(mscale: float) -> None:
    """Subnormal stiffness (1e-310): K^-1 f overflows; the refinement keeps its last finite
    iterate and overflowing directions are dropped (CI once failed here with a NaN error)."""
    K = 1e-310 * np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    s = duhamel.System(mscale * np.eye(3), K).add(E.Spring(2, k=1e-310, k3=1e-310))
    with np.errstate(all="ignore"):
        sol = duhamel.solve(
            s, duhamel.Semianalytic(modes=1), t_end=1.0, dt=0.1, x0=[0.0, 0.0, 1e-3]
        )
    assert np.all(np.isfinite(sol.x))

"""The elements' linear parts in the background (issue 12): ``K`` plus a `Spring`'s ``k``,
the initial stiffness of the hysteretic elements, a friction pendulum's ``W / R`` give the
run's modes; only the remainder is a pseudo-force. The equation of motion is unchanged:
checked against the same model assembled by hand (exact for linear parts), against the
pseudo-force treatment as the step shrinks, and through the element histories."""

from __future__ import annotations

import numpy as np
import pytest
from _models import grounded_chain

import duhamel
from duhamel import elements as E
from duhamel import loads as L

N = 6


def chain(n: int = N, k: float = 100.0) -> np.ndarray:
    return grounded_chain(n, k)


def loaded(system: duhamel.System) -> duhamel.System:
    system.add_load(L.Harmonic(N - 1, amplitude=5.0, omega=9.0))
    system.add_load(L.Step(2, amplitude=1.0))
    return system


def test_a_linear_spring_is_exact_in_the_background() -> None:
    """Spring(k) with k3 = 0: the run equals the model with k assembled into K, exactly
    (both are exact linear runs), at a coarse step."""
    K = chain()
    by_hand = K.copy()
    by_hand[np.ix_([1, 4], [1, 4])] += 250.0 * np.array([[1.0, -1.0], [-1.0, 1.0]])
    by_hand[3, 3] += 80.0

    def run(stiffness: np.ndarray, beta: float, springs: bool, dt: float) -> duhamel.Solution:
        s = loaded(duhamel.System(np.eye(N), stiffness, rayleigh=(0.2, beta)))
        if springs:
            s.add(E.Spring(1, 4, k=250.0)).add(E.Spring(3, k=80.0))
        return duhamel.solve(s, duhamel.Semianalytic(), t_end=3.0, dt=dt)

    ref, sol = run(by_hand, 0.0, False, 0.05), run(K, 0.0, True, 0.05)
    assert np.abs(sol.x - ref.x).max() <= 1e-12 * np.abs(ref.x).max()
    # The element histories hold the whole force, the background's part included.
    spring = sol.elements[0]
    assert np.allclose(spring.axial_force, 250.0 * spring.deformation, rtol=1e-12, atol=0)
    # Rayleigh beta: beta (K + k) damps the background, the remainder gives back -beta k x'
    # as a pseudo-force (second order in dt); the reference has C = alpha M + beta K exactly.
    errors = []
    for dt in (0.02, 0.01):
        s = loaded(duhamel.System(np.eye(N), by_hand, C=0.2 * np.eye(N) + 1e-3 * K))
        exact = duhamel.solve(s, duhamel.Semianalytic(), t_end=3.0, dt=dt)
        damped = run(K, 1e-3, True, dt)
        errors.append(np.abs(damped.x - exact.x).max() / np.abs(exact.x).max())
    print(f"\nRayleigh beta given back as a pseudo-force: errors {errors}")
    assert errors[-1] < 1e-5
    assert errors[0] / errors[1] > 3.5  # second order


@pytest.mark.parametrize(
    "make",
    [
        lambda: E.Spring(2, 5, k=300.0, k3=4e5),
        lambda: E.Polynomial(3, coefficients=[0.0, 150.0, 0.0, 2e5]),
        lambda: E.Bilinear(2, 4, k=300.0, fy=2.0, alpha=0.1),
        lambda: E.BoucWen(1, k=200.0, fy=1.5, alpha=0.05),
        lambda: E.FrictionPendulum((0, 1), radius=0.5, mu=0.05, weight=40.0),
    ],
    ids=["spring", "polynomial", "bilinear", "bouc-wen", "friction-pendulum"],
)
@pytest.mark.parametrize("damping", [{"rayleigh": (0.3, 2e-3)}, {}])
def test_background_and_pseudo_force_converge_to_one_response(make, damping) -> None:
    """Same equation of motion, two splittings: the difference shrinks as dt^2 (both
    second-order schemes of one solution), and the element forces agree."""

    def run(parts: str, dt: float) -> duhamel.Solution:
        s = loaded(duhamel.System(np.eye(N), chain(), **damping)).add(make())
        return duhamel.solve(
            s, duhamel.Semianalytic(linear_parts=parts), t_end=2.0, dt=dt, v0=np.full(N, 0.3)
        )

    gaps = []
    for dt in (0.004, 0.002, 0.001):
        a, b = run("background", dt), run("pseudo-force", dt)
        scale = np.abs(b.x).max()
        gaps.append(np.abs(a.x - b.x).max() / scale)
        fa, fb = a.elements[0].force, b.elements[0].force
        force_gap = np.abs(fa - fb).max() / np.abs(fb).max()
    print(f"\n{make()!r} {damping}: gaps {gaps}, force gap {force_gap:.2e}")
    assert gaps[-1] < 1e-3
    slope = np.log(gaps[0] / gaps[-1]) / np.log(4)
    assert slope > 1.5, gaps
    assert force_gap < 1e-2


def test_auto_keeps_modal_damping_ratios_on_the_modes_of_k() -> None:
    s = loaded(duhamel.System(np.eye(N), chain(), zeta=0.05)).add(E.Spring(2, k=500.0, k3=1e4))
    auto = duhamel.solve(s, duhamel.Semianalytic(), t_end=1.0, dt=0.01)
    pseudo = duhamel.solve(s, duhamel.Semianalytic(linear_parts="pseudo-force"), t_end=1.0, dt=0.01)
    assert np.array_equal(auto.x, pseudo.x)
    fna = duhamel.solve(s, duhamel.Semianalytic(linear_parts="background"), t_end=1.0, dt=0.01)
    assert not np.allclose(fna.x, auto.x, rtol=1e-6, atol=0)  # other damping, by design


def test_store_runs_with_linear_parts_equal_in_memory(tmp_path) -> None:
    pytest.importorskip("zarr")

    def model() -> duhamel.System:
        s = duhamel.System(np.eye(N), chain(), rayleigh=(0.3, 1e-3))
        return loaded(s).add(E.Bilinear(2, 4, k=300.0, fy=2.0, alpha=0.1))

    kw = {"t_end": 1.0, "dt": 0.01}
    mem = duhamel.solve(model(), duhamel.Semianalytic(), **kw)
    stored = duhamel.solve(model(), duhamel.Semianalytic(), store=tmp_path / "r.zarr", **kw)
    assert np.array_equal(np.asarray(stored.x), mem.x)
    assert np.array_equal(np.asarray(stored.elements[0].force), mem.elements[0].force)


def test_the_background_is_computed_once() -> None:
    """The engine keeps a model's background in its own cache (weakly, by the model), never
    in the model object; a new element makes a new one; the entry goes with the model."""
    import gc

    from duhamel._engine import caches

    s = loaded(duhamel.System(np.eye(N), chain())).add(E.Spring(2, k=500.0, k3=1e4))
    before = dict(vars(s))
    duhamel.solve(s, duhamel.Semianalytic(modes=3), t_end=0.1, dt=0.01)
    assert vars(s).keys() == before.keys()  # nothing written into the model
    first = caches.of(s)["background"][1]
    duhamel.solve(s, duhamel.Semianalytic(modes=3), t_end=0.2, dt=0.01)
    assert caches.of(s)["background"][1] is first and 3 in first._modal_cache
    s.add(E.Cubic(4, k3=1.0))  # another element: a new background
    duhamel.solve(s, duhamel.Semianalytic(modes=3), t_end=0.1, dt=0.01)
    assert caches.of(s)["background"][1] is not first
    held = len(caches._CACHES)
    del s
    gc.collect()
    assert len(caches._CACHES) < held

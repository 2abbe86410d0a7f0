"""The substep rule of corrected reduced models counts only the static-correction
coordinates the elements can make unstable (issue 23, ``duhamel._engine.correction.resolved``).

A coordinate whose elements' largest tangent stiffness on it stays within ``2 zeta`` of its
own ``omega^2`` is stable at any ``omega dt`` (measured here on one oscillator with the
library's amplification matrices) and is stepped at ``dt``; a stiffer one, or one loaded by
an element whose tangent has no bound, is resolved in time as before. Both runs are checked
against the full model at ``dt / 16``.
"""

from __future__ import annotations

import numpy as np
import pytest

import duhamel
from duhamel import elements as E
from duhamel import loads as L
from duhamel._engine.correction import SAFE_RATIO, enriched, stiffness_ratios, substeps
from duhamel._engine.plan import plan
from duhamel.analysis import amplification_eigenvalues
from tests.engine.test_reduced_robust import AG, DT, T_END, TT, errors, fixed_chain

N = 60


def radius(h: float, a: float, zeta: float) -> float:
    """Spectral radius of the pseudo-force step on one oscillator (m = k = 1, `zeta`) with
    a linear element of stiffness `a` as its pseudo-force, at ``omega dt = h``."""
    s = duhamel.System(np.eye(1), np.eye(1), zeta=zeta).add(E.Spring(0, k=a))
    integ = duhamel.Semianalytic(linear_parts="pseudo-force", subdivisions=0)
    return float(np.abs(amplification_eigenvalues(s, integ, h)).max())


@pytest.mark.parametrize("zeta", [0.005, 0.02, 0.05])
def test_the_safe_ratio_is_stable_at_every_step(zeta) -> None:
    """Within ``SAFE_RATIO * zeta`` (either sign) the step is stable over omega dt from 0.05
    to 40, the band of the old rule (1-4) and half a period per step (pi) included; five
    times beyond, it is not, near pi."""
    h = np.concatenate([np.arange(0.05, 6.0, 0.01), [8.0, 10.0, 20.0, 40.0]])
    a = SAFE_RATIO * zeta
    for ratio in (a, -a):
        assert max(radius(x, ratio, zeta) for x in h) <= 1.0
    near_pi = np.arange(2.9, 3.4, 0.01)
    assert max(radius(x, -5.0 * a, zeta) for x in near_pi) > 1.0


def chain_with_devices(k: float) -> duhamel.System:
    """A 60-dof chain (as the issue's, 5 % damping) with a Bilinear link at mid-length and a
    Gap stop at the top, both of stiffness `k`, yielding and closing under the excitation."""
    s = duhamel.System(np.eye(N), fixed_chain(N), zeta=0.05)
    s.add(E.Bilinear(N // 2, N // 2 - 1, k=k, fy=3e-5 * k, alpha=0.05))
    s.add(E.Gap(N - 1, None, gap=0.002, k=k))
    s.add_load(L.BaseAcceleration(np.ones(N), t=TT, values=AG))
    return s


def response(x: np.ndarray, n: int) -> np.ndarray:
    return np.stack([x[:, n // 2] - x[:, n // 2 - 1], x[:, n - 1]], axis=1)


def test_the_ratio_is_the_projected_tangent() -> None:
    """stiffness_ratios: ``k |phi_i - phi_j|^2 / omega^2 - 2 zeta`` summed over the elements
    (their largest tangents: a Bilinear's k, a Gap's k), inf under an unbounded Cubic."""
    s = chain_with_devices(1e4)
    basis, omega = enriched(s, s.modal(5))
    w = np.sqrt(basis.omega2)
    cols = np.array([int(np.flatnonzero(w == v)[0]) for v in omega])
    phi = basis.phi[:, cols]
    i, j = N // 2, N // 2 - 1
    expected = 1e4 * ((phi[i] - phi[j]) ** 2 + phi[N - 1] ** 2) / omega**2 - SAFE_RATIO * 0.05
    assert np.allclose(stiffness_ratios(s, basis, cols), expected, rtol=1e-12, atol=0.0)
    s.add(E.Cubic(N // 4, k3=1e12))
    basis, omega = enriched(s, s.modal(5))
    w = np.sqrt(basis.omega2)
    cols = np.array([int(np.flatnonzero(w == v)[0]) for v in omega])
    assert np.all(np.isinf(stiffness_ratios(s, basis, cols)))


@pytest.mark.parametrize(("k", "stiff"), [(1e4, False), (1e6, True)])
def test_soft_elements_are_stepped_at_dt_and_stiff_ones_resolved(k, stiff) -> None:
    """5 modes + correction, dt = 5e-3: the three correction coordinates sit at omega dt =
    1.66, 2.19, 4.65 (the old rule: 5 internal steps whatever the elements). Elements at
    1e-2 of the link stiffness load them far below 2 zeta omega^2: one step; at the link
    stiffness they exceed it: resolved as before. Both within the issue's bound of the full
    model at dt / 16 (truncation + full model's error at dt + 1 %)."""
    s = chain_with_devices(k)
    route = plan(s, duhamel.Semianalytic(modes=5))
    assert np.allclose(route.correction * DT, [1.66, 2.19, 4.65], atol=0.01)
    assert substeps(route.correction, DT) == 5
    e = errors(s, N, 5, response)
    print(f"\nchain with devices k={k:g}: {e}")
    assert (e["substeps"] > 1) == stiff
    if not stiff:
        assert e["substeps"] == 1
    assert e["reduced"] <= e["truncation"] + e["full"] + 0.01
    # and the elements did act: the Bilinear yielded, the Gap closed
    sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=T_END, dt=DT)
    drift = response(sol.x, N)
    assert np.abs(drift[:, 0]).max() > 3e-5 and drift[:, 1].min() < -0.002


def test_a_stored_run_takes_the_same_internal_steps(tmp_path, monkeypatch) -> None:
    """A run into a store applies the same rule, and saves what the run in memory does."""
    import duhamel.store._run as stored

    seen: list[int] = []
    real = stored.substeps

    def recorded(omega, dt):
        seen.append(real(omega, dt))
        return seen[-1]

    monkeypatch.setattr(stored, "substeps", recorded)
    for k in (1e4, 1e6):
        s = chain_with_devices(k)
        integ = duhamel.Semianalytic(modes=5)
        kept = duhamel.solve(s, integ, t_end=0.1, dt=DT, store=tmp_path / f"{k:g}.zarr")
        memory = duhamel.solve(s, integ, t_end=0.1, dt=DT)
        assert np.array_equal(np.asarray(kept.x), memory.x)
        assert seen[-1] == memory.stats.substeps
    assert seen == [1, 5]


def test_an_unbounded_or_first_order_run_keeps_the_previous_rule() -> None:
    """A Python element (no bound on its tangent) keeps every coordinate it loads resolved;
    on the first-order route (an exactly integrated coupling) every coordinate is."""
    soft = chain_with_devices(1e4)
    assert plan(soft, duhamel.Semianalytic(modes=5)).resolve.size == 0
    python = chain_with_devices(1e4).add(E.Callable([N // 3], lambda x, v, t: 1e2 * x))
    route = plan(python, duhamel.Semianalytic(modes=5))
    assert route.resolve.size > 0
    assert substeps(route.resolve, DT) > 1
    G = np.zeros((N, N))
    G[0, 1], G[1, 0] = 1.0, -1.0
    coupled = chain_with_devices(1e4).add(E.LinearCoupling(C=G))
    route = plan(coupled, duhamel.Semianalytic(modes=5))
    assert route.route == "first-order"
    assert np.array_equal(route.resolve, route.correction)

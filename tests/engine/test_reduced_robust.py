"""Robust corrected reduced models (issue 23).

Two families run with ``Semianalytic(modes=m, static_correction=True)`` at the step where the
full model runs: the issue's chains (fixed at the base, three ``Cubic`` springs) and a shear
frame with a ``Bilinear`` brace, a ``Gap`` stop and a hardening ``Spring``. The reduced
model's error at ``dt`` (against the full model at ``dt / 16``, at the elements, over the
largest element peak) must stay within its own truncation error (the same reduced model at
``dt / 16``) plus the full model's error at ``dt`` plus 1 %.

The cause of the failures (a reduced run stopping with "the step equation did not converge",
or diverging with a larger ``max_iter``): the pseudo-force step is only conditionally stable
on a coordinate with ``1 <~ omega dt <~ 4`` whose own stiffness an element's tangent
exceeds, and a static-correction coordinate holds an element's whole residual flexibility
at such frequencies. The run resolves those coordinates in time (``SolveStats.substeps``).
"""

from __future__ import annotations

import numpy as np
import pytest

import duhamel
from duhamel import elements as E
from duhamel import loads as L
from duhamel._engine.correction import MAX_SUBSTEPS, substeps
from duhamel.analysis import amplification_eigenvalues

T_END = 2.0
DT = 5e-3
TT = np.linspace(0.0, T_END, 20001)
AG = 2.0 * np.sin(3 * np.pi * TT) * np.sin(np.pi * TT / 2) ** 2


def fixed_chain(n: int, k: float = 1e6) -> np.ndarray:
    """Unit masses in a row linked by `k`, the first linked to the base."""
    K = np.zeros((n, n))
    K[0, 0] = k
    for i in range(n - 1):
        K[i : i + 2, i : i + 2] += k * np.array([[1.0, -1.0], [-1.0, 1.0]])
    return K


def springs(n: int) -> tuple[int, int, int]:
    return n // 4, n // 2, 3 * n // 4


def chain(n: int, k3: float) -> duhamel.System:
    """The issue's family: three Cubic springs to ground at a quarter, half and three
    quarters of the length, 5 % modal damping, a smooth base excitation."""
    s = duhamel.System(np.eye(n), fixed_chain(n), zeta=0.05)
    for d in springs(n):
        s.add(E.Cubic(d, k3=k3))
    s.add_load(L.BaseAcceleration(np.ones(n), t=TT, values=AG))
    return s


def frame(n: int, level: float) -> duhamel.System:
    """A shear frame (unit storey masses, storey stiffness 1e6, fixed base) with a Bilinear
    brace at a quarter of the height, a Gap stop at the roof and a hardening Spring at three
    quarters, each `level` times the storey stiffness, sized on the linear frame's peaks
    (yield at half the brace's elastic peak drift, the gap half the roof's peak, the
    Spring's cubic term equal to its linear level at half its storey's peak drift)."""
    b, c = n // 4, 3 * n // 4
    linear = duhamel.System(np.eye(n), fixed_chain(n), zeta=0.05)
    linear.add_load(L.BaseAcceleration(np.ones(n), t=TT, values=AG))
    x = duhamel.solve(linear, duhamel.Semianalytic(), t_end=T_END, dt=DT).x
    db = np.abs(x[:, b] - x[:, b - 1]).max()
    dtop = np.abs(x[:, -1]).max()
    dc = np.abs(x[:, c] - x[:, c - 1]).max()
    k = 1e6 * level
    s = duhamel.System(np.eye(n), fixed_chain(n), zeta=0.05)
    s.add(E.Bilinear(b, b - 1, k=k, fy=0.5 * k * db, alpha=0.05))
    s.add(E.Gap(n - 1, None, gap=0.5 * dtop, k=k))
    s.add(E.Spring(c, c - 1, k=0.0, k3=k / (0.5 * dc) ** 2))
    s.add_load(L.BaseAcceleration(np.ones(n), t=TT, values=AG))
    return s


def chain_response(x: np.ndarray, n: int) -> np.ndarray:
    return x[:, list(springs(n))]


def frame_response(x: np.ndarray, n: int) -> np.ndarray:
    b, c = n // 4, 3 * n // 4
    return np.stack([x[:, b] - x[:, b - 1], x[:, n - 1], x[:, c] - x[:, c - 1]], axis=1)


def errors(system: duhamel.System, n: int, modes: int, at) -> dict[str, float]:
    """Errors at the elements over the largest element peak, against the full model at
    dt / 16: the full model at dt, the reduced one at dt and at dt / 16."""

    def run(dt: float, **kw) -> tuple[np.ndarray, duhamel.Solution]:
        sol = duhamel.solve(system, duhamel.Semianalytic(**kw), t_end=T_END, dt=dt)
        return at(sol.x, n), sol

    ref, _ = run(DT / 16)
    peak = np.abs(ref).max()
    full, _ = run(DT)
    reduced, sol = run(DT, modes=modes, static_correction=True)
    fine, _ = run(DT / 16, modes=modes, static_correction=True)
    return {
        "full": np.abs(full - ref[::16]).max() / peak,
        "reduced": np.abs(reduced - ref[::16]).max() / peak,
        "truncation": np.abs(fine - ref).max() / peak,
        "substeps": sol.stats.substeps,
    }


# Every chain of the issue's family that failed ("the step equation did not converge"), or
# ran outside the bound, before the correction coordinates were resolved in time.
FAILED_CHAINS = [
    (60, 1e14, 5),
    (60, 1e15, 5),
    (60, 1e15, 10),
    (120, 1e13, 10),
    (120, 1e14, 5),
    (120, 1e14, 10),
    (120, 1e15, 5),
    (120, 1e15, 10),
    (120, 1e15, 20),
    (120, 1e14, 20),  # ran, but 4.1 % off against a bound of 3.1 %
]


@pytest.mark.parametrize(("n", "k3", "modes"), FAILED_CHAINS)
def test_the_issue_chains_run_reduced_where_the_full_model_runs(n, k3, modes) -> None:
    e = errors(chain(n, k3), n, modes, chain_response)
    print(f"\nchain n={n} k3={k3:g} modes={modes}: {e}")
    assert e["substeps"] > 1
    assert e["reduced"] <= e["truncation"] + e["full"] + 0.01


def test_the_issue_headline_case_is_as_good_as_the_full_model() -> None:
    """120 dofs, k3 = 1e12, 10 modes ran before too (1.6 % against the full model's 1.8 %
    in the issue): it stays as good."""
    e = errors(chain(120, 1e12), 120, 10, chain_response)
    print(f"\nchain 120, 1e12, 10 modes: {e}")
    assert e["reduced"] <= e["full"]


# Frames whose reduced run at dt added 3-17 % of the largest element peak beyond its own
# truncation error and the full model's error at dt before the fix.
FAILED_FRAMES = [
    (40, 1.0, 5),
    (40, 3.0, 5),
    (80, 1.0, 5),
    (80, 1.0, 10),
    (80, 3.0, 5),
    (80, 3.0, 10),
]


@pytest.mark.parametrize(("n", "level", "modes"), FAILED_FRAMES)
def test_shear_frame_with_devices(n, level, modes) -> None:
    e = errors(frame(n, level), n, modes, frame_response)
    print(f"\nframe n={n} level={level:g} modes={modes}: {e}")
    assert e["substeps"] > 1
    assert e["reduced"] <= e["truncation"] + e["full"] + 0.01


def test_the_cause_one_oscillator() -> None:
    """The pseudo-force step on one oscillator (zeta 0.05) with a linear element of `ratio`
    times its stiffness as a pseudo-force: unstable at intermediate omega dt, stable when the
    oscillator is resolved (omega dt <= 1, ratio 10) or stiff (omega dt >= 4, any ratio).
    An element at least twice the background's stiffness is watched by the stiffness check
    (docs/nonlinear.md, "Stiff elements"): its step is subdivided, or the run stops."""

    def radius(h: float, ratio: float, subdivisions: int = 4) -> float:
        s = duhamel.System(np.eye(1), np.eye(1), zeta=0.05).add(E.Spring(0, k=ratio))
        integ = duhamel.Semianalytic(linear_parts="pseudo-force", subdivisions=subdivisions)
        lam = amplification_eigenvalues(s, integ, h)
        return float(np.abs(lam).max())

    assert radius(2.5, 1.0) > 1.2  # below the check's ratio 2: the plain step, unstable
    with pytest.raises(duhamel.SolverError) as err:  # the plain step would be (2.15)
        radius(1.5, 10.0, subdivisions=0)
    assert err.value.reason == "stiffness" and "element 0" in str(err.value)
    assert radius(1.5, 10.0) < 1.0  # subdivided by the check
    assert radius(1.0, 10.0) < 1.0
    for h in (4.0, 10.0, 100.0):  # stable, or stopped by the check (never silently wrong)
        try:
            assert radius(h, 1e4) < 1.0
        except duhamel.SolverError as exc:
            assert exc.reason == "stiffness"


def test_the_cause_on_the_reduced_basis(monkeypatch) -> None:
    """The issue's 120-dof chain, k3 = 1e14, 10 modes: its four correction coordinates sit
    at omega dt = 1.6-2.8; at the springs' largest tangent before the divergence (1.35e6)
    their stiffness ratios k_t phi_d^2 / omega^2 are 0.27-1.5, where one oscillator's step
    is unstable. Resolved in time (3 internal steps, omega dt <= 0.94) they are stable.
    Stepped at dt (the rule switched off), the stiffness check stops the run where the
    springs dominate the coordinates they load, or subdivides those steps: either way no
    divergence goes unseen, and the subdivided run agrees with the resolved one."""
    import duhamel._engine.modal as modal
    from duhamel._engine.correction import enriched

    s = chain(120, 1e14)
    _, omega = enriched(s, s.modal(10))
    assert np.allclose(omega * DT, [1.64, 2.10, 2.30, 2.81], atol=0.01)
    resolved = duhamel.solve(s, duhamel.Semianalytic(modes=10), t_end=T_END, dt=DT)
    assert resolved.stats.substeps == 3
    monkeypatch.setattr(modal, "substeps", lambda omega, dt: 1)
    with pytest.raises(duhamel.SolverError) as err:
        duhamel.solve(s, duhamel.Semianalytic(modes=10, subdivisions=0), t_end=T_END, dt=DT)
    assert err.value.reason == "stiffness" and 0.2 < err.value.time < 0.7
    assert "too stiff for the step" in str(err.value)
    halved = duhamel.solve(s, duhamel.Semianalytic(modes=10), t_end=T_END, dt=DT)
    assert halved.stats.subdivided_steps > 0
    # both within 3 % of the full model at dt/16 at the springs (measured 2.4 % and 1.3 %)
    full = duhamel.solve(s, duhamel.Semianalytic(), t_end=T_END, dt=DT / 16, save_every=16)
    cols = list(springs(120))
    peak = np.abs(full.x[:, cols]).max()
    for sol in (resolved, halved):
        assert np.abs(sol.x[:, cols] - full.x[:, cols]).max() < 0.03 * peak


def test_a_failed_run_says_what_it_tried_and_which_coordinate_diverged() -> None:
    """The note appended to a convergence failure of a run with elements."""
    from types import SimpleNamespace

    from duhamel._engine.run import failure_note

    t = np.arange(40)
    q = np.ones((40, 3))
    q[30:, 2] = np.exp(0.5 * (t[30:] - 29))  # coordinate 2 diverges at the end
    error = SimpleNamespace(kind="convergence", step=117)
    note = failure_note(
        error, SimpleNamespace(q=q), forces=True, route="pseudo-force",
        omega=np.array([10.0, 100.0, 420.0]), correction=np.array([420.0]),
        subdivisions=4, dt=5e-3, sub=3,
    )  # fmt: skip
    assert "3 internal steps per step" in note
    assert "retried in halves down to dt/16" in note
    assert "modal coordinate 2 (a static-correction coordinate, omega dt = 2.1)" in note
    assert "more `max_iter` does not" in note
    # no note without elements, or for another kind of failure
    assert failure_note(error, None, forces=False, route="pseudo-force", omega=q[0],
                        correction=q[0], subdivisions=4, dt=1.0, sub=1) == ""  # fmt: skip
    other = SimpleNamespace(kind="callback", step=3)
    assert failure_note(other, None, forces=True, route="pseudo-force", omega=q[0],
                        correction=q[0], subdivisions=4, dt=1.0, sub=1) == ""  # fmt: skip


def test_the_substep_rule() -> None:
    assert substeps(np.zeros(0), 1.0) == 1
    assert substeps(np.array([100.0, 900.0]), 1e-3) == 1  # resolved already
    assert substeps(np.array([5000.0, 9000.0]), 1e-3) == 1  # stiff: stable at any ratio
    assert substeps(np.array([330.0, 560.0]), 5e-3) == 3  # 1.65, 2.8 -> 0.55, 0.93
    # a stiff coordinate is not left in the band when the others are resolved: 3.2, 5.2
    n = substeps(np.array([642.0, 1036.0]), 5e-3)
    h = np.array([642.0, 1036.0]) * 5e-3 / n
    assert np.all((h <= 1.0) | (h >= 4.0))
    rng = np.random.default_rng(1)
    for _ in range(200):
        omega = rng.uniform(0.0, 1e4, size=5)
        n = substeps(omega, 1e-2)
        h = omega * 1e-2 / n
        assert 1 <= n <= MAX_SUBSTEPS
        assert n == MAX_SUBSTEPS or np.all((h <= 1.0) | (h >= 4.0))


def test_linear_and_full_runs_take_no_substeps() -> None:
    n = 60
    s = duhamel.System(np.eye(n), fixed_chain(n), zeta=0.05)
    s.add_load(L.BaseAcceleration(np.ones(n), t=TT, values=AG))
    linear = duhamel.solve(
        s, duhamel.Semianalytic(modes=5, static_correction=True), t_end=0.1, dt=DT
    )
    assert linear.stats.substeps == 1
    full = duhamel.solve(chain(n, 1e14), duhamel.Semianalytic(), t_end=0.1, dt=DT)
    assert full.stats.substeps == 1
    reduced = duhamel.solve(chain(n, 1e14), duhamel.Semianalytic(modes=5), t_end=0.1, dt=DT)
    assert reduced.stats.substeps > 1
    assert np.array_equal(reduced.t, full.t)  # the saved instants are the user's


def test_the_benchmarks_reduced_chain() -> None:
    """benchmarks/compare.py's "modes3-static-correction": 14 dofs, three hardening springs,
    four loads, 3 modes (+ correction), dt = 0.01. Its reduced run at dt was 0.82 of the
    peak off the full model at dt / 16 (its own truncation 0.24, the full model at dt 0.17);
    resolved in time (2 internal steps) 0.30."""
    n = 14
    K = 1e4 * (2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1))
    K[-1, -1] = 1e4
    t = np.arange(0.0, 4.0 + 0.005, 0.01)
    a = 3.0 * np.sin(7.0 * t) * np.exp(-0.3 * t) + 0.5 * np.sin(23.0 * t)

    def make() -> duhamel.System:
        s = duhamel.System(np.eye(n), K, zeta=0.03)
        s.add_load(L.Harmonic(n - 1, amplitude=50.0, omega=11.0, phase=0.3))
        s.add_load(L.Step(n // 2, amplitude=20.0))
        s.add_load(L.Tabulated(1, t=[0.0, 0.5, 1.0, 3.0], values=[0.0, 30.0, -10.0, 0.0]))
        s.add_load(L.BaseAcceleration(np.ones(n), t=t, values=a))
        for d in (1, 6, 13):
            s.add(E.Spring(d, None, k=0.0, k3=2e9))
        return s

    def at(dt: float, **kw) -> tuple[np.ndarray, duhamel.Solution]:
        sol = duhamel.solve(make(), duhamel.Semianalytic(**kw), t_end=2.0, dt=dt)
        return sol.x[:, [1, 6, 13]], sol

    ref, _ = at(0.01 / 16)
    peak = np.abs(ref).max()
    full, _ = at(0.01)
    reduced, sol = at(0.01, modes=3)
    fine, _ = at(0.01 / 16, modes=3)
    e_full = np.abs(full - ref[::16]).max() / peak
    e_red = np.abs(reduced - ref[::16]).max() / peak
    e_trunc = np.abs(fine - ref).max() / peak
    print(f"\nbenchmark chain: full {e_full:.3f} reduced {e_red:.3f} truncation {e_trunc:.3f}")
    assert sol.stats.substeps == 2
    assert e_red <= e_trunc + e_full + 0.01

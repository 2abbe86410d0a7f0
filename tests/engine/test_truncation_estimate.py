"""The basis-truncation estimate of reduced runs (issue 41, "Large reduced models"):
``sol.stats.truncation_estimate`` / ``element_truncation_estimate`` against the full model's
error, on a 2,016-dof lattice with four yielding Bilinear springs (the 20,384-dof family is
``benchmarks/truncation_lattice.py``, its table in docs/accuracy.md).

The truth is an independent run of the full model: ``Newmark`` at a quarter of the step (its
own error is below 0.3 % of the springs' peaks on this family: checked on the 512-dof lattice
against ``Semianalytic()`` on all modes, see the benchmark)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import scipy.sparse as sp

import duhamel
from duhamel import elements as E
from duhamel import loads as L

DT, T_END = 1e-3, 1.0


def lattice(shape: tuple[int, int, int], k: float) -> tuple[sp.csr_array, sp.csr_array]:
    """Unit masses, links ``k`` to the six neighbours, the bottom layer tied to the ground."""
    index = np.arange(np.prod(shape)).reshape(shape)
    rows, cols = [], []
    for axis in range(3):
        a = np.moveaxis(index, axis, 0)
        rows.append(a[:-1].ravel())
        cols.append(a[1:].ravel())
    i, j = np.concatenate(rows), np.concatenate(cols)
    n = index.size
    links = sp.coo_array((np.full(i.size, k), (i, j)), shape=(n, n))
    degree = np.bincount(i, minlength=n) + np.bincount(j, minlength=n)
    ground = np.zeros(n)
    ground[index[:, :, 0].ravel()] = k
    stiffness = sp.diags(k * degree + ground) - links - links.T
    return sp.identity(n, format="csr"), sp.csr_array(stiffness)


def model(load: str, shape: tuple[int, int, int] = (12, 12, 14)) -> tuple[duhamel.System, list]:
    m, k = lattice(shape, 1e4)
    n = m.shape[0]
    tip = n - 1
    dofs = [int(d) for d in np.random.default_rng(3).choice(n - 1, size=4, replace=False)]
    system = duhamel.System(m, k, rayleigh=(0.5, 1e-4))
    if load == "pulse":  # excites the truncated modes dynamically
        t = np.linspace(0.0, 0.05, 51)
        system.add_load(L.Tabulated(tip, t=t, values=2000.0 * np.sin(np.pi * t / 0.05)))
    else:  # quasi-static for them
        system.add_load(L.Harmonic(tip, amplitude=300.0, omega=6.0))
    for d in dofs:
        system.add(E.Bilinear(d, k=1e4, fy=0.5, alpha=0.05))
    return system, [tip, *dofs]


@pytest.fixture(scope="module", params=["pulse", "harmonic"])
def family(request: pytest.FixtureRequest) -> list[tuple[float, float, bool]]:
    """(true error, estimate, warned) per reduced run and spring."""
    system, saved = model(request.param)
    full = duhamel.solve(
        system, duhamel.Newmark(), t_end=T_END, dt=DT / 4, save_every=4, dofs=saved
    )
    out = []
    for modes in (5, 20, 50, 100):
        for correct in (False, True):
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                sol = duhamel.solve(
                    system,
                    duhamel.Semianalytic(modes=modes, static_correction=correct),
                    t_end=T_END,
                    dt=DT,
                    dofs=saved,
                )
            warned = any(
                issubclass(w.category, duhamel.AccuracyWarning)
                and "reduced basis" in str(w.message)
                for w in caught
            )
            for index in range(4):
                a, b = sol.x[:, index + 1], full.x[:, index + 1]
                true = float(np.abs(a - b).max() / np.abs(b).max())
                # the element's deformation is the saved dof's displacement (to ground)
                assert np.allclose(sol.elements[index].x[:, 0], a)
                out.append((true, sol.stats.element_truncation_estimate[index], warned))
    return out


def test_estimate_within_a_factor_3_of_the_full_models_error(family: list) -> None:
    ratios = np.array([est / true for true, est, _ in family])
    assert np.all(np.isfinite(ratios))
    within = np.mean((ratios >= 1.0 / 3.0) & (ratios <= 3.0))
    assert within >= 0.9, (within, np.round(ratios, 2))


def test_every_run_10_percent_off_warns(family: list) -> None:
    silent = [(true, est) for true, est, warned in family if true >= 0.1 and not warned]
    assert not silent
    assert any(true >= 0.1 for true, _, _ in family)  # the family has such runs


def test_linear_reduced_run_against_the_full_model() -> None:
    """Without elements: the estimate of the left-out modes' response to a point pulse
    against the full model's (Semianalytic on all modes, exact for the linear run)."""
    m, k = lattice((6, 6, 8), 1e4)
    system = duhamel.System(m, k, rayleigh=(0.5, 1e-4))
    t = np.linspace(0.0, 0.05, 51)
    tip = m.shape[0] - 1
    system.add_load(L.Tabulated(tip, t=t, values=np.sin(np.pi * t / 0.05)))
    full = duhamel.solve(system, duhamel.Semianalytic(), t_end=0.5, dt=DT, dofs=[tip])
    assert full.stats.truncation_estimate is None  # nothing left out: not a reduced run
    for modes in (5, 20, 80):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", duhamel.AccuracyWarning)
            sol = duhamel.solve(
                system, duhamel.Semianalytic(modes=modes), t_end=0.5, dt=DT, dofs=[tip]
            )
        true = float(np.abs(sol.x - full.x).max() / np.abs(full.x).max())
        assert 1.0 / 3.0 <= sol.stats.truncation_estimate / true <= 3.0


def test_summary_and_silence() -> None:
    system, saved = model("pulse", shape=(5, 5, 6))
    run = duhamel.Semianalytic(modes=5, error_warning=None)
    with warnings.catch_warnings():
        warnings.simplefilter("error", duhamel.AccuracyWarning)
        sol = duhamel.solve(system, run, t_end=0.3, dt=DT, dofs=saved)
    assert sol.stats.truncation_estimate > 0.01
    assert len(sol.stats.element_truncation_estimate) == 4
    assert "estimated basis truncation error" in sol.summary()
    with pytest.warns(duhamel.AccuracyWarning, match="reduced basis .5 modes"):
        duhamel.solve(system, duhamel.Semianalytic(modes=5), t_end=0.3, dt=DT, dofs=saved)


def test_chain_under_a_step_against_newmark() -> None:
    """Another family: docs/basis.md's 5,000-dof chain (Rayleigh damping) under a step at
    its free end (a wave front the low modes cannot hold), against Newmark at dt/10."""
    n = 5000
    k = sp.diags_array(
        [-np.ones(n - 1), np.r_[np.full(n - 1, 2.0), 1.0], -np.ones(n - 1)],
        offsets=[-1, 0, 1],
        format="csr",
    )
    system = duhamel.System(sp.identity(n, format="csr"), 1e6 * k, rayleigh=(0.1, 1e-5))
    system.add_load(L.Step(dof=n - 1, amplitude=1e3))
    dofs = [n - 1, n - 10, n - 50]
    ref = duhamel.solve(system, duhamel.Newmark(), t_end=0.1, dt=1e-4, save_every=10, dofs=dofs)
    for modes in (40, 200):  # (1000: 0.009 / 0.009 and 0.006 / 0.008, docs/accuracy.md)
        for correct in (False, True):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", duhamel.AccuracyWarning)
                run = duhamel.Semianalytic(modes=modes, static_correction=correct)
                sol = duhamel.solve(system, run, t_end=0.1, dt=DT, dofs=dofs)
            true = float(np.abs(sol.x - ref.x).max() / np.abs(ref.x).max())
            assert 1.0 / 3.0 <= sol.stats.truncation_estimate / true <= 3.0, (modes, correct)


@pytest.mark.parametrize("zeta", [0.0, 0.02, 0.7, 1.5])
def test_residual_oscillators_against_lsim(zeta: float) -> None:
    """The left-out modes' response (the core's exact steps under inputs linear between
    samples, from rest at the first sample) equals scipy's ``lsim`` (its own matrix
    exponential, ``interp=True``) for an undamped, lightly, heavily and over-damped
    oscillator, at low and high ``w dt``, an input that starts at zero and one that
    does not."""
    from scipy.signal import lsim

    from duhamel._engine.truncation import response

    t = np.linspace(0.0, 2.0, 801)
    omega = np.array([3.0, 40.0, 900.0])  # w dt = 0.0075, 0.1, 2.25
    g = np.vstack([np.sin(5.0 * t) + 0.3 * t, np.cos(17.0 * t), np.where(t < 0.4, t, 0.0)])
    q = response(omega**2, 2.0 * zeta * omega, g, t)
    for m, w in enumerate(omega):
        system = ([1.0], [1.0, 2.0 * zeta * w, w * w])
        _, want, _ = lsim(system, g[m], t, interp=True)
        assert np.abs(q[m] - want).max() <= 1e-10 * np.abs(want).max()

"""The error estimate's arithmetic in the core (issue 35's overhead: ``_core.mode_bounds``,
``_core.row_errors``, ``_core.parabola_moments``, ``_core.Estimator``) against independent
numpy constructions: the parabola moments from the exponential of the augmented oscillator
(Van Loan), the per-mode bounds from the vectorised numpy definition of issue 41 (second
differences, secant frequency, blocked decaying accumulation), the propagated errors from
the recurrence with ``expm`` transitions, the run's estimates and bounds from the saved
response and the element histories."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import scipy.linalg

import duhamel
from duhamel import _core
from duhamel._engine.accuracy import mode_bounds, parabola_moments


def _reference_decaying_max(x: np.ndarray, decay: np.ndarray) -> np.ndarray:
    """Issue 41's numpy definition: blocked ``decay^-i`` sums, fast rows bounded, slow rows
    lumped in groups of ``g`` (``g rate <= 0.1``)."""
    n, rows = x.shape
    rate = -np.log(np.clip(decay, 1e-300, 1.0))
    best = np.zeros(n)
    fast = rate > 0.5
    if fast.any():
        best[fast] = x[fast].max(axis=1, initial=0.0) / (1.0 - decay[fast])
    slow = np.flatnonzero(~fast)
    if slow.size == 0 or rows == 0:
        return best
    x, rate = x[slow], rate[slow]
    if not rate.any():
        best[slow] = np.cumsum(x, axis=1).max(axis=1, initial=0.0)
        return best
    g = int(min(rows, 0.1 // float(rate.max())))
    if g >= 2:
        whole = rows // g * g
        x = np.concatenate(
            [x[:, :whole].reshape(slow.size, -1, g).sum(axis=2), x[:, whole:].sum(axis=1)[:, None]],
            axis=1,
        )
        rate = rate * g
        rows = x.shape[1]
    length = int(min(rows, 50.0 // float(rate.max())))
    grow = np.exp(np.outer(rate, np.arange(1, length + 1)))
    carry, top = np.zeros(slow.size), np.zeros(slow.size)
    for s in range(0, rows, length):
        block = x[:, s : s + length]
        acc = (np.cumsum(block * grow[:, : block.shape[1]], axis=1) + carry[:, None]) / grow[
            :, : block.shape[1]
        ]
        top = np.maximum(top, acc.max(axis=1))
        carry = acc[:, -1]
    best[slow] = top * np.exp(rate) if g >= 2 else top
    return best


def _reference_bounds(pseudo, q, omega, c, h, k, span):
    """Issue 41's numpy definition of the per-mode bounds (moments by ``expm``)."""
    rows, n = pseudo.shape
    if rows < 3:
        return np.zeros(n)
    second = np.abs(pseudo[2:] + pseudo[:-2] - 2.0 * pseudo[1:-1]).T
    moments = parabola_moments(omega, c, h)
    finite = np.where(np.isfinite(omega), omega, 0.0)
    qq = np.einsum("ij,ij->j", q, q)
    stiffening = -np.einsum("ij,ij->j", pseudo, q) / np.where(qq > 0.0, qq, 1.0)
    w = np.maximum(np.sqrt(finite**2 + np.maximum(stiffening, 0.0)), 2.0 / max(span, h))
    scale = np.hypot(moments[:, 0], moments[:, 1] / w) / (8.0 * k)
    decay = np.exp(-0.5 * np.where(np.isfinite(c) & (c > 0.0), c, 0.0) * k * h)
    out = scale * second.sum(axis=1)
    order = np.argsort(out, kind="stable")
    small = order[np.cumsum(out[order]) <= 0.05 * out.sum()]
    big = np.setdiff1d(np.arange(n), small)
    out[big] = scale[big] * _reference_decaying_max(second[big], decay[big])
    return out


def _reference_errors(pseudo, q, omega, c, h, k, span, signed):
    """The propagated estimate by its definition: per mode, the local error of each saved
    interval (the parabola moments times ``-D2 / (8 k^2)`` per internal step, ``D2`` the
    mean of the second differences at the interval's ends) carried by the exact transition
    of ``e'' + c e' + w^2 e = 0`` (``expm``, ``w`` the secant frequency), combined with
    the signed shapes; the largest magnitude over the rows (no jump in these histories)."""
    rows, n = pseudo.shape
    second = np.zeros_like(pseudo)
    second[1:-1] = pseudo[2:] + pseudo[:-2] - 2.0 * pseudo[1:-1]
    second[0], second[-1] = second[1], second[-2]
    d2 = 0.5 * (second[:-1] + second[1:])
    moments = parabola_moments(omega, c, h)
    finite = np.where(np.isfinite(omega), omega, 0.0)
    qq = np.einsum("ij,ij->j", q, q)
    stiffening = -np.einsum("ij,ij->j", pseudo, q) / np.where(qq > 0.0, qq, 1.0)
    w = np.maximum(np.sqrt(finite**2 + np.maximum(stiffening, 0.0)), 2.0 / max(span, h))
    errors = np.zeros((rows, n))
    for m in range(n):
        damping = c[m] if np.isfinite(c[m]) and c[m] > 0.0 else 0.0
        a = scipy.linalg.expm(np.array([[0.0, 1.0], [-(w[m] ** 2), -damping]]) * h)
        local = sum(np.linalg.matrix_power(a, j) for j in range(k)) @ moments[m]
        carry, e = np.linalg.matrix_power(a, k), np.zeros(2)
        for r in range(1, rows):
            e = carry @ e - local * d2[r - 1, m] / (8.0 * k * k)
            errors[r, m] = e[0]
    return np.abs(errors @ signed.T).max(axis=0)


@pytest.mark.parametrize(("rows", "k"), [(3, 1), (40, 1), (700, 3)])
def test_core_propagated_errors_are_the_recurrence(rows, k):
    rng = np.random.default_rng(rows)
    n, g = 5, 7
    t = np.linspace(0.0, 4.0, rows)
    omega = np.array([0.0, 2.0, 7.0, 30.0, np.inf])
    c = np.array([0.0, 0.1, 0.7, 1.5, 0.02])
    # smooth, resolved histories (no interval stands out: no force jump)
    q = np.sin(np.outer(t, [0.5, 1.0, 2.0, 3.0, 1.0]) + rng.uniform(0.0, 6.0, n))
    pseudo = -np.outer(np.ones(rows), [0.3, 1.0, 4.0, 0.0, 1.0]) * q**3
    signed = rng.normal(size=(g, n))
    h, span = 0.01, float(t[-1])
    got = _core.row_errors(pseudo, q, omega, c, signed, (h, k, span))
    want = _reference_errors(pseudo, q, omega, c, h, k, span, signed)
    np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-14 * want.max())


def test_modes_of_small_share_are_bounded_instead_of_combined():
    """A mode whose bound makes up less than 1e-3 of every row's is left out of the
    combination and its bound added: the estimate is the full combination's, plus at most
    1e-3 of the row's bound (``sum_m |signed[r, m]| bound_m``)."""
    rows, n, g = 400, 4, 3
    t = np.linspace(0.0, 4.0, rows)
    omega = np.array([1.0, 2.0, 3.0, 5.0])
    c = np.full(n, 0.05)
    q = np.sin(np.outer(t, omega)) * np.array([1.0, 1.0, 1.0, 1e-2])  # mode 3: small
    pseudo = -(q**3)
    rng = np.random.default_rng(3)
    signed = rng.normal(size=(g, n))
    step = (0.01, 1, float(t[-1]))
    got = _core.row_errors(pseudo, q, omega, c, signed, step)
    want = _reference_errors(pseudo, q, omega, c, *step, signed)
    bound = np.abs(signed) @ _core.mode_bounds(pseudo, q, omega, c, step)
    assert np.all(got >= want * (1 - 1e-12))
    assert np.all(got <= want + 1e-3 * bound)
    assert np.any(got > want * (1 + 1e-12))  # the tiny mode was left out and bounded


@pytest.mark.parametrize("h", [1e-4, 0.01, 0.3, 2.0, 40.0])
def test_core_moments_are_the_augmented_exponentials(h):
    omega = np.array([0.0, 0.5, 3.0, 10.0, 60.0, np.inf, 7.0])
    c = np.array([0.0, 0.05, 2 * 0.02 * 3.0, 2 * 0.9 * 10.0, 2 * 1.5 * 60.0, 1.0, 0.0])
    got = _core.parabola_moments(omega, c, h)
    want = parabola_moments(omega, c, h)
    assert got.shape == (omega.size, 2)
    scale = np.abs(want).max(axis=1, keepdims=True)
    scale[scale == 0.0] = 1.0
    assert np.abs(got - want).max() <= 1e-12 * scale.max(), (got, want)
    np.testing.assert_allclose(got, want, rtol=1e-11, atol=1e-14 * float(scale.max()))
    assert np.all(got[5] == 0.0)  # a massless dof's coordinate carries no quadrature


@pytest.mark.parametrize(("rows", "k", "seed"), [(3, 1, 0), (40, 1, 1), (800, 2, 2), (5001, 4, 3)])
def test_core_bounds_are_the_numpy_definition(rows, k, seed):
    rng = np.random.default_rng(seed)
    n = 12
    omega = np.sort(rng.uniform(0.0, 80.0, n))
    omega[0] = 0.0
    c = 2 * rng.uniform(0.0, 0.3, n) * omega
    c[3] = 0.0
    h = 0.004
    t = np.arange(rows) * k * h
    pseudo = np.sin(np.outer(t, rng.uniform(1.0, 30.0, n))) * rng.uniform(0.1, 10.0, n)
    q = np.cos(np.outer(t, omega + 0.1)) * rng.uniform(0.1, 1.0, n)
    span = float(t[-1])
    got = mode_bounds(pseudo, q, omega, c, h, k, span)
    want = _reference_bounds(pseudo, q, omega, c, h, k, span)
    np.testing.assert_allclose(got, want, rtol=1e-11, atol=0.0)


def test_core_decaying_max_is_the_numpy_definition():
    rng = np.random.default_rng(5)
    x = rng.random((7, 3001)) * np.sin(np.linspace(0, 30, 3001)) ** 2
    for decay in (
        np.array([1.0, 0.99999, 0.9999, 0.999, 0.99, 0.7, 1e-3]),
        np.ones(7),
        np.full(7, 0.5),
    ):
        np.testing.assert_allclose(
            _core.decaying_max(x, decay), _reference_decaying_max(x, decay), rtol=1e-11
        )


def test_a_runs_estimates_are_its_bounds_over_its_peaks():
    """``stats.error_bound`` and ``element_error_bound`` of a run: the largest bound over
    the saved dofs (and along each element's deformation) over the peak response there,
    from the bounds of the run's own modal history; ``error_estimate`` and
    ``element_error_estimate`` the same of the propagated errors."""
    n = 4
    k = 400.0 * (2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1))
    k[-1, -1] = 400.0
    system = duhamel.System(np.eye(n), k, zeta=0.03)
    system.add(duhamel.elements.Bilinear(0, 1, k=300.0, fy=0.02, alpha=0.1))
    system.add(duhamel.elements.Cubic(3, k3=2e3))
    system.add_load(duhamel.loads.Harmonic(n - 1, amplitude=5.0, omega=9.0))
    dt = 0.01
    prepared = duhamel.prepare(system, duhamel.Semianalytic(), dt=dt)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", duhamel.AccuracyWarning)
        sol = prepared.run(t_end=3.0, save_every=2)
    phi = prepared._modal.route.basis.phi  # the run's basis
    modal = sol.modal
    bounds = _reference_bounds(
        modal.pseudo_force, modal.q, modal.omega, modal.c, dt, 2, float(sol.t[-1])
    )
    want = float((np.abs(phi) @ bounds).max() / np.abs(sol.x).max())
    assert sol.stats.error_bound == pytest.approx(want, rel=1e-10)
    bilinear, cubic = sol.elements
    along = float(np.abs(phi[0] - phi[1]) @ bounds) / np.abs(bilinear.deformation).max()
    at = float(np.abs(phi[3]) @ bounds) / np.abs(cubic.deformation).max()
    assert sol.stats.element_error_bound == pytest.approx((along, at), rel=1e-10)
    shapes = np.vstack([phi, phi[0] - phi[1], phi[3]])
    span = float(sol.t[-1])
    errors = _reference_errors(
        modal.pseudo_force, modal.q, modal.omega, modal.c, dt, 2, span, shapes
    )
    assert sol.stats.error_estimate == pytest.approx(
        errors[:n].max() / np.abs(sol.x).max(), rel=1e-9
    )
    peaks = np.abs(bilinear.deformation).max(), np.abs(cubic.deformation).max()
    assert sol.stats.element_error_estimate == pytest.approx(errors[n:] / peaks, rel=1e-9)
    # the estimate carries the local errors with their signs: below the bound here
    assert 0.0 < sol.stats.error_estimate < sol.stats.error_bound


def test_a_run_in_segments_has_the_estimate_of_the_whole_run():
    """A run with a terminal event is taken in chunks and joined (no core ``RunResult``): its
    estimate, from the joined history, is the whole run's when the event never fires."""
    from duhamel import events

    n = 3
    k = 400.0 * (2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1))
    k[-1, -1] = 400.0
    system = duhamel.System(np.eye(n), k, zeta=0.03)
    system.add(duhamel.elements.Bilinear(0, 1, k=300.0, fy=0.02, alpha=0.1))
    system.add_load(duhamel.loads.Harmonic(n - 1, amplitude=5.0, omega=9.0))
    prepared = duhamel.prepare(system, duhamel.Semianalytic(), dt=0.005)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", duhamel.AccuracyWarning)
        whole = prepared.run(t_end=10.0)
        never = [events.threshold(0, 1e6, terminal=True)]
        joined = prepared.run(t_end=10.0, events=never)
    assert np.array_equal(whole.x, joined.x)
    assert whole.stats.error_estimate is not None and whole.stats.error_estimate > 0
    assert joined.stats.error_estimate == pytest.approx(whole.stats.error_estimate, rel=1e-12)
    assert joined.stats.error_bound == pytest.approx(whole.stats.error_bound, rel=1e-12)
    assert joined.stats.element_error_bound == pytest.approx(
        whole.stats.element_error_bound, rel=1e-12
    )
    assert joined.stats.element_error_estimate == pytest.approx(
        whole.stats.element_error_estimate, rel=1e-12
    )

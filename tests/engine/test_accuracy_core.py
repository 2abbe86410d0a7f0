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


def _carry(w2, damping, h, k, moments):
    """The exact transition of ``e'' + c e' + w2 e = 0`` over the ``k`` internal steps of a
    saved interval (``expm``), and the local error it adds per unit ``-D2 / (8 k^2)``."""
    a = scipy.linalg.expm(np.array([[0.0, 1.0], [-w2, -damping]]) * h)
    local = sum(np.linalg.matrix_power(a, j) for j in range(k)) @ moments
    return np.linalg.matrix_power(a, k), local


def _ramp(omega, damping, span):
    """``(q, v)`` at ``span`` of ``q'' + c q' + omega^2 q = tau / span`` from rest (``expm``
    of the oscillator augmented with the ramp)."""
    z = np.zeros((4, 4))
    z[0, 1], z[1, 0], z[1, 1], z[1, 2], z[2, 3] = 1.0, -(omega**2), -damping, 1.0 / span, 1.0
    return scipy.linalg.expm(z * span)[:2, 3]


def _kinked_inputs(p, omega, damping, h, k, middle, keys):
    """Per saved interval of one mode's pseudo-force `p`: the second difference its local
    error takes and a kink's error. A kink: ``D_i``, ``D_{i+1}`` of one sign and their
    outer neighbours together below half of them (``D`` 0 at the ends); it sits at
    ``theta = D_{i+1} / (D_i + D_{i+1})`` with the slope change ``D_i + D_{i+1}`` per saved
    spacing, in internal step ``j = floor(theta k)``: its error is the response to
    ``change/k ((tau - t)_+ - (1 - t) tau)`` (``t`` the place in that step), carried over the
    interval's remaining internal steps at the tangent's bin. Its neighbours take their
    outer second difference, the others the mean of their ends' (ends clamped)."""
    rows = p.size
    d = np.zeros(rows)
    d[1:-1] = p[2:] + p[:-2] - 2.0 * p[1:-1]
    beyond = np.append(d, 0.0)
    kinks = {}
    for i in range(1, rows - 2):
        a, b = d[i], d[i + 1]
        if a * b > 0.0 and abs(d[i - 1]) + abs(beyond[i + 2]) < 0.5 * (abs(a) + abs(b)):
            kinks[i] = (b / (a + b), a + b)
    clamped = lambda r: d[min(max(r, 1), rows - 2)]  # noqa: E731
    out = []
    for i in range(rows - 1):
        if i in kinks:
            theta, change = kinks[i]
            j = min(int(np.floor(theta * k)), k - 1)
            t = theta * k - j
            if t >= 1.0:  # at the step's end: no error
                out.append((0.0, np.zeros(2)))
                continue
            late = _ramp(omega, damping, (1.0 - t) * h)
            error = change / k * (1.0 - t) * (late - _ramp(omega, damping, h))
            w2 = middle[keys[i]]
            step = scipy.linalg.expm(np.array([[0.0, 1.0], [-w2, -damping]]) * h)
            out.append((0.0, np.linalg.matrix_power(step, k - 1 - j) @ error))
        elif i - 1 in kinks:
            out.append((d[i + 1], 0.0))
        elif i + 1 in kinks:
            out.append((d[i], 0.0))
        else:
            out.append((0.5 * (clamped(i) + clamped(i + 1)), 0.0))
    return out


def _reference_errors(pseudo, q, omega, c, h, k, span, signed):
    """The final estimate of :func:`_reference_parts`."""
    return _reference_parts(pseudo, q, omega, c, h, k, span, signed)[0]


def _reference_parts(pseudo, q, omega, c, h, k, span, signed):
    """``(estimate, secant's, tangent's, bound)`` per row. The propagated estimate by its
    definition: per mode, the local error of each saved interval (the parabola moments
    times ``-D2 / (8 k^2)`` per internal step, ``D2`` the mean of the second differences
    at the interval's ends) carried by the exact transition of ``e'' + c e' + w^2 e =
    0`` (``expm``, ``w`` the secant frequency), combined with the signed shapes; the
    largest magnitude over the rows (no jump in these histories). Raised, row by row, to
    the same errors carried at each interval's tangent (``w^2 = omega^2 - dp dq /
    dq^2``, at least the secant's floor, at the middle of its bin of 32 an octave; the
    local errors of kinks, :func:`_kinked_inputs`) where that is larger and at most the
    row's bound, in a run of one mode."""
    rows, n = pseudo.shape
    second = np.zeros_like(pseudo)
    second[1:-1] = pseudo[2:] + pseudo[:-2] - 2.0 * pseudo[1:-1]
    second[0], second[-1] = second[1], second[-2]
    d2 = 0.5 * (second[:-1] + second[1:])
    moments = parabola_moments(omega, c, h)
    finite = np.where(np.isfinite(omega), omega, 0.0)
    qq = np.einsum("ij,ij->j", q, q)
    stiffening = -np.einsum("ij,ij->j", pseudo, q) / np.where(qq > 0.0, qq, 1.0)
    floor = 2.0 / max(span, h)
    w = np.maximum(np.sqrt(finite**2 + np.maximum(stiffening, 0.0)), floor)
    dp, dq = np.diff(pseudo, axis=0), np.diff(q, axis=0)
    tangent = -dp * dq / np.where(dq != 0.0, dq * dq, 1.0)
    # the grid bin: the exponent and the first five bits of the mantissa (32 an octave)
    keys = np.maximum(finite**2 + tangent, floor**2).view(np.int64) >> 47
    secant, carried = np.zeros((rows, n)), np.zeros((rows, n))
    for m in range(n):
        if not np.isfinite(omega[m]):
            continue  # a massless dof's coordinate: no error
        damping = c[m] if np.isfinite(c[m]) and c[m] > 0.0 else 0.0
        carry, local = _carry(w[m] ** 2, damping, h, k, moments[m])
        bins = np.unique(keys[:, m])
        middle = dict(zip(bins, ((bins << 47) | (1 << 46)).view(np.float64), strict=True))
        at = {key: _carry(w2, damping, h, k, moments[m]) for key, w2 in middle.items()}
        inputs = _kinked_inputs(pseudo[:, m], omega[m], damping, h, k, middle, keys[:, m])
        e, f = np.zeros(2), np.zeros(2)
        for r in range(1, rows):
            e = carry @ e - local * d2[r - 1, m] / (8.0 * k * k)
            a, b = at[keys[r - 1, m]]
            d, extra = inputs[r - 1]
            f = a @ f - b * d / (8.0 * k * k) + extra
            secant[r, m], carried[r, m] = e[0], f[0]
    out = np.abs(secant @ signed.T).max(axis=0)
    if np.isfinite(omega).sum() > 1:
        return out, out, out, out  # several modes: the secant's (no tangent is read)
    raised = np.abs(carried @ signed.T).max(axis=0)
    bound = np.abs(signed) @ _reference_bounds(pseudo, q, omega, c, h, k, span)
    return np.where((raised <= bound) & (raised > out), raised, out), out, raised, bound


def _modal_history(element, k0=0.0, save_every=1):
    """The modal history of an SDOF (mass 1, 5 % Rayleigh on a period of 1 s) with `element`
    under a band-limited record, at a quarter of the record's step."""
    t = np.arange(0.0, 12.0 + 0.005, 0.01)
    rng = np.random.default_rng(11)
    ag = np.convolve(rng.normal(0.0, 2.5, t.size), np.ones(8) / 8, mode="same") * np.sin(
        np.pi * t / 12.0
    )
    w = 2 * np.pi
    system = duhamel.System(np.eye(1), k0 * np.eye(1), (0.05 * w + 0.05 / w * w**2) * np.eye(1))
    system.add(element)
    system.add_load(duhamel.loads.BaseAcceleration(np.ones(1), t=t, values=ag))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", duhamel.AccuracyWarning)
        sol = duhamel.solve(
            system, duhamel.Semianalytic(), t_end=12.0, dt=0.0025, save_every=save_every
        )
    m = sol.modal
    step = (0.0025, save_every, float(sol.t[-1]))
    return m.pseudo_force, m.q, m.omega, m.c, step


@pytest.mark.parametrize("save_every", [1, 4])
def test_a_yielding_history_is_carried_at_its_tangent(save_every):
    """A bilinear SDOF on a linear background spring: the errors carried at the tangent (soft
    while it yields) are above the secant's and within the bound, so the estimate is theirs;
    the core's equals the reference's."""
    w2 = (2 * np.pi) ** 2
    element = duhamel.elements.Bilinear(0, k=w2, fy=0.02 * w2, alpha=0.05)
    pseudo, q, omega, c, step = _modal_history(element, k0=w2, save_every=save_every)
    signed = np.ones((1, 1))
    got = _core.row_errors(pseudo, q, omega, c, signed, step)
    want, secant, raised, bound = _reference_parts(pseudo, q, omega, c, *step, signed)
    assert secant[0] < raised[0] <= bound[0]
    np.testing.assert_allclose(got, want, rtol=1e-9)


@pytest.mark.parametrize("save_every", [1, 3])
def test_a_contact_history_is_carried_with_its_kinks(save_every):
    """A gap closing and opening on a linear spring: the pseudo-force kinks where the gap
    closes; the kinks' errors are found (the reference finds them too) and the errors
    carried at the tangent are the estimate."""
    w2 = (2 * np.pi) ** 2
    element = duhamel.elements.Gap(0, gap=0.01, k=10 * w2)
    pseudo, q, omega, c, step = _modal_history(element, k0=w2, save_every=save_every)
    signed = np.ones((1, 1))
    got = _core.row_errors(pseudo, q, omega, c, signed, step)
    want, secant, raised, bound = _reference_parts(pseudo, q, omega, c, *step, signed)
    middle = {0: 1.0}
    inputs = _kinked_inputs(pseudo[:, 0], omega[0], c[0], step[0], step[1], middle,
                            np.zeros(pseudo.shape[0], dtype=np.int64))  # fmt: skip
    assert sum(np.any(extra != 0.0) for _, extra in inputs) >= 5  # the gap closed
    assert secant[0] < raised[0] <= bound[0]
    np.testing.assert_allclose(got, want, rtol=1e-9)


def test_a_tangent_that_pumps_is_not_used():
    """A friction pendulum: its tangent switches between sticking (stiff) and sliding (soft),
    and errors carried at it grow far beyond the bound (the run's do not): the estimate
    stays the secant's."""
    element = duhamel.elements.FrictionPendulum(0, radius=2.0, mu=0.06, weight=9.81)
    pseudo, q, omega, c, step = _modal_history(element)
    signed = np.ones((1, 1))
    got = _core.row_errors(pseudo, q, omega, c, signed, step)
    want, secant, raised, bound = _reference_parts(pseudo, q, omega, c, *step, signed)
    assert raised[0] > bound[0]
    assert want[0] == secant[0]
    np.testing.assert_allclose(got, want, rtol=1e-9)


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

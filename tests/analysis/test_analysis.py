"""duhamel.analysis: the paper's section 3 (Figs. 1 and 2, eqs. 22-27) reproduced and checked.

References share nothing with the code under test where possible: closed forms typed in
from NOTES.md section 2 and the paper (eqs. 22, 23a-c, 24a-b, 26, 27), ``scipy.linalg.expm``
of a first-order matrix built here from M, C, K, and a Newmark recurrence written out step
by step. Measured numbers are printed (``pytest -s``).
"""

from __future__ import annotations

import types

import numpy as np
import pytest
import scipy.linalg as sla

import duhamel
from duhamel import analysis as an
from duhamel import elements as E
from duhamel import loads as L

SCHEMES = {s: duhamel.Semianalytic(scheme=s, linear_parts="pseudo-force") for s in "abc"}
HAS_NEWMARK = hasattr(duhamel, "Newmark")
NEEDS_NEWMARK = pytest.mark.skipif(
    not HAS_NEWMARK, reason="duhamel.Newmark is not implemented yet (issue 4, integrators half)"
)


def first_order(m, k, c):
    n = m.shape[0]
    minv = np.linalg.inv(m)
    f = np.zeros((2 * n, 2 * n))
    f[:n, n:] = np.eye(n)
    f[n:, :n] = -minv @ k
    f[n:, n:] = -minv @ c
    return f


def newmark_step(x0, v0, m, c, k, dt, gamma, beta):
    """One Newmark step, predictor-corrector form (accelerations from equilibrium)."""
    a0 = np.linalg.solve(m, -(c @ v0 + k @ x0))
    xp = x0 + dt * v0 + dt * dt * (0.5 - beta) * a0
    vp = v0 + dt * (1.0 - gamma) * a0
    a1 = np.linalg.solve(m + gamma * dt * c + beta * dt * dt * k, -(c @ vp + k @ xp))
    return xp + beta * dt * dt * a1, vp + gamma * dt * a1


def newmark_reference(m, c, k, dt, gamma, beta):
    n = m.shape[0]
    out = np.empty((2 * n, 2 * n))
    for j in range(2 * n):
        y = np.zeros(2 * n)
        y[j] = 1.0
        x1, v1 = newmark_step(y[:n], y[n:], m, c, k, dt, gamma, beta)
        out[:, j] = np.concatenate([x1, v1])
    return out


def eq22(omega, zeta, dt):
    h, z = omega * dt, zeta
    c, s = np.cos(h), np.sin(h)
    a = np.array(
        [[2 * z + (h - 2 * z) * c, dt * s], [-omega * omega * dt * s, -2 * z + (h + 2 * z) * c]]
    )
    return a / (h + 2 * z * (1 - c))


# --------------------------------------------------------------------------------------------
# 1. Eq. 22 and exactness
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("zeta", [0.1, 0.3])
def test_scheme_b_amplification_is_eq22(zeta):
    omega = 1.7
    model = an.model_oscillator(omega, zeta)
    worst = 0.0
    for x in [1e-3, 0.013, 0.25, 0.5, 0.7, 1.0, 3.3, 47.0, 1e3]:
        dt = x * 2 * np.pi / omega
        a = an.amplification_matrix(model, SCHEMES["b"], dt)
        ref = eq22(omega, zeta, dt)
        dev = np.max(np.abs(a - ref) / np.maximum(1.0, np.abs(ref)))
        worst = max(worst, dev)
    print(f"\neq. 22, zeta={zeta}: largest deviation {worst:.2e} over dt/T in [1e-3, 1e3]")
    assert worst <= 1e-12


N3 = 3
M3 = np.diag([1.0, 1.5, 0.8])
K3 = np.array([[3.0, -1.2, 0.0], [-1.2, 2.5, -1.0], [0.0, -1.0, 1.6]])
RAYLEIGH3 = (0.2, 0.03)


def test_exact_for_linear_background():
    system = duhamel.System(M3, K3, rayleigh=RAYLEIGH3)
    f = first_order(M3, K3, RAYLEIGH3[0] * M3 + RAYLEIGH3[1] * K3)
    worst, worst_t = 0.0, 0.0
    print()
    for dt in [1e-3, 0.05, 0.7, 6.0]:  # the last is longer than every natural period
        expm = sla.expm(f * dt)
        a = an.amplification_matrix(system, duhamel.Semianalytic(), dt)
        worst = max(worst, np.max(np.abs(a - expm)) / np.max(np.abs(expm)))
        worst_t = max(worst_t, np.max(np.abs(an.exact_transition_matrix(system, dt) - expm)))
        errs = an.modal_errors(system, duhamel.Semianalytic(), dt)
        assert errs.omega.size == N3
        err = max(np.abs(errs.period_error).max(), np.abs(errs.damping_error).max())
        print(f"exact background, dt = {dt}: period/damping errors <= {err:.1e}")
        # zeta_num comes from log|lambda| with |lambda| = 1 - O(zeta omega dt): its relative
        # round-off is ~ eps / (zeta omega dt), 1e-12 at dt = 1e-3 here
        assert err <= (1e-10 if dt < 0.01 else 1e-12)
    print(
        f"exact background: |A - expm| / |expm| <= {worst:.1e}, "
        f"exact_transition_matrix {worst_t:.1e}"
    )
    assert worst <= 1e-13
    assert worst_t <= 1e-13


def test_exact_with_modal_reduction():
    system = duhamel.System(M3, K3, zeta=0.05)
    dt = 0.4
    a = an.amplification_matrix(system, duhamel.Semianalytic(modes=2), dt)
    # Galerkin-reduced reference built here: Phi_r expm(S_r dt) Phi_r^T M
    w2, phi = sla.eigh(K3, M3)
    phi = phi[:, :2]
    s = first_order(np.eye(2), np.diag(w2[:2]), np.diag(2 * 0.05 * np.sqrt(w2[:2])))
    e = sla.expm(s * dt)
    q = np.block([[phi, np.zeros((3, 2))], [np.zeros((3, 2)), phi]])
    p = np.block([[phi.T @ M3, np.zeros((2, 3))], [np.zeros((2, 3)), phi.T @ M3]])
    ref = q @ e @ p
    dev = np.max(np.abs(a - ref))
    dev_t = np.max(np.abs(an.exact_transition_matrix(system, dt, modes=2) - ref))
    print(f"\nmodes=2 of 3: |A - reduced expm| = {dev:.1e}, exact_transition_matrix {dev_t:.1e}")
    assert dev <= 1e-13 and dev_t <= 1e-13
    assert np.linalg.matrix_rank(a) == 4


def test_loads_are_ignored():
    system = an.model_oscillator(1.0, 0.1)
    loaded = an.model_oscillator(1.0, 0.1)
    loaded.add_load(L.Step(dof=0, amplitude=3.0))
    a = an.amplification_matrix(system, SCHEMES["b"], 0.3)
    b = an.amplification_matrix(loaded, SCHEMES["b"], 0.3)
    assert np.array_equal(a, b)
    assert len(loaded.loads) == 1  # the caller's system is untouched


# --------------------------------------------------------------------------------------------
# 2. Fig. 1: damping as a pseudo-force, zeta = 0.1, dt/T in [1e-3, 1e3]
# --------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def fig1():
    x = np.logspace(-3, 3, 1201)
    return an.stability_chart(SCHEMES, x, 0.1)


def test_fig1_scheme_b_never_exceeds_one(fig1):
    rho = fig1.curve("b")
    # rho = 1 exactly where cos(omega dt) = +-1 (dt/T = k/2): refine around those points too
    touch = [
        an.spectral_radius(fig1.system, SCHEMES["b"], k * np.pi * (1 + d))
        for k in (1, 2, 3, 20)
        for d in (-1e-6, 0.0, 1e-6)
    ]
    print(f"\nFig. 1(b): max rho on the grid {rho.max():.16f}, near dt/T = k/2 {max(touch):.16f}")
    assert rho.max() <= 1.0 + 1e-12
    assert max(touch) <= 1.0 + 1e-12
    assert fig1.unstable_intervals("b") == []


def test_fig1_scheme_a(fig1):
    (lo, hi), *rest = fig1.unstable_intervals("a")
    where, peak = fig1.peak("a")
    print(f"\nFig. 1(a): max {peak:.6f} at dt/T = {where:.6f}; first unstable ({lo:.9f}, {hi:.9f})")
    # NOTES.md: max 1.1055, first on (0.500, 0.999)
    assert abs(peak - 1.1055) <= 1e-4
    assert abs(lo - 0.500) <= 1e-3 and abs(hi - 0.999) <= 1e-3 + 1e-9
    # sharper: at dt/T = 1/2 and 1 the matrix is -I and I, so the ends are exactly 1/2 and 1
    assert abs(lo - 0.5) <= 1e-8 and abs(hi - 1.0) <= 1e-8
    assert rest[0][0] == pytest.approx(1.5, abs=1e-8) and rest[0][1] == pytest.approx(2.0, abs=1e-8)
    # closed form (derived, see docs/analysis.md): rho_a = sqrt((1 - z sin h)/(1 + z sin h))
    h = 2 * np.pi * fig1.dt_over_T
    closed = np.sqrt((1 - 0.1 * np.sin(h)) / (1 + 0.1 * np.sin(h)))
    dev = np.max(np.abs(fig1.curve("a") - closed))
    print(f"Fig. 1(a): |rho - sqrt((1 - z sin h)/(1 + z sin h))| <= {dev:.1e}")
    assert dev <= 1e-13
    assert peak == pytest.approx(np.sqrt(1.1 / 0.9), abs=1e-12)
    assert where == pytest.approx(0.75, abs=1e-6)


def test_fig1_scheme_c(fig1):
    (lo, hi), *_ = fig1.unstable_intervals("c")
    where, peak = fig1.peak("c")
    print(f"\nFig. 1(c): max {peak:.6f} at dt/T = {where:.6f}; first unstable ({lo:.6f}, {hi:.6f})")
    # NOTES.md: max 1.2002, first on (0.933, 1.357)
    assert abs(peak - 1.2002) <= 1e-4
    assert abs(lo - 0.933) <= 1e-3 and abs(hi - 1.357) <= 1e-3
    # the ends are roots of rho - 1 (not grid points)
    for end in (lo, hi):
        assert abs(fig1.spectral_radius("c", end) - 1.0) <= 1e-9


def test_fig1_exact_curve(fig1):
    ref = np.exp(-0.1 * 2 * np.pi * fig1.dt_over_T)
    assert np.max(np.abs(fig1.exact - ref)) <= 1e-14


def test_plot_stability_chart(fig1, tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    fig = an.plot_stability_chart(fig1)
    assert len(fig.axes) == 3
    assert all(ax.get_xscale() == "log" for ax in fig.axes)
    assert [ax.get_title() for ax in fig.axes] == ["a", "b", "c"]
    # 3 curves (scheme, exact, |lambda| = 1) in each panel
    assert all(len(ax.get_lines()) == 3 for ax in fig.axes)
    fig.savefig(tmp_path / "fig1.png", dpi=60)
    assert (tmp_path / "fig1.png").stat().st_size > 1000
    import matplotlib.pyplot as plt

    _, ax = plt.subplots()
    fig2 = an.plot_stability_chart(fig1, ax)
    assert fig2.axes == [ax] and len(ax.get_lines()) == 5  # 3 schemes + exact + 1
    plt.close("all")


# --------------------------------------------------------------------------------------------
# 3. Local truncation errors (eqs. 23a-c) and period/damping errors (24a, 24b)
# --------------------------------------------------------------------------------------------
def eq23(scheme, z, w, x0, v0, dt):
    if scheme == "a":
        return (z * x0 - (1 - 2 * z * z) * v0 / w) * z * w**4 * dt**2 / 3
    if scheme == "b":
        return (z * x0 - (1 - 4 * z * z) * v0 / (2 * w)) * z * w**4 * dt**2 / 3
    return ((1 - 4 * z * z) * x0 + 4 * z * (1 - 2 * z * z) * v0 / w) * z * w**5 * dt**3 / 36


def check_leading_term(label, hs, measured, predicted, order):
    """Ratio measured/predicted -> 1 and slope -> order (both extrapolated over the two
    smallest steps, Richardson for an O(h) approach)."""
    ratio = np.asarray(measured) / np.asarray(predicted)
    extrapolated = 2 * ratio[-1] - ratio[-2]  # the ratio approaches 1 like 1 + O(h)
    pairwise = np.diff(np.log(np.abs(measured))) / np.diff(np.log(hs))
    slope = 2 * pairwise[-1] - pairwise[-2]  # the slope approaches the order like O(h)
    print(
        f"{label}: ratios {np.array2string(ratio, precision=6)}, "
        f"extrapolated {extrapolated:.6f}, slope {slope:.4f}"
    )
    assert abs(ratio[-1] - 1) <= 2e-2
    assert abs(extrapolated - 1) <= 5e-4
    assert abs(slope - order) <= 0.005


@pytest.mark.parametrize("zeta", [0.1, 0.25])
@pytest.mark.parametrize("scheme", ["a", "b", "c"])
def test_local_truncation_error_eq23(scheme, zeta):
    w = 1.3
    model = an.model_oscillator(w, zeta)
    hs = [0.16, 0.08, 0.04, 0.02] if scheme == "c" else [0.04, 0.02, 0.01, 0.005]
    order = 3 if scheme == "c" else 2
    print()
    for x0, v0 in [(1.0, 0.0), (0.0, 1.0)]:
        measured = [an.local_truncation_error(model, SCHEMES[scheme], h / w, x0, v0) for h in hs]
        predicted = [eq23(scheme, zeta, w, x0, v0, h / w) for h in hs]
        check_leading_term(
            f"eq. 23{scheme}, zeta={zeta}, (x0, v0)=({x0}, {v0})", hs, measured, predicted, order
        )


@pytest.mark.parametrize("zeta", [0.1, 0.25])
def test_period_and_damping_errors_eq24(zeta):
    w = 1.3
    model = an.model_oscillator(w, zeta)
    hs = np.array([0.08, 0.04, 0.02, 0.01])
    errs = [an.modal_errors(model, SCHEMES["b"], h / w) for h in hs]
    period = np.array([e.period_error[0] for e in errs])
    damping = np.array([e.damping_error[0] for e in errs])
    assert np.allclose([e.period[0] for e in errs], 2 * np.pi / (w * np.sqrt(1 - zeta**2)))
    eq24a = -(3 - 4 * zeta**2) * zeta**2 * hs**2 / (12 * (1 - zeta**2))
    eq24b = -(1 - 2 * zeta**2) * hs**2 / 12
    print()
    for label, meas, pred in [("eq. 24a", period, eq24a), ("eq. 24b", damping, eq24b)]:
        ratio = meas / pred
        extrapolated = (4 * ratio[-1] - ratio[-2]) / 3  # 1 + O(h^2)
        slope = np.polyfit(np.log(hs), np.log(np.abs(meas)), 1)[0]
        print(
            f"{label}, zeta={zeta}: ratios {np.array2string(ratio, precision=7)}, "
            f"extrapolated {extrapolated:.8f}, slope {slope:.4f}"
        )
        assert abs(ratio[-1] - 1) <= 1e-4
        assert abs(extrapolated - 1) <= 1e-6
        assert abs(slope - 2) <= 1e-3
    # the functions agree with modal_errors
    assert an.period_error(model, SCHEMES["b"], hs[0] / w)[0] == period[0]
    assert an.damping_error(model, SCHEMES["b"], hs[0] / w)[0] == damping[0]


def test_one_step_error_orders():
    w, z = 1.3, 0.1
    model = an.model_oscillator(w, z)
    hs = np.array([0.04, 0.02, 0.01, 0.005])
    print()
    for scheme, order in [("a", 2), ("b", 2), ("c", 3)]:
        errs = [
            np.abs(an.one_step_error(model, SCHEMES[scheme], h / w, 1.0, 0.5)).max() for h in hs
        ]
        slopes = np.diff(np.log(errs)) / np.diff(np.log(hs))
        extrapolated = 2 * slopes[-1] - slopes[-2]  # slope = order + 1 + O(h)
        print(
            f"one-step error, scheme {scheme}: pairwise slopes {np.round(slopes, 4)}, "
            f"extrapolated {extrapolated:.4f} (order {order} + 1)"
        )
        assert abs(slopes[-1] - (order + 1)) <= 0.03
        assert abs(extrapolated - (order + 1)) <= 0.005


# --------------------------------------------------------------------------------------------
# 4. Newmark's closed form, and Fig. 2 (eq. 25, alpha = 0.3, zeta = 0.1)
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("gamma, beta", [(0.5, 0.25), (0.5, 0.0), (0.6, 0.3025), (0.5, 1 / 6)])
@pytest.mark.parametrize("alpha_sign", [1, -1])
def test_newmark_amplification_closed_form(gamma, beta, alpha_sign):
    w, z, alpha = 1.3, 0.1, 0.3
    k = (1 - alpha_sign * alpha) * w * w
    dts = np.array([0.01, 0.3, 1.4, 20.0])
    closed = an.newmark_amplification(w, z, dts, gamma, beta, alpha, alpha_sign=alpha_sign)
    one = np.ones((1, 1))
    for dt, a in zip(dts, closed, strict=True):
        ref = newmark_reference(one, 2 * z * w * one, k * one, dt, gamma, beta)
        # round-off of terms of size dt^2 k that cancel
        bound = 1e-15 * (1 + dt * dt * k) * max(1.0, np.abs(ref).max())
        assert np.max(np.abs(a - ref)) <= bound
    # the same via ClosedFormNewmark on the model oscillator (damping treated implicitly)
    model = an.model_oscillator(w, z, alpha=alpha, alpha_sign=alpha_sign, damping="background")
    a = an.amplification_matrix(model, an.ClosedFormNewmark(gamma, beta), 0.3)
    assert np.max(np.abs(a - closed[1])) <= 1e-14


def test_newmark_textbook_properties():
    dts = np.logspace(-3, 3, 200)
    rho = np.abs(np.linalg.eigvals(an.newmark_amplification(1.0, 0.0, dts, 0.5, 0.25))).max(axis=1)
    assert np.max(np.abs(rho - 1.0)) <= 1e-12  # average acceleration: no numerical damping
    # central difference (gamma = 1/2, beta = 0): stable up to omega dt = 2
    cd = np.abs(np.linalg.eigvals(an.newmark_amplification(1.0, 0.0, [1.999, 2.001], 0.5, 0.0)))
    assert cd[0].max() <= 1.0 + 1e-12 and cd[1].max() > 1.01
    # period elongation of the trapezoidal rule: (omega dt)^2 / 12 to leading order
    osc = duhamel.System([[1.0]], [[1.0]])
    h = 1e-2
    assert an.period_error(osc, an.ClosedFormNewmark(), h)[0] / (h * h / 12) == pytest.approx(
        1, abs=1e-4
    )


def test_closed_form_newmark_multi_dof_and_modal_errors():
    c3 = RAYLEIGH3[0] * M3 + RAYLEIGH3[1] * K3
    system = duhamel.System(M3, K3, rayleigh=RAYLEIGH3)
    a = an.amplification_matrix(system, an.ClosedFormNewmark(0.55, 0.28), 0.2)
    ref = newmark_reference(M3, c3, K3, 0.2, 0.55, 0.28)
    assert np.max(np.abs(a - ref)) <= 1e-13
    # per mode: the trapezoidal rule's period error (omega_k dt)^2 / 12, no algorithmic damping
    undamped = duhamel.System(M3, K3)
    dt = 5e-3
    errs = an.modal_errors(undamped, an.ClosedFormNewmark(), dt)
    omega = np.sqrt(sla.eigh(K3, M3, eigvals_only=True))
    ratio = errs.period_error / ((omega * dt) ** 2 / 12)
    print(
        f"\nNewmark per mode: omega {np.round(errs.omega, 6)}, period error / (w dt)^2/12 = {ratio}"
    )
    assert np.allclose(errs.omega, omega, rtol=1e-12)
    assert np.allclose(ratio, 1.0, atol=1e-4)
    assert np.max(np.abs(errs.damping_error)) <= 1e-10  # absolute (zeta = 0)


@pytest.fixture(scope="module")
def fig2():
    x = np.logspace(-3, 3, 601)
    integrators = {"scheme (b)": SCHEMES["b"], "Newmark": an.ClosedFormNewmark(0.5, 0.25)}
    if HAS_NEWMARK:
        integrators["duhamel.Newmark"] = duhamel.Newmark(gamma=0.5, beta=0.25)
    return {
        sign: an.stability_chart(
            integrators, x, 0.1, alpha=0.3, alpha_sign=sign, damping="background"
        )
        for sign in (1, -1)
    }


def test_fig2_data_and_sign(fig2):
    x = fig2[1].dt_over_T
    print()
    for sign, chart in fig2.items():
        nm = np.abs(
            np.linalg.eigvals(
                an.newmark_amplification(1.0, 0.1, 2 * np.pi * x, 0.5, 0.25, 0.3, alpha_sign=sign)
            )
        ).max(axis=1)
        h2 = (2 * np.pi * x) ** 2  # round-off of terms of size dt^2 omega^2 that cancel
        assert np.all(np.abs(chart.curve("Newmark") - nm) <= 1e-15 * (1 + h2))
        assert np.max(np.abs(chart.exact - np.exp(-0.1 * 2 * np.pi * x))) <= 1e-14
        for label in chart.labels:
            rho = chart.curve(label)
            print(
                f"Fig. 2, sign {sign:+d}, {label}: rho at dt/T = 1e-3, 0.1, 1, 10, 1e3: "
                f"{np.array2string(np.interp([1e-3, 0.1, 1, 10, 1e3], x, rho), precision=5)}; "
                f"max {rho.max():.6f}"
            )
            assert rho.max() <= 1.0 + 1e-12  # both unconditionally stable on eq. 25
    for label in fig2[1].labels:
        diff = np.max(np.abs(fig2[1].curve(label) - fig2[-1].curve(label)))
        print(f"Fig. 2, {label}: largest difference between the two signs {diff:.4f}")
        assert diff > 0.01


@NEEDS_NEWMARK
def test_fig2_newmark_class_matches_closed_form(fig2):
    h2 = (2 * np.pi * fig2[1].dt_over_T) ** 2
    for sign, chart in fig2.items():
        dev = np.abs(chart.curve("duhamel.Newmark") - chart.curve("Newmark"))
        print(
            f"\nsign {sign:+d}: duhamel.Newmark vs closed form: {dev.max():.1e}, "
            f"relative to 1 + (omega dt)^2: {np.max(dev / (1 + h2)):.1e}"
        )
        assert np.all(dev <= 1e-15 * (1 + h2))  # round-off of the dt^2 k terms


def test_eq26_holds_for_the_plus_sign():
    """Eq. 26, tau = alpha [(1 - alpha) X0 + 2 zeta X0'/omega] omega^4 dt^2 / 12: the printed
    minus sign of eq. 25 turns (1 - alpha) into (1 + alpha) and flips the sign."""
    w, z, alpha = 1.3, 0.1, 0.3
    hs = [0.04, 0.02, 0.01, 0.005]
    print()
    for sign in (1, -1):
        model = an.model_oscillator(w, z, alpha=alpha, alpha_sign=sign, damping="background")
        a = sign * alpha  # the signed coefficient of the right-hand side
        for x0, v0 in [(1.0, 0.0), (0.0, 1.0)]:
            measured = [an.local_truncation_error(model, SCHEMES["b"], h / w, x0, v0) for h in hs]
            printed = [
                alpha * ((1 - alpha) * x0 + 2 * z * v0 / w) * w**4 * (h / w) ** 2 / 12 for h in hs
            ]
            signed = [a * ((1 - a) * x0 + 2 * z * v0 / w) * w**4 * (h / w) ** 2 / 12 for h in hs]
            ratio_printed = measured[-1] / printed[-1]
            print(
                f"eq. 26, sign {sign:+d}, (x0, v0)=({x0}, {v0}): tau / eq. 26 = {ratio_printed:.5f}"
            )
            if sign == 1:
                check_leading_term("  eq. 26 (+ sign)", hs, measured, printed, 2)
            else:
                assert abs(ratio_printed - 1) > 0.5  # the printed form does not hold
                check_leading_term("  eq. 26 with alpha -> -alpha", hs, measured, signed, 2)


def test_eq27_newmark_local_error_for_the_plus_sign():
    """Eq. 27 (zeta = 0): tau = (1 - alpha)(gamma - 1/2) omega^2 dt X0' + ... and, for
    gamma = 1/2, (1/12 - beta)(1 - alpha)^2 omega^4 dt^2 X0 (with (1 + alpha) for the - sign)."""
    w, alpha = 1.3, 0.3
    hs = [0.04, 0.02, 0.01, 0.005]
    print()
    for sign in (1, -1):
        model = an.model_oscillator(w, 0.0, alpha=alpha, alpha_sign=sign)
        f = 1 - sign * alpha
        meas = [
            an.local_truncation_error(model, an.ClosedFormNewmark(0.5, 0.25), h / w, 1.0, 0.0)
            for h in hs
        ]
        pred = [(1 / 12 - 0.25) * f**2 * w**4 * (h / w) ** 2 for h in hs]
        check_leading_term(f"eq. 27, beta term, sign {sign:+d}", hs, meas, pred, 2)
        meas = [
            an.local_truncation_error(model, an.ClosedFormNewmark(0.6, 0.3), h / w, 0.0, 1.0)
            for h in hs
        ]
        pred = [f * (0.6 - 0.5) * w**2 * (h / w) for h in hs]
        check_leading_term(f"eq. 27, gamma term, sign {sign:+d}", hs, meas, pred, 1)


# --------------------------------------------------------------------------------------------
# 5. Convergence orders
# --------------------------------------------------------------------------------------------
def test_convergence_order_against_exact_oscillator():
    w, z = 1.0, 0.1
    model = an.model_oscillator(w, z)
    wd = w * np.sqrt(1 - z * z)

    def exact(t):  # the damped oscillator from x0 = 1, v0 = 0.5
        return np.exp(-z * w * t) * (np.cos(wd * t) + (0.5 + z * w) / wd * np.sin(wd * t))

    problem = an.ReferenceProblem(model, 8.0, exact, x0=[1.0], v0=[0.5])
    dts = [0.2, 0.1, 0.05, 0.025]
    print()
    for scheme, order in [("a", 2), ("b", 2), ("c", 3)]:
        result = an.convergence_order(problem, SCHEMES[scheme], dts)
        print(
            f"scheme {scheme}: errors {np.array2string(result.errors, precision=3)}, "
            f"order {result.order:.4f}, pairwise {np.array2string(result.orders, precision=4)}"
        )
        assert abs(result.order - order) <= 0.05
        assert np.all(np.abs(result.orders - order) <= 0.1)
    final = an.ReferenceProblem(model, 8.0, exact, x0=[1.0], v0=[0.5], measure="final")
    assert final(SCHEMES["b"], 0.1) <= problem(SCHEMES["b"], 0.1)


def test_convergence_order_with_a_plain_callable():
    calls = []

    def problem(integrator, dt):
        calls.append((integrator, dt))
        return 3.0 * dt**4

    result = an.convergence_order(problem, "anything", [0.1, 0.05])
    assert result.order == pytest.approx(4.0, abs=1e-12)
    assert calls == [("anything", 0.1), ("anything", 0.05)]


# --------------------------------------------------------------------------------------------
# 6. The one-step check and input validation
# --------------------------------------------------------------------------------------------
def fake_solve(two_step):
    """A stand-in for duhamel.solve: a linear one-step map, or one with a hidden memory."""
    a = np.array([[0.9, 0.1], [-0.2, 0.8]])

    def run(system, integrator, *, t_end, dt, x0, v0):
        y = np.concatenate([x0, v0])
        history, memory = [y], y
        for _ in range(round(t_end / dt)):
            new = a @ y + (0.05 * (y - memory) if two_step else 0.0)
            memory, y = y, new
            history.append(y)
        h = np.array(history)
        return types.SimpleNamespace(x=h[:, :1], v=h[:, 1:])

    return run


def test_one_step_check(monkeypatch):
    from duhamel.analysis import matrices

    system = duhamel.System([[1.0]], [[1.0]])
    monkeypatch.setattr(matrices, "solve", fake_solve(two_step=False))
    assert np.allclose(an.amplification_matrix(system, object(), 0.1), [[0.9, 0.1], [-0.2, 0.8]])
    monkeypatch.setattr(matrices, "solve", fake_solve(two_step=True))
    with pytest.raises(ValueError, match=r"`integrator` \(object\) is not a one-step map"):
        an.amplification_matrix(system, object(), 0.1)
    # check=False returns the one-step map
    assert np.allclose(
        an.amplification_matrix(system, object(), 0.1, check=False), [[0.9, 0.1], [-0.2, 0.8]]
    )


def test_realization_recovers_a_hidden_state(monkeypatch):
    """A step that remembers the previous state: eigenvalues of the full 4 x 4 map."""
    from duhamel.analysis import matrices

    monkeypatch.setattr(matrices, "solve", fake_solve(two_step=True))
    system = duhamel.System([[1.0]], [[1.0]])
    a = np.array([[0.9, 0.1], [-0.2, 0.8]])
    full = np.block([[a + 0.05 * np.eye(2), -0.05 * np.eye(2)], [np.eye(2), np.zeros((2, 2))]])
    expected = np.sort_complex(np.linalg.eigvals(full))
    got = np.sort_complex(an.amplification_eigenvalues(system, object(), 0.1))
    print(f"\nrealization: {np.round(got, 12)} vs {np.round(expected, 12)}")
    assert got.size == 4 and np.max(np.abs(got - expected)) <= 1e-12
    assert an.spectral_radius(system, object(), 0.1) == pytest.approx(np.abs(expected).max())


def chung_hulbert(omega, dt, alpha_m, alpha_f, gamma, beta):
    """The (x, v, a) step of the generalized-alpha family for x'' + omega^2 x = 0."""
    w2 = omega * omega
    lhs = (1 - alpha_m) + w2 * (1 - alpha_f) * beta * dt * dt
    a1 = -np.array(
        [w2, w2 * (1 - alpha_f) * dt, alpha_m + w2 * (1 - alpha_f) * dt * dt * (0.5 - beta)]
    )
    a1 /= lhs
    return np.array(
        [
            np.array([1, dt, dt * dt * (0.5 - beta)]) + dt * dt * beta * a1,
            np.array([0, 1, dt * (1 - gamma)]) + dt * gamma * a1,
            a1,
        ]
    )


@pytest.mark.skipif(
    not (hasattr(duhamel, "HHT") and hasattr(duhamel, "GeneralizedAlpha")),
    reason="duhamel.HHT / GeneralizedAlpha are not implemented yet (issue 4, integrators half)",
)
def test_integrators_with_their_own_acceleration():
    osc = duhamel.System([[1.0]], [[1.0]])
    cases = [
        duhamel.HHT(alpha=-0.1),
        duhamel.HHT(alpha=-0.3),
        duhamel.GeneralizedAlpha(rho_inf=0.5),
    ]
    print()
    for integrator in cases:
        with pytest.raises(ValueError, match="not a one-step map"):
            an.amplification_matrix(osc, integrator, 0.1)
        worst = 0.0
        for x in [1e-3, 0.05, 0.3, 1.0, 10.0, 1e3]:
            dt = 2 * np.pi * x
            c = integrator.coefficients
            ref = chung_hulbert(1.0, dt, c["alpha_m"], c["alpha_f"], c["gamma"], c["beta"])
            ref = np.sort(np.abs(np.linalg.eigvals(ref)))[::-1]
            got = np.sort(np.abs(an.amplification_eigenvalues(osc, integrator, dt)))[::-1]
            assert got.size == 3
            worst = max(worst, abs(got[0] - ref[0]) / ref[0])
        print(f"{integrator}: realized spectral radius vs Chung-Hulbert form, worst {worst:.1e}")
        assert worst <= 1e-7
    # the published limit of HHT: (1 + alpha) / (1 - alpha)
    rho = an.spectral_radius(osc, duhamel.HHT(alpha=-0.1), 2 * np.pi * 1e3)
    print(f"HHT(-0.1) at dt/T = 1e3: {rho:.8f} vs {0.9 / 1.1:.8f}")
    assert rho == pytest.approx(0.9 / 1.1, abs=1e-6)
    # period and damping errors through the realization: HHT damps like (omega dt)^3
    d = [an.damping_error(osc, duhamel.HHT(alpha=-0.1), h)[0] for h in (0.04, 0.02, 0.01)]
    slopes = np.diff(np.log(d)) / np.diff(np.log([0.04, 0.02, 0.01]))
    print(f"HHT(-0.1) algorithmic damping {np.array2string(np.array(d), precision=3)}")
    print(f"HHT(-0.1) algorithmic damping slopes {slopes}")
    assert np.all(np.abs(slopes - 3) <= 0.01)
    chart = an.stability_chart([duhamel.HHT(alpha=-0.1)], np.logspace(-2, 2, 9), zeta=0.0)
    assert chart.moduli.shape == (1, 9, 3)
    assert chart.curve("HHT")[-1] == pytest.approx(0.9 / 1.1, abs=1e-3)


def _cubic():
    return duhamel.System([[1.0]], [[1.0]]).add(E.Cubic(0, k3=2.0))


def _mass():
    return duhamel.System([[1.0]], [[1.0]]).set_mass_law(duhamel.mass.Exponential(rate=-0.1))


OSC = duhamel.System([[1.0]], [[1.0]])
TWO = duhamel.System(np.eye(2), [[2.0, -1.0], [-1.0, 2.0]])
B = SCHEMES["b"]
BAD = [
    ("not a system", lambda: an.amplification_matrix("sys", B, 0.1), TypeError, "`system`"),
    ("nonlinear", lambda: an.amplification_matrix(_cubic(), B, 0.1), ValueError, "`system`"),
    ("mass law", lambda: an.spectral_radius(_mass(), B, 0.1), ValueError, "`system`"),
    (
        "constant force",
        lambda: an.amplification_matrix(
            duhamel.System([[1.0]], [[1.0]]).add(E.Polynomial(0, coefficients=[1.0, 2.0])), B, 0.1
        ),
        ValueError,
        "`system`",
    ),
    (
        "contact",
        lambda: an.amplification_matrix(
            duhamel.System(np.eye(2), np.eye(2)).add(
                E.Contact((0, 1), clearance=1e-3, stiffness=1e3)
            ),
            B,
            0.1,
        ),
        ValueError,
        "`system`",
    ),
    ("dt <= 0", lambda: an.amplification_matrix(OSC, B, -0.1), ValueError, "`dt`"),
    ("dt nan", lambda: an.spectral_radius(OSC, B, float("nan")), ValueError, "`dt`"),
    ("check", lambda: an.amplification_matrix(OSC, B, 0.1, check="yes"), TypeError, "`check`"),
    ("integrator", lambda: an.amplification_matrix(OSC, "newmark", 0.1), TypeError, "`integrator`"),
    (
        "lte 2 dof",
        lambda: an.local_truncation_error(TWO, B, 0.1, [1, 0], [0, 0]),
        ValueError,
        "`system`",
    ),
    ("lte x0", lambda: an.local_truncation_error(OSC, B, 0.1, [1.0, 2.0], 0.0), ValueError, "`x0`"),
    ("one-step v0", lambda: an.one_step_error(TWO, B, 0.1, [1, 0], [0]), ValueError, "`v0`"),
    ("exact dt", lambda: an.exact_transition_matrix(OSC, 0.0), ValueError, "`dt`"),
    ("exact modes", lambda: an.exact_transition_matrix(TWO, 0.1, modes=3), ValueError, "`modes`"),
    ("newmark dt", lambda: an.newmark_amplification(1.0, 0.0, 0.0, 0.5, 0.25), ValueError, "`dt`"),
    (
        "newmark omega",
        lambda: an.newmark_amplification(-1.0, 0.0, 0.1, 0.5, 0.25),
        ValueError,
        "`omega`",
    ),
    (
        "newmark gamma",
        lambda: an.newmark_amplification(1.0, 0.0, 0.1, "0.5", 0.25),
        TypeError,
        "`gamma`",
    ),
    (
        "newmark sign",
        lambda: an.newmark_amplification(1.0, 0.0, 0.1, 0.5, 0.25, 0.3, alpha_sign=2),
        ValueError,
        "`alpha_sign`",
    ),
    ("closed beta", lambda: an.ClosedFormNewmark(0.5, float("inf")), ValueError, "`beta`"),
    ("model omega", lambda: an.model_oscillator(0.0), ValueError, "`omega`"),
    (
        "model sign",
        lambda: an.model_oscillator(alpha=0.3, alpha_sign=True),
        ValueError,
        "`alpha_sign`",
    ),
    ("model damping", lambda: an.model_oscillator(damping="rhs"), ValueError, "`damping`"),
    ("chart grid", lambda: an.stability_chart([B], [1.0, 0.5]), ValueError, "`dt_over_T`"),
    ("chart grid 2d", lambda: an.stability_chart([B], [[1.0, 2.0]]), ValueError, "`dt_over_T`"),
    ("chart empty", lambda: an.stability_chart([], [0.1, 1.0]), ValueError, "`integrators`"),
    ("chart str", lambda: an.stability_chart("b", [0.1, 1.0]), TypeError, "`integrators`"),
    ("chart zeta", lambda: an.stability_chart([B], [0.1, 1.0], zeta=None), TypeError, "`zeta`"),
    ("plot data", lambda: an.plot_stability_chart({"a": 1}), TypeError, "`data`"),
    ("problem", lambda: an.convergence_order(None, B, [0.1, 0.05]), TypeError, "`problem`"),
    ("dts short", lambda: an.convergence_order(lambda i, h: h, B, [0.1]), ValueError, "`dts`"),
    ("dts dup", lambda: an.convergence_order(lambda i, h: h, B, [0.1, 0.1]), ValueError, "`dts`"),
    ("dts neg", lambda: an.convergence_order(lambda i, h: h, B, [0.1, -0.1]), ValueError, "`dts`"),
    (
        "zero error",
        lambda: an.convergence_order(lambda i, h: 0.0, B, [0.1, 0.05]),
        ValueError,
        "`problem`",
    ),
    (
        "error type",
        lambda: an.convergence_order(lambda i, h: "x", B, [0.1, 0.05]),
        TypeError,
        "`problem`",
    ),
    ("reference", lambda: an.ReferenceProblem(OSC, 1.0, 3.0), TypeError, "`reference`"),
    (
        "measure",
        lambda: an.ReferenceProblem(OSC, 1.0, np.cos, measure="rms"),
        ValueError,
        "`measure`",
    ),
    ("t_end", lambda: an.ReferenceProblem(OSC, -1.0, np.cos), ValueError, "`t_end`"),
]


@pytest.mark.parametrize("label, call, exc, name", BAD, ids=[b[0] for b in BAD])
def test_bad_input(label, call, exc, name):
    with pytest.raises(exc, match=name):
        call()


def test_chart_label_and_plot_axes_errors(fig1):
    with pytest.raises(ValueError, match="`label`"):
        fig1.curve("d")
    with pytest.raises(ValueError, match="`ax`"):
        an.plot_stability_chart(fig1, [None, None])


def test_chart_labels_and_peak_tie_break():
    chart = an.stability_chart(
        [SCHEMES["a"], SCHEMES["a"], an.ClosedFormNewmark()], np.logspace(-1, 0.5, 31)
    )
    assert chart.labels == ("scheme (a)", "scheme (a) #2", "Newmark (gamma=0.5, beta=0.25)")
    assert chart.radius.shape == (3, 31) and chart.moduli.shape == (3, 31, 2)
    # equal maxima at dt/T = 0.75, 1.75, ...: the first one is reported
    assert chart.peak("scheme (a)")[0] == pytest.approx(0.75, abs=1e-6)

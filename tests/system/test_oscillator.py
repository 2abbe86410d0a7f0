"""The oscillator kernel against an independent reference.

The reference is Van Loan's augmented matrix exponential evaluated in 60- to 300-digit
arithmetic (mpmath), from the exact values of the float inputs: one exponential of
``[[F dt, e2 w3], [0, N]]`` (``N`` the shift of the polynomial chain w0 -> w1 -> w2 -> w3)
gives ``A`` and the Duhamel moments of ``s^0 .. s^3``.

Accuracy is measured in energy-scaled, dimensionless coordinates (``x``, ``x'/max(omega,
1/dt)``, load scaled to a displacement), max-norm relative to the largest entry of each
matrix. The only error the kernel cannot avoid is the rounding of its inputs' products
(``omega*dt`` and ``zeta*omega*dt``): a phase error ``~ omega*dt * eps``; the tolerance is
``1e-13 + 8 eps omega dt``, i.e. 1e-13 up to ``omega dt ~ 50`` and 1.9e-12 at ``omega dt = 1e3``.
"""

from __future__ import annotations

import mpmath as mp
import numpy as np
import pytest

from duhamel import _core
from duhamel.oscillator import transfer_matrices, transfer_moments

EPS = np.finfo(float).eps
ZETAS = [-0.5, -0.05, 0.0, 0.05, 0.5, 0.9999, 1.0 - 1e-9, 1.0, 1.0 + 1e-9, 1.0001, 1.5, 5.0, 20.0]
HS = [1e-8, 1e-5, 1e-3, 0.05, 0.7, 1.2, 1.45, 1.55, 2.1, 3.0, 10.0, 47.0, 200.0, 1000.0]


def reference(omega: float, zeta: float, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """A (2, 2) and moments (2, 4) from a high-precision Van Loan exponential."""
    w, z, t = mp.mpf(omega), mp.mpf(zeta), mp.mpf(dt)
    h = w * t
    # the phase h must keep ~60 digits after its integer part
    mp.mp.dps = 60 if h < 20 else max(300, int(mp.log10(h)) + 80)
    w, z, t = mp.mpf(omega), mp.mpf(zeta), mp.mpf(dt)
    g = mp.zeros(6, 6)
    # states: x, v, w3, w2, w1, w0 in the time unit dt; w3' = w2, w2' = w1, w1' = w0
    g[0, 1] = 1
    g[1, 0] = -((w * t) ** 2)
    g[1, 1] = -2 * z * w * t
    g[1, 2] = 1
    g[2, 3] = g[3, 4] = g[4, 5] = 1
    e = mp.expm(g)
    a = np.array([[e[0, 0], e[0, 1] * t], [e[1, 0] / t, e[1, 1]]], dtype=float)
    # initial w_j = 1 (state 5 - j) makes w3 = s^(3-j)/(3-j)!: column 2 + k gives s^k / k!
    m = np.zeros((2, 4))
    for k in range(4):
        col = 2 + k
        m[0, k] = float(e[0, col] * mp.factorial(k) * t**2)
        m[1, k] = float(e[1, col] * mp.factorial(k) * t)
    return a, m


def scaled_error(a, m, a_ref, m_ref, omega, dt):
    """Max-norm relative error in energy-scaled dimensionless coordinates."""
    s = max(omega, 1.0 / dt)
    sc = np.diag([1.0, 1.0 / s])
    sc_inv = np.diag([1.0, s])
    load = s * s  # a load p moves x by ~ p / s^2
    err = 0.0
    for got, ref in ((sc @ a @ sc_inv, sc @ a_ref @ sc_inv), (sc @ m * load, sc @ m_ref * load)):
        scale = np.abs(ref).max()
        if scale > 1e-280:  # everything underflowed (e.g. exp(-20000)): nothing to compare
            err = max(err, np.abs(got - ref).max() / scale)
    return err


@pytest.mark.parametrize("zeta", ZETAS)
def test_kernel_matches_high_precision_van_loan(zeta):
    omega = 3.0
    worst = []
    for h in HS:
        dt = h / omega
        a, m = transfer_moments(omega, zeta, dt)
        a_ref, m_ref = reference(omega, zeta, dt)
        err = scaled_error(a, m, a_ref, m_ref, omega, dt)
        worst.append(err)
        assert err <= 1e-13 + 8 * EPS * h, f"zeta={zeta} omega*dt={h}: error {err:.2e}"
    print(f"zeta={zeta}: max scaled error {max(worst):.1e}")


# Extreme but representable: (omega, zeta, dt) whose dimensionless h^2 = (omega dt)^2 or
# a^2 = (zeta omega dt)^2 overflows although the matrices are ordinary numbers (the issue's
# three examples first), and the edges of the far regime (omega dt > 1e50).
EXTREMES = [
    (1e200, 0.05, 1.0),
    (1.0, 0.1, 1e300),
    (1.0, 1e300, 1.0),
    (1e60, 0.0, 1.0),
    (1e60, 0.3, 1.0),
    (1e60, -1e-62, 1.0),
    (1.0, 0.05, 1e60),
    (1.0, 2.0, 1e60),
    (1.0, 1.0, 1e60),
    (1e-30, 0.01, 1e90),
    (3.0, 1e40, 1e10),
    (3.0, 1e160, 1.0),
    (1e100, 1e55, 1e-40),
    (2.0, 0.2, 3e49),
]


@pytest.mark.parametrize(("omega", "zeta", "dt"), EXTREMES)
def test_extreme_parameters_are_evaluated_not_refused(omega, zeta, dt):
    a, m = transfer_moments(omega, zeta, dt)
    assert np.all(np.isfinite(a)) and np.all(np.isfinite(m))
    a_ref, m_ref = reference(omega, zeta, dt)
    with np.errstate(over="ignore", invalid="ignore"):
        err = scaled_error(a, m, a_ref, m_ref, omega, dt)
    if np.isfinite(err):
        print(f"({omega:g}, {zeta:g}, {dt:g}): scaled error {err:.1e}")
        assert err <= 1e-12
    else:  # the energy scaling itself overflows (omega^2 = 1e400): every entry on its own
        print(f"({omega:g}, {zeta:g}, {dt:g}): A max {np.abs(a_ref).max():.1e}")
        assert np.allclose(a, a_ref, rtol=1e-12, atol=1e-300)
        assert np.allclose(m, m_ref, rtol=1e-12, atol=1e-300)
    # and entry by entry, wherever the exact value is a normal number
    for got, ref in ((a, a_ref), (m, m_ref)):
        normal = np.abs(ref) > 1e-305
        assert np.all(np.abs(got - ref)[normal] <= 1e-13 * np.abs(ref)[normal])
    # the stiffness-damping form agrees
    k, c = omega * omega, 2 * zeta * omega
    if np.isfinite(k) and np.isfinite(c):
        a_kc, b_kc = _core.transfer_kc(np.array([k]), np.array([c]), dt)
        _, b = transfer_matrices(omega, zeta, dt)
        assert np.allclose(a_kc[0], a, rtol=1e-12, atol=1e-300)
        assert np.allclose(b_kc[0], b, rtol=1e-12, atol=1e-12 * np.abs(b).max() + 1e-300)


@pytest.mark.parametrize(
    ("omega", "zeta", "dt"), [(1.0, -1000.0, 10.0), (1e200, -0.05, 1.0), (1e-300, 0.0, 1e300)]
)
def test_unrepresentable_step_matrices_are_refused(omega, zeta, dt):
    # growth e^(2e4), e^(5e198); displacement per unit load 1/omega^2 = 1e600
    with pytest.raises(ValueError, match="cannot be evaluated in double precision"):
        transfer_matrices(omega, zeta, dt)


@pytest.mark.parametrize("ratio", [0.9999, 1.0 - 1e-12, 1.0, 1.0 + 1e-7, 3.0])
def test_stiffness_damping_form_near_critical(ratio):
    """From (k, c) as modal analysis gives them: exact inputs k, c, dt in the reference."""
    k = 9.0
    c = 2.0 * ratio * 3.0
    for h in [0.5, 3.0, 47.0, 200.0]:
        dt = h / 3.0
        a, m = _core.transfer_kc(np.array([k]), np.array([c]), dt, True)
        mp.mp.dps = 300
        kk, cc, t = mp.mpf(k), mp.mpf(c), mp.mpf(dt)
        g = mp.zeros(6, 6)
        g[0, 1] = 1
        g[1, 0] = -kk * t * t
        g[1, 1] = -cc * t
        g[1, 2] = 1
        g[2, 3] = g[3, 4] = g[4, 5] = 1
        e = mp.expm(g)
        a_ref = np.array([[e[0, 0], e[0, 1] * t], [e[1, 0] / t, e[1, 1]]], dtype=float)
        m_ref = np.array(
            [[e[r, 2 + j] * mp.factorial(j) * t ** (2 - r) for j in range(4)] for r in range(2)],
            dtype=float,
        )
        err = scaled_error(a[0], m[0], a_ref, m_ref, 3.0, dt)
        assert err <= 1e-13 + 8 * EPS * h, f"c/(2 omega)={ratio} omega*dt={h}: {err:.2e}"


@pytest.mark.parametrize("c", [0.0, 0.3, 2.0, 40.0, -0.2])
def test_rigid_body_mode_with_damping(c):
    """omega = 0 with damping c (q'' + c q' = p): a Rayleigh-damped rigid-body mode."""
    for dt in [1e-6, 0.01, 0.5, 3.0, 100.0]:
        a, m = _core.transfer_kc(np.array([0.0]), np.array([c]), dt, True)
        # closed form of q'' + c q' = s^k from rest via high precision
        mp.mp.dps = 50
        cc, t = mp.mpf(c), mp.mpf(dt)
        g = mp.zeros(6, 6)
        g[0, 1] = 1
        g[1, 1] = -cc * t
        g[1, 2] = 1
        g[2, 3] = g[3, 4] = g[4, 5] = 1
        e = mp.expm(g)
        ref_a = np.array([[e[0, 0], e[0, 1] * t], [e[1, 0] / t, e[1, 1]]], dtype=float)
        assert np.allclose(a[0], ref_a, rtol=1e-14, atol=1e-300)
        for k in range(4):
            col = 2 + k
            ref = np.array([e[0, col] * t**2, e[1, col] * t], dtype=float) * float(mp.factorial(k))
            np.testing.assert_allclose(m[0][:, k], ref, rtol=1e-13)


def test_b_is_built_from_the_parabola_basis():
    """B applied to (p0, Dp, DDp) equals the moments applied to the parabola's coefficients."""
    omega, zeta, dt = 7.0, 0.03, 0.21
    _, b = transfer_matrices(omega, zeta, dt)
    _, m = transfer_moments(omega, zeta, dt)
    p0, dp, ddp = 1.3, -0.4, 0.25
    # p(s) = p0 + Dp s + 4 DDp s (1 - s) = p0 + (Dp + 4 DDp) s - 4 DDp s^2
    coeffs = np.array([p0, dp + 4 * ddp, -4 * ddp, 0.0])
    np.testing.assert_allclose(b @ [p0, dp, ddp], m @ coeffs, rtol=1e-14)


def test_rigid_body_paper_values():
    dt = 0.4
    a, b = transfer_matrices(0.0, 0.0, dt)
    np.testing.assert_array_equal(a, [[1.0, dt], [0.0, 1.0]])
    expect = [[dt**2 / 2, dt**2 / 6, dt**2 / 3], [dt, dt / 2, 2 * dt / 3]]
    np.testing.assert_allclose(b, expect, rtol=1e-15)


def test_paper_closed_forms_where_they_are_accurate():
    """The paper's b11..b23 (NOTES.md section 1) at h = 0.9, where they lose nothing."""
    omega, zeta, dt = 3.0, 0.05, 0.3
    h = omega * dt
    wd = omega * np.sqrt(1 - zeta**2)
    r = np.sqrt(1 - zeta**2)
    e, c, sn = np.exp(-zeta * h), np.cos(wd * dt), np.sin(wd * dt)
    b11 = (1 - e * (c + zeta * sn / r)) / omega**2
    b12 = (h - 2 * zeta + e * (2 * zeta * c - (1 - 2 * zeta**2) * sn / r)) / (omega**2 * h)
    b13 = (
        8 * (1 + zeta * h - 4 * zeta**2)
        - 4 * e * ((1 - 2 * zeta**2) * h + 2 * zeta * (3 - 4 * zeta**2)) * sn / r
        - 8 * e * (1 - zeta * h - 4 * zeta**2) * c
    ) / (omega**2 * h**2)
    b21 = e * sn / wd
    b23 = (
        4 * (4 * zeta - h)
        - 4 * e * (4 * zeta + h) * c
        + 4 * (2 * (1 - 2 * zeta**2) - zeta * h) * e * sn / r
    ) / (omega * h**2)
    _, b = transfer_matrices(omega, zeta, dt)
    np.testing.assert_allclose(b, [[b11, b12, b13], [b21, b11 / dt, b23]], rtol=1e-12)


def test_shapes_and_broadcasting():
    a, b = transfer_matrices([1.0, 2.0, 3.0], 0.05, 0.1)
    assert a.shape == (3, 2, 2) and b.shape == (3, 2, 3)
    a1, _ = transfer_matrices(2.0, 0.05, 0.1)
    np.testing.assert_array_equal(a[1], a1)
    a, m = transfer_moments(np.array([1.0, 2.0]), np.array([0.0, 1.0]), 0.1)
    assert a.shape == (2, 2, 2) and m.shape == (2, 2, 4)


@pytest.mark.parametrize(
    ("args", "exc", "match"),
    [
        ((1.0, 0.0, 0.0), ValueError, "`dt`"),
        ((1.0, 0.0, -1.0), ValueError, "`dt`"),
        ((1.0, 0.0, float("nan")), ValueError, "`dt`"),
        ((-1.0, 0.0, 0.1), ValueError, "`omega`"),
        ((float("nan"), 0.0, 0.1), ValueError, "`omega`"),
        ((1.0, float("inf"), 0.1), ValueError, "`zeta`"),
        (([1.0, 2.0], [0.1, 0.2, 0.3], 0.1), ValueError, "`omega` and `zeta`"),
        ((np.ones((2, 2)), 0.0, 0.1), ValueError, "`omega`"),
        ((1 + 2j, 0.0, 0.1), TypeError, "`omega`"),
        (("fast", 0.0, 0.1), TypeError, "`omega`"),
        ((1.0, 0.0, "0.1"), TypeError, "`dt`"),
    ],
)
def test_bad_input_names_the_parameter(args, exc, match):
    with pytest.raises(exc, match=match):
        transfer_matrices(*args)


def test_core_rejects_wrong_dtype_and_non_contiguous_arrays():
    k = np.arange(8.0)
    with pytest.raises(TypeError, match=r"`omega`.*float64"):
        _core.transfer(k.astype(np.float32), np.zeros(8, dtype=np.float32), 0.1)
    with pytest.raises(TypeError, match=r"`k`.*float64"):
        _core.transfer_kc(k.astype(np.int64), np.zeros(8), 0.1)
    with pytest.raises(ValueError, match=r"`omega` must be C-contiguous"):
        _core.transfer(k[::2], np.zeros(4), 0.1)
    with pytest.raises(TypeError, match="`zeta`"):
        _core.transfer(k, [0.0] * 8, 0.1)

"""The exact reference solutions of ``duhamel.exact`` against tight ``solve_ivp`` solutions.

Every closed form is compared with DOP853 at ``rtol = 1e-13`` (and ``atol`` 1e-15 of the
amplitude); the agreement required is 1e-9 of the largest amplitude (measured: 1e-11 or
better).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg as sla
import scipy.sparse as sp
from scipy.integrate import solve_ivp
from scipy.special import ellipk

import duhamel
from duhamel import exact

TOL = 1e-9


def ivp(rhs, y0, t, scale, events=None):
    """DOP853 at rtol 1e-13; returns the states at `t` (shape (len(t), n)) and the solution."""
    sol = solve_ivp(
        rhs,
        (0.0, float(t[-1])),
        np.asarray(y0, dtype=float),
        method="DOP853",
        rtol=1e-13,
        atol=1e-15 * scale,
        t_eval=t,
        events=events,
    )
    assert sol.success, sol.message
    return sol.y.T, sol


def rel_err(got, want):
    return float(np.max(np.abs(got - want)) / np.max(np.abs(want)))


# --------------------------------------------------------------------------------- Duffing


def duffing_ivp(t, omega, b, x0, events=None):
    def rhs(_, y):
        return [y[1], -(omega**2) * y[0] - b * y[0] ** 3]

    return ivp(rhs, [x0, 0.0], t, abs(x0), events)


@pytest.mark.parametrize(
    ("omega", "b", "x0"),
    [
        (1.0, 4.0, 1.0),  # the paper's case, b x0^2 = 4 omega^2
        (2.0, 16.0, -1.0),  # the same ratio, other omega and sign of x0
        (1.3, 0.3, 2.0),  # mildly hardening
        (0.0, 1.0, 1.5),  # pure cubic, m = 1/2
        (2.0, -1.0, 1.5),  # softening, m < 0
        (1.0, -0.9, 1.0),  # softening close to the separatrix
        (1.0, 0.0, 0.7),  # linear
    ],
)
def test_duffing_matches_ivp(omega, b, x0):
    period = exact.duffing_period(omega, b, x0)
    t = np.linspace(0.0, 10.0 * period, 2001)
    x, v = exact.duffing(t, omega, b, x0)
    y, _ = duffing_ivp(t, omega, b, x0)
    assert x.shape == v.shape == t.shape
    amp = abs(x0)
    assert np.max(np.abs(x - y[:, 0])) < TOL * amp
    assert np.max(np.abs(v - y[:, 1])) < TOL * amp * np.max(np.abs(y[:, 1])) / amp


def test_duffing_paper_case_period():
    # b x0^2 = 4 omega^2: Omega = sqrt(5) omega, m = 0.4, period 3.179723 / omega
    for omega in (1.0, 2.5):
        x0 = 0.3
        b = 4.0 * omega**2 / x0**2
        period = exact.duffing_period(omega, b, x0)
        assert period * omega == pytest.approx(3.179723, abs=5e-7)
        assert period * omega == pytest.approx(4 * ellipk(0.4) / math.sqrt(5), rel=1e-14)
    omega, b, x0 = 1.0, 4.0, 1.0
    period = exact.duffing_period(omega, b, x0)
    # the same period from the zero crossings of the numerical solution
    t = np.linspace(0.0, 3.2 * period, 50)

    def crossing(_, y):
        return y[0]

    _, sol = duffing_ivp(t, omega, b, x0, events=crossing)
    zeros = sol.t_events[0]
    assert zeros.size >= 6
    assert np.max(np.abs(np.diff(zeros[::2]) - period)) < 1e-10
    assert zeros[0] == pytest.approx(period / 4, abs=1e-10)
    x, v = exact.duffing([period, 5 * period], omega, b, x0)
    np.testing.assert_allclose(x, x0, atol=1e-12)
    np.testing.assert_allclose(v, 0.0, atol=1e-11)


def test_duffing_period_other_cases():
    assert exact.duffing_period(2.0, 0.0, 1.0) == pytest.approx(math.pi, rel=1e-15)
    assert exact.duffing_period(2.0, 5.0, 0.0) == pytest.approx(math.pi, rel=1e-15)
    assert exact.duffing_period(1.0, -1.0, 1.0) == math.inf  # at the barrier top
    assert exact.duffing_period(0.0, 1.0, 0.0) == math.inf
    # softening lengthens the period, increasingly towards the separatrix
    periods = [exact.duffing_period(1.0, b, 1.0) for b in (0.0, -0.5, -0.9, -0.99)]
    assert np.all(np.diff(periods) > 0)


def test_duffing_equilibria_and_shapes():
    x, v = exact.duffing(np.array([[0.0, 1.0], [2.0, 3.0]]), 1.0, -1.0, 1.0)  # barrier top
    assert x.shape == (2, 2)
    np.testing.assert_array_equal(x, 1.0)
    np.testing.assert_array_equal(v, 0.0)
    x, v = exact.duffing(2.0, 1.0, 3.0, 0.0)
    assert x.shape == () and float(x) == 0.0 and float(v) == 0.0


@pytest.mark.parametrize(("omega", "b", "x0"), [(1.0, 4.0, 1.0), (2.0, -1.0, 1.5)])
def test_duffing_against_mpmath(omega, b, x0):
    # 40-digit cn(u | m) (mpmath accepts m < 0 directly); the argument reduction modulo 4 K
    # keeps the error at the conditioning level eps * Omega t even for 1e5 s
    mp = pytest.importorskip("mpmath")
    mp.mp.dps = 40
    big = mp.sqrt(mp.mpf(omega) ** 2 + mp.mpf(b) * mp.mpf(x0) ** 2)
    m = mp.mpf(b) * mp.mpf(x0) ** 2 / (2 * big**2)
    t = np.array([0.7, 123.4, 98765.4])
    x, v = exact.duffing(t, omega, b, x0)
    for xi, vi, ti in zip(x, v, t, strict=True):
        u = big * mp.mpf(float(ti))
        cn, sn, dn = (mp.re(mp.ellipfun(k, u, m=m)) for k in ("cn", "sn", "dn"))
        tol = 1e-14 + 1e-15 * float(big) * ti
        assert abs(xi - float(x0 * cn)) < tol * abs(x0)
        assert abs(vi + float(x0 * big * sn * dn)) < tol * abs(x0) * float(big)


def test_duffing_errors():
    with pytest.raises(ValueError, match="unbounded"):
        exact.duffing([0.0, 1.0], 1.0, -2.0, 1.0)
    with pytest.raises(ValueError, match="`omega`"):
        exact.duffing([0.0], -1.0, 1.0, 1.0)
    with pytest.raises(ValueError, match="`t`"):
        exact.duffing([-1.0], 1.0, 1.0, 1.0)
    with pytest.raises(ValueError, match="`t`"):
        exact.duffing([np.nan], 1.0, 1.0, 1.0)
    with pytest.raises(TypeError, match="`b`"):
        exact.duffing([0.0], 1.0, "4", 1.0)
    with pytest.raises(ValueError, match="`x0`"):
        exact.duffing([0.0], 1.0, 1.0, math.inf)
    with pytest.raises(ValueError, match="unbounded"):
        exact.duffing_period(0.0, -1.0, 1.0)


# ----------------------------------------------------------------- decaying-mass pendulum


def pendulum_ivp(t, a, omega, w0, v0, f_step, m0):
    def rhs(s, y):
        return [y[1], a * omega * y[1] - omega**2 * y[0] + f_step / m0 * math.exp(a * omega * s)]

    scale = max(abs(w0), abs(v0) / omega, abs(f_step) / (m0 * omega**2))
    return ivp(rhs, [w0, v0], t, scale)[0]


@pytest.mark.parametrize(
    ("a", "omega", "w0", "v0", "f_step", "m0"),
    [
        (0.1, 1.0, 1.0, 2.0, 1.0, 1.0),  # the paper's case
        (0.1, 2.5, 0.2, 1.0, 3.75, 3.0),  # the same dimensionless case, other units
        (0.1, 1.0, 0.0, 0.5, 1.0, 1.0),  # w0 = 0
        (0.1, 1.0, 0.0, 0.0, 2.0, 1.0),  # from rest
        (-0.4, 1.5, 1.0, -1.0, 0.5, 2.0),  # growing mass (positive damping)
        (1.9, 1.0, 1.0, 0.0, 0.0, 1.0),  # fast decay, free vibration
    ],
)
def test_pendulum_matches_ivp(a, omega, w0, v0, f_step, m0):
    t = np.linspace(0.0, 5 * 2 * np.pi / omega, 1001)
    w, wdot = exact.decaying_mass_pendulum(t, a, omega, w0, v0, f_step, m0)
    y = pendulum_ivp(t, a, omega, w0, v0, f_step, m0)
    assert w.shape == wdot.shape == t.shape
    assert rel_err(w, y[:, 0]) < TOL
    assert rel_err(wdot, y[:, 1]) < TOL


def test_pendulum_is_the_corrected_eq31():
    # eq. 31 in the paper's dimensionless form, with the corrected sine coefficient
    # (v0 / (w0 omega) - a/2) / sqrt(1 - (a/2)^2); f = f_step / (omega^2 w0 m0)
    a, omega, w0, m0 = 0.1, 1.3, 0.5, 2.0
    ratio, f = 2.0, 1.0
    v0, f_step = ratio * w0 * omega, f * omega**2 * w0 * m0
    t = np.linspace(0.0, 5 * 2 * np.pi / omega, 501)
    wd = omega * math.sqrt(1 - (a / 2) ** 2)
    r = math.sqrt(1 - (a / 2) ** 2)
    c, s = np.cos(wd * t), np.sin(wd * t)
    free = np.exp(a * omega * t / 2) * (c + (ratio - a / 2) / r * s)
    forced = f * (np.exp(a * omega * t) - np.exp(a * omega * t / 2) * (c + (a / 2) / r * s))
    w, _ = exact.decaying_mass_pendulum(t, a, omega, w0, v0, f_step, m0)
    assert rel_err(w / w0, free + forced) < 1e-13
    # the printed sign (+ a/2) does not solve the equation
    wrong = np.exp(a * omega * t / 2) * (c + (ratio + a / 2) / r * s) + forced
    assert rel_err(wrong, w / w0) > 1e-2


def test_pendulum_errors():
    args = dict(omega=1.0, w0=1.0, v0=0.0, f_step=1.0)
    for a in (2.0, -2.0, 3.0):
        with pytest.raises(ValueError, match=r"`a` must satisfy \|a\| < 2"):
            exact.decaying_mass_pendulum([0.0], a, **args)
    with pytest.raises(ValueError, match="`omega` must be positive"):
        exact.decaying_mass_pendulum([0.0], 0.1, 0.0, 1.0, 0.0, 1.0)
    with pytest.raises(ValueError, match="`m0` must be positive"):
        exact.decaying_mass_pendulum([0.0], 0.1, **args, m0=0.0)
    with pytest.raises(ValueError, match="`t`"):
        exact.decaying_mass_pendulum([0.0, -0.1], 0.1, **args)
    with pytest.raises(TypeError, match="`f_step`"):
        exact.decaying_mass_pendulum([0.0], 0.1, 1.0, 1.0, 0.0, None)


# ------------------------------------------------------------------------- Bessel mass law


def bessel_ivp(t, a, K, omega, x0, v0):
    def rhs(s, y):
        return [y[1], 2 * a * omega * y[1] - omega**2 / K * math.exp(2 * a * omega * s) * y[0]]

    return ivp(rhs, [x0, v0], t, max(abs(x0), abs(v0) / omega))[0]


@pytest.mark.parametrize(
    ("a", "K", "omega", "x0", "v0", "t_end"),
    [
        (1 / 20, 1.0, 1.0, 1.0, 0.0, 40.0),  # the paper's case, chi = a sqrt(K) = 1/20
        (1 / 20, 4.0, 1.0, 1.0, 0.0, 60.0),  # heavier initial mass, chi = 1/10
        (1 / 20, 0.25, 2.0, 1.0, 0.0, 20.0),
        (0.2, 0.5, 1.0, 0.0, 1.0, 20.0),  # from the rest position
        (-0.05, 2.0, 1.5, 1.0, 0.3, 40.0),  # growing mass
        (0.0, 2.0, 1.0, 1.0, -0.5, 30.0),  # constant mass
    ],
)
def test_bessel_mass_matches_ivp(a, K, omega, x0, v0, t_end):
    t = np.linspace(0.0, t_end, 1201)
    x, v = exact.bessel_mass(t, a, K, omega, x0, v0)
    y = bessel_ivp(t, a, K, omega, x0, v0)
    assert x.shape == v.shape == t.shape
    assert rel_err(x, y[:, 0]) < TOL
    assert rel_err(v, y[:, 1]) < TOL


def test_bessel_mass_paper_form():
    # x = xi [C1 J1(xi / chi) + C2 Y1(xi / chi)], xi = exp(a omega t): two solutions of the
    # same ODE are combinations of the same two functions
    from scipy.special import j1, y1

    a, K, omega = 0.05, 1.0, 1.0
    chi = a * math.sqrt(K)
    t = np.linspace(0.0, 30.0, 7)
    xi = np.exp(a * omega * t)
    basis = np.column_stack([xi * j1(xi / chi), xi * y1(xi / chi)])
    for x0, v0 in ((1.0, 0.0), (0.0, 1.0), (0.3, -2.0)):
        x, _ = exact.bessel_mass(t, a, K, omega, x0, v0)
        coef, *_ = np.linalg.lstsq(basis, x, rcond=None)
        assert rel_err(basis @ coef, x) < 1e-12


def test_bessel_mass_errors():
    with pytest.raises(ValueError, match="`K` must be positive"):
        exact.bessel_mass([0.0], 0.05, 0.0, 1.0, 1.0, 0.0)
    with pytest.raises(ValueError, match="`omega` must be positive"):
        exact.bessel_mass([0.0], 0.05, 1.0, -1.0, 1.0, 0.0)
    with pytest.raises(ValueError, match="`t`"):
        exact.bessel_mass([-1.0], 0.05, 1.0, 1.0, 1.0, 0.0)
    with pytest.raises(ValueError, match="`a`"):
        exact.bessel_mass([0.0], math.nan, 1.0, 1.0, 1.0, 0.0)
    with pytest.raises(TypeError, match="`v0`"):
        exact.bessel_mass([0.0], 0.05, 1.0, 1.0, 1.0, [0.0])


# ------------------------------------------------------------------------- linear systems

M3 = np.diag([1.0, 2.0, 1.5])
K3 = np.array([[300.0, -100.0, 0.0], [-100.0, 250.0, -150.0], [0.0, -150.0, 150.0]])
X0 = np.array([0.01, -0.02, 0.03])
V0 = np.array([0.1, 0.0, -0.2])


def linear_ivp(m, k, c, x0, v0, t, force):
    n = m.shape[0]
    minv = np.linalg.inv(m)

    def rhs(s, y):
        return np.concatenate([y[n:], minv @ (force(s) - k @ y[:n] - c @ y[n:])])

    y, _ = ivp(rhs, np.concatenate([x0, v0]), t, 1e-3)
    return y[:, :n], y[:, n:]


def modal_damping(m, k, zeta):
    lam, phi = sla.eigh(k, m)
    mphi = m @ phi
    return (mphi * (2 * zeta * np.sqrt(np.clip(lam, 0, None)))) @ mphi.T


POLY = np.array([[1.0, 0.0, 2.0], [0.5, -1.0, 0.0], [0.0, 0.3, 0.1], [0.02, 0.0, -0.01]])


def poly_force(s):
    return sum(POLY[k] * s**k for k in range(POLY.shape[0]))


def harmonic_force(s):
    return np.array([1.0, -2.0, 0.5]) * np.sin(7.3 * s + 0.4)


LOADS = {
    "polynomial": (("polynomial", POLY), poly_force),
    "harmonic": (("harmonic", np.array([1.0, -2.0, 0.5]), 7.3, 0.4), harmonic_force),
    "free": (None, lambda s: np.zeros(3)),
}

DAMPINGS = {
    "zeta": (dict(zeta=0.03), modal_damping(M3, K3, 0.03)),
    "rayleigh": (dict(rayleigh=(0.2, 1e-3)), 0.2 * M3 + 1e-3 * K3),
    "matrix": (dict(C=0.01 * K3 + 0.1 * M3), 0.01 * K3 + 0.1 * M3),
    "none": ({}, np.zeros((3, 3))),
}


@pytest.mark.parametrize(
    ("load_name", "damping"),
    [("polynomial", d) for d in DAMPINGS]
    + [(ld, d) for ld in ("harmonic", "free") for d in ("zeta", "none")],
)
def test_linear_matches_ivp(load_name, damping):
    kwargs, c = DAMPINGS[damping]
    load, force = LOADS[load_name]
    system = duhamel.System(M3, K3, **kwargs)
    t = np.linspace(0.0, 4.0, 161)
    x, v = exact.linear(system, t, X0, V0, load)
    xr, vr = linear_ivp(M3, K3, c, X0, V0, t, force)
    assert x.shape == v.shape == (t.size, 3)
    assert rel_err(x, xr) < TOL
    assert rel_err(v, vr) < TOL


def test_linear_sparse_and_unsorted_times():
    system = duhamel.System(sp.csr_matrix(M3), sp.csr_matrix(K3), zeta=0.03)
    t = np.array([3.0, 0.5, 0.0, 2.25, 0.5])
    load = LOADS["harmonic"][0]
    x, v = exact.linear(system, t, X0, V0, load)
    xr, vr = exact.linear(duhamel.System(M3, K3, zeta=0.03), np.sort(t), X0, V0, load)
    order = np.argsort(t, kind="stable")
    np.testing.assert_allclose(x[order], xr, rtol=0, atol=1e-15)
    np.testing.assert_allclose(v[order], vr, rtol=0, atol=1e-14)
    np.testing.assert_array_equal(x[2], X0)


def test_linear_free_free_rigid_body():
    # two masses on one spring, no support: a rigid-body mode and Rayleigh damping alpha M
    m = np.diag([1.0, 3.0])
    k = np.array([[40.0, -40.0], [-40.0, 40.0]])
    alpha, beta = 0.1, 0.002
    system = duhamel.System(m, k, rayleigh=(alpha, beta))
    assert system.modal().omega2[0] == 0.0
    coeffs = np.array([[1.0, 0.0], [0.0, 0.5]])  # f = (1, 0.5 t)
    x0, v0 = np.array([0.0, 0.1]), np.array([1.0, -0.5])
    t = np.linspace(0.0, 10.0, 201)
    x, v = exact.linear(system, t, x0, v0, ("polynomial", coeffs))
    xr, vr = linear_ivp(m, k, alpha * m + beta * k, x0, v0, t, lambda s: coeffs[0] + coeffs[1] * s)
    assert rel_err(x, xr) < TOL
    assert rel_err(v, vr) < TOL
    # the centre of mass obeys mt y'' + alpha mt y' = total force, in closed form
    mt = np.trace(m)
    p = m.diagonal() @ v0
    y0 = m.diagonal() @ x0 / mt
    a0, a1 = coeffs.sum(axis=1) / mt  # total force / mt = a0 + a1 t
    # y' = u: u' + alpha u = a0 + a1 t
    u_inf = (a0 - a1 / alpha) / alpha + a1 * t / alpha
    u = u_inf + (p / mt - (a0 - a1 / alpha) / alpha) * np.exp(-alpha * t)
    np.testing.assert_allclose(v @ m.diagonal() / mt, u, rtol=1e-12, atol=1e-12)
    y = (
        y0
        + (a0 - a1 / alpha) / alpha * t
        + a1 * t**2 / (2 * alpha)
        + (p / mt - (a0 - a1 / alpha) / alpha) * (1 - np.exp(-alpha * t)) / alpha
    )
    np.testing.assert_allclose(x @ m.diagonal() / mt, y, rtol=1e-12, atol=1e-12)


def test_linear_undamped_free_free_is_polynomial():
    # no stiffness at all: x = x0 + v0 t + M^-1 (c0 t^2 / 2 + c1 t^3 / 6)
    m = np.diag([2.0, 4.0])
    system = duhamel.System(m, np.zeros((2, 2)))
    coeffs = np.array([[2.0, -4.0], [6.0, 12.0]])
    t = np.linspace(0.0, 5.0, 11)
    x0, v0 = np.array([1.0, 2.0]), np.array([-1.0, 0.5])
    x, v = exact.linear(system, t, x0, v0, ("polynomial", coeffs))
    minv = 1 / m.diagonal()
    tt = t[:, None]
    xr = x0 + v0 * tt + minv * (coeffs[0] * tt**2 / 2 + coeffs[1] * tt**3 / 6)
    vr = v0 + minv * (coeffs[0] * tt + coeffs[1] * tt**2 / 2)
    np.testing.assert_allclose(x, xr, rtol=1e-13, atol=1e-13)
    np.testing.assert_allclose(v, vr, rtol=1e-13, atol=1e-13)


def test_linear_errors():
    system = duhamel.System(M3, K3, zeta=0.03)
    t = [0.0, 1.0]
    with pytest.raises(TypeError, match="`system`"):
        exact.linear(M3, t, X0, V0)
    with pytest.raises(TypeError, match="`load`"):
        exact.linear(system, t, X0, V0, lambda s: np.zeros(3))
    with pytest.raises(ValueError, match="`load` kind"):
        exact.linear(system, t, X0, V0, ("ramp", POLY))
    with pytest.raises(ValueError, match="`load`"):
        exact.linear(system, t, X0, V0, ("polynomial",))
    with pytest.raises(ValueError, match="`load`"):
        exact.linear(system, t, X0, V0, ("harmonic", np.ones(3), 1.0))
    with pytest.raises(ValueError, match="`coeffs`"):
        exact.linear(system, t, X0, V0, ("polynomial", np.ones((2, 2))))
    with pytest.raises(ValueError, match="`coeffs`"):
        exact.linear(system, t, X0, V0, ("polynomial", np.ones(3)))
    with pytest.raises(ValueError, match="`amplitude`"):
        exact.linear(system, t, X0, V0, ("harmonic", np.ones(2), 1.0, 0.0))
    with pytest.raises(ValueError, match="`Omega`"):
        exact.linear(system, t, X0, V0, ("harmonic", np.ones(3), math.inf, 0.0))
    with pytest.raises(ValueError, match="`x0`"):
        exact.linear(system, t, X0[:2], V0)
    with pytest.raises(ValueError, match="`v0`"):
        exact.linear(system, t, X0, [0.0, 0.0, math.nan])
    with pytest.raises(ValueError, match="`t`"):
        exact.linear(system, [[0.0, 1.0]], X0, V0)
    with pytest.raises(ValueError, match="`t`"):
        exact.linear(system, [-1.0, 1.0], X0, V0)

"""Time-varying mass: accuracy and convergence of the two pseudo-force treatments.

Models (Holl, Belyaev & Irschik 1999, sections 4.2 and 4.3; NOTES.md section 3):

* the pendulum with decaying mass, ``(m w')' + m omega^2 w = f_step``,
  ``m = m0 exp(-a omega t)``: momentum form, stiffness scaling with the mass;
* the Bessel mass, ``(m x')' + m0 omega^2 x = 0``, ``m = m0 K exp(-2 a omega t)``: momentum
  form, constant stiffness;
* a harmonic mass ``M0 [1 + xi sin(nu t)]`` against a tight ``solve_ivp`` reference.

Errors are normalised like the paper's Fig. 4(b), ``max |w_calc - w_exact| / w0``. Orders are
least-squares slopes of ``log(error)`` against ``log(dt)`` over four halvings of the step.
``pytest -s tests/system/test_mass.py`` prints the measured numbers (they are the table of
docs/mass.md).
"""

from __future__ import annotations

import functools
import itertools
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import duhamel
from duhamel.exact import bessel_mass, decaying_mass_pendulum

TREATMENTS = ("eliminate", "estimate")

# The paper's pendulum, in non-unit dimensions (the normalised error does not depend on them):
# a = 1/10, w0'/(w0 omega) = 2, f_step/(omega^2 w0 m0) = 1, omega dt = 2 pi/10, five periods.
P_A, P_OMEGA, P_M0, P_W0 = 0.1, 2.0, 3.0, 0.5
P_V0 = 2.0 * P_W0 * P_OMEGA
P_F = P_OMEGA**2 * P_W0 * P_M0
P_PERIOD = 2.0 * math.pi / P_OMEGA

# Section 4.3: a = 1/20 (chi = a sqrt(K) = 1/20 for K = 1), x0 = 1, v0 = 0. The paper gives no
# time span; we use omega t in [0, 20] (the mass decays to exp(-2) = 13.5 %, the instantaneous
# frequency grows to e omega). Over five periods (omega t = 31.4, mass 4.3 %, frequency
# 4.8 omega) the paper's step leaves about two steps per instantaneous period.
B_A, B_OMEGA, B_M0 = 0.05, 1.0, 1.0
B_T_END = 20.0 / B_OMEGA
B_PERIOD = 2.0 * math.pi / B_OMEGA

PAPER_STEPS = 10  # steps per period: omega dt = 2 pi / 10
ORDER_STEPS = (40, 80, 160, 320)  # four halvings, in the asymptotic range
ALL_STEPS = (PAPER_STEPS, 20, *ORDER_STEPS)


def order(steps, errors):
    """Least-squares slope of log(error) against log(dt), dt = period / steps."""
    dts = 1.0 / np.asarray(steps, dtype=float)
    return float(np.polyfit(np.log(dts), np.log(np.asarray(errors)), 1)[0])


def integrator(treatment, quadrature="trapezoid"):
    return duhamel.Semianalytic(scheme="b", quadrature=quadrature, mass_treatment=treatment)


def one_dof(m, k):
    return duhamel.System(np.array([[m]]), np.array([[k]]))


# ------------------------------------------------------------------------------ the models


def pendulum_system(scale_stiffness=True):
    sys = one_dof(P_M0, P_M0 * P_OMEGA**2)
    sys.set_mass_law(
        duhamel.mass.Exponential(rate=-P_A * P_OMEGA),
        form="momentum",
        scale_stiffness=scale_stiffness,
    )
    sys.add_load(duhamel.loads.Step(0, amplitude=P_F))
    return sys


@functools.cache
def pendulum_error(treatment, steps, quadrature="trapezoid", scale_stiffness=True):
    sol = duhamel.solve(
        pendulum_system(scale_stiffness),
        integrator(treatment, quadrature),
        t_end=5 * P_PERIOD,
        dt=P_PERIOD / steps,
        x0=[P_W0],
        v0=[P_V0],
    )
    assert sol.t[-1] == pytest.approx(5 * P_PERIOD)
    w, _ = decaying_mass_pendulum(sol.t, P_A, P_OMEGA, P_W0, P_V0, P_F, P_M0)
    return float(np.abs(sol.x[:, 0] - w).max() / P_W0)


def bessel_system(K):
    sys = one_dof(B_M0, B_M0 * B_OMEGA**2)
    sys.set_mass_law(
        duhamel.mass.Exponential(rate=-2.0 * B_A * B_OMEGA, scale=K),
        form="momentum",
        scale_stiffness=False,
    )
    return sys


@functools.cache
def bessel_error(treatment, steps, K, t_end=B_T_END):
    sol = duhamel.solve(
        bessel_system(K),
        integrator(treatment),
        t_end=t_end,
        dt=B_PERIOD / steps,
        x0=[1.0],
        v0=[0.0],
    )
    x, _ = bessel_mass(sol.t, B_A, K, B_OMEGA, 1.0, 0.0)
    return float(np.abs(sol.x[:, 0] - x).max())  # x0 = 1: already normalised


MODELS = {
    "pendulum": lambda treatment, steps: pendulum_error(treatment, steps),
    "bessel K=1": lambda treatment, steps: bessel_error(treatment, steps, 1.0),
    "bessel K=2": lambda treatment, steps: bessel_error(treatment, steps, 2.0),
}


# ------------------------------------------------- the duhamel models are the exact equations


@pytest.mark.parametrize("treatment", TREATMENTS)
@pytest.mark.parametrize("model", list(MODELS))
def test_model_converges_to_the_exact_solution(model, treatment):
    # A fine step approaches the closed form, and each halving divides the error by 4: the
    # duhamel model solves the equation of the exact solution (not a neighbouring one).
    fine, finer = (MODELS[model](treatment, n) for n in (640, 1280))
    print(
        f"\n{model:11s} {treatment:9s} error at 640 / 1280 steps per period: "
        f"{fine:.3e} / {finer:.3e}"
    )
    assert finer < 2e-3
    assert fine / finer == pytest.approx(4.0, rel=0.02)


def test_pendulum_without_scaled_stiffness_is_another_equation():
    # Negative control: a constant stiffness m0 omega^2 is not the pendulum, and the error
    # against the pendulum's closed form does not shrink with the step.
    errors = [pendulum_error("eliminate", n, scale_stiffness=False) for n in (40, 160, 640)]
    print("\nconstant-stiffness 'pendulum' vs eq. 31:", " ".join(f"{e:.3g}" for e in errors))
    assert min(errors) > 1.0


# ----------------------------------------------------------------------- error and order


@pytest.mark.parametrize("treatment", TREATMENTS)
@pytest.mark.parametrize("model", list(MODELS))
def test_error_and_order(model, treatment):
    errors = [MODELS[model](treatment, n) for n in ALL_STEPS]
    p = order(ORDER_STEPS, errors[2:])
    local = [math.log2(e0 / e1) for e0, e1 in itertools.pairwise(errors)]
    print(
        f"\n{model:11s} {treatment:9s} paper step {errors[0]:.4g}; errors at "
        + ", ".join(f"{n}: {e:.3e}" for n, e in zip(ALL_STEPS, errors, strict=True))
        + f"; order (40-320) {p:.3f}; local orders "
        + " ".join(f"{q:.2f}" for q in local)
    )
    # Both treatments are second order (measured 1.99-2.00 for all six cases). The estimate
    # (v1 - v0)/dt is first-order at the step ends, but its errors at the two ends cancel in
    # the trapezoid, so it costs accuracy, not order.
    assert abs(p - 2.0) < 0.1
    assert all(abs(q - 2.0) < 0.1 for q in local[2:])


def test_pendulum_paper_step_eliminate_beats_estimate():
    elim = pendulum_error("eliminate", PAPER_STEPS)
    est = pendulum_error("estimate", PAPER_STEPS)
    # NOTES.md's 16.6 is the estimate with the parabolic quadrature; the default trapezoid
    # gives 17.7. Newmark: 6.6 (NOTES.md).
    est_parabolic = pendulum_error("estimate", PAPER_STEPS, quadrature="parabolic")
    elim_parabolic = pendulum_error("eliminate", PAPER_STEPS, quadrature="parabolic")
    print(
        f"\npendulum at omega dt = 2 pi/10, 5 periods: eliminate {elim:.4f}, estimate "
        f"{est:.3f} (ratio {est / elim:.1f}); parabolic quadrature: eliminate "
        f"{elim_parabolic:.4f}, estimate {est_parabolic:.3f}"
    )
    assert elim == pytest.approx(0.413, abs=0.005)
    assert est == pytest.approx(17.7, abs=0.1)
    assert est_parabolic == pytest.approx(16.6, abs=0.05)
    assert est / elim > 40.0
    # still true at every step of the convergence study (ratio 43-63)
    for n in ALL_STEPS:
        assert pendulum_error("estimate", n) > 30.0 * pendulum_error("eliminate", n)


@functools.cache
def pendulum_error_scheme(treatment, scheme, quadrature):
    sol = duhamel.solve(
        pendulum_system(),
        duhamel.Semianalytic(scheme=scheme, quadrature=quadrature, mass_treatment=treatment),
        t_end=5 * P_PERIOD,
        dt=P_PERIOD / PAPER_STEPS,
        x0=[P_W0],
        v0=[P_V0],
    )
    w, _ = decaying_mass_pendulum(sol.t, P_A, P_OMEGA, P_W0, P_V0, P_F, P_M0)
    return float(np.abs(sol.x[:, 0] - w).max() / P_W0)


def test_pendulum_paper_step_other_schemes():
    # Eliminating wins with every scheme and quadrature; scheme "c" (parabolic displacement
    # with the start slope) is 9x more accurate still on this case.
    print("\npendulum at the paper's step, scheme x quadrature: eliminate / estimate")
    for scheme in "abc":
        row = []
        for quadrature in ("trapezoid", "parabolic", "exact"):
            elim = pendulum_error_scheme("eliminate", scheme, quadrature)
            est = pendulum_error_scheme("estimate", scheme, quadrature)
            row.append(f"{quadrature}: {elim:.3f} / {est:.2f}")
            assert est > 5.0 * elim
        print(f"  scheme {scheme}: " + ", ".join(row))
    assert pendulum_error_scheme("eliminate", "c", "trapezoid") < 0.05


@pytest.mark.parametrize("K", [1.0, 2.0])
def test_bessel_treatments_are_equally_accurate(K):
    # Constant stiffness: the pseudo-force has to carry the growing frequency either way, and
    # the two treatments differ by less than 15 % at every step (eliminate 8-12 % better at
    # the paper's step, estimate up to 8.4 % better at finer steps).
    ratios = [bessel_error("estimate", n, K) / bessel_error("eliminate", n, K) for n in ALL_STEPS]
    print(
        f"\nbessel K={K:g}: estimate/eliminate error ratios "
        + ", ".join(f"{n}: {r:.3f}" for n, r in zip(ALL_STEPS, ratios, strict=True))
    )
    assert all(0.85 < r < 1.15 for r in ratios)
    assert ratios[0] > 1.0  # at the paper's step, eliminate is (slightly) better


def test_bessel_over_five_periods_is_unresolved_at_the_paper_step():
    # Over omega t = 10 pi the mass falls to 4.3 % and the paper's step leaves about two steps
    # per instantaneous period: both treatments are O(1) wrong, yet still converge.
    t_end = 5 * B_PERIOD
    for treatment in TREATMENTS:
        errors = [bessel_error(treatment, n, 1.0, t_end) for n in (10, 40, 80, 160, 320)]
        p = order((40, 80, 160, 320), errors[1:])
        print(
            f"\nbessel K=1, 5 periods, {treatment}: "
            + " ".join(f"{e:.3e}" for e in errors)
            + f"; order (40-320) {p:.3f}"
        )
        assert errors[0] > 1.0
        assert abs(p - 2.0) < 0.15


# --------------------------------------------------------------------- constant mass law


M3 = np.diag([1.0, 2.0, 1.5])
K3 = np.array([[300.0, -100.0, 0.0], [-100.0, 250.0, -150.0], [0.0, -150.0, 150.0]])


def three_dof(law=None, form="acceleration", scale_stiffness=False, **damping):
    sys = duhamel.System(M3, K3, **damping)
    sys.add_load(duhamel.loads.Step(1, amplitude=5.0, t0=0.13))
    sys.add_load(duhamel.loads.Harmonic(2, amplitude=3.0, omega=7.0))
    if law is not None:
        sys.set_mass_law(law, form=form, scale_stiffness=scale_stiffness)
    return sys


@pytest.mark.parametrize("damping", [{}, {"zeta": 0.05}, {"rayleigh": (0.1, 1e-3)}])
@pytest.mark.parametrize("treatment", TREATMENTS)
@pytest.mark.parametrize(
    ("form", "scale_stiffness"),
    [("acceleration", False), ("acceleration", True), ("momentum", False)],
)
def test_constant_mass_law_reproduces_constant_mass(damping, treatment, form, scale_stiffness):
    # mu = 1, mu' = 0: the pseudo-force vanishes and the nonlinear loop must give the exact
    # linear solution.
    kw = dict(t_end=3.0, dt=0.01, x0=[0.01, 0.0, -0.02], v0=[0.0, 0.1, 0.0])
    ref = duhamel.solve(three_dof(**damping), duhamel.Semianalytic(), **kw)
    law = duhamel.mass.Exponential(rate=0.0)
    sol = duhamel.solve(
        three_dof(law, form, scale_stiffness, **damping), integrator(treatment), **kw
    )
    ex = np.abs(sol.x - ref.x).max() / np.abs(ref.x).max()
    ev = np.abs(sol.v - ref.v).max() / np.abs(ref.v).max()
    assert ex < 1e-12 and ev < 1e-12


# ------------------------------------------------------------------------- harmonic mass

H_M, H_K, H_XI, H_NU = 1.5, 6.0, 0.3, 3.0
H_X0, H_V0, H_T_END = 1.0, 0.5, 10.0
H_STEPS = (100, 200, 400, 800)  # dt = 0.1 ... 0.0125; omega = 2, nu = 3


def harmonic_reference(t, form, scale_stiffness=False):
    """``(mu m x')' + k x = 0`` or ``mu m x'' + k x = 0`` (``k mu`` if scaled), DOP853."""

    def rhs(s, y):
        mu = 1.0 + H_XI * math.sin(H_NU * s)
        dmu = H_XI * H_NU * math.cos(H_NU * s)
        k = H_K * (mu if scale_stiffness else 1.0)
        drag = dmu * H_M * y[1] if form == "momentum" else 0.0
        return [y[1], (-k * y[0] - drag) / (mu * H_M)]

    r = solve_ivp(
        rhs, (0.0, t[-1]), [H_X0, H_V0], method="DOP853", rtol=1e-12, atol=1e-14, t_eval=t
    )
    assert r.success
    return r.y[0], r.y[1]


@functools.cache
def harmonic_error(form, treatment, steps, scale_stiffness=False):
    sys = one_dof(H_M, H_K)
    sys.set_mass_law(duhamel.mass.Harmonic(H_XI, H_NU), form=form, scale_stiffness=scale_stiffness)
    sol = duhamel.solve(
        sys, integrator(treatment), t_end=H_T_END, dt=H_T_END / steps, x0=[H_X0], v0=[H_V0]
    )
    x, _ = harmonic_reference(sol.t, form, scale_stiffness)
    return float(np.abs(sol.x[:, 0] - x).max() / H_X0)


# Measured est/elim error ratios at dt = 0.05: acceleration form 4.4, momentum form 0.21.
HARMONIC_RATIO = {"acceleration": (3.0, 6.0), "momentum": (0.1, 0.3)}


@pytest.mark.parametrize("form", ["acceleration", "momentum"])
def test_harmonic_mass_against_solve_ivp(form):
    result = {}
    for treatment in TREATMENTS:
        errors = [harmonic_error(form, treatment, n) for n in H_STEPS]
        result[treatment] = errors
        p = order(H_STEPS, errors)
        print(
            f"\nharmonic mass, {form} form, {treatment}: "
            + " ".join(f"{e:.3e}" for e in errors)
            + f"; order {p:.3f}"
        )
        assert abs(p - 2.0) < 0.1
    assert result["eliminate"][-1] < 5e-4  # dt = 0.0125
    lo, hi = HARMONIC_RATIO[form]
    ratios = [est / elim for est, elim in zip(result["estimate"], result["eliminate"], strict=True)]
    print(f"harmonic mass, {form} form: estimate/eliminate " + " ".join(f"{r:.2f}" for r in ratios))
    # acceleration form: eliminating wins; momentum form: the estimate wins
    assert all(lo < r < hi for r in ratios)


def test_harmonic_mass_with_scaled_stiffness_is_exact_when_eliminated():
    # mu m x'' + mu k x = 0 divided by mu is the constant oscillator: the eliminated
    # pseudo-force (1/mu - 1)(p - c v) vanishes without load and damping.
    elim = harmonic_error("acceleration", "eliminate", 200, scale_stiffness=True)
    est = harmonic_error("acceleration", "estimate", 200, scale_stiffness=True)
    print(f"\nharmonic mass, scaled stiffness, dt = 0.05: eliminate {elim:.2e}, estimate {est:.2e}")
    assert elim < 1e-10
    assert est > 1e-4


def test_acceleration_output_satisfies_the_equation_of_motion():
    # sol.a is the acceleration of the variable-mass equation at the computed states
    for treatment in TREATMENTS:
        sol = duhamel.solve(
            pendulum_system(),
            integrator(treatment),
            t_end=5 * P_PERIOD,
            dt=P_PERIOD / 40,
            x0=[P_W0],
            v0=[P_V0],
        )
        t, w, v = sol.t, sol.x[:, 0], sol.v[:, 0]
        m = P_M0 * np.exp(-P_A * P_OMEGA * t)
        expect = P_A * P_OMEGA * v - P_OMEGA**2 * w + P_F / m
        assert np.abs(sol.a[:, 0] - expect).max() < 1e-12 * np.abs(expect).max()


# ------------------------------------------------------------------------ tabulated mass

T_TS = (0.0, 1.0, 2.5, 4.0)  # breakpoints on the step grid of every run below
T_MU = (1.0, 0.6, 1.4, 1.0)
T_K, T_END = 4.0, 5.0
T_STEPS = (100, 200, 400, 800)


def tabulated_reference(t, form):
    """Piecewise DOP853 between the breakpoints (mu' jumps there), ``m = 1``, ``k = 4``."""
    ts, mus = np.array(T_TS), np.array(T_MU)
    edges = [0.0, *[b for b in T_TS if 0.0 < b < T_END], T_END]
    out, y = np.empty_like(t), np.array([1.0, 0.0])
    for a, b in itertools.pairwise(edges):
        i = int(np.searchsorted(ts, 0.5 * (a + b)))
        dmu = (mus[i] - mus[i - 1]) / (ts[i] - ts[i - 1]) if b <= ts[-1] else 0.0
        drag = dmu if form == "momentum" else 0.0

        def rhs(s, z, drag=drag):
            return [z[1], (-T_K * z[0] - drag * z[1]) / np.interp(s, ts, mus)]

        r = solve_ivp(rhs, (a, b), y, method="DOP853", rtol=1e-12, atol=1e-14, dense_output=True)
        sel = (t >= a - 1e-12) & (t <= b + 1e-12)
        out[sel] = r.sol(t[sel])[0]
        y = r.sol(b)
    return out


def tabulated_errors(form, treatment):
    errors = []
    for n in T_STEPS:
        sys = one_dof(1.0, T_K).set_mass_law(duhamel.mass.Tabulated(T_TS, T_MU), form=form)
        sol = duhamel.solve(
            sys, integrator(treatment), t_end=T_END, dt=T_END / n, x0=[1.0], v0=[0.0]
        )
        errors.append(float(np.abs(sol.x[:, 0] - tabulated_reference(sol.t, form)).max()))
    print(
        f"\ntabulated mass, {form} form, {treatment}: "
        + " ".join(f"{e:.3e}" for e in errors)
        + f"; order {order(T_STEPS, errors):.3f}"
    )
    return errors


@pytest.mark.parametrize("treatment", TREATMENTS)
def test_tabulated_mass_acceleration_form(treatment):
    # Only mu enters the pseudo-force, and mu is continuous: second order.
    assert abs(order(T_STEPS, tabulated_errors("acceleration", treatment)) - 2.0) < 0.1


def test_tabulated_mass_momentum_form():
    # mu' jumps at the breakpoints; a step that ends on one takes the slope from the left.
    # The default (eliminate) is second order. The estimated-acceleration variant is first
    # order here, and only here: with a straight table (no jump in mu') it is second order
    # too (measured 2.00); the cause is not established. Measured, not tuned: 1.00.
    assert abs(order(T_STEPS, tabulated_errors("momentum", "eliminate")) - 2.0) < 0.1
    assert abs(order(T_STEPS, tabulated_errors("momentum", "estimate")) - 1.0) < 0.1


# ---------------------------------------------------------------------------- bad input


def test_mass_law_reaching_zero_is_rejected():
    with pytest.raises(ValueError, match="`mu` must stay positive"):
        duhamel.mass.Tabulated(t=[0.0, 1.0, 2.0], mu=[1.0, 0.0, 1.0])
    with pytest.raises(ValueError, match="`mu` must stay positive"):
        duhamel.mass.Tabulated(t=[0.0, 1.0], mu=[1.0, -0.5])
    for amplitude in (1.0, -1.0, 1.5):
        with pytest.raises(ValueError, match="`amplitude` must be below 1"):
            duhamel.mass.Harmonic(amplitude, 2.0)
    for scale in (0.0, -1.0):
        with pytest.raises(ValueError, match="`scale` must be positive"):
            duhamel.mass.Exponential(-0.1, scale=scale)
    # a decay that underflows to zero within the run is caught by the solve
    sys = one_dof(1.0, 1.0).set_mass_law(duhamel.mass.Exponential(-1000.0))
    with pytest.raises(ValueError, match="`mass law` reaches 0"):
        duhamel.solve(sys, integrator("eliminate"), t_end=10.0, dt=0.1, x0=[1.0])


def test_bad_form_law_and_treatment():
    sys = one_dof(1.0, 1.0)
    with pytest.raises(ValueError, match="`form`"):
        sys.set_mass_law(duhamel.mass.Exponential(0.0), form="bogus")
    with pytest.raises(TypeError, match="`law`"):
        sys.set_mass_law(3.0)
    with pytest.raises(TypeError, match="`law`"):
        sys.set_mass_law(duhamel.mass.Exponential)  # the class, not a law
    with pytest.raises(TypeError, match="`scale_stiffness`"):
        sys.set_mass_law(duhamel.mass.Exponential(0.0), scale_stiffness="yes")
    with pytest.raises(ValueError, match="`mass_treatment`"):
        duhamel.Semianalytic(mass_treatment="x")
    assert sys.mass_law is None  # failed calls leave the system unchanged

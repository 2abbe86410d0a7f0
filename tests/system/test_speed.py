"""Speed laws, the unbalance load and time-scaled couplings (issue 6, part B).

References share nothing with the code under test: ``scipy.integrate.quad`` for the rotation
angle, the built-in ``Harmonic`` load for a constant speed, and ``scipy.integrate.solve_ivp``
(DOP853, rtol 1e-11, restarted at the end of the run-up) on the equations of motion written
out here, with the speed law and the unbalance force coded independently in this file.
Measured numbers are printed (``pytest -s tests/system/test_speed.py``).
"""

from __future__ import annotations

import functools
import itertools
import math
import re

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.integrate import quad, solve_ivp

import duhamel
from duhamel import _core
from duhamel import elements as E
from duhamel import loads as L
from duhamel.speed import ConstantSpeed, LinearRunUp


def slopes(dts, errs):
    """Least-squares slope of log(error) against log(dt), and the pairwise slopes."""
    ld, le = np.log(np.asarray(dts)), np.log(np.asarray(errs))
    return float(np.polyfit(ld, le, 1)[0]), np.diff(le) / np.diff(ld)


def assert_order(label, dts, errs, order, tol=0.1):
    fit, pair = slopes(dts, errs)
    print(
        f"\n{label}: errors {np.array2string(np.asarray(errs), precision=3)}, "
        f"slope {fit:.4f}, pairwise {np.array2string(pair, precision=4)}"
    )
    assert abs(fit - order) <= tol, (label, fit, pair)
    assert np.all(np.abs(pair - order) <= tol), (label, pair)


def runup(w0, w1, t1):
    """The run-up written out independently: omega, omega', theta as scalar functions."""
    a = (w1 - w0) / t1

    def omega(t):
        return w0 + a * t if t < t1 else w1

    def domega(t):
        return a if t < t1 else 0.0

    def theta(t):
        return w0 * t + 0.5 * a * t * t if t < t1 else 0.5 * (w0 + w1) * t1 + w1 * (t - t1)

    return omega, domega, theta


def dop853(rhs, z0, t_grid, breaks):
    """solve_ivp(DOP853) at `t_grid`, restarted at each time of `breaks` (where the right-hand
    side jumps), rtol 1e-11."""
    edges = [0.0, *[b for b in breaks if 0.0 < b < t_grid[-1]], float(t_grid[-1])]
    rows = [np.asarray(z0, dtype=float)]
    z = np.asarray(z0, dtype=float)
    for a, b in itertools.pairwise(edges):
        inside = t_grid[(t_grid > a) & (t_grid < b)]
        times = np.append(inside, b)  # the grid times inside, and the state at the break
        r = solve_ivp(rhs, (a, b), z, method="DOP853", rtol=1e-11, atol=1e-16, t_eval=times)
        assert r.success, r.message
        rows.extend(r.y[:, : inside.size].T)
        z = r.y[:, -1]
        if b == t_grid[-1] or b in t_grid:
            rows.append(z)
    return np.array(rows)


# --------------------------------------------------------------------------------------------
# 1. The speed laws: theta is the exact integral of omega, omega is the integral of omega'
# --------------------------------------------------------------------------------------------
LAWS = {
    "constant": ConstantSpeed(157.0),
    "run-up": LinearRunUp(omega0=0.0, omega1=300.0, t1=2.5),
    "run-down": LinearRunUp(omega0=200.0, omega1=-50.0, t1=0.7),
}


@pytest.mark.parametrize("name", list(LAWS))
def test_theta_is_exact_vs_quadrature(name):
    law = LAWS[name]
    t1 = getattr(law, "t1", None)
    worst = 0.0
    for t in [0.0, 1e-3, 0.3, 0.7, 1.1, 2.5, 2.5 + 1e-9, 4.0, 40.0]:
        points = [t1] if t1 is not None and 0.0 < t1 < t else None
        exact, err = quad(lambda s: float(law.omega(s)), 0.0, t, points=points, epsabs=0.0)
        got = float(law.theta(t))
        rel = abs(got - exact) / max(1.0, abs(exact))
        worst = max(worst, rel)
        assert rel <= 1e-13, (name, t, got, exact, err)
        speed, _ = quad(lambda s: float(law.domega(s)), 0.0, t, points=points, epsabs=0.0)
        assert abs(float(law.omega(t)) - float(law.omega(0.0)) - speed) <= 1e-12 * max(
            1.0, abs(speed)
        )
    print(f"\n{name}: max relative error of theta against quad: {worst:.2e}")


def test_speed_law_values_and_vectorisation():
    law = LinearRunUp(10.0, 30.0, 4.0)
    t = np.array([[-1.0, 0.0, 2.0], [4.0, 5.0, 9.0]])
    np.testing.assert_array_equal(law.omega(t), [[10, 10, 20], [30, 30, 30]])
    np.testing.assert_array_equal(law.domega(t), [[0, 5, 5], [0, 0, 0]])  # right-continuous
    np.testing.assert_allclose(law.theta(t), [[-10, 0, 30], [80, 110, 230]], rtol=1e-15)
    assert law(2.0) == 20.0 and isinstance(law.theta(2.0), float)
    assert LinearRunUp(3.0, 3.0, 1.0).constant_value() == 3.0
    assert law.constant_value() is None and ConstantSpeed(2).constant_value() == 2.0


# --------------------------------------------------------------------------------------------
# 2. Constant speed: the unbalance is two harmonic loads
# --------------------------------------------------------------------------------------------
M3 = np.diag([2.0, 2.0, 1.0])
K3 = np.array([[900.0, 0.0, -100.0], [0.0, 1100.0, 0.0], [-100.0, 0.0, 400.0]])


@pytest.mark.parametrize(
    "integrator",
    [duhamel.Semianalytic(), duhamel.Newmark(), duhamel.CubicHermite()],
    ids=["Semianalytic", "Newmark", "CubicHermite"],
)
@pytest.mark.parametrize("speed", [47.0, ConstantSpeed(47.0)], ids=["float", "ConstantSpeed"])
def test_constant_speed_unbalance_equals_harmonic_loads(integrator, speed):
    me, w, phase = 2e-3, 47.0, 0.7
    runs = []
    for loads in (
        [L.Unbalance((0, 1), m_e=me, speed=speed, phase=phase)],
        [
            L.Harmonic(0, amplitude=me * w * w, omega=w, phase=phase + math.pi / 2),
            L.Harmonic(1, amplitude=me * w * w, omega=w, phase=phase),
        ],
    ):
        s = duhamel.System(M3, K3, zeta=0.03)
        for load in loads:
            s.add_load(load)
        runs.append(duhamel.solve(s, integrator, t_end=3.0, dt=0.004, x0=[1e-4, 0, 0]))
    for key in ("x", "v", "a"):
        got, want = getattr(runs[0], key), getattr(runs[1], key)
        d = np.abs(got - want).max() / np.abs(want).max()
        print(f"\n{type(integrator).__name__} {key}: unbalance vs harmonic {d:.1e}")
        assert d <= 1e-13


def test_unbalance_evaluate_matches_the_force_of_an_eccentric_mass():
    me, phase = 0.5, -0.4
    law = LinearRunUp(20.0, 80.0, 1.5)
    omega, domega, theta = runup(20.0, 80.0, 1.5)
    s = duhamel.System(np.eye(3), np.eye(3))
    load = L.Unbalance((2, 0), m_e=me, speed=law, phase=phase)
    ts = np.array([0.0, 0.4, 1.5 - 1e-12, 1.5, 2.2])
    got = load.evaluate(s, ts)
    for row, t in zip(got, ts, strict=True):
        th, w, dw = theta(t) + phase, omega(t), domega(t)
        want = [me * (w * w * math.sin(th) - dw * math.cos(th)), 0.0]
        want.insert(0, me * (w * w * math.cos(th) + dw * math.sin(th)))
        np.testing.assert_allclose(row, [want[1], 0.0, want[0]], rtol=1e-13, atol=1e-12)
    np.testing.assert_array_equal(load.evaluate(s, 0.4), got[1])


# --------------------------------------------------------------------------------------------
# 3. Run-up unbalance on an isotropic 2-dof oscillator against DOP853
# --------------------------------------------------------------------------------------------
M2, K2, ZETA2 = 2.0, 1800.0, 0.02  # omega_n = 30 rad/s: the run-up crosses the resonance
ME2, PHASE2, T2 = 1e-3, 0.3, 1.5
N0_2 = 30  # errors on the grid of the coarsest run


@functools.lru_cache
def oscillator_reference(w0, w1, t1):
    omega, domega, theta = runup(w0, w1, t1)
    c = 2 * ZETA2 * math.sqrt(K2 / M2) * M2

    def rhs(t, z):
        th, w, dw = theta(t) + PHASE2, omega(t), domega(t)
        f = ME2 * np.array(
            [w * w * math.cos(th) + dw * math.sin(th), w * w * math.sin(th) - dw * math.cos(th)]
        )
        return np.concatenate([z[2:], (f - c * z[2:] - K2 * z[:2]) / M2])

    return dop853(rhs, np.zeros(4), np.linspace(0.0, T2, N0_2 + 1), [t1])[:, :2]


def oscillator_errors(integrator, steps, w0, w1, t1):
    ref = oscillator_reference(w0, w1, t1)
    system = duhamel.System(M2 * np.eye(2), K2 * np.eye(2), zeta=ZETA2)
    system.add_load(L.Unbalance((0, 1), m_e=ME2, speed=LinearRunUp(w0, w1, t1), phase=PHASE2))
    errs = []
    for n in steps:
        sol = duhamel.solve(system, integrator, t_end=T2, dt=T2 / n)
        errs.append(np.abs(sol.x[:: n // N0_2] - ref).max() / np.abs(ref).max())
    return [T2 / n for n in steps], errs


# Semi-analytic steps from T/120 (omega_max dt = 0.75 rad at the top speed; at T/60, 1.5 rad,
# the slope to the next halving is still 4.09 / 4.15: not yet asymptotic).
def test_runup_unbalance_semianalytic_is_fourth_order():
    # t1 on every grid: the load is smooth within each step; the parabola per step gives
    # fourth order, as for a harmonic load
    dts, errs = oscillator_errors(duhamel.Semianalytic(), [120, 240, 480, 960], 0.0, 60.0, 1.0)
    assert_order("run-up unbalance, Semianalytic, t1 on the grid", dts, errs, 4.0)
    assert errs[-1] < 1e-7


def test_runup_unbalance_ending_inside_a_step_stays_fourth_order():
    # t1 = 0.98713 falls inside a step on every grid: the jump of m_e omega' there (and of the
    # force's first two derivatives) is integrated exactly, so the order does not drop
    dts, errs = oscillator_errors(duhamel.Semianalytic(), [120, 240, 480, 960], 5.0, 60.0, 0.98713)
    assert_order("run-up unbalance, Semianalytic, t1 inside a step", dts, errs, 4.0)
    assert errs[-1] < 1e-7


def test_runup_unbalance_newmark_is_second_order():
    dts, errs = oscillator_errors(duhamel.Newmark(), [240, 480, 960, 1920], 0.0, 60.0, 1.0)
    assert_order("run-up unbalance, Newmark", dts, errs, 2.0)


# --------------------------------------------------------------------------------------------
# 4. A rigid rotor on two bearings during a run-up: gyroscopic omega(t) G and speed-dependent
#    cross-coupled stiffness as LinearCoupling(scale=law), against DOP853
# --------------------------------------------------------------------------------------------
# dofs (x, y, theta_x, theta_y) of the rotor's centre; bearings at z = -0.2 m and z = 0.3 m
MR, ID, IP = 10.0, 0.05, 0.1
MROT = np.diag([MR, MR, ID, ID])
KROT = np.zeros((4, 4))
for _k, _z in ((2e5, -0.2), (3e5, 0.3)):
    KROT[np.ix_([0, 3], [0, 3])] += _k * np.array([[1.0, _z], [_z, _z * _z]])
    KROT[np.ix_([1, 2], [1, 2])] += _k * np.array([[1.0, -_z], [-_z, _z * _z]])
GROT = np.zeros((4, 4))
GROT[2, 3], GROT[3, 2] = IP, -IP  # gyroscopic matrix per unit spin speed (skew)
KQ = np.zeros((4, 4))
KQ[0, 1], KQ[1, 0] = 50.0, -50.0  # cross-coupled stiffness per unit speed (N/m per rad/s)
RAYLEIGH_ROT = (1.0, 1e-5)
W0R, W1R, T1R, TR = 0.0, 300.0, 0.5, 0.8
MER = 1e-4
X0R = np.array([0.0, 0.0, 1e-4, 0.0])
N0_R = 80


@functools.lru_cache
def rotor_reference():
    omega, domega, theta = runup(W0R, W1R, T1R)
    c = RAYLEIGH_ROT[0] * MROT + RAYLEIGH_ROT[1] * KROT
    minv = np.linalg.inv(MROT)

    def rhs(t, z):
        x, v = z[:4], z[4:]
        th, w, dw = theta(t), omega(t), domega(t)
        f = np.zeros(4)
        f[0] = MER * (w * w * math.cos(th) + dw * math.sin(th))
        f[1] = MER * (w * w * math.sin(th) - dw * math.cos(th))
        return np.concatenate([v, minv @ (f - c @ v - KROT @ x - w * (GROT @ v + KQ @ x))])

    z0 = np.concatenate([X0R, np.zeros(4)])
    return dop853(rhs, z0, np.linspace(0.0, TR, N0_R + 1), [T1R])[:, :4]


def rotor_system(sparse=False):
    law = LinearRunUp(W0R, W1R, T1R)
    wrap = sp.csr_array if sparse else np.asarray
    s = duhamel.System(wrap(MROT), wrap(KROT), rayleigh=RAYLEIGH_ROT)
    s.add(E.LinearCoupling(K=wrap(KQ), C=wrap(GROT), scale=law))
    s.add_load(L.Unbalance((0, 1), m_e=MER, speed=law))
    return s


@pytest.mark.parametrize(
    ("name", "integrator", "steps", "order"),
    [
        ("Semianalytic", duhamel.Semianalytic(), [6400, 12800, 25600, 51200], 2.0),
        ("Newmark", duhamel.Newmark(), [6400, 12800, 25600, 51200], 2.0),
        ("CubicHermite", duhamel.CubicHermite(), [1600, 3200, 6400, 12800], 4.0),
    ],
)
def test_scaled_coupling_runup_converges(name, integrator, steps, order):
    ref = rotor_reference()
    scale = np.abs(ref).max(axis=0)
    system = rotor_system()
    errs = []
    for n in steps:
        sol = duhamel.solve(system, integrator, t_end=TR, dt=TR / n, x0=X0R)
        errs.append((np.abs(sol.x[:: n // N0_R] - ref) / scale).max())
    assert_order(
        f"rigid rotor run-up, omega(t) (G, Kq), {name}", [TR / n for n in steps], errs, order
    )
    if name == "Newmark":
        # the iteration matrix follows the speed: one factorisation per step
        assert sol.stats.factorizations == steps[-1]


def test_semianalytic_beats_newmark_on_the_runup_at_equal_step():
    ref = rotor_reference()
    scale = np.abs(ref).max(axis=0)
    errs = {}
    for name, integrator in (
        ("Semianalytic", duhamel.Semianalytic()),
        ("Newmark", duhamel.Newmark()),
    ):
        sol = duhamel.solve(rotor_system(), integrator, t_end=TR, dt=TR / 1600, x0=X0R)
        errs[name] = (np.abs(sol.x[:: 1600 // N0_R] - ref) / scale).max()
    print(f"\nrotor run-up, dt = T/1600: {errs}")
    assert errs["Semianalytic"] < errs["Newmark"]


def test_scaled_coupling_sparse_equals_dense():
    for integrator in (duhamel.Newmark(), duhamel.CubicHermite()):
        dense = duhamel.solve(rotor_system(), integrator, t_end=TR, dt=TR / 800, x0=X0R)
        sparse = duhamel.solve(rotor_system(True), integrator, t_end=TR, dt=TR / 800, x0=X0R)
        d = np.abs(dense.x - sparse.x).max() / np.abs(dense.x).max()
        print(f"\n{type(integrator).__name__}: sparse vs dense {d:.1e}")
        assert d <= 1e-12


# --------------------------------------------------------------------------------------------
# 5. A constant scale is the constant coupling
# --------------------------------------------------------------------------------------------
def _coupled(**kwargs):
    s = duhamel.System(MROT, KROT, rayleigh=RAYLEIGH_ROT)
    s.add(E.LinearCoupling(**kwargs))
    s.add_load(L.Unbalance((0, 1), m_e=MER, speed=120.0))
    return s


RUN5 = {"t_end": 0.2, "dt": 2e-4, "x0": X0R}


@pytest.mark.parametrize(
    "integrator", [duhamel.Semianalytic(), duhamel.Newmark()], ids=["Semianalytic", "Newmark"]
)
def test_scale_none_and_constant_scale_are_the_constant_coupling(integrator):
    w = 120.0
    base = duhamel.solve(_coupled(K=KQ, C=GROT), integrator, **RUN5).x
    same = duhamel.solve(_coupled(K=KQ, C=GROT, scale=None), integrator, **RUN5).x
    np.testing.assert_array_equal(base, same)
    folded = duhamel.solve(_coupled(K=w * KQ, C=w * GROT), integrator, **RUN5).x
    for scale in (w, ConstantSpeed(w), LinearRunUp(w, w, 0.1)):
        got = duhamel.solve(_coupled(K=KQ, C=GROT, scale=scale), integrator, **RUN5).x
        d = np.abs(got - folded).max() / np.abs(folded).max()
        assert d <= 1e-13, (scale, d)


def test_engine_scaled_path_with_a_unit_law_is_the_constant_path():
    # The time-scaled code paths of both engines, driven by a constant unit law, against the
    # constant couplings: the semi-analytic one is the same arithmetic, the direct one adds
    # the matrices in another order.
    from duhamel._engine.dispatch import options

    system = _coupled(K=KQ, C=GROT)
    basis = system.modal(None)
    phi = np.ascontiguousarray(basis.phi)
    kq, cq = (np.ascontiguousarray(m) for m in system.couplings[0].modal(phi))
    specs = [
        _core.Load(np.ascontiguousarray(phi.T @ term.pattern), term.time)
        for term in system.loads[0]._terms(system)
    ]
    q0 = np.ascontiguousarray(phi.T @ MROT @ X0R)
    run = _core.RunSpec(_core.Grid(0.0, 2e-4, 1000, 1), q0, np.zeros(4))
    unit = _core.SpeedLaw.constant(1.0)

    def pseudo(**couplings):
        route = _core.PseudoForceRoute([], options(duhamel.Semianalytic()), **couplings)
        model = _core.ModalModel(
            np.ascontiguousarray(basis.omega2), np.ascontiguousarray(basis.c), phi, specs, route
        )
        return model.run(run)

    dense = _core.Matrix.dense
    a = pseudo(coupling_k=dense(kq), coupling_c=dense(cq))
    b = pseudo(scaled=[_core.ScaledCoupling(dense(kq), dense(cq), unit)])
    np.testing.assert_array_equal(a.q, b.q)

    from duhamel._engine.direct import physical_matrices
    from duhamel._engine.dispatch import matrices as core_matrices
    from duhamel._engine.dispatch import matrix as _matrix

    mats = core_matrices(physical_matrices(_coupled(K=KQ, C=GROT)))
    bare = physical_matrices(duhamel.System(MROT, KROT, rayleigh=RAYLEIGH_ROT))
    assert bare["scaled"] == [] and not bare["sparse"]
    m, k, c, k_fixed = (
        None if bare[key] is None else _matrix(bare[key], False)
        for key in ("m", "k", "c", "k_fixed")
    )
    scaled = [_core.ScaledCoupling(_matrix(KQ, False), _matrix(GROT, False), unit)]
    bare_scaled = _core.Matrices(m, k, c, k_fixed, scaled)
    dspecs = system.loads[0]._terms(system)
    direct_run = _core.DirectRun(
        _core.Grid(0.0, 2e-4, 1000, 1),
        np.ascontiguousarray(X0R, dtype=np.float64),
        np.zeros(4),
        np.arange(4, dtype=np.int64),
    )

    def direct(matrices):
        method = duhamel.Newmark()._method()
        return _core.DirectModel(matrices, [], None, method, 1e-10, 25).run(direct_run, dspecs)

    folded, scaled_path = direct(mats).x, direct(bare_scaled).x
    diff = np.abs(folded - scaled_path).max() / np.abs(folded).max()
    print(f"\ndirect engine, scaled path with a unit law vs folded matrices: {diff:.1e}")
    assert diff <= 1e-13


# --------------------------------------------------------------------------------------------
# 6. One mode: the closed form still applies with a time-varying scale
# --------------------------------------------------------------------------------------------
def test_single_mode_with_scaled_coupling_closed_form_equals_newton():
    law = LinearRunUp(2.0, 12.0, 1.0)
    s = duhamel.System(np.eye(1), 25.0 * np.eye(1), zeta=0.05)
    s.add(E.Cubic(0, k3=40.0))
    s.add(E.LinearCoupling(K=np.array([[3.0]]), C=np.array([[0.2]]), scale=law))
    s.add_load(L.Harmonic(0, amplitude=1.0, omega=7.0))
    run = {"t_end": 3.0, "dt": 0.01, "x0": [0.2]}
    auto = duhamel.solve(s, duhamel.Semianalytic(), **run)
    newton = duhamel.solve(s, duhamel.Semianalytic(solver="newton"), **run)
    assert auto.stats.closed_form_steps == 300 and auto.stats.newton_iterations == 0
    assert newton.stats.closed_form_steps == 0
    d = np.abs(auto.x - newton.x).max() / np.abs(newton.x).max()
    print(f"\none mode, scaled coupling: closed form vs Newton {d:.1e}")
    assert d <= 1e-12


# --------------------------------------------------------------------------------------------
# 7. Analyses need constant coefficients
# --------------------------------------------------------------------------------------------
def test_analysis_refuses_a_time_varying_scale_and_folds_a_constant_one():
    from duhamel.analysis._linear import check_system, modal_model

    varying = _coupled(C=GROT, scale=LinearRunUp(0.0, 100.0, 1.0))
    with pytest.raises(ValueError, match=r"(?s)`system`.*time-varying scale"):
        check_system(varying)
    a = modal_model(check_system(_coupled(C=GROT, scale=100.0)))
    b = modal_model(check_system(_coupled(C=100.0 * GROT)))
    np.testing.assert_allclose(a.c_q, b.c_q, rtol=0, atol=1e-12 * np.abs(b.c_q).max())


# --------------------------------------------------------------------------------------------
# 8. Bad input
# --------------------------------------------------------------------------------------------
BAD = [
    ("t1-negative", lambda: LinearRunUp(0.0, 10.0, -1.0), ValueError, "`t1`"),
    ("t1-zero", lambda: LinearRunUp(0.0, 10.0, 0.0), ValueError, "`t1`"),
    ("t1-nan", lambda: LinearRunUp(0.0, 10.0, float("nan")), ValueError, "`t1`"),
    ("omega0-nan", lambda: LinearRunUp(float("nan"), 10.0, 1.0), ValueError, "`omega0`"),
    ("omega1-inf", lambda: LinearRunUp(0.0, float("inf"), 1.0), ValueError, "`omega1`"),
    ("omega-nan", lambda: ConstantSpeed(float("nan")), ValueError, "`omega`"),
    ("omega-str", lambda: ConstantSpeed("fast"), TypeError, "`omega`"),
    ("me-nan", lambda: L.Unbalance((0, 1), m_e=float("nan"), speed=10.0), ValueError, "`m_e`"),
    ("me-negative", lambda: L.Unbalance((0, 1), m_e=-1.0, speed=10.0), ValueError, "`m_e`"),
    (
        "phase-inf",
        lambda: L.Unbalance((0, 1), m_e=1.0, speed=10.0, phase=float("inf")),
        ValueError,
        "`phase`",
    ),
    ("speed-nan", lambda: L.Unbalance((0, 1), m_e=1.0, speed=float("nan")), ValueError, "`speed`"),
    ("speed-type", lambda: L.Unbalance((0, 1), m_e=1.0, speed="fast"), TypeError, "`speed`"),
    ("scale-type", lambda: E.LinearCoupling(K=np.eye(2), scale="x"), TypeError, "`scale`"),
    ("scale-nan", lambda: E.LinearCoupling(K=np.eye(2), scale=np.nan), ValueError, "`scale`"),
    (
        "same-dofs",
        lambda: duhamel.System(np.eye(2), np.eye(2)).add_load(
            L.Unbalance((1, 1), m_e=1.0, speed=5.0)
        ),
        ValueError,
        "`dofs` must be two different dofs",
    ),
    (
        "dof-range",
        lambda: duhamel.System(np.eye(2), np.eye(2)).add_load(
            L.Unbalance((2, 1), m_e=1.0, speed=5.0)
        ),
        ValueError,
        "`dofs[0]`",
    ),
    (
        "core-t1",
        lambda: _core.SpeedLaw.run_up(0.0, 1.0, -2.0),
        ValueError,
        "`t1`",
    ),
    (
        "core-omega",
        lambda: _core.SpeedLaw.constant(np.nan),
        ValueError,
        "`omega`",
    ),
]


@pytest.mark.parametrize(("label", "make", "exc", "name"), BAD, ids=[b[0] for b in BAD])
def test_bad_input_names_the_parameter(label, make, exc, name):
    with pytest.raises(exc, match=re.escape(name)):
        make()

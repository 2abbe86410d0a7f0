"""Force elements as modal pseudo-forces: references, convergence orders, stability, errors.

References share nothing with the code under test: the matrix exponential of the full
first-order system (linear cases, exact for step loads), the closed-form damped oscillator,
the amplification matrices of the paper's schemes (eq. 22 for scheme "b"), and
``scipy.integrate.solve_ivp`` (DOP853) for the rotor rub. Measured numbers are printed
(``pytest -s``).
"""

from __future__ import annotations

import re

import numpy as np
import pytest
import scipy.linalg as sla
import scipy.sparse as sp
from _callbacks import callback_failure
from scipy.integrate import solve_ivp

import duhamel
from duhamel import elements as E
from duhamel import loads as L


def slopes(dts, errs):
    """Least-squares slope of log(err) vs log(dt), and the pairwise slopes."""
    ld, le = np.log(np.asarray(dts)), np.log(np.asarray(errs))
    return float(np.polyfit(ld, le, 1)[0]), np.diff(le) / np.diff(ld)


def assert_order(label, dts, errs, order=2.0, tol=0.1):
    fit, pair = slopes(dts, errs)
    print(f"\n{label}: errors {np.array2string(np.asarray(errs), precision=3)}")
    print(f"{label}: fitted slope {fit:.4f}, pairwise {np.array2string(pair, precision=4)}")
    assert abs(fit - order) <= tol, (label, fit, pair)
    assert np.all(np.abs(pair - order) <= tol), (label, pair)


# --------------------------------------------------------------------------------------------
# 1. LinearCoupling (non-classical damping, skew stiffness) vs the matrix exponential
# --------------------------------------------------------------------------------------------
N = 5
M5 = np.diag([1.0, 2.0, 1.5, 1.0, 0.8])
K5 = 100.0 * (2.0 * np.eye(N) - np.eye(N, k=1) - np.eye(N, k=-1))
K5[0, 0] += 50.0
# symmetric, not diagonalised by the undamped modes: a discrete damper at dof 0, one at dof 2
# and a dashpot between dofs 1 and 3
C5 = np.zeros((N, N))
C5[0, 0] = 2.0
C5[2, 2] = 0.5
C5[np.ix_([1, 3], [1, 3])] += 0.4 * np.array([[1.0, -1.0], [-1.0, 1.0]])
# cross-coupled (circulatory) stiffness, k12 = -k21
KX5 = np.zeros((N, N))
KX5[1, 2], KX5[2, 1] = 20.0, -20.0
F5 = np.array([-3.0, 0.0, 0.0, 0.0, 10.0])
X0_5 = np.array([0.01, 0.0, 0.02, 0.0, -0.01])
V0_5 = np.array([0.0, 0.1, 0.0, -0.2, 0.0])
RAYLEIGH = (0.3, 2e-3)
T_END_1 = 2.0
DT0_1 = 0.02
DTS_1 = DT0_1 / 2.0 ** np.arange(6)  # 5 halvings


def expm_history(c_total, k_total, dt, n_steps):
    """Exact x(k dt), k = 0..n_steps, of M x'' + C x' + K x = F (step load at t = 0)."""
    minv = np.linalg.inv(M5)
    a = np.zeros((2 * N + 1, 2 * N + 1))
    a[:N, N : 2 * N] = np.eye(N)
    a[N : 2 * N, :N] = -minv @ k_total
    a[N : 2 * N, N : 2 * N] = -minv @ c_total
    a[N : 2 * N, 2 * N] = minv @ F5  # augmented constant load
    step = sla.expm(a * dt)
    z = np.concatenate([X0_5, V0_5, [1.0]])
    out = [z[:N]]
    for _ in range(n_steps):
        z = step @ z
        out.append(z[:N])
    return np.array(out)


def build_coupled(variant):
    """(system, total C, total K) of the variants of test 1."""
    if variant == "undamped+LinearCoupling(K,C)":
        s = duhamel.System(M5, K5).add(E.LinearCoupling(K=KX5, C=C5))
        c_tot, k_tot = C5, K5 + KX5
    elif variant == "rayleigh+LinearCoupling(sparse K,C)":
        s = duhamel.System(M5, K5, rayleigh=RAYLEIGH)
        s.add(E.LinearCoupling(K=sp.csr_matrix(KX5), C=C5))
        c_tot, k_tot = RAYLEIGH[0] * M5 + RAYLEIGH[1] * K5 + C5, K5 + KX5
    elif variant == "System(C=nonclassical)":
        s = duhamel.System(M5, K5, C=C5)
        c_tot, k_tot = C5, K5
    elif variant == "System(C=nonclassical)+LinearCoupling(K)":
        s = duhamel.System(M5, K5, C=C5).add(E.LinearCoupling(K=KX5))
        c_tot, k_tot = C5, K5 + KX5
    else:  # pragma: no cover
        raise AssertionError(variant)
    for i in np.flatnonzero(F5):
        s.add_load(L.Step(int(i), amplitude=float(F5[i])))
    return s, c_tot, k_tot


@pytest.mark.parametrize(
    "variant",
    [
        "undamped+LinearCoupling(K,C)",
        "rayleigh+LinearCoupling(sparse K,C)",
        "System(C=nonclassical)",
        "System(C=nonclassical)+LinearCoupling(K)",
    ],
)
def test_linear_coupling_second_order_vs_expm(variant):
    system, c_tot, k_tot = build_coupled(variant)
    n0 = round(T_END_1 / DT0_1)
    ref = expm_history(c_tot, k_tot, DT0_1, n0)
    scale = np.abs(ref).max()
    errs = []
    for i, dt in enumerate(DTS_1):
        # The paper's route: couplings as pseudo-forces (the default integrates a linear
        # coupled system exactly; tests/engine/test_coupled_exact.py).
        integrator = duhamel.Semianalytic(coupling="pseudo-force")
        sol = duhamel.solve(system, integrator, t_end=T_END_1, dt=dt, x0=X0_5, v0=V0_5)
        assert sol.t.shape == (n0 * 2**i + 1,)
        errs.append(np.abs(sol.x[:: 2**i] - ref).max() / scale)  # max over the common grid
    assert_order(f"LinearCoupling [{variant}]", DTS_1, errs)
    assert errs[-1] < 1e-6


def test_nonclassical_damping_is_a_pseudo_force():
    basis = duhamel.System(M5, K5, C=C5).modal()
    assert basis.c_coupling is not None and np.abs(basis.c_coupling).max() > 1e-3


def test_linear_coupling_quadratures_agree_and_sparse_equals_dense():
    # The pseudo-force of a linear coupling is linear in time along scheme b: every
    # quadrature integrates it exactly, so they agree to round-off.
    runs = {}
    for q in ("trapezoid", "parabolic", "exact"):
        s, _, _ = build_coupled("undamped+LinearCoupling(K,C)")
        runs[q] = duhamel.solve(
            s,
            duhamel.Semianalytic(quadrature=q, coupling="pseudo-force"),
            t_end=1.0,
            dt=0.01,
            x0=X0_5,
            v0=V0_5,
        ).x
    scale = np.abs(runs["trapezoid"]).max()
    for q in ("parabolic", "exact"):
        d = np.abs(runs[q] - runs["trapezoid"]).max() / scale
        print(f"\nquadrature {q} vs trapezoid (linear pseudo-force): {d:.2e}")
        assert d < 1e-12
    dense = duhamel.System(M5, K5).add(E.LinearCoupling(K=KX5, C=C5))
    sparse = duhamel.System(M5, K5).add(E.LinearCoupling(K=sp.csr_matrix(KX5), C=sp.csc_matrix(C5)))
    for s in (dense, sparse):
        s.add_load(L.Step(4, amplitude=10.0))
    a = duhamel.solve(dense, duhamel.Semianalytic(), t_end=1.0, dt=0.01, x0=X0_5).x
    b = duhamel.solve(sparse, duhamel.Semianalytic(), t_end=1.0, dt=0.01, x0=X0_5).x
    assert np.abs(a - b).max() <= 1e-13 * np.abs(a).max()


# --------------------------------------------------------------------------------------------
# 2. Callable element
# --------------------------------------------------------------------------------------------
K3 = 4.0
NEWTON = duhamel.Semianalytic(solver="newton")
RUN_2 = {"t_end": 20.0, "dt": 0.05, "x0": [1.0], "v0": [0.0]}


def duffing(element):
    s = duhamel.System(np.eye(1), np.eye(1), zeta=0.02).add(element)
    return s.add_load(L.Harmonic(0, amplitude=0.5, omega=1.3))


def cubic_jacobian(x, v, t):
    return np.array([[3.0 * K3 * x[0] ** 2]]), np.zeros((1, 1))


def test_callable_reproduces_cubic():
    ref = duhamel.solve(duffing(E.Cubic(0, k3=K3)), NEWTON, **RUN_2)
    assert ref.stats.newton_iterations > ref.stats.steps  # really iterating
    assert np.abs(ref.x).max() > 0.5  # strongly nonlinear: k3 x^2 ~ 4 omega^2
    with_jac = duhamel.solve(
        duffing(E.Callable([0], lambda x, v, t: K3 * x**3, jacobian=cubic_jacobian)),
        NEWTON,
        **RUN_2,
    )
    finite_diff = duhamel.solve(
        duffing(E.Callable([0], lambda x, v, t: K3 * x**3)), NEWTON, **RUN_2
    )
    e_jac = max(np.abs(with_jac.x - ref.x).max(), np.abs(with_jac.v - ref.v).max())
    e_fd = max(np.abs(finite_diff.x - ref.x).max(), np.abs(finite_diff.v - ref.v).max())
    e_acc = np.abs(with_jac.a - ref.a).max()
    print(
        f"\nCallable+jacobian vs Cubic: {e_jac:.2e} (a: {e_acc:.2e}); "
        f"finite differences: {e_fd:.2e}"
    )
    print(
        f"Newton iterations: Cubic {ref.stats.newton_iterations}, Callable+jac "
        f"{with_jac.stats.newton_iterations}, Callable FD {finite_diff.stats.newton_iterations}"
    )
    assert e_jac < 1e-12
    assert e_acc < 1e-11
    assert e_fd < 1e-9
    # the closed-form (auto) single-mode cubic solver agrees with Newton as well
    auto = duhamel.solve(duffing(E.Cubic(0, k3=K3)), duhamel.Semianalytic(), **RUN_2)
    assert auto.stats.closed_form_steps == auto.stats.steps
    assert np.abs(auto.x - ref.x).max() < 1e-12


def test_callable_multi_dof_and_velocity():
    """A 2-dof Callable on dofs [2, 0] (reversed order) reproduces Spring(0, 2, k3=...), and a
    velocity-dependent Callable reproduces a Damper: x and v reach fn in the dofs' order."""
    m = np.diag([1.0, 1.0, 2.0])
    k = np.array([[200.0, -100.0, 0.0], [-100.0, 200.0, -100.0], [0.0, -100.0, 100.0]])
    k3, cd = 3e4, 1.5

    def spring_fn(x, v, t):  # x = [x2, x0]
        s = k3 * (x[1] - x[0]) ** 3
        return np.array([-s, s])

    def spring_jac(x, v, t):
        g = 3.0 * k3 * (x[1] - x[0]) ** 2
        return np.array([[g, -g], [-g, g]]), np.zeros((2, 2))

    def run(*elements):
        s = duhamel.System(m, k, zeta=0.01)
        for e in elements:
            s.add(e)
        s.add_load(L.Step(2, amplitude=5.0))
        return duhamel.solve(
            s, NEWTON, t_end=2.0, dt=0.005, x0=[0.05, 0.0, -0.05], v0=[0.0, 0.3, 0.0]
        )

    ref = run(E.Spring(0, 2, k3=k3), E.Damper(1, c=cd))
    got = run(
        E.Callable([2, 0], spring_fn, jacobian=spring_jac),
        E.Callable(
            [1], lambda x, v, t: cd * v, jacobian=lambda x, v, t: (0 * x[:, None], cd * np.eye(1))
        ),
    )
    fd = run(E.Callable([2, 0], spring_fn), E.Callable([1], lambda x, v, t: cd * v))
    scale = np.abs(ref.x).max()
    e_jac = np.abs(got.x - ref.x).max() / scale
    e_fd = np.abs(fd.x - ref.x).max() / scale
    print(f"\n2-dof Callable vs Spring+Damper: jacobian {e_jac:.2e}, finite differences {e_fd:.2e}")
    assert e_jac < 1e-12
    assert e_fd < 1e-9


def _solve_callable(fn):
    return duhamel.solve(duffing(E.Callable([0], fn)), NEWTON, **RUN_2)


def test_callable_wrong_shape_raises():
    with callback_failure(ValueError, r"shape \(2,\).*expected \(1,\).*t = ") as info:
        _solve_callable(lambda x, v, t: np.zeros(2))
    print(f"\nwrong shape: {info.value}")


def test_callable_nan_raises_with_time():
    with callback_failure(ValueError, r"NaN") as info:
        _solve_callable(lambda x, v, t: np.array([np.nan]) if t > 1.0 else K3 * x**3)
    err = info.value
    print(f"\nNaN: {err}")
    assert 1.0 < err.time <= 1.0 + RUN_2["dt"] + 1e-12
    assert err.partial.t[-1] <= 1.0 and np.all(np.isfinite(err.partial.x))


def test_callable_exception_propagates():
    class Boom(Exception):
        pass

    def fn(x, v, t):
        if t > 1.0:
            raise Boom("inside fn")
        return K3 * x**3

    with callback_failure(Boom, "inside fn"):
        _solve_callable(fn)
    with callback_failure(ZeroDivisionError, "division by zero"):
        _solve_callable(lambda x, v, t: 1 / 0)


def test_callable_bad_jacobian_shape():
    bad = E.Callable(
        [0], lambda x, v, t: K3 * x**3, jacobian=lambda x, v, t: (np.zeros(3), np.zeros((1, 1)))
    )
    with callback_failure(ValueError, r"jacobian.*\(1, 1\)"):
        duhamel.solve(duffing(bad), NEWTON, **RUN_2)


# --------------------------------------------------------------------------------------------
# 3. Springs and dampers
# --------------------------------------------------------------------------------------------
M3 = np.diag([1.0, 2.0, 1.0])
K3M = np.array([[200.0, -100.0, 0.0], [-100.0, 200.0, -100.0], [0.0, -100.0, 100.0]])


def _pair_matrix(n, i, j, value):
    out = np.zeros((n, n))
    if j is None:
        out[i, i] = value
    else:
        out[np.ix_([i, j], [i, j])] = value * np.array([[1.0, -1.0], [-1.0, 1.0]])
    return out


@pytest.mark.parametrize(
    ("element", "coupling"),
    [
        (E.Spring(0, 2, k=50.0), E.LinearCoupling(K=_pair_matrix(3, 0, 2, 50.0))),
        (E.Spring(1, k=50.0), E.LinearCoupling(K=_pair_matrix(3, 1, None, 50.0))),
        (E.Damper(0, 1, c=3.0), E.LinearCoupling(C=_pair_matrix(3, 0, 1, 3.0))),
        (E.Damper(2, c=3.0), E.LinearCoupling(C=_pair_matrix(3, 2, None, 3.0))),
    ],
    ids=["spring-between", "spring-ground", "damper-between", "damper-ground"],
)
def test_spring_damper_equal_linear_coupling(element, coupling):
    def run(el):
        s = duhamel.System(M3, K3M, zeta=0.02).add(el)
        s.add_load(L.Step(2, amplitude=1.0))
        s.add_load(L.Harmonic(0, amplitude=2.0, omega=7.0))
        # Both as pseudo-forces: the same scheme (a constant LinearCoupling alone would
        # otherwise be integrated exactly).
        return duhamel.solve(
            s,
            duhamel.Semianalytic(coupling="pseudo-force", linear_parts="pseudo-force"),
            t_end=5.0,
            dt=0.01,
            x0=[0.01, -0.02, 0.03],
            v0=[0.1, 0, -0.1],
        )

    a, b = run(element), run(coupling)
    d = np.abs(a.x - b.x).max() / np.abs(b.x).max()
    dv = np.abs(a.v - b.v).max() / np.abs(b.v).max()
    print(f"\n{element} vs LinearCoupling: x {d:.2e}, v {dv:.2e}")
    assert d < 1e-13
    assert dv < 1e-13


W1, Z1 = 3.0, 0.05


def damped_exact(t, x0=1.0, v0=0.5):
    wd = W1 * np.sqrt(1.0 - Z1**2)
    return np.exp(-Z1 * W1 * t) * (x0 * np.cos(wd * t) + (v0 + Z1 * W1 * x0) / wd * np.sin(wd * t))


@pytest.mark.parametrize("quadrature", ["trapezoid", "parabolic", "exact"])
def test_damper_on_undamped_background_second_order(quadrature):
    dts = 0.1 / 2.0 ** np.arange(5)
    errs = []
    for dt in dts:
        s = duhamel.System(np.eye(1), np.array([[W1**2]])).add(E.Damper(0, c=2 * Z1 * W1))
        sol = duhamel.solve(
            s, duhamel.Semianalytic(quadrature=quadrature), t_end=10.0, dt=dt, x0=[1.0], v0=[0.5]
        )
        errs.append(np.abs(sol.x[:, 0] - damped_exact(sol.t)).max())
    assert_order(f"Damper as pseudo-force [{quadrature}]", dts, errs)


# --------------------------------------------------------------------------------------------
# 4. Stability with damping on the right-hand side (NOTES.md section 2)
# --------------------------------------------------------------------------------------------
W4, Z4 = 2.0, 0.1
DT4 = 0.7 * 2.0 * np.pi / W4  # dt/T = 0.7
N4 = 2000


def amplification(scheme, dt, w=W4, z=Z4):
    """Amplification matrix of (x, v) for x'' + w^2 x = -2 z w x' with the damping force
    evaluated along the scheme's state (constant over the step for "a" and "b")."""
    c, h = 2.0 * z * w, w * dt
    ch, sh = np.cos(h), np.sin(h)
    a0 = np.array([[ch, sh / w], [-w * sh, ch]])
    if scheme == "b":  # q = -c (x1 - x0)/dt
        p, r = c * (1 - ch) / (w * w * dt), c * sh / (w * dt)
        lhs, rhs = np.array([[1 + p, 0.0], [r, 1.0]]), a0 + np.array([[p, 0.0], [r, 0.0]])
    elif scheme == "a":  # q = -c (v0 + v1)/2
        p, r = c * (1 - ch) / (2 * w * w), c * sh / (2 * w)
        lhs, rhs = np.array([[1.0, p], [0.0, 1 + r]]), a0 - np.array([[0.0, p], [0.0, r]])
    else:  # pragma: no cover
        raise AssertionError(scheme)
    return np.linalg.solve(lhs, rhs)


def test_amplification_matrix_b_is_eq22():
    h, z, dt, w = W4 * DT4, Z4, DT4, W4
    eq22 = np.array(
        [
            [2 * z + (h - 2 * z) * np.cos(h), dt * np.sin(h)],
            [-(w**2) * dt * np.sin(h), -2 * z + (h + 2 * z) * np.cos(h)],
        ]
    ) / (h + 2 * z * (1 - np.cos(h)))
    np.testing.assert_allclose(amplification("b", DT4), eq22, rtol=1e-13, atol=1e-14)


def _damper_run(scheme, quadrature, n_steps=N4, dt=DT4, growth_limit=None):
    """The raw scheme: without the growth guard (which stops the unstable runs early, see
    test_growth_guard_stops_scheme_a), so that the growth rate can be measured."""
    s = duhamel.System(np.eye(1), np.array([[W4**2]])).add(E.Damper(0, c=2 * Z4 * W4))
    opt = duhamel.Semianalytic(scheme=scheme, quadrature=quadrature, growth_limit=growth_limit)
    return duhamel.solve(s, opt, t_end=n_steps * dt, dt=dt, x0=[1.0])


@pytest.mark.parametrize("quadrature", ["trapezoid", "parabolic", "exact"])
def test_scheme_b_stable_with_damping_on_rhs(quadrature):
    sol = _damper_run("b", quadrature)
    x = np.abs(sol.x[:, 0])
    assert np.all(np.isfinite(x))
    g = amplification("b", DT4)
    rho = max(abs(np.linalg.eigvals(g)))
    rate = (x[-100:].max() / x[:100].max()) ** (1.0 / (N4 - 100))
    # the run is the amplification matrix applied N times, to round-off relative to rho^n
    z = np.array([1.0, 0.0])
    dev = 0.0
    for n in range(1, N4 + 1):
        z = g @ z
        dev = max(dev, abs(sol.x[n, 0] - z[0]) / rho**n)
    print(
        f"\nscheme b [{quadrature}] dt/T=0.7: max|x| first 10 steps {x[:10].max():.3g}, "
        f"last 100 {x[-100:].max():.3g}; measured rate {rate:.6f}, spectral radius {rho:.6f}; "
        f"deviation from G^n {dev:.1e}"
    )
    assert rho < 1.0
    assert x[-100:].max() <= x[:10].max()
    assert x[-100:].max() < 1e-40  # decays: 0.942^2000
    assert abs(rate - rho) < 1e-3
    assert dev < 1e-9


@pytest.mark.parametrize("quadrature", ["trapezoid", "parabolic", "exact"])
def test_scheme_a_unstable_with_damping_on_rhs(quadrature):
    rho = max(abs(np.linalg.eigvals(amplification("a", DT4))))
    try:
        sol = _damper_run("a", quadrature)
    except duhamel.SolverError as err:  # the accepted alternative: the run overflows
        print(f"\nscheme a [{quadrature}]: stopped at t = {err.time} ({err.reason})")
        assert err.reason == "nonfinite"
        return
    x = np.abs(sol.x[:, 0])
    rate = (x[-100:].max() / x[:100].max()) ** (1.0 / (N4 - 100))
    print(
        f"\nscheme a [{quadrature}] dt/T=0.7: max|x| first 10 steps {x[:10].max():.3g}, "
        f"last 100 {x[-100:].max():.3g}; measured rate {rate:.6f}, spectral radius {rho:.6f}"
    )
    assert rho > 1.1  # NOTES.md: max 1.1055 on dt/T in (0.500, 0.999)
    assert x[-100:].max() > 1e50 * x[:10].max()
    assert abs(rate - rho) < 1e-3


def test_scheme_a_overflows_to_solver_error():
    with pytest.raises(duhamel.SolverError) as info:
        _damper_run("a", "trapezoid", n_steps=10_000)
    err = info.value
    print(f"\nscheme a, 10000 steps: {err}")
    assert err.reason == "nonfinite"
    assert err.partial.t[-1] < err.time
    assert np.all(np.isfinite(err.partial.x))


def test_growth_guard_stops_scheme_a():
    """With the guard (the default), scheme a's growth at its spectral radius 1.1 per step
    stops once the energy passes 100 times the initial one (a passive damper supplies
    nothing): at step ln(100) / (2 ln 1.1) = 24 or soon after, not at the overflow (step
    ~7,400)."""
    with pytest.raises(duhamel.SolverError) as info:
        _damper_run("a", "trapezoid", n_steps=10_000, growth_limit=100.0)
    err = info.value
    assert err.reason == "growth"
    assert 20 <= err.step <= 60, err.step
    assert np.abs(err.partial.x).max() < 11.0


def test_scheme_c_unstable_window():
    """NOTES.md: scheme c's spectral radius exceeds 1 on dt/T in (0.933, 1.357)."""
    rates = {}
    for ratio in (0.7, 1.1):
        dt = ratio * 2 * np.pi / W4
        x = np.abs(_damper_run("c", "trapezoid", n_steps=400, dt=dt).x[:, 0])
        rates[ratio] = (x[-50:].max() / x[:50].max()) ** (1.0 / 350)
    print(f"\nscheme c growth rates per step: {rates}")
    assert rates[0.7] < 1.0 < rates[1.1]


# --------------------------------------------------------------------------------------------
# 5. Contact: Jeffcott rotor rubbing on its stator
# --------------------------------------------------------------------------------------------
RM, RK, RC = 1.0, 100.0, 0.2  # omega = 10 rad/s, zeta = 0.01
GAP, KC, MU = 0.01, 1e4, 0.1  # contact stiffness 100 k
EPS, VEPS = 1e-3, 1e-2  # smoothing (0.1 gap) and velocity smoothing
OM, FU = 8.0, 2.0  # rotating (unbalance-like) load, static radius F/(k - m Om^2) = 0.056 > g
T5 = 3.0
X0_R, V0_R = [0.001, 0.0], [0.0, 0.0]


def _softplus(z):
    return np.maximum(z, 0.0) + np.log1p(np.exp(-abs(z)))


def contact_force(x, y, vx, vy):
    """The documented law: r = F_n n + F_t t (left-hand side)."""
    rho = np.hypot(x, y)
    n = np.array([x, y]) / rho
    t = np.array([-y, x]) / rho
    fn = KC * EPS * _softplus((rho - GAP) / EPS)
    vt = (x * vy - y * vx) / rho
    return fn * n + MU * fn * np.tanh(vt / VEPS) * t


def rotor_rhs(t, z):
    x, y, vx, vy = z
    f = FU * np.array([np.cos(OM * t), np.sin(OM * t)])
    a = (f - RC * np.array([vx, vy]) - RK * np.array([x, y]) - contact_force(x, y, vx, vy)) / RM
    return [vx, vy, a[0], a[1]]


@pytest.fixture(scope="module")
def rotor_reference():
    ref = solve_ivp(
        rotor_rhs,
        (0.0, T5),
        X0_R + V0_R,
        method="DOP853",
        rtol=1e-12,
        atol=1e-15,
        dense_output=True,
    )
    assert ref.success
    return ref


def rotor(contact=True, clearance=GAP):
    s = duhamel.System(RM * np.eye(2), RK * np.eye(2), C=RC * np.eye(2))
    if contact:
        s.add(
            E.Contact(
                (0, 1),
                clearance=clearance,
                stiffness=KC,
                friction=MU,
                smoothing=EPS,
                velocity_smoothing=VEPS,
            )
        )
    s.add_load(L.Harmonic(0, amplitude=FU, omega=OM, phase=np.pi / 2))  # F cos(Om t)
    s.add_load(L.Harmonic(1, amplitude=FU, omega=OM))  # F sin(Om t)
    return s


def test_contact_converges_to_solve_ivp(rotor_reference):
    dts = 0.01 / 2.0 ** np.arange(5)
    errs = []
    radius = 0.0
    for dt in dts:
        sol = duhamel.solve(rotor(), duhamel.Semianalytic(), t_end=T5, dt=dt, x0=X0_R, v0=V0_R)
        ref = rotor_reference.sol(sol.t)[:2].T
        errs.append(np.abs(sol.x - ref).max() / GAP)
        radius = np.hypot(sol.x[:, 0], sol.x[:, 1]).max()
        iters = sol.stats.newton_iterations / sol.stats.steps
        print(
            f"\ncontact dt={dt:.3g}: error/gap {errs[-1]:.3e}, max radius/gap "
            f"{radius / GAP:.4f}, Newton iterations/step {iters:.2f}"
        )
    fit, pair = slopes(dts, errs)
    print(f"contact: fitted slope {fit:.4f}, pairwise {np.array2string(pair, precision=4)}")
    assert fit >= 1.8
    assert pair[-1] >= 1.8
    assert radius > 1.05 * GAP  # the contact is really active
    ref_r = np.hypot(*rotor_reference.sol(np.linspace(0, T5, 3001))[:2])
    assert ref_r.max() > 1.05 * GAP
    # and it matters: the free rotor's orbit differs by far more than the error
    free = duhamel.solve(rotor(False), duhamel.Semianalytic(), t_end=T5, dt=dts[-1], x0=X0_R)
    assert np.abs(free.x - rotor_reference.sol(free.t)[:2].T).max() > 1e3 * errs[-1] * GAP


def test_contact_huge_clearance_equals_linear():
    kw = {"t_end": T5, "dt": 0.01, "x0": X0_R, "v0": V0_R}
    far = duhamel.solve(rotor(True, clearance=1e3), duhamel.Semianalytic(), **kw)
    lin = duhamel.solve(rotor(False), duhamel.Semianalytic(), **kw)
    dx = np.abs(far.x - lin.x).max() / np.abs(lin.x).max()
    dv = np.abs(far.v - lin.v).max() / np.abs(lin.v).max()
    da = np.abs(far.a - lin.a).max() / np.abs(lin.a).max()
    print(f"\nhuge clearance vs linear run: x {dx:.1e}, v {dv:.1e}, a {da:.1e}")
    assert dx < 1e-13 and dv < 1e-13 and da < 1e-13


# --------------------------------------------------------------------------------------------
# 6. Bad input
# --------------------------------------------------------------------------------------------
def _sys2():
    return duhamel.System(np.eye(2), np.eye(2))


BAD = [
    ("cubic-dof", lambda: _sys2().add(E.Cubic(5, k3=1.0)), ValueError, "`i`"),
    ("cubic-negative-dof", lambda: _sys2().add(E.Cubic(-1, k3=1.0)), ValueError, "`i`"),
    ("cubic-float-dof", lambda: _sys2().add(E.Cubic(0.5, k3=1.0)), TypeError, "`i`"),
    (
        "polynomial-dof",
        lambda: _sys2().add(E.Polynomial(2, coefficients=[0.0, 1.0])),
        ValueError,
        "`i`",
    ),
    ("spring-same", lambda: _sys2().add(E.Spring(0, 0)), ValueError, "`j`"),
    ("spring-i", lambda: _sys2().add(E.Spring(3)), ValueError, "`i`"),
    ("spring-j", lambda: _sys2().add(E.Spring(0, 7)), ValueError, "`j`"),
    ("spring-k-inf", lambda: E.Spring(0, 1, k=np.inf), ValueError, "`k`"),
    ("damper-negative", lambda: E.Damper(0, c=-1.0), ValueError, "`c`"),
    ("cubic-k3-nan", lambda: E.Cubic(0, k3=np.nan), ValueError, "`k3`"),
    (
        "contact-clearance",
        lambda: E.Contact((0, 1), clearance=-1.0, stiffness=1.0),
        ValueError,
        "`clearance`",
    ),
    (
        "contact-stiffness-0",
        lambda: E.Contact((0, 1), clearance=1.0, stiffness=0.0),
        ValueError,
        "`stiffness`",
    ),
    (
        "contact-stiffness-neg",
        lambda: E.Contact((0, 1), clearance=1.0, stiffness=-1.0),
        ValueError,
        "`stiffness`",
    ),
    (
        "contact-friction",
        lambda: E.Contact((0, 1), clearance=1.0, stiffness=1.0, friction=-0.1),
        ValueError,
        "`friction`",
    ),
    (
        "contact-smoothing",
        lambda: E.Contact((0, 1), clearance=1.0, stiffness=1.0, smoothing=0.0),
        ValueError,
        "`smoothing`",
    ),
    (
        "contact-vsmoothing",
        lambda: E.Contact((0, 1), clearance=1.0, stiffness=1.0, velocity_smoothing=-1.0),
        ValueError,
        "`velocity_smoothing`",
    ),
    (
        "contact-same-dof",
        lambda: _sys2().add(E.Contact((0, 0), clearance=1.0, stiffness=1.0)),
        ValueError,
        "`dof_y`",
    ),
    (
        "contact-dof",
        lambda: _sys2().add(E.Contact((0, 2), clearance=1.0, stiffness=1.0)),
        ValueError,
        "`dofs",
    ),
    ("callable-fn", lambda: E.Callable(3.0, [0]), TypeError, "`fn`"),
    (
        "callable-jacobian",
        lambda: E.Callable([0], lambda x, v, t: x, jacobian=1),
        TypeError,
        "`jacobian`",
    ),
    (
        "callable-dofs",
        lambda: _sys2().add(E.Callable([4], lambda x, v, t: x)),
        ValueError,
        "`dofs`",
    ),
    (
        "callable-dofs-dup",
        lambda: _sys2().add(E.Callable([0, 0], lambda x, v, t: x)),
        ValueError,
        "`dofs`",
    ),
    ("callable-dofs-empty", lambda: E.Callable([], lambda x, v, t: x), ValueError, "`dofs`"),
    ("coupling-K-shape", lambda: _sys2().add(E.LinearCoupling(K=np.eye(3))), ValueError, "`K`"),
    ("coupling-C-shape", lambda: _sys2().add(E.LinearCoupling(C=np.eye(3))), ValueError, "`C`"),
    ("coupling-1d", lambda: _sys2().add(E.LinearCoupling(K=np.ones(2))), ValueError, "`K`"),
    (
        "coupling-sparse-shape",
        lambda: _sys2().add(E.LinearCoupling(K=sp.eye(3, format="csr"))),
        ValueError,
        "`K`",
    ),
    (
        "coupling-nan",
        lambda: E.LinearCoupling(K=np.array([[np.nan, 0], [0, 0]])),
        ValueError,
        "`K`",
    ),
    ("coupling-empty", lambda: E.LinearCoupling(), ValueError, "LinearCoupling"),
    ("scheme", lambda: duhamel.Semianalytic(scheme="d"), ValueError, "`scheme`"),
    ("quadrature", lambda: duhamel.Semianalytic(quadrature="x"), ValueError, "`quadrature`"),
    ("tol-0", lambda: duhamel.Semianalytic(tol=0), ValueError, "`tol`"),
    ("tol-nan", lambda: duhamel.Semianalytic(tol=np.nan), ValueError, "`tol`"),
    ("max_iter-0", lambda: duhamel.Semianalytic(max_iter=0), ValueError, "`max_iter`"),
    ("max_iter-float", lambda: duhamel.Semianalytic(max_iter=2.5), ValueError, "`max_iter`"),
    ("solver", lambda: duhamel.Semianalytic(solver="cg"), ValueError, "`solver`"),
    ("add-str", lambda: _sys2().add("not an element"), TypeError, "`element`"),
    ("add-None", lambda: _sys2().add(None), TypeError, "`element`"),
    ("add-load-as-element", lambda: _sys2().add(L.Step(0, amplitude=1.0)), TypeError, "`element`"),
    ("add_load-element", lambda: _sys2().add_load(E.Cubic(0, k3=1.0)), TypeError, "`load`"),
    ("callable-float-dofs", lambda: E.Callable([0.7], lambda x, v, t: x), TypeError, "`dofs"),
]


def _bad_id(case):
    return case.values[0] if hasattr(case, "values") else case[0]


@pytest.mark.parametrize(("label", "call", "exc", "name"), BAD, ids=[_bad_id(b) for b in BAD])
def test_bad_input(label, call, exc, name):
    with pytest.raises(exc, match=re.escape(name)):
        call()


def test_rejected_element_is_not_added():
    s = _sys2()
    with pytest.raises(ValueError):
        s.add(E.Cubic(5, k3=1.0))
    assert s.elements == []


# --------------------------------------------------------------------------------------------
# 7. Newton non-convergence
# --------------------------------------------------------------------------------------------
def hard_chain():
    """3-dof chain with strong cubic springs, at rest until a step load hits at t = 0.3."""
    k = 100.0 * np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    s = duhamel.System(np.eye(3), k, zeta=0.02)
    for i in range(3):
        s.add(E.Cubic(i, k3=1e4))
    s.add(E.Spring(0, 2, k3=5e3))
    return s.add_load(L.Step(2, amplitude=50.0, t0=0.3))


def test_non_convergence_raises_solver_error():
    ok = duhamel.solve(hard_chain(), duhamel.Semianalytic(), t_end=2.0, dt=0.01)
    assert ok.stats.newton_iterations > ok.stats.steps  # needs several iterations per step
    with pytest.raises(duhamel.SolverError) as info:
        duhamel.solve(
            hard_chain(), duhamel.Semianalytic(max_iter=1, subdivisions=0), t_end=2.0, dt=0.01
        )
    err = info.value
    msg = str(err)
    print(f"\nmax_iter=1: {msg}")
    assert err.reason == "convergence"
    assert isinstance(err, RuntimeError)
    assert re.search(r"t = 0\.31\b", msg)  # names the time
    assert "residual" in msg
    assert re.search(r"1 Newton iteration", msg)
    assert abs(err.time - 0.31) < 1e-12
    part = err.partial
    assert part.t[-1] < err.time
    np.testing.assert_allclose(part.t[-1], 0.30, atol=1e-12)
    assert np.all(np.isfinite(part.x))
    # the partial history is the good run's history up to the failure
    n = part.t.shape[0]
    np.testing.assert_allclose(part.x, ok.x[:n], rtol=0, atol=1e-12)


def test_non_convergence_partial_stats():
    with pytest.raises(duhamel.SolverError) as info:
        duhamel.solve(
            hard_chain(), duhamel.Semianalytic(max_iter=1, subdivisions=0), t_end=2.0, dt=0.01
        )
    part = info.value.partial
    assert part.stats.steps == part.t.shape[0] - 1

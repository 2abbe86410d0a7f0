"""Linear systems are integrated exactly: checks against a matrix-exponential reference.

The reference integrates the first-order system ``z' = F z + G f(t)`` with ``scipy.linalg.expm``
of an augmented matrix over every interval on which the load is a quadratic polynomial
(between step-grid points, load kinks and jumps), so it is exact to round-off and shares
nothing with the modal Duhamel code under test.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
import scipy.linalg as sla
from _callbacks import callback_failure

import duhamel
from duhamel import loads


def first_order(system: duhamel.System, c_matrix: np.ndarray):
    m = np.asarray(system.M.toarray() if hasattr(system.M, "toarray") else system.M)
    k = np.asarray(system.K.toarray() if hasattr(system.K, "toarray") else system.K)
    n = m.shape[0]
    minv = np.linalg.inv(m)
    f = np.zeros((2 * n, 2 * n))
    f[:n, n:] = np.eye(n)
    f[n:, :n] = -minv @ k
    f[n:, n:] = -minv @ c_matrix
    g = np.zeros((2 * n, n))
    g[n:, :] = minv
    return f, g, minv, k


def expm_reference(system, c_matrix, load_fn, x0, v0, times, breaks):
    """State at `times` for ``M x'' + C x' + K x = load_fn(t)``; load quadratic between `breaks`."""
    f, g, minv, k = first_order(system, c_matrix)
    n2 = f.shape[0]
    n = n2 // 2
    pts = np.unique(np.concatenate([times, breaks]))
    pts = pts[(pts >= times[0]) & (pts <= times[-1])]
    z = np.concatenate([x0, v0])
    out = {0: z.copy()}
    want = {float(t): i for i, t in enumerate(times)}
    for a, b in itertools.pairwise(pts):
        h = b - a
        # quadratic through s = 0 (right-continuous start), 1/2, 3/4 -- never the end point
        s = np.array([0.0, 0.5, 0.75])
        vals = np.stack([load_fn(a + si * h) for si in s])  # (3, n)
        coef = np.linalg.solve(np.vander(s, 3, increasing=True), vals)  # c0 + c1 s + c2 s^2
        # augmented: [z, w2, w1, w0] with w0 = 1, w1 = s, w2 = s^2 (time unit h)
        aug = np.zeros((n2 + 3, n2 + 3))
        aug[:n2, :n2] = f * h
        aug[:n2, n2] = (g @ coef[2]) * h
        aug[:n2, n2 + 1] = (g @ coef[1]) * h
        aug[:n2, n2 + 2] = (g @ coef[0]) * h
        aug[n2, n2 + 1] = 2.0  # (s^2)' = 2 s
        aug[n2 + 1, n2 + 2] = 1.0  # s' = 1
        e = sla.expm(aug)
        z = e[:n2, :n2] @ z + e[:n2, n2 + 2]
        if float(b) in want:
            out[want[float(b)]] = z.copy()
    zs = np.stack([out[i] for i in range(len(times))])
    x, v = zs[:, :n], zs[:, n:]
    fs = np.stack([load_fn(t) for t in times])
    acc = (fs - v @ c_matrix.T - x @ k.T) @ minv.T
    return x, v, acc


def rel_err(got, ref):
    return np.abs(got - ref).max() / np.abs(ref).max()


def total_load(system):
    def f(t):
        return sum(ld.evaluate(system, t) for ld in system.loads)

    return f


REGIMES = [-0.05, 0.0, 0.05, 1.0, 2.5]


@pytest.mark.filterwarnings("ignore::duhamel.errors.DampingWarning")  # heavy damping is meant
@pytest.mark.parametrize("zeta", REGIMES)
@pytest.mark.parametrize("dt", [1.3, 0.65])
def test_single_dof_exact_in_every_damping_regime(zeta, dt):
    """Steps (one jumping inside a step), ramps and a quadratic load; dt up to 1.3 T."""
    omega = 2 * np.pi
    sys = duhamel.System(np.array([[2.0]]), np.array([[2.0 * omega**2]]), zeta=zeta)
    sys.add_load(loads.Step(0, amplitude=30.0, t0=0.9))  # inside the first step for both dt
    sys.add_load(loads.Tabulated(0, t=[0.0, 2.6, 5.2], values=[0.0, 40.0, -20.0], hold=True))
    sys.add_load(loads.Callable(lambda t: np.array([0.8 * t**2 - 3.0 * t])))
    x0, v0 = np.array([0.3]), np.array([-1.0])
    sol = duhamel.solve(sys, duhamel.Semianalytic(), t_end=13.0, dt=dt, x0=x0, v0=v0)
    c = np.array([[2.0 * 2.0 * zeta * omega]])
    breaks = np.array([0.9, 2.6, 5.2])
    x, v, a = expm_reference(sys, c, total_load(sys), x0, v0, sol.t, breaks)
    errs = rel_err(sol.x, x), rel_err(sol.v, v), rel_err(sol.a, a)
    print(f"zeta={zeta} dt={dt}: relative errors x {errs[0]:.1e} v {errs[1]:.1e} a {errs[2]:.1e}")
    assert max(errs) < 1e-10


@pytest.mark.parametrize("hold", [False, True])
@pytest.mark.parametrize("coupled", [False, True], ids=["uncoupled", "coupled"])
def test_record_ends_inside_a_step_are_exact(hold, coupled):
    """A record whose first and last samples miss the step grid: mid-step (0.37, 1.83 with
    dt = 0.3) or by one rounding (1.8 against 6 * 0.3 = 1.7999999999999998). The jumps at its
    ends (to and from zero, or the held value) are integrated exactly, like a Step's, on the
    uncoupled and on the coupled (first-order modes) route."""
    m = np.diag([2.0, 1.0])
    k = np.array([[30.0, -10.0], [-10.0, 10.0]])
    for t_rec in ([0.37, 0.9, 1.83], [0.0, 0.9, 1.8]):
        sys = duhamel.System(m, k, zeta=0.03)
        if coupled:
            sys.add(duhamel.elements.LinearCoupling(C=np.array([[0.0, 0.4], [-0.4, 0.0]])))
        sys.add_load(loads.Tabulated(0, t=t_rec, values=[5.0, -3.0, 4.0], hold=hold))
        sol = duhamel.solve(sys, duhamel.Semianalytic(), t_end=4.2, dt=0.3, x0=[0.1, 0.0])
        assert sol.stats.coupling == ("exact" if coupled else None)
        c = m @ sys.modal().phi @ np.diag(sys.modal().c) @ sys.modal().phi.T @ m
        if coupled:
            c = c + np.array([[0.0, 0.4], [-0.4, 0.0]])
        x, v, _ = expm_reference(
            sys, c, total_load(sys), np.array([0.1, 0.0]), np.zeros(2), sol.t, np.array(t_rec)
        )
        errs = rel_err(sol.x, x), rel_err(sol.v, v)
        print(f"record {t_rec}, hold={hold}, coupled={coupled}: x {errs[0]:.1e} v {errs[1]:.1e}")
        assert max(errs) < 1e-12


def free_free_chain(n=12):
    """A free-free chain (one rigid-body mode) of unequal masses; shortest period ~0.006 s."""
    rng = np.random.default_rng(7)
    masses = rng.uniform(1.0, 3.0, n)
    springs = rng.uniform(2e5, 6e5, n - 1)
    k = np.zeros((n, n))
    for i, s in enumerate(springs):
        k[i : i + 2, i : i + 2] += s * np.array([[1.0, -1.0], [-1.0, 1.0]])
    return np.diag(masses), k


def test_chain_with_rayleigh_damping_and_rigid_body_mode_is_exact():
    m, k = free_free_chain()
    alpha, beta = 0.4, 2e-4
    sys = duhamel.System(m, k, rayleigh=(alpha, beta))
    basis = sys.modal()
    assert basis.omega2[0] == 0.0 and basis.c[0] == pytest.approx(alpha)
    t_min = 2 * np.pi / basis.omega.max()
    dt = 0.01
    assert dt > t_min  # larger than the shortest natural period
    rec_t = np.arange(0.0, 0.5 + 1e-12, 0.02)  # a record sampled on the step grid
    rec = 3.0 * np.sin(25 * rec_t) * np.exp(-3 * rec_t)
    sys.add_load(loads.Step(3, amplitude=500.0, t0=0.013))  # jumps inside a step
    sys.add_load(loads.Tabulated(11, t=[0.0, 0.1, 0.3], values=[0.0, -800.0, 200.0]))
    sys.add_load(loads.BaseAcceleration(np.ones(12), t=rec_t, values=rec))
    x0 = np.linspace(-1e-3, 1e-3, 12)
    v0 = np.full(12, 0.05)
    sol = duhamel.solve(sys, duhamel.Semianalytic(), t_end=0.8, dt=dt, x0=x0, v0=v0)
    c = alpha * m + beta * k
    breaks = np.concatenate([[0.013, 0.1, 0.3], rec_t])
    x, v, a = expm_reference(sys, c, total_load(sys), x0, v0, sol.t, breaks)
    errs = rel_err(sol.x, x), rel_err(sol.v, v), rel_err(sol.a, a)
    ratio = dt / t_min
    print(f"12-dof chain, dt/T_min = {ratio:.2f}: x {errs[0]:.1e} v {errs[1]:.1e} a {errs[2]:.1e}")
    assert max(errs) < 1e-10


def test_result_does_not_depend_on_the_step():
    m, k = free_free_chain()
    sys = duhamel.System(m, k, zeta=0.03)
    sys.add_load(loads.Tabulated(5, t=[0.0, 0.2, 0.4], values=[0.0, 1e3, 0.0]))
    coarse = duhamel.solve(sys, duhamel.Semianalytic(), t_end=1.0, dt=0.1, v0=np.ones(12))
    fine = duhamel.solve(sys, duhamel.Semianalytic(), t_end=1.0, dt=0.1 / 7, v0=np.ones(12))
    assert rel_err(coarse.x[-1], fine.x[-1]) < 1e-10
    assert rel_err(coarse.x, fine.x[::7]) < 1e-10


def harmonic_reference(omega, zeta, big_omega, amp, times):
    """1-dof x'' + 2 zeta omega x' + omega^2 x = amp sin(big_omega t), exact via expm."""
    f = np.array(
        [
            [0.0, 1.0, 0.0, 0.0],
            [-(omega**2), -2 * zeta * omega, amp, 0.0],
            [0.0, 0.0, 0.0, big_omega],  # s' = Omega c
            [0.0, 0.0, -big_omega, 0.0],  # c' = -Omega s
        ]
    )
    z0 = np.array([0.0, 0.0, 0.0, 1.0])  # s = sin, c = cos
    return np.array([(sla.expm(f * t) @ z0)[0] for t in times])


def test_harmonic_load_error_is_fourth_order():
    omega, zeta, big_omega, amp = 2 * np.pi, 0.05, 1.7 * 2 * np.pi, 5.0
    sys = duhamel.System(np.eye(1), np.array([[omega**2]]), zeta=zeta)
    sys.add_load(loads.Harmonic(0, amplitude=amp, omega=big_omega))
    t_end = 4.0
    check = np.linspace(0.0, t_end, 41)
    ref = harmonic_reference(omega, zeta, big_omega, amp, check)
    dts, errs = [], []
    for n_per in [1, 2, 4, 8]:
        dt = 0.1 / n_per
        sol = duhamel.solve(sys, duhamel.Semianalytic(), t_end=t_end, dt=dt)
        every = round(0.1 / dt)
        got = sol.x[::every, 0]
        dts.append(dt)
        errs.append(np.abs(got - ref).max() / np.abs(ref).max())
    slope = np.polyfit(np.log(dts), np.log(errs), 1)[0]
    print("harmonic: dt", dts, "errors", [f"{e:.2e}" for e in errs], f"slope {slope:.3f}")
    assert 3.8 < slope < 4.2


def test_callable_matches_builtin_load():
    sys_a = duhamel.System(
        np.diag([1.0, 2.0]), np.array([[300.0, -100.0], [-100.0, 100.0]]), zeta=0.02
    )
    sys_b = duhamel.System(sys_a.M, sys_a.K, zeta=0.02)
    sys_a.add_load(loads.Harmonic(1, amplitude=3.0, omega=4.0, phase=0.3))
    sys_b.add_load(loads.Callable(lambda t: np.array([0.0, 3.0 * np.sin(4.0 * t + 0.3)])))
    a = duhamel.solve(sys_a, duhamel.Semianalytic(), t_end=5.0, dt=0.01)
    b = duhamel.solve(sys_b, duhamel.Semianalytic(), t_end=5.0, dt=0.01)
    assert rel_err(b.x, a.x) < 1e-12


def test_modal_reduction_and_output_options_are_consistent():
    m, k = free_free_chain()
    sys = duhamel.System(m, k, zeta=0.02)
    sys.add_load(loads.Step(11, amplitude=100.0))
    full = duhamel.solve(sys, duhamel.Semianalytic(), t_end=0.5, dt=0.002, v0=np.ones(12))
    red = duhamel.solve(sys, duhamel.Semianalytic(modes=4), t_end=0.5, dt=0.002, v0=np.ones(12))
    phi4 = sys.modal(4).phi
    assert red.modal.q.shape == (full.t.size, 4)
    np.testing.assert_allclose(red.modal.q, full.modal.q[:, :4], rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(red.x, full.modal.q[:, :4] @ phi4.T, rtol=1e-10, atol=1e-14)
    sub = duhamel.solve(
        sys, duhamel.Semianalytic(), t_end=0.5, dt=0.002, v0=np.ones(12), dofs=[11, 2]
    )
    np.testing.assert_allclose(sub.x, full.x[:, [11, 2]], rtol=1e-13)
    np.testing.assert_allclose(sub.a, full.a[:, [11, 2]], rtol=1e-13)
    assert sub.dofs.tolist() == [11, 2]
    every = duhamel.solve(
        sys, duhamel.Semianalytic(), t_end=0.5, dt=0.002, v0=np.ones(12), save_every=7
    )
    assert every.t[-1] == pytest.approx(0.5) and every.t[1] == pytest.approx(0.014)
    np.testing.assert_allclose(every.x[:-1], full.x[::7], rtol=1e-13)
    np.testing.assert_allclose(every.x[-1], full.x[-1], rtol=1e-13)
    assert full.stats.steps == 250 and full.stats.modes == 12


def test_threads_give_identical_results():
    n = 150
    k = 2e4 * (np.diag(np.full(n, 2.0)) - np.diag(np.ones(n - 1), 1) - np.diag(np.ones(n - 1), -1))
    sys = duhamel.System(np.eye(n), k, zeta=0.01)
    sys.add_load(loads.Harmonic(n - 1, amplitude=1.0, omega=30.0))
    one = duhamel.solve(sys, duhamel.Semianalytic(), t_end=0.2, dt=1e-3, threads=1)
    two = duhamel.solve(sys, duhamel.Semianalytic(), t_end=0.2, dt=1e-3, threads=2)
    np.testing.assert_array_equal(one.modal.q, two.modal.q)


def test_divergence_stops_with_time_and_keeps_the_history():
    sys = duhamel.System(np.eye(1), np.array([[100.0]]), zeta=-0.5)
    with pytest.raises(duhamel.SolverError, match="non-finite") as info:
        duhamel.solve(sys, duhamel.Semianalytic(), t_end=400.0, dt=0.01, x0=[1.0])
    err = info.value
    # |x| ~ exp(5 t) overflows near t = ln(1.8e308) / 5 = 142
    assert 135.0 < err.time < 145.0
    part = err.partial
    assert part.t.size > 0 and part.t[-1] < err.time
    assert np.all(np.isfinite(part.x)) and np.abs(part.x).max() > 1e250
    assert err.reason == "nonfinite"


def test_callable_errors_are_clear_and_chain_their_cause():
    sys = duhamel.System(np.eye(2), np.eye(2))
    sys.add_load(loads.Callable(lambda t: np.zeros(3)))
    with callback_failure(ValueError, r"shape \(3,\).*expected \(2,\)") as info:
        duhamel.solve(sys, duhamel.Semianalytic(), t_end=1.0, dt=0.1)
    # the first load evaluation fails: nothing was computed
    assert info.value.partial.t.size == 0 and "nothing is kept" in str(info.value)
    sys = duhamel.System(np.eye(2), np.eye(2))
    sys.add_load(loads.Callable(lambda t: np.array([np.nan if t > 0.5 else 0.0, 0.0])))
    with callback_failure(ValueError, r"NaN or inf at t = 0\.55"):
        duhamel.solve(sys, duhamel.Semianalytic(), t_end=1.0, dt=0.1)

    def broken(t):
        return 1.0 / 0.0

    sys = duhamel.System(np.eye(2), np.eye(2))
    sys.add_load(loads.Callable(broken))
    with callback_failure(ZeroDivisionError, "division by zero") as info:
        duhamel.solve(sys, duhamel.Semianalytic(), t_end=1.0, dt=0.1)
    assert "a Python load or element function failed at t = 0.0" in str(info.value)


def _chain_system():
    sys = duhamel.System(np.eye(3), np.diag([1.0, 2.0, 3.0]), zeta=0.01)
    return sys


@pytest.mark.parametrize(
    ("kwargs", "exc", "match"),
    [
        ({"dt": 0.0}, ValueError, "`dt`"),
        ({"dt": -0.1}, ValueError, "`dt`"),
        ({"dt": float("nan")}, ValueError, "`dt`"),
        ({"dt": "0.1"}, TypeError, "`dt`"),
        ({"t_end": 0.05}, ValueError, "`t_end`"),
        ({"t_end": -1.0}, ValueError, "`t_end`"),
        ({"x0": [1.0, 2.0]}, ValueError, "`x0`"),
        ({"x0": [1.0, np.nan, 0.0]}, ValueError, "`x0`"),
        ({"v0": np.array([1j, 0, 0])}, TypeError, "`v0`"),
        ({"v0": ["a", "b", "c"]}, TypeError, "`v0`"),
        ({"dofs": [0, 3]}, ValueError, r"`dofs\[1\]`"),
        ({"dofs": [-1]}, ValueError, r"`dofs\[0\]`"),
        ({"save_every": 0}, ValueError, "`save_every`"),
        ({"threads": 0}, ValueError, "`threads`"),
    ],
)
def test_solve_rejects_bad_input_naming_the_parameter(kwargs, exc, match):
    args = {"t_end": 1.0, "dt": 0.1, **kwargs}
    with pytest.raises(exc, match=match):
        duhamel.solve(_chain_system(), duhamel.Semianalytic(), **args)


def test_bad_models_loads_and_integrators_are_rejected():
    with pytest.raises(ValueError, match="`modes`"):
        duhamel.solve(_chain_system(), duhamel.Semianalytic(modes=4), t_end=1.0, dt=0.1)
    with pytest.raises(ValueError, match="`modes`"):
        duhamel.Semianalytic(modes=0)
    with pytest.raises(TypeError, match="`integrator`"):
        duhamel.solve(_chain_system(), "newmark", t_end=1.0, dt=0.1)
    with pytest.raises(TypeError, match="`system`"):
        duhamel.solve(np.eye(3), duhamel.Semianalytic(), t_end=1.0, dt=0.1)
    with pytest.raises(ValueError, match="`dof`"):
        _chain_system().add_load(loads.Step(3, amplitude=1.0))
    with pytest.raises(ValueError, match="`dof`"):
        _chain_system().add_load(loads.Harmonic(-1, amplitude=1.0, omega=2.0))
    with pytest.raises(ValueError, match="`t` must be strictly increasing"):
        loads.Tabulated(0, t=[0.0, 1.0, 1.0], values=[0.0, 1.0, 2.0])
    with pytest.raises(ValueError, match="`values`"):
        loads.Tabulated(0, t=[0.0, 1.0], values=[0.0, 1.0, 2.0])
    with pytest.raises(ValueError, match="`amplitude`"):
        loads.Step(0, amplitude=float("inf"))
    with pytest.raises(ValueError, match="`direction_vector`"):
        _chain_system().add_load(
            loads.BaseAcceleration(np.ones(2), t=[0.0, 1.0], values=[0.0, 1.0])
        )
    with pytest.raises(TypeError, match="`fn`"):
        loads.Callable(3.0)


def test_core_rejects_wrong_dtype_and_non_contiguous_input():
    from duhamel import _core

    k = np.ones(4)
    grid = _core.Grid(0.0, 0.1, 5, 1)
    model = _core.ModalModel(k, k, np.eye(4), [])

    # Each typed class refuses a malformed value when made, naming it.
    with pytest.raises(ValueError, match="`x0` must be C-contiguous"):
        _core.RunSpec(grid, np.ones(8)[::2], k)
    with pytest.raises(TypeError, match="`v0`"):
        _core.RunSpec(grid, k, np.ones(4, dtype=np.int32))
    with pytest.raises(ValueError, match=r"`c` has length 3, expected 4"):
        _core.ModalModel(k, np.ones(3), np.eye(4), [])
    with pytest.raises(ValueError, match="`load pattern`"):
        _core.Load(np.ones(4)[::2], _core.TimeFunction.step(0.0))
    with pytest.raises(ValueError, match="a load's pattern must be finite, got NaN at entry 1"):
        _core.Load(np.array([0.0, np.nan]), _core.TimeFunction.step(0.0))
    with pytest.raises(TypeError, match="'loads'"):
        _core.ModalModel(k, k, np.eye(4), [k])
    with pytest.raises(TypeError, match="'route'"):
        _core.ModalModel(k, k, np.eye(4), [], "pseudo-force")
    with pytest.raises(TypeError, match="'grid'"):
        _core.RunSpec(None, k, k)
    # A run checks the values against the model.
    with pytest.raises(ValueError, match="`save_every`"):
        model.run(_core.RunSpec(_core.Grid(0.0, 0.1, 5, 0), k, k))

"""Magnetic bearings first-class (issue 40): a :class:`Rotor` with :class:`MagneticBearing`
among its bearings has modes, Campbell diagram, unbalance and frequency responses and
critical speeds of the closed loop, and its System carries the controllers' states
(:class:`duhamel.feedback.Feedback`), so ``duhamel.solve`` runs transients and run-ups
through a speed law with the controllers and nonlinear elements.

References written out here: the closed loop's state matrix built column by column from its
ODE (modes), its balanced state-space frequency response (unbalance response, receptances),
and ``solve_ivp`` (DOP853, rtol 1e-12) on the ODE with the touchdown contact's documented
law (transients and run-ups, second order in the step).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.integrate
import scipy.linalg

import duhamel
from duhamel.feedback import Feedback
from duhamel.rotor import PID, STEEL, Disk, MagneticBearing, Rotor, Shaft, Unbalance

SPEED = 400.0
PIDS = {0: PID(3e4, 1e5, 30.0, 1e-4), 4: PID(2.5e4, 0.0, 25.0, 2e-4)}
CLEARANCE, K_C, MU = 4e-6, 2e7, 0.1
EPS, VEPS = 1e-3 * CLEARANCE, 1e-3  # the Contact's default smoothing


def rotor() -> Rotor:
    ambs = [MagneticBearing(n, k_i=100.0, k_s=1e6, controller=PIDS[n]) for n in (0, 4)]
    return Rotor(
        [Shaft(0.25, 0.05, material=STEEL)] * 4, [Disk(2, 20.0, 0.3, 0.15)], ambs,
        rayleigh=(0.0, 1e-5),
    )  # fmt: skip


def written_out(r: Rotor, speed, force, contact=None):
    """``s' = rhs(t, s)``: x, v, then per bearing (0, 4) and axis (x, y) the PID's integral
    (when ki != 0) and derivative-filter states; `speed(t)`, `force(t)` on the dofs."""
    M, K, C, G = r.matrices(0.0)
    n = M.shape[0]
    M_inv = np.linalg.inv(M)
    axes = [(r.dof(b.node, a), b) for b in r.magnetic for a in ("x", "y")]

    def rhs(t, s):
        x, v = s[:n], s[n : 2 * n]
        f = force(t) - K @ x - (C + speed(t) * G) @ v
        if contact is not None:
            f -= contact(x, v)
        dz, k = [], 2 * n
        for j, b in axes:
            c, e = b.controller, x[j]
            i = -c.kp * e
            if c.ki:
                i -= c.ki * s[k]
                dz.append(e)
                k += 1
            if c.kd:
                i -= c.kd / c.tau * (e - s[k])
                dz.append((e - s[k]) / c.tau)
                k += 1
            f[j] += b.k_s * e + b.k_i * i
        return np.concatenate([v, M_inv @ f, dz])

    n_states = 2 * n + sum(bool(b.controller.ki) + bool(b.controller.kd) for _, b in axes)
    return rhs, n_states


def state_matrix(rhs, n_states):
    """The linear ODE's matrix, column by column (exact: it is linear)."""
    return np.column_stack([rhs(0.0, e) for e in np.eye(n_states)])


def softplus(z):
    return np.maximum(z, 0.0) + np.log1p(np.exp(-np.abs(z)))


def contact_law(dx, dy, n):
    """duhamel.elements.Contact's documented force (left-hand side)."""

    def force(x, v):
        X, Y, VX, VY = x[dx], x[dy], v[dx], v[dy]
        rho = np.hypot(X, Y)
        out = np.zeros(n)
        if rho == 0.0:
            return out
        fn = K_C * EPS * softplus((rho - CLEARANCE) / EPS)
        vt = (X * VY - Y * VX) / rho
        ft = MU * fn * np.tanh(vt / VEPS)
        out[dx] = fn * X / rho - ft * Y / rho
        out[dy] = fn * Y / rho + ft * X / rho
        return out

    return force


# ------------------------------------------------------------------------------ analyses
def test_modes_are_the_eigenvalues_of_the_written_out_closed_loop():
    r = rotor()
    rhs, n_states = written_out(r, lambda t: SPEED, lambda t: np.zeros(r.n_dof))
    lam = scipy.linalg.eigvals(state_matrix(rhs, n_states))
    modes = r.modes(SPEED)
    ref = lam[lam.imag > 0]
    err = max(float(np.min(np.abs(ref - m)) / abs(m)) for m in modes.eigenvalues)
    assert modes.n_modes >= 16 and err < 1e-8
    # every closed-loop eigenvalue is a mode, or listed as overdamped (the controllers'
    # real poles)
    found = np.concatenate([modes.eigenvalues, modes.eigenvalues.conj(), modes.overdamped])
    assert found.size == lam.size
    assert all(np.min(np.abs(found - v)) <= 1e-8 * max(abs(v), 1.0) for v in lam)
    assert modes.whirl[:2] == ("backward", "forward")


def balanced_response(A, B, ws):
    """``(i w - A)^-1 B`` of the state-space model, balanced first (``T^-1 A T``)."""
    _, (scale, _) = scipy.linalg.matrix_balance(A, permute=False, separate=True)
    Ab = A * scale[None, :] / scale[:, None]
    Bb = B / scale[:, None]
    out = [scale[:, None] * np.linalg.solve(1j * w * np.eye(A.shape[0]) - Ab, Bb) for w in ws]
    return np.array(out)


def test_unbalance_response_equals_the_balanced_state_space_response():
    r = rotor()
    speeds = np.linspace(20.0, 3000.0, 150)
    res = r.unbalance_response(speeds, [(2, 1e-4, 0.3)])
    n = r.n_dof
    ref = np.empty((speeds.size, n), dtype=complex)
    for k, w in enumerate(speeds):
        rhs, n_states = written_out(r, lambda t, w=w: w, lambda t: np.zeros(n))
        A = state_matrix(rhs, n_states)
        F = np.zeros(n, dtype=complex)
        F[r.dof(2, "x")] = 1e-4 * w**2 * np.exp(0.3j)
        F[r.dof(2, "y")] = -1j * F[r.dof(2, "x")]
        B = np.zeros((n_states, 1), dtype=complex)
        B[n : 2 * n, 0] = np.linalg.solve(r.matrices().M, F)
        ref[k] = balanced_response(A, B, [w])[0, :n, 0]
    err = float(np.abs(res.response - ref).max() / np.abs(ref).max())
    print(f"\nunbalance response vs balanced state space: {err:.1e}")
    assert err < 1e-8


def test_receptances_equal_the_closed_loop_and_its_map():
    r = rotor()
    freqs = np.linspace(10.0, 3000.0, 80)
    d = [r.dof(2, "x"), r.dof(0, "y")]
    frf = r.frequency_response(SPEED, freqs, d, d)
    loop = r.closed_loop(SPEED)
    ref = loop.frequency_response(freqs, d, d)
    assert float(np.abs(frf.response - ref).max() / np.abs(ref).max()) < 1e-9
    fmap = r.frequency_response_map([0.0, SPEED], freqs, d, d)
    np.testing.assert_allclose(fmap.response[1], frf.response, rtol=0, atol=1e-14)
    sync = r.frequency_response("synchronous", freqs[:5], d, d).response
    for k, w in enumerate(freqs[:5]):
        one = r.closed_loop(float(w)).frequency_response([w], d, d)[0]
        assert np.abs(sync[k] - one).max() < 1e-9 * np.abs(one).max()


def test_campbell_and_critical_speeds_of_the_closed_loop():
    r = rotor()
    diagram = r.campbell(np.linspace(0.0, 2000.0, 11), n_modes=4)
    assert diagram.frequencies.shape[0] == 11 and np.all(np.isfinite(diagram.frequencies[:, :2]))
    crit = r.critical_speeds(np.linspace(0.0, 3000.0, 31))
    assert crit.size >= 1
    for c in crit.critical:  # a closed-loop mode's frequency equals the speed there
        assert np.min(np.abs(r.modes(c.speed).frequencies - c.speed)) < 1e-9 * c.speed
        assert np.isfinite(c.amplification_factor)
    res = r.closed_loop(SPEED)
    assert res.stability == "stable" and res.stable


# ------------------------------------------------------------------------------ transients
def test_the_system_carries_the_controllers():
    r = rotor()
    system = r.system(SPEED)
    fb = [e for e in system.couplings if isinstance(e, Feedback)]
    assert len(fb) == 1 and fb[0].n_states == 6  # 2 + 1 states per axis, 2 axes, 2 bearings
    with pytest.raises(ValueError, match="Semianalytic"):
        duhamel.solve(system, duhamel.Newmark(), t_end=0.01, dt=1e-4)
    with pytest.raises(ValueError, match="feedback states"):
        duhamel.solve(system, duhamel.Semianalytic(coupling="pseudo-force"), t_end=0.01, dt=1e-4)


def test_a_linear_transient_is_exact():
    """Without elements the closed loop is stepped exactly: the step response equals DOP853
    at any step."""
    r = rotor()
    n, dx = r.n_dof, r.dof(2, "x")
    system = r.system(SPEED)
    system.add_load(duhamel.loads.Step(dx, amplitude=500.0))
    T = 0.02
    sol = duhamel.solve(system, duhamel.Semianalytic(), t_end=T, dt=1e-3)
    f = np.zeros(n)
    f[dx] = 500.0
    rhs, n_states = written_out(r, lambda t: SPEED, lambda t: f)
    ref = scipy.integrate.solve_ivp(rhs, (0.0, T), np.zeros(n_states), "DOP853", t_eval=sol.t,
                                    rtol=1e-12, atol=1e-20).y.T  # fmt: skip
    err = float(np.abs(sol.x - ref[:, :n]).max() / np.abs(ref[:, :n]).max())
    assert err < 1e-8


def converges(system_of, rhs, n_states, n, T, steps):
    errors = []
    for m in steps:
        sol = duhamel.solve(system_of(), duhamel.Semianalytic(), t_end=T, dt=T / m)
        ref = scipy.integrate.solve_ivp(rhs, (0.0, T), np.zeros(n_states), "DOP853",
                                        t_eval=sol.t, rtol=1e-12, atol=1e-20).y.T  # fmt: skip
        errors.append(float(np.abs(sol.x - ref[:, :n]).max() / np.abs(ref[:, :n]).max()))
    return np.array(errors), np.log2(errors[:-1] / np.array(errors[1:]))


def test_touchdown_contact_on_the_controlled_rotor_converges_at_second_order():
    r = rotor()
    n, dx, dy = r.n_dof, r.dof(2, "x"), r.dof(2, "y")
    f = np.zeros(n)
    f[dx] = 300.0

    def system_of():
        s = r.system(SPEED)
        s.add(duhamel.elements.Contact((dx, dy), clearance=CLEARANCE, stiffness=K_C, friction=MU))
        s.add_load(duhamel.loads.Step(dx, amplitude=300.0))
        return s

    rhs, n_states = written_out(r, lambda t: SPEED, lambda t: f, contact_law(dx, dy, n))
    errors, orders = converges(system_of, rhs, n_states, n, 0.01, (1000, 2000, 4000))
    print(f"\ncontroller + touchdown contact vs DOP853: errors {errors}, orders {orders}")
    assert errors[-1] < 1e-4 and np.all(orders > 1.8)


def test_run_up_with_controllers_and_a_touchdown_contact_converges_at_second_order():
    """A run-up 100 -> 1500 rad/s through the speed law: the gyroscopic term follows
    omega(t), the unbalance the law's angle; the contact touches down."""
    r = rotor()
    n, dx, dy = r.n_dof, r.dof(2, "x"), r.dof(2, "y")
    T, m_e = 0.02, 4e-4
    law = duhamel.speed.LinearRunUp(100.0, 1500.0, T)

    def system_of():
        s = r.system(law, [Unbalance(2, m_e=m_e)])
        s.add(duhamel.elements.Contact((dx, dy), clearance=CLEARANCE, stiffness=K_C, friction=MU))
        return s

    a = (1500.0 - 100.0) / T

    def force(t):
        theta, w = 100.0 * t + 0.5 * a * t * t, 100.0 + a * t
        f = np.zeros(n)
        # minus the mass's acceleration: m_e (w^2 (cos, sin) - w' (-sin, cos))
        f[dx] = m_e * (w * w * np.cos(theta) + a * np.sin(theta))
        f[dy] = m_e * (w * w * np.sin(theta) - a * np.cos(theta))
        return f

    rhs, n_states = written_out(r, lambda t: 100.0 + a * t, force, contact_law(dx, dy, n))
    errors, orders = converges(system_of, rhs, n_states, n, T, (2000, 4000, 8000))
    free = duhamel.solve(r.system(law, [Unbalance(2, m_e=m_e)]), duhamel.Semianalytic(),
                         t_end=T, dt=T / 8000)  # fmt: skip
    assert np.hypot(free.x[:, dx], free.x[:, dy]).max() > 2 * CLEARANCE  # it touches down
    print(f"\nrun-up, controllers, touchdown vs DOP853: errors {errors}, orders {orders}")
    assert errors[-1] < 1e-4 and np.all(orders > 1.8)


def test_a_stored_run_with_controllers_resumes_bit_for_bit(tmp_path):
    from duhamel.store import resume

    r = rotor()
    system = r.system(SPEED, [Unbalance(2, m_e=1e-4)])
    system.add(
        duhamel.elements.Contact((r.dof(2, "x"), r.dof(2, "y")), clearance=CLEARANCE, stiffness=K_C)
    )
    kw = {"t_end": 0.01, "dt": 1e-5}
    memory = duhamel.solve(system, duhamel.Semianalytic(), **kw)
    path = tmp_path / "amb.zarr"
    stored = duhamel.solve(system, duhamel.Semianalytic(), store=path, checkpoint_every=300, **kw)
    np.testing.assert_array_equal(np.asarray(stored.x), memory.x)
    np.testing.assert_array_equal(np.asarray(resume(path).x), memory.x)
    # along a speed law the gyroscopic change is a Python element: refused, by name
    law = duhamel.speed.LinearRunUp(100.0, 800.0, 0.05)
    with pytest.raises(ValueError, match="`store`"):
        duhamel.solve(r.system(law), duhamel.Semianalytic(), store=tmp_path / "b.zarr", **kw)


def test_feedback_refuses_bad_input():
    with pytest.raises(ValueError, match="`B`"):
        Feedback(K=np.zeros((2, 2)), A=np.zeros((1, 1)), B=np.zeros((1, 3)), F=np.zeros((2, 1)))
    with pytest.raises(ValueError, match="`F`"):
        Feedback(K=np.zeros((2, 2)), A=np.zeros((1, 1)), B=np.zeros((1, 2)), F=np.zeros((1, 1)))
    with pytest.raises(ValueError, match="no `C`"):
        Feedback(K=np.zeros((2, 2)), C=np.eye(2), A=[[0.0]], B=[[0, 1.0]], F=[[1.0], [0]])
    fb = Feedback(K=np.zeros((2, 2)), A=[[-1.0]], B=[[0.0, 1.0]], F=[[1.0], [0.0]])
    assert repr(fb) == "Feedback(n_dof=2, n_states=1)"
    system = duhamel.System(np.eye(3), np.eye(3))
    with pytest.raises(ValueError, match="`K`"):
        system.add(fb)

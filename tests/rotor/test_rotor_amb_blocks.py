"""Magnetic-bearing controller blocks (sensor, PID, low-pass, notch, amplifier, any state
space, in series): each realization against its transfer function in closed form, the
closed loop with the whole chain against the augmented ODE written out by hand here
(solve_ivp DOP853; eigenvalues of the matrix built column by column from it), the
sensitivity against 1 / (1 + L), a notch that damps a bending mode, and duhamel elements
(a cubic spring, a rub) on top of the closed loop."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.integrate
import scipy.linalg

import duhamel
from duhamel.rotor import (
    PID,
    STEEL,
    Amplifier,
    Disk,
    LowPass,
    MagneticBearing,
    Notch,
    Rotor,
    Sensor,
    Series,
    Shaft,
    StateSpace,
)
from duhamel.rotor.assembly import RotorMatrices
from duhamel.rotor.controllers import realization_response
from duhamel.rotor.magnetic import closed_loop

S = 1j * np.logspace(0, 5, 400)

SENSOR = Sensor(gain=1.0, bandwidth=3e4)
CTRL = PID(3e4, 1e5, 30.0, 1e-4)
LP = LowPass(2.5e4, order=2, damping=0.6)
NOTCH = Notch(1.2e4, zeta=0.08, depth=0.1)
AMP = Amplifier(gain=1.0, bandwidth=4e4)
CHAIN = [SENSOR, CTRL, LP, NOTCH, AMP]


@pytest.mark.parametrize(
    ("block", "closed_form"),
    [
        (PID(3e4, 1e5, 30.0, 1e-4), lambda s: 3e4 + 1e5 / s + 30.0 * s / (1 + 1e-4 * s)),
        (LowPass(800.0), lambda s: 800.0 / (s + 800.0)),
        (LowPass(800.0, order=2, damping=0.3), lambda s: 800.0**2 / (s * s + 480.0 * s + 6.4e5)),
        (
            Notch(500.0, zeta=0.1, depth=0.2),
            lambda s: (s * s + 20.0 * s + 2.5e5) / (s * s + 100.0 * s + 2.5e5),
        ),
        (Sensor(gain=8e3, bandwidth=2e4), lambda s: 8e3 * 2e4 / (s + 2e4)),
        (Sensor(gain=8e3), lambda s: 8e3 + 0 * s),
        (Amplifier(gain=0.5, bandwidth=6e3), lambda s: 0.5 * 6e3 / (s + 6e3)),
        (StateSpace([[-50.0]], [50.0], [2.0], 0.5), lambda s: 2.0 * 50.0 / (s + 50.0) + 0.5),
    ],
)
def test_each_block_realization_equals_its_transfer_function(block, closed_form):
    ref = closed_form(S)
    np.testing.assert_allclose(block(S), ref, rtol=1e-12, atol=0)
    np.testing.assert_allclose(realization_response(block, S), ref, rtol=1e-12, atol=0)


def test_series_is_the_product_in_either_form():
    chain = Series(*CHAIN)
    ref = SENSOR(S) * CTRL(S) * LP(S) * NOTCH(S) * AMP(S)
    assert chain.n_states == 1 + 2 + 2 + 2 + 1
    np.testing.assert_allclose(chain(S), ref, rtol=1e-12, atol=0)
    err = np.abs(realization_response(chain, S) / ref - 1).max()
    print(f"\nseries realization vs the product of closed forms: {err:.1e}")
    assert err < 1e-12
    assert (SENSOR * CTRL * LP).n_states == 5


def model():
    rotor = Rotor(
        [Shaft(0.25, 0.05, material=STEEL)] * 4,
        [Disk(2, 20.0, 0.3, 0.15)],
        rayleigh=(0.0, 1e-5),
    )
    ambs = [MagneticBearing(n, k_i=100.0, k_s=1e6, controller=CHAIN) for n in (0, 4)]
    return rotor, ambs


def written_out(rotor, ambs, speed, extra_force=None):
    """Each axis's chain by hand: sensor y' = wb (x - y); PID on y (integral z, filter z_d);
    low-pass u'' + 2 d w u' + w^2 u = w^2 p; notch q'' + 2 zeta w q' + w^2 q = u,
    out = u + 2 zeta w (depth - 1) q'; amplifier i' = wa (g out - i); force k_s x - k_i i."""
    M, K, C, G = rotor.matrices(speed)
    n = M.shape[0]
    D = C + speed * G
    M_inv = np.linalg.inv(M)
    per_axis = 8

    def rhs(s, f_ext):
        x, v = s[:n], s[n : 2 * n]
        force = f_ext - K @ x - D @ v
        if extra_force is not None:
            force += extra_force(x, v)
        dz = []
        k = 2 * n
        for b in ambs:
            for axis in ("x", "y"):
                j = rotor.dof(b.node, axis)
                ys, zi, zd, u, du, q, dq, i = s[k : k + per_axis]
                dys = SENSOR.bandwidth * (SENSOR.gain * x[j] - ys)
                p = CTRL.kp * ys + CTRL.ki * zi + CTRL.kd / CTRL.tau * (ys - zd)
                w, d = LP.cutoff, LP.damping
                ddu = w * w * p - 2 * d * w * du - w * w * u
                wn, z = NOTCH.frequency, NOTCH.zeta
                ddq = u - 2 * z * wn * dq - wn * wn * q
                out = u + 2 * z * wn * (NOTCH.depth - 1.0) * dq
                di = AMP.bandwidth * (AMP.gain * out - i)
                dz += [dys, ys, (ys - zd) / CTRL.tau, du, ddu, dq, ddq, di]
                force[j] += b.k_s * x[j] - b.k_i * i
                k += per_axis
        return np.concatenate([v, M_inv @ force, dz])

    return rhs, 2 * n + per_axis * 2 * len(ambs)


SPEED = 400.0


def test_chain_transient_equals_dop853_on_the_written_out_ode():
    rotor, ambs = model()
    loop = rotor.closed_loop(SPEED, ambs)
    rhs, n_states = written_out(rotor, ambs, SPEED)
    assert loop.A.shape == (n_states, n_states)
    dx = rotor.dof(2, "x")
    x0 = np.zeros(rotor.n_dof)
    x0[dx] = 2e-5
    t = np.linspace(0.0, 0.02, 201)
    states = loop.transient(t, np.full((t.size, 1), 40.0), [dx], x0=x0)
    f_ext = np.zeros(rotor.n_dof)
    f_ext[dx] = 40.0
    s0 = np.zeros(n_states)
    s0[: rotor.n_dof] = x0
    sol = scipy.integrate.solve_ivp(
        lambda tt, s: rhs(s, f_ext), (0.0, t[-1]), s0, "DOP853", t_eval=t, rtol=1e-12, atol=1e-20
    )
    n = rotor.n_dof
    err = float(np.abs(states[:, :n] - sol.y.T[:, :n]).max() / np.abs(sol.y.T[:, :n]).max())
    print(f"\nclosed loop with sensor, PID, low-pass, notch, amplifier vs DOP853: {err:.1e}")
    assert err < 1e-8


def test_chain_eigenvalues_equal_the_hand_built_matrix():
    rotor, ambs = model()
    loop = rotor.closed_loop(SPEED, ambs)
    rhs, n_states = written_out(rotor, ambs, SPEED)
    zero = np.zeros(rotor.n_dof)
    A = np.column_stack([rhs(e, zero) for e in np.eye(n_states)])
    ref = scipy.linalg.eigvals(A)
    ours = loop.eigenvalues
    gap = max(float(np.min(np.abs(ref - lam))) / abs(lam) for lam in ours)
    print(f"\nchain eigenvalues vs the hand-built augmented matrix: {gap:.1e}")
    assert gap < 1e-9 and ours.size == ref.size
    assert loop.stable


def test_sensitivity_with_the_chain_equals_one_over_one_plus_loop_gain():
    m, k_s, k_i = 5.0, 4e5, 60.0
    mats = RotorMatrices(np.diag([m, m, 0.1, 0.1]), np.diag([0.0, 0.0, 1e4, 1e4]),
                         np.diag([0.0, 0.0, 1.0, 1.0]), np.zeros((4, 4)))  # fmt: skip
    chain = [Sensor(bandwidth=2e4), PID(2e4, 5e4, 15.0, 1e-4), LowPass(1.5e4, order=2)]
    amb = MagneticBearing(0, k_i=k_i, k_s=k_s, controller=chain)
    loop = closed_loop(mats, [amb], 0.0, dof=lambda node, d: {"x": 0, "y": 1}[d])
    ws = np.linspace(1.0, 8000.0, 4000)
    s = 1j * ws
    ref = 1.0 / (1.0 + k_i * amb.controller(s) / (m * s**2 - k_s))
    Sx = loop.sensitivity(ws)
    np.testing.assert_allclose(Sx[:, 0], ref, rtol=1e-10, atol=0)
    peak, w_peak, _ = loop.peak_sensitivity(ws)
    print(f"\npeak sensitivity with sensor and low-pass: {peak:.3f} at {w_peak:.0f} rad/s")
    assert peak == pytest.approx(np.abs(ref).max(), rel=1e-10)
    assert loop.stable


def bending_case(notch=None):
    """A low-pass at 4e4 rad/s leaves the first bending mode (about 19500 rad/s) with
    0.13 % damping; a notch 5 % below it (phase lead at the mode) damps it."""
    rotor = Rotor([Shaft(0.25, 0.05, material=STEEL)] * 4, [Disk(2, 20.0, 0.3, 0.15)],
                  rayleigh=(0.0, 1e-6))  # fmt: skip
    chain = [PID(3e4, 1e5, 30.0, 1e-4), LowPass(4e4, order=2)] + ([notch] if notch else [])
    return rotor, rotor.closed_loop(0.0, [MagneticBearing(n, 100.0, 1e6, chain) for n in (0, 4)])


def _band(loop, lo=1.5e4, hi=2.5e4):
    lam = loop.eigenvalues
    lam = lam[(lam.imag > lo) & (lam.imag < hi)]
    return lam, -lam.real / np.abs(lam)


def test_a_notch_tuned_to_a_bending_mode_lowers_its_response():
    rotor, plain = bending_case()
    lam, zeta = _band(plain)
    w_mode = float(np.abs(lam[0]))
    rotor, notched = bending_case(Notch(0.95 * w_mode, zeta=0.05))
    assert plain.stable and notched.stable
    _, zeta_n = _band(notched)
    ws = np.linspace(0.9 * w_mode, 1.1 * w_mode, 2001)
    d = rotor.dof(0, "x")
    peak = [float(np.abs(lp.frequency_response(ws, [d], [d])[:, 0, 0]).max())
            for lp in (plain, notched)]  # fmt: skip
    print(f"\nbending mode {w_mode:.0f} rad/s: damping {zeta.min():.4f} -> {zeta_n.min():.4f}, "
          f"peak receptance at the bearing x{peak[1] / peak[0]:.3f}")  # fmt: skip
    assert zeta.min() < 0.002 and zeta_n.min() > 5 * zeta.min()
    assert peak[1] < 0.5 * peak[0]


def test_elements_on_top_of_the_closed_loop_converge_to_dop853():
    """A cubic spring at the disk (a hardening bearing) on the loop with the whole chain:
    the core's first-order route on the closed-loop modes, second order in the step."""
    rotor, ambs = model()
    loop = rotor.closed_loop(SPEED, ambs)
    dx, dy = rotor.dof(2, "x"), rotor.dof(2, "y")
    k3 = 4e15
    spring = duhamel.elements.Spring(dx, None, k=0.0, k3=k3)

    def cubic(x, v):
        f = np.zeros(rotor.n_dof)
        f[dx] = -k3 * x[dx] ** 3
        return f

    rhs, n_states = written_out(rotor, ambs, SPEED, cubic)
    x0 = np.zeros(rotor.n_dof)
    x0[dx] = 5e-5
    T = 0.01
    f_ext = np.zeros(rotor.n_dof)
    f_ext[dy] = 100.0
    s0 = np.zeros(n_states)
    s0[: rotor.n_dof] = x0
    errors = []
    n = rotor.n_dof
    for steps in (500, 1000, 2000):
        t = np.linspace(0.0, T, steps + 1)
        ours = loop.transient(t, np.full((t.size, 1), 100.0), [dy], x0=x0, elements=[spring])
        ref = scipy.integrate.solve_ivp(lambda tt, s: rhs(s, f_ext), (0.0, T), s0, "DOP853",
                                        t_eval=t, rtol=1e-12, atol=1e-20).y.T  # fmt: skip
        errors.append(float(np.abs(ours[:, :n] - ref[:, :n]).max() / np.abs(ref[:, :n]).max()))
    linear = loop.transient(t, np.full((t.size, 1), 100.0), [dy], x0=x0)
    effect = float(np.abs(linear[:, :n] - ref[:, :n]).max() / np.abs(ref[:, :n]).max())
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    print(
        f"\nclosed loop + cubic spring vs DOP853: errors {errors}, orders {orders}, "
        f"the spring's effect {effect:.2e}"
    )
    assert effect > 1e-2  # the element matters
    assert errors[-1] < 1e-5 and np.all(orders > 1.8)


def test_a_rub_on_top_of_the_closed_loop_holds_the_rotor_at_the_stator():
    rotor, ambs = model()
    loop = rotor.closed_loop(SPEED, ambs)
    dx, dy = rotor.dof(2, "x"), rotor.dof(2, "y")
    clearance, k_c = 1e-5, 1e8
    rub = duhamel.elements.Contact((dx, dy), clearance=clearance, stiffness=k_c, friction=0.1)
    # dt = 1e-5: the coarse run (2e-5) stays below the coupled route's stiffness limit,
    # omega_c dt = 0.5 for the closed contact (k_c on the rotor at the rub: 0.26 at 2e-5)
    t = np.linspace(0.0, 0.03, 3001)
    f = np.full((t.size, 1), 2e3)
    s = loop.transient(t, f, [dx], elements=[rub])
    free = loop.transient(t, f, [dx])
    x_end, free_end = s[-1, dx], free[-1, dx]
    # at rest against the stator the contact carries what the loop does not: k_c (x - g)
    # plus the loop's static stiffness (k_i kp - k_s + the shaft) times x equals 2 kN
    assert free_end > 1e-4 and clearance < x_end < clearance + 2e3 / k_c
    coarse = loop.transient(t[::2], f[::2], [dx], elements=[rub])
    assert abs(coarse[-1, dx] - x_end) < 1e-3 * x_end


def test_blocks_refuse_bad_input():
    with pytest.raises(ValueError, match="order"):
        LowPass(100.0, order=3)
    with pytest.raises(ValueError, match="cutoff"):
        LowPass(-1.0)
    with pytest.raises(ValueError, match="zeta"):
        Notch(100.0, zeta=0.0)
    with pytest.raises(ValueError, match="bandwidth"):
        Sensor(bandwidth=0.0)
    with pytest.raises(ValueError, match="`B`"):
        StateSpace(np.eye(2), [1.0], [1.0, 0.0])
    with pytest.raises(TypeError, match="controller"):
        MagneticBearing(0, 1.0, 1e5, controller=[PID(1e4), "lowpass"])
    with pytest.raises(TypeError, match="block"):
        Series(PID(1e4), 3.0)
    rotor, ambs = model()
    loop = rotor.closed_loop(SPEED, ambs)
    t = np.linspace(0.0, 1e-3, 11)
    with pytest.raises(TypeError, match="elements"):
        loop.transient(t, elements=["rub"])


def test_an_unstable_loop_has_no_frequency_response():
    """A low-pass at 2e4 rad/s destabilises the first bending mode (spillover): the modes
    show it, and the sensitivity and receptances, no steady state then, are refused."""
    rotor, loop = bending_case()
    assert loop.stable
    chain = [PID(3e4, 1e5, 30.0, 1e-4), LowPass(2e4, order=2)]
    unstable = rotor.closed_loop(0.0, [MagneticBearing(n, 100.0, 1e6, chain) for n in (0, 4)])
    assert not unstable.stable and np.max(unstable.eigenvalues.real) > 0.0
    ws = np.linspace(1.0, 3e4, 100)
    with pytest.raises(ValueError, match="unstable"):
        unstable.sensitivity(ws)
    with pytest.raises(ValueError, match="unstable"):
        unstable.peak_sensitivity(ws)
    with pytest.raises(ValueError, match="unstable"):
        unstable.frequency_response(ws, [0], [0])


def test_a_failing_element_step_stops_with_the_history_kept():
    """A stiff rub with too few Newton iterations: SolverError at its step, the states up to
    it in `partial` (no silent result)."""
    rotor, ambs = model()
    loop = rotor.closed_loop(SPEED, ambs)
    dx, dy = rotor.dof(2, "x"), rotor.dof(2, "y")
    rub = duhamel.elements.Contact((dx, dy), clearance=1e-6, stiffness=1e12)
    t = np.linspace(0.0, 0.02, 101)
    with pytest.raises(duhamel.SolverError, match="did not converge") as info:
        loop.transient(t, np.full((t.size, 1), 2e4), [dx], elements=[rub], max_iter=2)
    assert info.value.partial.shape[1] == loop.A.shape[0]

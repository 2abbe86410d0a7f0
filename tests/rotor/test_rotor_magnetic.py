"""Active magnetic bearings: the closed loop against the augmented ODE written out here
(solve_ivp DOP853 at tight tolerance; its matrix built column by column from that ODE), the
sensitivity function against 1 / (1 + L) in closed form, and an unstable tuning."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.integrate
import scipy.linalg

from duhamel.rotor import STEEL, Bearing, Disk, Rotor, Shaft
from duhamel.rotor.assembly import RotorMatrices
from duhamel.rotor.magnetic import PID, MagneticBearing, closed_loop

SPEED = 400.0
PIDS = {0: PID(3e4, 1e5, 30.0, 1e-4), 4: PID(2.5e4, 0.0, 25.0, 2e-4)}  # no integrator at 4


def model():
    rotor = Rotor(
        [Shaft(0.25, 0.05, material=STEEL)] * 4,
        [Disk(2, 20.0, 0.3, 0.15)],
        [Bearing(2, 0.0, 0.0, kxy=1e4, kyx=-1e4, cxx=50.0, cyy=50.0)],  # a seal at the disk
        rayleigh=(0.0, 1e-5),
    )
    ambs = [MagneticBearing(n, k_i=100.0, k_s=1e6, controller=PIDS[n]) for n in (0, 4)]
    return rotor, ambs


def written_out(rotor, ambs, speed):
    """The closed loop's right-hand side, state (x, v, then per bearing, per axis x, y: the
    integral of x when ki != 0, the derivative filter state)."""
    M, K, C, G = rotor.matrices(speed)
    n = M.shape[0]
    D = C + speed * G
    M_inv = np.linalg.inv(M)

    def rhs(s, f_ext):
        x, v = s[:n], s[n : 2 * n]
        force = f_ext - K @ x - D @ v
        dz = []
        k = 2 * n
        for b in ambs:
            c = b.controller
            for axis in ("x", "y"):
                j = rotor.dof(b.node, axis)
                e = x[j]
                i = -c.kp * e
                if c.ki:
                    i -= c.ki * s[k]
                    dz.append(e)
                    k += 1
                if c.kd:
                    i -= c.kd / c.tau * (e - s[k])
                    dz.append((e - s[k]) / c.tau)
                    k += 1
                force[j] += b.k_s * x[j] + b.k_i * i
        return np.concatenate([v, M_inv @ force, dz])

    n_states = 2 * n + sum(2 * (bool(b.controller.ki) + bool(b.controller.kd)) for b in ambs)
    return rhs, n_states


def test_transient_equals_dop853_on_the_written_out_ode():
    rotor, ambs = model()
    loop = rotor.closed_loop(SPEED, ambs)
    rhs, n_states = written_out(rotor, ambs, SPEED)
    assert loop.A.shape == (n_states, n_states)
    dx, dy = rotor.dof(2, "x"), rotor.dof(2, "y")
    x0 = np.zeros(rotor.n_dof)
    x0[dx] = 2e-5  # a displaced disk, released
    t = np.linspace(0.0, 0.025, 251)
    t_ramp = 0.01  # on the grid: the forces are linear between samples, FOH is exact
    ramp = np.minimum(t / t_ramp, 1.0)
    forces = np.column_stack([30.0 * ramp, -50.0 * ramp])
    states = loop.transient(t, forces, [dx, dy], x0=x0)

    def f_ext(time):
        f = np.zeros(rotor.n_dof)
        r = min(time / t_ramp, 1.0)
        f[dx], f[dy] = 30.0 * r, -50.0 * r
        return f

    s0 = np.zeros(n_states)
    s0[: rotor.n_dof] = x0
    ref = []
    for a, b in ((0.0, t_ramp), (t_ramp, t[-1])):  # split at the ramp's kink
        keep = t[(t >= a) & (t <= b)]
        sol = scipy.integrate.solve_ivp(
            lambda tt, s: rhs(s, f_ext(tt)),
            (a, b),
            s0,
            "DOP853",
            t_eval=keep,
            rtol=1e-12,
            atol=1e-18,
        )
        ref.append(sol.y.T if a == 0.0 else sol.y.T[1:])
        s0 = sol.y[:, -1]
    ref = np.vstack(ref)
    x_ours, x_ref = states[:, : rotor.n_dof], ref[:, : rotor.n_dof]
    err = float(np.abs(x_ours - x_ref).max() / np.abs(x_ref).max())
    print(f"\nclosed-loop transient vs DOP853: {err:.1e}")
    assert err < 1e-8
    assert loop.stable


def test_eigenvalues_equal_the_augmented_matrix_of_the_written_out_ode():
    rotor, ambs = model()
    loop = rotor.closed_loop(SPEED, ambs)
    rhs, n_states = written_out(rotor, ambs, SPEED)
    zero = np.zeros(rotor.n_dof)
    A = np.column_stack([rhs(e, zero) for e in np.eye(n_states)])  # the ODE is linear
    ref = scipy.linalg.eigvals(A)
    ours = loop.eigenvalues
    gap = max(float(np.min(np.abs(ref - lam))) / abs(lam) for lam in ours)
    print(f"\nclosed-loop eigenvalues vs the written-out matrix: {gap:.1e}")
    assert gap < 1e-9 and ours.size == ref.size
    assert np.all(ref.real < 0.0)


TUNED = PID(2e4, 5e4, 15.0, 1e-4)


def point_mass(m=5.0, controller=TUNED, k_s=4e5, k_i=60.0):
    """A point mass in x, y (tilts held by damped springs): one magnetic bearing, SISO per
    axis."""
    mats = RotorMatrices(np.diag([m, m, 0.1, 0.1]), np.diag([0.0, 0.0, 1e4, 1e4]),
                         np.diag([0.0, 0.0, 1.0, 1.0]), np.zeros((4, 4)))  # fmt: skip
    amb = MagneticBearing(0, k_i=k_i, k_s=k_s, controller=controller)
    return closed_loop(mats, [amb], 0.0, dof=lambda node, d: {"x": 0, "y": 1}[d]), amb, m


def test_sensitivity_equals_one_over_one_plus_loop_gain():
    loop, amb, m = point_mass()
    ws = np.linspace(1.0, 5000.0, 4000)
    S = loop.sensitivity(ws)
    s = 1j * ws
    L = amb.k_i * amb.controller(s) / (m * s**2 - amb.k_s)
    ref = 1.0 / (1.0 + L)
    assert S.shape == (ws.size, 2)
    np.testing.assert_allclose(S[:, 0], ref, rtol=1e-10, atol=0)
    np.testing.assert_allclose(S[:, 1], ref, rtol=1e-10, atol=0)
    peak, w_peak, axis = loop.peak_sensitivity(ws)
    print(f"\npeak sensitivity {peak:.3f} ({20 * np.log10(peak):.1f} dB) at {w_peak:.0f} rad/s")
    assert peak == pytest.approx(np.abs(ref).max(), rel=1e-10) and axis in (0, 1)
    # the closed-loop receptance of the mass: 1 / (m s^2 - k_s + k_i C(s))
    H = loop.frequency_response(ws, [0], [0])[:, 0, 0]
    np.testing.assert_allclose(H, 1.0 / (m * s**2 - amb.k_s + amb.k_i * amb.controller(s)),
                               rtol=1e-10)  # fmt: skip


def test_unstable_tuning_is_detected_from_the_modes():
    """P control with k_i kp below k_s cannot hold the mass: a real eigenvalue
    sqrt((k_s - k_i kp) / m) > 0 (and the rotor's transient refuses to run on)."""
    loop, amb, m = point_mass(controller=PID(5e3), k_s=4e5, k_i=60.0)
    assert not loop.stable
    grow = np.sqrt((amb.k_s - amb.k_i * 5e3) / m)
    assert np.max(loop.eigenvalues.real) == pytest.approx(grow, rel=1e-12)
    stable, _, _ = point_mass()
    assert stable.stable
    rotor, ambs = model()
    weak = [MagneticBearing(b.node, b.k_i, b.k_s, PID(1e3, 0.0, 30.0, 1e-4)) for b in ambs]
    assert not rotor.closed_loop(SPEED, weak).stable


def test_refuses_bad_input():
    with pytest.raises(ValueError, match="tau"):
        PID(1e4, 0.0, 10.0)
    with pytest.raises(ValueError, match="k_i"):
        MagneticBearing(0, k_i=0.0, k_s=1e5, controller=PID(1e4))
    with pytest.raises(TypeError, match="controller"):
        MagneticBearing(0, k_i=1.0, k_s=1e5, controller=(1e4, 0, 0))
    rotor, ambs = model()
    with pytest.raises(TypeError, match="MagneticBearing"):
        rotor.closed_loop(SPEED, [Bearing(0, 1e6, 1e6)])
    loop = rotor.closed_loop(SPEED, ambs)
    with pytest.raises(ValueError, match="equally spaced"):
        loop.transient([0.0, 0.1, 0.3])

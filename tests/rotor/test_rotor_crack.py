"""The breathing crack (duhamel.rotor.BreathingCrack): its stiffness in the open and closed
states in the rotating frame, the force harmonics of the cosine model against their closed
form, and a cracked Jeffcott rotor against solve_ivp with the order of convergence."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import duhamel
from duhamel.rotor import BreathingCrack
from duhamel.speed import ConstantSpeed, LinearRunUp

K0, DK_XI, DK_ETA = 1e4, 1.5e3, 4e2


def rotation(phi: float) -> np.ndarray:
    return np.array([[np.cos(phi), -np.sin(phi)], [np.sin(phi), np.cos(phi)]])


@pytest.mark.parametrize("breathing", ["switching", "cosine"])
def test_open_and_closed_stiffness_in_the_rotating_frame(breathing) -> None:
    law = LinearRunUp(omega0=10.0, omega1=80.0, t1=1.0)
    crack = BreathingCrack(0, 1, DK_XI, DK_ETA, breathing=breathing, speed=law, phase=0.3)
    for t in (0.0, 0.37, 0.81, 1.4):
        phi = float(law.theta(np.array([t]))[0]) + 0.3
        R = rotation(phi)
        xi_axis = R[:, 0]
        # open: a displacement along +xi (switching); phi itself (cosine: f = (1 + cos phi)/2)
        r, K, C = crack.evaluate(1e-3 * xi_axis, t=t)
        f = 1.0 if breathing == "switching" else 0.5 * (1 + np.cos(phi))
        total = R.T @ (K0 * np.eye(2) + K) @ R  # the shaft's stiffness seen by the rotor
        np.testing.assert_allclose(
            total, np.diag([K0 - f * DK_XI, K0 - f * DK_ETA]), rtol=0, atol=1e-12 * K0
        )
        np.testing.assert_allclose(r, K @ (1e-3 * xi_axis), rtol=0, atol=1e-15 * K0)
        assert np.all(C == 0.0)
        if breathing == "switching":  # closed under compression: the whole shaft
            r, K, _ = crack.evaluate(-1e-3 * xi_axis, t=t)
            assert np.all(K == 0.0) and np.all(r == 0.0)
    # the cosine crack closes fully at phi = pi
    closed = BreathingCrack(0, 1, DK_XI, DK_ETA, breathing="cosine", speed=0.0, phase=np.pi)
    assert np.abs(closed.evaluate([1e-3, 2e-3])[1]).max() <= 1e-12 * DK_XI


def test_cosine_crack_force_harmonics_are_the_closed_form() -> None:
    """Under a fixed sag ``(0, -d)`` the Mayes-Davies crack's force has 0x..3x harmonics:
    ``r_x = d (a - b) [sin 1x / 8 + sin 2x / 4 + sin 3x / 8]``, ``r_y = d [(a + b)/4 +
    ((a + b)/4 - (a - b)/8) cos 1x - (a - b)/4 cos 2x - (a - b)/8 cos 3x]``."""
    omega, d, a, b, n = 50.0, 2e-4, DK_XI, DK_ETA, 64
    crack = BreathingCrack(0, 1, a, b, breathing="cosine", speed=ConstantSpeed(omega))
    t = 2 * np.pi / omega * np.arange(n) / n
    r = np.array([crack.evaluate([0.0, -d], t=ti)[0] for ti in t])
    spec = np.fft.rfft(r, axis=0) / n  # r = sum c_h e^{i h phi} + conj: cos -> 2 Re, sin -> -2 Im
    expected_x = {1: d * (a - b) / 8, 2: d * (a - b) / 4, 3: d * (a - b) / 8}
    expected_y = {1: d * ((a + b) / 4 - (a - b) / 8), 2: -d * (a - b) / 4, 3: -d * (a - b) / 8}
    assert spec[0, 1].real == pytest.approx(d * (a + b) / 4, rel=1e-12)
    for h in range(1, 8):
        sin_x, cos_y = -2 * spec[h, 0].imag, 2 * spec[h, 1].real
        assert sin_x == pytest.approx(expected_x.get(h, 0.0), abs=1e-12 * d * a)
        assert cos_y == pytest.approx(expected_y.get(h, 0.0), abs=1e-12 * d * a)
        assert abs(spec[h, 0].real) + abs(spec[h, 1].imag) <= 1e-12 * d * a


def _jeffcott(crack: BreathingCrack) -> duhamel.System:
    s = duhamel.System(np.eye(2), K0 * np.eye(2), 2.0 * np.eye(2))
    s.add(crack)
    s.add_load(duhamel.loads.Step(dof=1, amplitude=-9.81))
    return s


def _reference(law, breathing: str, t_end: float, t_eval) -> np.ndarray:
    def rhs(t, z):
        x, v = z[:2], z[2:]
        phi = float(law.theta(np.array([t]))[0])
        R = rotation(phi)
        xi = R[:, 0] @ x
        f = 0.5 * (1 + np.cos(phi)) if breathing == "cosine" else float(xi > 0)
        K = K0 * np.eye(2) - f * R @ np.diag([DK_XI, DK_ETA]) @ R.T
        return np.concatenate([v, np.array([0.0, -9.81]) - K @ x - 2.0 * v])

    sol = solve_ivp(rhs, (0, t_end), np.zeros(4), method="DOP853", rtol=1e-12, atol=1e-16,
                    t_eval=t_eval)  # fmt: skip
    return sol.y[:2].T


def test_cracked_jeffcott_converges_to_solve_ivp() -> None:
    law = LinearRunUp(omega0=20.0, omega1=60.0, t1=0.3)
    crack = BreathingCrack(0, 1, DK_XI, DK_ETA, breathing="cosine", speed=law)
    t_end = 0.4
    errors = []
    for dt in (4e-3, 2e-3, 1e-3):
        res = duhamel.solve(_jeffcott(crack), duhamel.Semianalytic(), t_end=t_end, dt=dt)
        ref = _reference(law, "cosine", t_end, np.asarray(res.t))
        errors.append(np.abs(np.asarray(res.x) - ref).max() / np.abs(ref).max())
    slopes = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    print("cosine crack errors", errors, "slopes", slopes)
    # second order (the pseudo-force route), measured slopes ~2.0
    assert errors[-1] < 5e-4
    assert np.all((slopes > 1.9) & (slopes < 2.1))


def test_switching_crack_follows_solve_ivp() -> None:
    """The switching crack under gravity opens and closes once a turn (weight dominance):
    the run agrees with solve_ivp (adaptive steps, rtol 1e-12, which shrink at the switches)
    and improves as the step shrinks (more slowly than the cosine crack: the force has a
    kink, and with dk_eta > 0 a jump, where the crack switches inside a step)."""
    law = ConstantSpeed(35.0)
    crack = BreathingCrack(0, 1, DK_XI, DK_ETA, breathing="switching", speed=law)
    errors = []
    for dt in (2e-3, 1e-3, 5e-4):
        res = duhamel.solve(_jeffcott(crack), duhamel.Semianalytic(), t_end=0.4, dt=dt)
        ref = _reference(law, "switching", 0.4, np.asarray(res.t))
        errors.append(np.abs(np.asarray(res.x) - ref).max() / np.abs(ref).max())
    print("switching crack errors", errors)
    assert errors[-1] < 1e-3
    assert errors[0] > errors[1] > errors[2]


def test_bad_input_is_named() -> None:
    with pytest.raises(ValueError, match="dk_xi"):
        BreathingCrack(0, 1, -1.0)
    with pytest.raises(ValueError, match="breathing"):
        BreathingCrack(0, 1, 1.0, breathing="open")
    with pytest.raises(ValueError, match="phase"):
        BreathingCrack(0, 1, 1.0, phase=float("nan"))
    s = duhamel.System(np.eye(2), np.eye(2))
    with pytest.raises(ValueError, match="dof_y"):
        s.add(BreathingCrack(0, 0, 1.0))

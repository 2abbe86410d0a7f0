"""Issue 15, the short journal bearing: Ocvirk's static forces and the closed-form
linearised coefficients at the static equilibrium found by the library (finite differences
of the element force, to 1e-6), the attitude angle, and clear errors."""

from __future__ import annotations

import numpy as np
import pytest

import duhamel
from duhamel.constants import STANDARD_GRAVITY
from duhamel.rotor import Disk, Gravity, Rotor, ShortJournalBearing
from duhamel.rotor.journal import JournalElement, ocvirk_coefficients

D, L, C, MU = 0.05, 0.02, 5e-5, 0.015


def rotor_on_one_journal(mass: float) -> Rotor:
    """A rigid disk carried by one journal (a single node: no shaft)."""
    return Rotor([], [Disk(0, mass, 0.1, 0.05)], [ShortJournalBearing(0, D, L, C, MU)])


def rotation(phi: float) -> np.ndarray:
    return np.array([[np.cos(phi), -np.sin(phi)], [np.sin(phi), np.cos(phi)]])


@pytest.mark.parametrize(("mass", "speed"), [(5.0, 300.0), (20.0, 400.0), (40.0, 150.0)])
def test_linearisation_at_equilibrium_is_the_closed_form(mass, speed) -> None:
    rotor = rotor_on_one_journal(mass)
    x = rotor.static_equilibrium(speed)
    p = x[:2]
    eps, phi = np.hypot(*p) / C, np.arctan2(p[1], p[0])
    element = JournalElement(0, 1, D / 2, L, C, MU, speed)
    r, K, Cm = element.evaluate(p)
    # the film carries the weight ...
    np.testing.assert_allclose(
        r, [0.0, -mass * STANDARD_GRAVITY], atol=1e-9 * mass * STANDARD_GRAVITY
    )
    # ... at Ocvirk's eccentricity and attitude angle (tan = pi sqrt(1 - e^2) / (4 e))
    k = MU * speed * (D / 2) * L**3 / C**2
    W = k * eps / (1 - eps**2) ** 2 * np.sqrt(eps**2 + np.pi**2 * (1 - eps**2) / 16)
    assert W == pytest.approx(mass * STANDARD_GRAVITY, rel=1e-10)
    attitude = np.arctan2(np.pi * np.sqrt(1 - eps**2), 4 * eps)
    load_line = -np.pi / 2  # the journal sits below, rotated with the spin
    assert phi - load_line == pytest.approx(attitude, abs=1e-10)
    # closed-form coefficients, rotated from the line of centres to (x, y)
    r0, K0, C0 = ocvirk_coefficients(eps, speed, D / 2, L, C, MU)
    R = rotation(phi)
    K_ref, C_ref = R @ K0 @ R.T, R @ C0 @ R.T
    np.testing.assert_allclose(R @ r0, r, rtol=1e-12, atol=1e-12 * np.abs(r).max())
    # finite differences of the element force (central, steps 1e-6 of the clearance and of
    # the whirl velocity scale)
    fd_k, fd_c = np.zeros((2, 2)), np.zeros((2, 2))
    h, hv = 1e-6 * C, 1e-6 * C * speed
    for j in range(2):
        e = np.eye(2)[j]
        fd_k[:, j] = (element.evaluate(p + h * e)[0] - element.evaluate(p - h * e)[0]) / (2 * h)
        fd_c[:, j] = (element.evaluate(p, hv * e)[0] - element.evaluate(p, -hv * e)[0]) / (2 * hv)
    for fd, exact, ref in ((fd_k, K, K_ref), (fd_c, Cm, C_ref)):
        scale = np.abs(ref).max()
        assert np.abs(fd - ref).max() <= 1e-6 * scale
        assert np.abs(exact - ref).max() <= 1e-10 * scale
    # the rotor's linear analyses use that linearisation
    _, Kr, Cr, _ = rotor.matrices(speed)
    np.testing.assert_allclose(Kr[:2, :2], K, rtol=1e-12)
    np.testing.assert_allclose(Cr[:2, :2], Cm, rtol=1e-12)


def test_transient_rests_at_the_equilibrium_and_errors_are_clear() -> None:
    rotor = rotor_on_one_journal(20.0)
    x0 = rotor.static_equilibrium(400.0)
    system = rotor.system(400.0, [Gravity()])
    for integrator in (duhamel.Semianalytic(), duhamel.Newmark()):
        sol = duhamel.solve(system, integrator, t_end=0.05, dt=1e-4, x0=x0)
        assert np.abs(sol.x - x0).max() <= 1e-9 * C
    with pytest.raises(ValueError, match="no static load at speed 0"):
        rotor.static_equilibrium(0.0)
    with pytest.raises(ValueError, match="`clearance`"):
        ShortJournalBearing(0, D, L, -1.0, MU)
    # knocked into the wall: the run stops, saying where and why, and keeps what it computed
    kick = np.r_[x0[:2], 0.0, 0.0]
    with pytest.raises(duhamel.SolverError) as err:
        duhamel.solve(system, duhamel.Semianalytic(), t_end=0.05, dt=1e-4, x0=kick,
                      v0=[0.0, -5.0, 0.0, 0.0])  # fmt: skip
    assert err.value.reason == "domain" and "eccentricity ratio" in str(err.value)
    assert err.value.partial.t.size >= 1


def test_unbalance_response_uses_each_speeds_linearisation() -> None:
    rotor = rotor_on_one_journal(20.0)
    ws = np.array([200.0, 400.0])
    res = rotor.unbalance_response(ws, [(0, 1e-5, 0.0)])
    for i, w in enumerate(ws):
        M, K, Cm, G = rotor.matrices(w)
        F = 1e-5 * w**2 * np.array([1.0, -1j, 0.0, 0.0])
        ref = np.linalg.solve(K - w**2 * M + 1j * w * (Cm + w * G), F)
        np.testing.assert_allclose(res.response[i], ref, rtol=1e-12)

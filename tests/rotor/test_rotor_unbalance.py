"""Issue 15, steady-state unbalance response: exact in the frequency domain, equal to the
amplitude of a long transient run once the start-up transient has decayed; peaks,
amplification factors and API 684 separation margins."""

from __future__ import annotations

import numpy as np
import pytest

import duhamel
from duhamel.rotor import STEEL, Bearing, Disk, Rotor, Shaft, Unbalance
from duhamel.rotor.assembly import RotorMatrices
from duhamel.rotor.unbalance import unbalance_response


def rotor() -> Rotor:
    b = lambda n: Bearing(n, 1e7, 1.4e7, kxy=2e5, kyx=-2e5, cxx=800.0, cyy=900.0)  # noqa: E731
    return Rotor([Shaft(0.25, 0.05, material=STEEL)] * 4, [Disk(2, 30.0, 0.6, 0.3)],
                 [b(0), b(4)], zeta=0.05)  # fmt: skip


def steady_amplitude(r: Rotor, w: float, per_period: int, periods: int) -> np.ndarray:
    """Complex amplitudes of the disk's x and y from a transient started from rest, over the
    last 4 periods (a discrete Fourier coefficient over whole periods)."""
    m_e, phase = 1e-4, 0.7
    system = r.system(w, [Unbalance(2, m_e=m_e, phase=phase)])
    T = 2 * np.pi / w
    dt = T / per_period
    sol = duhamel.solve(system, duhamel.Semianalytic(), t_end=periods * T, dt=dt,
                        dofs=[r.dof(2, "x"), r.dof(2, "y")])  # fmt: skip
    tail = slice(sol.t.size - 1 - 4 * per_period, sol.t.size - 1)
    e = np.exp(-1j * w * sol.t[tail])
    return 2.0 * (sol.x[tail] * e[:, None]).mean(axis=0)


@pytest.mark.parametrize("w", [280.0, 700.0])
def test_equals_the_steady_state_of_a_transient(w) -> None:
    r = rotor()
    X = r.unbalance_response([w], [Unbalance(2, m_e=1e-4, phase=0.7)]).response
    X = X[0, [r.dof(2, "x"), r.dof(2, "y")]]
    # 2.7 s: the slowest start-up transient (zeta ~ 0.05 at 265 rad/s) decays by e^-35 ...
    periods = int(120 * w / 280.0)
    err = {
        k: np.abs(steady_amplitude(r, w, k, periods) - X).max() / np.abs(X).max() for k in (50, 100)
    }
    assert err[100] < 1e-6
    # ... so what remains is the time step's: it converges to the frequency-domain
    # amplitude at fourth order (the harmonic load's quadrature)
    assert 12.0 < err[50] / err[100] < 20.0


def test_jeffcott_closed_form_peaks_and_margins() -> None:
    """A Jeffcott rotor (point mass on isotropic springs): X = m_e W^2 / (k - m W^2 + i c W)
    forward-circular; its half-power amplification factor is about 1 / (2 zeta)."""
    m, k, zeta = 10.0, 1e6, 0.01
    c = 2 * zeta * np.sqrt(k * m)
    mats = RotorMatrices(np.diag([m, m]), np.diag([k, k]), np.diag([c, c]), np.zeros((2, 2)))
    wn = np.sqrt(k / m)
    ws = np.linspace(0.5 * wn, 1.5 * wn, 20001)
    res = unbalance_response(mats, ws, [(0, 2e-4, 0.3)], dof=lambda n, d: {"x": 0, "y": 1}[d])
    exact = 2e-4 * ws**2 * np.exp(0.3j) / (k - m * ws**2 + 1j * c * ws)
    np.testing.assert_allclose(res.response[:, 0], exact, rtol=1e-12)
    np.testing.assert_allclose(res.response[:, 1], -1j * exact, rtol=1e-12)
    np.testing.assert_allclose(res.major_axis(0), np.abs(exact), rtol=1e-12)
    np.testing.assert_allclose(res.minor_axis(0), np.abs(exact), rtol=1e-10)
    assert set(res.whirl(0)) == {"forward"}
    (peak,) = res.peaks(0, "x", operating=(1.2 * wn, 1.4 * wn))
    assert peak.speed == pytest.approx(wn / np.sqrt(1 - 2 * zeta**2), rel=1e-6)
    assert peak.amplification_factor == pytest.approx(1 / (2 * zeta), rel=2e-2)
    af = peak.amplification_factor
    assert peak.required_margin == pytest.approx(min(0.16, 0.17 * (1 - 1 / (af - 1.5))))
    assert peak.margin == pytest.approx((1.2 * wn - peak.speed) / peak.speed)
    assert peak.meets_margin
    with pytest.raises(ValueError, match="m_e"):
        unbalance_response(mats, ws, [(0, -1.0, 0.0)], dof=lambda n, d: 0)


def test_speed_dependent_bearings_are_evaluated_at_each_speed() -> None:
    speeds = [0.0, 500.0, 1000.0]
    tab = Bearing(0, [1e7, 2e7, 4e7], [1e7, 2e7, 4e7], cxx=[900.0, 600.0, 300.0],
                  cyy=[900.0, 600.0, 300.0], speeds=speeds)  # fmt: skip
    shafts = [Shaft(0.25, 0.05, material=STEEL)] * 4
    r = Rotor(shafts, [Disk(2, 30.0, 0.6, 0.3)], [tab, Bearing(4, 1e7, 1e7, cxx=500.0, cyy=500.0)])
    ws = np.array([150.0, 420.0, 830.0])
    res = r.unbalance_response(ws, [(2, 1e-4, 0.0)])
    for i, w in enumerate(ws):
        M, K, C, G = r.matrices(w)
        F = np.zeros(r.n_dof, complex)
        F[r.dof(2, "x")], F[r.dof(2, "y")] = 1e-4 * w**2, -1j * 1e-4 * w**2
        ref = np.linalg.solve(K - w**2 * M + 1j * w * (C + w * G), F)
        np.testing.assert_allclose(res.response[i], ref, rtol=1e-12, atol=1e-20)


def test_long_rotors_are_solved_banded() -> None:
    """A 60-element rotor with Rayleigh damping (banded matrices, 244 dofs): the banded LU
    gives the dense solve's responses, both backward stable."""
    from duhamel.rotor._banded import bandwidths
    from duhamel.rotor.unbalance import _direct, _dynamic_stiffness

    ne = 60
    b = lambda n: Bearing(n, 1e7, 1.2e7, kxy=1e6, kyx=-1e6, cxx=800.0, cyy=900.0)  # noqa: E731
    r = Rotor([Shaft(0.05, 0.05, material=STEEL)] * ne, [Disk(ne // 2, 30.0, 0.6, 0.3)],
              [b(0), b(ne)], rayleigh=(1.0, 1e-5))  # fmt: skip
    mats = tuple(np.asarray(a) for a in r.matrices(0.0))
    assert bandwidths(mats) == (7, 7)
    ws = np.linspace(10.0, 2000.0, 50)
    got = r.unbalance_response(ws, [(ne // 2, 1e-4, 0.3)]).response
    F0 = np.zeros(r.n_dof, complex)
    F0[r.dof(ne // 2, "x")] = 1e-4 * np.exp(0.3j)
    F0[r.dof(ne // 2, "y")] = -1j * 1e-4 * np.exp(0.3j)
    dense = _direct(mats, ws, F0)
    assert np.abs(got - dense).max() <= 1e-8 * np.abs(dense).max()
    A = _dynamic_stiffness(mats, ws)
    residual = np.abs(np.einsum("sij,sj->si", A, got) - (ws**2)[:, None] * F0).max(axis=1)
    assert np.all(residual <= 1e-13 * np.abs(A).max(axis=(1, 2)) * np.abs(got).max(axis=1))

"""Damping made explicit: Rayleigh from periods, restricted Rayleigh, zeta per mode or as a
function of frequency, and each mode's resulting ratio (System.damping_summary)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg
import scipy.sparse as sp
from _frames import moment_frame

import duhamel


def test_rayleigh_from_periods_and_frequencies():
    T1, T2, z = 1.3, 0.25, 0.04
    r = duhamel.Rayleigh.from_periods(T1, T2, z)
    for T in (T1, T2):
        w = 2 * np.pi / T
        assert (r.alpha / w + r.beta * w) / 2 == pytest.approx(z, rel=1e-13)
    r2 = duhamel.Rayleigh.from_frequencies(3.0, 30.0, (0.02, 0.06))
    assert (r2.alpha / 3.0 + r2.beta * 3.0) / 2 == pytest.approx(0.02, rel=1e-13)
    assert (r2.alpha / 30.0 + r2.beta * 30.0) / 2 == pytest.approx(0.06, rel=1e-13)
    M, K, _ = moment_frame(3, 1)
    system = duhamel.System(M, K, rayleigh=r)
    assert system.rayleigh == (r.alpha, r.beta)
    basis = system.modal()
    assert np.allclose(basis.zeta, (r.alpha / basis.omega + r.beta * basis.omega) / 2)
    with pytest.raises(ValueError, match="`omega1` and `omega2` must differ"):
        duhamel.Rayleigh.from_frequencies(2.0, 2.0, 0.05)
    with pytest.raises(ValueError, match="`T1`"):
        duhamel.Rayleigh.from_periods(-1.0, 2.0, 0.05)


def test_zeta_per_mode_as_array_and_function():
    M, K, _ = moment_frame(4, 2)
    w = duhamel.System(M, K).modal().omega
    f = lambda omega: 0.02 + 0.001 * omega  # noqa: E731
    system = duhamel.System(M, K, zeta=f)
    assert np.allclose(system.modal().zeta, f(w), rtol=1e-13)
    assert np.allclose(system.damping_summary().zeta, f(w), rtol=1e-10)
    per_mode = duhamel.System(M, K, zeta=f(w))
    assert np.array_equal(per_mode.modal().c, system.modal().c)
    bad = duhamel.System(M, K, zeta=lambda omega: np.ones(2))
    with pytest.raises(ValueError, match=r"`zeta`.*one finite ratio per mode"):
        bad.modal()


def _isolated(n_storeys: int = 4):
    """A shear building on an isolation floor (dof 0); the isolators are a linear Spring
    element to the ground, so `K` alone has the rigid-body mode."""
    n = n_storeys + 1
    m = np.full(n, 4e5)
    k = np.full(n_storeys, 8e8)
    K = np.zeros((n, n))
    for s in range(n_storeys):  # storey s between floors s and s + 1
        K[np.ix_([s, s + 1], [s, s + 1])] += k[s] * np.array([[1, -1], [-1, 1]])
    k_iso = 4e6 * n  # isolation period about 2.5 s
    return np.diag(m), K, k_iso


def _decay_ratio(x: np.ndarray, dt: float) -> float:
    """Damping ratio from the logarithmic decrement of the positive peaks of `x`."""
    peaks = np.flatnonzero((x[1:-1] > x[:-2]) & (x[1:-1] >= x[2:])) + 1
    peaks = peaks[x[peaks] > 0]
    delta = np.log(x[peaks[0]] / x[peaks[-1]]) / (peaks.size - 1)
    return float(delta / np.sqrt(4 * np.pi**2 + delta**2))


@pytest.mark.parametrize("linear_parts", ["auto", "background"])
def test_isolation_mode_damping_is_stated_and_checked(linear_parts):
    M, K, k_iso = _isolated()
    system = duhamel.System(M, K, zeta=0.05).add(duhamel.elements.Spring(0, None, k=k_iso))
    summary = system.damping_summary(linear_parts)
    w2, phi = scipy.linalg.eigh(K + np.diag([k_iso] + [0.0] * (K.shape[0] - 1)), M)
    assert np.allclose(summary.omega, np.sqrt(w2), rtol=1e-10)
    if linear_parts == "auto":
        # zeta damps the modes of K: the isolation mode is K's rigid-body mode (omega 0),
        # so it keeps almost no damping (only its small difference from that mode's shape)
        assert summary.background == "K"
        assert summary.zeta[0] < 0.005
    else:
        assert summary.background == "K + elements"
        assert summary.classical
        assert np.allclose(summary.zeta, 0.05, rtol=1e-10)
    assert "isolation" not in str(summary) and "zeta" in str(summary)
    # the free vibration in the isolation mode decays at the stated ratio
    T = 2 * np.pi / summary.omega[0]
    dt = T / 200
    sol = duhamel.solve(
        system, duhamel.Semianalytic(linear_parts=linear_parts), t_end=8 * T, dt=dt,
        x0=phi[:, 0] / phi[0, 0] * 0.1,
    )  # fmt: skip
    measured = _decay_ratio(sol.x[:, 0], dt)
    assert measured == pytest.approx(summary.zeta[0], abs=2e-3)


def test_superstructure_only_rayleigh_equals_hand_formed_matrix():
    M, K, k_iso = _isolated()
    n = M.shape[0]
    rayleigh = duhamel.Rayleigh.from_periods(0.5, 0.1, 0.05, stiffness=K)  # K: frame only
    system = duhamel.System(M, K, rayleigh=rayleigh).add(duhamel.elements.Spring(0, None, k=k_iso))
    assert system.damping == "matrix"
    hand = rayleigh.alpha * M + rayleigh.beta * K
    assert np.allclose(system.C, hand, rtol=0, atol=1e-12 * np.abs(hand).max())
    # by dofs: the superstructure's floors only, both terms
    upper = np.arange(1, n)
    by_dofs = duhamel.Rayleigh(rayleigh.alpha, rayleigh.beta, dofs=upper)
    hand2 = np.zeros((n, n))
    block = np.ix_(upper, upper)
    hand2[block] = rayleigh.alpha * M[block] + rayleigh.beta * K[block]
    s2 = duhamel.System(M, K, rayleigh=by_dofs)
    assert np.allclose(s2.C, hand2, rtol=0, atol=1e-12 * np.abs(hand2).max())
    s3 = duhamel.System(sp.csr_array(M), sp.csr_array(K), rayleigh=by_dofs)
    assert np.allclose(s3.C.toarray(), hand2, rtol=0, atol=1e-12 * np.abs(hand2).max())
    # the run equals one on the hand-formed matrix, and the isolation mode's damping is
    # only what the frame's stiffness-proportional part gives it
    t = np.arange(0.0, 6.0, 0.01)
    load = duhamel.loads.BaseAcceleration(np.ones(n), t=t, values=2.0 * np.sin(2.5 * t))
    by_hand = duhamel.System(M, K, C=hand).add(duhamel.elements.Spring(0, None, k=k_iso))
    a = duhamel.solve(system.add_load(load), duhamel.Semianalytic(), t_end=6.0, dt=0.01)
    b = duhamel.solve(by_hand.add_load(load), duhamel.Semianalytic(), t_end=6.0, dt=0.01)
    assert np.array_equal(a.x, b.x)
    # each mode's ratio: the complex eigenvalues of the physical first-order model
    summary = system.damping_summary()
    assert not summary.classical
    K_lin = K + np.diag([k_iso] + [0.0] * (n - 1))
    Minv = np.linalg.inv(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-Minv @ K_lin, -Minv @ hand]])
    lam = np.linalg.eigvals(A)
    lam = lam[np.imag(lam) > 0]
    lam = lam[np.argsort(np.abs(lam))]
    assert np.allclose(summary.zeta, -lam.real / np.abs(lam), rtol=1e-8)

"""Issue 15, modes: heavily damped bearings and overdamped modes give no spurious natural
frequencies; the first forward critical speed matches a dense reference to 1e-8."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

from duhamel.rotor import STEEL, Bearing, Disk, Rotor, Shaft


def dense_eigenvalues(rotor: Rotor, w: float) -> np.ndarray:
    """Every eigenvalue of the state matrix ``[[0, I], [-M^-1 K, -M^-1 (C + w G)]]``."""
    M, K, C, G = rotor.matrices(w)
    n = M.shape[0]
    A = np.block(
        [[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, K), -np.linalg.solve(M, C + w * G)]]
    )
    return np.linalg.eigvals(A)


def damped_rotor() -> Rotor:
    """The issue's second rotor: 12 elements, anisotropic cross-coupled bearings with
    4e3 N s/m, Rayleigh beta = 1.2e-5 (the top modes are overdamped)."""
    b = lambda n: Bearing(n, 2.5e7, 3.5e7, kxy=1e6, kyx=-1e6, cxx=4e3, cyy=4e3)  # noqa: E731
    return Rotor(
        [Shaft(0.1, 0.05, material=STEEL)] * 12, [Disk(6, 30.0, 0.6, 0.3)], [b(0), b(12)],
        rayleigh=(0.0, 1.2e-5),
    )  # fmt: skip


@pytest.mark.parametrize("speed", [0.0, 600.0])
def test_heavily_damped_rotor_has_no_spurious_mode(speed) -> None:
    rotor = damped_rotor()
    modes = rotor.modes(speed)
    lam = dense_eigenvalues(rotor, speed)
    ref = lam[lam.imag > 0]
    zeta = -ref.real / np.abs(ref)
    ref = np.sort(ref[zeta < 0.99].imag)  # what an engineer would list
    # at 600 rad/s the overdamped pairs are coupled by the gyroscopic terms into genuinely
    # complex ones (Im ~ 140 rad/s, zeta = 1 - 1e-6): listed before, never now
    assert modes.n_modes == ref.size
    np.testing.assert_allclose(modes.frequencies, ref, rtol=1e-8)
    assert modes.frequencies[0] > 200.0 and np.all(modes.damping_ratios < 0.99)
    # every other eigenvalue is reported as overdamped
    assert 2 * modes.n_modes + modes.overdamped.size == lam.size
    assert np.all(-modes.overdamped.real / np.abs(modes.overdamped) > 0.999)
    np.testing.assert_array_equal(rotor.natural_frequencies(speed), modes.frequencies)
    tracked = rotor.campbell([0.0, 300.0, 600.0])
    assert np.nanmin(tracked.frequencies) > 200.0


def test_overdamped_by_design_and_round_off_pairs() -> None:
    """A disk on a soft, heavily damped bearing: its translation modes are overdamped (real
    pairs, zeta > 1); the first rotor of the issue (cxx = 3e3, beta = 1e-5) has real pairs
    that round-off splits into sigma +- 0.15i."""
    shafts = [Shaft(0.2, 0.04, material=STEEL)] * 2
    disk = [Disk(1, 50.0, 0.5, 0.25)]
    over = Rotor(shafts, disk, [Bearing(0, 1e5, 1e5, cxx=1e5, cyy=1e5),
                                Bearing(2, 1e5, 1e5, cxx=1e5, cyy=1e5)])  # fmt: skip
    modes = over.modes(0.0)
    lam = dense_eigenvalues(over, 0.0)
    real = lam[np.abs(lam.imag) == 0.0]
    assert real.size >= 4  # the design has real eigenvalues
    for r in real:  # each is reported as overdamped, none as a frequency
        assert np.min(np.abs(modes.overdamped - r)) <= 1e-8 * abs(r)
    assert 2 * modes.n_modes + modes.overdamped.size == lam.size
    b = lambda n: Bearing(n, 1e7, 1e7, cxx=3e3, cyy=3e3)  # noqa: E731
    issue = Rotor([Shaft(0.1, 0.05, material=STEEL)] * 12, [Disk(6, 30.0, 0.6, 0.3)],
                  [b(0), b(12)], rayleigh=(0.0, 1e-5))  # fmt: skip
    first = issue.natural_frequencies(0.0)[:4]
    assert first[0] > 200.0  # not the 0.2 Hz "modes" the issue found
    text = issue.modes(0.0).summary()
    assert "overdamped:" in text and text.count("forward") + text.count("backward") >= 4


def test_first_forward_critical_speed_matches_dense_reference() -> None:
    rotor = damped_rotor()
    found = rotor.critical_speeds(np.linspace(0.0, 1500.0, 31))

    def forward(w: float) -> float:
        """Frequency of the forward mode of the lowest pair, from the dense eigenproblem,
        minus the speed (its orbit sense from the disk node's x, y amplitudes)."""
        M, K, C, G = rotor.matrices(w)
        n = M.shape[0]
        A = np.block(
            [[np.zeros((n, n)), np.eye(n)],
             [-np.linalg.solve(M, K), -np.linalg.solve(M, C + w * G)]]
        )  # fmt: skip
        lam, vec = np.linalg.eig(A)
        keep = (lam.imag > 0) & (-lam.real / np.abs(lam) < 0.99)
        lam, vec = lam[keep], vec[:, keep]
        low = np.argsort(lam.imag)[:2]
        X, Y = vec[4 * 6, low], vec[4 * 6 + 1, low]
        fwd = low[int(np.argmax(-np.imag(np.conj(X) * Y) / (np.abs(X) ** 2 + np.abs(Y) ** 2)))]
        return float(lam[fwd].imag) - w

    ref = brentq(forward, 100.0, 400.0, xtol=1e-13, rtol=1e-15)
    assert found[0] == pytest.approx(ref, rel=1e-8)
    assert 210.0 < found[0] < 215.0
    with pytest.raises(ValueError, match="`whirl`"):
        rotor.critical_speeds([0.0, 100.0], whirl="sideways")

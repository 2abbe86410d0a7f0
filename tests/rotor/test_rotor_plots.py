"""Issue 15 plots draw what they say: mode shapes (3-D orbits, 2-D major semi-axis), Bode and
polar plots of the unbalance response, a run-up spectrogram; Campbell log decrements."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import pytest

import duhamel
from duhamel.rotor import STEEL, Bearing, Disk, Rotor, Shaft, plot_spectrogram, spectrogram


@pytest.fixture
def rotor() -> Rotor:
    b = lambda n: Bearing(n, 1e7, 1.2e7, cxx=600.0, cyy=600.0)  # noqa: E731
    return Rotor([Shaft(0.25, 0.05, material=STEEL)] * 4, [Disk(2, 30.0, 0.6, 0.3)],
                 [b(0), b(4)], zeta=0.02)  # fmt: skip


def test_mode_shape_plots(rotor) -> None:
    modes = rotor.modes(300.0)
    ax = rotor.plot_mode(300.0, 1)
    assert modes.whirl[1] in ax.get_title() and len(ax.lines) == 2 * rotor.n_nodes + 1
    ax2 = rotor.plot_mode(300.0, 1, kind="2d")
    major = ax2.lines[0].get_ydata()
    X = modes.shapes[0::4, 1]
    Y = modes.shapes[1::4, 1]
    np.testing.assert_allclose(
        major, np.abs(X + 1j * Y) / 2 + np.abs(np.conj(X) + 1j * np.conj(Y)) / 2
    )
    with pytest.raises(ValueError, match="`kind`"):
        rotor.plot_mode(300.0, 0, kind="4d")
    plt.close("all")


def test_bode_polar_and_campbell_log_dec(rotor) -> None:
    res = rotor.unbalance_response(np.linspace(100.0, 500.0, 201), [(2, 1e-4, 0.0)])
    ax_a, ax_p = res.plot_bode(2, "x")
    np.testing.assert_allclose(ax_a.lines[0].get_ydata(), res.amplitude(2, "x"))
    assert len(ax_p.lines) == 1
    ax = res.plot_polar(2, "y")
    np.testing.assert_allclose(ax.lines[0].get_xdata(), res.response[:, rotor.dof(2, "y")].real)
    c = rotor.campbell([0.0, 300.0], n_modes=4)
    z = c.damping_ratios
    np.testing.assert_allclose(c.log_dec, 2 * np.pi * z / np.sqrt(1 - z**2))
    plt.close("all")


def test_spectrogram_finds_a_tone_along_a_run_up() -> None:
    law = duhamel.speed.LinearRunUp(omega0=100.0, omega1=300.0, t1=4.0)
    t = np.arange(0.0, 4.0, 1e-3)
    x = 2e-5 * np.sin(150.0 * t)  # a tone at 150 rad/s
    times, speeds, freqs, amps = spectrogram(t, x, law, window=0.5)
    np.testing.assert_allclose(speeds, law.omega(times))
    k = np.argmax(amps, axis=0)
    assert np.all(np.abs(freqs[k] - 150.0) <= freqs[1] - freqs[0])
    assert amps.max() == pytest.approx(2e-5, rel=0.2)
    ax = plot_spectrogram(t, x, law, window=0.5)
    assert ax.get_xlabel() == "speed (rad/s)"
    plt.close("all")

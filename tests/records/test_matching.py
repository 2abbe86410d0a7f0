"""Spectral matching (duhamel.records.match) on 5 different records and a pair: the matched
spectrum within 0.9-1.3 of the target at every period of the range (checked with the fast
kernel on a fine grid and with scipy.signal.lsim at a few periods), the record ending at
rest, the PGA within 30 % of the prescaled record."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy import signal

from duhamel.errors import MatchWarning
from duhamel.records import GroundMotion, GroundMotionPair, match
from duhamel.spectra import TargetSpectrum, asce7, eurocode8, response_spectrum


def record(seed: int, n: int = 4000, dt: float = 0.005) -> GroundMotion:
    """Five different characters: envelopes of different length and rise, white or
    coloured content, a pulse."""
    rng = np.random.default_rng(seed)
    t = dt * np.arange(n)
    env = (t / (1.0 + seed)) ** 2 * np.exp(-t / (1.0 + seed))
    x = rng.standard_normal(n)
    if seed % 2:
        x = np.convolve(x, np.exp(-np.arange(40) / (5.0 + 4 * seed)), "same")  # low-passed
    if seed == 4:
        x += 3.0 * np.sin(2 * np.pi * t / 1.5) * np.exp(-(((t - 6.0) / 1.0) ** 2))  # a pulse
    a = env * x
    return GroundMotion(0.3 * a / np.abs(a).max(), dt, "g", name=f"rec{seed}")


def lsim_psa(gm: GroundMotion, periods: np.ndarray, zeta: float = 0.05) -> np.ndarray:
    out = []
    for p in periods:
        w = 2 * np.pi / p
        sys = ([[0.0, 1.0], [-w * w, -2 * zeta * w]], [[0.0], [-1.0]], [[1.0, 0.0]], [[0.0]])
        _, y, _ = signal.lsim(sys, gm.a, gm.t, interp=True)
        out.append(w * w * np.abs(y).max())
    return np.array(out)


TARGET = asce7(sds=1.0, sd1=0.6, tl=8.0)
RANGE = (0.1, 3.0)


@pytest.mark.parametrize("seed", range(5))
def test_matched_record_meets_the_acceptance(seed):
    gm = record(seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", MatchWarning)
        m = match(gm, TARGET, RANGE)
    info = m.metadata["match"]
    fine = np.geomspace(*RANGE, 300)
    ratio = response_spectrum(m, fine).psa[0, 0] / TARGET(fine)
    assert 0.9 <= ratio.min() and ratio.max() <= 1.3, (ratio.min(), ratio.max())
    few = np.array([0.1, 0.25, 0.6, 1.3, 3.0])
    np.testing.assert_allclose(lsim_psa(m, few), response_spectrum(m, few).psa[0, 0], rtol=1e-9)
    assert info["converged"] and info["min_ratio"] >= 0.9 and info["max_ratio"] <= 1.3
    assert info["misfit"] == pytest.approx(np.abs(ratio - 1).max(), abs=0.02)
    # ends at rest: velocity and displacement below 1e-3 of their peaks
    assert abs(m.velocity[-1]) < 1e-3 * m.pgv and abs(m.displacement[-1]) < 1e-3 * m.pgd
    # PGA within 30 % of the record scaled to the target before matching
    assert abs(m.pga / gm.scaled(info["scale"]).pga - 1.0) < 0.3
    assert m.metadata["processing"][-1]["step"] == "matched"
    assert m.a.size == gm.a.size and m.dt == gm.dt


def test_pair_is_matched_in_rotd100():
    p = GroundMotionPair(record(1, n=2400), record(2, n=2400).scaled(0.7))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", MatchWarning)
        m = match(p, eurocode8(0.25, "C"), (0.15, 2.0))
    assert isinstance(m, GroundMotionPair)
    fine = np.geomspace(0.15, 2.0, 120)
    ratio = m.rotd100(fine) / eurocode8(0.25, "C")(fine)
    assert 0.9 <= ratio.min() and ratio.max() <= 1.3
    for c in m:
        assert abs(c.velocity[-1]) < 1e-3 * c.pgv and abs(c.displacement[-1]) < 1e-3 * c.pgd


def test_ratios_of_one_give_the_record_back():
    """A target the record already meets (its own spectrum): nothing is adjusted, and the
    wavelet reconstruction (with its padding) returns the record, baseline-corrected."""
    gm = record(0).baseline_corrected(5)
    grid = np.geomspace(0.05, 4.0, 400)
    own = TargetSpectrum(grid, response_spectrum(gm, grid).psa[0, 0])
    m = match(gm, own, RANGE, tolerance=0.02)
    info = m.metadata["match"]
    assert info["iterations"] == 0 and info["converged"] and info["kept"] == 0
    ref = gm.scaled(info["scale"]).baseline_corrected(5)
    np.testing.assert_allclose(m.a, ref.a, rtol=0, atol=1e-12 * ref.pga)
    assert abs(info["scale"] - 1.0) < 0.01


def test_a_tolerance_not_reached_warns():
    with pytest.warns(MatchWarning, match="after 1 iterations"):
        m = match(record(3), TARGET, RANGE, tolerance=1e-4, max_iterations=1)
    assert not m.metadata["match"]["converged"]


def test_match_errors_name_the_parameter():
    gm = record(0)
    with pytest.raises(ValueError, match="`periods`"):
        match(gm, TARGET, (3.0, 0.1))
    with pytest.raises(ValueError, match="`periods`"):
        match(gm, eurocode8(0.2, "A"), (0.1, 6.0))
    with pytest.raises(ValueError, match="`tolerance`"):
        match(gm, TARGET, RANGE, tolerance=0.0)
    with pytest.raises(TypeError, match="`record`"):
        match(gm.a, TARGET, RANGE)

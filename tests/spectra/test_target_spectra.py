"""Target spectra (duhamel.spectra.target) against an independent evaluation of the code
formulas (ASCE 7-22 section 11.4.5.2, EN 1998-1:2004 section 3.2.2.2) written out here
branch by branch, and a published worked example."""

from __future__ import annotations

import math

import numpy as np
import pytest

from duhamel.spectra import TargetSpectrum, asce7, asce7_multi_period, eurocode8

G = 9.80665


def asce7_reference(t: float, sds: float, sd1: float, tl: float) -> float:
    """ASCE 7-22 eq. 11.4-5 to 11.4-8, one period at a time, in g."""
    t0 = 0.2 * sd1 / sds
    ts = sd1 / sds
    if t < t0:
        return sds * (0.4 + 0.6 * t / t0)
    if t <= ts:
        return sds
    if t <= tl:
        return sd1 / t
    return sd1 * tl / t**2


EC8 = {  # EN 1998-1 tables 3.2 and 3.3: S, TB, TC, TD
    (1, "A"): (1.0, 0.15, 0.4, 2.0),
    (1, "B"): (1.2, 0.15, 0.5, 2.0),
    (1, "C"): (1.15, 0.2, 0.6, 2.0),
    (1, "D"): (1.35, 0.2, 0.8, 2.0),
    (1, "E"): (1.4, 0.15, 0.5, 2.0),
    (2, "A"): (1.0, 0.05, 0.25, 1.2),
    (2, "B"): (1.35, 0.05, 0.25, 1.2),
    (2, "C"): (1.5, 0.1, 0.25, 1.2),
    (2, "D"): (1.8, 0.1, 0.3, 1.2),
    (2, "E"): (1.6, 0.05, 0.25, 1.2),
}


def ec8_reference(t: float, ag: float, key: tuple[int, str], gamma: float, xi: float) -> float:
    """EN 1998-1 eq. 3.2 to 3.6, in g."""
    s, tb, tc, td = EC8[key]
    a = gamma * ag
    eta = max(math.sqrt(10.0 / (5.0 + 100.0 * xi)), 0.55)
    if t <= tb:
        return a * s * (1.0 + t / tb * (eta * 2.5 - 1.0))
    if t <= tc:
        return a * s * eta * 2.5
    if t <= td:
        return a * s * eta * 2.5 * tc / t
    return a * s * eta * 2.5 * tc * td / t**2


def periods_with_corners(t_max: float, corners: list[float]) -> np.ndarray:
    p = np.concatenate([np.linspace(0.0, t_max, 200 - 2 * len(corners)), corners])
    p = np.concatenate([p, np.nextafter(np.asarray(corners), 0.0)])
    return np.sort(p[p <= t_max])


@pytest.mark.parametrize(
    ("sds", "sd1", "tl", "mce"),
    [(1.0, 0.6, 8.0, False), (1.644, 0.887, 4.0, True), (0.3, 0.45, 2.0, False)],
)
def test_asce7_equals_the_formulas_at_200_periods(sds, sd1, tl, mce):
    ts = asce7(sds, sd1, tl, mce=mce)
    t0, t_s = 0.2 * sd1 / sds, sd1 / sds
    p = periods_with_corners(10.0, [t0, t_s, tl])
    assert p.size == 200
    ref = np.array([asce7_reference(t, sds, sd1, tl) for t in p]) * (1.5 if mce else 1.0)
    got = ts(p) / G
    np.testing.assert_allclose(got, ref, rtol=1e-12, atol=0.0)
    # every branch was visited
    assert np.any(p < t0) and np.any((p > t0) & (p < t_s))
    assert np.any((p > t_s) & (p < tl)) and np.any(p > tl)
    np.testing.assert_allclose(ts.sa_g, ts.sa / G)
    assert ts.metadata["t0"] == pytest.approx(t0) and ts.metadata["ts"] == pytest.approx(t_s)


def test_asce7_published_example():
    """Moehle, CE 120 (UC Berkeley, spring 2015), solution of assignment 7, method 2 (ASCE
    7-10 section 11.4.5, the same two-period spectrum): SDS = 1.644 g, SD1 = 0.887 g give
    T0 = 0.2 SD1 / SDS = 0.1 s (rounded) and Sa(0) = 0.4 SDS = 0.66 g."""
    ts = asce7(1.644, 0.887, 8.0)
    assert round(ts.metadata["t0"], 2) == 0.11 and round(ts.metadata["t0"], 1) == 0.1
    assert round(float(ts(0.0)) / G, 2) == 0.66
    assert float(ts(0.3)) / G == pytest.approx(1.644, rel=1e-15)
    assert float(ts(1.0)) / G == pytest.approx(0.887, rel=1e-15)


@pytest.mark.parametrize("key", sorted(EC8))
@pytest.mark.parametrize(("gamma", "xi"), [(1.0, 0.05), (1.2, 0.02), (0.8, 0.5)])
def test_eurocode8_equals_the_formulas_at_200_periods(key, gamma, xi):
    ag = 0.25
    ts = eurocode8(ag, key[1], spectrum_type=key[0], importance=gamma, damping=xi)
    _, tb, tc, td = EC8[key]
    p = periods_with_corners(4.0, [tb, tc, td])
    ref = np.array([ec8_reference(t, ag, key, gamma, xi) for t in p])
    np.testing.assert_allclose(ts(p) / G, ref, rtol=1e-12, atol=0.0)
    assert np.any(p < tb) and np.any((p > tb) & (p < tc)) and np.any(p > td)
    if xi == 0.5:
        assert ts.metadata["eta"] == 0.55  # the lower bound of eta


def test_eurocode8_plateau_and_pga():
    ts = eurocode8(0.3, "B", importance=1.0)
    # at T = 0 the spectrum is ag S; on the plateau 2.5 ag S (eta = 1 at 5 %)
    assert float(ts(0.0)) / G == pytest.approx(0.3 * 1.2, rel=1e-14)
    assert float(ts(0.3)) / G == pytest.approx(2.5 * 0.3 * 1.2, rel=1e-14)
    with pytest.raises(ValueError, match="range"):
        ts(5.0)


def test_table_interpolates_log_log_and_refuses_extrapolation():
    p = np.array([0.0, 0.1, 1.0, 4.0])
    s = np.array([3.0, 8.0, 4.0, 0.5])
    ts = TargetSpectrum(p, s)
    np.testing.assert_allclose(ts(p), s, rtol=1e-15)
    q = np.array([0.3, 2.0])
    ref = np.exp(np.interp(np.log(q), np.log(p[1:]), np.log(s[1:])))
    np.testing.assert_allclose(ts(q), ref, rtol=1e-14)
    assert float(ts(0.05)) == pytest.approx(5.5, rel=1e-14)  # linear below the first period
    with pytest.raises(ValueError, match="`periods` must lie"):
        ts(4.5)


def test_multi_period_is_two_thirds_of_the_mce_table():
    p, s = [0.0, 0.2, 1.0, 5.0], [0.6, 1.5, 0.9, 0.15]
    design, mce = asce7_multi_period(p, s), asce7_multi_period(p, s, mce=True)
    np.testing.assert_allclose(design.sa_g, 2.0 / 3.0 * np.array(s), rtol=1e-15)
    np.testing.assert_allclose(mce.sa_g, s, rtol=1e-15)


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda: asce7(-1.0, 0.5, 8.0), "`sds`"),
        (lambda: asce7(1.0, 0.5, 0.1), "`tl`"),
        (lambda: asce7(1.0, float("nan"), 8.0), "`sd1`"),
        (lambda: eurocode8(0.2, "S1"), "`ground_type`"),
        (lambda: eurocode8(0.2, "A", spectrum_type=3), "`spectrum_type`"),
        (lambda: eurocode8(0.2, "A", damping=5.0), "`damping`"),
        (lambda: TargetSpectrum([0.0, 1.0], [1.0, -1.0]), "`sa`"),
        (lambda: TargetSpectrum([1.0, 0.5], [1.0, 1.0]), "`periods`"),
    ],
)
def test_bad_input_names_the_parameter(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_plot(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    ax = asce7(1.0, 0.6, 8.0).plot()
    line = ax.get_lines()[0]
    assert np.max(line.get_ydata()) == pytest.approx(1.0)

"""scale_suite on 7 synthetic pairs: the ASCE 7-22 section 16.2.3 criterion recomputed with
scipy.signal.lsim (first-order hold: exact for records linear between samples) RotD100
spectra of the scaled pairs, the smallest common factor, the least-squares factors against
scipy.optimize, Sa at one period."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import optimize, signal

from duhamel.records import GroundMotion, GroundMotionPair, Suite, scale_suite
from duhamel.spectra import asce7

G = 9.80665


def synthetic_pair(seed: int, n: int = 1500, dt: float = 0.01) -> GroundMotionPair:
    rng = np.random.default_rng(seed)
    t = dt * np.arange(n)
    env = (t / 2.0) ** 2 * np.exp(-t / 2.0)
    colour = np.exp(-0.5 * (np.fft.rfftfreq(n, dt) - 1.0 - 0.3 * seed) ** 2)  # a site peak
    comps = []
    for k in range(2):
        white = rng.standard_normal(n)
        shaped = np.fft.irfft(np.fft.rfft(white) * (0.3 + colour), n)
        comps.append(GroundMotion(0.05 * env * shaped, dt, "g", name=f"P{seed}_{k}"))
    return GroundMotionPair(*comps)


def lsim_rotd100(pair: GroundMotionPair, periods: np.ndarray, zeta: float = 0.05):
    """RotD100 pseudo-acceleration from scipy.signal.lsim displacement histories of both
    components, combined along 180 directions."""
    t = pair.t
    u = np.column_stack([pair.first.a, pair.second.a])
    theta = np.deg2rad(np.arange(180.0))
    out = np.empty(periods.size)
    for j, period in enumerate(periods):
        w = 2 * np.pi / period
        a1 = np.array([[0.0, 1.0], [-w * w, -2 * zeta * w]])
        a = np.block([[a1, np.zeros((2, 2))], [np.zeros((2, 2)), a1]])
        b = np.array([[0.0, 0.0], [-1.0, 0.0], [0.0, 0.0], [0.0, -1.0]])
        c = np.array([[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]])
        _, y, _ = signal.lsim((a, b, c, np.zeros((2, 2))), u, t, interp=True)
        proj = np.cos(theta)[:, None] * y[:, 0] + np.sin(theta)[:, None] * y[:, 1]
        out[j] = w * w * np.abs(proj).max()
    return out


@pytest.fixture(scope="module")
def suite7():
    return [synthetic_pair(s) for s in range(7)]


@pytest.fixture(scope="module")
def target():
    return asce7(sds=1.0, sd1=0.6, tl=8.0)


@pytest.fixture(scope="module")
def lsim_spectra(suite7, target):
    """The unscaled RotD100 spectra by lsim at the periods of the criterion's table."""
    periods = scale_suite(suite7, target, (0.3, 3.0), n_periods=24).table.period
    return periods, np.array([lsim_rotd100(p, periods) for p in suite7])


@pytest.mark.parametrize("minimise_misfit", [False, True])
def test_asce7_criterion_holds_with_lsim_spectra_and_the_factor_is_smallest(
    suite7, target, lsim_spectra, minimise_misfit
):
    res = scale_suite(suite7, target, (0.3, 3.0), n_periods=24, minimise_misfit=minimise_misfit)
    periods, ref = lsim_spectra
    np.testing.assert_array_equal(res.table.period, periods)
    assert periods.size == 25 and 0.6 in periods  # TS = 0.6 s, the corner, is checked
    np.testing.assert_allclose(res.spectra, ref, rtol=1e-9)
    mean = np.mean(res.factors[:, None] * ref, axis=0)
    assert np.all(mean >= 0.9 * target(periods) * (1 - 1e-9))  # holds at every period
    assert res.passes and bool(np.all(res.table.passes))
    # smallest: any smaller common multiple fails at some period
    assert np.any(0.999999 * mean < 0.9 * target(periods))
    if not minimise_misfit:
        assert np.ptp(res.factors) == 0.0  # one common factor
    else:
        # the shape of the factors is each record's least-squares fit
        ls = scale_suite(suite7, target, (0.3, 3.0), n_periods=24, method="least_squares")
        np.testing.assert_allclose(res.factors / ls.factors, res.factors[0] / ls.factors[0])
    # the scaled records are the records times the factors
    np.testing.assert_allclose(res.records[3].first.a, res.factors[3] * suite7[3].first.a)
    assert "passes" in str(res.table) and res.table.to_dataframe().shape[0] == periods.size


def test_least_squares_minimises_the_log_misfit(suite7, target):
    res = scale_suite(suite7, target, (0.2, 2.0), method="least_squares", n_periods=40)
    sa = target(res.table.period)
    for f, s in zip(res.factors, res.spectra, strict=True):

        def misfit(lnf, s=s):
            return np.sum((lnf + np.log(s) - np.log(sa)) ** 2)

        best = optimize.minimize_scalar(misfit, bracket=(-3.0, 3.0), tol=1e-12)
        assert np.log(f) == pytest.approx(best.x, abs=1e-7)


def test_sa_at_one_period_with_lsim(suite7, target):
    res = scale_suite(suite7[:3], target, 1.0, method="sa")
    for f, p in zip(res.factors, suite7[:3], strict=True):
        assert f * lsim_rotd100(p, np.array([1.0]))[0] == pytest.approx(
            float(target(1.0)), rel=1e-9
        )


def test_single_records_use_their_own_spectrum(target):
    recs = [synthetic_pair(s).first for s in range(3)]
    res = scale_suite(recs, target, (0.5, 1.5), n_periods=10)
    assert res.passes and res.table.ratio.min() == pytest.approx(0.9, rel=1e-12)


def test_suite_cases_feed_solve_many(suite7, target):
    import duhamel
    from duhamel.ensemble import solve_many

    res = scale_suite(suite7[:2], target, (0.3, 3.0), n_periods=12)
    suite = res.suite
    cases = suite.cases(orientations=(0.0, 90.0))
    assert len(cases) == 4 and cases[1]["orientation"] == 90.0
    m = np.eye(2)
    k = np.array([[400.0, 0.0], [0.0, 900.0]])  # x and y oscillators
    model = duhamel.System(m, k, zeta=0.05)

    def make(case):
        return model, {"loads": suite.loads(case, [1.0, 0.0], [0.0, 1.0])}

    ens = solve_many(make, cases, duhamel.Semianalytic(), t_end=14.0, dt=0.01, workers=1,
                     reduce=lambda sol: float(np.abs(sol.x[:, 0]).max()))  # fmt: skip
    # the x oscillator's peak under case 1 (turned by 90) is its peak under component 2
    x1, _ = suite.motions(cases[1])
    np.testing.assert_allclose(x1.a, res.factors[0] * suite7[0].second.a, rtol=1e-12, atol=1e-15)
    alone = duhamel.prepare(model, duhamel.Semianalytic(), dt=0.01).run(t_end=14.0,
                          loads=[x1.as_load([1.0, 0.0])])  # fmt: skip
    assert ens.results[1] == pytest.approx(float(np.abs(alone.x[:, 0]).max()), rel=1e-12)
    ds = ens.to_xarray()
    assert list(ds["record"].values) == [suite.names[0]] * 2 + [suite.names[1]] * 2
    np.testing.assert_allclose(ds["factor"].values, np.repeat(res.factors, 2))


def test_scale_suite_errors(suite7, target):
    with pytest.raises(ValueError, match="`method`"):
        scale_suite(suite7, target, (0.3, 3.0), method="mse")
    with pytest.raises(ValueError, match="`period_range`"):
        scale_suite(suite7, target, (0.3, 30.0))
    with pytest.raises(TypeError, match=r"`records_or_pairs\[0\]`"):
        scale_suite([1.0], target, (0.3, 3.0))
    with pytest.raises(ValueError, match="`factors`"):
        Suite(suite7, factors=[1.0])

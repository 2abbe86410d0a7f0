"""Response spectra (issue 13) against independent references: scipy ``lsim`` (its
first-order hold is exact for records linear between samples) for the elastic spectra over
dampings 0..0.2 and periods 0.01..20 s; a brute-force rotation for RotD; solve_ivp with
branch events for the bilinear oscillator; and the properties of the ductility search."""

from __future__ import annotations

import matplotlib
import numpy as np
import pytest
import scipy.integrate
import scipy.signal

from duhamel import _core
from duhamel.records import G, GroundMotion
from duhamel.spectra import ductility_spectrum, response_spectrum, rotd

matplotlib.use("Agg")

DT = 0.005
RNG = np.random.default_rng(2026)


def synthetic(n: int = 4000, seed: int = 0) -> np.ndarray:
    """Filtered noise with a build-up and decay envelope, m/s^2 (a record-like signal)."""
    rng = np.random.default_rng(seed)
    t = DT * np.arange(n)
    b, a = scipy.signal.butter(4, [0.2, 12.0], btype="band", fs=1 / DT)
    env = np.minimum(t / 2.0, 1.0) * np.exp(-np.maximum(t - 8.0, 0.0) / 4.0)
    return 3.0 * env * scipy.signal.lfilter(b, a, rng.normal(size=n))


def lsim_peaks(acc: np.ndarray, dt: float, period: float, zeta: float) -> np.ndarray:
    w = 2 * np.pi / period
    A = np.array([[0.0, 1.0], [-w * w, -2 * zeta * w]])
    sys = scipy.signal.StateSpace(A, np.array([[0.0], [-1.0]]), np.eye(2), np.zeros((2, 1)))
    t = dt * np.arange(acc.size)
    _, y, _ = scipy.signal.lsim(sys, acc, t, interp=True)
    x, v = y[:, 0], y[:, 1]
    return np.array([np.abs(x).max(), np.abs(v).max(), np.abs(w * w * x + 2 * zeta * w * v).max()])


PERIODS = np.geomspace(0.01, 20.0, 12)
DAMPINGS = np.array([0.0, 0.02, 0.05, 0.2])


def test_elastic_spectrum_equals_lsim_to_1e10_of_the_peak() -> None:
    acc = synthetic()
    rs = response_spectrum(GroundMotion(acc, DT), PERIODS, DAMPINGS)
    assert rs.sd.shape == (1, 4, 12)
    worst = 0.0
    for j, z in enumerate(DAMPINGS):
        for k, p in enumerate(PERIODS):
            ref = lsim_peaks(acc, DT, p, z)
            got = np.array([rs.sd[0, j, k], rs.sv[0, j, k], rs.sa[0, j, k]])
            worst = max(worst, float(np.max(np.abs(got - ref) / ref)))
    assert worst <= 1e-10, worst
    w = 2 * np.pi / PERIODS
    np.testing.assert_allclose(rs.psa[0], w**2 * rs.sd[0], rtol=1e-15)
    np.testing.assert_allclose(rs.psv[0], w * rs.sd[0], rtol=1e-15)


def test_limits_rigid_and_flexible() -> None:
    """T -> 0: Sa -> PGA (period 0 exactly the PGA); T -> large: Sd -> peak ground
    displacement (the mass stays in place)."""
    gm = GroundMotion(synthetic(), DT)
    rs = response_spectrum(gm, [0.0, 1e-4, 1e6], [0.0])
    assert rs.sa[0, 0, 0] == gm.pga and rs.sd[0, 0, 0] == 0.0 and rs.psa[0, 0, 0] == gm.pga
    assert rs.sa[0, 0, 1] == pytest.approx(gm.pga, rel=1e-6)
    assert rs.sd[0, 0, 2] == pytest.approx(gm.pgd, rel=1e-6)


def test_several_motions_and_threads_agree() -> None:
    recs = [GroundMotion(synthetic(3000, s), DT, name=f"r{s}") for s in range(3)]
    many = response_spectrum(recs, PERIODS, [0.05, 0.1])
    one = response_spectrum(recs, PERIODS, [0.05, 0.1], threads=1)
    np.testing.assert_array_equal(many.sa, one.sa)
    for i, r in enumerate(recs):
        single = response_spectrum(r, PERIODS, [0.05, 0.1])
        np.testing.assert_array_equal(single.sd[0], many.sd[i])
    pair = response_spectrum((recs[0].t, recs[0].a), PERIODS, 0.05)
    np.testing.assert_array_equal(pair.sd[0, 0], many.sd[0, 0])
    assert many.names == ["r0", "r1", "r2"]


def test_errors_name_the_parameter() -> None:
    gm = GroundMotion(synthetic(200), DT)
    with pytest.raises(ValueError, match="`periods`"):
        response_spectrum(gm, [-1.0, 1.0])
    with pytest.raises(ValueError, match="`damping`"):
        response_spectrum(gm, [1.0], damping=-0.1)
    with pytest.raises(ValueError, match="`periods`"):
        response_spectrum(gm, [np.nan])
    with pytest.raises(ValueError, match="`motions`"):
        response_spectrum([], [1.0])
    with pytest.raises(TypeError, match=r"`motions\[0\]`"):
        response_spectrum(["x"], [1.0])
    t = np.array([0.0, 0.01, 0.03])
    with pytest.raises(ValueError, match="uniformly spaced"):
        response_spectrum((t, np.ones(3)), [1.0])
    with pytest.raises(ValueError, match="overflows"):
        response_spectrum((np.array([0.0, 1e3, 2e3]), np.array([0, 1e308, -1e308])), [1e4])


def test_rotd_against_brute_force_rotation() -> None:
    a1, a2 = synthetic(2000, 1), synthetic(2000, 2)
    periods = np.array([0.2, 1.0, 3.0])
    r = rotd(GroundMotion(a1, DT), GroundMotion(a2, DT), periods, percentiles=(0, 50, 100))
    for k, p in enumerate(periods):
        w = 2 * np.pi / p
        A = np.array([[0.0, 1.0], [-w * w, -0.1 * w]])
        sys = scipy.signal.StateSpace(A, [[0.0], [-1.0]], [[1.0, 0.0]], [[0.0]])
        t = DT * np.arange(a1.size)
        x1 = scipy.signal.lsim(sys, a1, t)[1]
        x2 = scipy.signal.lsim(sys, a2, t)[1]
        theta = np.deg2rad(np.arange(180.0))
        peaks = np.abs(np.cos(theta)[:, None] * x1 + np.sin(theta)[:, None] * x2).max(axis=1)
        np.testing.assert_allclose(r.peaks[0, k], peaks, rtol=1e-10)
        ref = np.percentile(peaks, [0, 50, 100])
        np.testing.assert_allclose(r.sd[0, :, k], ref, rtol=1e-10)
    single = response_spectrum([GroundMotion(a1, DT), GroundMotion(a2, DT)], periods).sd
    assert np.all(r.sd[0, 2] >= single[:, 0].max(axis=0) * (1 - 1e-12))
    with pytest.raises(ValueError, match="`motion_2`"):
        rotd(GroundMotion(a1, DT), GroundMotion(a2, 2 * DT), periods)


def bilinear_reference(acc, dt, omega, zeta, alpha, uy) -> float:
    """Peak |u| at the samples by solve_ivp (DOP853, rtol 1e-12) over each sample interval,
    with the branch switches (yield |z| = uy, unloading v = 0) located as events."""
    k, c = omega**2, 2 * zeta * omega
    y = np.zeros(3)  # u, v, z
    peak = 0.0
    for i in range(acc.size - 1):
        t0, t1 = i * dt, (i + 1) * dt

        def ag(t, i=i, t0=t0):
            return acc[i] + (acc[i + 1] - acc[i]) * (t - t0) / dt

        while t0 < t1:
            plastic = abs(y[2]) >= uy * (1 - 1e-12) and y[1] * np.sign(y[2]) > 0
            d = np.sign(y[2])

            def rhs(t, s, plastic=plastic):
                f = k * (alpha * s[0] + (1 - alpha) * s[2])
                return [s[1], -ag(t) - c * s[1] - f, 0.0 if plastic else s[1]]

            if plastic:
                ev = lambda t, s: s[1]  # noqa: E731
            else:
                ev = lambda t, s: abs(s[2]) - uy  # noqa: E731
            ev.terminal, ev.direction = True, (-d if plastic else 1)
            sol = scipy.integrate.solve_ivp(
                rhs, (t0, t1), y, method="DOP853", rtol=1e-12, atol=1e-14 * uy, events=ev
            )
            y = sol.y[:, -1].copy()
            if sol.status == 1:  # event: switch branch
                if plastic:
                    y[1] = 0.0
                else:
                    y[2] = np.sign(y[2]) * uy
                t0 = sol.t[-1]
                if t1 - t0 < 1e-13:
                    break
            else:
                t0 = t1
        peak = max(peak, abs(y[0]))
    return peak


@pytest.mark.parametrize("alpha", [0.0, 0.05])
def test_bilinear_oscillator_against_solve_ivp_with_events(alpha: float) -> None:
    acc = synthetic(700, 3)
    omega, zeta = 2 * np.pi / 0.6, 0.05
    el = response_spectrum(GroundMotion(acc, DT), [0.6], zeta).sd[0, 0, 0]
    uy = 0.3 * el
    got = _core.bilinear_peak(acc, DT, omega, zeta, alpha, uy)
    ref = bilinear_reference(acc, DT, omega, zeta, alpha, uy)
    assert got > el * 1.01 or got < el * 0.99  # it did yield and change the response
    assert got == pytest.approx(ref, rel=1e-8)


def test_ductility_spectrum_reaches_its_targets() -> None:
    gm = GroundMotion(synthetic(2000, 4), DT, name="s4")
    periods = np.array([0.1, 0.5, 1.0, 2.0])
    ds = ductility_spectrum(gm, periods, ductility=[1.0, 2.0, 4.0, 8.0], alpha=0.02)
    assert ds.uy.shape == (1, 4, 4)
    np.testing.assert_array_equal(ds.uy[0, 0], ds.elastic_sd[0])  # ductility 1: elastic
    for m, mu in enumerate(ds.ductility[1:], start=1):
        for k, p in enumerate(periods):
            uy = ds.uy[0, m, k]
            got = _core.bilinear_peak(gm.a, DT, 2 * np.pi / p, 0.05, 0.02, uy) / uy
            assert got == pytest.approx(mu, rel=1e-6)
    assert np.all(ds.r[0, 1:] > 1.0)
    np.testing.assert_allclose(ds.cy, (2 * np.pi / periods) ** 2 * ds.uy / G, rtol=1e-15)
    np.testing.assert_allclose(ds.sd, ds.ductility[None, :, None] * ds.uy, rtol=1e-15)
    with pytest.raises(ValueError, match="`ductility`"):
        ductility_spectrum(gm, periods, ductility=[0.5])
    with pytest.raises(ValueError, match="`periods`"):
        ductility_spectrum(gm, [0.0, 1.0], ductility=[2.0])
    with pytest.raises(ValueError, match="`alpha`"):
        ductility_spectrum(gm, [1.0], ductility=[2.0], alpha=1.0)


def test_plot_and_xarray(tmp_path) -> None:
    import matplotlib.pyplot as plt

    recs = [GroundMotion(synthetic(1000, s), DT, name=f"r{s}") for s in range(2)]
    rs = response_spectrum(recs, np.geomspace(0.05, 5.0, 20), [0.02, 0.05])
    ax = rs.plot("psa")
    assert len(ax.get_lines()) == 4 and ax.get_xscale() == "log"
    ax = rs.plot(tripartite=True)
    assert "PSV" in ax.get_ylabel()
    plt.close("all")
    with pytest.raises(ValueError, match="`quantity`"):
        rs.plot("foo")
    xr = pytest.importorskip("xarray")
    ds = rs.to_xarray()
    assert dict(ds.sizes) == {"motion": 2, "damping": 2, "period": 20}
    np.testing.assert_array_equal(ds["psa"].values, rs.psa)
    path = tmp_path / "rs.nc"
    try:
        ds.to_netcdf(path)
    except (ImportError, ValueError):  # no netCDF engine installed
        return
    np.testing.assert_array_equal(xr.open_dataset(path)["sd"].values, rs.sd)


def _fine_reference(acc: np.ndarray, dt: float, period: float, zeta: float) -> np.ndarray:
    """Peaks (sd, sv, sa) of the oscillator under the piecewise-linear record `acc`: lsim
    at 100 times finer sampling, each peak then refined between its neighbouring fine
    samples where the quantity's derivative vanishes (matrix exponential, brentq)."""
    from scipy.linalg import expm
    from scipy.optimize import brentq

    w = 2 * np.pi / period
    k, c = w * w, 2 * zeta * w
    a = np.array([[0.0, 1.0], [-k, -c]])
    sys = scipy.signal.StateSpace(a, [[0.0], [1.0]], np.eye(2), np.zeros((2, 1)))
    t = np.arange(acc.size) * dt
    tf = np.arange((acc.size - 1) * 100 + 1) * (dt / 100)
    pf = -np.interp(tf, t, acc)
    _, _, y = scipy.signal.lsim(sys, pf, tf, interp=True)
    aug = np.zeros((4, 4))
    aug[:2, :2], aug[1, 2], aug[2, 3] = a, 1.0, 1.0

    def state(m: int, s: float) -> np.ndarray:
        slope = (pf[m + 1] - pf[m]) / (tf[1] - tf[0])
        return (expm(aug * s) @ np.array([*y[m], pf[m], slope]))[:2]

    def quantities(st: np.ndarray, m: int, s: float) -> np.ndarray:
        p = pf[m] + (pf[m + 1] - pf[m]) * s / (tf[1] - tf[0])
        acc_rel = p - c * st[1] - k * st[0]
        return np.array([st[0], st[1], k * st[0] + c * st[1]]), np.array(
            [st[1], acc_rel, k * st[1] + c * acc_rel]
        )

    peaks = []
    whole = [y[:, 0], y[:, 1], k * y[:, 0] + c * y[:, 1]]
    for q in range(3):
        m = int(np.argmax(np.abs(whole[q])))
        best = abs(whole[q][m])
        for n in (m - 1, m):
            if n < 0 or n + 1 >= tf.size:
                continue
            h = tf[1] - tf[0]
            d = lambda s, n=n, q=q: quantities(state(n, s), n, s)[1][q]  # noqa: E731
            if d(0.0) * d(h) < 0:
                s = brentq(d, 0.0, h, xtol=1e-16 * h + 1e-300, rtol=1e-15)
                best = max(best, abs(quantities(state(n, s), n, s)[0][q]))
        peaks.append(best)
    return np.array(peaks)


def test_exact_peaks_against_lsim_at_100_times_finer_sampling() -> None:
    rng = np.random.default_rng(11)
    dt = 0.01
    raw = rng.standard_normal(300)
    acc = np.convolve(raw, np.ones(3) / 3, mode="same") * np.hanning(300) * 3.0
    periods = [0.013, 0.03, 0.1, 0.45, 2.0]
    exact = response_spectrum((np.arange(300) * dt, acc), periods, 0.05, peaks="exact")
    sampled = response_spectrum((np.arange(300) * dt, acc), periods, 0.05)
    for i, period in enumerate(periods):
        ref = _fine_reference(acc, dt, period, 0.05)
        got = np.array([exact.sd[0, 0, i], exact.sv[0, 0, i], exact.sa[0, 0, i]])
        np.testing.assert_allclose(got, ref, rtol=1e-10, err_msg=f"T = {period}")
    for name in ("sd", "sv", "sa"):
        assert np.all(getattr(exact, name) >= getattr(sampled, name))
    # The shortest period, below two samples, peaks well between them.
    assert exact.sd[0, 0, 0] > 1.01 * sampled.sd[0, 0, 0]
    with pytest.raises(ValueError, match="peaks"):
        response_spectrum((np.arange(300) * dt, acc), periods, 0.05, peaks="max")
    with pytest.raises(ValueError, match="damping"):
        response_spectrum((np.arange(300) * dt, acc), periods, 1.0, peaks="exact")

"""Record processing (GroundMotion.baseline_corrected, filtered, resampled, padded, fourier,
cav, bracketed_duration, write_at2) against independent references."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import signal

from duhamel.records import GroundMotion, read_at2
from duhamel.records.processing import konno_ohmachi


def synthetic(n: int = 4000, dt: float = 0.01, seed: int = 1) -> GroundMotion:
    rng = np.random.default_rng(seed)
    t = dt * np.arange(n)
    env = (t / 3.0) ** 2 * np.exp(-t / 3.0)
    return GroundMotion(env * rng.standard_normal(n), dt, "g", name=f"syn{seed}")


def integrate(a: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """Exact velocity and displacement of the piecewise-linear columns of `a`, written
    independently of the library: per segment v += dt (a0 + a1) / 2, d += v dt +
    dt^2 (a0 / 3 + a1 / 6)."""
    v = np.zeros_like(a)
    d = np.zeros_like(a)
    for k in range(a.shape[0] - 1):
        d[k + 1] = d[k] + v[k] * dt + dt * dt * (a[k] / 3.0 + a[k + 1] / 6.0)
        v[k + 1] = v[k] + 0.5 * dt * (a[k] + a[k + 1])
    return v, d


@pytest.mark.parametrize(("low", "high"), [(0.1, None), (None, 20.0), (0.2, 15.0)])
@pytest.mark.parametrize("order", [2, 4])
def test_filtered_equals_sosfiltfilt_on_the_padded_record(low, high, order):
    gm = synthetic()
    f = gm.filtered(low, high, order=order)
    fs = 1.0 / gm.dt
    if low and high:
        sos = signal.butter(order, [low, high], "bandpass", fs=fs, output="sos")
    elif low:
        sos = signal.butter(order, low, "highpass", fs=fs, output="sos")
    else:
        sos = signal.butter(order, high, "lowpass", fs=fs, output="sos")
    pad = max(10, int(np.ceil(1.5 * order / (low or high) * fs)))
    ref = signal.sosfiltfilt(sos, np.pad(gm.a, (pad, pad)), padtype=None)
    scale = np.abs(ref).max()
    np.testing.assert_allclose(f.a, ref[pad:-pad], rtol=0, atol=1e-12 * scale)
    kept = gm.filtered(low, high, order=order, keep_padding=True)
    np.testing.assert_allclose(kept.a, ref, rtol=0, atol=1e-12 * scale)
    causal = gm.filtered(low, high, order=order, zero_phase=False)
    ref_c = signal.sosfilt(sos, np.pad(gm.a, (pad, pad)))[pad:-pad]
    np.testing.assert_allclose(causal.a, ref_c, rtol=0, atol=1e-12 * scale)
    step = f.metadata["processing"][-1]
    assert step["step"] == "filtered" and step["pad"] == pad and step["order"] == order


def test_filter_removes_what_it_should():
    dt = 0.005
    t = dt * np.arange(8000)
    slow, fast = np.sin(2 * np.pi * 1.0 * t), np.sin(2 * np.pi * 40.0 * t)
    out = GroundMotion(slow + fast, dt).filtered(high=10.0, order=6)
    assert np.abs(out.a - slow)[400:-400].max() < 2e-3


@pytest.mark.parametrize("zero_end", [True, False])
@pytest.mark.parametrize("order", [3, 5])
def test_baseline_removes_a_known_polynomial_drift_exactly(zero_end, order):
    n, dt = 1500, 0.01
    t = dt * np.arange(n)
    tau = t / t[-1]
    basis = tau[:, None] ** np.arange(order - 1)[None, :]
    _, db = integrate(basis, dt)
    # a record a0 = raw + E y whose displacement is orthogonal to the drifts' displacements
    # (and, for zero_end, that ends at rest): the least-squares fit then finds the drift
    # exactly, whatever a0 is otherwise
    rng = np.random.default_rng(3)
    raw = np.sin(7.0 * t) * np.exp(-0.3 * t) + 0.2 * rng.standard_normal(n)
    k = order - 1 + (2 if zero_end else 0)
    shapes = np.column_stack([np.sin((j + 1) * np.pi * tau) * tau for j in range(k)])
    vr, dr = integrate(raw[:, None], dt)
    vs, ds = integrate(shapes, dt)
    rows, rhs = [db.T @ ds], [-(db.T @ dr[:, 0])]
    if zero_end:
        rows += [vs[-1:], ds[-1:]]
        rhs += [-vr[-1], -dr[-1]]
    a0 = raw + shapes @ np.linalg.solve(np.vstack(rows), np.concatenate(rhs))
    v0, d0 = integrate(a0[:, None], dt)
    assert np.abs(db.T @ d0[:, 0]).max() < 1e-10 * np.abs(db).max() * np.abs(d0).max() * n
    if zero_end:
        assert abs(v0[-1, 0]) < 1e-12 and abs(d0[-1, 0]) < 1e-12
    drift = basis @ np.array([0.3, -0.5, 0.8, 0.1, -0.2][: order - 1])
    fixed = GroundMotion(a0 + drift, dt).baseline_corrected(order, zero_end=zero_end)
    np.testing.assert_allclose(fixed.a, a0, rtol=0, atol=1e-11 * np.abs(a0).max())
    pure = GroundMotion(drift, dt).baseline_corrected(order, zero_end=zero_end)
    assert np.abs(pure.a).max() < 1e-11
    assert fixed.metadata["processing"][-1]["step"] == "baseline_corrected"


def test_baseline_ends_a_drifting_record_at_rest():
    gm = synthetic(seed=4)
    assert abs(gm.displacement[-1]) > 1e-3  # it drifts
    bc = gm.baseline_corrected()
    assert abs(bc.velocity[-1]) < 1e-12 * bc.pgv and abs(bc.displacement[-1]) < 1e-12 * bc.pgd
    with pytest.raises(ValueError, match="`order`"):
        gm.baseline_corrected(2)


def test_fourier_equals_numpy_fft_scaling_and_parseval():
    gm = synthetic(n=3001)
    fas = gm.fourier()
    full = np.fft.fft(gm.a)
    n = gm.a.size
    np.testing.assert_allclose(fas.amplitude, gm.dt * np.abs(full[: n // 2 + 1]), rtol=1e-13)
    np.testing.assert_allclose(fas.frequency, np.arange(n // 2 + 1) / (n * gm.dt), rtol=1e-15)
    # Parseval: sum a^2 dt = sum |A|^2 df over all (two-sided) frequencies
    two_sided = np.sum((gm.dt * np.abs(full)) ** 2) / (n * gm.dt)
    assert two_sided == pytest.approx(np.sum(gm.a**2) * gm.dt, rel=1e-12)


def test_konno_ohmachi_against_the_formula():
    gm = synthetic(n=2000)
    fas = gm.fourier(smoothing=40.0)
    f, s = fas.frequency, fas.amplitude
    for k in (1, 7, 50, 333, 999, f.size - 1):
        fc = f[k]
        w = np.zeros_like(f)
        for i, fi in enumerate(f):
            if fi == 0.0:
                continue
            if fi == fc:
                w[i] = 1.0
            else:
                x = 40.0 * np.log10(fi / fc)
                w[i] = (np.sin(x) / x) ** 4
        assert fas.smoothed[k] == pytest.approx(np.dot(w, s) / w.sum(), rel=1e-12)
    assert fas.smoothed[0] == 0.0
    # a constant spectrum stays constant
    np.testing.assert_allclose(konno_ohmachi(f, np.ones_like(f), 20.0)[1:], 1.0, rtol=1e-12)


def test_resampled_refines_exactly_and_coarsens_a_slow_signal():
    gm = synthetic(n=1001)
    fine = gm.resampled(gm.dt / 4)
    np.testing.assert_allclose(fine.a[::4], gm.a, rtol=0, atol=1e-15)
    np.testing.assert_allclose(fine.a[2::4], 0.5 * (gm.a[:-1] + gm.a[1:]), atol=1e-15)
    t = 0.005 * np.arange(4001)
    slow = GroundMotion(np.sin(2 * np.pi * 0.5 * t), 0.005)
    coarse = slow.resampled(0.02)
    ref = np.sin(2 * np.pi * 0.5 * coarse.t)
    assert np.abs(coarse.a - ref)[20:-20].max() < 1e-3
    assert coarse.metadata["processing"][-1]["antialias"] is True


def test_padded_cav_and_bracketed_duration():
    gm = GroundMotion([1.0, 2.0, -1.0], dt=0.5)
    p = gm.padded(before=1.0, after=0.4)
    assert p.a.tolist() == [0.0, 0.0, 1.0, 2.0, -1.0, 0.0]
    # CAV: trapezoid 0.5 * 1.5 = 0.75, then a sign change from 2 to -1: (4 + 1) / (2 * 3) / 2
    assert gm.cav() == pytest.approx(0.75 + 0.5 * (4.0 + 1.0) / 6.0, rel=1e-15)
    # against a fine quadrature of |a|
    t = np.linspace(0.0, 1.0, 2_000_001)
    fine = np.abs(np.interp(t, gm.t, gm.a))
    assert gm.cav() == pytest.approx(np.trapezoid(fine, t), rel=1e-9)
    # |a| >= 1.5 first at t = 0.25 (1 -> 2) and last at t = 0.5 + 0.5/6 (2 -> -1)
    bd = gm.bracketed_duration(1.5, units="m/s^2")
    assert bd == pytest.approx(0.5 + 0.5 / 6.0 - 0.25, rel=1e-14)
    assert gm.bracketed_duration(5.0, units="m/s^2") == 0.0


def test_write_at2_round_trip(tmp_path):
    gm = synthetic(n=1234).baseline_corrected()
    path = tmp_path / "ROUND.AT2"
    gm.write_at2(path)
    back = read_at2(path)
    assert back.dt == gm.dt and back.a.size == gm.a.size
    np.testing.assert_allclose(back.a, gm.a, rtol=1e-15, atol=1e-300)
    assert "baseline_corrected" in back.metadata["description"]
    gm.write_at2(tmp_path / "CM.AT2", units="cm/s^2")
    np.testing.assert_allclose(read_at2(tmp_path / "CM.AT2").a, gm.a, rtol=1e-15)


def test_processing_errors_name_the_parameter():
    gm = synthetic(n=500)
    with pytest.raises(ValueError, match="`high`"):
        gm.filtered(high=60.0)
    with pytest.raises(ValueError, match="`low`"):
        gm.filtered(low=5.0, high=1.0)
    with pytest.raises(ValueError, match="pass `low`"):
        gm.filtered()
    with pytest.raises(ValueError, match="`dt`"):
        gm.resampled(-0.01)
    with pytest.raises(ValueError, match="`before`"):
        gm.padded(before=-1.0)
    with pytest.raises(ValueError, match="`threshold`"):
        gm.bracketed_duration(0.0)

"""Record processing behind the :class:`~duhamel.records.GroundMotion` methods: baseline
correction, Butterworth filtering with pads, resampling, padding, the Fourier amplitude
spectrum with Konno-Ohmachi smoothing, CAV, bracketed duration and the PEER ``.AT2``
writer. Each returns a new record whose ``metadata['processing']`` lists what was done."""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.memory import check_fits
from duhamel._engine.validate import (
    as_float_array,
    finite_float,
    flag,
    int_in_range,
    positive_float,
)
from duhamel.records.units import UNITS, _unit

#: A :class:`~duhamel.records.GroundMotion` (not imported here: the record's methods import
#: this module).
GroundMotion = Any

__all__ = [
    "FourierSpectrum",
    "baseline_corrected",
    "bracketed_duration",
    "cav",
    "filtered",
    "fourier",
    "konno_ohmachi",
    "padded",
    "resampled",
    "write_at2",
]


def _new(gm: GroundMotion, a: NDArray[np.float64], dt: float, step: dict[str, Any]) -> Any:
    """A record like `gm` with acceleration `a` (m/s^2) and `step` appended to its
    ``metadata['processing']``."""
    meta = dict(gm.metadata)
    meta["processing"] = [*meta.get("processing", []), step]
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{step['step']} of record {gm.name!r} gave non-finite values")
    return type(gm)(a, dt, "m/s^2", gm.name, meta)


def _seconds(value: Any, name: str, *, positive: bool = False) -> float:
    """`value` as a finite number of seconds (> 0 with `positive`, else >= 0); a string or
    another non-number is a TypeError."""
    v = finite_float(value, name)
    if v < 0.0 or (positive and v == 0.0):
        bound = "> 0" if positive else ">= 0"
        raise ValueError(f"`{name}` must be a finite number of seconds {bound}, got {value!r}")
    return v


def _samples(count: float, what: str, advice: str, arrays: int = 3) -> int:
    """`count` samples as an int, after checking that `arrays` float64 arrays of that many
    samples fit in memory: else a ValueError saying `what` asks for them (naming the
    parameter) and `advice`."""
    check_fits(8.0 * arrays * count, f"{what}: {count:.4g} samples", advice)
    return int(count)


def _integrate(a: NDArray[np.float64], dt: float) -> tuple[NDArray[np.float64], ...]:
    """Velocity and displacement (exact for piecewise-linear `a`, from rest) of the
    columns of `a` (shape ``(n,)`` or ``(n, k)``)."""
    v = np.zeros_like(a)
    np.cumsum(0.5 * dt * (a[1:] + a[:-1]), axis=0, out=v[1:])
    d = np.zeros_like(a)
    np.cumsum(v[:-1] * dt + dt * dt * (2.0 * a[:-1] + a[1:]) / 6.0, axis=0, out=d[1:])
    return v, d


def baseline_corrected(gm: GroundMotion, order: int = 3, zero_end: bool = True) -> Any:
    """The record minus the acceleration polynomial whose displacement best fits (least
    squares over the samples) the record's displacement: ``sum_k c_k t^k`` for ``k = 0 ..
    order - 2``, whose displacement from rest is a polynomial of degree `order`. With
    `zero_end`, the fit is constrained so that the corrected record ends with zero velocity
    and displacement (needs ``order >= 3``)."""
    order = int_in_range(order, "order", 2, 12, "the displacement polynomial's degree")
    zero_end = flag(zero_end, "zero_end")
    if zero_end and order < 3:
        raise ValueError("`zero_end=True` fixes two end values: `order` must be >= 3")
    n, dt = gm.a.size, gm.dt
    tau = np.arange(n, dtype=np.float64) / (n - 1)  # scaled time for conditioning
    basis = tau[:, None] ** np.arange(order - 1)[None, :]
    vb, db = _integrate(basis, dt)
    v, d = _integrate(gm.a, dt)
    if zero_end:
        # min |db c - d|^2 subject to [vb[-1]; db[-1]] c = [v[-1]; d[-1]]: the KKT system
        k = order - 1
        cons = np.vstack([vb[-1], db[-1]])
        kkt = np.zeros((k + 2, k + 2))
        kkt[:k, :k] = db.T @ db
        kkt[:k, k:] = cons.T
        kkt[k:, :k] = cons
        rhs = np.concatenate([db.T @ d, [v[-1], d[-1]]])
        c = np.linalg.lstsq(kkt, rhs, rcond=None)[0][:k]
    else:
        c = np.linalg.lstsq(db, d, rcond=None)[0]
    step = {"step": "baseline_corrected", "order": order, "zero_end": bool(zero_end)}
    step["coefficients"] = (c * (1.0 / ((n - 1) * dt)) ** np.arange(order - 1)).tolist()
    return _new(gm, gm.a - basis @ c, dt, step)


def _corners(low: float | None, high: float | None, dt: float) -> None:
    """The corner frequencies (Hz) within (0, Nyquist), `low` below `high`, one at least."""
    nyq = 0.5 / dt
    for name, f in (("low", low), ("high", high)):
        if f is not None and not (0.0 < f < nyq):
            raise ValueError(
                f"`{name}` must be a corner frequency in Hz between 0 and the Nyquist "
                f"frequency {nyq:g} Hz, got {f!r}"
            )
    if low is not None and high is not None and not low < high:
        raise ValueError(f"`low` ({low:g} Hz) must be below `high` ({high:g} Hz)")
    if low is None and high is None:
        raise ValueError("pass `low` (high-pass corner), `high` (low-pass corner) or both, in Hz")


def _butter(low: float | None, high: float | None, order: int, dt: float) -> Any:
    from scipy.signal import butter

    _corners(low, high, dt)
    if low is not None and high is not None:
        return butter(order, [low, high], "bandpass", fs=1.0 / dt, output="sos")
    if low is not None:
        return butter(order, low, "highpass", fs=1.0 / dt, output="sos")
    return butter(order, high, "lowpass", fs=1.0 / dt, output="sos")


def filter_pad(
    low: float | None, high: float | None, order: int, dt: float, n: int | None = None
) -> int:
    """Samples of zeros added at each end before filtering: ``1.5 order / f`` seconds for
    the lowest corner f (Converse and Brady 1992; Boore 2005), at least 10 samples. With the
    record's `n` samples, a padded record that would not fit in memory is refused, naming
    the corner (`low`, or `high` for a low-pass filter)."""
    name, f = ("low", low) if low is not None else ("high", high)
    assert f is not None
    with np.errstate(over="ignore"):
        pad = max(10.0, float(np.ceil(1.5 * order / f / dt)))
    if n is not None:
        what = f"`{name}` = {f:g} Hz pads the record with 1.5 order / {name} s of zeros each side"
        advice = (
            f"raise `{name}` (a corner below 1 / duration = {1.0 / ((n - 1) * dt):.3g} Hz "
            "acts on periods longer than the record)"
        )
        _samples(n + 2.0 * pad, what, advice, arrays=6)
    return int(pad)


def filtered(
    gm: GroundMotion,
    low: float | None = None,
    high: float | None = None,
    order: int = 4,
    zero_phase: bool = True,
    keep_padding: bool = False,
) -> Any:
    """Butterworth filter (second-order sections) of the record padded with zeros at both
    ends; see :meth:`GroundMotion.filtered`."""
    order = int_in_range(order, "order", 1, 20, "the Butterworth filter's order")
    low = None if low is None else positive_float(low, "low")
    high = None if high is None else positive_float(high, "high")
    zero_phase = flag(zero_phase, "zero_phase")
    keep_padding = flag(keep_padding, "keep_padding")
    _corners(low, high, gm.dt)  # checked before the pads are sized, the filter designed
    pad = filter_pad(low, high, order, gm.dt, gm.a.size)
    sos = _butter(low, high, order, gm.dt)
    x = np.pad(gm.a, (pad, pad))
    from scipy.signal import sosfilt, sosfiltfilt

    y = sosfiltfilt(sos, x, padtype=None) if zero_phase else sosfilt(sos, x)
    if not keep_padding:
        y = y[pad:-pad]
    step = {"step": "filtered", "low": low, "high": high, "order": order}
    step.update(zero_phase=bool(zero_phase), pad=pad, keep_padding=bool(keep_padding))
    return _new(gm, np.ascontiguousarray(y), gm.dt, step)


def resampled(gm: GroundMotion, dt: float, antialias: bool = True) -> Any:
    """The piecewise-linear record read at the samples ``k dt`` (up to its end); a coarser
    `dt` is first low-passed at 0.8 of the new Nyquist frequency (8th order, zero phase)
    unless ``antialias=False``."""
    new = _seconds(dt, "dt", positive=True)
    antialias = flag(antialias, "antialias")
    with np.errstate(over="ignore"):
        count = float(np.floor(gm.duration / new * (1 + 1e-12))) + 1.0
    if count < 2:
        raise ValueError(f"`dt` = {new:g} s leaves fewer than 2 samples of the record")
    what = f"`dt` = {new:g} s resamples the {gm.duration:g} s record"
    n = _samples(count, what, "pass a larger `dt`")
    src = gm
    if new > gm.dt * (1 + 1e-12) and antialias:
        src = filtered(gm, high=0.8 * 0.5 / new, order=8)
    a = np.interp(new * np.arange(n), src.t, src.a)
    step = {"step": "resampled", "dt": new, "from_dt": gm.dt, "antialias": src is not gm}
    return _new(src, a, new, step)


def padded(gm: GroundMotion, before: float = 0.0, after: float = 0.0) -> Any:
    """Zeros added: `before` and `after` in seconds (rounded up to whole samples)."""
    seconds = {"before": _seconds(before, "before"), "after": _seconds(after, "after")}
    with np.errstate(over="ignore"):
        counts = {k: float(np.ceil(v / gm.dt - 1e-9)) for k, v in seconds.items()}
    name = max(counts, key=lambda k: counts[k])  # the one that makes the record long
    what = f"`{name}` = {seconds[name]:g} s of zeros makes the padded record"
    total = counts["before"] + counts["after"] + gm.a.size
    _samples(total, what, f"pass a shorter `{name}`", arrays=2)
    nb, na = int(counts["before"]), int(counts["after"])
    step = {"step": "padded", "before": nb * gm.dt, "after": na * gm.dt}
    return _new(gm, np.pad(gm.a, (nb, na)), gm.dt, step)


def cav(gm: GroundMotion) -> float:
    """Cumulative absolute velocity, the exact integral of ``|a|`` (m/s)."""
    a0, a1 = gm.a[:-1], gm.a[1:]
    same = a0 * a1 >= 0.0
    s = np.abs(a0) + np.abs(a1)
    safe = np.where(s > 0.0, s, 1.0)
    seg = np.where(same, 0.5 * s, 0.5 * (a0 * a0 + a1 * a1) / safe)
    return float(gm.dt * seg.sum())


def bracketed_duration(gm: GroundMotion, threshold: float, units: str = "g") -> float:
    """Time between the first and the last instant ``|a|`` reaches `threshold` (in
    `units`, default g), located exactly on the piecewise-linear record; 0 if never."""
    thr = positive_float(threshold, "threshold") * UNITS[_unit(units)]
    if not (np.isfinite(thr) and thr > 0.0):
        raise ValueError(f"`threshold` must be a positive acceleration, got {threshold!r}")
    a = np.abs(gm.a)
    above = np.flatnonzero(a >= thr)
    if above.size == 0:
        return 0.0
    i, j = int(above[0]), int(above[-1])

    def crossing(k: int, m: int) -> float:
        """Time where |a| = thr on the segment from sample k (below) to m (at or above)."""
        ak, am = gm.a[k], gm.a[m]
        frac = (np.sign(am) * thr - ak) / (am - ak)
        return gm.dt * (k + (m - k) * float(np.clip(frac, 0.0, 1.0)))

    t0 = crossing(i - 1, i) if i > 0 else 0.0
    t1 = crossing(j + 1, j) if j < a.size - 1 else gm.duration
    return float(t1 - t0)


@dataclass(frozen=True, eq=False)
class FourierSpectrum:
    """Fourier amplitude spectrum ``|A(f)|`` in m/s (the continuous transform of the
    record, approximated by ``dt |FFT(a)|``) at ``frequency`` (Hz); ``smoothed`` is the
    Konno-Ohmachi average (or None)."""

    frequency: NDArray[np.float64]
    amplitude: NDArray[np.float64]
    smoothed: NDArray[np.float64] | None = None
    bandwidth: float | None = None

    def plot(self, ax: Any = None) -> Any:
        """Amplitude (and the smoothed one) against frequency, log axes."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(6.5, 4.5))
        f = self.frequency[1:]
        ax.loglog(f, self.amplitude[1:], color="0.6", lw=0.6, label="FAS")
        if self.smoothed is not None:
            ax.loglog(f, self.smoothed[1:], lw=1.5, label=f"Konno-Ohmachi b={self.bandwidth:g}")
        ax.set_xlabel("Frequency [Hz]")
        ax.set_ylabel("Fourier amplitude [m/s]")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize="small")
        return ax


def konno_ohmachi(
    frequency: ArrayLike, amplitude: ArrayLike, bandwidth: float = 40.0, centres: Any = None
) -> NDArray[np.float64]:
    """Konno and Ohmachi (1998) smoothing: at each centre ``fc`` the average of the
    amplitudes weighted by ``W(f) = [sin(b log10(f/fc)) / (b log10(f/fc))]^4`` (1 at
    ``f = fc``, 0 at ``f = 0``); centres default to the frequencies themselves (0 stays 0)."""
    f = as_float_array(frequency, "frequency", ndim=1)
    s = as_float_array(amplitude, "amplitude", ndim=1)
    b = positive_float(bandwidth, "bandwidth")
    fc = f if centres is None else as_float_array(centres, "centres", ndim=1)
    out = np.zeros(fc.size)
    pos = f > 0.0
    lf, sp = np.log10(f[pos]), s[pos]
    for lo in range(0, fc.size, 256):  # blocks of centres: (256, n) weights at a time
        c = fc[lo : lo + 256]
        ok = c > 0.0
        x = b * (lf[None, :] - np.log10(np.where(ok, c, 1.0))[:, None])
        small = np.abs(x) < 1e-3  # sin(x)/x to round-off: 1 - x^2/6 + x^4/120
        w = np.where(small, 1.0 - x * x / 6.0 + x**4 / 120.0, np.sin(x) / np.where(small, 1, x))
        w = w**4
        out[lo : lo + 256] = np.where(ok, (w @ sp) / w.sum(axis=1), 0.0)
    return out


def fourier(gm: GroundMotion, smoothing: float | None = None, n_fft: int | None = None) -> Any:
    """The Fourier amplitude spectrum ``dt |FFT(a)|`` at ``k / (n_fft dt)``, with
    Konno-Ohmachi smoothing of bandwidth `smoothing` (b, typically 20 to 40) if given."""
    b = None if smoothing is None else positive_float(smoothing, "smoothing")
    n = gm.a.size if n_fft is None else int_in_range(n_fft, "n_fft", 1, 2**62, "an FFT length")
    if n < gm.a.size:
        raise ValueError(f"`n_fft` must be >= the record's {gm.a.size} samples, got {n_fft}")
    what = f"`n_fft` = {n} zero-pads the record for its transform"
    _samples(n, what, "pass a smaller `n_fft`", arrays=4)
    amp = gm.dt * np.abs(np.fft.rfft(gm.a, n))
    f = np.fft.rfftfreq(n, gm.dt)
    sm = None if b is None else konno_ohmachi(f, amp, b)
    return FourierSpectrum(f, amp, sm, b)


def write_at2(gm: GroundMotion, path: str | os.PathLike[str], units: str = "g") -> None:
    """Write the record as a PEER NGA-West2 ``.AT2`` file (values in `units`, 17
    significant digits, five per line) that :func:`~duhamel.records.read_at2` reads back
    exactly."""
    u = _unit(units)
    label = {"g": "G", "cm/s^2": "CM/S^2", "m/s^2": "M/S^2"}.get(u, u.upper())
    title = str(gm.metadata.get("title", "PEER NGA STRONG MOTION DATABASE RECORD (duhamel)"))
    event = str(gm.metadata.get("event", gm.name or "record"))
    done = [p.get("step", "?") for p in gm.metadata.get("processing", [])]
    desc = "ACCELERATION TIME SERIES IN UNITS OF " + label
    if done:
        desc += "   (" + ", ".join(done) + ")"
    values = gm.a / UNITS[u]
    lines = [title, event, desc, f"NPTS= {values.size:7d}, DT= {gm.dt:.10g} SEC"]
    for k in range(0, values.size, 5):
        lines.append("".join(f"{v:25.16E}" for v in values[k : k + 5]))
    with open(os.fspath(path), "w", encoding="latin-1") as fh:
        fh.write("\n".join(lines) + "\n")

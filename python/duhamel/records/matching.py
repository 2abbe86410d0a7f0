"""Spectral matching of a record (or of a pair, in RotD100) to a target spectrum by
wavelet adjustment (:func:`match`); exported from :mod:`duhamel.records`.

The record is decomposed, as in REQPY (Montejo and Suarez 2013; Montejo 2021), on the
Suarez-Montejo wavelet ``psi(t) = exp(-zeta Omega |t|) sin(Omega t)`` at scales whose
periods cover the matching range, each scale's component is multiplied by the ratio of the
target to the record's spectrum at its period, and the components are summed again; this
repeats until the spectrum is within the tolerance. Scaling a scale's continuous-wavelet
coefficients by one number over the whole record is a linear time-invariant operation:
its frequency response is the wavelets' energy ``|psi_hat_j(f)|^2`` weighted by the
ratios. It is applied here in that form, with the weights normalised so that ratios of 1
give the record back exactly, and with zero padding so that the adjustment does not wrap
around; the phase of the record, and so its non-stationary character, is kept. Each
iterate is baseline-corrected (:meth:`GroundMotion.baseline_corrected`, ending at rest),
so the spectrum measured is the returned record's.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.validate import (
    as_float_array,
    finite_float,
    flag,
    int_in_range,
)
from duhamel.errors import MatchWarning
from duhamel.records.motion import GroundMotion
from duhamel.records.pair import GroundMotionPair
from duhamel.records.wavelets import TimeDomainStep

__all__ = ["match"]

#: Ratio of neighbouring periods of the time-domain stage.
TD_SPACING = 1.03
#: Matching stops inside the band narrowed at each end by this fraction of the distance to
#: the aim (the spectrum is checked 1 % apart; between those periods it may stray a little
#: further).
MARGIN = 0.1


@dataclass(frozen=True)
class _Bank:
    """The wavelet bank on the padded record's FFT frequencies: normalised weights
    ``(n_scales, n_freq)`` with ``sum_j w_j(f) <= 1`` (1 inside the band, decaying to 0
    outside it)."""

    periods: NDArray[np.float64]
    weights: NDArray[np.float64]


def _bank(periods: NDArray[np.float64], freqs: NDArray[np.float64], zeta: float) -> _Bank:
    omega = 2.0 * np.pi * freqs[None, :]
    big = 2.0 * np.pi / periods[:, None]
    a = zeta * big

    def lorentz(x: NDArray[np.float64]) -> NDArray[np.float64]:
        return 2.0 * a / (a * a + x * x)

    energy = 0.25 * (lorentz(omega - big) - lorentz(omega + big)) ** 2
    energy /= energy.max(axis=1, keepdims=True)
    total = energy.sum(axis=0)
    floor = 0.05 * total.max()  # outside the band the weights fade: the record is kept
    return _Bank(periods, energy / (total + floor)[None, :])


def _gain(bank: _Bank, log_ratio: NDArray[np.float64]) -> NDArray[np.float64]:
    """``exp(sum_j w_j(f) ln r_j)``: ratios of 1 give a gain of 1 everywhere."""
    return np.exp(log_ratio @ bank.weights)


def _spectrum(rec: Any, periods: NDArray[np.float64], damping: float) -> NDArray[np.float64]:
    if isinstance(rec, GroundMotionPair):
        return rec.rotd100(periods, damping)
    from duhamel.spectra.response import response_spectrum

    return np.asarray(response_spectrum(rec, periods, damping).psa[0, 0])


def _check_range(periods: Any, target: Any) -> tuple[float, float]:
    from duhamel.spectra.target import check_target

    check_target(target)
    p = as_float_array(periods, "periods", finite=False).ravel()
    if p.size != 2 or not (np.all(np.isfinite(p)) and 0.0 < p[0] < p[1]):
        raise ValueError(
            f"`periods` must be the matching range (lo, hi) with 0 < lo < hi s, got {periods}"
        )
    if p[0] < target.periods[0] or p[1] > target.periods[-1]:
        raise ValueError(
            f"`periods` ({p[0]:g}, {p[1]:g}) s leaves the target's periods "
            f"[{target.periods[0]:g}, {target.periods[-1]:g}] s"
        )
    return float(p[0]), float(p[1])


def match(
    record: GroundMotion | GroundMotionPair,
    target: Any,
    periods: ArrayLike,
    damping: float = 0.05,
    *,
    tolerance: float | tuple[float, float] = (0.9, 1.3),
    aim: float | None = None,
    max_iterations: int = 40,
    frequency_iterations: int = 6,
    n_scales: int | None = None,
    prescale: bool = True,
    baseline_order: int = 5,
) -> Any:
    """Match a record's spectrum (a pair's RotD100 spectrum) to `target` over a range.

    Parameters
    ----------
    record : GroundMotion or GroundMotionPair
        A pair is matched in RotD100 (both components adjusted by the same wavelet ratios,
        Montejo 2021).
    target : TargetSpectrum
    periods : (float, float)
        The matching range in s.
    damping : float, optional
        Damping of the spectra (default 0.05).
    tolerance : float or (float, float), optional
        The acceptance band of ``S(T) / target(T)`` at every period of the range (checked
        on a grid of 1 % spacing): ``(low, high)``, default ``(0.9, 1.3)``, or ``tol`` for
        ``(1 - tol, 1 + tol)``. Matching stops as soon as the spectrum is inside the band
        narrowed at each end by a tenth of its distance to the aim (so that periods between
        the checked ones stay in it).
    aim : float, optional
        The ratio to the target the adjustments aim at (default: the band's geometric
        centre, 1.08 for the default band, 1 for a symmetric tolerance). The adjustments
        leave the spectrum a few per cent around the aim between the matching periods; an
        aim above 1 keeps it above the target, as ASCE 7-16 section 16.2.3.3 asks of matched
        records (110 % of the target on average).
    max_iterations : int, optional
        At most this many adjustments in all (default 40); if the tolerance is not reached
        a :class:`duhamel.errors.MatchWarning` says by how much.
    frequency_iterations : int, optional
        Adjustments of the first stage (wavelet ratios over the whole record, REQPY's way;
        default 6) before the time-domain stage (wavelets at the oscillators' peaks,
        RspMatch's way) takes over.
    n_scales : int, optional
        Wavelet scales (log-spaced periods over the range widened by 20 % each side);
        default: one per 2 % of period, at least 60.
    prescale : bool, optional
        First scale the record to the target's least-squares fit over the range (the
        record matching starts from; its factor is reported).
    baseline_order : int, optional
        Degree of the baseline polynomial removed at each iteration (default 5).

    Returns
    -------
    GroundMotion or GroundMotionPair
        The matched record: the first iterate inside the band, or the one closest to it
        (``metadata['match']['kept']`` says which; 0 is the prescaled record).
        ``metadata['match']`` (of each component, for a pair) holds ``iterations``
        (adjustments made), ``misfit`` (largest ``|S/target - 1|`` over the range, on a
        grid of 1 % spacing), ``rms_misfit``, ``min_ratio``, ``max_ratio``, ``converged``
        (inside the band), ``scale`` (the prescaling factor), the range, the band and the
        aim.

    Examples
    --------
    >>> import numpy as np
    >>> from duhamel.records import GroundMotion, match
    >>> from duhamel.spectra import asce7
    >>> rng = np.random.default_rng(1)
    >>> t = np.arange(4000) * 0.01
    >>> gm = GroundMotion(rng.standard_normal(4000) * t * np.exp(-t / 5) / 5, 0.01, "g")
    >>> m = match(gm, asce7(1.0, 0.6, 8.0), (0.1, 3.0))
    >>> info = m.metadata["match"]
    >>> bool(info["converged"] and 0.9 <= info["min_ratio"] and info["max_ratio"] <= 1.3)
    True
    """
    if not isinstance(record, GroundMotion | GroundMotionPair):
        raise TypeError(
            f"`record` must be a GroundMotion or GroundMotionPair, got {type(record).__name__}"
        )
    lo, hi = _check_range(periods, target)
    zeta = finite_float(damping, "damping")
    if not 0.0 < zeta < 1.0:
        raise ValueError(f"`damping` must be a ratio in (0, 1), got {damping!r}")
    low, high = _band(tolerance)
    aim = float(np.sqrt(low * high)) if aim is None else finite_float(aim, "aim")
    if not low < aim < high:
        raise ValueError(f"`aim` must lie inside the band ({low:g}, {high:g}), got {aim!r}")
    max_iterations = int_in_range(max_iterations, "max_iterations", 1, 10_000, "adjustments")
    frequency_iterations = int_in_range(
        frequency_iterations, "frequency_iterations", 0, 10_000, "adjustments"
    )
    if n_scales is not None:
        n_scales = int_in_range(n_scales, "n_scales", 2, 100_000, "a number of wavelet scales")
    # each iterate ends at rest (zero velocity and displacement): a degree of 3 at least
    meaning = "the degree of the baseline displacement polynomial"
    baseline_order = int_in_range(baseline_order, "baseline_order", 3, 12, meaning)
    prescale = flag(prescale, "prescale")
    if not any(np.any(c.a) for c in (record if isinstance(record, GroundMotionPair) else [record])):
        raise ValueError(
            f"`record` {record.name!r} is zero at every sample: it has no spectrum to match "
            "(the wavelets adjust what the record holds)"
        )
    tmin = max(lo / 1.2, target.periods[target.periods > 0][0], 2.5 * record.dt)
    tmax = min(hi * 1.2, target.periods[-1])
    if n_scales is None:
        n_scales = max(60, int(np.ceil(np.log(tmax / tmin) / np.log(1.02))))
    scales = np.geomspace(tmin, tmax, int(n_scales))
    # the periods checked: 1 % apart over the range, finer than the scales
    check = np.geomspace(lo, hi, int(np.ceil(np.log(hi / lo) / np.log(1.01))) + 1)
    want = aim * target(scales)
    target_check = target(check)

    comps = list(record) if isinstance(record, GroundMotionPair) else [record]
    scale = 1.0
    if prescale:
        s0 = _spectrum(record, check, zeta)
        scale = float(np.exp(np.mean(np.log(target_check / s0))))
    dt, n = record.dt, comps[0].a.size
    pad = int(np.ceil(4.0 * tmax / dt))
    n_fft = _fast_len(n + 2 * pad)
    spectra0 = [np.fft.rfft(np.pad(scale * c.a, (pad, n_fft - n - pad))) for c in comps]
    bank = _bank(scales, np.fft.rfftfreq(n_fft, dt), zeta)
    log_r = np.zeros(scales.size)

    def build(log_ratio: NDArray[np.float64]) -> Any:
        g = _gain(bank, log_ratio)
        arrays = [np.fft.irfft(g * f0, n_fft)[pad : pad + n] for f0 in spectra0]
        return _assemble(arrays, comps, dt, baseline_order, record.name)

    both = np.unique(np.concatenate([scales, check]))
    at_scales, at_check = np.searchsorted(both, scales), np.searchsorted(both, check)
    best: tuple[tuple[float, float], int, Any] | None = None
    iterations = 0

    def score(ratio: NDArray[np.float64], margin: float = MARGIN) -> tuple[float, float]:
        """(violation of the band narrowed by `margin`, misfit to the aim): smaller is
        better. The margin keeps the periods between the checked ones inside the band."""
        lo_m, hi_m = low + margin * (aim - low), high - margin * (high - aim)
        out = max(0.0, lo_m - float(ratio.min())) + max(0.0, float(ratio.max()) - hi_m)
        return out, float(np.max(np.abs(ratio / aim - 1.0)))

    # stage 1: the wavelet (CWT) ratios, REQPY's way, while it improves quickly
    current = build(log_r)
    while True:
        s_all = _spectrum(current, both, zeta)
        sc = score(s_all[at_check] / target_check)
        if best is None or sc < best[0]:
            best = (sc, iterations, current)
        if sc[0] == 0.0 or iterations >= min(int(max_iterations), frequency_iterations):
            break
        log_r += np.log(want / s_all[at_scales])
        current = build(log_r)
        iterations += 1
    # stage 2: time-domain wavelets at the peaks (RspMatch's way) from the best so far
    current = best[2]
    if best[0][0] > 0.0 and iterations < int(max_iterations):
        n_td = max(20, int(np.ceil(np.log(tmax / tmin) / np.log(TD_SPACING))))
        td_periods = np.geomspace(tmin, tmax, n_td)
        stepper = TimeDomainStep(td_periods, n, dt, zeta)
        want_td = aim * target(td_periods)
        while iterations < int(max_iterations):
            parts = list(current) if isinstance(current, GroundMotionPair) else [current]
            ratio_td = want_td / _spectrum(current, td_periods, zeta)
            arrays = stepper.step([c.a for c in parts], ratio_td)
            current = _assemble(arrays, comps, dt, baseline_order, record.name)
            iterations += 1
            sc = score(_spectrum(current, check, zeta) / target_check)
            if sc < best[0]:
                best = (sc, iterations, current)
            if sc[0] == 0.0:
                break
    _, kept, current = best
    ratio = _spectrum(current, check, zeta) / target_check
    converged = score(ratio, 0.0)[0] == 0.0
    info = {
        "iterations": iterations,
        "kept": kept,
        "misfit": float(np.max(np.abs(ratio - 1.0))),
        "rms_misfit": float(np.sqrt(np.mean((ratio - 1.0) ** 2))),
        "min_ratio": float(ratio.min()),
        "max_ratio": float(ratio.max()),
        "converged": bool(converged),
        "scale": scale,
        "range": (lo, hi),
        "band": (low, high),
        "aim": aim,
        "damping": zeta,
    }
    if not converged:
        warnings.warn(
            f"match of {record.name!r}: after {iterations} iterations the spectrum is "
            f"{ratio.min():.3f} to {ratio.max():.3f} times the target over ({lo:g}, {hi:g}) s, "
            f"outside the band ({low:g}, {high:g})",
            MatchWarning,
            stacklevel=2,
        )
    return _tag(current, info)


def _band(tolerance: Any) -> tuple[float, float]:
    """(low, high) ratios of the acceptance band from a tolerance or a band."""
    if np.ndim(tolerance) == 0:
        tol = finite_float(tolerance, "tolerance")
        if not 0.0 < tol < 1.0:
            raise ValueError(
                f"`tolerance` must be in (0, 1) or a band (low, high), got {tolerance!r}"
            )
        return 1.0 - tol, 1.0 + tol
    b = as_float_array(tolerance, "tolerance", finite=False).ravel()
    if b.size != 2 or not (np.all(np.isfinite(b)) and 0.0 < b[0] < 1.0 < b[1]):
        raise ValueError(
            f"`tolerance` must be a band (low, high) with 0 < low < 1 < high, got {tolerance!r}"
        )
    return float(b[0]), float(b[1])


def _assemble(
    arrays: list[NDArray[np.float64]], like: list[GroundMotion], dt: float, order: int, name: str
) -> Any:
    """Baseline-corrected GroundMotions (a pair for two) from component arrays."""
    out = [
        GroundMotion(a, dt, "m/s^2", c.name, c.metadata).baseline_corrected(order, zero_end=True)
        for a, c in zip(arrays, like, strict=True)
    ]
    return GroundMotionPair(out[0], out[1], name) if len(out) == 2 else out[0]


def _tag(rec: Any, info: dict[str, Any]) -> Any:
    """`rec` with ``metadata['match']`` and a processing step saying what was done."""
    step = {"step": "matched", **{k: info[k] for k in ("iterations", "misfit", "scale")}}

    def tagged(gm: GroundMotion) -> GroundMotion:
        meta = dict(gm.metadata)
        meta["match"] = info
        meta["processing"] = [*meta.get("processing", []), step]
        return GroundMotion(gm.a, gm.dt, "m/s^2", gm.name, meta)

    if isinstance(rec, GroundMotionPair):
        return GroundMotionPair(tagged(rec.first), tagged(rec.second), rec.name)
    return tagged(rec)


def _fast_len(n: int) -> int:
    """The smallest 2^a 3^b 5^c >= n (a fast FFT length)."""
    best = 1 << int(np.ceil(np.log2(n)))
    f5 = 1
    while f5 < best:
        f35 = f5
        while f35 < best:
            m = f35
            while m < n:
                m *= 2
            best = min(best, m)
            f35 *= 3
        f5 *= 5
    return best

"""Amplitude scaling of a suite of records or pairs to a target spectrum
(:func:`scale_suite`): the ASCE 7-22 section 16.2.3 criterion, least squares per record,
Sa at one period; exported from :mod:`duhamel.records`."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel._engine.validate import as_float_array, finite_float, flag, int_in_range
from duhamel.records.motion import G, GroundMotion
from duhamel.records.pair import GroundMotionPair
from duhamel.records.suite import Suite

__all__ = ["CriterionTable", "ScaledSuite", "record_spectra", "scale_suite"]

Record = GroundMotion | GroundMotionPair
METHODS = ("asce7", "least_squares", "sa")


@dataclass(frozen=True, eq=False)
class CriterionTable:
    """The criterion at each period of the range: the target, the suite's mean spectrum
    (of the scaled records; RotD100 of pairs), their ratio and whether the mean reaches
    ``fraction`` of the target there."""

    period: NDArray[np.float64]
    target: NDArray[np.float64]
    mean: NDArray[np.float64]
    fraction: float

    @property
    def ratio(self) -> NDArray[np.float64]:
        """Mean over target."""
        return self.mean / self.target

    @property
    def passes(self) -> NDArray[np.bool_]:
        """Per period: ``mean >= fraction * target`` (to 1e-12 relative)."""
        return self.mean >= self.fraction * self.target * (1.0 - 1e-12)

    def to_dataframe(self) -> Any:
        """A ``pandas.DataFrame`` (needs pandas) with Sa in g."""
        import pandas as pd

        return pd.DataFrame(
            {
                "period_s": self.period,
                "target_g": self.target / G,
                "mean_g": self.mean / G,
                "ratio": self.ratio,
                "passes": self.passes,
            }
        )

    def __str__(self) -> str:
        rows = [f"{'T [s]':>8} {'target [g]':>11} {'mean [g]':>10} {'ratio':>7}  passes"]
        for t, a, m, r, ok in zip(
            self.period, self.target / G, self.mean / G, self.ratio, self.passes, strict=True
        ):
            rows.append(f"{t:8.4g} {a:11.4g} {m:10.4g} {r:7.3f}  {'yes' if ok else 'NO'}")
        return "\n".join(rows)


@dataclass(frozen=True, eq=False)
class ScaledSuite:
    """The result of :func:`scale_suite`.

    Attributes
    ----------
    factors : ndarray
        One amplitude factor per record or pair.
    records : list
        The scaled records (GroundMotion or GroundMotionPair), in the input order.
    table : CriterionTable
        The criterion (mean scaled spectrum against ``fraction`` of the target) at each
        period of the range.
    passes : bool
        Whether the criterion holds at every period of the range.
    spectra : ndarray
        The unscaled spectra, ``(n_records, n_periods)`` at ``table.period`` (m/s^2):
        pseudo-acceleration of single records, RotD100 of pairs.
    method : str
    names : list of str
    """

    factors: NDArray[np.float64]
    records: list[Record]
    table: CriterionTable
    passes: bool
    spectra: NDArray[np.float64]
    method: str
    names: list[str]
    originals: list[Record]
    target: Any

    @property
    def suite(self) -> Suite:
        """The records, factors and names as a :class:`~duhamel.records.Suite` for
        :func:`duhamel.ensemble.solve_many`."""
        return Suite(self.originals, self.factors, self.names)

    def plot(self, ax: Any = None, periods: Any = None) -> Any:
        """The scaled spectra (thin), their mean (thick), the target and ``fraction`` of it,
        the range shaded; at the criterion's periods, or at `periods` (s, computed here)
        to see the spectra beyond the range. Returns the matplotlib Axes."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(6.5, 4.5))
        if periods is None:
            p, spectra = self.table.period, self.spectra
        else:
            p = np.asarray(periods, dtype=np.float64)
            p = p[(p >= self.target.periods[0]) & (p <= self.target.periods[-1]) & (p > 0)]
            spectra = record_spectra(self.originals, p, self.target.damping)
        scaled = self.factors[:, None] * spectra
        for s in scaled:
            ax.plot(p, s / G, color="0.7", lw=0.7)
        ax.plot(p, scaled.mean(axis=0) / G, lw=2.0, label="suite mean")
        ax.plot(p, self.target(p) / G, "k", lw=1.5, label="target")
        frac = self.table.fraction
        ax.plot(p, frac * self.target(p) / G, "k--", lw=1.0, label=f"{100 * frac:g} % target")
        lo, hi = self.table.period[0], self.table.period[-1]
        ax.axvspan(lo, hi, color="C1", alpha=0.12, label="range")
        ax.set_xscale("log")
        ax.set_xlabel("Period [s]")
        ax.set_ylabel("Sa [g]")
        ax.set_title(f"{self.method}: {'passes' if self.passes else 'FAILS'}", fontsize="small")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize="small")
        return ax


def record_spectra(
    records: Sequence[Record], periods: NDArray[np.float64], damping: float = 0.05
) -> NDArray[np.float64]:
    """Spectra used for scaling, ``(n_records, n_periods)`` in m/s^2: the 5 %-damped
    pseudo-acceleration of a single record, the maximum-direction (RotD100) spectrum of a
    pair (ASCE 7-22 section 16.2.3.2)."""
    from duhamel.spectra.response import response_spectrum

    out = np.empty((len(records), periods.size))
    singles = [i for i, r in enumerate(records) if isinstance(r, GroundMotion)]
    if singles:
        rs = response_spectrum([records[i] for i in singles], periods, damping)
        out[singles] = rs.psa[:, 0, :]
    for i, r in enumerate(records):
        if isinstance(r, GroundMotionPair):
            out[i] = r.rotd100(periods, damping)
    return out


def _records(records_or_pairs: Any) -> list[Record]:
    if isinstance(records_or_pairs, GroundMotion | GroundMotionPair):
        return [records_or_pairs]
    if (
        isinstance(records_or_pairs, str | bytes)
        or not isinstance(records_or_pairs, Sequence | np.ndarray)
        or np.ndim(records_or_pairs) == 0
    ):
        raise TypeError(
            "`records_or_pairs` must be a GroundMotion, a GroundMotionPair or a sequence of "
            f"them, got {type(records_or_pairs).__name__}"
        )
    items = list(records_or_pairs)
    if not items:
        raise ValueError("`records_or_pairs` is empty")
    for i, r in enumerate(items):
        if not isinstance(r, GroundMotion | GroundMotionPair):
            raise TypeError(
                f"`records_or_pairs[{i}]` must be a GroundMotion or GroundMotionPair, got "
                f"{type(r).__name__}"
            )
    return items


def _range(period_range: Any, target: Any) -> tuple[float, float]:
    from duhamel.spectra.target import check_target

    check_target(target)
    p = as_float_array(period_range, "period_range", finite=False).ravel()
    if p.size not in (1, 2):
        raise ValueError(
            f"`period_range` must be (lo, hi) in s, or one period for method='sa', got {p.size} "
            "values"
        )
    lo, hi = float(p[0]), float(p[-1])
    if not (np.isfinite(lo) and np.isfinite(hi) and 0.0 < lo <= hi):
        raise ValueError(f"`period_range` must be (lo, hi) with 0 < lo <= hi s, got {period_range}")
    tp = target.periods
    if lo < tp[0] or hi > tp[-1]:
        raise ValueError(
            f"`period_range` ({lo:g}, {hi:g}) s leaves the target's periods "
            f"[{tp[0]:g}, {tp[-1]:g}] s"
        )
    return lo, hi


def scale_suite(
    records_or_pairs: Any,
    target: Any,
    period_range: Any,
    *,
    method: str = "asce7",
    minimise_misfit: bool = False,
    fraction: float = 0.9,
    damping: float = 0.05,
    n_periods: int = 100,
) -> ScaledSuite:
    """Amplitude scaling of records or pairs (one factor per pair) to a target spectrum.

    Methods:

    * ``'asce7'``: ASCE 7-22 section 16.2.3.2 (amplitude scaling): the mean over the suite of
      the scaled maximum-direction (RotD100) spectra must not fall below ``fraction`` (90 %)
      of the target at any period of the range. With one common factor (default) the factor
      is the smallest that satisfies it, ``max_T fraction target(T) / mean_i S_i(T)``; with
      ``minimise_misfit=True`` each record is first fitted to the target (the least-squares
      factor of ``'least_squares'``) and then all are multiplied by the smallest common
      factor that satisfies the criterion.
    * ``'least_squares'``: per record, the factor minimising ``sum_T (ln(f S_i(T)) -
      ln target(T))^2`` over the periods of the range (log-spaced): ``f_i = exp(mean ln(
      target / S_i))``.
    * ``'sa'``: per record, ``target(T1) / S_i(T1)`` at the period ``T1 = period_range``
      (one number).

    The criterion's table is computed for every method.

    Parameters
    ----------
    records_or_pairs : sequence of GroundMotion or GroundMotionPair
    target : TargetSpectrum
    period_range : (float, float) or float
        The range in s (for ``'sa'``, the period).
    method : {'asce7', 'least_squares', 'sa'}, optional
    minimise_misfit : bool, optional
        For ``'asce7'``: fit each record first (see above).
    fraction : float, optional
        Of the target the mean must reach (0.9 in ASCE 7-22 16.2.3.2).
    damping : float, optional
        Damping of the spectra (default 0.05, the target's).
    n_periods : int, optional
        Log-spaced periods of the range (default 100), with the target's own table periods
        in the range (for a code spectrum, its corner periods) added.

    Returns
    -------
    ScaledSuite

    Examples
    --------
    >>> import numpy as np
    >>> from duhamel.records import GroundMotion, scale_suite
    >>> from duhamel.spectra import asce7
    >>> rng = np.random.default_rng(0)
    >>> recs = [GroundMotion(rng.standard_normal(2000) * 0.1, 0.01, "g") for _ in range(3)]
    >>> res = scale_suite(recs, asce7(1.0, 0.6, 8.0), (0.2, 2.0))
    >>> bool(res.passes), bool(np.isclose(res.table.ratio.min(), 0.9))
    (True, True)
    """
    items = _records(records_or_pairs)
    if not isinstance(method, str) or method not in METHODS:
        raise ValueError(f"`method` must be one of {METHODS}, got {method!r}")
    minimise_misfit = flag(minimise_misfit, "minimise_misfit")
    lo, hi = _range(period_range, target)
    frac = finite_float(fraction, "fraction")
    if not 0.0 < frac <= 2.0:
        raise ValueError(f"`fraction` must be in (0, 2], got {fraction!r}")
    damping = finite_float(damping, "damping")
    if not 0.0 <= damping < 1.0:
        raise ValueError(f"`damping` must be a ratio in [0, 1), got {damping!r}")
    n_periods = int_in_range(n_periods, "n_periods", 2, 100_000, "a number of periods")
    if lo == hi:
        periods = np.array([lo])
    else:
        own = _corners(target)
        own = own[(own >= lo) & (own <= hi)]
        periods = np.unique(np.concatenate([np.geomspace(lo, hi, int(n_periods)), own]))
    sa = target(periods)
    spectra = record_spectra(items, periods, damping)
    if np.any(spectra <= 0.0):
        bad = int(np.flatnonzero(np.any(spectra <= 0.0, axis=1))[0])
        raise ValueError(f"record {bad} ({_name(items[bad])!r}) has a zero spectrum in the range")
    logfit = np.exp(np.mean(np.log(sa[None, :] / spectra), axis=1))
    if method == "sa":
        if lo != hi:
            raise ValueError("method='sa' scales at one period: pass `period_range` as a number")
        factors = sa[0] / spectra[:, 0]
    elif method == "least_squares":
        factors = logfit
    else:
        shape = logfit if minimise_misfit else np.ones(len(items))
        common = np.max(frac * sa / np.mean(shape[:, None] * spectra, axis=0))
        factors = common * shape
    mean = np.mean(factors[:, None] * spectra, axis=0)
    table = CriterionTable(periods, sa, mean, frac)
    scaled = [r.scaled(float(f)) for r, f in zip(items, factors, strict=True)]
    names = [_name(r) for r in items]
    return ScaledSuite(
        factors, scaled, table, bool(np.all(table.passes)), spectra, method, names, items, target
    )


def _corners(target: Any) -> NDArray[np.float64]:
    """The periods the criterion must see besides the log-spaced grid: a table's own
    periods, or a code spectrum's corner periods (T0, TS, TL; TB, TC, TD)."""
    if getattr(target, "formula", None) is None:
        return np.asarray(target.periods, dtype=np.float64)
    keys = ("t0", "ts", "tl", "TB", "TC", "TD")
    meta = getattr(target, "metadata", {})
    return np.array([float(meta[k]) for k in keys if k in meta], dtype=np.float64)


def _name(r: Record) -> str:
    return r.name

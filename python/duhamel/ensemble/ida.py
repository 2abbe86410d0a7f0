"""Incremental dynamic analysis (:func:`~duhamel.ensemble.ida`): every motion scaled to
every intensity, one run each through :func:`~duhamel.ensemble.solve_many`."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from duhamel._engine.validate import as_float_array, finite_float, positive_float
from duhamel.ensemble.run import solve_many
from duhamel.errors import SolverError
from duhamel.events import Event
from duhamel.records.motion import GroundMotion
from duhamel.results.solution import Solution

__all__ = ["IDA", "fractiles", "ida"]


@dataclass(frozen=True, eq=False)
class IDA:
    """Incremental dynamic analysis curves: ``measures[i, j]`` is the response measure of
    motion ``i`` scaled to intensity ``intensities[j]``; ``inf`` where the run collapsed (it
    stopped with :class:`duhamel.SolverError`, or met the `collapse` event)."""

    intensities: np.ndarray
    measures: np.ndarray
    names: list[str]
    intensity: str
    factors: np.ndarray
    #: With ``collapse=``: the instant each run met the collapse event (NaN: it did not).
    collapse_times: np.ndarray | None = None

    def fractiles(self, q: Sequence[float] = (16, 50, 84)) -> np.ndarray:
        """Percentiles `q` of the measure over the motions at each intensity, shape
        ``(len(q), n_intensities)``; collapses count as infinitely large.

        The percentile is numpy's default (``np.percentile``'s ``'linear'``: the sorted
        values ``x_0 <= ... <= x_(n-1)`` at ``h = (n - 1) q / 100``, linear between
        ``x_floor(h)`` and ``x_ceil(h)``), except that an interpolation toward a collapse is a
        collapse and a percentile landing exactly on a finite value is that value: it never
        multiplies ``inf`` by 0 (``np.percentile`` gives NaN there). With ``k`` collapses
        among ``n`` motions, the percentiles up to ``100 (n - k - 1) / (n - 1)`` are finite
        and those above are ``inf``; the median of ``[1, 2, inf]`` is 2, as ``np.median``
        gives.

        Examples
        --------
        >>> import numpy as np
        >>> from duhamel.ensemble import IDA
        >>> res = IDA(np.array([1.0]), np.array([[1.0], [2.0], [np.inf]]), ["a", "b", "c"],
        ...           "PGA", np.ones((3, 1)))
        >>> res.fractiles((0, 50, 60, 100))[:, 0].tolist()
        [1.0, 2.0, inf, inf]
        """
        return fractiles(self.measures, q)

    def plot(self, ax: Any = None, q: Sequence[float] = (16, 50, 84)) -> Any:
        """The IDA curves (measure on x, intensity on y), one thin line per motion, and the
        fractiles; returns the matplotlib Axes."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(6, 4.5))
        finite = np.where(np.isfinite(self.measures), self.measures, np.nan)
        for row in finite:
            ax.plot(row, self.intensities, color="0.75", lw=0.8)
        for qi, curve in zip(q, self.fractiles(q), strict=True):
            ax.plot(np.where(np.isfinite(curve), curve, np.nan), self.intensities, lw=2.2,
                    label=f"{qi:g} %")  # fmt: skip
        ax.set_xlabel("response measure")
        ax.set_ylabel(self.intensity)
        ax.legend(title="fractiles", fontsize="small")
        ax.grid(True, alpha=0.3)
        return ax


def fractiles(values: np.ndarray, q: Sequence[float]) -> np.ndarray:
    """Percentiles `q` (in [0, 100]) of `values` along axis 0, with ``+inf`` (collapses)
    as infinitely large values: see :meth:`IDA.fractiles`."""
    qs = np.atleast_1d(as_float_array(q, "q"))
    if qs.ndim != 1 or qs.size == 0 or np.any((qs < 0.0) | (qs > 100.0)):
        raise ValueError(f"`q` must be percentiles in [0, 100], got {q!r}")
    x = as_float_array(values, "values", finite=False)
    if x.ndim not in (1, 2) or x.shape[0] == 0:
        raise ValueError(
            "`values` must be the measures of at least one run along axis 0 (1-D, or 2-D: "
            f"runs x intensities), got shape {x.shape}"
        )
    x = np.sort(x, axis=0)
    if np.isnan(x).any() or np.isneginf(x).any():
        raise ValueError(
            "`values` (the measures) contain NaN or -inf: only collapses (+inf) are allowed"
        )
    n = x.shape[0]
    h = (n - 1) * (qs / 100.0)  # numpy's virtual index, rounded as numpy rounds it
    lo = np.floor(h).astype(np.intp)
    hi = np.minimum(lo + 1, n - 1)
    frac = (h - lo)[:, None]
    x_lo, x_hi = x[lo], x[hi]
    with np.errstate(invalid="ignore"):
        # numpy's lerp: from the nearer end (bit for bit np.percentile's 'linear')
        diff = x_hi - x_lo
        between = np.where(frac >= 0.5, x_hi - diff * (1.0 - frac), x_lo + diff * frac)
    return np.where(frac == 0.0, x_lo, np.where(np.isinf(x_hi), np.inf, between))


def _scale_factor(motion: Any, intensity: str, period: float | None, damping: float) -> float:
    """Intensity of `motion` at scale 1: its PGA, or its PSA at `period`."""
    if intensity == "pga":
        return float(motion.pga)
    from duhamel.spectra.response import response_spectrum

    return float(response_spectrum(motion, [period], damping, threads=1).psa[0, 0, 0])


@dataclass(frozen=True)
class _Collapsed:
    """The reduction of a run with a collapse event: ``(measure or inf, collapse time or
    NaN)`` (picklable for a Dask cluster)."""

    measure: Callable[[Solution], float]

    def __call__(self, sol: Solution) -> tuple[float, float]:
        stops = [o for o in sol.events if o.terminal]
        if stops:
            return np.inf, stops[0].time
        return float(self.measure(sol)), np.nan


def _ida_case(case: tuple[Any, Any, float]) -> Any:
    factory, motion, factor = case
    return factory(motion.scaled(factor))


def _measure(result: Any, i: int, j: int) -> float:
    """A run's measure: ``inf`` for a collapse, else the finite number `measure` gave."""
    if isinstance(result, SolverError):
        return np.inf
    try:
        value = float(result)
    except (TypeError, ValueError):
        raise TypeError(
            f"`measure` must return a number, got {type(result).__name__} (motion {i}, "
            f"intensity {j})"
        ) from None
    if not np.isfinite(value):
        raise ValueError(
            f"`measure` returned {value!r} for motion {i} at intensity {j}: a measure must be "
            "finite (collapses are the runs that stop with SolverError)"
        )
    return value


def ida(
    system_factory: Callable[[Any], Any],
    motions: Sequence[Any],
    intensities: Sequence[float],
    measure: Callable[[Solution], float],
    integrator: Any = None,
    *,
    intensity: str = "sa",
    period: float | None = None,
    damping: float = 0.05,
    dt: float | None = None,
    client: Any = None,
    workers: int | None = None,
    collapse: Event | None = None,
) -> IDA:
    """Incremental dynamic analysis (Vamvatsikos and Cornell 2002): every motion scaled to
    every intensity, one run each, its response measure kept.

    Parameters
    ----------
    system_factory : callable
        ``GroundMotion -> System`` loaded by that (scaled) motion, or ``GroundMotion ->
        (System, {"loads": [...]})``: one model under each motion's loads, prepared once per
        process and reused by every run (see :func:`solve_many`).
    motions : sequence of GroundMotion
        The records.
    intensities : sequence of float
        Target intensities: PSA at `period` (m/s^2) for ``intensity='sa'``, PGA (m/s^2) for
        ``'pga'``.
    measure : callable
        ``Solution -> float``, e.g. the peak inter-storey drift.
    integrator : optional
        Default ``duhamel.Semianalytic()``.
    intensity : {'sa', 'pga'}
        How the motions are scaled.
    period, damping : float
        The spectral period (s; required for ``'sa'``) and damping of Sa.
    dt : float, optional
        Step (default: each motion's sampling interval).
    client, workers
        As in :func:`solve_many` (a Dask cluster, or in-process threads).
    collapse : duhamel.Event, optional
        A terminal event that counts as collapse, e.g. ``duhamel.events.drift(i, j, 0.1,
        height, terminal=True)``: a run that meets it ends there (located inside its step)
        and its measure is ``inf``; ``collapse_times`` keeps when (docs/events.md). Runs
        that fail with :class:`duhamel.SolverError` before it still count as collapsed.

    Returns
    -------
    IDA
        ``measures`` of shape ``(n_motions, n_intensities)``, ``fractiles()``, ``plot()``.
    """
    from duhamel.integrators import Semianalytic

    if not isinstance(intensity, str) or intensity not in ("sa", "pga"):
        raise ValueError(f"`intensity` must be 'sa' or 'pga', got {intensity!r}")
    for name, fn in (("system_factory", system_factory), ("measure", measure)):
        if not callable(fn):
            raise TypeError(f"`{name}` must be callable, got {type(fn).__name__}")
    damping = finite_float(damping, "damping")
    if not 0.0 <= damping < 1.0:
        raise ValueError(f"`damping` must be a ratio in [0, 1), got {damping!r}")
    if dt is not None:
        dt = positive_float(dt, "dt")
    if intensity == "sa":
        if period is None:
            raise ValueError("`period` must be a positive period (s) for intensity='sa', got None")
        period = positive_float(period, "period")
    ims = np.atleast_1d(as_float_array(intensities, "intensities"))
    if ims.ndim != 1 or ims.size == 0 or np.any(ims <= 0):
        raise ValueError("`intensities` must be a non-empty 1-D array of positive numbers")
    if isinstance(motions, GroundMotion):
        motions = [motions]
    try:
        if isinstance(motions, str | bytes):
            raise TypeError
        motions = list(motions)
    except TypeError:  # a number, a string, a 0-d array
        raise TypeError(
            f"`motions` must be a sequence of GroundMotion, got {type(motions).__name__}"
        ) from None
    if not motions:
        raise ValueError("`motions` is empty")
    for i, m in enumerate(motions):
        if not isinstance(m, GroundMotion):
            raise TypeError(f"`motions[{i}]` must be a GroundMotion, got {type(m).__name__}")
    integ = Semianalytic() if integrator is None else integrator
    unit = np.array([_scale_factor(m, intensity, period, damping) for m in motions])
    if np.any(unit <= 0):
        raise ValueError("a motion has zero intensity: it cannot be scaled")
    factors = ims[None, :] / unit[:, None]
    extra: dict[str, Any] = {}
    if collapse is not None:
        if not isinstance(collapse, Event) or not collapse.terminal:
            raise ValueError(
                "`collapse` must be a terminal duhamel.Event (e.g. duhamel.events.drift(i, j, "
                f"limit, height, terminal=True)), got {collapse!r}"
            )
        extra = {"events": [collapse]}
    reduce = measure if collapse is None else _Collapsed(measure)
    rows, times = [], []
    for i, m in enumerate(motions):
        cases = [(system_factory, m, float(f)) for f in factors[i]]
        ens = solve_many(
            _ida_case, cases, integ, t_end=m.duration, dt=dt or m.dt, reduce=reduce,
            client=client, workers=workers, on_error="keep", **extra,
        )  # fmt: skip
        if collapse is None:
            rows.append([_measure(r, i, j) for j, r in enumerate(ens.results)])
        else:
            out = [(np.inf, np.nan) if isinstance(r, SolverError) else r for r in ens.results]
            rows.append([float(r[0]) for r in out])
            times.append([float(r[1]) for r in out])
    label = "PGA [m/s^2]" if intensity == "pga" else f"Sa(T = {period:g} s) [m/s^2]"
    return IDA(
        ims, np.array(rows), [m.name for m in motions], label, factors,
        None if collapse is None else np.array(times),
    )  # fmt: skip

"""Incremental dynamic analysis (:func:`~duhamel.ensemble.ida`): every motion scaled to
every intensity, one run each through :func:`~duhamel.ensemble.solve_many`; each record's
collapse intensity (refined by bisection with ``tolerance=``) and the lognormal collapse
fragility (:meth:`IDA.fragility`)."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from duhamel._engine.validate import as_float_array, finite_float, positive_float, positive_int
from duhamel.ensemble.batches import _Job, dispatch
from duhamel.ensemble.collapse import first_collapse, outcome, refine
from duhamel.ensemble.fragility import Fragility, fit_fragility
from duhamel.ensemble.run import MAX_WORKERS, solve_many
from duhamel.errors import SolverError
from duhamel.events import Event
from duhamel.records.motion import GroundMotion
from duhamel.results.solution import Solution

__all__ = ["IDA", "fractiles", "ida"]


@dataclass(frozen=True, eq=False)
class IDA:
    """Incremental dynamic analysis curves: ``measures[i, j]`` is the response measure of
    motion ``i`` scaled to intensity ``intensities[j]``; ``inf`` where the run collapsed (it
    stopped with :class:`duhamel.SolverError` and ``solver_error='collapse'``, or met the
    `collapse` event).

    ``collapse_intensities[i]`` is motion ``i``'s collapse intensity: its first collapse on
    the grid, or, with ``tolerance=``, the upper end of the bracket ``collapse_brackets[i] =
    (lower, upper)`` bisected until ``upper - lower <= tolerance * upper`` (no collapse at
    `lower`, a collapse at `upper`); ``inf`` (and ``lower`` the largest intensity) for a
    record that did not collapse on the grid."""

    intensities: np.ndarray
    measures: np.ndarray
    names: list[str]
    intensity: str
    factors: np.ndarray
    #: With ``collapse=``: the instant each run met the collapse event (NaN: it did not).
    collapse_times: np.ndarray | None = None
    #: Per motion, the lowest intensity found to collapse (``inf``: none on the grid).
    collapse_intensities: np.ndarray | None = None
    #: Per motion, ``(lower, upper)``: the intensity that did not collapse below the first
    #: that did (0 when the first grid intensity collapsed).
    collapse_brackets: np.ndarray | None = None
    #: ``failed[i, j]``: the run stopped with SolverError (counted as a collapse).
    failed: np.ndarray | None = None
    #: The relative tolerance of the bisection (None: the grid's).
    tolerance: float | None = None
    #: Runs made by the bisection, beyond the grid's.
    refinement_runs: int = 0
    #: Per motion, the measure of the run at ``collapse_brackets[:, 0]`` (NaN when that is 0
    #: or the motion did not collapse).
    collapse_measures: np.ndarray | None = None

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

    def fragility(self, method: str = "mle", *, mce: float | None = None) -> Fragility:
        """The lognormal collapse fragility fitted to :attr:`collapse_intensities` (the
        records that did not collapse are right-censored at the largest intensity): see
        :func:`duhamel.ensemble.fit_fragility`; `mce` (``S_MT``, the units of the
        intensities) gives FEMA P695's collapse margin ratio ``.cmr``.

        Examples
        --------
        >>> import numpy as np
        >>> from duhamel.ensemble import IDA
        >>> inf = np.inf
        >>> res = IDA(np.array([1.0, 2.0, 3.0]), np.array([[1, inf, inf], [1, 2, inf],
        ...           [1, 2, 3.0]]), ["a", "b", "c"], "PGA", np.ones((3, 3)))
        >>> res.collapse_intensities.tolist()
        [2.0, 3.0, inf]
        >>> frag = res.fragility(mce=1.0)                 # 'c' censored at 3
        >>> bool(frag.median > np.sqrt(6.0)), bool(frag.cmr == frag.median)
        (True, True)
        """
        if self.collapse_intensities is None:
            raise ValueError("this IDA has no collapse intensities")
        return fit_fragility(self.collapse_intensities, method,
                             censored_at=float(self.intensities.max()), mce=mce)  # fmt: skip

    def __post_init__(self) -> None:
        if self.collapse_intensities is None and np.ndim(self.measures) == 2:
            ims = np.asarray(self.intensities, dtype=np.float64)
            lo, hi, at = first_collapse(np.asarray(self.measures, dtype=np.float64), ims)
            object.__setattr__(self, "collapse_intensities", hi)
            object.__setattr__(self, "collapse_brackets", np.stack([lo, hi], axis=1))
            object.__setattr__(self, "collapse_measures", at)

    def plot(self, ax: Any = None, q: Sequence[float] = (16, 50, 84)) -> Any:
        """The IDA curves (measure on x, intensity on y), one thin line per motion, each
        ending in a flat line (red) at its collapse intensity, and the fractiles; returns the
        matplotlib Axes."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(6, 4.5))
        finite = np.where(np.isfinite(self.measures), self.measures, np.nan)
        caps, brackets, at = (
            self.collapse_intensities,
            self.collapse_brackets,
            self.collapse_measures,
        )
        right = np.nanmax(np.r_[finite.ravel(), 0.0])
        for i, row in enumerate(finite):
            x, y = row, self.intensities
            if (
                caps is not None
                and brackets is not None
                and at is not None
                and np.isfinite(caps[i])
            ):
                keep = y < brackets[i, 0]  # the grid below the last run without collapse
                x, y = np.r_[row[keep], at[i]], np.r_[y[keep], brackets[i, 0]]
                first = i == int(np.argmax(np.isfinite(caps)))
                ax.plot([at[i], max(right, at[i]) * 1.05], [caps[i], caps[i]], color="C3",
                        lw=0.8, label="collapse" if first else None)  # fmt: skip
            ax.plot(x, y, color="0.6", lw=0.8)
        for qi, curve in zip(q, self.fractiles(q), strict=True):
            ax.plot(np.where(np.isfinite(curve), curve, np.nan), self.intensities, lw=2.2,
                    label=f"{qi:g} %")  # fmt: skip
        ax.set_xlabel("response measure")
        ax.set_ylabel(self.intensity)
        ax.legend(fontsize="small")
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


@dataclass(frozen=True)
class _Cases:
    """The runs of an IDA as one study: case ``(motion, factor)`` -> the factory's model
    under ``motions[motion]`` scaled by `factor`, on that motion's grid (picklable: the
    motions travel once per worker with the study, each case only its two numbers)."""

    factory: Callable[[Any], Any]
    motions: tuple[GroundMotion, ...]
    dt: float | None

    def __call__(self, case: tuple[int, float]) -> tuple[Any, dict[str, Any]]:
        motion = self.motions[case[0]]
        made = self.factory(motion.scaled(case[1]))
        grid = {"t_end": motion.duration, "dt": self.dt or motion.dt}
        if isinstance(made, tuple) and len(made) == 2 and isinstance(made[1], dict):
            if any(name in made[1] for name in ("threads", "t_end", "dt")):
                raise ValueError(
                    "make_system's options may not set `threads`, `t_end` or `dt` (the "
                    "study's grid)"
                )
            return made[0], {**made[1], **grid}
        return made, grid


def _measure(result: Any, where: str) -> float:
    """A run's measure: ``inf`` for a collapse (a SolverError, or the collapse event met:
    ``(inf, time)``), else the finite number `measure` gave."""
    if isinstance(result, SolverError):
        return np.inf
    if isinstance(result, tuple):  # _Collapsed's (measure or inf, time or NaN)
        if not np.isnan(result[1]):
            return np.inf
        result = result[0]
    try:
        value = float(result)
    except (TypeError, ValueError):
        raise TypeError(
            f"`measure` must return a number, got {type(result).__name__} ({where})"
        ) from None
    if not np.isfinite(value):
        raise ValueError(
            f"`measure` returned {value!r} for {where}: a measure must be finite (collapses "
            "are the runs that stop with SolverError or meet the `collapse` event)"
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
    solver_error: str = "collapse",
    tolerance: float | None = None,
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
        that fail with :class:`duhamel.SolverError` before it still count as collapsed
        (unless ``solver_error='raise'``).
    solver_error : {'collapse', 'raise'}
        A run that stops with :class:`duhamel.SolverError` (no equilibrium in a step, a
        diverging state): a collapse (the default, as before; for a deteriorating model
        whose lateral strength is lost, state it), marked in ``failed``; or ``'raise'``: the
        error is raised with a note naming the motion and intensity (a model that should not
        fail).
    tolerance : float, optional
        Refine each record's collapse intensity by bisection on its scale factor, between
        the last grid intensity that did not collapse and the first that did, until the
        bracket is within `tolerance` (relative, in (0, 1)) of its upper end; the records
        in parallel threads (`workers`), each run as on the grid. Default: the grid's
        resolution.

    Returns
    -------
    IDA
        ``measures`` of shape ``(n_motions, n_intensities)``, ``fractiles()``, ``plot()``,
        ``collapse_intensities``, ``fragility()``.

    Examples
    --------
    An elastic-perfectly-plastic SDOF whose P-Delta (a leaning column) makes its post-yield
    stiffness negative, under three records; collapse at a drift of 10 %:

    >>> import numpy as np, duhamel
    >>> from duhamel.ensemble import ida
    >>> from duhamel.records import GroundMotion
    >>> t = np.arange(0.0, 8.0, 0.02)
    >>> motions = [GroundMotion(np.sin(w * t) * np.exp(-0.3 * t), 0.02, name=f"w{w}")
    ...            for w in (4.0, 6.0, 8.0)]
    >>> def sdof(motion):
    ...     s = duhamel.System(np.eye(1), [[4.0]], zeta=0.05)  # 4: the elastic column
    ...     s.add(duhamel.elements.PDelta(0, None, P=4.0, height=1.0))
    ...     s.add(duhamel.elements.Bilinear(0, k=36.0, fy=0.9, alpha=-0.05))
    ...     return s.add_load(motion.as_load([1.0]))
    >>> drift = lambda sol: float(np.abs(sol.x).max())
    >>> stop = duhamel.events.drift(0, None, 0.1, height=1.0, terminal=True)
    >>> res = ida(sdof, motions, [0.5, 1.0, 2.0, 4.0], drift, intensity="pga",
    ...           collapse=stop, solver_error="raise", tolerance=0.01, workers=1)
    >>> lo, hi = res.collapse_brackets.T
    >>> bool(np.all((hi - lo <= 0.01 * hi) & (hi <= 4.0)))
    True
    >>> frag = res.fragility(mce=0.5)
    >>> bool(0.5 < frag.median < 4.0)
    True
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
    if not isinstance(solver_error, str) or solver_error not in ("collapse", "raise"):
        raise ValueError(f"`solver_error` must be 'collapse' or 'raise', got {solver_error!r}")
    if tolerance is not None:
        tolerance = finite_float(tolerance, "tolerance")
        if not 0.0 < tolerance < 1.0:
            raise ValueError(
                f"`tolerance` must be a relative tolerance in (0, 1), got {tolerance!r}"
            )
        if collapse is None and solver_error == "raise":
            raise ValueError(
                "`tolerance` refines collapse intensities, but there is no collapse criterion: "
                "give a terminal `collapse` event or solver_error='collapse'"
            )
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
    # every run in one study (the motions shipped once per worker, one batch of tasks)
    job = _Job(_Cases(system_factory, tuple(motions), dt), integ, reduce, extra, True, True)
    cases = [(i, float(f)) for i in range(len(motions)) for f in factors[i]]
    if workers is not None:
        workers = positive_int(workers, "workers", MAX_WORKERS)
    stream, *_ = dispatch(job, cases, client, workers, None, None)
    flat = list(stream)
    rows, times, failed = [], [], []
    for i, m in enumerate(motions):
        results = flat[i * ims.size : (i + 1) * ims.size]
        failed.append([isinstance(r, SolverError) for r in results])
        where = [f"motion {i} ({m.name!r}) at intensity {im:g}" for im in ims]
        for j, r in enumerate(results):
            if isinstance(r, SolverError):  # raises with solver_error='raise'
                outcome(r, solver_error, where[j])
        rows.append([_measure(r, where[j]) for j, r in enumerate(results)])
        if collapse is not None:
            times.append([np.nan if isinstance(r, SolverError) else float(r[1])
                          for r in results])  # fmt: skip
    measures = np.array(rows)
    lower, upper, at_lower = first_collapse(measures, ims)
    n_refined = 0
    if tolerance is not None:

        def collapses(motion: GroundMotion, factor: float) -> tuple[bool, float]:
            ens = solve_many(
                _ida_case, [(system_factory, motion, factor)], integ, t_end=motion.duration,
                dt=dt or motion.dt, reduce=reduce, client=client, workers=1, on_error="keep",
                **extra,
            )  # fmt: skip
            where = f"motion {motion.name!r} at scale factor {factor:g}"
            if isinstance(ens.results[0], SolverError):
                return outcome(ens.results[0], solver_error, where)
            value = _measure(ens.results[0], where)
            return not np.isfinite(value), value

        lower, upper, at_lower, n_refined = refine(
            collapses, motions, unit, lower, upper, at_lower, tolerance, workers
        )
    label = "PGA [m/s^2]" if intensity == "pga" else f"Sa(T = {period:g} s) [m/s^2]"
    return IDA(
        ims, measures, [m.name for m in motions], label, factors,
        None if collapse is None else np.array(times), upper, np.stack([lower, upper], axis=1),
        np.array(failed), tolerance, n_refined, at_lower,
    )  # fmt: skip

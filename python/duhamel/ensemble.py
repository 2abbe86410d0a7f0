"""Many runs: parameter studies, record suites, Monte Carlo samples — in parallel on one
machine, or on a Dask cluster with the same call.

:func:`solve_many` runs ``solve(make_system(p), integrator, ...)`` for every ``p`` of
`params` and keeps, per run, the :class:`~duhamel.Solution` or what ``reduce(solution)``
returns (peak values, a drift, chosen histories), so that a 10,000-run study does not hold
10,000 histories. In-process, runs go to a pool of threads: the time loop of each run is Rust
with the GIL released, so runs proceed in parallel (one per core, each run single-threaded);
results that stay numeric are never pickled. With ``client=`` a
``dask.distributed.Client``, the runs are sent to the cluster in chunks (several runs per
task, so the per-task overhead is small against the work) and gathered in order.

Examples
--------
>>> import numpy as np, duhamel
>>> from duhamel.ensemble import solve_many
>>> def frame(k):
...     return duhamel.System(np.eye(1), k * np.eye(1), zeta=0.05)
>>> peaks = solve_many(frame, [1.0, 4.0, 9.0], duhamel.Semianalytic(), t_end=5.0, dt=0.01,
...                    x0=[1.0], reduce=lambda sol: float(np.abs(sol.v).max()))
>>> [round(p, 2) for p in peaks.results]  # about omega exp(-zeta pi / 2)
[0.93, 1.85, 2.78]
"""

from __future__ import annotations

import math
import os
import time
from collections.abc import Callable, Iterable, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from duhamel.errors import SolverError
from duhamel.solution import Solution
from duhamel.solve import solve

__all__ = ["IDA", "Ensemble", "ida", "solve_many"]


@dataclass(frozen=True, eq=False)
class Ensemble:
    """Results of :func:`solve_many`, in the order of `params`.

    Attributes
    ----------
    params : list
        The parameters, as given.
    results : list
        Per run, the Solution or what `reduce` returned.
    stats : dict
        ``runs``, ``wall_time`` (s), ``workers``, ``where`` (``'threads'`` or ``'dask'``),
        ``chunk_size``.
    """

    params: list[Any]
    results: list[Any]
    stats: dict[str, Any] = field(default_factory=dict)

    def __len__(self) -> int:
        return len(self.results)

    def to_xarray(self) -> Any:
        """The results stacked along a ``case`` dimension: Solutions as their
        :meth:`~duhamel.Solution.to_xarray` datasets (same times and dofs), dicts of numbers
        or arrays as one variable per key, numbers or arrays as ``result``. Parameters that
        are dicts of scalars become coordinates along ``case``."""
        try:
            import xarray as xr
        except ImportError as exc:
            raise ImportError("to_xarray needs xarray: pip install 'duhamel[xarray]'") from exc
        failed = [i for i, r in enumerate(self.results) if isinstance(r, BaseException)]
        if failed:
            raise ValueError(
                f"cases {failed[:10]} failed (their results are the exceptions): select the "
                "others from `results` before stacking"
            )
        n = len(self.results)
        first = self.results[0] if n else None
        if isinstance(first, Solution):
            ds = xr.concat([r.to_xarray() for r in self.results], dim="case")
        else:
            rows = [r if isinstance(r, dict) else {"result": r} for r in self.results]
            keys = list(rows[0]) if rows else []
            data = {}
            for key in keys:
                values = np.stack([np.asarray(row[key]) for row in rows])
                dims = ("case", *[f"{key}_dim_{i}" for i in range(values.ndim - 1)])
                data[key] = (dims, values)
            ds = xr.Dataset(data)
        ds = ds.assign_coords(case=np.arange(n))
        if n and all(isinstance(p, dict) for p in self.params):
            for key in self.params[0]:
                values = [p.get(key) for p in self.params]
                if all(np.isscalar(v) for v in values):
                    ds = ds.assign_coords({key: ("case", np.asarray(values))})
        return ds


@dataclass(frozen=True)
class _Job:
    """One study's runs: picklable, so that a Dask worker receives it whole."""

    make_system: Callable[[Any], Any]
    integrator: Any
    reduce: Callable[[Solution], Any] | None
    options: dict[str, Any]
    keep_failures: bool

    def __call__(self, index: int, p: Any) -> Any:
        try:
            sol = solve(self.make_system(p), self.integrator, threads=1, **self.options)
            return sol if self.reduce is None else self.reduce(sol)
        except Exception as exc:
            if self.keep_failures and isinstance(exc, SolverError):
                return exc
            exc.add_note(f"in duhamel.ensemble.solve_many, case {index}: params = {p!r}")
            raise

    def chunk(self, cases: Sequence[tuple[int, Any]]) -> list[Any]:
        """A Dask task: several runs, one after the other."""
        return [self(i, p) for i, p in cases]


def solve_many(
    make_system: Callable[[Any], Any],
    params: Iterable[Any],
    integrator: Any,
    *,
    t_end: float,
    dt: float,
    reduce: Callable[[Solution], Any] | None = None,
    client: Any = None,
    workers: int | None = None,
    chunk_size: int | None = None,
    on_error: str = "raise",
    **solve_options: Any,
) -> Ensemble:
    """Run ``solve(make_system(p), integrator, t_end=t_end, dt=dt, **solve_options)`` for
    every ``p`` in `params`.

    Parameters
    ----------
    make_system : callable
        ``p -> System`` (picklable for a Dask cluster: a module-level function).
    params : iterable
        Any values: a record and a scale factor, a dict of stiffnesses, an initial state...
    integrator : Semianalytic or DirectIntegrator
        The same for every run.
    t_end, dt : float
        As in :func:`duhamel.solve`.
    reduce : callable, optional
        ``Solution -> anything`` kept per run instead of the Solution (peaks, drifts, a few
        histories).
    client : dask.distributed.Client, optional
        Run on this cluster instead of in-process threads.
    workers : int, optional
        In-process threads (default: the machine's cores).
    chunk_size : int, optional
        Runs per Dask task (default: about four tasks per worker thread).
    on_error : {'raise', 'keep'}, optional
        A run that stops with :class:`duhamel.SolverError` (divergence, no convergence: a
        collapse in a study): raise it (default), or keep the exception as that run's result
        and go on.
    **solve_options
        Passed to :func:`duhamel.solve` (``x0``, ``v0``, ``save_every``, ``dofs``...); each run
        uses one thread (``threads=1``): the parallelism is across runs.

    Returns
    -------
    Ensemble
        ``results`` in the order of `params`.

    Raises
    ------
    Exception
        The first failing run's exception, with a note naming its case index and parameters.
    """
    if not callable(make_system):
        raise TypeError(f"`make_system` must be callable, got {type(make_system).__name__}")
    if reduce is not None and not callable(reduce):
        raise TypeError(f"`reduce` must be callable, got {type(reduce).__name__}")
    if "threads" in solve_options:
        raise ValueError("`threads` is set per run by solve_many (1); use `workers`")
    if on_error not in ("raise", "keep"):
        raise ValueError(f"`on_error` must be 'raise' or 'keep', got {on_error!r}")
    ps = list(params)
    options = {"t_end": t_end, "dt": dt, **solve_options}
    job = _Job(make_system, integrator, reduce, options, on_error == "keep")
    started = time.perf_counter()
    if client is None:
        n = (os.cpu_count() or 1) if workers is None else int(workers)
        if n < 1:
            raise ValueError(f"`workers` must be >= 1, got {workers}")
        with ThreadPoolExecutor(max_workers=n) as pool:
            futures = [pool.submit(job, i, p) for i, p in enumerate(ps)]
            results = [f.result() for f in futures]
        stats = {"where": "threads", "workers": n, "chunk_size": 1}
    else:
        if chunk_size is not None and int(chunk_size) < 1:
            raise ValueError(f"`chunk_size` must be >= 1, got {chunk_size}")
        threads = sum(client.nthreads().values()) or 1
        size = int(chunk_size) if chunk_size else max(1, math.ceil(len(ps) / (4 * threads)))
        indexed = list(enumerate(ps))
        chunks = [indexed[i : i + size] for i in range(0, len(indexed), size)]
        futures = client.map(job.chunk, chunks, pure=False)
        results = [r for chunk in client.gather(futures) for r in chunk]
        stats = {"where": "dask", "workers": threads, "chunk_size": size}
    stats.update(runs=len(ps), wall_time=time.perf_counter() - started)
    return Ensemble(ps, results, stats)


@dataclass(frozen=True, eq=False)
class IDA:
    """Incremental dynamic analysis curves: ``measures[i, j]`` is the response measure of
    motion ``i`` scaled to intensity ``intensities[j]``; ``inf`` where the run collapsed (it
    stopped with :class:`duhamel.SolverError`)."""

    intensities: np.ndarray
    measures: np.ndarray
    names: list[str]
    intensity: str
    factors: np.ndarray

    def fractiles(self, q: Sequence[float] = (16, 50, 84)) -> np.ndarray:
        """Percentiles `q` of the measure over the motions at each intensity (collapses
        count as infinitely large), shape ``(len(q), n_intensities)``."""
        return np.percentile(self.measures, np.asarray(q, dtype=float), axis=0)

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


def _scale_factor(motion: Any, intensity: str, period: float | None, damping: float) -> float:
    """Intensity of `motion` at scale 1: its PGA, or its PSA at `period`."""
    if intensity == "pga":
        return float(motion.pga)
    from duhamel.spectra import response_spectrum

    return float(response_spectrum(motion, [period], damping, threads=1).psa[0, 0, 0])


def _ida_case(case: tuple[Any, Any, float]) -> Any:
    factory, motion, factor = case
    return factory(motion.scaled(factor))


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
) -> IDA:
    """Incremental dynamic analysis (Vamvatsikos and Cornell 2002): every motion scaled to
    every intensity, one run each, its response measure kept.

    Parameters
    ----------
    system_factory : callable
        ``GroundMotion -> System`` loaded by that (scaled) motion.
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

    Returns
    -------
    IDA
        ``measures`` of shape ``(n_motions, n_intensities)``, ``fractiles()``, ``plot()``.
    """
    from duhamel.integrators import Semianalytic

    if intensity not in ("sa", "pga"):
        raise ValueError(f"`intensity` must be 'sa' or 'pga', got {intensity!r}")
    if intensity == "sa" and not (period is not None and period > 0):
        raise ValueError(f"`period` must be a positive period (s) for intensity='sa', got {period}")
    ims = np.asarray(intensities, dtype=float)
    if ims.ndim != 1 or ims.size == 0 or np.any(~np.isfinite(ims)) or np.any(ims <= 0):
        raise ValueError("`intensities` must be a non-empty 1-D array of positive numbers")
    motions = list(motions)
    if not motions:
        raise ValueError("`motions` is empty")
    integ = Semianalytic() if integrator is None else integrator
    unit = np.array([_scale_factor(m, intensity, period, damping) for m in motions])
    if np.any(unit <= 0):
        raise ValueError("a motion has zero intensity: it cannot be scaled")
    factors = ims[None, :] / unit[:, None]
    rows = []
    for i, m in enumerate(motions):
        cases = [(system_factory, m, float(f)) for f in factors[i]]
        ens = solve_many(
            _ida_case, cases, integ, t_end=m.duration, dt=dt or m.dt, reduce=measure,
            client=client, workers=workers, on_error="keep",
        )  # fmt: skip
        rows.append([np.inf if isinstance(r, SolverError) else float(r) for r in ens.results])
    label = "PGA [m/s^2]" if intensity == "pga" else f"Sa(T = {period:g} s) [m/s^2]"
    return IDA(ims, np.array(rows), [m.name for m in motions], label, factors)

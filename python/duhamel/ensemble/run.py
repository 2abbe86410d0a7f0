""":func:`~duhamel.ensemble.solve_many` and its :class:`~duhamel.ensemble.Ensemble`: the
runs of a study in a pool of threads or on a Dask cluster, results in the order of the
parameters, kept in memory or appended to a zarr store as they finish."""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel._engine.request import steps
from duhamel._engine.spellings import deprecated
from duhamel._engine.validate import finite_float, positive_float, positive_int
from duhamel.ensemble.batches import _Job, check_model, dispatch
from duhamel.ensemble.statistics import statistics
from duhamel.ensemble.zarr import ZarrWriter, stack
from duhamel.modal import ModalBasis
from duhamel.prepared import Prepared
from duhamel.results.solution import Solution

__all__ = ["Ensemble", "EnsembleStats", "solve_many"]

#: The most in-process worker threads a study takes (as `threads` of duhamel.solve).
MAX_WORKERS = 1024


@dataclass(frozen=True)
class EnsembleStats:
    """How a study ran (:attr:`Ensemble.stats`).

    Attributes
    ----------
    runs : int
        The runs (cases) of the study.
    wall_time : float
        Seconds for the whole study.
    workers : int
        Worker threads in this process, or the Dask cluster's threads.
    where : {"threads", "dask"}
        Where the runs ran.
    chunk_size : int
        Runs per task (1 in threads).
    basis : {"per run", "shared"}
        Whether every run made its own modal basis or all shared one (``basis=``).

    Examples
    --------
    >>> from duhamel.ensemble import EnsembleStats
    >>> EnsembleStats(runs=4, wall_time=0.5, workers=2, where="threads", chunk_size=1,
    ...               basis="per run").runs
    4
    """

    runs: int
    wall_time: float
    workers: int
    where: str
    chunk_size: int
    basis: str

    def __getitem__(self, key: str) -> Any:
        """Deprecated: the dict of the previous release (``stats["runs"]``)."""
        if key not in self.keys():
            raise KeyError(key)
        deprecated(f"`Ensemble.stats[{key!r}]` is deprecated, use `Ensemble.stats.{key}`")
        return getattr(self, key)

    def get(self, key: str, default: Any = None) -> Any:
        """Deprecated: the dict of the previous release."""
        if key not in self.keys():
            return default
        deprecated(f"`Ensemble.stats.get({key!r})` is deprecated, use `Ensemble.stats.{key}`")
        return getattr(self, key)

    def keys(self) -> list[str]:
        """The attributes' names (as the previous release's dict had its keys)."""
        return [f.name for f in fields(self)]

    def items(self) -> list[tuple[str, Any]]:
        """Deprecated: the dict of the previous release; use :func:`dataclasses.asdict`."""
        deprecated("`Ensemble.stats.items()` is deprecated, use dataclasses.asdict(stats)")
        return [(k, getattr(self, k)) for k in self.keys()]

    def __contains__(self, key: object) -> bool:
        return key in self.keys()


@dataclass(frozen=True, eq=False)
class Ensemble:
    """Results of :func:`solve_many`, in the order of `params`.

    Attributes
    ----------
    params : list
        The parameters, as given.
    results : list
        Per run, the Solution or what `reduce` returned; empty when the results were written
        to a zarr store (`store`).
    stats : EnsembleStats or None
        How the study ran: ``runs``, ``wall_time`` (s), ``workers``, ``where``
        (``'threads'`` or ``'dask'``), ``chunk_size``, ``basis`` (``'per run'`` or
        ``'shared'``); None for an Ensemble made by hand.
    store : pathlib.Path or None
        The zarr store the results were written to (``solve_many(to_zarr=...)``).
    """

    params: list[Any]
    results: list[Any]
    stats: EnsembleStats | None = None
    store: Path | None = None

    def __len__(self) -> int:
        return len(self.params)

    def to_xarray(self, statistics: bool = False) -> Any:
        """The results stacked along a ``case`` dimension: Solutions as their
        :meth:`~duhamel.Solution.to_xarray` datasets (same times and dofs), dicts of numbers
        or arrays as one variable per key, numbers or arrays as ``result``. Parameters that
        are dicts of scalars become coordinates along ``case``. Results written to a zarr
        store are opened from it (lazily). ``statistics=True`` adds the variables of
        :meth:`statistics` (``<quantity>_mean``, ``<quantity>_mean_plus_sigma``,
        ``<quantity>_max``, without the ``case`` dimension; in-memory results only)."""
        if self.store is not None:
            if statistics:
                raise ValueError("`statistics`: results written to a store are not in memory")
            import xarray as xr

            return xr.open_zarr(self.store, consolidated=False)
        ds = stack(self.params, self.results)
        if statistics:
            for name, stats in self.statistics().items():
                for kind, values in stats.items():
                    dims = ("dof",) if values.ndim == 1 and "dof" in ds.dims else None
                    if dims is None:
                        dims = tuple(f"{name}_dim_{i}" for i in range(values.ndim))
                    ds[f"{name}_{kind}"] = (dims, values)
        return ds

    def statistics(
        self, quantities: Sequence[str] | None = None
    ) -> dict[str, dict[str, NDArray[np.float64]]]:
        """The statistics of a set of records that design codes ask for: per quantity, the
        mean, the mean plus one (sample) standard deviation and the maximum over the runs.

        A quantity is, for Solution results, the peak magnitude of each saved dof of
        ``"x"``, ``"v"``, ``"a"`` or ``"a_absolute"`` (default all four); for dicts returned by
        `reduce`, a key (default all); for other results, ``"result"``.

        Returns
        -------
        dict
            ``{quantity: {"mean": ..., "mean_plus_sigma": ..., "max": ...}}``, arrays of the
            shape of one run's value.

        Examples
        --------
        >>> from duhamel.ensemble import Ensemble
        >>> ens = Ensemble([1, 2, 3], [{"drift": 1.0}, {"drift": 2.0}, {"drift": 3.0}])
        >>> s = ens.statistics()["drift"]
        >>> float(s["mean"]), float(s["mean_plus_sigma"]), float(s["max"])
        (2.0, 3.0, 3.0)
        """
        return statistics(self.results, quantities)


def _shared_basis(basis: Any, make_system: Callable, ps: list, integrator: Any) -> Any:
    """The ModalBasis every run uses, or None (each run computes its own)."""
    if basis is None or isinstance(basis, ModalBasis):
        return basis
    if not isinstance(basis, str) or basis != "first":
        raise ValueError(f"`basis` must be None, 'first' or a duhamel.ModalBasis, got {basis!r}")
    if not ps:
        return None
    modes = getattr(integrator, "modes", None)
    try:
        made = make_system(ps[0])
        if isinstance(made, tuple) and len(made) == 2 and isinstance(made[1], dict):
            made = made[0]  # (system, per-run options)
        check_model(made)
        if isinstance(made, Prepared):
            made = made.system
        return made.modal(modes)
    except Exception as exc:
        exc.add_note("in duhamel.ensemble.solve_many, computing the shared basis of case 0")
        raise


def _counted(
    stream: Iterator[Any], n: int, progress: bool | Callable[[int, int], Any] | None
) -> Iterator[Any]:
    """`stream`, reporting each result: a tqdm bar over the runs (``progress=True``, shown
    for studies lasting more than a second), or ``progress(done, n_runs)``."""
    if progress is None or progress is False:
        yield from stream
        return
    if progress is True:
        from tqdm.auto import tqdm

        with tqdm(total=n, unit="run", delay=1.0, leave=False, desc="solve_many") as bar:
            for result in stream:
                bar.update(1)
                yield result
        return
    for done, result in enumerate(stream, start=1):
        progress(done, n)
        yield result


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
    basis: ModalBasis | str | None = None,
    to_zarr: str | Path | None = None,
    progress: bool | Callable[[int, int], Any] | None = None,
    **solve_options: Any,
) -> Ensemble:
    """Run ``solve(make_system(p), integrator, t_end=t_end, dt=dt, **solve_options)`` for
    every ``p`` in `params`.

    Parameters
    ----------
    make_system : callable
        ``p -> System``, or ``p -> (System, options)`` with per-run options of
        :meth:`duhamel.Prepared.run` (an initial state ``x0``/``v0`` drawn per case, the
        case's ``loads``...) that override `solve_options` (picklable for a Dask cluster: a
        module-level function). A run whose system is the same, unchanged object as an
        earlier run's in the same process (a study of one model under many records: return
        ``(model, {"loads": [record]})``) reuses that run's :class:`duhamel.Prepared` (the
        modal analysis, the route and the core's model); `make_system` may also return a
        Prepared (with the study's `integrator` and `dt`).
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
        In-process threads, 1 to 1024 (default: the machine's cores).
    chunk_size : int, optional
        Runs per Dask task (default: sized from the measured time of each worker's first
        runs so that a task lasts about 0.2 s, smaller toward the end so that the workers
        finish together), and cases per block of a zarr store (default 64).
    on_error : {'raise', 'keep'}, optional
        A run that stops with :class:`duhamel.SolverError` (divergence, no convergence: a
        collapse in a study): raise it (default), or keep the exception as that run's result
        and go on.
    basis : ModalBasis or 'first', optional
        The undamped modes every run uses (:meth:`duhamel.System.use_basis`) instead of
        computing its own: a basis, or ``'first'`` to compute it once from the first case's
        system. For studies that vary the loads, records or elements of one linear model;
        on a cluster the basis is scattered to every worker once. A run whose model it does
        not fit raises ValueError.
    to_zarr : str or path, optional
        A new zarr store to which the results are appended in case order as the runs
        finish (blocks of `chunk_size` cases, stacked as :meth:`Ensemble.to_xarray` does), so
        that no more than a few blocks are ever in memory; ``results`` is then empty and
        :meth:`Ensemble.to_xarray` opens the store. Needs xarray and zarr; not with
        ``on_error='keep'``.
    progress : bool or callable, optional
        ``True`` shows a tqdm progress bar over the runs (runs done, rate, ETA) for studies
        lasting more than about a second, as ``duhamel.solve(progress=True)`` does over the
        steps of one run; a function is called as ``progress(done, n_runs)`` as the results
        arrive (in case order). The runs themselves report nothing.
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

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> from duhamel.ensemble import solve_many
    >>> def loaded(amplitude):
    ...     s = duhamel.System(np.eye(2), [[2.0, -1.0], [-1.0, 1.0]], zeta=0.02)
    ...     return s.add_load(duhamel.loads.Harmonic(1, amplitude=amplitude, omega=1.0))
    >>> ens = solve_many(loaded, [1.0, 2.0], duhamel.Semianalytic(), t_end=20.0, dt=0.05,
    ...                  basis="first", reduce=lambda sol: float(np.abs(sol.x).max()))
    >>> ens.stats.basis, round(ens.results[1] / ens.results[0], 12)
    ('shared', 2.0)
    """
    if not callable(make_system):
        raise TypeError(f"`make_system` must be callable, got {type(make_system).__name__}")
    if reduce is not None and not callable(reduce):
        raise TypeError(f"`reduce` must be callable, got {type(reduce).__name__}")
    if "threads" in solve_options:
        raise ValueError("`threads` is set per run by solve_many (1); use `workers`")
    if not (progress is None or isinstance(progress, bool) or callable(progress)):
        raise TypeError(
            f"`progress` must be a bool or a function (done, n_runs), got {type(progress).__name__}"
        )
    if not isinstance(on_error, str) or on_error not in ("raise", "keep"):
        raise ValueError(f"`on_error` must be 'raise' or 'keep', got {on_error!r}")
    if to_zarr is not None and on_error == "keep":
        raise ValueError("`to_zarr` stores complete studies: use on_error='raise' with it")
    if chunk_size is not None:
        chunk_size = positive_int(chunk_size, "chunk_size")
    if workers is not None:
        workers = positive_int(workers, "workers", MAX_WORKERS)
    # the study's grid, checked as solve checks it, also when there are no cases
    steps(
        finite_float(t_end, "t_end"),
        positive_float(dt, "dt"),
        finite_float(solve_options.get("t0", 0.0), "t0"),
    )
    try:
        if isinstance(params, str | bytes):
            raise TypeError
        ps = list(params)
    except TypeError:  # None, a number, a 0-d array
        raise TypeError(
            "`params` must be an iterable of the cases' parameters (a list: records, scale "
            f"factors, dicts ...), got {type(params).__name__}"
        ) from None
    options = {"t_end": t_end, "dt": dt, **solve_options}
    job = _Job(make_system, integrator, reduce, options, on_error == "keep")
    started = time.perf_counter()
    shared = _shared_basis(basis, make_system, ps, integrator)
    stream, where, workers, sizes = dispatch(job, ps, client, workers, chunk_size, shared)
    size = int(chunk_size) if chunk_size else 64
    stream = _counted(stream, len(ps), progress)
    results: list[Any] = []
    store = None
    if to_zarr is None:
        results = list(stream)
    else:
        writer = ZarrWriter(to_zarr, size)
        block: list[Any] = []
        for result in stream:
            block.append(result)
            if len(block) == size:
                writer.write(ps[writer.written : writer.written + size], block)
                block = []
        if block or not ps:
            writer.write(ps[writer.written :], block)  # an empty study: an empty dataset
        store = writer.path
    stats = EnsembleStats(
        runs=len(ps),
        wall_time=time.perf_counter() - started,
        workers=workers,
        where=where,
        chunk_size=max(sizes, default=1),
        basis="per run" if shared is None else "shared",
    )
    return Ensemble(ps, results, stats, store)

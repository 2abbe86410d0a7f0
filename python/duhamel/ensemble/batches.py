"""How the runs of a study reach their workers (:func:`~duhamel.ensemble.solve_many`,
:func:`~duhamel.ensemble.ida`): one run (:class:`_Job`), the models a process prepared once
(:func:`_prepared`), the in-process threads (:func:`threads`) and the Dask cluster
(:func:`dask`), whose tasks are batches of runs sized from the measured time of the first
runs (:func:`batch_sizes`), the study's job and basis shipped once per worker."""

from __future__ import annotations

import math
import os
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import Any

from duhamel.errors import SolverError
from duhamel.modal import ModalBasis
from duhamel.prepared import Prepared, prepare
from duhamel.results.solution import Solution

#: The time a Dask task should last (s): long against the cluster's cost per task (a few
#: ms: scheduling, the parameters and results on the wire), short against the study.
TASK_SECONDS = 0.2
#: The shortest task the batches' tail is cut into (s).
TAIL_SECONDS = 0.02


@dataclass(frozen=True)
class _Job:
    """One study's runs: picklable, so that a Dask worker receives it whole.

    ``own_grid`` (:func:`~duhamel.ensemble.ida`'s studies of records of different lengths):
    `make_system`'s per-run options may set the run's ``t_end`` and ``dt``."""

    make_system: Callable[[Any], Any]
    integrator: Any
    reduce: Callable[[Solution], Any] | None
    options: dict[str, Any]
    keep_failures: bool
    own_grid: bool = False

    def __call__(self, index: int, p: Any, basis: ModalBasis | None = None) -> Any:
        try:
            system, options = self.make_system(p), self.options
            if isinstance(system, tuple) and len(system) == 2 and isinstance(system[1], dict):
                system, own = system  # per-run solve options: an initial state, a dofs list
                fixed = ("threads",) if self.own_grid else ("threads", "t_end", "dt")
                if any(name in own for name in fixed):
                    raise ValueError(
                        "make_system's options may not set `threads`, `t_end` or `dt` (the "
                        "study's grid)"
                    )
                options = {**options, **own}
            sol = _prepared(system, self.integrator, options["dt"], basis).run(
                **{k: v for k, v in options.items() if k != "dt"}
            )
            return sol if self.reduce is None else self.reduce(sol)
        except Exception as exc:
            if self.keep_failures and isinstance(exc, SolverError):
                return exc
            exc.add_note(f"in duhamel.ensemble.solve_many, case {index}: params = {p!r}")
            raise

    def chunk(self, cases: Sequence[tuple[int, Any]], basis: ModalBasis | None = None) -> list:
        """Several runs, one after the other."""
        return [self(i, p, basis) for i, p in cases]

    def timed(
        self, cases: Sequence[tuple[int, Any]], basis: ModalBasis | None = None
    ) -> tuple[list, list[float]]:
        """Several runs, one after the other, and each one's CPU time on this thread (s: the
        work of the run, not what other processes on a loaded machine take from it)."""
        results, seconds = [], []
        for i, p in cases:
            started = time.thread_time()
            results.append(self(i, p, basis))
            seconds.append(time.thread_time() - started)
        return results, seconds


#: Per process, the models prepared by the runs of a study: a run whose `make_system` returns
#: the same, unchanged System as an earlier run (a study over records, scale factors or
#: initial states of one model) reuses its Prepared instead of preparing it again.
_PREPARED: dict[int, Prepared] = {}
#: How many of them a process keeps.
_KEPT = 8
_LOCK = threading.Lock()


def check_model(made: Any) -> None:
    """TypeError unless `made` (what `make_system` returned) is a System or a Prepared."""
    from duhamel.system import System

    if not isinstance(made, System | Prepared):
        raise TypeError(
            "`make_system` must return a duhamel.System, a (System, options) pair or a "
            f"duhamel.Prepared, got {type(made).__name__}"
        )


def _prepared(system: Any, integrator: Any, dt: float, basis: ModalBasis | None) -> Prepared:
    """The Prepared of `system` (one thread per run), made once per unchanged system."""
    check_model(system)
    if isinstance(system, Prepared):
        if system.dt != dt or system.integrator != integrator:
            raise ValueError(
                "make_system returned a duhamel.Prepared whose `dt` or integrator differ from "
                "the study's: prepare it with the same ones"
            )
        return system
    with _LOCK:
        known = _PREPARED.get(id(system))
        if known is not None and known.matches(system, integrator, dt):
            return known
        if basis is not None:
            system.use_basis(basis)
        prepared = prepare(system, integrator, dt=dt, threads=1)
        _PREPARED.pop(id(system), None)
        while len(_PREPARED) >= _KEPT:  # the oldest first (they hold their systems alive)
            del _PREPARED[next(iter(_PREPARED))]
        _PREPARED[id(system)] = prepared
        return prepared


def threads(job: _Job, ps: list, n: int, basis: Any) -> Iterator[Any]:
    """The results in order, at most a few runs per thread in flight (one run per task:
    the threads take the next run as they finish, so none waits on another's batch)."""
    with ThreadPoolExecutor(max_workers=n) as pool:
        pending: dict[int, Any] = {}
        window, nxt = 4 * n, 0
        for i in range(len(ps)):
            while len(pending) < window and nxt < len(ps):
                pending[nxt] = pool.submit(job, nxt, ps[nxt], basis)
                nxt += 1
            yield pending.pop(i).result()


def batch_sizes(n: int, seconds: float, workers: int) -> list[int]:
    """Runs per task for `n` runs of about `seconds` each on `workers` workers: tasks of
    about :data:`TASK_SECONDS`, fewer toward the end (at most ``1 / (2 workers)`` of the runs
    left, down to tasks of :data:`TAIL_SECONDS`) so that the workers finish together.

    Examples
    --------
    >>> from duhamel.ensemble.batches import batch_sizes
    >>> sizes = batch_sizes(1000, 0.004, 2)
    >>> sum(sizes), sizes[0], sizes[-8:]
    (1000, 50, [16, 12, 9, 7, 5, 5, 5, 4])
    """
    seconds = max(float(seconds), 1e-9)
    most = max(1, int(TASK_SECONDS / seconds))
    least = min(most, max(1, math.ceil(TAIL_SECONDS / seconds)))
    sizes, left = [], n
    while left > 0:
        size = min(left, max(least, min(most, math.ceil(left / (2 * workers)))))
        sizes.append(size)
        left -= size
    return sizes


def _chunk(cases: Sequence[tuple[int, Any]], job: _Job, basis: ModalBasis | None) -> list:
    """A Dask task: `job`'s runs of `cases` (`job` and `basis` arrive once per worker)."""
    return job.chunk(cases, basis)


def _timed(
    cases: Sequence[tuple[int, Any]], job: _Job, basis: ModalBasis | None
) -> tuple[list, list[float]]:
    """A Dask task timing its runs (the study's first, whose CPU times size the batches)."""
    return job.timed(cases, basis)


def _run_seconds(seconds: list[float]) -> float:
    """A run's time from a first task's: its first run prepares the worker's model, so the
    others when there are any."""
    rest = sorted(seconds[1:] or seconds)
    return rest[len(rest) // 2]


def dask(
    job: _Job, ps: list, client: Any, size: int | None, basis: Any, workers: int
) -> tuple[Iterator[Any], list[int]]:
    """The results in order from batched tasks on the cluster, and the batches' sizes so
    far (filled as the study goes): the study's job (its `make_system` with what it holds,
    a model or records) and the basis scattered to every worker once, each task carrying
    only its cases' parameters. Without `size`, each worker first runs two tasks of two
    cases, timed on the worker (CPU time), and the remaining cases go in
    :func:`batch_sizes`' batches, sized from the first of them to finish."""
    shared = None if basis is None else client.scatter(basis, broadcast=True)
    shipped = client.scatter(job, broadcast=True, hash=False)
    indexed = list(enumerate(ps))
    sizes: list[int] = []

    def cut(start: int, lengths: list[int]) -> list[list[tuple[int, Any]]]:
        out = []
        for length in lengths:
            out.append(indexed[start : start + length])
            start += length
        return out

    def stream() -> Iterator[Any]:
        start = 0
        futures: list[Any] = []
        if size is None:
            # two timed tasks of two runs per worker: the second keeps it busy while the
            # first's times come back and the rest is cut
            first = [indexed[k : k + 2] for k in range(0, min(len(indexed), 4 * workers), 2)]
            futures = [client.submit(_timed, c, job=shipped, basis=shared, pure=False)
                       for c in first]  # fmt: skip
            sizes.extend(len(c) for c in first)
            start = sum(sizes)
            if start < len(indexed):
                from distributed import wait

                done = next(iter(wait(futures, return_when="FIRST_COMPLETED").done))
                if done.status == "finished":
                    seconds = _run_seconds(done.result()[1])
                    lengths = batch_sizes(len(indexed) - start, seconds, workers)
                else:  # a failed run: raised in case order below
                    lengths = [len(indexed) - start]
        else:
            lengths = [size] * math.ceil(len(indexed) / size)
        if start < len(indexed):
            chunks = cut(start, lengths)
            sizes.extend(len(c) for c in chunks)
            futures += client.map(_chunk, chunks, job=shipped, basis=shared, pure=False)
        for k in range(len(futures)):
            got = futures[k].result()
            futures[k] = None  # the cluster can forget it
            yield from (got[0] if isinstance(got, tuple) else got)

    return stream(), sizes


def dispatch(
    job: _Job, ps: list, client: Any, workers: int | None, chunk_size: int | None, basis: Any
) -> tuple[Iterator[Any], str, int, list[int]]:
    """`job`'s runs of `ps` on `client`'s cluster or in `workers` threads (default: the
    machine's cores): the results in order, where (``'threads'`` or ``'dask'``), the
    workers, and the tasks' sizes (filled as the study goes; ``[1]`` in threads)."""
    if client is None:
        n = (os.cpu_count() or 1) if workers is None else workers
        return threads(job, ps, n, basis), "threads", n, [1]
    n = sum(client.nthreads().values()) or 1
    stream, sizes = dask(job, ps, client, chunk_size, basis, n)
    return stream, "dask", n, sizes

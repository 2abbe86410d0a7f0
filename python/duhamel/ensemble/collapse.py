"""Collapse intensities of an IDA: each record's first collapse on the intensity grid, and
its refinement by bisection on the scale factor (:func:`duhamel.ensemble.ida` with
``tolerance=``).

A run has collapsed when it met the terminal `collapse` event (a drift limit), or stopped
with :class:`duhamel.SolverError` and ``solver_error='collapse'`` was stated (a
deteriorating model that lost its lateral strength: the Newton iterations of a step find
no equilibrium). The collapse intensity of a record is the lowest intensity found to
collapse above its last intensity that did not, in the order of the grid (the first
collapse of a hunt up the grid): a record that "resurrects" at a higher intensity keeps
its first collapse.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import numpy as np

from duhamel.errors import SolverError

__all__ = ["first_collapse", "refine"]


def first_collapse(collapsed: np.ndarray, ims: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per record (rows of `collapsed`, over the grid `ims`, taken in ascending order), the bracket
    ``(lower, upper)``: the grid intensity before the first collapse (0 when the first
    intensity collapsed) and the first collapse (``inf`` when none)."""
    order = np.argsort(ims, kind="stable")
    grid, hit = ims[order], collapsed[:, order]
    lower = np.full(hit.shape[0], float(grid[-1]))
    upper = np.full(hit.shape[0], np.inf)
    for i, row in enumerate(hit):
        hits = np.flatnonzero(row)
        if hits.size:
            j = hits[0]
            upper[i] = grid[j]
            lower[i] = grid[j - 1] if j > 0 else 0.0
    return lower, upper


def _bisect_one(
    run: Callable[[Any, float], bool],
    motion: Any,
    unit: float,
    lower: float,
    upper: float,
    tolerance: float,
) -> tuple[float, float, int]:
    """Bisect ``[lower, upper]`` (no collapse at `lower`, collapse at `upper`) until
    ``upper - lower <= tolerance * upper``; returns the bracket and the runs made."""
    runs = 0
    while upper - lower > tolerance * upper:
        mid = 0.5 * (lower + upper)
        runs += 1
        if run(motion, mid / unit):
            upper = mid
        else:
            lower = mid
    return lower, upper, runs


def refine(
    run: Callable[[Any, float], bool],
    motions: Sequence[Any],
    unit: np.ndarray,
    lower: np.ndarray,
    upper: np.ndarray,
    tolerance: float,
    workers: int | None,
) -> tuple[np.ndarray, np.ndarray, int]:
    """Bisect each record's bracket on its scale factor (``run(motion, factor) ->
    collapsed``), the records in parallel threads; returns the brackets and the number of
    runs made."""
    todo = [i for i in range(len(motions)) if np.isfinite(upper[i])]
    lo, hi = lower.copy(), upper.copy()
    if not todo:
        return lo, hi, 0
    n_threads = max(1, min(len(todo), workers or os.cpu_count() or 1))
    with ThreadPoolExecutor(n_threads) as pool:
        futures = {
            i: pool.submit(
                _bisect_one,
                run,
                motions[i],
                float(unit[i]),
                float(lower[i]),
                float(upper[i]),
                tolerance,
            )
            for i in todo
        }
        total = 0
        for i, fut in futures.items():
            lo[i], hi[i], runs = fut.result()
            total += runs
    return lo, hi, total


def is_collapse(result: Any, solver_error: str, where: str) -> bool:
    """Whether one run's result (``(measure, time)`` of a run with the collapse event, a
    measure, or the SolverError it stopped with) is a collapse."""
    if isinstance(result, SolverError):
        if solver_error == "collapse":
            return True
        result.add_note(
            f"{where}: if the model deteriorates and this is its loss of lateral strength, "
            "pass solver_error='collapse' to count such a run as a collapse"
        )
        raise result
    if isinstance(result, tuple):
        return not np.isfinite(result[0])
    return False

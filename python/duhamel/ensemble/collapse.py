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

__all__ = ["first_collapse", "outcome", "refine"]


def first_collapse(
    measures: np.ndarray, ims: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per record (rows of `measures`, ``inf`` a collapse, over the grid `ims`, taken in
    ascending order), the bracket
    ``(lower, upper)``: the grid intensity before the first collapse (0 when the first
    intensity collapsed) and the first collapse (``inf`` when none), and the measure at the
    lower end (NaN at 0 and where there was no collapse)."""
    order = np.argsort(ims, kind="stable")
    grid, hit = ims[order], ~np.isfinite(measures[:, order])
    lower = np.full(hit.shape[0], float(grid[-1]))
    upper = np.full(hit.shape[0], np.inf)
    at_lower = np.full(hit.shape[0], np.nan)
    for i, row in enumerate(hit):
        hits = np.flatnonzero(row)
        if hits.size:
            j = hits[0]
            upper[i] = grid[j]
            lower[i] = grid[j - 1] if j > 0 else 0.0
            if j > 0:
                at_lower[i] = measures[i, order[j - 1]]
    return lower, upper, at_lower


def _bisect_one(
    run: Callable[[Any, float], tuple[bool, float]],
    motion: Any,
    unit: float,
    lower: float,
    upper: float,
    at_lower: float,
    tolerance: float,
) -> tuple[float, float, float, int]:
    """Bisect ``[lower, upper]`` (no collapse at `lower`, where the measure is `at_lower`;
    a collapse at `upper`) until ``upper - lower <= tolerance * upper``; returns the
    bracket, the measure at its lower end and the runs made."""
    runs, floor = 0, upper * 2.0**-30
    while upper - lower > tolerance * upper:
        if lower == 0.0 and upper < floor:
            raise ValueError(
                f"motion {getattr(motion, 'name', motion)!r} collapses at every intensity "
                f"tried, down to {upper:.3g} (2^-30 of the first of the grid): the model "
                "fails without load? (see the runs' SolverError with solver_error='raise')"
            )
        mid = 0.5 * (lower + upper)
        runs += 1
        collapsed, value = run(motion, mid / unit)
        if collapsed:
            upper = mid
        else:
            lower, at_lower = mid, value
    return lower, upper, at_lower, runs


def refine(
    run: Callable[[Any, float], tuple[bool, float]],
    motions: Sequence[Any],
    unit: np.ndarray,
    lower: np.ndarray,
    upper: np.ndarray,
    at_lower: np.ndarray,
    tolerance: float,
    workers: int | None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    """Bisect each record's bracket on its scale factor (``run(motion, factor) ->
    (collapsed, measure)``), the records in parallel threads; returns the brackets, the
    measures at their lower ends and the number of runs made."""
    todo = [i for i in range(len(motions)) if np.isfinite(upper[i])]
    lo, hi, at = lower.copy(), upper.copy(), at_lower.copy()
    if not todo:
        return lo, hi, at, 0
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
                float(at_lower[i]),
                tolerance,
            )
            for i in todo
        }
        total = 0
        for i, fut in futures.items():
            lo[i], hi[i], at[i], runs = fut.result()
            total += runs
    return lo, hi, at, total


def outcome(result: SolverError, solver_error: str, where: str) -> tuple[bool, float]:
    """A run that stopped with SolverError: a collapse (``(True, inf)``) with
    ``solver_error='collapse'``, else the error raised with a note naming `where`."""
    if solver_error == "collapse":
        return True, np.inf
    result.add_note(
        f"{where}: if the model deteriorates and this is its loss of lateral strength, "
        "pass solver_error='collapse' to count such a run as a collapse"
    )
    raise result

"""The statistics a design code asks of a set of records (ASCE 7, Eurocode 8): per quantity,
the mean, the mean plus one standard deviation and the maximum over the records."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel.results.solution import Solution

__all__ = ["SOLUTION_QUANTITIES", "statistics"]

#: What a Solution contributes per record: the peak magnitude of each saved dof.
SOLUTION_QUANTITIES = ("x", "v", "a", "a_absolute")


def _per_record(results: Sequence[Any], quantities: Sequence[str] | None) -> dict[str, NDArray]:
    """Per quantity, the records' values stacked along a first axis."""
    failed = [i for i, r in enumerate(results) if isinstance(r, BaseException)]
    if failed:
        raise ValueError(
            f"cases {failed[:10]} failed (their results are the exceptions): statistics need "
            "every record"
        )
    if not results:
        raise ValueError("statistics need at least one record")
    if quantities is not None:
        if isinstance(quantities, str) or not isinstance(quantities, Sequence):
            raise TypeError(
                f"`quantities` must be a list of names, got {type(quantities).__name__}"
            )
        if not all(isinstance(q, str) for q in quantities):
            raise TypeError(f"`quantities` must be a list of names (strings), got {quantities!r}")
    if isinstance(results[0], Solution):
        names = list(quantities or SOLUTION_QUANTITIES)
        bad = [q for q in names if q not in SOLUTION_QUANTITIES]
        if bad:
            raise ValueError(f"`quantities` must be among {SOLUTION_QUANTITIES}, got {bad}")
        return {q: np.stack([np.abs(getattr(r, q)).max(axis=0) for r in results]) for q in names}
    rows = [r if isinstance(r, dict) else {"result": r} for r in results]
    names = list(quantities or rows[0])
    missing = [q for q in names if q not in rows[0]]
    if missing:
        raise ValueError(f"`quantities`: {missing} are not keys of the results")
    return {q: np.stack([np.asarray(row[q], dtype=np.float64) for row in rows]) for q in names}


def statistics(
    results: Sequence[Any], quantities: Sequence[str] | None = None
) -> dict[str, dict[str, NDArray[np.float64]]]:
    """See :meth:`duhamel.ensemble.Ensemble.statistics`."""
    out = {}
    for name, values in _per_record(results, quantities).items():
        mean = values.mean(axis=0)
        sigma = values.std(axis=0, ddof=1) if values.shape[0] > 1 else np.zeros_like(mean)
        out[name] = {"mean": mean, "mean_plus_sigma": mean + sigma, "max": values.max(axis=0)}
    return out

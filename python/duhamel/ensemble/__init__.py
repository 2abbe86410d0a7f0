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
``basis=`` shares one modal basis between all runs (scattered once to a cluster's workers);
``to_zarr=`` appends the results to a zarr store in case order as the runs finish.
:func:`property_bounds` and :func:`solve_bounds` make and run the lower- and upper-bound
models of a system's devices from property modification factors; :meth:`Ensemble.statistics`
gives the mean, mean + sigma and maximum over records.

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

from duhamel.ensemble.bounds import property_bounds, solve_bounds
from duhamel.ensemble.fragility import Fragility, fit_fragility
from duhamel.ensemble.ida import IDA, fractiles, ida
from duhamel.ensemble.run import Ensemble, EnsembleStats, solve_many

__all__ = [
    "IDA",
    "Ensemble",
    "EnsembleStats",
    "Fragility",
    "fit_fragility",
    "fractiles",
    "ida",
    "property_bounds",
    "solve_bounds",
    "solve_many",
]

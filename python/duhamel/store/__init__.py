"""Streamed runs with checkpoints: ``duhamel.solve(..., store="run.zarr")`` writes the saved
steps to a zarr store segment by segment (memory bounded whatever the number of steps) with
checkpoints, and :func:`resume` continues a run killed at any point (docs/store.md).

zarr is needed only when a store is used (``pip install 'duhamel[store]'``).

Examples
--------
>>> import tempfile, numpy as np, duhamel
>>> sys = duhamel.System(np.eye(1), np.eye(1), zeta=0.05)
>>> path = tempfile.mkdtemp() + "/run.zarr"
>>> sol = duhamel.solve(sys, duhamel.Semianalytic(), t_end=10.0, dt=0.01, x0=[1.0],
...                     store=path)
>>> sol.x                       # read from the store on access
StoredArray(shape=(1001, 1), dtype=float64)
>>> ref = duhamel.solve(sys, duhamel.Semianalytic(), t_end=10.0, dt=0.01, x0=[1.0])
>>> bool(np.array_equal(sol.x[:], ref.x))    # bit for bit
True
"""

from __future__ import annotations

from duhamel.store._array import StoredArray
from duhamel.store._codec import StoreError
from duhamel.store._run import FORMAT, Store, resume

__all__ = ["FORMAT", "Store", "StoreError", "StoredArray", "resume"]

"""A very long streamed run (issue 14): 1e8 steps of a 10-dof chain saving one dof every step
to a zarr store (``modal=False``); run it under ``/usr/bin/time -v`` for the peak memory.

Usage::

    /usr/bin/time -v python benchmarks/store_long.py 1e8 /tmp/long.zarr   # then rm -r it

The store takes about 30 MB per 1e6 steps (3 GB for 1e8).
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import sys  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

import duhamel  # noqa: E402
from duhamel.store import Store  # noqa: E402


def main(argv: list[str]) -> int:
    steps, path = int(float(argv[0])), argv[1]
    n = 10
    K = 100.0 * (2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1))
    s = duhamel.System(np.eye(n), K, zeta=0.02)
    s.add_load(duhamel.loads.Harmonic(dof=n - 1, amplitude=1.0, omega=3.0))
    t0 = time.perf_counter()
    sol = duhamel.solve(
        s, duhamel.Semianalytic(), store=Store(path, modal=False), t_end=steps * 1e-3, dt=1e-3,
        dofs=[n - 1],
    )  # fmt: skip
    rows = sol.t.shape[0]
    print(f"{steps:,} steps, {rows:,} rows stored (all: {rows == steps + 1}), last t "
          f"{float(sol.t[-1]):g} s, {time.perf_counter() - t0:.1f} s")  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))

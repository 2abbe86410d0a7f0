"""The cost of the store's checksums (issue 24, format 2): a streamed run of 1e6 steps of a
10-dof chain saving one dof every step (``modal=False``), then ``resume`` of the complete
store (which reads and checks every committed chunk). Prints one line; run it with
``PYTHONPATH`` on each tree to compare, interleaved.

Usage::

    PYTHONPATH=python python benchmarks/store_checksums.py issue24
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import shutil  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

import duhamel  # noqa: E402
from duhamel.store import Store  # noqa: E402


def main(label: str) -> None:
    n = 10
    k = 2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    s = duhamel.System(np.eye(n), 1e3 * k, zeta=0.02)
    s.add_load(duhamel.loads.Harmonic(n - 1, 1.0, omega=3.0))
    where = tempfile.mkdtemp()
    try:
        start = time.perf_counter()
        duhamel.solve(s, duhamel.Semianalytic(), t_end=1e4, dt=0.01, dofs=[9],
                      store=Store(where + "/r.zarr", modal=False))  # fmt: skip
        run = time.perf_counter() - start
        start = time.perf_counter()
        duhamel.resume(where + "/r.zarr")
        again = time.perf_counter() - start
    finally:
        shutil.rmtree(where)
    print(f"{label} run {run:.3f} resume {again:.3f}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "this tree")

"""The cost of the store's checks: the CRC-32C of every data chunk (issue 24, format 2) and
the chunk digests, manifest and sealed checkpoints of a store that knows its chunks (issue
38, format 3).

A streamed run of a 10-dof chain saving one dof every step (``modal=False``), ``resume`` of
the complete store (which reads and checks every committed chunk), then a read of the whole
``x`` history through the returned Solution. Prints one line per repeat: the three times and,
on a tree with format 3, the seconds spent inside the checks (recording the digests during
the run; comparing them and the checkpoints' chains on resume; comparing them on the read).
Run it with ``PYTHONPATH`` on each tree to compare, interleaved.

Usage::

    PYTHONPATH=python python benchmarks/store_checksums.py LABEL [--steps 1e7]
        [--segment-bytes 33554432] [--repeats 1]
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import shutil  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from collections import defaultdict  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

import duhamel  # noqa: E402
from duhamel.store import Store  # noqa: E402

#: Seconds spent in each instrumented check (format 3 trees only).
SPENT: dict[str, float] = defaultdict(float)


def _instrument() -> bool:
    """Wraps the format-3 checks with timers; False on a tree without them."""
    try:
        from duhamel.store import _ledger
    except ImportError:
        return False

    def timed(cls: Any, name: str, key: str) -> None:
        inner = getattr(cls, name)

        def wrapper(*args: Any, **kwargs: Any) -> Any:
            start = time.perf_counter()
            try:
                return inner(*args, **kwargs)
            finally:
                SPENT[key] += time.perf_counter() - start

        setattr(cls, name, wrapper)

    timed(_ledger.Ledger, "record", "record")
    timed(_ledger.Ledger, "chain", "chain")
    timed(_ledger.Ledger, "check", "check")
    return True


def main(label: str, steps: float, segment_bytes: int, repeats: int) -> None:
    checks = _instrument()
    n = 10
    k = 2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    s = duhamel.System(np.eye(n), 1e3 * k, zeta=0.02)
    s.add_load(duhamel.loads.Harmonic(n - 1, amplitude=1.0, omega=3.0))
    dt = 0.01
    for _ in range(repeats):
        where = tempfile.mkdtemp()
        path = where + "/r.zarr"
        try:
            SPENT.clear()
            start = time.perf_counter()
            duhamel.solve(s, duhamel.Semianalytic(), t_end=steps * dt, dt=dt, dofs=[9],
                          store=Store(path, modal=False, segment_bytes=segment_bytes))  # fmt: skip
            run = time.perf_counter() - start
            in_run = dict(SPENT)
            SPENT.clear()
            start = time.perf_counter()
            sol = duhamel.resume(path)
            again = time.perf_counter() - start
            in_resume = dict(SPENT)
            SPENT.clear()
            start = time.perf_counter()
            total = float(np.asarray(sol.x).sum())
            read = time.perf_counter() - start
            in_read = dict(SPENT)
            chunks = len(os.listdir(path + "/data/x/c"))
        finally:
            shutil.rmtree(where)
        line = (
            f"{label} steps {steps:.0e} chunks/array {chunks} run {run:.3f} resume {again:.3f} "
            f"read-x {read:.3f}"
        )
        if checks:
            rec = in_run.get("record", 0.0) + in_run.get("chain", 0.0)
            ver = in_resume.get("check", 0.0) + in_resume.get("chain", 0.0)
            line += (
                f" | checks: in run {rec:.4f} ({100 * rec / run:.2f} %), in resume {ver:.4f} "
                f"({100 * ver / again:.2f} %), in read {in_read.get('check', 0.0):.4f} "
                f"({100 * in_read.get('check', 0.0) / read:.2f} %)"
            )
        print(line, f"[{total:.3e}]", flush=True)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("label", nargs="?", default="this tree")
    parser.add_argument("--steps", type=float, default=1e6)
    parser.add_argument("--segment-bytes", type=int, default=32 * 2**20)
    parser.add_argument("--repeats", type=int, default=1)
    args = parser.parse_args()
    main(args.label, args.steps, args.segment_bytes, args.repeats)

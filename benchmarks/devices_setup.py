"""What a call of the devices benchmark spends beyond duhamel's loop (issue 22).

The four models of ``benchmarks/devices.py`` at its coarsest step (the record's 5 ms, 4,000
steps), each call building its System anew as that benchmark does: the whole call, the core's
loop (``stats.loop_time``, or ``stats.wall_time`` in builds without it) and their difference,
best of 15 calls (the difference: median). Run it once per build to compare::

    .venv/bin/python benchmarks/devices_setup.py
    PYTHONPATH=../baseline/python .venv/bin/python benchmarks/devices_setup.py
"""

from __future__ import annotations

import os
import sys
import time

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

sys.path.insert(0, os.path.dirname(__file__))
import devices as d  # noqa: E402
import numpy as np  # noqa: E402

import duhamel  # noqa: E402


def call(case: d.Case, gm: d.GroundMotion) -> duhamel.Solution:
    """One call as ``devices.run_duhamel`` makes it at k = 1."""
    if case.name == d.FPS:
        s = duhamel.System(d.M * np.eye(2), np.zeros((2, 2)))
        s.add(case.device).add_load(gm.as_load(np.array([1.0, 0.0])))
    else:
        s = duhamel.System(d.M * np.eye(1), d.K_FRAME * np.eye(1), C=d.A0 * d.M * np.eye(1))
        s.add(case.device).add_load(gm.as_load(np.ones(1)))
    return duhamel.solve(s, duhamel.Semianalytic(), t_end=gm.duration, dt=d.DT_REC)


def main() -> None:
    gm = d.record(20.0)
    print(f"1-min load average {os.getloadavg()[0]:.2f}")
    print("| model | call [ms] | loop [ms] | beyond the loop [ms] |")
    print("|---|---:|---:|---:|")
    for case in d.cases():
        total, loop = [], []
        for _ in range(15):
            t = time.perf_counter()
            sol = call(case, gm)
            total.append(time.perf_counter() - t)
            stats = sol.stats
            loop.append(float(getattr(stats, "loop_time", stats.wall_time)))
        tot, lp = np.array(total), np.array(loop)
        print(
            f"| {case.name} | {1e3 * tot.min():.2f} | {1e3 * lp.min():.2f} | "
            f"{1e3 * np.median(tot - lp):.3f} |"
        )


if __name__ == "__main__":
    main()

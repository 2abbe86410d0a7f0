"""Table 1's Newmark / semi-analytic ratio (issue 41: at least 1.8 on a quiet machine) for
one or more builds of duhamel, in alternating subprocesses.

Each subprocess runs the paper's case (section 4.4: beta = 0.1, xi = 0.1, 5000 steps of
1e-4 s) with the full model (``Semianalytic(modes=20, coupling="pseudo-force",
static_correction=False)``, as ``duhamel.paper.rotor.table1``) and ``Newmark()``, one of
each `--repeats` times, interleaved, after one untimed pair. Reported per build: the loop time
(:attr:`duhamel.SolveStats.wall_time`, the time ``table1`` reports), best and median, and
the thread CPU time of each whole ``solve`` call (less sensitive to a loaded machine; it
includes the set-up outside the loop, printed apart), with the 1-minute load average
before and after.

    python benchmarks/table1_ratio.py --builds /work/main/python,python --rounds 4

(`--builds`: directories holding a ``duhamel`` package, first on ``sys.path`` in turn.)
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys

import numpy as np

CHILD = r"""
import json, time, warnings
import duhamel
from duhamel.paper.rotor_model import COUPLING, DT, T_END, paper_system
warnings.simplefilter("ignore")
system = paper_system(0.1, 0.1)
out = {"sa": [], "nm": []}
for first in [True] + [False] * REPEATS:  # the first pair warms the caches, untimed
    for key, make in (
        ("sa", lambda: duhamel.Semianalytic(modes=20, coupling=COUPLING, static_correction=False)),
        ("nm", lambda: duhamel.Newmark()),
    ):
        cpu = time.thread_time()
        sol = duhamel.solve(system, make(), t_end=T_END, dt=DT)
        cpu = time.thread_time() - cpu
        st = sol.stats
        if not first:
            out[key].append((st.wall_time, cpu, st.total_time - st.wall_time, st.steps))
print(json.dumps(out))
"""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--builds", required=True, help="comma-separated package directories")
    parser.add_argument("--rounds", type=int, default=4, help="subprocesses per build")
    parser.add_argument("--repeats", type=int, default=5, help="runs of each per subprocess")
    args = parser.parse_args()
    builds = [os.path.abspath(b) for b in args.builds.split(",")]
    child = CHILD.replace("REPEATS", str(int(args.repeats)))
    runs: dict[str, dict[str, list]] = {b: {"sa": [], "nm": []} for b in builds}
    loads = [os.getloadavg()[0]]
    for _ in range(args.rounds):
        for b in builds:
            env = dict(os.environ, PYTHONPATH=b, OPENBLAS_NUM_THREADS="1")
            proc = subprocess.run(
                [sys.executable, "-c", child], env=env, capture_output=True, text=True, check=True
            )
            got = json.loads(proc.stdout)
            for key in ("sa", "nm"):
                runs[b][key].extend(got[key])
        loads.append(os.getloadavg()[0])
    print(f"load average (1 min): {min(loads):.2f} - {max(loads):.2f}")
    for b in builds:
        sa, nm = np.array(runs[b]["sa"]), np.array(runs[b]["nm"])
        us = 1e6 / sa[0, 3]
        pairs = nm[:, 0] / sa[:, 0]
        print(
            f"{b}\n  loop [us/step]: semi-analytic best {us * sa[:, 0].min():.2f} median "
            f"{us * np.median(sa[:, 0]):.2f}, Newmark best {us * nm[:, 0].min():.2f} median "
            f"{us * np.median(nm[:, 0]):.2f}; ratio of bests "
            f"{nm[:, 0].min() / sa[:, 0].min():.3f}, "
            f"median of the paired ratios {np.median(pairs):.3f} ({len(sa)} pairs)\n"
            f"  whole solve, thread CPU [us/step]: semi-analytic best {us * sa[:, 1].min():.2f}, "
            f"Newmark best {us * nm[:, 1].min():.2f}; ratio {nm[:, 1].min() / sa[:, 1].min():.3f} "
            f"(outside the loop: {us * sa[:, 2].min():.2f} and {us * nm[:, 2].min():.2f})"
        )


if __name__ == "__main__":
    main()

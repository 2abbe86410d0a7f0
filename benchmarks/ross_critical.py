"""Critical speeds of ROSS's compressor, two builds of duhamel interleaved (issue 40).

``rotor.critical_speeds(np.linspace(50, 1500, 30))`` on ``from_ross(compressor_example())``
(the forward critical speeds, each with its amplification factor from the unbalance
response), in a fresh process per build and round, builds alternating; each process times
3 calls after one warm-up and reports the best wall and CPU (``time.process_time``) time and
the first critical speed's numbers, so that the builds' answers are compared too.

Usage::

    python benchmarks/ross_critical.py --old /work/main/python --new python [--rounds 3]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys

CHILD = r"""
import contextlib, io, json, os, time, warnings
import numpy as np
with warnings.catch_warnings(), contextlib.redirect_stdout(io.StringIO()), \
        contextlib.redirect_stderr(io.StringIO()):
    warnings.simplefilter("ignore")
    import ross
    rr = ross.compressor_example()
from duhamel.rotor import from_ross
model = from_ross(rr, 0.0)
grid = np.linspace(50.0, 1500.0, 30)
model.rotor.critical_speeds(grid)
times = []
for _ in range(3):
    w0, c0 = time.perf_counter(), time.process_time()
    crit = model.rotor.critical_speeds(grid)
    times.append((time.perf_counter() - w0, time.process_time() - c0))
c = crit.critical[0]
print(json.dumps({"wall": min(t[0] for t in times), "cpu": min(t[1] for t in times),
                  "load": os.getloadavg()[0], "speed": c.speed, "peak": c.peak_speed,
                  "af": c.amplification_factor, "half": list(c.half_power),
                  "zeta": c.damping_ratio}))
"""


def run(path: str) -> dict:
    env = dict(os.environ, PYTHONPATH=path, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")
    out = subprocess.run([sys.executable, "-c", CHILD], env=env, capture_output=True,
                         text=True, check=True).stdout  # fmt: skip
    return json.loads(out.strip().splitlines()[-1])


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--old", required=True, help="PYTHONPATH of the old build")
    parser.add_argument("--new", required=True, help="PYTHONPATH of the new build")
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args(argv)
    rows: dict[str, list[dict]] = {"old": [], "new": []}
    for _ in range(args.rounds):
        for name in ("old", "new"):
            rows[name].append(run(getattr(args, name)))
    print("| build | best wall [s] | best CPU [s] | load | speed [rad/s] | N_c [rad/s] | AF |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for name, rs in rows.items():
        for r in rs:
            print(f"| {name} | {r['wall']:.3f} | {r['cpu']:.3f} | {r['load']:.1f} | "
                  f"{r['speed']:.10f} | {r['peak']:.8f} | {r['af']:.9f} |")  # fmt: skip
    for key in ("speed", "peak", "af", "zeta"):
        old = [r[key] for r in rows["old"]]
        new = [r[key] for r in rows["new"]]
        ref = sum(old) / len(old)
        spread_old = (max(old) - min(old)) / abs(ref)
        spread_new = (max(new) - min(new)) / abs(ref)
        diff = max(abs(n - o) for n in new for o in old) / abs(ref)
        print(
            f"{key}: old spread {spread_old:.1e}, new spread {spread_new:.1e}, "
            f"largest old-new difference {diff:.1e}"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

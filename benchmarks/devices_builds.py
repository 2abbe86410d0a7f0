"""The devices benchmark's duhamel calls under two builds, interleaved (issue 23): is a change
faster, and are its answers the same?

The models of ``benchmarks/devices.py`` that issue 23 names (``Bilinear``, ``ViscousDamper``
without brace, the bidirectional ``FrictionPendulum``), each call made as that benchmark
makes it (the System built anew, one ``solve`` at ``dt = 0.005 / k``, saving at the record's
samples), timed whole; each build runs in its own subprocess per repeat, the builds
alternating (old, new, old, new, ...), so that the machine's load hits both alike. The
table gives the best time of each build and their ratio, and whether the two builds'
displacements are identical bit for bit (else their largest difference over the peak)::

    .venv/bin/python benchmarks/devices_builds.py --old ../baseline/python --new python
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
MODELS = ("Bilinear / Steel01", "ViscousDamper / Viscous", "FrictionPendulum / singleFPBearing")

WORKER = r"""
import json, sys, time
sys.path.insert(0, sys.argv[1])
import numpy as np
import devices as d
gm = d.record(20.0)
cases = {c.name: c for c in d.cases()}
ks, calls, out = json.loads(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
times, arrays = {}, {}
for name in json.loads(sys.argv[5]):
    for k in ks:
        arrays[f"{name}|{k}"] = d.run_duhamel(cases[name], gm, k)
        best = float("inf")
        for _ in range(calls):
            t0 = time.perf_counter()
            d.run_duhamel(cases[name], gm, k)
            best = min(best, time.perf_counter() - t0)
        times[f"{name}|{k}"] = best
np.savez(out, **arrays)
print(json.dumps(times))
"""


def run(build: str, ks: list[int], calls: int, out: str) -> dict[str, float]:
    env = dict(os.environ, PYTHONPATH=os.path.abspath(build), OPENBLAS_NUM_THREADS="1")
    args = [sys.executable, "-c", WORKER, HERE, json.dumps(ks), str(calls), out]
    done = subprocess.run(
        [*args, json.dumps(MODELS)], env=env, capture_output=True, text=True, check=True
    )
    return json.loads(done.stdout.strip().splitlines()[-1])


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--old", required=True, help="directory holding the old duhamel")
    parser.add_argument("--new", required=True, help="directory holding the new duhamel")
    parser.add_argument("--repeats", type=int, default=3, help="subprocesses per build")
    parser.add_argument("--calls", type=int, default=5, help="timed calls per subprocess")
    parser.add_argument("--k", default="1,2,4,8", help="the steps 0.005/k, comma-separated")
    args = parser.parse_args(argv)
    ks = [int(k) for k in args.k.split(",")]
    load0 = os.getloadavg()[0]
    best: dict[str, dict[str, float]] = {"old": {}, "new": {}}
    tmp = tempfile.mkdtemp()
    for _ in range(args.repeats):
        for which in ("old", "new"):
            times = run(getattr(args, which), ks, args.calls, os.path.join(tmp, which))
            for key, t in times.items():
                best[which][key] = min(best[which].get(key, float("inf")), t)
    old, new = np.load(os.path.join(tmp, "old.npz")), np.load(os.path.join(tmp, "new.npz"))
    print(f"1-min load average before {load0:.2f}, after {os.getloadavg()[0]:.2f}\n")
    print("| model | k | old [ms] | new [ms] | old / new | answers |")
    print("|---|---:|---:|---:|---:|---|")
    for key in best["old"]:
        name, k = key.split("|")
        a, b = old[key], new[key]
        same = a.tobytes() == b.tobytes()
        diff = "identical" if same else f"differ by {np.abs(a - b).max() / np.abs(a).max():.1e}"
        to, tn = 1e3 * best["old"][key], 1e3 * best["new"][key]
        print(f"| {name} | {k} | {to:.2f} | {tn:.2f} | {to / tn:.2f} | {diff} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

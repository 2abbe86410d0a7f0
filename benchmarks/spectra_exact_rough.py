"""Exact-peak spectra against sampled ones on rough records and short periods (issue 42).

200 log-spaced periods 0.02..5 s, 5 % damping, one core, records of 20,000 samples at
0.01 s with a 2-s build-up and a decay after 60 s: band-limited noise (0.2-12 Hz) and white
noise (the roughest). In each process ``response_spectrum(..., peaks="sampled")`` and
``peaks="exact"`` alternate (``--repeats`` pairs per record); the ratio exact / sampled is
taken in the same process, so the machine's load hits both alike. Wall time and the
process's CPU time (``time.thread_time``: what a loaded machine's other processes do not
add) are both given. With ``--old DIR`` the same is run in processes of another build
(a directory holding the ``duhamel`` package with its compiled ``_core``), alternating
with the new one, and the exact peaks of the two builds are compared value by value.

Usage::

    python benchmarks/spectra_exact_rough.py --old ../baseline/src/python --new python
    python benchmarks/spectra_exact_rough.py --new python --quick
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys

WORKER = r"""
import json, sys, time
import numpy as np
import scipy.signal
from duhamel.spectra import response_spectrum

repeats = int(sys.argv[1])
dt, n = 0.01, 20000
rng = np.random.default_rng(0)
t = dt * np.arange(n)
env = np.minimum(t / 2, 1) * np.exp(-np.maximum(t - 60, 0) / 30)
b, a = scipy.signal.butter(4, [0.2, 12.0], btype="band", fs=1 / dt)
records = {}
x = env * scipy.signal.lfilter(b, a, rng.normal(size=n))
records["band-limited"] = 3 * x / abs(x).max()
x = env * rng.normal(size=n)
records["white"] = 3 * x / abs(x).max()
periods = np.logspace(np.log10(0.02), np.log10(5.0), 200)
out = {}
for name, acc in records.items():
    times = {"sampled": ([], []), "exact": ([], [])}
    for _ in range(repeats):
        for kind, (wall, cpu) in times.items():
            w0, c0 = time.perf_counter(), time.thread_time()
            s = response_spectrum((t, acc), periods, 0.05, threads=1, peaks=kind)
            cpu.append(time.thread_time() - c0)
            wall.append(time.perf_counter() - w0)
            if kind == "exact":
                peaks = np.concatenate([s.sd.ravel(), s.sv.ravel(), s.sa.ravel()])
    out[name] = {"times": times, "exact": peaks.tolist()}
print(json.dumps(out))
"""


def measure(path: str, repeats: int) -> dict:
    env = dict(os.environ, PYTHONPATH=os.path.abspath(path), OPENBLAS_NUM_THREADS="1")
    run = subprocess.run(
        [sys.executable, "-c", WORKER, str(repeats)], env=env, capture_output=True, text=True
    )
    if run.returncode != 0:
        sys.exit(f"the build in {path} failed:\n{run.stderr}")
    return json.loads(run.stdout.strip().splitlines()[-1])


def ratios(runs: list[dict], name: str, clock: int) -> tuple[float, float, float, float]:
    """Sampled and exact, best and median (ms), over every call of every process."""
    s = [v for r in runs for v in r[name]["times"]["sampled"][clock]]
    e = [v for r in runs for v in r[name]["times"]["exact"][clock]]
    return 1e3 * min(s), 1e3 * statistics.median(s), 1e3 * min(e), 1e3 * statistics.median(e)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--new", required=True, help="directory holding the new duhamel")
    parser.add_argument("--old", help="directory holding the old duhamel (optional)")
    parser.add_argument("--processes", type=int, default=3, help="processes per build")
    parser.add_argument("--repeats", type=int, default=7, help="pairs per record and process")
    parser.add_argument("--quick", action="store_true", help="1 process, 2 pairs")
    args = parser.parse_args(argv)
    if args.quick:
        args.processes, args.repeats = 1, 2
    builds = {"new": args.new} | ({"old": args.old} if args.old else {})
    load_before = os.getloadavg()[0]
    runs: dict[str, list[dict]] = {k: [] for k in builds}
    for _ in range(args.processes):
        for key, path in reversed(builds.items()):
            runs[key].append(measure(path, args.repeats))
    load_after = os.getloadavg()[0]
    print(
        f"1-min load average {load_before:.2f} before, {load_after:.2f} after; "
        f"{args.processes} processes per build x {args.repeats} interleaved pairs per record"
    )
    print()
    print(
        "| build | record | clock | sampled best / median [ms] | exact best / median [ms] "
        "| exact / sampled (best / median) |"
    )
    print("|---|---|---|---:|---:|---:|")
    for key in builds:
        for name in runs[key][0]:
            for clock, label in ((0, "wall"), (1, "CPU")):
                sb, sm, eb, em = ratios(runs[key], name, clock)
                print(
                    f"| {key} | {name} | {label} | {sb:.2f} / {sm:.2f} | {eb:.2f} / {em:.2f} "
                    f"| {eb / sb:.2f} / {em / sm:.2f} |"
                )
    if args.old:
        for name in runs["new"][0]:
            a = runs["old"][0][name]["exact"]
            b = runs["new"][0][name]["exact"]
            same = sum(x == y for x, y in zip(a, b, strict=True))
            worst = max(abs(x - y) / abs(x) for x, y in zip(a, b, strict=True) if x != 0)
            print(
                f"\n{name}: exact peaks old vs new: {same} of {len(a)} identical, "
                f"largest relative difference {worst:.1e}"
            )


if __name__ == "__main__":
    main()

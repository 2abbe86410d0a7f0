"""What a short run costs beyond the core's time loop, in two builds of duhamel (issue 22).

A 10-dof fixed-free chain (unit masses, link stiffness 1e4, 5 % modal damping, a harmonic
load at the top, ``dt = 5 ms``), integrated by ``Semianalytic()``:

* ``solve`` on a fresh ``System`` (made before each call: its construction with the load and
  element is timed apart and reported too; ``solve`` then does the modal analysis), 10 steps,
  linear — with the same matrices every call (a study that rebuilds its model: the checks of
  ``M``, ``K`` and the first modal analysis are shared by content since issue 22) and with
  matrices never seen before (``K`` scaled by ``1 + 1e-9 k`` at call ``k``: nothing shared);
* the same with one ``duhamel.elements.Bilinear`` between dofs 3 and 4, 10 and 800 steps;
* where the build has ``duhamel.prepare``: ``Prepared.run`` of the same three cases, on one
  ``Prepared`` made once.

Per call: the total time (``time.perf_counter`` around the call), the core's loop time
(``sol.stats.loop_time`` where the build has it, else ``sol.stats.wall_time``) and their
difference, "beyond the loop". Each build runs in fresh subprocesses (``--repeats`` of
them, the builds alternating old, new, old, new, ... so that the machine's load hits both
alike), each process warming up then timing ``--calls`` calls of every case; the table gives
the median over all calls and the best call. A build is a directory holding the ``duhamel``
package with its compiled ``_core`` (as for ``compare.py``)::

    .venv/bin/python benchmarks/overhead.py --old ../baseline/python --new python --repeats 3

The targets of issue 22: beyond the loop, ``solve`` on a fresh System <= 0.15 ms and
``Prepared.run`` <= 0.03 ms, linear and with the Bilinear element.
"""

from __future__ import annotations

import argparse
import json
import os
import shlex
import statistics
import subprocess
import sys

WORKER = r"""
import gc, json, sys, time
import numpy as np
import duhamel
from duhamel import elements as E, loads as L

calls, warmup = int(sys.argv[1]), int(sys.argv[2])
N, DT = 10, 0.005
K = 1e4 * (2 * np.eye(N) - np.eye(N, k=1) - np.eye(N, k=-1))
K[-1, -1] = 1e4
M = np.eye(N)
INTEGRATOR = duhamel.Semianalytic()


def fresh(element, stiffness=K):
    s = duhamel.System(M, stiffness, zeta=0.05)
    s.add_load(L.Harmonic(N - 1, amplitude=10.0, omega=12.0))  # both builds take keywords
    if element:
        s.add(E.Bilinear(3, 4, k=5e3, fy=0.02, alpha=0.05))
    return s


def loop_time(sol):
    stats = sol.stats
    return float(getattr(stats, "loop_time", stats.wall_time))


CASES = [("linear", False, 10), ("bilinear", True, 10), ("bilinear", True, 800)]
out = {"prepare": hasattr(duhamel, "prepare"),
       "loop_attr": "loop_time" if hasattr(duhamel.SolveStats, "loop_time")
       or "loop_time" in getattr(duhamel.SolveStats, "__dataclass_fields__", {})
       else "wall_time",
       "rows": []}
for name, element, steps in CASES:
    t_end = steps * DT
    # solve on a fresh System: the same matrices every call, then matrices never seen before
    # (nothing shared between systems)
    for label, scale in (("", lambda k: 1.0), ("new matrices, ", lambda k: 1.0 + 1e-9 * (k + 1))):
        construct, total, loop = [], [], []
        for k in range(warmup + calls):
            stiffness = K * scale(k)
            t0 = time.perf_counter()
            s = fresh(element, stiffness)
            t1 = time.perf_counter()
            sol = duhamel.solve(s, INTEGRATOR, t_end=t_end, dt=DT)
            t2 = time.perf_counter()
            if k >= warmup:
                construct.append(t1 - t0)
                total.append(t2 - t1)
                loop.append(loop_time(sol))
        assert sol.t.size == steps + 1
        out["rows"].append({"case": f"solve, fresh System, {label}{name}", "steps": steps,
                            "total": total, "loop": loop, "construct": construct})
    if out["prepare"]:
        t0 = time.perf_counter()
        prepared = duhamel.prepare(fresh(element), INTEGRATOR, dt=DT)
        made = time.perf_counter() - t0
        total, loop = [], []
        for k in range(warmup + calls):
            t1 = time.perf_counter()
            sol = prepared.run(t_end=t_end)
            t2 = time.perf_counter()
            if k >= warmup:
                total.append(t2 - t1)
                loop.append(loop_time(sol))
        assert sol.t.size == steps + 1
        out["rows"].append({"case": f"Prepared.run, {name}", "steps": steps,
                            "total": total, "loop": loop, "construct": [made]})
print(json.dumps(out))
"""


def measure(path: str, calls: int, warmup: int) -> dict:
    env = dict(os.environ, PYTHONPATH=os.path.abspath(path), OPENBLAS_NUM_THREADS="1")
    out = subprocess.run(
        [sys.executable, "-c", WORKER, str(calls), str(warmup)],
        env=env,
        capture_output=True,
        text=True,
    )
    if out.returncode != 0:
        sys.exit(f"the build in {path} failed:\n{out.stderr}")
    return json.loads(out.stdout.strip().splitlines()[-1])


def merge(runs: list[dict]) -> dict[tuple[str, int], dict[str, list[float]]]:
    """Every call of every process, per case."""
    merged: dict[tuple[str, int], dict[str, list[float]]] = {}
    for run in runs:
        for row in run["rows"]:
            into = merged.setdefault(
                (row["case"], row["steps"]),
                {"total": [], "loop": [], "beyond": [], "construct": []},
            )
            into["total"] += row["total"]
            into["loop"] += row["loop"]
            into["beyond"] += [t - w for t, w in zip(row["total"], row["loop"], strict=True)]
            into["construct"] += row["construct"]
    return merged


def ms(values: list[float]) -> str:
    return f"{1e3 * statistics.median(values):.3f} / {1e3 * min(values):.3f}"


def cell(data: dict[str, list[float]] | None, key: str) -> str:
    return "—" if data is None or not data[key] else ms(data[key])


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--old", required=True, help="directory holding the old duhamel")
    parser.add_argument("--new", required=True, help="directory holding the new duhamel")
    parser.add_argument("--repeats", type=int, default=3, help="processes per build")
    parser.add_argument("--calls", type=int, default=200, help="timed calls per case and process")
    parser.add_argument("--warmup", type=int, default=30, help="untimed calls first")
    parser.add_argument("--label", default="", help="what the two builds are, for the report")
    parser.add_argument("--append", metavar="MD", help="append the report to this markdown file")
    args = parser.parse_args(argv)
    load_before = os.getloadavg()[0]
    old, new = [], []
    for _ in range(args.repeats):
        old.append(measure(args.old, args.calls, args.warmup))
        new.append(measure(args.new, args.calls, args.warmup))
    load_after = os.getloadavg()[0]
    o, n = merge(old), merge(new)
    keys = list(o) + [k for k in n if k not in o]
    lines = [
        f"## Overhead beyond the core's loop{': ' + args.label if args.label else ''}",
        "",
        "A 10-dof chain (`benchmarks/overhead.py`): milliseconds per call, median / best over "
        f"{args.repeats} fresh processes per build x {args.calls} calls (after {args.warmup} "
        "warm-up calls), the builds alternating. *total*: the call; *loop*: the core's time "
        f"loop (old: `stats.{old[0]['loop_attr']}`, new: `stats.{new[0]['loop_attr']}`); "
        "*beyond* = total - loop, per call; *System*: making the fresh `System` with its "
        "load (and element), not in *total* (for `Prepared.run`: `prepare` once). Targets "
        "(issue 22), beyond the loop: `solve` on a fresh System <= 0.15 ms, `Prepared.run` "
        "<= 0.03 ms. Command:",
        "",
        "```sh",
        shlex.join([".venv/bin/python", "benchmarks/overhead.py", *sys.argv[1:]]),
        "```",
        "",
        f"1-min load average: {load_before:.2f} before, {load_after:.2f} after.",
        "",
        "| case | steps | old total | old loop | old beyond | old System | new total | new loop "
        "| new beyond | new System |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for key in keys:
        a, b = o.get(key), n.get(key)
        lines.append(
            f"| {key[0]} | {key[1]} | "
            + " | ".join(cell(a, k) for k in ("total", "loop", "beyond", "construct"))
            + " | "
            + " | ".join(cell(b, k) for k in ("total", "loop", "beyond", "construct"))
            + " |"
        )
    lines.append("")
    print("\n".join(lines))
    if args.append:
        with open(args.append, "a", encoding="utf-8") as f:
            f.write("\n" + "\n".join(lines))


if __name__ == "__main__":
    main()

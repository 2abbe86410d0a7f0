"""Two builds of duhamel on the same cases, interleaved: is a change slower?

Each case runs in a fresh subprocess per build and repeat, the builds alternating (old, new,
old, new, ...), so the machine's load hits both alike; the table gives the best loop time
(``Solution.stats.wall_time``) of each and their ratio. A build is a directory holding the
``duhamel`` package with its compiled ``_core`` (e.g. a ``git worktree`` of an older commit
with the extension copied in, and ``python/`` of this checkout)::

    .venv/bin/python benchmarks/compare.py --old ../baseline/python --new python --repeats 7

The cases are the engine's routes: the uncoupled linear loop (every step saved, and the
kernel alone), the closed-form and the Newton Duffing step, a 5-mode Newton chain, a
gyroscopic rotor on the exact first-order background (linear, and with a rub), and Newmark
on a 20-dof chain.
"""

from __future__ import annotations

import argparse
import json
import os
import shlex
import subprocess
import sys

CASE = r"""
import json, sys, time
import numpy as np
import duhamel
from duhamel import elements as E, loads as L

def chain(n, k=1e6):
    return k * (2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1))

case = sys.argv[1]
if case.startswith("linear"):
    n = 100
    K = chain(n); K[-1, -1] = 1e6
    s = duhamel.System(np.eye(n), K, zeta=0.02)
    s.add_load(L.Harmonic(n - 1, 1000.0, 4 * np.pi)).add_load(L.Step(49, 500.0))
    steps = 100_000
    save = steps if case == "linear-kernel" else 1
    run = lambda: duhamel.solve(s, duhamel.Semianalytic(), t_end=steps * 1e-3, dt=1e-3,
                                dofs=[n - 1], threads=1, save_every=save)
elif case.startswith("duffing"):
    s = duhamel.System(np.eye(1), np.eye(1)).add(E.Cubic(0, 4.0))
    steps = 1_000_000 if case == "duffing" else 200_000
    solver = "newton" if case == "duffing-newton" else "auto"
    run = lambda: duhamel.solve(s, duhamel.Semianalytic(solver=solver), t_end=steps * 0.0628,
                                dt=0.0628, x0=[1.0])
elif case == "chain-newton":
    n = 20
    s = duhamel.System(np.eye(n), chain(n, 1e4), zeta=0.02)
    for d in (3, 8, 13, 18):
        s.add(E.Spring(d, None, k=0.0, k3=1e7))
    s.add_load(L.Harmonic(n - 1, 50.0, 20.0))
    steps = 100_000
    run = lambda: duhamel.solve(s, duhamel.Semianalytic(modes=5), t_end=steps * 1e-3,
                                dt=1e-3)
elif case.startswith("rotor"):
    from duhamel import rotor as R
    steel = R.Material(E=211e9, rho=7810.0, nu=0.3)
    shafts = [R.Shaft(0.1, 0.05, material=steel) for _ in range(12)]
    disks = [R.Disk.from_geometry(6, 0.07, 0.28, 0.05, steel)]
    bearings = [R.Bearing(0, kxx=1e7, kyy=1e7, cxx=1e3, cyy=1e3, kxy=1e6, kyx=-1e6),
                R.Bearing(12, kxx=1e7, kyy=1e7, cxx=1e3, cyy=1e3)]
    machine = R.Rotor(shafts, disks, bearings, rayleigh=(1.0, 1e-5))
    speed = R.rpm(3000)
    s = machine.system(speed, loads=[R.Unbalance(6, 1e-4, speed)])
    if case == "rotor-rub":
        dx, dy = machine.dof(6, "x"), machine.dof(6, "y")
        s.add(E.Contact(dx, dy, clearance=2e-6, stiffness=1e7, friction=0.1))
    steps = 100_000 if case == "rotor" else 20_000
    run = lambda: duhamel.solve(s, duhamel.Semianalytic(), t_end=steps * 1e-4, dt=1e-4,
                                threads=1)
elif case == "newmark":
    n = 20
    s = duhamel.System(np.eye(n), chain(n, 1e4), zeta=0.02)
    s.add_load(L.Harmonic(n - 1, 50.0, 20.0))
    steps = 100_000
    run = lambda: duhamel.solve(s, duhamel.Newmark(), t_end=steps * 1e-3, dt=1e-3)
run()  # warm-up: first calls of a process are slower (page faults, caches)
sol = run()
print(json.dumps({"wall": sol.stats.wall_time, "steps": sol.stats.steps,
                  "route": sol.stats.coupling}))
"""

CASES = [
    "linear",
    "linear-kernel",
    "duffing",
    "duffing-newton",
    "chain-newton",
    "rotor",
    "rotor-rub",
    "newmark",
]


def measure(path: str, case: str) -> float:
    env = dict(os.environ, PYTHONPATH=os.path.abspath(path), OPENBLAS_NUM_THREADS="1")
    out = subprocess.run(
        [sys.executable, "-c", CASE, case], env=env, capture_output=True, text=True, check=True
    )
    return float(json.loads(out.stdout.strip().splitlines()[-1])["wall"])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--old", required=True, help="directory holding the old duhamel")
    parser.add_argument("--new", required=True, help="directory holding the new duhamel")
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--cases", default=",".join(CASES))
    parser.add_argument("--label", default="", help="what the two builds are, for the report")
    parser.add_argument("--append", metavar="MD", help="append the report to this markdown file")
    args = parser.parse_args()
    lines = [
        f"## Two builds compared{': ' + args.label if args.label else ''}",
        "",
        "Loop time (`Solution.stats.wall_time`), best of "
        f"{args.repeats} fresh processes per build, the builds alternating. Command:",
        "",
        "```sh",
        shlex.join([".venv/bin/python", "benchmarks/compare.py", *sys.argv[1:]]),
        "```",
        "",
        f"1-min load average before: {os.getloadavg()[0]:.2f}",
        "",
        "| case | old best [s] | new best [s] | new / old |",
        "|---|---:|---:|---:|",
    ]
    print("\n".join(lines), flush=True)
    for case in args.cases.split(","):
        old, new = [], []
        for _ in range(args.repeats):
            old.append(measure(args.old, case))
            new.append(measure(args.new, case))
        row = f"| {case} | {min(old):.4g} | {min(new):.4g} | {min(new) / min(old):.3f} |"
        print(row, flush=True)
        lines.append(row)
    lines += ["", f"1-min load average after: {os.getloadavg()[0]:.2f}", ""]
    print(lines[-2])
    if args.append:
        with open(args.append, "a") as f:
            f.write("\n" + "\n".join(lines))


if __name__ == "__main__":
    main()

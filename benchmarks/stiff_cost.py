"""What the stiff-element substep rule costs (issue 23): two builds, interleaved, on the
family of tests/engine/test_stiff_elements.py, the issue's stop and the coupled (first-order)
route's family of tests/engine/test_stiff_coupled.py (``coupled-*``: Newmark at half that step as
the reference), per run the loop time
(``Solution.stats.wall_time``, best of the repeats) and the error against Newmark at
``omega_c dt = 0.01`` (at most 1e-3), as a fraction of the peak::

    .venv/bin/python benchmarks/stiff_cost.py --old ../baseline/python --new python --repeats 5

Each build runs in its own subprocess per repeat, the builds alternating, so that the
machine's load hits both alike.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys

WORKER = r"""
import json, sys
import numpy as np
import duhamel
from duhamel import elements as E
from duhamel.loads import BaseAcceleration

def family(kind, ratio):
    n = 2 if kind == "contact" else 1
    s = duhamel.System(np.eye(n), np.eye(n), zeta=0.05)
    s.add({"gap": lambda: E.Gap(0, gap=0.3, k=ratio),
           "contact": lambda: E.Contact(0, 1, clearance=0.3, stiffness=ratio),
           "cubic": lambda: E.Cubic(0, (ratio / 3.0) ** 3),
           "bilinear": lambda: E.Bilinear(0, k=ratio, fy=0.5, alpha=0.05)}[kind]())
    t = np.linspace(0.0, 6.0, 12001)
    s.add_load(BaseAcceleration(np.ones(n), t, np.sin(0.8 * t)))
    return s, 6.0, float(np.sqrt(1.0 + ratio))

def issue_gap(_kind, _ratio):
    t = np.linspace(0.0, 3.0, 30001)
    s = duhamel.System(10.0 * np.eye(1), 1e4 * np.eye(1), zeta=0.05)
    s.add(E.Gap(0, gap=0.02, k=1e8))
    s.add_load(BaseAcceleration(np.ones(1), t, 40.0 * np.sin(2 * np.pi * t)))
    return s, 3.0, float(np.sqrt(1e7 + 1e3))

def coupled(kind, ratio):
    s = duhamel.System(np.eye(2), np.diag([1.0, 4.0]), C=np.array([[0.1, 0.03], [0.03, 0.2]]))
    s.add({"gap": lambda: E.Gap(0, gap=0.3, k=ratio),
           "contact": lambda: E.Contact(0, 1, clearance=0.3, stiffness=ratio),
           "cubic": lambda: E.Cubic(0, (ratio / 3.0) ** 3)}[kind]())
    t = np.linspace(0.0, 6.0, 12001)
    scale = 2.0 if kind == "contact" else 1.0
    s.add_load(BaseAcceleration(np.ones(2), t, scale * np.sin(0.8 * t)))
    return s, 6.0, float(np.sqrt(1.0 + ratio))

CASES = [("gap", 1e4, 0.1), ("gap", 1e4, 1.0), ("contact", 1e4, 0.1), ("contact", 1e6, 1.0),
         ("cubic", 1e2, 0.1), ("cubic", 1e4, 1.0), ("cubic", 1e6, 0.1),
         ("bilinear", 1e4, 0.1), ("bilinear", 1e6, 1.0),
         ("issue-gap", 0.0, 0.316), ("issue-gap", 0.0, 3.16),
         ("coupled-gap", 1e4, 0.1), ("coupled-gap", 1e6, 0.1), ("coupled-gap", 1e6, 0.5),
         ("coupled-contact", 1e4, 0.1), ("coupled-cubic", 1e4, 0.25)]
out = {}
for kind, ratio, h in CASES:
    coupled_kind = kind.startswith("coupled-")
    make = issue_gap if kind == "issue-gap" else coupled if coupled_kind else family
    elem = kind.removeprefix("coupled-")
    s, t_end, w = make(elem, ratio)
    dt = h / w
    name = f"{kind} kappa={ratio:g} omega_c dt={h:g}" if ratio else f"{kind} omega_c dt={h:g}"
    try:
        semi = duhamel.Semianalytic
        integrator = semi(coupling="exact") if coupled_kind else semi()
        sol = duhamel.solve(s, integrator, t_end=t_end, dt=dt)
    except duhamel.SolverError as e:
        out[name] = {"wall": None, "error": "stop: " + e.reason}
        continue
    row = {"wall": sol.stats.wall_time, "sub": sol.stats.subdivided_steps, "steps": sol.stats.steps}
    if sys.argv[1] == "1":
        ref = duhamel.solve(make(elem, ratio)[0], duhamel.Newmark(), t_end=t_end,
                            dt=min(0.01 / w, 1e-3) / (2 if coupled_kind else 1))
        nm = duhamel.solve(make(elem, ratio)[0], duhamel.Newmark(), t_end=t_end, dt=dt)
        def err(a):
            x = np.interp(a.t, ref.t, ref.x[:, 0])
            return float(np.abs(a.x[:, 0] - x).max() / np.abs(ref.x[:, 0]).max())
        row["error"], row["newmark"] = err(sol), err(nm)
    out[name] = row
print(json.dumps(out))
"""


def run(build: str, errors: bool) -> dict:
    env = {**os.environ, "PYTHONPATH": build, "OPENBLAS_NUM_THREADS": "1"}
    cmd = [sys.executable, "-c", WORKER, "1" if errors else "0"]
    done = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True)
    return json.loads(done.stdout)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--old", required=True, help="directory holding the old duhamel")
    parser.add_argument("--new", required=True, help="directory holding the new duhamel")
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    first = {"old": run(args.old, True), "new": run(args.new, True)}
    best = {b: {k: v.get("wall") for k, v in first[b].items()} for b in first}
    for _ in range(args.repeats - 1):
        for b, path in (("old", args.old), ("new", args.new)):
            for k, v in run(path, False).items():
                if v.get("wall") is not None and best[b][k] is not None:
                    best[b][k] = min(best[b][k], v["wall"])
    print("| case | old: error / loop | new: error / loop (substeps) | new / old | Newmark |")
    print("|---|---|---|---|---|")
    for k in first["new"]:
        o, n = first["old"][k], first["new"][k]

        def cell(r, b, k=k):
            if r.get("wall") is None:
                return r["error"]
            return f"{r['error']:.3g} / {best[b][k] * 1e3:.2f} ms"

        ratio = (
            f"{best['new'][k] / best['old'][k]:.2f}"
            if best["new"][k] is not None and best["old"][k] is not None
            else "-"
        )
        nm = n.get("newmark", o.get("newmark", "-"))
        nm = f"{nm:.3g}" if isinstance(nm, float) else nm
        print(
            f"| {k} | {cell(o, 'old')} | {cell(n, 'new')} "
            f"({n.get('sub', 0)}/{n.get('steps', '-')}) | {ratio} | {nm} |"
        )


if __name__ == "__main__":
    main()

"""Non-classical damping on 56 dofs against classical damping: the cost of a fresh `solve`.

A 56-dof chain (an isolated building's size after condensing its rotations) under a 40 s
record, dt = 0.01 s: modal damping ratios (classical, the uncoupled route) against Rayleigh
damping restricted to the superstructure's stiffness (non-classical, the exact first-order
route). Each call builds a fresh `System` (as a study does), so the classical run takes its
modes from an earlier identical system (issue 22) and the non-classical run its first-order
modes (issue 25); *first call* clears that cache for the non-classical run (the
decomposition is made). Median / best milliseconds over interleaved repeats, and the ratio
to the classical run.

    .venv/bin/python benchmarks/damping_nonclassical.py [--quick] [--append BENCHMARKS.md]
"""

from __future__ import annotations

import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))

from _section import main as _main
from _section import timed

import duhamel
from duhamel._engine import coupled

N = 56


def _model() -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    K = 1e8 * (2 * np.eye(N) - np.eye(N, k=1) - np.eye(N, k=-1))
    K[-1, -1] = 1e8
    M = 1e5 * np.eye(N)
    upper = np.arange(8, N)  # the superstructure's dofs
    Ks = np.zeros_like(K)
    Ks[np.ix_(upper, upper)] = K[np.ix_(upper, upper)]
    t = np.arange(0.0, 40.0, 0.01)
    return M, K, Ks, t, np.sin(3 * t) * np.exp(-0.05 * t)


def section(quick: bool, repeats: int = 15) -> list[str]:
    M, K, Ks, t, ag = _model()
    load = duhamel.loads.BaseAcceleration(np.ones(N), t=t, values=ag)
    rayleigh = duhamel.Rayleigh(0.0, 0.002, stiffness=Ks)

    def run(kind: str) -> None:
        if kind == "classical":
            system = duhamel.System(M, K, zeta=0.05)
        else:
            system = duhamel.System(M, K, rayleigh=rayleigh)
        duhamel.solve(system.add_load(load), duhamel.Semianalytic(), t_end=40.0, dt=0.01)

    def first(kind: str) -> None:
        coupled._KNOWN.clear()
        run(kind)

    cases = {
        "classical (zeta = 0.05)": lambda: run("classical"),
        "non-classical, first-order modes cached": lambda: run("non-classical"),
        "non-classical, first call (decomposed)": lambda: first("non-classical"),
    }
    for f in cases.values():  # warm-up
        f()
    times: dict[str, list[float]] = {k: [] for k in cases}
    for _ in range(2 if quick else repeats):
        for name, f in cases.items():  # interleaved
            times[name].append(1e3 * timed(f))
    base = float(np.median(times["classical (zeta = 0.05)"]))
    load_avg = os.getloadavg()[0]
    lines = [
        "## Non-classical damping on 56 dofs (issue 25)",
        "",
        __doc__.split("\n\n")[1].replace("\n", " "),
        "",
        "```sh",
        ".venv/bin/python benchmarks/damping_nonclassical.py --append BENCHMARKS.md",
        "```",
        "",
        f"1-min load average: {load_avg:.2f}.",
        "",
        "| case | median ms | best ms | median / classical |",
        "|---|---:|---:|---:|",
    ]
    for name, ts in times.items():
        med = float(np.median(ts))
        lines.append(f"| {name} | {med:.2f} | {min(ts):.2f} | {med / base:.2f} |")
    return lines


if __name__ == "__main__":
    raise SystemExit(_main(__doc__, section, "two repeats", None))

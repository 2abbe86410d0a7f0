"""The cost of one nonlinear step against the linear one (issue 23's per-step targets).

Models (the devices benchmark's record, 30 s at dt = 0.005 / 4, 24,000 steps):

* one dof, ``m = 1e5``, ``T = 1 s``, 2 % mass-proportional damping, with and without
  ``Bilinear(k, fy = 0.1 m g, alpha = 0.05)``;
* a 10-dof shear chain of the same storey, 5 % modal damping, with and without the same
  ``Bilinear`` at the base;
* one dof with a hardening ``Cubic`` (the closed-form cubic step).

Per step: the core's loop time (``SolveStats.loop_time``) over the steps, best of `--repeats`
runs of a `duhamel.Prepared`, the models interleaved in each repeat.

    python benchmarks/step_cost.py [--repeats 7]
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Callable

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

from devices import A0, DT_REC, FY, K_FRAME, M, record

import duhamel
from duhamel import elements as E

GM = record(30.0)
DT = DT_REC / 4


def one_dof(bilinear: bool) -> duhamel.System:
    s = duhamel.System(M * np.eye(1), K_FRAME * np.eye(1), C=A0 * M * np.eye(1))
    if bilinear:
        s.add(E.Bilinear(0, k=K_FRAME, fy=FY, alpha=0.05))
    return s.add_load(GM.as_load(np.ones(1)))


def chain(bilinear: bool, n: int = 10) -> duhamel.System:
    K = np.zeros((n, n))
    for i in range(n):
        K[i, i] += K_FRAME
        if i + 1 < n:
            K[i, i] += K_FRAME
            K[i, i + 1] -= K_FRAME
            K[i + 1, i] -= K_FRAME
    s = duhamel.System(M * np.eye(n), K, zeta=0.05)
    if bilinear:
        s.add(E.Bilinear(0, k=K_FRAME, fy=FY, alpha=0.05))
    return s.add_load(GM.as_load(np.ones(n)))


def cubic() -> duhamel.System:
    s = duhamel.System(np.eye(1), (2 * np.pi) ** 2 * np.eye(1), zeta=0.02)
    s.add(E.Cubic(0, k3=1e3))
    return s.add_load(GM.as_load(np.ones(1)))


MODELS: dict[str, Callable[[], duhamel.System]] = {
    "one dof, linear": lambda: one_dof(False),
    "one dof, Bilinear": lambda: one_dof(True),
    "10-dof chain, linear": lambda: chain(False),
    "10-dof chain, Bilinear": lambda: chain(True),
    "one dof, Cubic (closed form)": cubic,
}


def main(argv: list[str] | None = None) -> dict[str, float]:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args(argv)
    n = round(GM.duration / DT)
    prepared = {k: duhamel.prepare(f(), duhamel.Semianalytic(), dt=DT) for k, f in MODELS.items()}
    best = dict.fromkeys(MODELS, np.inf)
    for _ in range(args.repeats):
        for name, p in prepared.items():
            sol = p.run(t_end=n * DT, save_every=n)
            best[name] = min(best[name], sol.stats.loop_time / n)
    print(f"load average {os.getloadavg()[0]:.2f}; {n} steps, best of {args.repeats}")
    print("| model | ns per step |")
    print("|---|---|")
    for name, t in best.items():
        print(f"| {name} | {1e9 * t:.0f} |")
    chain_ratio = best["10-dof chain, Bilinear"] / best["10-dof chain, linear"]
    print(f"\n10-dof chain: the Bilinear step costs {chain_ratio:.1f} times the linear one")
    return best


if __name__ == "__main__":
    main()

"""One cell of ``benchmarks/local.py``'s table: the lattice's nonlinear step against its
linear one at one mode count and one number of cubic springs, timed as that benchmark
times them (``duhamel.solve``, 1e4 steps, ``Solution.stats.wall_time`` per step, best of
`--repeats`, the two interleaved), without its other cells and accuracy runs: quick enough
to interleave builds (run it under each build's ``PYTHONPATH`` in turn).

    python benchmarks/lattice_step.py [--modes 100] [--springs 3] [--repeats 5]
"""

from __future__ import annotations

import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402
from local import Setup, _run, lattice  # noqa: E402

import duhamel  # noqa: E402
from duhamel import elements as E  # noqa: E402
from duhamel import loads as L  # noqa: E402


def main(argv: list[str] | None = None) -> dict[str, float]:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--modes", type=int, default=100)
    parser.add_argument("--springs", type=int, default=3)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args(argv)
    s = Setup()
    m, k = lattice(s.shape, s.k)
    n = m.shape[0]
    tip = n - 1
    basis = duhamel.System(m, k, zeta=0.02).modal(args.modes)
    # the springs local.py places: the same generator, seed and draw
    dofs = np.random.default_rng(7).choice(n - 1, size=max(s.springs), replace=False)
    load = L.Harmonic(tip, amplitude=s.force, omega=s.frequency)

    def system(n_springs: int) -> duhamel.System:
        sys_ = duhamel.System(m, k, zeta=0.02).use_basis(basis).add_load(load)
        for d in dofs[:n_springs]:
            sys_.add(E.Cubic(int(d), k3=s.k3))
        return sys_

    linear, nonlinear = system(0), system(args.springs)
    best = {"linear": np.inf, "springs": np.inf}
    for _ in range(args.repeats):
        best["linear"] = min(best["linear"], _run(linear, args.modes, "auto", s, tip))
        best["springs"] = min(best["springs"], _run(nonlinear, args.modes, "auto", s, tip))
    ratio = best["springs"] / best["linear"]
    print(
        f"load average {os.getloadavg()[0]:.2f}; {args.modes} modes: linear "
        f"{1e6 * best['linear']:.3f} us/step, {args.springs} springs "
        f"{1e6 * best['springs']:.3f} us/step = {ratio:.2f} x linear (best of {args.repeats})"
    )
    return best


if __name__ == "__main__":
    main()

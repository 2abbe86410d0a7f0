"""The cost of the basis-truncation estimate (issue 41): reduced runs with
``duhamel._engine.modal.attach_truncation`` on and off, interleaved, process CPU time, best
and median of 7, and the estimate's own time taken around its call (the whole runs' times
vary by more than the estimate under load). A 60-dof chain with a Bilinear and a cubic
spring, 10 modes, 5,000 steps; the 20,384-dof lattice of ``benchmarks/truncation_lattice.py``
with its harmonic load, 100 modes, 2,000 steps; caches warmed by one run first.

    python benchmarks/truncation_cost.py
"""

from __future__ import annotations

import os
import sys
import time
import warnings

sys.path.insert(0, os.path.dirname(__file__))
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402
from truncation_lattice import model  # noqa: E402

import duhamel  # noqa: E402
import duhamel._engine.modal as mod  # noqa: E402
from duhamel import elements as E  # noqa: E402
from duhamel import loads as L  # noqa: E402


def chain(n: int = 60) -> duhamel.System:
    k = np.diag(np.full(n, 2e4)) - np.diag(np.full(n - 1, 1e4), 1)
    k = k - np.diag(np.full(n - 1, 1e4), -1)
    k[-1, -1] = 1e4
    s = duhamel.System(np.eye(n), k, zeta=0.02)
    s.add(E.Bilinear(0, k=1e4, fy=0.05, alpha=0.1))
    s.add(E.Cubic(10, k3=1e7))
    s.add_load(L.Harmonic(n - 1, amplitude=100.0, omega=5.0))
    return s


def main() -> None:
    warnings.simplefilter("ignore", duhamel.AccuracyWarning)
    on = mod.attach_truncation
    spent: list[float] = []

    def timed(*args, **kwargs):  # the estimate, its own process CPU time taken
        started = time.process_time()
        on(*args, **kwargs)
        spent.append(time.process_time() - started)

    cases = (
        ("60-dof chain, 10 modes, 5,000 steps", chain(), 10, 5000),
        (
            "20,384-dof lattice, 100 modes, 2,000 steps",
            model((28, 28, 26), "harmonic")[0],
            100,
            2000,
        ),
    )
    print(f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load {os.getloadavg()}")
    for name, system, modes, steps in cases:
        duhamel.solve(system, duhamel.Semianalytic(modes=modes), t_end=steps * 1e-3, dt=1e-3)
        for correct in (False, True):
            times: dict[str, list[float]] = {"on": [], "off": []}
            spent.clear()
            for _ in range(7):
                for label, fn in (("on", timed), ("off", lambda *a, **k: None)):
                    mod.attach_truncation = fn
                    run = duhamel.Semianalytic(modes=modes, static_correction=correct)
                    started = time.process_time()
                    duhamel.solve(system, run, t_end=steps * 1e-3, dt=1e-3)
                    times[label].append(time.process_time() - started)
            mod.attach_truncation = on
            best = {k: min(v) for k, v in times.items()}
            median = {k: float(np.median(v)) for k, v in times.items()}
            own = (min(spent), float(np.median(spent)))
            print(
                f"{name}, correction {correct}: the estimate {1e3 * own[0]:.2f} ms best, "
                f"{1e3 * own[1]:.2f} ms median = {100 * own[0] / best['off']:.1f} % / "
                f"{100 * own[1] / median['off']:.1f} % of the run without it (best "
                f"{1e3 * best['off']:.1f} ms, median {1e3 * median['off']:.1f} ms); whole "
                f"runs with it: best {1e3 * best['on']:.1f} ms "
                f"(+{100 * (best['on'] / best['off'] - 1):.1f} %), median "
                f"{1e3 * median['on']:.1f} ms (+{100 * (median['on'] / median['off'] - 1):.1f} "
                f"%); load average {os.getloadavg()[0]:.1f}"
            )


if __name__ == "__main__":
    main()

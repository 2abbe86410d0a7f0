"""The basis-truncation estimate of reduced runs against the full model (issue 41, "Large
reduced models"): a 3-D scalar lattice (``benchmarks/local.py``'s, unit masses, links
``k = 1e4``, Rayleigh damping ``0.5 M + 1e-4 K``: 1.8 % at the top frequency, 2.5 %
at 10 rad/s) with four yielding ``Bilinear`` springs to ground at random dofs
(``k = 1e4``, ``fy = 0.5``, ``alpha = 0.05``), under a point force at a top corner: a
half-sine pulse (2,000 N over 50 ms: it excites the truncated modes dynamically) or a
harmonic force (300 N at 6 rad/s: quasi-static for them). Reduced runs
``Semianalytic(modes=m, static_correction=c)`` for m in 5, 20, 50, 100 with and without the
correction, 2 s in steps of 1 ms; the truth is the full model: ``Semianalytic()`` on all
modes (``--reference full``, small lattices) or ``Newmark`` at ``dt/4`` saved every 4th step
(``--reference newmark``, the 20,000-dof lattice, whose dense eigenproblem does not fit).
Per spring: the true error (largest deformation error over the run relative to the full
model's peak deformation) against ``sol.stats.element_truncation_estimate``, and whether the
run warned (``duhamel.AccuracyWarning`` at the default ``error_warning=0.01``).

    python benchmarks/truncation_lattice.py --shape 12x12x14 --reference full
    python benchmarks/truncation_lattice.py --shape 28x28x26 --reference newmark
"""

from __future__ import annotations

import argparse
import os
import sys
import time
import warnings

sys.path.insert(0, os.path.dirname(__file__))
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402
from local import lattice  # noqa: E402

import duhamel  # noqa: E402
from duhamel import elements as E  # noqa: E402
from duhamel import loads as L  # noqa: E402

MODES = (5, 20, 50, 100)
DT, T_END = 1e-3, 2.0


def model(
    shape: tuple[int, int, int], load: str, springs: int = 4
) -> tuple[duhamel.System, list[int]]:
    """The lattice with its springs and load, and the dofs to save: the loaded one, then the
    springs' (their deformations)."""
    m, k = lattice(shape, 1e4)
    n = m.shape[0]
    tip = n - 1
    dofs = np.random.default_rng(3).choice(n - 1, size=springs, replace=False)
    system = duhamel.System(m, k, rayleigh=(0.5, 1e-4))
    if load == "pulse":
        t = np.linspace(0.0, 0.05, 51)
        system.add_load(L.Tabulated(tip, t=t, values=2000.0 * np.sin(np.pi * t / 0.05)))
    else:
        system.add_load(L.Harmonic(tip, amplitude=300.0, omega=6.0))
    for d in dofs:
        system.add(E.Bilinear(int(d), k=1e4, fy=0.5, alpha=0.05))
    return system, [tip, *(int(d) for d in dofs)]


def reference(system: duhamel.System, saved: list[int], how: str) -> duhamel.Solution:
    """The full model's run (saved at the reduced runs' instants)."""
    if how == "full":
        return duhamel.solve(system, duhamel.Semianalytic(), t_end=T_END, dt=DT, dofs=saved)
    return duhamel.solve(
        system, duhamel.Newmark(), t_end=T_END, dt=DT / 4, save_every=4, dofs=saved
    )


def rows(
    system: duhamel.System, saved: list[int], full: duhamel.Solution, modes=MODES
) -> list[dict]:
    """One row per reduced run and spring: true error, estimate, warned."""
    out = []
    for m in modes:
        for correct in (False, True):
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                run = duhamel.Semianalytic(modes=m, static_correction=correct)
                started = time.perf_counter()
                sol = duhamel.solve(system, run, t_end=T_END, dt=DT, dofs=saved)
                seconds = time.perf_counter() - started
            warned = any(
                issubclass(w.category, duhamel.AccuracyWarning)
                and "reduced basis" in str(w.message)
                for w in caught
            )
            for index in range(len(saved) - 1):
                a, b = sol.x[:, index + 1], full.x[:, index + 1]
                true = float(np.abs(a - b).max() / np.abs(b).max())
                est = sol.stats.element_truncation_estimate[index]
                out.append(
                    {
                        "modes": m,
                        "correction": correct,
                        "spring": index,
                        "true": true,
                        "estimate": est,
                        "warned": warned,
                        "seconds": seconds,
                    }
                )
    return out


def table(result: list[dict]) -> str:
    lines = [
        "| modes | correction | spring | true error | estimate | estimate / true | warned |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in result:
        lines.append(
            f"| {r['modes']} | {'yes' if r['correction'] else 'no'} | {r['spring']} | "
            f"{r['true']:.3g} | {r['estimate']:.3g} | {r['estimate'] / r['true']:.2f} | "
            f"{'yes' if r['warned'] else 'NO'} |"
        )
    ratios = np.array([r["estimate"] / r["true"] for r in result])
    within = float(np.mean((ratios >= 1 / 3) & (ratios <= 3)))
    silent = [r for r in result if r["true"] >= 0.1 and not r["warned"]]
    lines.append("")
    lines.append(
        f"{len(result)} cases: estimate within a factor 3 of the truth in {100 * within:.0f} %; "
        f"ratio {ratios.min():.2f} - {ratios.max():.2f}; runs 10 % or more off without a "
        f"warning: {len(silent)}"
    )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--shape", default="12x12x14")
    parser.add_argument("--reference", choices=("full", "newmark"), default="full")
    parser.add_argument("--loads", default="pulse,harmonic")
    parser.add_argument("--t-end", type=float, default=2.0, help="run length [s]")
    args = parser.parse_args(argv)
    global T_END
    T_END = args.t_end
    shape = tuple(int(a) for a in args.shape.split("x"))
    for load in args.loads.split(","):
        system, saved = model(shape, load)  # type: ignore[arg-type]
        started = time.perf_counter()
        full = reference(system, saved, args.reference)
        print(
            f"\n### {args.shape} lattice ({system.n_dof:,} dofs), {load}; full model: "
            f"{args.reference} ({time.perf_counter() - started:.0f} s); {T_END:g} s; load average "
            f"{os.getloadavg()[0]:.1f}; {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}\n",
            flush=True,
        )
        print(table(rows(system, saved, full)), flush=True)


if __name__ == "__main__":
    main()

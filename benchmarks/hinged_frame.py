"""The hinged frame of issue 36: duhamel against OpenSees on the same model, time to equal
accuracy and where duhamel's step time goes.

The frame (``tests/_support/_hinged.py``): 4 storeys, 2 bays, elastic beam-columns, floor masses at
the column nodes, rotational ``zeroLength`` ``Steel01`` hinges at the 16 beam ends (52 dofs
in duhamel: 24 with mass, 28 massless rotations), Rayleigh damping 5 % at 0.6 s and 0.1 s on
the current tangent (``betaK``: the massless rotations are first-order), no gravity; 6 s of
a synthetic record (PGA 4 m/s^2).

* OpenSees: Newmark (average acceleration), ``Newton``, ``NormDispIncr`` 1e-12,
  ``BandGeneral`` with RCM, ``k`` steps per record interval of 0.01 s; timed: the analysis.
* duhamel: ``Semianalytic()`` at ``dt = 0.01 / k``; timed: ``from_opensees()``, the load and
  the run with its modal analysis (a fresh system every time); per step: the core's loop
  time (``SolveStats.loop_time``) over the steps.

Error: the largest roof displacement difference over the run, divided by the largest roof
displacement, against each program's own converged run (OpenSees at k = 64, duhamel at
k = 32). Where the step time goes: the same model linear (the hinges elastic, in ``K``; the
same first-order coordinates, coupled to the modes), and with the hinges but no damping at
the massless dofs (mass-proportional only: static coordinates, no coupling).

Usage::

    python benchmarks/hinged_frame.py [--repeats 3] [--append BENCHMARKS.md]
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import importlib.util  # noqa: E402
import subprocess  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

import duhamel  # noqa: E402
import duhamel.opensees  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
_spec = importlib.util.spec_from_file_location(
    "_hinged", ROOT / "tests" / "_support" / "_hinged.py"
)
assert _spec is not None and _spec.loader is not None
hf = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(hf)

STOREYS, BAYS = 4, 2
W1, W3 = 2 * np.pi / 0.6, 2 * np.pi / 0.1
A0, A1 = 2 * 0.05 * W1 * W3 / (W1 + W3), 2 * 0.05 / (W1 + W3)
TOLS = (1e-2, 1e-3, 1e-4)


def build(rayleigh=(A0, A1, 0.0, 0.0)) -> None:
    hf.build(storeys=STOREYS, bays=BAYS, rayleigh=rayleigh)


def run_opensees(t, a, k):
    build()
    t0 = time.perf_counter()
    x, _, _ = hf.run_opensees(
        t, a, k, hf.node(STOREYS, 0), [hf.node(0, line) for line in range(BAYS + 1)]
    )
    return time.perf_counter() - t0, x


def system(t, a, rayleigh=(A0, A1, 0.0, 0.0), linear=False):
    build(rayleigh)
    s = duhamel.opensees.from_opensees()
    if linear:  # the hinges elastic: their stiffness back in K, no elements
        K = np.array(s.K, dtype=float)
        for e in s.elements:
            dofs, k0 = e._linear()
            K[np.ix_(dofs, dofs)] += k0
        C = None if s.C is None else np.asarray(s.C)
        s = duhamel.System(s.M, K, C=C).label_dofs(s.opensees.labels)
    return s.add_load(duhamel.loads.BaseAcceleration("ux", t=t, values=a))


def run_duhamel(t, a, k, **kw):
    t0 = time.perf_counter()
    s = system(t, a, **kw)
    roof = s.dof(hf.node(STOREYS, 0), "ux")
    sol = duhamel.solve(
        s, duhamel.Semianalytic(), t_end=float(t[-2]), dt=0.01 / k, save_every=k, dofs=[roof]
    )
    return time.perf_counter() - t0, sol.x[:, 0], sol.stats


def err(x, ref) -> float:
    return float(np.abs(x - ref).max() / np.abs(ref).max())


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--append")
    args = parser.parse_args()
    t, a = hf.record(duration=6.0)
    ks_os, ks_du = (1, 2, 4, 8, 16), (1, 2, 4, 8)
    _, ref_os = run_opensees(t, a, 64)
    _, ref_du, _ = run_duhamel(t, a, 32)
    rows: dict = {}
    step_us: dict = {}
    for _ in range(args.repeats):  # interleaved
        for k_os, k_du in zip(ks_os, (*ks_du, None), strict=True):
            wall, x = run_opensees(t, a, k_os)
            best = rows.get(("OpenSees", k_os), (np.inf, 0.0))[0]
            rows["OpenSees", k_os] = (min(best, wall), err(x, ref_os))
            if k_du is None:
                continue
            wall, x, stats = run_duhamel(t, a, k_du)
            best = rows.get(("duhamel", k_du), (np.inf, 0.0))[0]
            rows["duhamel", k_du] = (min(best, wall), err(x, ref_du))
            us = 1e6 * stats.loop_time / stats.steps
            step_us[k_du] = min(step_us.get(k_du, np.inf), us)
        for name, kw in (
            ("linear", dict(linear=True)),
            ("undamped massless", dict(rayleigh=(A0, 0.0, 0.0, 0.0))),
        ):
            _, _, stats = run_duhamel(t, a, 4, **kw)
            us = 1e6 * stats.loop_time / stats.steps
            step_us[name] = min(step_us.get(name, np.inf), us)
    _, _, stats = run_duhamel(t, a, 4)
    load = os.getloadavg()[0]
    rev = subprocess.run(
        ["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True, text=True
    ).stdout.strip()
    out = [
        "## The hinged frame of issue 36 against OpenSees",
        "",
        f"Generated by `benchmarks/hinged_frame.py --repeats {args.repeats}` at {rev}: "
        f"{STOREYS} storeys, {BAYS} bays, 52 dofs (28 massless), 16 hinges, 6 s; best of "
        f"{args.repeats}, interleaved; load average {load:.2f} (2 cores shared).",
        "",
        "| program | k (dt = 0.01/k) | wall [s] | error vs own converged run | step [us] |",
        "|---|---|---|---|---|",
    ]
    for (name, k), (wall, e) in rows.items():
        us = f"{step_us[k]:.1f}" if name == "duhamel" else ""
        out.append(f"| {name} | {k} | {wall:.3f} | {e:.1e} | {us} |")
    out.append("")
    out.append(f"Converged runs against each other: {err(ref_du, ref_os):.1e} of the peak.")
    out.append(
        f"Step at k = 4: {step_us[4]:.1f} us with the hinges "
        f"({stats.newton_iterations / stats.steps:.2f} "
        f"Newton iterations and {stats.factorizations / stats.steps:.2f} factorisations per "
        f"step, coupling {stats.coupling}); the same frame linear {step_us['linear']:.1f} us; "
        f"with the hinges and undamped massless dofs {step_us['undamped massless']:.1f} us."
    )
    out.append("")
    for tol in TOLS:
        best = {}
        for name in ("OpenSees", "duhamel"):
            ok = [(w, k) for (n, k), (w, e) in rows.items() if n == name and e <= tol]
            best[name] = min(ok) if ok else None
        if best["OpenSees"] and best["duhamel"]:
            ratio = best["OpenSees"][0] / best["duhamel"][0]
            out.append(
                f"* error <= {tol:g}: OpenSees k = {best['OpenSees'][1]} "
                f"({best['OpenSees'][0]:.3f} s), duhamel k = {best['duhamel'][1]} "
                f"({best['duhamel'][0]:.3f} s): **{ratio:.1f}x**"
            )
        else:
            missing = [n for n in best if not best[n]]
            out.append(f"* error <= {tol:g}: not reached on this grid by {missing}")
    text = "\n".join(out)
    print(text)
    if args.append:
        with open(args.append, "a", encoding="utf-8") as f:
            f.write("\n" + text + "\n")


if __name__ == "__main__":
    main()

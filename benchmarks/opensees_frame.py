"""An isolated frame built in OpenSees: duhamel (through ``duhamel.opensees.from_opensees``)
against OpenSees on the same model, time to equal accuracy, in one run (issue 25).

The frame of ``examples/opensees_frame.py`` at the size of the issue's model: 6 storeys,
3 bays (elastic beam-columns, lumped floor masses, ``equalDOF`` floors), on ``zeroLength``
``Steel01`` isolators and a ``flatSliderBearing`` under one column, gravity applied first;
8 s of the example's synthetic record (PGA 3 m/s^2).

* OpenSees: Newmark (average acceleration), ``Newton``, ``NormDispIncr`` 1e-12,
  ``BandGeneral`` with RCM, ``k`` steps per record interval of 0.01 s; timed: the analysis
  (its set-up and the step loop), not the model's definition.
* duhamel: ``Semianalytic()`` (all modes) and ``Semianalytic(modes=20)`` (20 modes and the
  static correction of the isolators' directions) at ``dt = 0.01 / k``; timed:
  ``from_opensees()`` (the matrices from OpenSees, the translation), the load and the run
  with its modal analysis (a fresh system every time).

Error: the largest displacement difference at the isolator and the roof over the run,
divided by the largest displacement, against each program's own converged run (OpenSees at
k = 64, duhamel with all modes at k = 32; the reduced runs are measured against it too), so
that each is measured on its own idealisation (duhamel's
slider keeps the axial load it had at import, OpenSees' follows the overturning; the
difference of the two converged runs is printed). Times: best of `repeats`, the two
programs interleaved.

Usage::

    python benchmarks/opensees_frame.py
    python benchmarks/opensees_frame.py --append BENCHMARKS.md
    python benchmarks/opensees_frame.py --quick          # 3 storeys, 2 bays, 3 s

Needs openseespy (and ``apt-get install -y libblas3 liblapack3`` on a fresh machine).
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import importlib.util  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(__file__))
import _section  # noqa: E402

import duhamel  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
_spec = importlib.util.spec_from_file_location("frame", ROOT / "examples" / "opensees_frame.py")
assert _spec is not None and _spec.loader is not None
frame = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(frame)

TOLS = (1e-2, 1e-3, 1e-4)
#: The reduced contender: this many modes plus the static correction (the default).
MODES = 20


def watch(storeys: int) -> list[tuple[int, int]]:
    return [(frame.node_tag(0, 0), 1), (frame.node_tag(storeys, 0), 1)]


def run_opensees(size, t, a, k):
    frame.build(storeys=size[0], bays=size[1])
    t0 = time.perf_counter()
    x = frame.run_opensees(t, a, k, watch(size[0]))
    return time.perf_counter() - t0, x


def run_duhamel(size, t, a, k, modes=None):
    frame.build(storeys=size[0], bays=size[1])
    t0 = time.perf_counter()
    system = duhamel.opensees.from_opensees()
    system.add_load(duhamel.loads.BaseAcceleration("ux", t=t, values=a))
    dofs = [(n, "ux") for n, _ in watch(size[0])]
    sol = duhamel.solve(
        system,
        duhamel.Semianalytic(modes=modes),
        t_end=float(t[-1]),
        dt=0.01 / k,
        save_every=k,
        dofs=dofs,
    )
    return time.perf_counter() - t0, sol.x, system.n_dof


def err(x, ref) -> float:
    return float(np.abs(x - ref).max() / np.abs(ref).max())


def section(quick: bool) -> list[str]:
    size, duration, repeats = ((3, 2), 3.0, 1) if quick else ((6, 3), 8.0, 3)
    t, a = frame.record(duration=duration)
    ks_os, ks_du = (1, 2, 4, 8, 16), (1, 2, 4, 8)
    _, ref_os = run_opensees(size, t, a, 16 if quick else 64)
    _, ref_du, n_dof = run_duhamel(size, t, a, 32)
    names = ("OpenSees", "duhamel", f"duhamel, {MODES} modes")
    rows = {("OpenSees", k): [math_inf(), None] for k in ks_os}
    for name in names[1:]:
        rows.update({(name, k): [math_inf(), None] for k in ks_du})
    for _ in range(repeats):  # interleaved
        for k_os, k_du in zip(ks_os, (*ks_du, None), strict=True):
            wall, x = run_opensees(size, t, a, k_os)
            rows["OpenSees", k_os] = [min(rows["OpenSees", k_os][0], wall), err(x, ref_os)]
            if k_du is None:
                continue
            for name, modes in zip(names[1:], (None, MODES), strict=True):
                wall, x, _ = run_duhamel(size, t, a, k_du, modes)
                rows[name, k_du] = [min(rows[name, k_du][0], wall), err(x, ref_du)]
    load = os.getloadavg()[0]
    rev = subprocess.run(
        ["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True, text=True
    ).stdout.strip()
    out = [
        "## An isolated frame from OpenSees: time to equal accuracy (issue 25)",
        "",
        f"Generated by `benchmarks/opensees_frame.py{' --quick' if quick else ''} --append "
        f"BENCHMARKS.md` at {rev}: {size[0]} storeys, {size[1]} bays, {n_dof} dofs in duhamel, "
        f"{duration:g} s of record; best of {repeats}, interleaved; load average {load:.2f} "
        "(`os.getloadavg`, 2 cores shared).",
        "",
        "| program | k (dt = 0.01/k) | wall [s] | error vs own converged run |",
        "|---|---|---|---|",
    ]
    for (name, k), (wall, e) in rows.items():
        out.append(f"| {name} | {k} | {wall:.3f} | {e:.1e} |")
    out.append("")
    out.append(
        f"Converged runs against each other (the two idealisations): {err(ref_du, ref_os):.1e} "
        "of the peak."
    )
    out.append("")
    for tol in TOLS:
        best = {}
        for name in names:
            ok = [(w, k) for (n, k), (w, e) in rows.items() if n == name and e <= tol]
            best[name] = min(ok) if ok else None
        parts = []
        for name in names:
            if best[name] is None:
                parts.append(f"{name} not reached on this grid")
            elif name == "OpenSees":
                parts.append(f"OpenSees k = {best[name][1]} ({best[name][0]:.3f} s)")
            elif best["OpenSees"] is not None:
                ratio = best["OpenSees"][0] / best[name][0]
                parts.append(
                    f"{name} k = {best[name][1]} ({best[name][0]:.3f} s): **{ratio:.0f}x**"
                )
        out.append(f"* error <= {tol:g}: " + "; ".join(parts))
    return out


def math_inf() -> float:
    return float("inf")


if __name__ == "__main__":
    sys.exit(_section.main(__doc__ or "", section, "3 storeys, 2 bays, 3 s", sys.argv[1:]))

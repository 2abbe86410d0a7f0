"""Local nonlinearities in a large model: the cost of a nonlinear step against the linear one.

The model is a 3-D scalar lattice (``nx x ny x nz`` unit masses, springs ``k`` to their six
neighbours, the bottom layer tied to the ground by the same springs; 29,700 dofs by
default), modal damping ``zeta = 0.02``, under a harmonic force at a top corner. A few cubic
springs to ground ``Cubic(dof, k3)`` at random dofs make it nonlinear: the situation of a
building with a few isolators or dampers (SAP2000's "Fast Nonlinear Analysis").

The lowest 200 modes come from one shift-invert ``eigsh`` (timed); the 50- and 100-mode
bases are its leading columns. For 50, 100 and 200 modes and 3, 30 and 100 springs, it
times ``Semianalytic(modes=m)`` (the default solver: Newton in the springs' dofs when they
are fewer than the modes) and ``solver="modal-newton"`` (Newton on all modal coordinates,
the previous method; up to 100 modes), against the linear run without springs, 1e4 steps of
1 ms, the tip displacement saved every step. Times are ``Solution.stats.wall_time`` per
step, best of `repeats`, the contenders interleaved in each repeat.

Usage::

    python benchmarks/local.py                        # print the table
    python benchmarks/local.py --append BENCHMARKS.md # as a section of BENCHMARKS.md
    python benchmarks/local.py --quick                # smoke test (a small lattice)
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import time  # noqa: E402
from dataclasses import dataclass  # noqa: E402

import _section  # noqa: E402
import numpy as np  # noqa: E402
import scipy.sparse as sp  # noqa: E402

import duhamel  # noqa: E402
from duhamel import elements as E  # noqa: E402
from duhamel import loads as L  # noqa: E402


@dataclass(frozen=True)
class Setup:
    shape: tuple[int, int, int] = (30, 30, 33)
    k: float = 1e4
    k3: float = 1e9
    force: float = 100.0
    frequency: float = 6.0
    modes: tuple[int, ...] = (50, 100, 200)
    springs: tuple[int, ...] = (3, 30, 100)
    modal_newton_up_to: int = 100
    reference_modes: int = 300
    accuracy_springs: int = 3
    steps: int = 10_000
    dt: float = 1e-3
    repeats: int = 3


QUICK = Setup(
    shape=(8, 8, 8), modes=(20, 40), springs=(3, 10), steps=2000, repeats=1, reference_modes=80
)


def lattice(shape: tuple[int, int, int], k: float) -> tuple[sp.csr_array, sp.csr_array]:
    """Mass and stiffness of the lattice (CSR)."""
    nx, ny, nz = shape
    n = nx * ny * nz
    index = np.arange(n).reshape(shape)
    rows, cols = [], []
    for axis in range(3):
        a = np.moveaxis(index, axis, 0)
        rows.append(a[:-1].ravel())
        cols.append(a[1:].ravel())
    i, j = np.concatenate(rows), np.concatenate(cols)
    ones = np.full(i.size, k)
    links = sp.coo_array((ones, (i, j)), shape=(n, n))
    degree = np.bincount(i, minlength=n) + np.bincount(j, minlength=n)
    ground = np.zeros(n)
    ground[index[:, :, 0].ravel()] = k
    stiffness = sp.diags(k * degree + ground) - links - links.T
    return sp.identity(n, format="csr"), sp.csr_array(stiffness)


def _run(system: duhamel.System, modes: int, solver: str, s: Setup, tip: int) -> float:
    integ = duhamel.Semianalytic(modes=modes, solver=solver)
    sol = duhamel.solve(system, integ, t_end=s.steps * s.dt, dt=s.dt, dofs=[tip])
    return sol.stats.wall_time / s.steps


def accuracy(s: Setup, system: duhamel.System, dofs: np.ndarray) -> dict:
    """Error at the spring dofs (max over time and springs, relative to the reference's
    peak there) with and without the static correction, against the run with
    `reference_modes` modes plus the correction; and the coordinates each run has."""
    kw = {"t_end": s.steps * s.dt, "dt": s.dt, "dofs": dofs}
    ref_run = duhamel.Semianalytic(modes=s.reference_modes, static_correction=True)
    ref = duhamel.solve(system, ref_run, **kw)
    peak = np.abs(ref.x).max()
    out = {"reference": ref.stats.modes, "rows": []}
    for mm in s.modes:
        for correct in (False, True):
            run = duhamel.Semianalytic(modes=mm, static_correction=correct)
            sol = duhamel.solve(system, run, **kw)
            err = float(np.abs(sol.x - ref.x).max() / peak)
            out["rows"].append((mm, correct, sol.stats.modes, err))
    return out


def measure(s: Setup) -> dict:
    m, k = lattice(s.shape, s.k)
    n = m.shape[0]
    tip = n - 1
    load = L.Harmonic(tip, amplitude=s.force, omega=s.frequency)
    started = time.perf_counter()
    full = duhamel.System(m, k, zeta=0.02)
    biggest = full.modal(max(s.modes))
    eig_seconds = time.perf_counter() - started
    rng = np.random.default_rng(7)
    spring_dofs = rng.choice(n - 1, size=max(s.springs), replace=False)

    def system(n_springs: int) -> duhamel.System:
        # the same modes for every mode count: the leading columns of one eigsh
        sys_ = duhamel.System(m, k, zeta=0.02).use_basis(biggest).add_load(load)
        for d in spring_dofs[:n_springs]:
            sys_.add(E.Cubic(int(d), k3=s.k3))
        return sys_

    ref_basis = duhamel.System(m, k, zeta=0.02).use_basis(biggest, extend=True)
    ref_basis = ref_basis.modal(s.reference_modes)
    acc_system = duhamel.System(m, k, zeta=0.02).use_basis(ref_basis).add_load(load)
    for d in spring_dofs[: s.accuracy_springs]:
        acc_system.add(E.Cubic(int(d), k3=s.k3))
    acc = accuracy(s, acc_system, np.sort(spring_dofs[: s.accuracy_springs]))
    linear = {mm: np.inf for mm in s.modes}
    timed: dict[tuple[int, int, str], float] = {}
    systems = {ns: system(ns) for ns in (0, *s.springs)}
    load_before = os.getloadavg()[0]
    for _ in range(s.repeats):
        for mm in s.modes:
            linear[mm] = min(linear[mm], _run(systems[0], mm, "auto", s, tip))
            for ns in s.springs:
                for solver in ("auto", "modal-newton"):
                    if solver == "modal-newton" and mm > s.modal_newton_up_to:
                        continue
                    key = (mm, ns, solver)
                    timed[key] = min(timed.get(key, np.inf), _run(systems[ns], mm, solver, s, tip))
    return {
        "n": n,
        "eig_seconds": eig_seconds,
        "linear": linear,
        "timed": timed,
        "load": (load_before, os.getloadavg()[0]),
        "accuracy": acc,
    }


def markdown(s: Setup, r: dict) -> list[str]:
    us = 1e6
    out = [
        "## Local nonlinearities in a large model (issue 12)",
        "",
        "Generated by `benchmarks/local.py --append BENCHMARKS.md` (`make bench`). "
        f"Lattice {s.shape[0]} x {s.shape[1]} x {s.shape[2]} = {r['n']:,} dofs, cubic springs "
        f"to ground `k3 = {s.k3:g}` at random dofs, {s.steps:,} steps of {s.dt:g} s, best of "
        f"{s.repeats}, contenders interleaved. Modal analysis ({max(s.modes)} modes, one "
        f"shift-invert eigsh): {r['eig_seconds']:.1f} s. 1-min load average before "
        f"{r['load'][0]:.2f}, after {r['load'][1]:.2f} (2 cores).",
        "",
        "With `modes` given and springs present, the static correction is on (the default):",
        "the run has one more coordinate per spring and one for the load. Linear: no springs,",
        "no correction (plain modes).",
        "",
        "| modes | linear [us/step] | springs | element-space Newton [us/step] | x linear "
        "| modal Newton [us/step] | x linear |",
        "|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for mm in s.modes:
        lin = r["linear"][mm]
        for ns in s.springs:
            loc = r["timed"][(mm, ns, "auto")]
            dense = r["timed"].get((mm, ns, "modal-newton"))
            d = ("-", "-") if dense is None else (f"{dense * us:.1f}", f"{dense / lin:.0f}")
            out.append(
                f"| {mm} | {lin * us:.2f} | {ns} | {loc * us:.1f} | {loc / lin:.0f} | "
                f"{d[0]} | {d[1]} |"
            )
    a = r["accuracy"]
    out += [
        "",
        f"Accuracy at the {s.accuracy_springs} spring dofs (max error over time and springs / "
        f"the reference's peak there) against {s.reference_modes} modes + static correction "
        f"({a['reference']} coordinates), same steps:",
        "",
        "| modes | static correction | coordinates | error at the springs |",
        "|---:|:---:|---:|---:|",
    ]
    for mm, correct, n, err in a["rows"]:
        out.append(f"| {mm} | {'yes' if correct else 'no'} | {n} | {err:.2e} |")
    return out


def _measured(s: Setup) -> tuple[Setup, dict]:
    return s, measure(s)


def main(argv: list[str] | None = None) -> int:
    return _section.main(
        __doc__,
        lambda quick: markdown(*_measured(QUICK if quick else Setup())),
        "a small lattice, one repeat",
        argv,
    )


if __name__ == "__main__":
    raise SystemExit(main())

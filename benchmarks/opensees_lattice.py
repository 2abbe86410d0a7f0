"""A lattice with yielding springs: duhamel's reduced semi-analytic run against OpenSees' full
model, in one run (issue 12).

The lattice of ``benchmarks/local.py`` (unit masses, links 1e4 N/m, grounded at one face),
mass-proportional damping ``2.0 M``, ten bilinear springs to ground at random dofs
(``k = 1e5 N/m, fy = 50 N, alpha = 0.05``: duhamel ``Bilinear``, OpenSees ``Steel01``; cubic
springs, the issue's first choice, have no OpenSees material), a force ``1000 sin(6 t)`` N on
the first spring's dof, 1 s of response.

* OpenSees: every link and spring a ``zeroLength`` element, Newmark average acceleration,
  ``SparseSYM`` with RCM numbering and ``ModifiedNewton -initial`` (the fastest of UmfPack /
  SparseSYM x Newton / ModifiedNewton measured on this model), ``NormDispIncr`` 1e-10.
* duhamel: ``Semianalytic(modes=m)`` with the static correction (default), and all modes.

Error: the largest displacement difference at the ten spring dofs over the run, divided by
their largest displacement, against duhamel with all modes at dt = 1 ms / 16 (cross-checked
by OpenSees at its finest step). Times: the whole call (model set-up included for OpenSees,
the System and its modal analysis for duhamel); one run each (OpenSees takes seconds to
minutes per run).

Usage::

    python benchmarks/opensees_lattice.py                          # 10 x 10 x 10 lattice
    python benchmarks/opensees_lattice.py --append BENCHMARKS.md
    python benchmarks/opensees_lattice.py --quick                  # 6 x 6 x 6

Needs openseespy (and ``apt-get install -y libblas3 liblapack3`` on a fresh machine).
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(__file__))
import _section  # noqa: E402
import local  # noqa: E402

import duhamel  # noqa: E402
from duhamel import elements as E  # noqa: E402
from duhamel import loads as L  # noqa: E402

K_LINK, KS, FY, ALPHA, A0, FORCE, OMEGA, DT = 1e4, 1e5, 50.0, 0.05, 2.0, 1000.0, 6.0, 1e-3


def springs(n: int) -> np.ndarray:
    return np.random.default_rng(0).choice(n, 10, replace=False)


def run_duhamel(shape, t_end: float, k: int, modes: int | None) -> tuple[float, np.ndarray]:
    t0 = time.perf_counter()
    m, kk = local.lattice(shape, K_LINK)
    dofs = springs(m.shape[0])
    s = duhamel.System(m, kk, rayleigh=(A0, 0.0))
    for d in dofs:
        s.add(E.Bilinear(int(d), k=KS, fy=FY, alpha=ALPHA))
    s.add_load(L.Harmonic(int(dofs[0]), amplitude=FORCE, omega=OMEGA))
    sol = duhamel.solve(
        s, duhamel.Semianalytic(modes=modes), t_end=t_end, dt=DT / k, save_every=k, dofs=dofs
    )
    return time.perf_counter() - t0, sol.x


def run_opensees(shape, t_end: float, k: int, path: str) -> tuple[float, np.ndarray]:
    import openseespy.opensees as ops

    t0 = time.perf_counter()
    m, kk = local.lattice(shape, K_LINK)
    n = m.shape[0]
    dofs = springs(n)
    ops.wipe()
    ops.model("basic", "-ndm", 1, "-ndf", 1)
    for i in range(n):
        ops.node(i + 1, 0.0)
        ops.mass(i + 1, 1.0)
    ops.node(n + 1, 0.0)
    ops.fix(n + 1, 1)
    ops.uniaxialMaterial("Elastic", 1, K_LINK)
    coo = kk.tocoo()
    upper = coo.row < coo.col
    e = 0
    for i, j in zip(coo.row[upper], coo.col[upper], strict=True):
        e += 1
        ops.element("zeroLength", e, int(i) + 1, int(j) + 1, "-mat", 1, "-dir", 1)
    ground = np.asarray(kk.sum(axis=1)).ravel()
    for i in np.flatnonzero(ground > 1e-6 * K_LINK):
        ops.uniaxialMaterial("Elastic", 10 + n + int(i), float(ground[i]))
        e += 1
        ops.element("zeroLength", e, n + 1, int(i) + 1, "-mat", 10 + n + int(i), "-dir", 1)
    ops.uniaxialMaterial("Steel01", 2, FY, KS, ALPHA)
    for d in dofs:
        e += 1
        ops.element("zeroLength", e, n + 1, int(d) + 1, "-mat", 2, "-dir", 1)
    ops.timeSeries("Trig", 1, 0.0, 1e9, 2 * np.pi / OMEGA)
    ops.pattern("Plain", 1, 1)
    ops.load(int(dofs[0]) + 1, FORCE)
    ops.rayleigh(A0, 0.0, 0.0, 0.0)
    ops.constraints("Plain")
    ops.numberer("RCM")
    ops.system("SparseSYM")
    ops.test("NormDispIncr", 1e-10, 100)
    ops.algorithm("ModifiedNewton", "-initial")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")
    ops.recorder("Node", "-file", path, "-node", *[int(d) + 1 for d in dofs], "-dof", 1, "disp")
    steps = round(t_end / DT) * k
    if ops.analyze(steps, DT / k) != 0:
        raise RuntimeError(f"OpenSees failed at dt = {DT / k}")
    ops.wipe()
    elapsed = time.perf_counter() - t0
    x = np.loadtxt(path).reshape(steps, -1)[k - 1 :: k]
    return elapsed, np.vstack([np.zeros((1, x.shape[1])), x])


def measure(shape, t_end: float, modes: tuple[int, ...], ks: tuple[int, ...]) -> dict:
    load0 = os.getloadavg()[0]
    path = os.path.join(tempfile.mkdtemp(), "disp.out")
    _, ref = run_duhamel(shape, t_end, 16, None)
    peak = np.abs(ref).max()

    def err(x: np.ndarray) -> float:
        return float(np.abs(x - ref).max() / peak)

    rows = []
    for k in ks:
        t, x = run_opensees(shape, t_end, k, path)
        rows.append(("OpenSees Newmark (full model)", k, t, err(x)))
    for mm in (*modes, None):
        for k in (1, 4):
            t, x = run_duhamel(shape, t_end, k, mm)
            label = f"duhamel, {mm} modes + correction" if mm else "duhamel, all modes"
            rows.append((label, k, t, err(x)))
    n = int(np.prod(shape))
    ductility = float(peak / (FY / KS))
    return {
        "rows": rows,
        "n": n,
        "t_end": t_end,
        "ductility": ductility,
        "load": (load0, os.getloadavg()[0]),
    }


def markdown(r: dict) -> list[str]:
    out = [
        "## A lattice with yielding springs against OpenSees (issue 12)",
        "",
        f"Generated by `benchmarks/opensees_lattice.py --append BENCHMARKS.md`. {r['n']:,} "
        f"dofs, ten bilinear springs (Steel01), {r['t_end']:g} s of response, dt = 1 ms / k. "
        "Error at the spring dofs against duhamel with all modes at dt = 1 ms / 16; the "
        f"largest spring displacement is {r['ductility']:.1f} times the yield displacement. "
        f"1-min load average before {r['load'][0]:.2f}, after {r['load'][1]:.2f}.",
        "",
        "| run | k | time [s] | error at the springs |",
        "|---|---:|---:|---:|",
    ]
    for label, k, t, e in r["rows"]:
        out.append(f"| {label} | {k} | {t:.2f} | {e:.1e} |")
    return out


#: (lattice shape, seconds, reduced mode counts, step divisions) of the full and --quick runs.
_SIZES = {False: ((10, 10, 10), 1.0, (50, 100), (1, 2, 4)), True: ((6, 6, 6), 0.2, (20,), (1,))}


def main(argv: list[str] | None = None) -> int:
    return _section.main(
        __doc__, lambda quick: markdown(measure(*_SIZES[quick])), "a 6 x 6 x 6 lattice", argv
    )


if __name__ == "__main__":
    raise SystemExit(main())

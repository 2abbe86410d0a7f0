"""The uniaxial materials of issue 37 on an SDOF: duhamel against OpenSees at equal accuracy
(issue 37's speed acceptance, issue 42's first rows).

The SDOF of ``tests/_support/_materials_system.py`` (mass 1, initial period 1 s, yield deformation
0.02, Rayleigh damping 5 % at 1 Hz on the mass and the initial stiffness) with one material
to the ground, each built with that file's parameters in both codes (OpenSees: the material
of the same name in a ``zeroLength`` with ``-doRayleigh 1``):

* ``Bilinear`` against ``Steel01`` (``b = 0.02``), ``Steel02``, ``MultiLinear``,
  ``ElasticMultiLinear`` (``-strain``/``-stress``), ``ModIMKPeakOriented``, ``IMKBilin``,
  ``Hysteretic``, ``Pinching4``;
* the wrappers: ``MinMax`` of a ``Steel02`` (limits +-3 yield deformations), ``Parallel`` of a
  ``Steel02`` and an ``ElasticMultiLinear``, ``Series`` of a stiff ``ElasticMultiLinear`` and a
  ``Steel02`` five times as stiff as the SDOF's (the Parallel's initial stiffness is 2 K0: its
  Rayleigh damping is on that in both codes);
* ``Takeda`` has no OpenSees material of that name: not compared.

The record: 20 s of band-limited noise (0.3-8 Hz) at 200 samples per second, PGA 0.4 g, linear
between samples in both codes (``benchmarks/devices.py``'s). OpenSees: ``UniformExcitation``
with a ``Path`` series, Newmark average acceleration, Newton with ``NormDispIncr`` 1e-12 (100
iterations), the displacement recorded every step by a ``Node`` recorder and ``analyze(n, dt)``
in one call (reading the file back is not timed). duhamel: ``Semianalytic()`` with its
defaults, saving at the record's samples.

Method (``benchmarks/devices.py``'s): each code against its own converged run (``dt =
0.005 / 256``), the largest difference over the record's samples divided by the peak
displacement; for each level, each code's largest step ``0.005 / k`` (k a power of 2 up to 64)
whose error is below it, timed over the whole call (model set-up included), best of repeats,
the codes interleaved. The ratio is OpenSees' time over duhamel's. The 1-min load average is
printed before and after. ``--cpu`` times each call by the process's CPU time instead (both
codes run on one thread): on a loaded machine the wall time of a call counts other jobs' time
slices, more of them in a longer call.

Usage::

    python benchmarks/materials_opensees.py                          # print the table
    python benchmarks/materials_opensees.py --append BENCHMARKS.md   # as a section
    python benchmarks/materials_opensees.py --quick                  # smoke test
    python benchmarks/materials_opensees.py --only Steel02           # the materials named so
    python benchmarks/materials_opensees.py --cpu --repeats 7        # CPU time, best of 7

Needs openseespy.
"""

from __future__ import annotations

import os
import sys

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

# the SDOF's materials: tests/_support/_materials_system.py (tests/ before the tests' layout)
for _dir in ("tests", os.path.join("tests", "_support")):
    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", _dir))

import tempfile  # noqa: E402
import time  # noqa: E402
from typing import Any  # noqa: E402

import _section  # noqa: E402
import numpy as np  # noqa: E402
import scipy.signal  # noqa: E402
from _materials_system import A0, A1, FY, K0, MATERIALS, SPRING, element  # noqa: E402

import duhamel  # noqa: E402
from duhamel import elements as E  # noqa: E402
from duhamel import loads as L  # noqa: E402

DT_REC = 0.005
G = 9.81

#: the OpenSees definitions the SDOF test leaves out (None there): tag 1 is the SDOF's material
_SPRING_ARGS = ("ElasticMultiLinear", "-strain", *SPRING["strain"], "-stress", *SPRING["stress"])
_STEEL_ARGS = MATERIALS["Steel02"][1]
_STIFF = {"strain": [-1.0, 0.0, 1.0], "stress": [-5 * K0 / 4, 0.0, 5 * K0 / 4]}
_STIFF_ARGS = ("ElasticMultiLinear", "-strain", *_STIFF["strain"], "-stress", *_STIFF["stress"])
_SERIES_STEEL = ("Steel02", FY, 5 * K0, 0.02)
_MINMAX = MATERIALS["MinMax"][0]

#: name -> the parts OpenSees defines first (tags 10, 11, ...) and the SDOF's material (tag 1)
OPENSEES: dict[str, tuple[list[tuple[Any, ...]], tuple[Any, ...]]] = {
    "Bilinear": ([], ("Steel01", FY, K0, 0.02)),
    **{k: ([], args) for k, (_, args) in MATERIALS.items() if args is not None},
    "ElasticMultiLinear": ([], _SPRING_ARGS),
    "MinMax": ([_STEEL_ARGS], ("MinMax", 10, "-min", _MINMAX["min"], "-max", _MINMAX["max"])),
    "Parallel": ([_STEEL_ARGS, _SPRING_ARGS], ("Parallel", 10, 11)),
    # OpenSees' SeriesMaterial at its default single iteration fails below dt = 1e-4: the
    # iterations of tests/elements/test_materials_wrappers.py
    "Series": ([_STIFF_ARGS, _SERIES_STEEL], ("Series", 10, 11, "-iter", 50, 1e-12)),
}
ORDER = [
    "Bilinear", "Steel02", "MultiLinear", "ElasticMultiLinear", "MinMax", "Parallel", "Series",
    "ModIMKPeakOriented", "IMKBilin", "Hysteretic", "Pinching4",
]  # fmt: skip
LABEL = {"Bilinear": "Bilinear / Steel01"}
#: the initial stiffness OpenSees' ``-doRayleigh`` damps (the Parallel's two parts: 2 K0)
K_INIT = {"Parallel": 2 * K0}


def record(seconds: float) -> np.ndarray:
    """The ground acceleration [m/s^2] at ``DT_REC``: devices.py's synthetic record."""
    n = round(seconds / DT_REC) + 1
    rng = np.random.default_rng(13)
    t = DT_REC * np.arange(n)
    b, a = scipy.signal.butter(4, [0.3, 8.0], btype="band", fs=1 / DT_REC)
    env = np.minimum(t / 2.0, 1.0) * np.exp(-np.maximum(t - 8.0, 0.0) / 4.0)
    x = env * scipy.signal.lfilter(b, a, rng.normal(size=n))
    return 0.4 * G * x / np.abs(x).max()


def material(name: str) -> E.Element:
    if name == "Bilinear":
        return E.Bilinear(0, k=K0, fy=FY, alpha=0.02)
    return element(name, MATERIALS[name][0])


def run_duhamel(name: str, a: np.ndarray, k: int) -> np.ndarray:
    """The whole call: the System, its material, the load and the solve."""
    t = DT_REC * np.arange(a.size)
    c = A0 + A1 * K_INIT.get(name, K0)  # Rayleigh on the initial stiffness, as OpenSees'
    s = duhamel.System(np.eye(1), np.zeros((1, 1)), c * np.eye(1))
    s.add(material(name))
    s.add_load(L.BaseAcceleration(np.ones(1), t=t, values=a))
    sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=t[-1], dt=DT_REC / k, save_every=k)
    return sol.x[:, 0]


def run_opensees(name: str, a: np.ndarray, k: int, path: str) -> None:
    import openseespy.opensees as ops

    parts, args = OPENSEES[name]
    ops.wipe()
    ops.model("basic", "-ndm", 1, "-ndf", 1)
    ops.node(1, 0.0)
    ops.node(2, 0.0)
    ops.fix(1, 1)
    ops.mass(2, 1.0)
    for tag, part in enumerate(parts, start=10):
        ops.uniaxialMaterial(part[0], tag, *part[1:])
    ops.uniaxialMaterial(args[0], 1, *args[1:])
    ops.element("zeroLength", 1, 1, 2, "-mat", 1, "-dir", 1, "-doRayleigh", 1)
    ops.rayleigh(A0, 0.0, A1, 0.0)
    ops.timeSeries("Path", 2, "-dt", DT_REC, "-values", *a.tolist())
    ops.pattern("UniformExcitation", 2, 1, "-accel", 2)
    ops.constraints("Plain")
    ops.numberer("Plain")
    ops.system("BandGeneral")
    ops.test("NormDispIncr", 1e-12, 100)
    ops.algorithm("Newton")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")
    ops.recorder("Node", "-file", path, "-node", 2, "-dof", 1, "disp")
    if ops.analyze((a.size - 1) * k, DT_REC / k) != 0:
        raise RuntimeError(f"OpenSees failed on {name} at dt = {DT_REC / k}")
    ops.wipe()  # closes the recorder


def read_opensees(path: str, k: int, n: int) -> np.ndarray:
    x = np.loadtxt(path).reshape(-1)
    return np.concatenate([[0.0], x[k - 1 :: k]])[:n]


ONLY: list[str] = []
REPEATS = [3]  # --repeats N: best of N timings
LEVELS = (1e-2, 1e-3, 1e-4)


#: --cpu: each call timed by the process's CPU time (``time.process_time``) instead of the
#: wall clock: on a machine shared with other jobs a one-thread call's CPU time is what it
#: costs, where its wall time counts the other jobs' time slices too
CPU: list[bool] = []


def timed(f) -> float:
    clock = time.process_time if CPU else time.perf_counter
    t0 = clock()
    f()
    return clock() - t0


def first_below(errors: dict[int, float], level: float) -> int | None:
    return next((k for k, e in sorted(errors.items()) if e <= level), None)


def measure(quick: bool) -> dict:
    load0 = os.getloadavg()[0]
    a = record(6.0 if quick else 20.0)
    ks = [1, 2, 4, 8, 16, 32, 64]
    k_ref = 64 if quick else 256
    repeats = 1 if quick else REPEATS[0]
    path = os.path.join(tempfile.mkdtemp(), "disp.out")
    rows = []
    for name in ORDER:
        if ONLY and not any(o == name for o in ONLY):
            continue
        ref_d = run_duhamel(name, a, k_ref)
        run_opensees(name, a, k_ref, path)
        ref_o = read_opensees(path, k_ref, a.size)
        peak = np.abs(ref_d).max()
        err_d, err_o = {}, {}
        for k in ks:
            err_d[k] = float(np.abs(run_duhamel(name, a, k) - ref_d).max() / peak)
            run_opensees(name, a, k, path)
            err_o[k] = float(np.abs(read_opensees(path, k, a.size) - ref_o).max() / peak)
        times: dict[tuple[str, int], float] = {}
        for level in LEVELS:
            kd, ko = first_below(err_d, level), first_below(err_o, level)
            if kd is None or ko is None or (("d", kd) in times and ("o", ko) in times):
                continue
            for _ in range(repeats):  # interleaved; the best of every timing of a step
                for key, f in (
                    (("d", kd), lambda n=name, k=kd: run_duhamel(n, a, k)),
                    (("o", ko), lambda n=name, k=ko: run_opensees(n, a, k, path)),
                ):
                    times[key] = min(times.get(key, np.inf), timed(f))
        rows.append(
            {
                "name": LABEL.get(name, name),
                "cross": float(np.abs(ref_d - ref_o).max() / peak),
                "peak": float(peak),
                "err_d": err_d,
                "err_o": err_o,
                "times": times,
            }
        )
    return {"rows": rows, "n": a.size, "load": (load0, os.getloadavg()[0])}


def at_level(row: dict, level: float) -> tuple[int, float, int, float] | None:
    kd, ko = first_below(row["err_d"], level), first_below(row["err_o"], level)
    if kd is None or ko is None:
        return None
    return kd, row["times"][("d", kd)], ko, row["times"][("o", ko)]


def markdown(r: dict) -> list[str]:
    out = [
        "### Materials on an SDOF (issue 37)",
        f"`python benchmarks/materials_opensees.py{' --cpu' if CPU else ''}` · load "
        f"{r['load'][0]:.2f} → {r['load'][1]:.2f}. The SDOF of tests/_support/_materials_system.py "
        f"(T = 1 s, uy = 0.02, Rayleigh 5 %), {r['n']} samples at 200 Hz (PGA 0.4 g), one "
        "material to the ground in both codes (OpenSees: the material of the same name in a "
        "`zeroLength`). Ratio: OpenSees time over duhamel's, the whole call, each code's "
        "largest step 0.005/k below the level against its own converged run; in brackets "
        "duhamel's k, ms and OpenSees' k, ms at 1e-3. Takeda: no OpenSees counterpart.",
        "",
        "| duhamel / OpenSees | converged | 1e-2 | 1e-3 | 1e-4 | at 1e-3: k, ms / k, ms "
        "| 30x at 1e-3 |",
        "|---|---:|---:|---:|---:|---|---|",
    ]
    for row in r["rows"]:
        cells = []
        for level in LEVELS:
            m = at_level(row, level)
            cells.append("—" if m is None else f"{m[3] / m[1]:.1f}")
        m = at_level(row, 1e-3)
        detail = "—" if m is None else f"{m[0]}, {1e3 * m[1]:.1f} / {m[2]}, {1e3 * m[3]:.1f}"
        verdict = "—" if m is None else ("reached" if m[3] / m[1] >= 30 else "**NOT reached**")
        out.append(
            f"| {row['name']} | {row['cross']:.1e} | {' | '.join(cells)} | {detail} | {verdict} |"
        )
    return out


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if "--cpu" in argv:
        argv.remove("--cpu")
        CPU.append(True)
    if "--repeats" in argv:
        at = argv.index("--repeats")
        REPEATS[0] = int(argv[at + 1])
        del argv[at : at + 2]
    while "--only" in argv:
        at = argv.index("--only")
        ONLY.append(argv[at + 1])
        del argv[at : at + 2]
    return _section.main(
        __doc__, lambda quick: markdown(measure(quick)), "a short record, one repeat", argv
    )


if __name__ == "__main__":
    raise SystemExit(main())

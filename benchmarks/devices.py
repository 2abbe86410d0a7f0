"""Hysteretic and device elements: duhamel against OpenSees on the same SDOF models (issues 13,
27).

A one-storey frame (m = 1e5 kg, frame stiffness for T = 1 s, 2 % mass-proportional damping)
with one device in parallel, under the same 20-s synthetic record (filtered noise, PGA 0.4 g,
200 samples per second, linear between samples in both codes):

* ``Bilinear(k = k_frame, fy = 0.1 m g, alpha = 0.05)`` against OpenSees ``Steel01`` (the same
  law: kinematic hardening, no isotropic hardening);
* ``BoucWen(k = k_frame, fy = 0.1 m g, alpha = 0.05, n = 1, beta = gamma = 0.5)`` against
  OpenSees ``BoucWen`` with ``z`` in displacement units (``beta, gamma`` scaled by ``k / fy``,
  ``A0 = 1``, no degradation);
* ``ViscousDamper(c, exponent = 0.5)`` (c for 10 % damping at 0.1 m/s) against OpenSees
  ``Viscous`` (the same power law; duhamel regularises below 1e-4 m/s);
* ``ViscousDamper(c, exponent = 0.35, brace_stiffness = 5 k_frame)`` (c for the same force
  at 0.1 m/s; issue 27) against OpenSees ``ViscousDamper`` with ``K = 5 k_frame`` (the Maxwell
  model: damper in series with its brace);
* a rigid mass on a friction pendulum, ``FrictionPendulum(radius = 2 m, mu = 0.05, weight =
  m g, yield_displacement = 2.5e-4 m)`` on (x, y) excited along x, against OpenSees
  ``singleFPBearing`` in 2-D (``Coulomb`` friction, the same radius and initial stiffness
  ``mu W / u_y``, stiff axial material, the weight applied by a static step first; its internal
  iteration set to 100 iterations at 1e-8, the default fails after 1.2 s). No frame, no
  viscous damping;
* the same mass on a uniaxial ``FrictionPendulum(0, dof_y=None, ...)`` (issue 27) against the
  same planar ``singleFPBearing``, with ``Coulomb`` friction and with velocity-dependent
  friction (``mu_slow = 0.025``, ``rate = 20`` s/m against OpenSees ``VelDependent`` with
  ``muSlow = 0.025``, ``muFast = 0.05``, ``transRate = 20``);
* the same mass on a uniaxial ``TripleFrictionPendulum`` (issue 27; mu = (0.02, 0.06, 0.10),
  radius = (0.3, 2.0, 2.5) m, capacities (0.05, 0.3, 0.35) m, uy = 0.5 mm, the record x 1.5)
  against OpenSees ``TripleFrictionPendulum`` in 3-D (``benchmarks/_triple.py``; both codes'
  errors against duhamel's converged run, OpenSees having none of its own);
* the same mass on a ``LeadRubberBearing(k, fy = 0.1 m g, alpha = 0.1)`` (initial period
  0.5 s), uniaxial against OpenSees ``elastomericBearingBoucWen`` in 2-D and bidirectional
  (the y record: 0.7 x the x record shifted by 1.5 s) against it in 3-D (``qd = (1 - alpha)
  fy``, ``eta = 1``, ``beta = gamma = 0.5``, stiff axial and rotational materials).

OpenSees: ``zeroLength`` elements, ``UniformExcitation`` with a ``Path`` series, Newmark
average acceleration, Newton with ``NormDispIncr`` 1e-12, the displacement recorded every step
to a file by a ``Node`` recorder and ``analyze(n, dt)`` in one call (its fastest route;
reading the file back is not timed). duhamel: ``Semianalytic()`` (defaults: the device's
initial stiffness in the modal background, the remainder as a pseudo-force; path-dependent
elements committed once per step), saving at the record's samples.

Accuracy: each code against its own converged run (``dt = 0.005 / 256``), the largest
difference over the record's samples divided by the peak displacement; the two converged runs
are compared with each other (plotting accuracy). Time to equal accuracy: for each code, the
largest step ``0.005 / 2^j`` whose error is below the level, timed over the whole call (model
set-up included, best of repeats, the codes interleaved); the ratio is OpenSees over duhamel.

Usage::

    python benchmarks/devices.py                          # print the tables
    python benchmarks/devices.py --append BENCHMARKS.md   # as a section of BENCHMARKS.md
    python benchmarks/devices.py --quick                  # smoke test
    python benchmarks/devices.py --only Maxwell           # the models whose name has it

Needs openseespy (``pip install openseespy``; on a fresh Debian/Ubuntu machine also
``apt-get install -y libblas3 liblapack3``).
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import tempfile  # noqa: E402
from collections.abc import Callable  # noqa: E402
from dataclasses import dataclass  # noqa: E402

import _section  # noqa: E402
import _triple  # noqa: E402
import numpy as np  # noqa: E402
import scipy.signal  # noqa: E402

import duhamel  # noqa: E402
from duhamel import elements as E  # noqa: E402
from duhamel.records import G, GroundMotion  # noqa: E402

M = 1e5
OMEGA = 2 * np.pi
K_FRAME = M * OMEGA**2
A0 = 2 * 0.02 * OMEGA  # mass-proportional damping, 2 % at T = 1 s
FY = 0.1 * M * G
DT_REC = 0.005


def record(seconds: float) -> GroundMotion:
    n = round(seconds / DT_REC) + 1
    rng = np.random.default_rng(13)
    t = DT_REC * np.arange(n)
    b, a = scipy.signal.butter(4, [0.3, 8.0], btype="band", fs=1 / DT_REC)
    env = np.minimum(t / 2.0, 1.0) * np.exp(-np.maximum(t - 8.0, 0.0) / 4.0)
    x = env * scipy.signal.lfilter(b, a, rng.normal(size=n))
    return GroundMotion(0.4 * x / np.abs(x).max(), DT_REC, units="g", name="synthetic")


@dataclass(frozen=True)
class Case:
    name: str
    device: duhamel.elements.Element
    opensees: Callable[[int], None]  # defines uniaxialMaterial `tag`


def cases() -> list[Case]:
    import openseespy.opensees as ops

    s = K_FRAME / FY  # OpenSees' z is a displacement: beta, gamma scale with (k / fy)^n
    c = 0.1 * 2 * M * OMEGA * 0.1**0.5  # 10 % damping-equivalent force at 0.1 m/s
    c35 = 0.1 * 2 * M * OMEGA * 0.1**0.65  # the same force at 0.1 m/s with exponent 0.35
    return [
        Case(
            "Bilinear / Steel01",
            E.Bilinear(0, k=K_FRAME, fy=FY, alpha=0.05),
            lambda tag: ops.uniaxialMaterial("Steel01", tag, FY, K_FRAME, 0.05),
        ),
        Case(
            "BoucWen / BoucWen",
            E.BoucWen(0, k=K_FRAME, fy=FY, alpha=0.05, n=1.0, beta=0.5, gamma=0.5),
            lambda tag: ops.uniaxialMaterial(
                "BoucWen", tag, 0.05, K_FRAME, 1.0, 0.5 * s, 0.5 * s, 1.0, 0.0, 0.0, 0.0
            ),
        ),
        Case(
            "ViscousDamper / Viscous",
            E.ViscousDamper(0, c=c, exponent=0.5),
            lambda tag: ops.uniaxialMaterial("Viscous", tag, c, 0.5),
        ),
        Case(
            MAXWELL,
            E.ViscousDamper(0, c=c35, exponent=0.35, brace_stiffness=5 * K_FRAME),
            lambda tag: ops.uniaxialMaterial("ViscousDamper", tag, 5 * K_FRAME, c35, 0.35),
        ),
        Case(
            FPS,
            E.FrictionPendulum(
                (0, 1), radius=RADIUS, mu=MU_FPS, weight=M * G, yield_displacement=UY_FPS
            ),
            lambda tag: None,
        ),
        Case(
            FPS_1,
            E.FrictionPendulum(
                0, radius=RADIUS, mu=MU_FPS, weight=M * G, yield_displacement=UY_FPS
            ),
            lambda tag: ops.frictionModel("Coulomb", tag, MU_FPS),
        ),
        Case(
            FPS_V,
            E.FrictionPendulum(
                0,
                radius=RADIUS,
                mu=MU_FPS,
                mu_slow=MU_SLOW,
                rate=RATE,
                weight=M * G,
                yield_displacement=UY_FPS,
            ),
            lambda tag: ops.frictionModel("VelDependent", tag, MU_SLOW, MU_FPS, RATE),
        ),
        Case(
            LRB_1,
            E.LeadRubberBearing(0, k=K_LRB, fy=FY, alpha=0.1),
            lambda tag: None,
        ),
        Case(
            LRB_2,
            E.LeadRubberBearing((0, 1), k=K_LRB, fy=FY, alpha=0.1),
            lambda tag: None,
        ),
        Case(_triple.TFP, _triple.bearing(M), lambda tag: None),
    ]


MAXWELL = "ViscousDamper(brace_stiffness) / ViscousDamper with K (Maxwell)"
K_LRB = M * (2 * np.pi / 0.5) ** 2  # initial period 0.5 s on the mass alone
LRB_1 = "LeadRubberBearing(dof_y=None) / elastomericBearingBoucWen 2-D"
LRB_2 = "LeadRubberBearing (x, y) / elastomericBearingBoucWen 3-D"


def y_record(gm: GroundMotion) -> GroundMotion:
    """The second component of the bidirectional runs: 0.7 x the record shifted by 1.5 s."""
    return GroundMotion(0.7 * np.roll(gm.a, 300), DT_REC, units="m/s^2", name="y")


def run_duhamel_lrb(case: Case, gm: GroundMotion, k: int) -> np.ndarray:
    n = 2 if case.name == LRB_2 else 1
    s = duhamel.System(M * np.eye(n), np.zeros((n, n)))
    s.add(case.device).add_load(gm.as_load(np.eye(n)[0]))
    if n == 2:
        s.add_load(y_record(gm).as_load(np.array([0.0, 1.0])))
    sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=gm.duration, dt=DT_REC / k, save_every=k)
    return sol.x[:, 0]


def run_opensees_lrb(case: Case, gm: GroundMotion, k: int, path: str) -> None:
    """OpenSees elastomericBearingBoucWen (kInit, qd = (1 - alpha) fy, alpha1, no alpha2,
    eta = 1, beta = gamma = 0.5), stiff axial and rotational materials, the mass alone."""
    import openseespy.opensees as ops

    qd, shape = 0.9 * FY, (0.1, 0.0, 2.0, 1.0, 0.5, 0.5)
    ops.wipe()
    if case.name == LRB_1:
        ops.model("basic", "-ndm", 2, "-ndf", 3)
        ops.node(1, 0.0, 0.0)
        ops.node(2, 0.0, 0.0)
        ops.fix(1, 1, 1, 1)
        ops.fix(2, 0, 1, 1)
        ops.mass(2, M, M, 0.0)
        for tag in (1, 2):
            ops.uniaxialMaterial("Elastic", tag, 1e12)
        ops.element(
            "elastomericBearingBoucWen", 1, 1, 2, K_LRB, qd, *shape, "-P", 1, "-Mz", 2,
            "-orient", 0, 1, 0, -1, 0, 0,
        )  # fmt: skip
        records = [gm]
    else:
        ops.model("basic", "-ndm", 3, "-ndf", 6)
        ops.node(1, 0.0, 0.0, 0.0)
        ops.node(2, 0.0, 0.0, 0.0)
        ops.fix(1, *[1] * 6)
        ops.fix(2, 0, 0, 1, 1, 1, 1)
        ops.mass(2, M, M, M, 0.0, 0.0, 0.0)
        for tag in (1, 2, 3, 4):
            ops.uniaxialMaterial("Elastic", tag, 1e12)
        ops.element(
            "elastomericBearingBoucWen", 1, 1, 2, K_LRB, qd, *shape, "-P", 1, "-T", 2,
            "-My", 3, "-Mz", 4, "-orient", 0, 0, 1, 1, 0, 0,
        )  # fmt: skip
        records = [gm, y_record(gm)]
    for d, rec in enumerate(records):
        ops.timeSeries("Path", d + 1, "-dt", DT_REC, "-values", *rec.a.tolist())
        ops.pattern("UniformExcitation", d + 1, d + 1, "-accel", d + 1)
    _transient(ops, path)
    if ops.analyze((gm.a.size - 1) * k, DT_REC / k) != 0:
        raise RuntimeError(f"OpenSees failed on {case.name} at dt = {DT_REC / k}")
    ops.wipe()


RADIUS, MU_FPS, UY_FPS = 2.0, 0.05, 2.5e-4
FPS = "FrictionPendulum / singleFPBearing"
MU_SLOW, RATE = 0.025, 20.0
FPS_1 = "FrictionPendulum(dof_y=None) / singleFPBearing"
FPS_V = "FrictionPendulum(mu_slow, rate) / singleFPBearing VelDependent"
PLANE = (FPS_1, FPS_V)  # uniaxial bearings (issue 27): a rigid mass on one dof


def run_duhamel(case: Case, gm: GroundMotion, k: int) -> np.ndarray:
    if case.name == _triple.TFP:
        return _triple.run_duhamel(case.device, M, gm, DT_REC, k)
    if case.name in (LRB_1, LRB_2):
        return run_duhamel_lrb(case, gm, k)
    if case.name in PLANE:
        s = duhamel.System(M * np.eye(1), np.zeros((1, 1)))
        s.add(case.device).add_load(gm.as_load(np.ones(1)))
        sol = duhamel.solve(
            s, duhamel.Semianalytic(), t_end=gm.duration, dt=DT_REC / k, save_every=k
        )
        return sol.x[:, 0]
    if case.name == FPS:
        s = duhamel.System(M * np.eye(2), np.zeros((2, 2)))
        s.add(case.device).add_load(gm.as_load(np.array([1.0, 0.0])))
        sol = duhamel.solve(
            s, duhamel.Semianalytic(), t_end=gm.duration, dt=DT_REC / k, save_every=k
        )
        return sol.x[:, 0]
    s = duhamel.System(M * np.eye(1), K_FRAME * np.eye(1), C=A0 * M * np.eye(1))
    s.add(case.device).add_load(gm.as_load(np.ones(1)))
    sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=gm.duration, dt=DT_REC / k, save_every=k)
    return sol.x[:, 0]


def _transient(ops, path: str) -> None:
    """Newmark average acceleration, Newton at NormDispIncr 1e-12, node 2's x recorded."""
    ops.constraints("Plain")
    ops.numberer("Plain")
    ops.system("BandGeneral")
    ops.test("NormDispIncr", 1e-12, 50)
    ops.algorithm("Newton")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")
    ops.recorder("Node", "-file", path, "-node", 2, "-dof", 1, "disp")


def run_opensees_fps(gm: GroundMotion, k: int, path: str, case: Case | None = None) -> None:
    import openseespy.opensees as ops

    w = M * G
    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    ops.node(1, 0.0, 0.0)
    ops.node(2, 0.0, 0.0)
    ops.fix(1, 1, 1, 1)
    ops.fix(2, 0, 0, 1)
    ops.mass(2, M, M, 0.0)
    if case is None:
        ops.frictionModel("Coulomb", 1, MU_FPS)
    else:
        case.opensees(1)
    ops.uniaxialMaterial("Elastic", 1, 1e12)
    ops.uniaxialMaterial("Elastic", 2, 1e12)
    ops.element(
        "singleFPBearing", 1, 1, 2, 1, RADIUS, MU_FPS * w / UY_FPS, "-P", 1, "-Mz", 2,
        "-orient", 0, 1, 0, -1, 0, 0, "-iter", 100, 1e-8,
    )  # fmt: skip
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    ops.load(2, 0.0, -w, 0.0)
    ops.constraints("Plain")
    ops.numberer("Plain")
    ops.system("BandGeneral")
    ops.test("NormDispIncr", 1e-12, 50)
    ops.algorithm("Newton")
    ops.integrator("LoadControl", 0.1)
    ops.analysis("Static")
    ops.analyze(10)
    ops.loadConst("-time", 0.0)
    ops.wipeAnalysis()
    ops.timeSeries("Path", 2, "-dt", DT_REC, "-values", *gm.a.tolist())
    ops.pattern("UniformExcitation", 2, 1, "-accel", 2)
    _transient(ops, path)
    if ops.analyze((gm.a.size - 1) * k, DT_REC / k) != 0:
        raise RuntimeError(f"OpenSees failed on the friction pendulum at dt = {DT_REC / k}")
    ops.wipe()


def run_opensees(case: Case, gm: GroundMotion, k: int, path: str) -> None:
    import openseespy.opensees as ops

    if case.name == FPS:
        run_opensees_fps(gm, k, path)
        return
    if case.name == _triple.TFP:
        _triple.run_opensees(M, gm, DT_REC, k, path)
        return
    if case.name in PLANE:
        run_opensees_fps(gm, k, path, case)
        return
    if case.name in (LRB_1, LRB_2):
        run_opensees_lrb(case, gm, k, path)
        return
    ops.wipe()
    ops.model("basic", "-ndm", 1, "-ndf", 1)
    ops.node(1, 0.0)
    ops.node(2, 0.0)
    ops.fix(1, 1)
    ops.mass(2, M)
    ops.uniaxialMaterial("Elastic", 1, K_FRAME)
    case.opensees(2)
    ops.element("zeroLength", 1, 1, 2, "-mat", 1, 2, "-dir", 1, 1)
    ops.timeSeries("Path", 1, "-dt", DT_REC, "-values", *gm.a.tolist())
    ops.pattern("UniformExcitation", 1, 1, "-accel", 1)
    ops.rayleigh(A0, 0.0, 0.0, 0.0)
    _transient(ops, path)
    n = (gm.a.size - 1) * k
    if ops.analyze(n, DT_REC / k) != 0:
        raise RuntimeError(f"OpenSees failed on {case.name} at dt = {DT_REC / k}")
    ops.wipe()  # closes the recorder


def read_opensees(path: str, k: int, n: int) -> np.ndarray:
    x = np.loadtxt(path).reshape(-1)
    return np.concatenate([[0.0], x[k - 1 :: k]])[:n]


ONLY: list[str] = []  # --only: the models whose name contains one of these


def measure(quick: bool) -> dict:
    load0 = os.getloadavg()[0]
    gm = record(6.0 if quick else 20.0)
    ks = [1, 2, 4, 8, 16, 32, 64]
    k_ref = 64 if quick else 256
    repeats = 1 if quick else 3
    tmp = tempfile.mkdtemp()
    path = os.path.join(tmp, "disp.out")
    out = []
    for case in cases():
        if ONLY and not any(o in case.name for o in ONLY):
            continue
        ref_d = run_duhamel(case, gm, k_ref)
        if case.name == _triple.TFP:  # no converged OpenSees run (benchmarks/_triple.py)
            ref_o = ref_d
        else:
            run_opensees(case, gm, k_ref, path)
            ref_o = read_opensees(path, k_ref, gm.a.size)
        peak = np.abs(ref_d).max()
        row = {"name": case.name, "cross": float(np.abs(ref_d - ref_o).max() / peak), "k": {}}
        for k in ks:
            xd = run_duhamel(case, gm, k)
            run_opensees(case, gm, k, path)
            xo = read_opensees(path, k, gm.a.size)
            td = min(
                _section.timed(lambda k=k, c=case: run_duhamel(c, gm, k)) for _ in range(repeats)
            )
            to = min(
                _section.timed(lambda k=k, c=case: run_opensees(c, gm, k, path))
                for _ in range(repeats)
            )
            row["k"][k] = {
                "err_d": float(np.abs(xd - ref_d).max() / peak),
                "err_o": float(np.abs(xo - ref_o).max() / peak),
                "t_d": td,
                "t_o": to,
            }
        out.append(row)
    return {
        "rows": out,
        "n": gm.a.size,
        "seconds": gm.duration,
        "load": (load0, os.getloadavg()[0]),
    }


def to_accuracy(row: dict, level: float, who: str) -> tuple[int, float] | None:
    for k, r in sorted(row["k"].items()):
        if r[f"err_{who}"] <= level:
            return k, r[f"t_{who}"]
    return None


def markdown(r: dict) -> list[str]:
    out = [
        "## Devices against OpenSees (issues 13 and 27)",
        "",
        "Generated by `benchmarks/devices.py --append BENCHMARKS.md`. One-storey frame (T = 1 s, "
        "2 % mass-proportional damping) with one device (the Maxwell damper: exponent 0.35 in "
        "series with a brace of 5 k_frame; the friction pendulums: a rigid mass on "
        "it, no frame; bidirectional on (x, y) excited along x, uniaxial on x with constant or "
        "velocity-dependent friction, mu_slow = 0.025, rate = 20 s/m, against the same planar "
        "singleFPBearing; lead-rubber bearings, uniaxial against the 2-D and bidirectional "
        "against the 3-D elastomericBearingBoucWen; the uniaxial triple friction pendulum "
        "against OpenSees' TripleFrictionPendulum, the record x 1.5, both codes' errors "
        "against duhamel's converged run), synthetic record of "
        f"{r['seconds']:.0f} s at 200 Hz (PGA 0.4 g). Error: largest difference at the "
        "record's samples against the same code at dt = 0.005/256, over the peak displacement; "
        "time: the whole call (set-up included), best of repeats, codes interleaved. "
        f"1-min load average before {r['load'][0]:.2f}, after {r['load'][1]:.2f}.",
        "",
        "| model | converged duhamel vs converged OpenSees | dt = 0.005/k | duhamel error | "
        "duhamel [ms] | OpenSees error | OpenSees [ms] |",
        "|---|---:|---:|---:|---:|---:|---:|",
    ]
    for row in r["rows"]:
        for k, v in sorted(row["k"].items()):
            out.append(
                f"| {row['name']} | {row['cross']:.1e} | {k} | {v['err_d']:.1e} | "
                f"{1e3 * v['t_d']:.1f} | {v['err_o']:.1e} | {1e3 * v['t_o']:.1f} |"
            )
    out += [
        "",
        "Time to equal accuracy (the largest step reaching the level, each code):",
        "",
        "| model | level | duhamel k, ms | OpenSees k, ms | OpenSees / duhamel |",
        "|---|---:|---:|---:|---:|",
    ]
    for row in r["rows"]:
        for level in (1e-2, 1e-3, 1e-4):
            d, o = to_accuracy(row, level, "d"), to_accuracy(row, level, "o")
            if d is None or o is None:
                show = [f"{w[0]}, {1e3 * w[1]:.1f}" if w else "not reached" for w in (d, o)]
                out.append(f"| {row['name']} | {level:.0e} | {show[0]} | {show[1]} | - |")
                continue
            out.append(
                f"| {row['name']} | {level:.0e} | {d[0]}, {1e3 * d[1]:.1f} | "
                f"{o[0]}, {1e3 * o[1]:.1f} | {o[1] / d[1]:.1f} |"
            )
    return out


def main(argv: list[str] | None = None) -> int:
    import sys

    argv = list(sys.argv[1:] if argv is None else argv)
    while "--only" in argv:
        at = argv.index("--only")
        ONLY.append(argv[at + 1])
        del argv[at : at + 2]
    return _section.main(
        __doc__, lambda quick: markdown(measure(quick)), "a short record, one repeat", argv
    )


if __name__ == "__main__":
    raise SystemExit(main())

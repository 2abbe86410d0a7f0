"""The friction pendulum with its vertical dof against OpenSees ``singleFPBearing``
(issue 27): a mass on the bearing with its axial stiffness, after gravity, under horizontal
and vertical records (the axial force varies), velocity-dependent friction; 2-D uniaxial and
3-D bidirectional. Each code's error against itself at dt = 0.005/128, and the time to the
same accuracy.

Run: ``PYTHONPATH=python python benchmarks/pendulum_axial.py [--append BENCHMARKS.md]``.
"""

from __future__ import annotations

import os
import sys
import tempfile

import numpy as np

import duhamel
from duhamel import elements as E
from duhamel import loads as L

sys.path.insert(0, os.path.dirname(__file__))
from _section import main, timed

M, G, R, UY, KV, DT = 1e5, 9.81, 2.0, 2.5e-4, 2e8, 0.005
W = M * G
FAST, SLOW, RATE = 0.07, 0.035, 15.0
SECONDS = 10.0
RECORDS = ((13, 0.4), (21, 0.3))  # horizontal x, y: (seed, peak in g)
VERTICAL = (7, 0.2)  # N between 0.08 W and 2 W, no uplift


def record(seed: int, peak: float) -> np.ndarray:
    import scipy.signal

    n = round(SECONDS / DT) + 1
    rng = np.random.default_rng(seed)
    t = DT * np.arange(n)
    b, a = scipy.signal.butter(4, [0.3, 8.0], btype="band", fs=1 / DT)
    env = np.minimum(t / 2.0, 1.0) * np.exp(-np.maximum(t - 8.0, 0.0) / 4.0)
    x = env * scipy.signal.lfilter(b, a, rng.normal(size=n))
    return peak * G * x / np.abs(x).max()


def inputs(ndm: int) -> list[tuple[int, np.ndarray]]:
    """(direction 0-based, acceleration) of the records: horizontal ones, then vertical."""
    horizontal = RECORDS[: ndm - 1]
    out = [(k, record(*r)) for k, r in enumerate(horizontal)]
    return [*out, (ndm - 1, record(*VERTICAL))]


def ours(ndm: int, k: int) -> np.ndarray:
    n = ndm
    t = DT * np.arange(round(SECONDS / DT) + 1)
    s = duhamel.System(M * np.eye(n), np.zeros((n, n)))
    s.add(
        E.FrictionPendulum(
            (0, None if ndm == 2 else 1, n - 1), radius=R, mu=FAST, weight=W,
            yield_displacement=UY, mu_slow=SLOW, rate=RATE, vertical_stiffness=KV,
        )
    )  # fmt: skip
    for dof, a in inputs(ndm):
        s.add_load(L.BaseAcceleration(np.eye(n)[dof], t=t, values=a))
    s.add_load(L.Step(n - 1, amplitude=-W))
    x0 = np.zeros(n)
    x0[-1] = -W / KV
    sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=t[-1], dt=DT / k, save_every=k, x0=x0)
    return sol.x[:, : n - 1]


def opensees(ndm: int, k: int) -> np.ndarray:
    import openseespy.opensees as ops

    path = os.path.join(tempfile.mkdtemp(), "disp.out")
    ops.wipe()
    ops.model("basic", "-ndm", ndm, "-ndf", 3 if ndm == 2 else 6)
    ops.node(1, *[0.0] * ndm)
    ops.node(2, *[0.0] * ndm)
    ops.frictionModel("VelDependent", 1, SLOW, FAST, RATE)
    ops.uniaxialMaterial("Elastic", 1, KV)
    ops.uniaxialMaterial("Elastic", 2, 1e12)
    if ndm == 2:
        ops.fix(1, 1, 1, 1)
        ops.fix(2, 0, 0, 1)
        ops.mass(2, M, M, 0.0)
        mats, orient, weight = ["-P", 1, "-Mz", 2], [0, 1, 0, -1, 0, 0], [0.0, -W, 0.0]
    else:
        ops.fix(1, 1, 1, 1, 1, 1, 1)
        ops.fix(2, 0, 0, 0, 1, 1, 1)
        ops.mass(2, M, M, M, 0.0, 0.0, 0.0)
        mats = ["-P", 1, "-T", 2, "-My", 2, "-Mz", 2]
        orient, weight = [0, 0, 1, 1, 0, 0], [0.0, 0.0, -W, 0.0, 0.0, 0.0]
    ops.element(
        "singleFPBearing", 1, 1, 2, 1, R, FAST * W / UY, *mats,
        "-orient", *orient, "-iter", 100, 1e-8,
    )  # fmt: skip
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    ops.load(2, *weight)
    common = (
        ("constraints", "Plain"),
        ("numberer", "Plain"),
        ("system", "FullGeneral"),
        ("test", "NormDispIncr", 1e-12, 50),
        ("algorithm", "Newton"),
    )
    for name, *args in (*common, ("integrator", "LoadControl", 0.1), ("analysis", "Static")):
        getattr(ops, name)(*args)
    ops.analyze(10)
    ops.loadConst("-time", 0.0)
    ops.wipeAnalysis()
    n = round(SECONDS / DT) + 1
    for tag, (dof, a) in enumerate(inputs(ndm), 2):
        ops.timeSeries("Path", tag, "-dt", DT, "-values", *a.tolist())
        ops.pattern("UniformExcitation", tag, dof + 1, "-accel", tag)
    for name, *args in (*common, ("integrator", "Newmark", 0.5, 0.25), ("analysis", "Transient")):
        getattr(ops, name)(*args)
    horizontal = list(range(1, ndm))
    ops.recorder("Node", "-file", path, "-node", 2, "-dof", *horizontal, "disp")
    assert ops.analyze((n - 1) * k, DT / k) == 0
    ops.wipe()
    x = np.loadtxt(path).reshape(-1, ndm - 1)
    return np.concatenate([np.zeros((1, ndm - 1)), x[k - 1 :: k]])[:n]


def section(quick: bool) -> list[str]:
    load0 = os.getloadavg()[0]
    ks = (1, 2, 4) if quick else (1, 2, 4, 8, 16, 32)
    ref_k = 8 if quick else 128
    rows = []
    for ndm in (2, 3):
        ref_ours, ref_os = ours(ndm, ref_k), opensees(ndm, ref_k)
        peak = np.abs(ref_ours).max()
        between = np.abs(ref_ours - ref_os).max() / peak
        for k in ks:
            t_ours, t_os = [], []
            for _ in range(2):  # interleaved, best of two
                t_ours.append(timed(lambda k=k, ndm=ndm: ours(ndm, k)))
                t_os.append(timed(lambda k=k, ndm=ndm: opensees(ndm, k)))
            e_ours = np.abs(ours(ndm, k) - ref_ours).max() / peak
            e_os = np.abs(opensees(ndm, k) - ref_os).max() / peak
            rows.append((ndm, between, k, e_ours, min(t_ours), e_os, min(t_os)))
    load1 = os.getloadavg()[0]
    lines = [
        "## The friction pendulum with its vertical dof against OpenSees (issue 27, branch "
        "issue-27p)",
        "",
        "Generated by `benchmarks/pendulum_axial.py --append BENCHMARKS.md`. A mass on the "
        "bearing (R = 2 m, VelDependent friction 0.035-0.07, rate 15 s/m, axial stiffness "
        "2e8 N/m, gravity first), horizontal records of 0.4 g (and 0.3 g across in 3-D) and a "
        "vertical one of 0.2 g (N between 0.08 W and 2 W), 10 s at 200 Hz; 2-D uniaxial and "
        "3-D bidirectional `singleFPBearing`. Error: largest difference of the horizontal "
        f"displacements against the same code at dt = 0.005/{ref_k}, over the peak; time: "
        "the whole call, best of two, codes interleaved. 1-min load average before "
        f"{load0:.2f}, after {load1:.2f}.",
        "",
        "| model | converged duhamel vs converged OpenSees | dt = 0.005/k | duhamel error "
        "| duhamel [ms] | OpenSees error | OpenSees [ms] |",
        "|---|---:|---:|---:|---:|---:|---:|",
    ]
    for ndm, between, k, e1, t1, e2, t2 in rows:
        lines.append(
            f"| {ndm}-D | {between:.1e} | {k} | {e1:.1e} | {1e3 * t1:.1f} | {e2:.1e} "
            f"| {1e3 * t2:.1f} |"
        )
    lines += ["", "Time to the same accuracy (the fastest run of each code within it):", ""]
    for ndm in (2, 3):
        mine = [r for r in rows if r[0] == ndm]
        for target in (1e-2, 3e-3, 1e-3):
            a = [r[4] for r in mine if r[3] <= target]
            b = [r[6] for r in mine if r[5] <= target]
            if a and b:
                lines.append(
                    f"* {ndm}-D, error <= {target:.0e}: duhamel {1e3 * min(a):.0f} ms, "
                    f"OpenSees {1e3 * min(b):.0f} ms, ratio {min(b) / min(a):.1f}"
                )
            else:
                lines.append(
                    f"* {ndm}-D, error <= {target:.0e}: not reached by both in k <= {ks[-1]}"
                )
    return lines


if __name__ == "__main__":
    raise SystemExit(main(__doc__ or "", section, "a smoke run (coarse steps)", sys.argv[1:]))

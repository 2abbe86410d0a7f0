"""OpenSees' ``ViscousDamper`` material (a power-law damper in series with its brace K)
imported by ``duhamel.opensees.from_opensees`` as ``ViscousDamper(..., brace_stiffness=K)``
(issue 27): a one-storey frame with the braced damper under a record, imported and run in
both codes, within 0.5 % of the peak of OpenSees' converged run."""

from __future__ import annotations

import os
import tempfile

import numpy as np
import pytest

import duhamel

try:  # the wheel needs the system BLAS/LAPACK (libblas3, liblapack3)
    import openseespy.opensees as ops
except Exception as exc:  # pragma: no cover - depends on the machine
    pytest.skip(reason=f"openseespy cannot be loaded: {exc}", allow_module_level=True)

from tests.elements.test_triple_pendulum import record

M, OMEGA = 1e5, 2 * np.pi  # T = 1 s
K_FRAME = M * OMEGA**2
DT = 0.005


def build(kb: float, c: float, alpha: float) -> None:
    ops.wipe()
    ops.model("basic", "-ndm", 1, "-ndf", 1)
    ops.node(1, 0.0)
    ops.node(2, 0.0)
    ops.fix(1, 1)
    ops.mass(2, M)
    ops.uniaxialMaterial("Elastic", 1, K_FRAME)
    ops.uniaxialMaterial("ViscousDamper", 2, kb, c, alpha)
    ops.element("zeroLength", 1, 1, 2, "-mat", 1, 2, "-dir", 1, 1)


def run(a: np.ndarray, n: int, k: int) -> np.ndarray:
    path = os.path.join(tempfile.mkdtemp(), "disp.out")
    ops.timeSeries("Path", 1, "-dt", DT, "-values", *a.tolist())
    ops.pattern("UniformExcitation", 1, 1, "-accel", 1)
    for name, *args in (
        ("constraints", "Plain"),
        ("numberer", "Plain"),
        ("system", "BandGeneral"),
        ("test", "NormDispIncr", 1e-12, 50),
        ("algorithm", "Newton"),
        ("integrator", "Newmark", 0.5, 0.25),
        ("analysis", "Transient"),
    ):
        getattr(ops, name)(*args)
    ops.recorder("Node", "-file", path, "-node", 2, "-dof", 1, "disp")
    assert ops.analyze((n - 1) * k, DT / k) == 0
    ops.wipe()
    x = np.loadtxt(path).reshape(-1)
    return np.concatenate([[0.0], x[k - 1 :: k]])[:n]


@pytest.mark.parametrize("alpha", [0.35, 1.0])
def test_braced_damper_import_against_opensees(alpha: float) -> None:
    t, a = record(12.0, 0.4)
    kb = 3 * K_FRAME  # a brace soft enough that the series matters
    c = 0.15 * 2 * M * OMEGA * 0.1 ** (1 - alpha)  # 15 % damping-equivalent at 0.1 m/s
    build(kb, c, alpha)
    s = duhamel.opensees.from_opensees()
    (damper,) = s.opensees.elements[1]
    # OpenSees prints this material as text, to 6 significant digits
    assert damper.brace_stiffness == pytest.approx(kb, rel=5e-6)
    assert (damper.c, damper.exponent) == (pytest.approx(c, rel=5e-6), alpha)
    assert s.K[0, 0] == pytest.approx(K_FRAME)  # the frame alone: the damper is an element
    s.add_load(duhamel.loads.BaseAcceleration(np.ones(1), t=t, values=a))
    ours = duhamel.solve(s, duhamel.Semianalytic(), t_end=float(t[-1]), dt=DT / 4, save_every=4)
    build(kb, c, alpha)
    theirs = run(a, t.size, 16)
    peak = np.abs(theirs).max()
    assert np.abs(ours.x[:, 0] - theirs).max() <= 5e-3 * peak
    # the brace's flexibility is in the model: the rigid-brace dashpot responds differently
    rigid = duhamel.System(M * np.eye(1), K_FRAME * np.eye(1))
    rigid.add(duhamel.elements.ViscousDamper(0, c=c, exponent=alpha))
    rigid.add_load(duhamel.loads.BaseAcceleration(np.ones(1), t=t, values=a))
    dashpot = duhamel.solve(rigid, duhamel.Semianalytic(), t_end=float(t[-1]), dt=DT).x[:, 0]
    assert np.abs(dashpot - theirs).max() > 2e-2 * peak  # 4.6 % and more

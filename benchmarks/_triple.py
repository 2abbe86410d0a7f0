"""The triple friction pendulum rows of ``benchmarks/devices.py`` (issue 27): a rigid mass on
one bearing, uniaxial, in duhamel and in OpenSees (``TripleFrictionPendulum``, Coulomb
friction, the weight applied by a static step on a stiff vertical material, y and the
rotations fixed).

OpenSees' element solves its series model to a tolerance relative to the step's increment
and its Newton iteration stalls below ``NormDispIncr`` 1e-7 m: its runs at small steps
accumulate that tolerance (at dt = 0.005/16 it has moved 1.3e-3 of the peak away from its
run at 0.005, while duhamel's runs agree to 1e-5), so it has no converged run of its own;
both codes' errors are measured against duhamel's converged run (the two codes agree to
6e-5 of the peak at dt = 0.005)."""

from __future__ import annotations

import numpy as np

import duhamel
from duhamel import elements as E
from duhamel.records import G, GroundMotion

TFP = "TripleFrictionPendulum(dof_y=None) / TripleFrictionPendulum"
MU, RADIUS, CAPACITY, UY = (0.02, 0.06, 0.10), (0.3, 2.0, 2.5), (0.05, 0.3, 0.35), 5e-4
SCALE = 1.5  # the record x 1.5 (0.6 g): the bearing reaches regime III


def bearing(m: float) -> E.TripleFrictionPendulum:
    return E.TripleFrictionPendulum(
        0, mu=MU, radius=RADIUS, displacement_capacity=CAPACITY, weight=m * G, yield_displacement=UY
    )


def run_duhamel(device: E.Element, m: float, gm: GroundMotion, dt: float, k: int) -> np.ndarray:
    s = duhamel.System(m * np.eye(1), np.zeros((1, 1)))
    s.add(device).add_load(gm.as_load(SCALE * np.ones(1)))
    sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=gm.duration, dt=dt / k, save_every=k)
    return sol.x[:, 0]


def run_opensees(m: float, gm: GroundMotion, dt: float, k: int, path: str) -> None:
    import openseespy.opensees as ops

    w = m * G
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    ops.node(1, 0.0, 0.0, 0.0)
    ops.node(2, 0.0, 0.0, 0.0)
    ops.fix(1, 1, 1, 1, 1, 1, 1)
    ops.fix(2, 0, 1, 0, 1, 1, 1)
    ops.mass(2, m, m, 0.0, 0.0, 0.0, 0.0)
    for tag, mu in enumerate(MU, start=1):
        ops.frictionModel("Coulomb", tag, mu)
    ops.uniaxialMaterial("Elastic", 1, 1e12)
    ops.uniaxialMaterial("Elastic", 2, 1e10)
    ops.element(
        "TripleFrictionPendulum", 1, 1, 2, 1, 2, 3, 1, 2, 2, 2,
        *RADIUS, *CAPACITY, w, UY, 1.0, 0.1, 1e-10,
    )  # fmt: skip
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    ops.load(2, 0.0, 0.0, -w, 0.0, 0.0, 0.0)
    for name, *args in (
        ("constraints", "Plain"),
        ("numberer", "Plain"),
        ("system", "BandGeneral"),
        ("test", "NormDispIncr", 1e-12, 50),
        ("algorithm", "Newton"),
        ("integrator", "LoadControl", 0.1),
        ("analysis", "Static"),
    ):
        getattr(ops, name)(*args)
    ops.analyze(10)
    ops.loadConst("-time", 0.0)
    ops.wipeAnalysis()
    ops.timeSeries("Path", 2, "-dt", dt, "-values", *(SCALE * gm.a).tolist())
    ops.pattern("UniformExcitation", 2, 1, "-accel", 2)
    for name, *args in (
        ("constraints", "Plain"),
        ("numberer", "Plain"),
        ("system", "BandGeneral"),
        ("test", "NormDispIncr", 1e-7, 100),
        ("algorithm", "Newton"),
        ("integrator", "Newmark", 0.5, 0.25),
        ("analysis", "Transient"),
    ):
        getattr(ops, name)(*args)
    ops.recorder("Node", "-file", path, "-node", 2, "-dof", 1, "disp")
    if ops.analyze((gm.a.size - 1) * k, dt / k) != 0:
        raise RuntimeError(f"OpenSees failed on the triple pendulum at dt = {dt / k}")
    ops.wipe()

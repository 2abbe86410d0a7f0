"""Base-isolated frames built in openseespy (tests of duhamel.opensees.from_opensees with
bearings that carry their axial force): 2-D (`bays` bays) or 3-D (one bay each way), two
storeys, a base slab on one bearing per column line, masses in every translation (so the
vertical dofs are dynamic and the bearings' axial forces vary under a vertical record and
the overturning), massless rotations. The gravity loads (the masses' weights) are applied by
a static analysis and held (``loadConst``); Rayleigh damping on the frame's elements
(``betaK0``; the bearings take none).

Bearings (zero length, ground below, base above; their axis up): ``singleFP``
(``singleFPBearing``, R = 2 m), ``flat`` (``flatSliderBearing``), ``rubber``
(``elastomericBearingBoucWen``, a lead-rubber bearing), ``plastic``
(``elastomericBearingPlasticity``), ``triple`` (3-D only: OpenSees'
``TripleFrictionPendulum``, friction ``TRIPLE_MU``, radii ``TRIPLE_L``, capacities
``TRIPLE_D``; its P-Delta moments act on the base slab's rotations, fixed with
``fix_base_rotations``).
"""

from __future__ import annotations

from typing import Any

import numpy as np

G = 9.81
H, BAY = 3.0, 6.0
M_FLOOR, M_BASE = 2.0e4, 1.5e4  # per column line
MU, RADIUS, KV = 0.06, 2.0, 5.0e9
E, A, I_SEC, J = 2.0e11, 1.0e-2, 3.0e-4, 1.0e-4
W_LINE = (M_BASE + 2 * M_FLOOR) * G  # the nominal weight per bearing
TRIPLE_MU, TRIPLE_L, TRIPLE_D = (0.02, 0.06, 0.10), (0.3, 2.0, 2.5), (0.05, 0.3, 0.35)
TRIPLE_MIN_FV = 0.1  # OpenSees' minFv, the normal force in uplift


def lines(ndm: int, bays: int) -> list[tuple[float, float]]:
    if ndm == 2:
        return [(k * BAY, 0.0) for k in range(bays + 1)]
    return [(0.0, 0.0), (BAY, 0.0), (BAY, BAY), (0.0, BAY)]


def node(level: int, line: int) -> int:
    """The column node of `line` at `level` (0: the base slab); the ground below is
    ``ground(line)``."""
    return 100 * (level + 1) + line + 1


def ground(line: int) -> int:
    return 10 + line


def build(
    bearing: str, *, ndm: int = 2, bays: int = 2, mu: float = MU, fix_base_rotations: bool = False
) -> list[int]:
    """Defines the frame (session wiped first) and runs its gravity analysis. Returns the
    bearings' tags."""
    import openseespy.opensees as ops

    ops.wipe()
    ops.model("basic", "-ndm", ndm, "-ndf", 3 if ndm == 2 else 6)
    up = ndm  # the vertical dof
    pts = lines(ndm, bays)
    for line, (x, y) in enumerate(pts):
        xy = (x,) if ndm == 2 else (x, y)
        ops.node(ground(line), *xy, 0.0)
        ops.fix(ground(line), *([1] * (3 if ndm == 2 else 6)))
        for level in range(3):
            ops.node(node(level, line), *xy, level * H)
            m = M_BASE if level == 0 else M_FLOOR
            ops.mass(node(level, line), *([m] * ndm + [0.0] * (1 if ndm == 2 else 3)))
        if __import__("os").environ.get("FIXROT"):
            ops.fix(node(0, line), 0, 0, 1)
        if fix_base_rotations:
            ops.fix(node(0, line), *([0] * ndm), *([1] * (3 if ndm == 3 else 1)))
    if ndm == 2:
        ops.geomTransf("Linear", 1)
        transforms = (1, 1)
    else:
        ops.geomTransf("Linear", 1, 1.0, 0.0, 0.0)
        ops.geomTransf("Linear", 2, 0.0, 0.0, 1.0)
        transforms = (1, 2)
    section = (A, E, I_SEC) if ndm == 2 else (A, E, 8e10, J, I_SEC, I_SEC)
    tag, frame = 1, []
    for line in range(len(pts)):
        for level in range(2):
            ops.element("elasticBeamColumn", tag, node(level, line), node(level + 1, line),
                        *section, transforms[0])  # fmt: skip
            frame.append(tag)
            tag += 1
    pairs = [(k, k + 1) for k in range(bays)] if ndm == 2 else [(k, (k + 1) % 4) for k in range(4)]
    for level in range(3):
        for a, b in pairs:
            ops.element("elasticBeamColumn", tag, node(level, a), node(level, b), *section,
                        transforms[1])  # fmt: skip
            frame.append(tag)
            tag += 1
    ops.region(1, "-ele", *frame, "-rayleigh", 0.2, 0.0, 0.002, 0.0)
    ops.uniaxialMaterial("Elastic", 1, KV)
    ops.uniaxialMaterial("Elastic", 2, 1e6)  # the bearings' rotations
    ops.frictionModel("Coulomb", 1, mu)
    mats = ["-P", 1, "-Mz", 2] if ndm == 2 else ["-P", 1, "-T", 2, "-My", 2, "-Mz", 2]
    orient = [0, 1, 0, -1, 0, 0] if ndm == 2 else [0, 0, 1, 1, 0, 0]
    k_init = mu * W_LINE / 5e-4  # the yield displacement 0.5 mm
    qd = 0.05 * W_LINE
    shape: dict[str, list[Any]] = {
        "singleFP": ["singleFPBearing", 1, RADIUS, k_init],
        "flat": ["flatSliderBearing", 1, k_init],
        "rubber": ["elastomericBearingBoucWen", qd / 0.01, qd, 0.1, 0.0, 2.0, 1.0, 0.5, 0.5],
        "plastic": ["elastomericBearingPlasticity", qd / 0.01, qd, 0.1, 0.0, 1.0],
    }
    if bearing == "triple":
        for k, m in enumerate(TRIPLE_MU):
            ops.frictionModel("Coulomb", 2 + k, m)
    tags = []
    for line in range(len(pts)):
        if bearing == "triple":  # the vertical, torsion, rx and ry materials; kvt, minFv, tol
            ops.element("TripleFrictionPendulum", 900 + line, ground(line), node(0, line),
                        2, 3, 4, 1, 2, 2, 2, *TRIPLE_L, *TRIPLE_D, W_LINE, 5e-4, 1.0,
                        TRIPLE_MIN_FV, 1e-10)  # fmt: skip
        else:
            kind, *args = shape[bearing]
            it = ["-iter", 100, 1e-8] if bearing in ("singleFP", "flat") else []
            ops.element(kind, 900 + line, ground(line), node(0, line), *args, *mats,
                        "-orient", *orient, *it)  # fmt: skip
        tags.append(900 + line)
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    for line in range(len(pts)):
        for level in range(3):
            m = M_BASE if level == 0 else M_FLOOR
            load = [0.0] * (3 if ndm == 2 else 6)
            load[up - 1] = -m * G
            ops.load(node(level, line), *load)
    ops.constraints("Transformation")
    ops.numberer("RCM")
    ops.system("BandGeneral")
    ops.test("NormDispIncr", 1e-12, 50)
    ops.algorithm("Newton")
    ops.integrator("LoadControl", 0.1)
    ops.analysis("Static")
    if ops.analyze(10) != 0:
        raise RuntimeError("the gravity analysis failed")
    ops.loadConst("-time", 0.0)
    ops.wipeAnalysis()
    return tags


def run_opensees(
    t: Any, records: list[tuple[int, Any]], substeps: int, ndm: int, bays: int = 2
) -> tuple[Any, Any, Any]:
    """The records ``(direction, accelerations)`` (Newmark, average acceleration, Newton,
    `substeps` steps per interval): the base slab's ux (line 0), the roof's ux acceleration
    relative to the ground and the base shear in x, at the record's instants but its last."""
    import openseespy.opensees as ops

    dt = float(t[1] - t[0])
    for k, (direction, values) in enumerate(records):
        ops.timeSeries("Path", 2 + k, "-dt", dt, "-values", *np.asarray(values).tolist())
        ops.pattern("UniformExcitation", 2 + k, direction, "-accel", 2 + k)
    ops.constraints("Transformation")
    ops.numberer("RCM")
    ops.system("BandGeneral")
    ops.test("NormDispIncr", 1e-10, 100)
    ops.algorithm("Newton")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")
    n = len(lines(ndm, bays))
    x, acc, shear = (np.zeros(t.size - 1) for _ in range(3))
    x[0] = ops.nodeDisp(node(0, 0), 1)  # the state at the start (after gravity)
    for k in range(1, t.size - 1):
        if ops.analyze(substeps, dt / substeps) != 0:
            raise RuntimeError(f"OpenSees failed at t = {t[k]}")
        ops.reactions()
        x[k], acc[k] = ops.nodeDisp(node(0, 0), 1), ops.nodeAccel(node(2, 0), 1)
        shear[k] = -sum(ops.nodeReaction(ground(line), 1) for line in range(n))
    return x, acc, shear

"""A 3-D steel moment frame with plastic hinges at the beam ends, built in openseespy (tests
of duhamel.opensees.from_opensees after a gravity analysis).

One bay in each direction (the column lines at the corners of a ``BAY x BAY`` square),
`storeys` levels. Columns and beams are 3-D ``elasticBeamColumn`` elements; floor masses are
lumped at the column nodes (ux, uy), every other dof is massless (uz, the rotations). Each
beam end is a node of its own, tied to the column node in every dof but the beam's bending
rotation in the vertical plane (``equalDOF``), with a rotational ``zeroLength`` hinge of
``Steel01`` about that axis: the hinge rotations are massless dofs. A uniform gravity load
on every beam is applied by a static analysis and held (``loadConst``); Rayleigh damping
``rayleigh(alphaM, betaK, betaK0, betaKc)`` on every element.
"""

from __future__ import annotations

from typing import Any

import numpy as np

H, BAY = 3.0, 6.0
E, G_SHEAR = 2.0e11, 8.0e10
A_COL, I_COL, J_COL = 1.2e-2, 3.0e-4, 1.0e-4
A_BEAM, I_BEAM, J_BEAM = 1.0e-2, 4.0e-4, 1.0e-4
M_NODE = 2.0e4
HINGE = 10.0
CORNERS = ((0.0, 0.0), (BAY, 0.0), (BAY, BAY), (0.0, BAY))


def node(storey: int, line: int) -> int:
    """The column node of corner `line` (0-3) at level `storey` (0: the fixed base)."""
    return 100 * (storey + 1) + line + 1


def build(
    *,
    storeys: int = 2,
    rayleigh: tuple[float, float, float, float] | None = (0.3, 0.002, 0.0, 0.0),
    my: float = 1.2e5,
    alpha: float = 0.02,
    gravity: float = 3.0e4,
) -> dict[str, list[int]]:
    """Defines the frame in the openseespy session (wiped first) and runs its gravity
    analysis. Returns the element tags by kind."""
    import openseespy.opensees as ops

    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    for line, (x, y) in enumerate(CORNERS):
        for storey in range(storeys + 1):
            ops.node(node(storey, line), x, y, storey * H)
            if storey == 0:
                ops.fix(node(storey, line), 1, 1, 1, 1, 1, 1)
            else:
                ops.mass(node(storey, line), M_NODE, M_NODE, 0.0, 0.0, 0.0, 0.0)
    ops.geomTransf("Linear", 1, 1.0, 0.0, 0.0)  # columns (along z)
    ops.geomTransf("Linear", 2, 0.0, 0.0, 1.0)  # beams (horizontal): local z up
    tags: dict[str, list[int]] = {"columns": [], "beams": [], "hinges": []}
    tag = 1
    for line in range(4):
        for storey in range(storeys):
            ops.element(
                "elasticBeamColumn", tag, node(storey, line), node(storey + 1, line),
                A_COL, E, G_SHEAR, J_COL, I_COL, I_COL, 1,
            )  # fmt: skip
            tags["columns"].append(tag)
            tag += 1
    ops.uniaxialMaterial("Steel01", 1, my, HINGE * 6 * E * I_BEAM / BAY, alpha)
    for storey in range(1, storeys + 1):
        for bay in range(4):  # the beams around the square: along x, y, x, y
            a, b = bay, (bay + 1) % 4
            # the bending rotation in the vertical plane: about y for a beam along x
            hinge = 5 if bay % 2 == 0 else 4  # ry or rx
            ends = []
            for side, line in ((0, a), (1, b)):
                end = 10000 + 100 * storey + 10 * bay + side
                x, y = CORNERS[line]
                ops.node(end, x, y, storey * H)
                ops.equalDOF(node(storey, line), end, *[d for d in range(1, 7) if d != hinge])
                ops.element("zeroLength", 5000 + tag, node(storey, line), end, "-mat", 1,
                            "-dir", hinge)  # fmt: skip
                tags["hinges"].append(5000 + tag)
                tag += 1
                ends.append(end)
            ops.element(
                "elasticBeamColumn", tag, *ends, A_BEAM, E, G_SHEAR, J_BEAM, I_BEAM, I_BEAM, 2
            )
            tags["beams"].append(tag)
            tag += 1
    if rayleigh is not None:
        ops.rayleigh(*rayleigh)
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    for beam in tags["beams"]:
        ops.eleLoad("-ele", beam, "-type", "-beamUniform", 0.0, -gravity)
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
    t: Any, a: Any, ay: Any, substeps: int, roof: int, base: list[int]
) -> tuple[Any, Any, Any]:
    """The records (`a` in x, `ay` in y) in the session's model (Newmark, average
    acceleration, Newton, `substeps` steps per record interval): the roof's ux and its
    acceleration relative to the ground, and the base shear in x, at the record's instants
    but its last."""
    import openseespy.opensees as ops

    dt = float(t[1] - t[0])
    for d, (series, values) in enumerate(((2, a), (3, ay))):
        ops.timeSeries("Path", series, "-dt", dt, "-values", *np.asarray(values).tolist())
        ops.pattern("UniformExcitation", series, d + 1, "-accel", series)
    ops.constraints("Transformation")
    ops.numberer("RCM")
    ops.system("BandGeneral")
    ops.test("NormDispIncr", 1e-12, 50)
    ops.algorithm("Newton")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")
    x, acc, shear = (np.zeros(t.size - 1) for _ in range(3))
    x[0] = ops.nodeDisp(roof, 1)  # the state at the start (after the gravity analysis)
    for k in range(1, t.size - 1):
        if ops.analyze(substeps, dt / substeps) != 0:
            raise RuntimeError(f"OpenSees failed at t = {t[k]}")
        ops.reactions()
        x[k], acc[k] = ops.nodeDisp(roof, 1), ops.nodeAccel(roof, 1)
        shear[k] = -sum(ops.nodeReaction(n, 1) for n in base)
    return x, acc, shear

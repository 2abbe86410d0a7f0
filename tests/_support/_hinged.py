"""A family of 2-D steel moment frames with plastic hinges at the beam ends, built in
openseespy (tests of duhamel.opensees.from_opensees and the massless dofs' damping).

Columns and beams are ``elasticBeamColumn`` elements; floor masses are lumped at the column
nodes (ux, uy), every rotation is massless. Each beam end is a node of its own, tied to the
column node in ux and uy (``equalDOF``), with a rotational ``zeroLength`` hinge of
``Steel01`` (stiffness ``HINGE * 6 EI / L``, yield moment `my`, hardening `alpha`) between
them: the hinge rotations are massless dofs at the massless joint rotations. Rayleigh
damping ``rayleigh(alphaM, betaK, betaK0, betaKc)`` on every element (OpenSees' zeroLength
leaves it out unless ``-doRayleigh``), or through a ``region`` of some elements only.
With `gravity`, a uniform load on every beam (and `leaning`, the vertical load on a leaning
column of its own: pinned, ``PDelta``, tied to the frame's floors in ux) is applied by a
static analysis first and held (``loadConst``), as a frame model is run.
"""

from __future__ import annotations

from typing import Any

import numpy as np

H, BAY = 3.0, 6.0
E, A_COL, I_COL, A_BEAM, I_BEAM = 2.0e11, 1.2e-2, 3.0e-4, 1.0e-2, 4.0e-4
M_NODE = 2.0e4
HINGE = 10.0  # the hinge's elastic stiffness over the beam's 6 EI / L


def node(storey: int, line: int) -> int:
    """The column node of `line` at level `storey` (0: the fixed base)."""
    return 100 * (storey + 1) + line + 1


def beam_end(storey: int, bay: int, side: int) -> int:
    return 10000 + 100 * storey + 10 * bay + side


def build(
    *,
    storeys: int = 3,
    bays: int = 2,
    rayleigh: tuple[float, float, float, float] | None = (0.3, 0.002, 0.0, 0.0),
    region: str | None = None,
    hinge_rayleigh: bool = False,
    my: float = 1.2e5,
    alpha: float = 0.02,
    gravity: float = 0.0,
    leaning: float = 0.0,
) -> dict[str, list[int]]:
    """Defines the frame in the openseespy session (wiped first); `region` ``"columns"``
    damps only the columns (the beams and hinges undamped); `gravity` (N/m on the beams) and
    `leaning` (N per floor on a leaning column) are applied by a static analysis and held.
    Returns the element tags by kind."""
    import openseespy.opensees as ops

    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    for line in range(bays + 1):
        for storey in range(storeys + 1):
            ops.node(node(storey, line), line * BAY, storey * H)
            if storey == 0:
                ops.fix(node(storey, line), 1, 1, 1)
            else:
                ops.mass(node(storey, line), M_NODE, M_NODE, 0.0)
    ops.geomTransf("Linear", 1)
    tags: dict[str, list[int]] = {"columns": [], "beams": [], "hinges": []}
    tag = 1
    for line in range(bays + 1):
        for storey in range(storeys):
            ops.element(
                "elasticBeamColumn", tag, node(storey, line), node(storey + 1, line),
                A_COL, E, I_COL, 1,
            )  # fmt: skip
            tags["columns"].append(tag)
            tag += 1
    ops.uniaxialMaterial("Steel01", 1, my, HINGE * 6 * E * I_BEAM / BAY, alpha)
    for storey in range(1, storeys + 1):
        for bay in range(bays):
            for side, line in ((0, bay), (1, bay + 1)):
                end = beam_end(storey, bay, side)
                ops.node(end, line * BAY, storey * H)
                ops.equalDOF(node(storey, line), end, 1, 2)
                extra: list[Any] = ["-doRayleigh", 1] if hinge_rayleigh else []
                ops.element(
                    "zeroLength", 5000 + tag, node(storey, line), end, "-mat", 1, "-dir", 3,
                    *extra,
                )  # fmt: skip
                tags["hinges"].append(5000 + tag)
                tag += 1
            ops.element(
                "elasticBeamColumn", tag, beam_end(storey, bay, 0), beam_end(storey, bay, 1),
                A_BEAM, E, I_BEAM, 1,
            )  # fmt: skip
            tags["beams"].append(tag)
            tag += 1
    if leaning:
        _leaning_column(ops, storeys, bays, tags)
    if rayleigh is not None:
        if region is None:
            ops.rayleigh(*rayleigh)
        else:
            ops.region(1, "-ele", *tags[region], "-rayleigh", *rayleigh)
    if gravity or leaning:
        _gravity(ops, storeys, bays, tags, gravity, leaning)
    return tags


def lean(storey: int) -> int:
    """The leaning column's node at level `storey`."""
    return 900 + storey


def _leaning_column(ops: Any, storeys: int, bays: int, tags: dict[str, list[int]]) -> None:
    """A column one bay beyond the frame, pinned at its base, its rotations held (a stiff
    axial member, no bending to speak of), carried by the floors (ux tied to the frame's
    last line): its vertical load acts through its ``PDelta`` transformation."""
    ops.geomTransf("PDelta", 2)
    x = (bays + 1) * BAY
    for storey in range(storeys + 1):
        ops.node(lean(storey), x, storey * H)
        ops.fix(lean(storey), *((1, 1, 1) if storey == 0 else (0, 0, 1)))
        if storey > 0:
            ops.equalDOF(node(storey, bays), lean(storey), 1)
    tags["leaning"] = []
    for storey in range(storeys):
        ops.element(
            "elasticBeamColumn", 800 + storey, lean(storey), lean(storey + 1), A_COL, E,
            1e-3 * I_COL, 2,
        )  # fmt: skip
        tags["leaning"].append(800 + storey)


def _gravity(
    ops: Any, storeys: int, bays: int, tags: dict[str, list[int]], w: float, p: float
) -> None:
    """The gravity loads by a static analysis (Newton, ten load steps), then held."""
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    for tag in tags["beams"]:
        ops.eleLoad("-ele", tag, "-type", "-beamUniform", -w)
    if p:
        for storey in range(1, storeys + 1):
            ops.load(lean(storey), 0.0, -p, 0.0)
    if not static_steps(ops):
        raise RuntimeError("the gravity analysis failed")
    ops.loadConst("-time", 0.0)
    ops.wipeAnalysis()


def static_steps(ops: Any) -> bool:
    """The static analysis of the loads defined (Newton to a displacement increment of
    1e-12, ten load steps of 0.1); whether it converged."""
    ops.constraints("Transformation")
    ops.numberer("RCM")
    ops.system("BandGeneral")
    ops.test("NormDispIncr", 1e-12, 50)
    ops.algorithm("Newton")
    ops.integrator("LoadControl", 0.1)
    ops.analysis("Static")
    return bool(ops.analyze(10) == 0)


def record(dt: float = 0.01, duration: float = 4.0, pga: float = 4.0) -> tuple[Any, Any]:
    """A smooth synthetic accelerogram (m/s^2): two decaying sines."""
    t = np.arange(0.0, duration + dt / 2, dt)
    env = (t / 1.5) ** 2 * np.exp(2.0 * (1.0 - t / 1.5))
    a = env * (np.sin(2 * np.pi * 0.9 * t) + 0.6 * np.sin(2 * np.pi * 2.7 * t + 0.4))
    return t, pga * a / np.abs(a).max()


def run_opensees(t: Any, a: Any, substeps: int, roof: int, base: list[int]) -> tuple[Any, Any, Any]:
    """The record in the session's model (Newmark, average acceleration, Newton, `substeps`
    steps per record interval): the roof's ux and its acceleration relative to the ground,
    and the base shear (the supports' horizontal reactions from the elements' resisting
    forces), at the record's instants but its last (where OpenSees' record ends within the
    step's substeps)."""
    import openseespy.opensees as ops

    dt = float(t[1] - t[0])
    ops.timeSeries("Path", 2, "-dt", dt, "-values", *a.tolist())
    ops.pattern("UniformExcitation", 2, 1, "-accel", 2)
    ops.constraints("Transformation")
    ops.numberer("RCM")
    ops.system("BandGeneral")
    ops.test("NormDispIncr", 1e-12, 50)
    ops.algorithm("Newton")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")
    x, acc, shear = (np.zeros(t.size - 1) for _ in range(3))
    x[0] = ops.nodeDisp(roof, 1)  # the state at the start (after the gravity analysis)
    for k in range(1, t.size - 1):  # to the record's last but one instant (its end is open)
        if ops.analyze(substeps, dt / substeps) != 0:
            raise RuntimeError(f"OpenSees failed at t = {t[k]}")
        ops.reactions()
        x[k], acc[k] = ops.nodeDisp(roof, 1), ops.nodeAccel(roof, 1)
        shear[k] = -sum(ops.nodeReaction(n, 1) for n in base)
    return x, acc, shear

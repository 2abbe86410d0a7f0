"""A 2-storey, 1-bay portal frame with rotational hinges of each uniaxial material of issue 37
at its beam ends, built in openseespy, gravity first (tests/opensees/test_frame_materials.py).

Columns and beams are ``elasticBeamColumn`` elements (``Linear`` transformation); the floor
masses are lumped at the column nodes (ux, uy), every rotation is massless. Each beam end is
a node of its own, tied to the column node in ux and uy (``equalDOF``), with a rotational
``zeroLength`` hinge (direction 3, no ``-doRayleigh``: OpenSees' default) of the material
between them: the hinge rotations are massless dofs. A leaning column (pinned at its base,
``PDelta``, tied to the floors in ux) carries the gravity load of the floors it stabilises;
Rayleigh damping ``rayleigh(A0, 0, A1, 0)`` (mass and initial stiffness) on every element
but the hinges. Gravity (a uniform load `w` on the beams and a vertical load at the leaning
column's floors) is applied by a static analysis first (ten load steps) and held
(``loadConst``): it gives the leaning column its geometric stiffness and loads the hinges
(by default :data:`W_GRAVITY`, about half their yield moment, elastic but well beyond
round-off in each law's curvature), which ``from_opensees`` imports in that state.

The hinges' laws are written for a yield rotation of 0.02 at a moment of 0.8 (initial
stiffness 40; the frame's units are consistent and otherwise arbitrary), with round
parameters, as ``from_opensees`` reads them printed to six significant digits.
"""

from __future__ import annotations

import os
import tempfile
from typing import Any

import numpy as np
from _hinged import _gravity

from duhamel import elements as E

H, BAY = 1.0, 2.0
EMOD, A_COL, I_COL, A_BEAM, I_BEAM = 1.0e4, 1.0, 4.0e-4, 1.0, 4.0e-3
M_NODE = 0.1
STOREYS = 2
#: gravity: the load at each floor of the leaning column
P_LEANING = 0.6
W1, W2 = 2 * np.pi / 0.7, 2 * np.pi / 0.2  # 3 % at these circular frequencies
A0, A1 = 2 * 0.03 * W1 * W2 / (W1 + W2), 2 * 0.03 / (W1 + W2)

#: gravity: the uniform load on the beams (hinge moments about half the yield moment)
W_GRAVITY = 3.0
K0, FY = 40.0, 0.8  # the hinges: initial stiffness, yield moment (rotation 0.02)
STEEL = ("Steel02", FY, K0, 0.02, 18.0, 0.9, 0.1, 0.01, 1.0, 0.02, 1.0)
IMK = ("ModIMKPeakOriented", K0, 0.03, 0.03, FY, -FY, 2.0, 2.0, 2.0, 2.0, 1.0, 1.0, 1.0, 1.0,
       0.03, 0.03, 0.1, 0.1, 0.4, 0.4, 0.3, 0.3, 1.0, 1.0)  # fmt: skip
BILIN = ("IMKBilin", K0, 0.03, 0.1, 0.3, FY, 1.1, 0.4, 0.03, 0.1, 0.3, FY, 1.1, 0.4,
         2.0, 2.0, 2.0, 1.0, 1.0, 1.0, 1.0, 1.0)  # fmt: skip
HYST = ("Hysteretic", 0.8, 0.02, 1.04, 0.08, 0.48, 0.2, -0.72, -0.02, -0.96, -0.1, -0.4, -0.24,
        0.6, 0.3, 0.01, 0.05, 0.3)  # fmt: skip
P4_POS = (0.8, 0.02, 1.2, 0.06, 1.36, 0.12, 0.32, 0.24)
P4_NEG = (-0.72, -0.02, -1.12, -0.06, -1.28, -0.12, -0.28, -0.24)
P4_REST = (0.5, 0.25, 0.05, 0.5, 0.25, 0.05, 1.0, 0.2, 0.3, 0.2, 0.9, 0.5, 0.5, 2.0, 2.0, 0.5,
           1.0, 0.0, 1.0, 1.0, 0.9, 10.0, "energy")  # fmt: skip
P4 = ("Pinching4", *P4_POS, *P4_NEG, *P4_REST)
ELASTIC = ("ElasticMultiLinear", "-strain", -0.5, -0.02, 0.0, 0.02, 0.5,
           "-stress", -1.2, -0.8, 0.0, 0.8, 1.2)  # fmt: skip
MULTI = ("MultiLinear", 0.02, 0.8, 0.06, 0.96, 0.16, 1.04)
#: Takeda's backbone (duhamel) and OpenSees' Hysteretic without pinching or damage
TAKEDA = {"strain": [0.02, 0.06, 0.3], "stress": [0.8, 1.0, 1.1], "alpha": 0.4}
TAKEDA_HYST = ("Hysteretic", 0.8, 0.02, 1.0, 0.06, 1.1, 0.3, -0.8, -0.02, -1.0, -0.06, -1.1,
               -0.3, 1.0, 1.0, 0.0, 0.0, 0.4)  # fmt: skip
STIFF = ("ElasticMultiLinear", "-strain", -1.0, 0.0, 1.0, "-stress", -200.0, 0.0, 200.0)

#: material -> OpenSees' definitions of one hinge (the last one the hinge's, the earlier
#: ones its parts, tagged from 1 in order)
DEFINITIONS: dict[str, list[tuple[Any, ...]]] = {
    "Steel02": [STEEL],
    "ModIMKPeakOriented": [IMK],
    "IMKBilin": [BILIN],
    "Hysteretic": [HYST],
    "Pinching4": [P4],
    "ElasticMultiLinear": [ELASTIC],
    "MultiLinear": [MULTI],
    "Takeda": [TAKEDA_HYST],
    "MinMax": [STEEL, ("MinMax", 1, "-min", -0.06, "-max", 0.06)],
    "Parallel": [STEEL, ELASTIC, ("Parallel", 1, 2, "-factors", 0.75, 0.5)],
    "Series": [STIFF, ("Steel02", FY, 50.0, *STEEL[3:]), ("Series", 1, 2)],
}


def hinge(kind: str, i: int | None, j: int | None, initial_deformation: float = 0.0) -> E.Element:
    """duhamel's hinge of the material `kind` on ``x_i - x_j`` (starting at
    `initial_deformation`), built directly from the parameters of :data:`DEFINITIONS`
    (Takeda: no OpenSees counterpart)."""
    if kind == "Takeda":
        return E.Takeda(i, j, **TAKEDA, initial_deformation=initial_deformation)  # type: ignore[arg-type]
    raise ValueError(f"`kind` {kind!r} is imported, not built")


#: Materials ``from_opensees`` cannot read back: Takeda has no OpenSees counterpart (its
#: OpenSees model is a Hysteretic without pinching or damage): the frame is imported with
#: that Hysteretic, whose elements are then replaced by duhamel's material built directly
#: on the same dofs, at the same initial deformation. (Pinching4 and
#: MultiLinear, which OpenSees prints without their parameters, are imported through
#: ``duhamel.opensees.recording``.)
BUILT = ("Takeda",)


def node(storey: int, line: int) -> int:
    """The column node of `line` (0, 1) at level `storey` (0: the fixed base)."""
    return 100 * (storey + 1) + line + 1


def beam_end(storey: int, side: int) -> int:
    return 1000 + 10 * storey + side


def lean(storey: int) -> int:
    """The leaning column's node at level `storey` (_hinged's numbering, its gravity)."""
    return 900 + storey


def build(
    definitions: list[tuple[Any, ...]],
    chain: bool = False,
    w: float = W_GRAVITY,
    hinge_rayleigh: bool = False,
) -> list[int]:
    """Defines the frame in the openseespy session (wiped first) with hinges of the material
    `definitions`, runs the gravity analysis (`w` on the beams) and holds it; returns the
    hinges' tags; `hinge_rayleigh`: the hinges damped too (``-doRayleigh 1``). With
    `chain`, a ``Series`` hinge is built as its parts in a chain of rotational ``zeroLength``
    elements through a node of its own (a massless rotation): OpenSees' Newton then
    balances the parts' forces exactly, where its ``SeriesMaterial`` iterates internally."""
    import openseespy.opensees as ops

    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    for line in (0, 1):
        for storey in range(STOREYS + 1):
            ops.node(node(storey, line), line * BAY, storey * H)
            if storey == 0:
                ops.fix(node(storey, line), 1, 1, 1)
            else:
                ops.mass(node(storey, line), M_NODE, M_NODE, 0.0)
    for tag, (kind, *args) in enumerate(definitions, start=1):
        ops.uniaxialMaterial(kind, tag, *args)
    mat = len(definitions)
    ops.geomTransf("Linear", 1)
    ops.geomTransf("PDelta", 2)
    hinges = []
    for line in (0, 1):
        for storey in range(STOREYS):
            ops.element(
                "elasticBeamColumn", 10 * line + storey + 1, node(storey, line),
                node(storey + 1, line), A_COL, EMOD, I_COL, 1,
            )  # fmt: skip
    for storey in range(1, STOREYS + 1):
        for side in (0, 1):
            end = beam_end(storey, side)
            ops.node(end, side * BAY, storey * H)
            ops.equalDOF(node(storey, side), end, 1, 2)
            tag = 500 + 10 * storey + side
            if chain:
                first, second = definitions[-1][1:3]
                mid = 2000 + 10 * storey + side
                ops.node(mid, side * BAY, storey * H)
                ops.equalDOF(node(storey, side), mid, 1, 2)
                ops.element("zeroLength", tag, node(storey, side), mid, "-mat", first, "-dir", 3)
                ops.element("zeroLength", tag + 100, mid, end, "-mat", second, "-dir", 3)
            else:
                damped = ["-doRayleigh", 1] if hinge_rayleigh else []
                ops.element(
                    "zeroLength", tag, node(storey, side), end, "-mat", mat, "-dir", 3, *damped
                )
            hinges.append(tag)
        ops.element(
            "elasticBeamColumn", 200 + storey, beam_end(storey, 0), beam_end(storey, 1),
            A_BEAM, EMOD, I_BEAM, 1,
        )  # fmt: skip
    for storey in range(STOREYS + 1):  # the leaning column, one bay beyond the frame
        ops.node(lean(storey), 2 * BAY, storey * H)
        ops.fix(lean(storey), *((1, 1, 1) if storey == 0 else (0, 0, 1)))
        if storey > 0:
            ops.equalDOF(node(storey, 1), lean(storey), 1)
    for storey in range(STOREYS):
        ops.element(
            "elasticBeamColumn", 800 + storey, lean(storey), lean(storey + 1), A_COL, EMOD,
            1e-3 * I_COL, 2,
        )  # fmt: skip
    ops.rayleigh(A0, 0.0, A1, 0.0)
    # the beams' load and the vertical loads at the leaning column's floors (900 + storey,
    # as _hinged's), by a static analysis (Newton, ten load steps), then held
    _gravity(ops, STOREYS, 1, {"beams": [200 + s for s in range(1, STOREYS + 1)]}, w, P_LEANING)
    return hinges


def record(dt: float = 0.01, duration: float = 5.0, pga: float = 6.0) -> tuple[Any, Any]:
    """A smooth synthetic accelerogram: two decaying sines (the frame's units per s^2)."""
    t = np.arange(0.0, duration + dt / 2, dt)
    env = (t / 1.5) ** 2 * np.exp(2.0 * (1.0 - t / 1.5))
    a = env * (np.sin(2 * np.pi * 1.2 * t) + 0.6 * np.sin(2 * np.pi * 3.1 * t + 0.4))
    return t, pga * a / np.abs(a).max()


def run_opensees(t: Any, a: Any, substeps: int) -> tuple[Any, Any]:
    """The record in the session's model (Newmark average acceleration, `substeps` steps per
    record interval): the record's instants but the last and the roof's ux there.

    Krylov-Newton to a displacement increment of 1e-11: OpenSees' ModIMKPeakOriented puts
    its stiffness tangent into the damping part of OpenSees' Newton matrix (``2/h`` times
    it, no damping force behind it), which shrinks the increments, so that a displacement
    increment of 1e-8 passes with the step unconverged (2.5e-3 of the peak off); plain
    Newton cycles on it from the elastic range on."""
    import openseespy.opensees as ops

    dt = float(t[1] - t[0])
    path = os.path.join(tempfile.mkdtemp(), "roof.out")
    ops.timeSeries("Path", 2, "-dt", dt, "-values", *a.tolist())
    ops.pattern("UniformExcitation", 2, 1, "-accel", 2)
    ops.constraints("Transformation")
    ops.numberer("RCM")
    ops.system("BandGeneral")
    ops.test("NormDispIncr", 1e-11, 200)
    ops.algorithm("KrylovNewton")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")
    roof = node(STOREYS, 0)
    ops.recorder("Node", "-file", path, "-time", "-node", roof, "-dof", 1, "disp")
    x0 = ops.nodeDisp(roof, 1)
    h = dt / substeps
    for k in range(1, t.size - 1):  # to the record's last but one instant (its end is open)
        if ops.analyze(substeps, h) != 0:
            raise RuntimeError(f"OpenSees failed before t = {t[k]}")
    ops.remove("recorders")
    out = np.loadtxt(path)
    x = np.concatenate([[x0], out[substeps - 1 :: substeps, 1]])
    return t[: x.size], x

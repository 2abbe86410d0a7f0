"""A 2-D steel moment frame on isolators, built in OpenSees and run in duhamel.

The frame (3 storeys of 3 m, 2 bays of 6 m; elastic beam-columns; floor masses lumped at the
nodes, tied per floor by ``equalDOF`` in ux) stands on three isolators: ``zeroLength``
elements with ``Steel01`` (the bilinear isolators, yield 4 % of their weight) and a
``flatSliderBearing`` (Coulomb friction 5 %) under the middle column.
Gravity is applied in OpenSees first (a static analysis), so the imported stiffness is the
tangent at the displaced state and the slider's friction is ``mu N`` with its axial load.

``duhamel.opensees.from_opensees()`` then reads the model: ``M``, ``C`` (the frame's
Rayleigh damping) and ``K``, the dof labels ``(node, "ux")``..., and the isolators as
duhamel ``Bilinear`` elements. The same record is run in OpenSees (Newmark, average
acceleration, at a fine step: converged) and in duhamel (``Semianalytic``); the script
prints the periods of both, the peak isolator and roof displacements, and the times.

Usage::

    python examples/opensees_frame.py

Needs openseespy (``pip install 'duhamel[opensees]'``).
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np

import duhamel

#: The gravity of the OpenSees model's loads (its isolators' strength is 4 % of a weight):
#: 9.81, not duhamel.STANDARD_GRAVITY, because from_opensees reads the materials from
#: OpenSees' printout, which keeps six significant digits, and this round weight keeps the
#: imported Steel01 exact (with 9.80665 its E = 13729310 N/m reads as 13729300).
G = 9.81
H, BAY, STOREYS, BAYS = 3.0, 6.0, 3, 2
M_NODE, M_BASE = 2.0e4, 1.0e4  # kg at each floor node, at each base node
#: Rotational inertia of every node (kg m^2); 0 makes the rotations massless.
ROT_INERTIA = 0.0
E_STEEL, A_COL, I_COL, A_BEAM, I_BEAM = 2.0e11, 1.2e-2, 3.0e-4, 1.0e-2, 4.0e-4
MU, K_SLIDER, ALPHA_ISO = 0.05, 5.0e7, 0.08
ZETA, T_DAMP = 0.03, (0.5, 0.1)  # frame Rayleigh damping: 3 % at these two periods


def node_tag(storey: int, line: int) -> int:
    """The node of column line `line` at level `storey` (0: the base, above the isolators)."""
    return 100 * (storey + 1) + line + 1


def ground_tag(line: int) -> int:
    return line + 1


def build(
    *,
    isolated: bool = True,
    gravity: bool = True,
    damping: bool = True,
    storeys: int = STOREYS,
    bays: int = BAYS,
    transformation: str = "Linear",
) -> None:
    """Defines the frame in the openseespy session (wiped first); ``transformation="PDelta"``
    gives the columns their geometric stiffness under the gravity load."""
    import openseespy.opensees as ops

    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    lines = bays + 1
    for line in range(lines):
        for storey in range(storeys + 1):
            ops.node(node_tag(storey, line), line * BAY, storey * H)
            m = M_BASE if storey == 0 else M_NODE
            ops.mass(node_tag(storey, line), m, m, ROT_INERTIA)
        if isolated:
            ops.node(ground_tag(line), line * BAY, 0.0)
            ops.fix(ground_tag(line), 1, 1, 1)
        else:
            ops.fix(node_tag(0, line), 1, 1, 1)
    ops.geomTransf(transformation, 1)
    tag = 1
    for line in range(lines):
        for storey in range(storeys):
            ops.element(
                "elasticBeamColumn",
                tag,
                node_tag(storey, line),
                node_tag(storey + 1, line),
                A_COL,
                E_STEEL,
                I_COL,
                1,
            )
            tag += 1
    for storey in range(0 if isolated else 1, storeys + 1):
        for line in range(bays):
            ops.element(
                "elasticBeamColumn",
                tag,
                node_tag(storey, line),
                node_tag(storey, line + 1),
                A_BEAM,
                E_STEEL,
                I_BEAM,
                1,
            )
            tag += 1
        for line in range(1, lines):  # rigid floors in their plane
            ops.equalDOF(node_tag(storey, 0), node_tag(storey, line), 1)
    if damping:
        w1, w2 = (2 * np.pi / t for t in T_DAMP)
        a0, a1 = 2 * ZETA * w1 * w2 / (w1 + w2), 2 * ZETA / (w1 + w2)
        ops.rayleigh(a0, a1, 0.0, 0.0)  # on the frame: the isolators take no Rayleigh part
    if isolated:
        ops.uniaxialMaterial("Elastic", 900, 1.0e11)  # vertical and rotational restraint
        w = (M_BASE + storeys * M_NODE) * G  # the weight on one isolator
        ops.uniaxialMaterial("Steel01", 901, 0.04 * w, 0.04 * w / 0.002, ALPHA_ISO)
        ops.frictionModel("Coulomb", 1, MU)
        for line in range(lines):
            if line == bays // 2:  # the slider under the middle column
                ops.element(
                    "flatSliderBearing",
                    950,
                    ground_tag(line),
                    node_tag(0, line),
                    1,
                    K_SLIDER,
                    "-P",
                    900,
                    "-Mz",
                    900,
                    "-orient",
                    0,
                    1,
                    0,
                    -1,
                    0,
                    0,
                )
            else:
                ops.element(
                    "zeroLength",
                    900 + line,
                    ground_tag(line),
                    node_tag(0, line),
                    "-mat",
                    901,
                    900,
                    900,
                    "-dir",
                    1,
                    2,
                    3,
                )
    if gravity:
        ops.timeSeries("Constant", 1)
        ops.pattern("Plain", 1, 1)
        for line in range(lines):
            for storey in range(storeys + 1):
                m = M_BASE if storey == 0 else M_NODE
                ops.load(node_tag(storey, line), 0.0, -m * G, 0.0)
        ops.constraints("Transformation")
        ops.numberer("RCM")
        ops.system("BandGeneral")
        ops.test("NormDispIncr", 1e-12, 20)
        ops.algorithm("Newton")
        ops.integrator("LoadControl", 1.0)
        ops.analysis("Static")
        if ops.analyze(1) != 0:
            raise RuntimeError("gravity analysis failed")
        ops.loadConst("-time", 0.0)
        ops.wipeAnalysis()


def record(dt: float = 0.01, duration: float = 8.0, pga: float = 3.0) -> tuple[Any, Any]:
    """A smooth synthetic accelerogram (m/s^2): two decaying sines."""
    t = np.arange(0.0, duration + dt / 2, dt)
    env = (t / 1.5) ** 2 * np.exp(2.0 * (1.0 - t / 1.5))
    a = env * (np.sin(2 * np.pi * 0.9 * t) + 0.6 * np.sin(2 * np.pi * 2.7 * t + 0.4))
    return t, pga * a / np.abs(a).max()


def run_opensees(t: Any, a: Any, substeps: int, watch: list[tuple[int, int]]) -> Any:
    """Runs the record in the session's model (Newmark, average acceleration, `substeps`
    steps per record interval); returns the displacements of the ``(node, dof)`` pairs of
    `watch` (dof from 1) at the record's instants, shape ``(len(t), len(watch))``."""
    import openseespy.opensees as ops

    dt = float(t[1] - t[0])
    ops.timeSeries("Path", 2, "-dt", dt, "-values", *a.tolist(), "-factor", 1.0)
    ops.pattern("UniformExcitation", 2, 1, "-accel", 2)
    ops.constraints("Transformation")
    ops.numberer("RCM")
    ops.system("BandGeneral")
    ops.test("NormDispIncr", 1e-12, 50)
    ops.algorithm("Newton")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")
    out = np.zeros((t.size, len(watch)))
    for k in range(1, t.size):
        if ops.analyze(substeps, dt / substeps) != 0:
            raise RuntimeError(f"OpenSees failed at t = {t[k]}")
        out[k] = [ops.nodeDisp(n, d) for n, d in watch]
    return out


def main() -> None:
    import openseespy.opensees as ops

    build()
    t, a = record()
    start = time.perf_counter()
    frame = duhamel.opensees.from_opensees()
    frame.add_load(duhamel.loads.BaseAcceleration("ux", t=t, values=a))
    sol = duhamel.solve(frame, duhamel.Semianalytic(), t_end=float(t[-1]), dt=0.005, save_every=2)
    t_duhamel = time.perf_counter() - start
    n_modes = 3
    lam = np.array(ops.eigen("-fullGenLapack", n_modes))
    print(f"{frame}, labels {frame.dof_labels[:3]}...")
    print("elements:", {tag: type(e[0]).__name__ for tag, e in frame.opensees.elements.items()})
    base, roof = node_tag(0, 0), node_tag(STOREYS, 0)
    start = time.perf_counter()
    ref = run_opensees(t, a, 20, [(base, 1), (roof, 1)])
    t_opensees = time.perf_counter() - start
    ours = sol.x[:, [frame.dof(base, "ux"), frame.dof(roof, "ux")]]
    print("OpenSees periods (tangent, s):", np.round(2 * np.pi / np.sqrt(lam), 4).tolist())
    for name, k in (("isolator", 0), ("roof", 1)):
        print(
            f"peak {name} displacement: duhamel {np.abs(ours[:, k]).max():.4f} m, "
            f"OpenSees {np.abs(ref[:, k]).max():.4f} m"
        )
    err = np.abs(ours - ref).max() / np.abs(ref).max()
    print(
        f"largest difference {err:.2e} of the peak; duhamel {t_duhamel:.2f} s "
        f"(import included), OpenSees {t_opensees:.2f} s"
    )


if __name__ == "__main__":
    main()

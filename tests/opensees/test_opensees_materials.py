"""``from_opensees`` with the uniaxial materials of issue 37 in ``zeroLength`` elements
(python/duhamel/opensees/_materials.py): each translated to duhamel's element of the same
name, the imported SDOF (Rayleigh damping on the mass and the initial stiffness, the
element defined with ``-doRayleigh 1``) run under a record and compared with OpenSees' own
transient of the same model at the same step (both DT / 16): to 1e-4 of the peak (the
acceptance asks 0.5 %). The parameters are round (OpenSees prints them to 6 significant
digits, which is what the import reads). Materials OpenSees prints without their parameters
are refused, naming the element and the material."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from _materials_system import (
    BILIN_ORDER,
    DT,
    HYST_ORDER,
    IMK_ORDER,
    SECONDS,
    newmark_transient,
    record,
)

import duhamel
from duhamel import elements as E

try:  # the wheel needs the system BLAS/LAPACK (libblas3, liblapack3)
    import openseespy.opensees as ops
except Exception as exc:  # pragma: no cover - depends on the machine
    pytest.skip(reason=f"openseespy cannot be loaded: {exc}", allow_module_level=True)

K0, FY = 40.0, 0.8  # mass 1: T = 0.99 s, yield at 0.02
A0, A1 = 0.3, 0.008

IMK = dict(zip(IMK_ORDER, [
    K0, 0.03, 0.03, FY, -FY, 2.0, 2.0, 2.0, 2.0, 1.0, 1.0, 1.0, 1.0,
    0.03, 0.03, 0.1, 0.1, 0.4, 0.4, 0.3, 0.3, 1.0, 1.0,
], strict=True))  # fmt: skip
BILIN = dict(zip(BILIN_ORDER, [
    K0, 0.03, 0.1, 0.3, FY, 1.1, 0.4, 0.03, 0.1, 0.3, FY, 1.1, 0.4,
    2.0, 2.0, 2.0, 1.0, 1.0, 1.0, 1.0, 1.0,
], strict=True))  # fmt: skip
HYST = dict(zip(HYST_ORDER, [
    0.8, 0.02, 1.04, 0.08, 0.48, 0.2, -0.72, -0.02, -0.96, -0.1, -0.4, -0.24,
    0.6, 0.3, 0.01, 0.05, 0.3,
], strict=True))  # fmt: skip
STEEL = (FY, K0, 0.02, 18.0, 0.9, 0.1, 0.01, 1.0, 0.02, 1.0)
SPRING = ("ElasticMultiLinear", "-strain", -0.5, -0.02, 0.0, 0.02, 0.5)
SPRING += ("-stress", -0.6, -0.2, 0.0, 0.2, 0.6)

STIFF = ("ElasticMultiLinear", "-strain", -1.0, 0.0, 1.0, "-stress", -200.0, 0.0, 200.0)
P4_ENVELOPE = (0.2, 0.01, 0.4, 0.02, 0.5, 0.04, 0.1, 0.08)

#: name -> (OpenSees' material definitions, the last one the element's; duhamel's class)
CASES: dict[str, tuple[list[tuple[Any, ...]], type]] = {
    "Steel02": ([("Steel02", *STEEL)], E.Steel02),
    "ModIMKPeakOriented": ([("ModIMKPeakOriented", *IMK.values())], E.ModIMKPeakOriented),
    "IMKBilin": ([("IMKBilin", *BILIN.values())], E.IMKBilin),
    "Hysteretic": ([("Hysteretic", *HYST.values())], E.Hysteretic),
    "MinMax": ([("Steel02", *STEEL), ("MinMax", 1, "-min", -0.06, "-max", 0.06)], E.MinMax),
    "Parallel": (
        [("Steel02", *STEEL), SPRING, ("Parallel", 1, 2, "-factors", 0.75, 0.5)],
        E.Parallel,
    ),
    # a stiff connection in series with a Steel02 (OpenSees' SeriesMaterial converges
    # within its transient's Newton iterations)
    "Series": ([STIFF, ("Steel02", FY, 50.0, *STEEL[2:]), ("Series", 1, 2)], E.Series),
}


def build(definitions: list[tuple[Any, ...]], fixed_first: bool = True) -> None:
    ops.wipe()
    ops.model("basic", "-ndm", 1, "-ndf", 1)
    ops.node(1, 0.0)
    ops.node(2, 0.0)
    ops.fix(1, 1)
    ops.mass(2, 1.0)
    for tag, (kind, *args) in enumerate(definitions, start=1):
        ops.uniaxialMaterial(kind, tag, *args)
    nodes = (1, 2) if fixed_first else (2, 1)
    ops.element("zeroLength", 1, *nodes, "-mat", len(definitions), "-dir", 1, "-doRayleigh", 1)
    ops.rayleigh(A0, 0.0, A1, 0.0)


def opensees_run(a: np.ndarray, k: int) -> np.ndarray:
    import os
    import tempfile

    path = os.path.join(tempfile.mkdtemp(), "disp.out")
    recorders = [("Node", "-file", path, "-node", 2, "-dof", 1, "disp")]
    assert newmark_transient(ops, a, DT, k, recorders), "OpenSees' transient did not converge"
    x = np.loadtxt(path).reshape(-1)
    return np.concatenate([[0.0], x[k - 1 :: k]])[: a.size]


@pytest.mark.parametrize("case", list(CASES))
def test_imported_material_runs_as_opensees(case: str) -> None:
    definitions, cls = CASES[case]
    t, a = record()
    build(definitions)
    s = duhamel.opensees.from_opensees(rayleigh=(A0, 0.0, A1, 0.0))
    (element,) = s.opensees.elements[1]
    assert type(element) is cls
    assert s.K[0, 0] == 0.0  # its stiffness is the element's, not the matrix's
    s.add_load(duhamel.loads.BaseAcceleration(np.ones(1), t=t, values=a))
    ours = duhamel.solve(s, duhamel.Semianalytic(), t_end=SECONDS, dt=DT / 16, save_every=16)
    build(definitions)
    theirs = opensees_run(a, 16)
    peak = np.abs(theirs).max()
    assert peak > 0.05, "the record should take the material well past yield (0.02)"
    err = np.abs(ours.x[:, 0] - theirs).max() / peak
    assert err <= 1e-4, f"{case}: {err:.2e} of the peak from OpenSees"


@pytest.mark.parametrize(
    ("definitions", "message"),
    [
        (
            [
                (
                    "Pinching4",
                    *P4_ENVELOPE,
                    *(-v for v in P4_ENVELOPE),
                    0.5,
                    0.25,
                    0.05,
                    0.5,
                    0.25,
                    0.05,
                    *([0.0] * 15),
                    10.0,
                    "energy",
                )
            ],
            r"element 1 \(ZeroLength\): Pinching4Material material 1: OpenSees prints none",
        ),
        (
            [("MultiLinear", 0.02, 0.8, 0.06, 1.0)],
            r"element 1 \(ZeroLength\): its material is printed with tag 0",
        ),
        (
            [
                (
                    "IMKPeakOriented",
                    K0,
                    0.03,
                    0.1,
                    0.3,
                    FY,
                    1.1,
                    0.4,
                    0.03,
                    0.1,
                    0.3,
                    FY,
                    1.1,
                    0.4,
                    2.0,
                    2.0,
                    2.0,
                    2.0,
                    1.0,
                    1.0,
                    1.0,
                    1.0,
                    1.0,
                    1.0,
                )
            ],
            r"IMKPeakOriented material 1 \(IMKPeakOriented: no duhamel counterpart\)",
        ),
    ],
    ids=["Pinching4", "MultiLinear", "IMKPeakOriented"],
)
def test_untranslatable_materials_are_refused_by_name(
    definitions: list[tuple[Any, ...]], message: str
) -> None:
    build(definitions)
    with pytest.raises(ValueError, match=message):
        duhamel.opensees.from_opensees(rayleigh=(A0, 0.0, A1, 0.0))


def test_an_asymmetric_law_towards_the_fixed_node_is_refused_a_symmetric_one_mirrored() -> None:
    build([("Steel02", *STEEL)], fixed_first=False)
    with pytest.raises(ValueError, match="Steel02 material 1 with its positive deformation"):
        duhamel.opensees.from_opensees(rayleigh=(A0, 0.0, A1, 0.0))
    t, a = record()
    build([SPRING], fixed_first=False)
    s = duhamel.opensees.from_opensees(rayleigh=(A0, 0.0, A1, 0.0))
    s.add_load(duhamel.loads.BaseAcceleration(np.ones(1), t=t, values=a))
    ours = duhamel.solve(s, duhamel.Semianalytic(), t_end=SECONDS, dt=DT / 16, save_every=16)
    build([SPRING], fixed_first=False)
    theirs = opensees_run(a, 16)
    assert np.abs(ours.x[:, 0] - theirs).max() <= 1e-4 * np.abs(theirs).max()

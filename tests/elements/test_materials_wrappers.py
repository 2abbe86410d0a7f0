"""MinMax, Parallel and Series (issue 37) against OpenSees, through the three histories, to
1e-8 of the largest force.

* ``MinMax`` and ``Parallel``: OpenSees' materials of the same name driven by ``setStrain``
  (MinMax past its limits in every history).
* ``Series``: OpenSees' ``SeriesMaterial`` under ``setStrain`` does not reach the series
  solution (it corrects its force once per strain, docs/materials.md; shown below), so the
  reference is OpenSees' own series: the same materials in a chain of ``zeroLength``
  elements, the end node's displacement prescribed, the equilibrium of the inner nodes
  solved to an unbalance of 1e-11.
"""

from __future__ import annotations

from types import ModuleType

import numpy as np
import pytest
from _materials import assert_matches, drive, element, histories, opensees, opensees_drive

from duhamel import elements

HISTORIES = ["cyclic", "random", "small after large"]

# the parts, as (duhamel's dict, OpenSees' arguments after the tag)
STEEL = ({"kind": "Steel02", "fy": 100.0, "E": 1.0e4, "b": 0.02}, ("Steel02", 100.0, 1.0e4, 0.02))
MULTI = (
    {"kind": "MultiLinear", "strain": [0.008, 0.03, 0.1], "stress": [120.0, 150.0, 170.0]},
    ("MultiLinear", 0.008, 120.0, 0.03, 150.0, 0.1, 170.0),
)
SPRING = (
    {"kind": "ElasticMultiLinear", "strain": [-1.0, 0.0, 1.0], "stress": [-3.0e4, 0.0, 3.0e4]},
    ("ElasticMultiLinear", "-strain", -1.0, 0.0, 1.0, "-stress", -3.0e4, 0.0, 3.0e4),
)


def define_all(ops: ModuleType, parts: list[tuple[str, ...]], first_tag: int) -> list[int]:
    tags = []
    for k, args in enumerate(parts):
        ops.uniaxialMaterial(args[0], first_tag + k, *args[1:])
        tags.append(first_tag + k)
    return tags


@pytest.mark.parametrize("history", HISTORIES)
@pytest.mark.parametrize("inner", ["Steel02", "MultiLinear"])
def test_minmax_equals_opensees(history: str, inner: str) -> None:
    ops = opensees()
    uy = 0.01
    u = histories(uy)[history]
    part = STEEL if inner == "Steel02" else MULTI
    lo, hi = -9.0 * uy, 11.0 * uy

    def define(ops):
        define_all(ops, [part[1]], 10)
        ops.uniaxialMaterial("MinMax", 1, 10, "-min", lo, "-max", hi)
        return 1

    ours = drive("MinMax", {"material": part[0], "min": lo, "max": hi}, u)
    assert np.any((u <= lo) | (u >= hi)), "the history goes past a limit"
    assert ours[0][-1] == 0.0
    assert_matches(ours, opensees_drive(ops, define, u), f"MinMax({inner})")


@pytest.mark.parametrize("history", HISTORIES)
@pytest.mark.parametrize("factors", [None, [1.5, 0.5, -0.2]])
def test_parallel_equals_opensees(history: str, factors: list[float] | None) -> None:
    ops = opensees()
    u = histories(0.01)[history]
    parts = [STEEL, MULTI, SPRING]

    def define(ops):
        tags = define_all(ops, [p[1] for p in parts], 10)
        extra = ["-factors", *factors] if factors else []
        ops.uniaxialMaterial("Parallel", 1, *tags, *extra)
        return 1

    ours = drive("Parallel", {"materials": [p[0] for p in parts], "factors": factors}, u)
    assert_matches(ours, opensees_drive(ops, define, u), f"Parallel factors {factors}")


def opensees_chain(
    ops: ModuleType, parts: list[list[tuple[str, ...]]], u: np.ndarray
) -> np.ndarray:
    """The force of OpenSees' zeroLength elements in a row carrying the materials that
    ``parts`` define (each a list of definitions, the last one the element's material), the
    last node's displacement prescribed to each point of ``u``, solved (Krylov-accelerated
    Newton) to an unbalance of 1e-11; a step that does not converge fails the test."""
    ops.wipe()
    ops.model("basic", "-ndm", 1, "-ndf", 1)
    n = len(parts)
    for k in range(n + 1):
        ops.node(k + 1, 0.0)
    ops.fix(1, 1)
    for k, definitions in enumerate(parts):
        tags = define_all(ops, definitions, 100 * (k + 1))
        ops.element("zeroLength", k + 1, k + 1, k + 2, "-mat", tags[-1], "-dir", 1)
    ops.timeSeries("Path", 1, "-time", *range(u.size + 1), "-values", 0.0, *u)
    ops.pattern("Plain", 1, 1)
    ops.sp(n + 1, 1, 1.0)
    ops.constraints("Transformation")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    ops.test("NormUnbalance", 1e-11, 500)
    ops.algorithm("KrylovNewton")  # plain Newton cycles between the MultiLinear's segments
    ops.integrator("LoadControl", 1.0)
    ops.analysis("Static")
    force = np.empty(u.size)
    for k in range(u.size):
        assert ops.analyze(1) == 0, f"OpenSees' chain did not converge at point {k}"
        force[k] = ops.eleResponse(1, "force")[1]
    ops.wipe()
    return force


SERIES_CASES = {
    "spring, steel, multilinear": [SPRING, STEEL, MULTI],
    "spring, parallel(steel, minmax(multilinear))": [
        SPRING,
        (
            {
                "kind": "Parallel",
                "materials": [STEEL[0], {"kind": "MinMax", "material": MULTI[0], "max": 0.12}],
            },
            None,
        ),
    ],
}


def series_parts_opensees(case: str) -> list[list[tuple[str, ...]]]:
    if case == "spring, steel, multilinear":
        return [[SPRING[1]], [STEEL[1]], [MULTI[1]]]
    # tags 200.. for the second element: 200 steel, 201 multilinear, 202 minmax, 203 parallel
    return [
        [SPRING[1]],
        [STEEL[1], MULTI[1], ("MinMax", 201, "-max", 0.12), ("Parallel", 200, 202)],
    ]


@pytest.mark.parametrize("history", HISTORIES)
@pytest.mark.parametrize("case", list(SERIES_CASES))
def test_series_equals_opensees_zero_length_chain(history: str, case: str) -> None:
    ops = opensees()
    u = histories(0.02)[history]
    ours = drive("Series", {"materials": [p[0] for p in SERIES_CASES[case]]}, u)
    theirs = opensees_chain(ops, series_parts_opensees(case), u)
    assert_matches(ours, (theirs, ours[1]), f"Series({case})", tangent=False)


def test_opensees_series_material_lags_the_series_solution() -> None:
    """The deliberate difference: OpenSees' SeriesMaterial under setStrain is off the
    converged series force (by 1e-5 to 1e-4 of the peak here, default and with -iter)."""
    ops = opensees()
    u = histories(0.02)["cyclic"][:300]
    parts = [SPRING, STEEL]
    chain = opensees_chain(ops, [[p[1]] for p in parts], u)
    ours, _ = drive("Series", {"materials": [p[0] for p in parts]}, u)
    np.testing.assert_allclose(ours, chain, rtol=0, atol=1e-8 * np.abs(chain).max())
    for extra in ([], ["-iter", 50, 1e-12]):

        def define(ops, extra=extra):
            tags = define_all(ops, [p[1] for p in parts], 10)
            ops.uniaxialMaterial("Series", 1, *tags, *extra)
            return 1

        lagging, _ = opensees_drive(ops, define, u)
        assert np.abs(lagging - chain).max() > 1e-6 * np.abs(chain).max()


def test_composite_input_is_checked() -> None:
    u = np.array([0.01])
    steel, spring = element(*kind_params(STEEL[0])), element(*kind_params(SPRING[0]))
    bilinear = elements.Bilinear(0, k=1.0, fy=1.0, alpha=0.0)
    with pytest.raises(ValueError, match=r"`materials` entry 1 must be a uniaxial material"):
        elements.Series(0, materials=[spring, bilinear])
    with pytest.raises(ValueError, match="`materials` must hold at least one material"):
        elements.Parallel(0, materials=[])
    with pytest.raises(TypeError, match=r"`materials\[1\]`"):
        elements.Parallel(0, materials=[steel, 1.0])
    with pytest.raises(ValueError, match=r"`materials\[0\]` acts on i=0, the Series on i=1"):
        elements.Series(1, materials=[spring])
    with pytest.raises(ValueError, match="`factors` has length 1"):
        drive("Parallel", {"materials": [STEEL[0], SPRING[0]], "factors": [1.0]}, u)
    with pytest.raises(ValueError, match="`max`"):
        drive("MinMax", {"material": STEEL[0], "min": 0.1, "max": -0.1}, u)
    with pytest.raises(ValueError, match="`tol`"):
        drive("Series", {"materials": [SPRING[0]], "tol": 2.0}, u)
    with pytest.raises(RuntimeError, match="did not converge"):
        drive("Series", {"materials": [SPRING[0], STEEL[0]], "max_iter": 1}, np.array([0.05]))


def kind_params(part: dict[str, object]) -> tuple[str, dict[str, object]]:
    """A part's ``"kind"`` and its parameters."""
    return str(part["kind"]), {k: v for k, v in part.items() if k != "kind"}

"""The multi-point constraints and matrices from_opensees reads, against what OpenSees
prints and forms: the constraints read through openseespy's queries (identity matrices,
without the text printout) tie the same dofs with the same matrices as the printout says,
for every constraint command; the ones the queries cannot say are read from the printout;
the three matrices formed on one analysis equal those of an analysis each; the JSON
printout read in memory equals the one read through a temporary file."""

from __future__ import annotations

import numpy as np
import pytest

try:  # the wheel needs the system BLAS/LAPACK (libblas3, liblapack3)
    import openseespy.opensees as ops
except Exception as exc:  # pragma: no cover - depends on the machine
    pytest.skip(reason=f"openseespy cannot be loaded: {exc}", allow_module_level=True)

from duhamel.opensees import _constraints
from duhamel.opensees._read import matrices, quiet

XYZ = {1: (0.0, 0.0, 0.0), 2: (1.5, 2.25, 0.75), 3: (0.3, -1.1, 0.0), 4: (2.0, 0.5, 0.0)}


def _model(ndm: int, ndf: int, commands: str) -> None:
    ops.wipe()
    ops.model("basic", "-ndm", ndm, "-ndf", ndf)
    for node, xyz in XYZ.items():
        ops.node(node, *xyz[:ndm])
    with quiet():
        exec(commands)


def _merged(printed: list) -> dict:
    """The printed constraints by pair of nodes, those of one pair one after the other (as
    openseespy's queries give them)."""
    out: dict = {}
    for c in printed:
        cd, rd, rows = out.setdefault((c.cnode, c.rnode), ([], [], []))
        cd.extend(c.cdofs)
        rd.extend(c.rdofs)
        rows.append(c.matrix)
    return out


@pytest.mark.parametrize(
    ("ndm", "ndf", "commands", "queried"),
    [
        (2, 3, "ops.equalDOF(1, 2, 1, 2)", True),
        (2, 3, "ops.equalDOF(1, 2, 3); ops.equalDOF(1, 3, 1)", True),
        (2, 3, "ops.equalDOF_Mixed(1, 2, 2, 1, 2, 2, 1)", True),
        (2, 3, "ops.rigidLink('bar', 1, 2)", True),
        (2, 2, "ops.rigidLink('beam', 1, 2)", True),  # no rotations: the identity
        (3, 6, "ops.rigidLink('bar', 1, 2)", True),
        (3, 6, "ops.equalDOF(1, 2, 1); ops.equalDOF(1, 2, 2)", True),
        (3, 6, "ops.equalDOF(1, 2, 4, 5, 6)", True),
        (2, 3, "ops.equalDOF(1, 2, 1, 2, 3)", False),  # as a rigid beam's dofs
        (2, 3, "ops.rigidLink('beam', 1, 2)", False),
        (3, 6, "ops.rigidLink('beam', 1, 2)", False),
        (3, 6, "ops.rigidDiaphragm(3, 1, 3, 4)", False),
    ],
)
def test_queried_constraints_are_the_printed_ones(ndm, ndf, commands, queried):
    _model(ndm, ndf, commands)
    printed = _constraints._parse(_constraints._text(ops))
    ties = _constraints._ties(ops)
    assert ties is not None and printed
    known = _constraints._identities(ops, ties)
    assert (known is not None) == queried
    read = _constraints.constraints(ops)
    if not queried:  # the printout's, one per OpenSees constraint
        assert [(c.cnode, c.rnode, c.cdofs, c.rdofs) for c in read] == [
            (c.cnode, c.rnode, c.cdofs, c.rdofs) for c in printed
        ]
        for a, b in zip(read, printed, strict=True):
            np.testing.assert_array_equal(a.matrix, b.matrix)
        return
    merged = _merged(printed)
    assert sorted((c.cnode, c.rnode) for c in read) == sorted(merged)
    for c in read:
        cdofs, rdofs, blocks = merged[c.cnode, c.rnode]
        assert (c.cdofs, c.rdofs) == (cdofs, rdofs)
        whole = np.zeros((len(cdofs), len(rdofs)))
        at = 0
        for block in blocks:  # the printed constraints of the pair, block by block
            k = block.shape[0]
            whole[at : at + k, at : at + k] = block
            at += k
        np.testing.assert_array_equal(c.matrix, whole)


def _three_analyses() -> tuple:
    """The matrices as the import formed them before: an analysis per matrix."""
    ops.wipeAnalysis()
    ops.constraints("Transformation")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    ops.algorithm("Linear")
    out = []
    for factors in ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)):
        ops.integrator("GimmeMCK", *factors)
        ops.analysis("Transient")
        with quiet():
            ops.analyze(1, 0.0)
        n = int(ops.systemSize())
        out.append(np.array(ops.printA("-ret")).reshape(n, n, order="F"))
    ops.wipeAnalysis()
    return tuple(out)


def test_matrices_of_one_analysis_equal_an_analysis_each():
    # a frame after gravity, with Rayleigh damping, hinges that yield under it (Steel01)
    # and a massless rotation: M singular, C and K at the loaded state
    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    for node, (x, y) in {1: (0, 0), 2: (0, 3), 3: (4, 3), 4: (4, 0), 5: (4, 3)}.items():
        ops.node(node, float(x), float(y))
    ops.fix(1, 1, 1, 1)
    ops.fix(4, 1, 1, 1)
    ops.mass(2, 1e3, 1e3, 0.0)
    ops.mass(5, 1e3, 1e3, 0.0)
    ops.geomTransf("PDelta", 1)
    ops.element("elasticBeamColumn", 1, 1, 2, 1e-2, 2e11, 1e-4, 1)
    ops.element("elasticBeamColumn", 2, 2, 3, 1e-2, 2e11, 2e-4, 1)
    ops.element("elasticBeamColumn", 3, 4, 5, 1e-2, 2e11, 1e-4, 1)
    ops.uniaxialMaterial("Steel01", 1, 1e3, 1e6, 0.05)
    ops.element("zeroLength", 4, 3, 5, "-mat", 1, "-dir", 3)
    ops.equalDOF(3, 5, 1, 2)
    ops.rayleigh(0.3, 0.002, 0.0, 0.0)
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    ops.load(2, 2e4, -5e4, 0.0)
    ops.load(5, 0.0, -5e4, 0.0)
    ops.constraints("Transformation")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    ops.test("NormDispIncr", 1e-12, 50)
    ops.algorithm("Newton")
    ops.integrator("LoadControl", 0.1)
    ops.analysis("Static")
    assert ops.analyze(10) == 0
    ops.loadConst("-time", 0.0)
    assert abs(ops.eleResponse(4, "material", "1", "tangent")[0]) < 1e6  # yielded
    before = _three_analyses()
    M, C, K, _ = matrices(ops)
    after = _three_analyses()
    for ours, each, again in zip((M, C, K), before, after, strict=True):
        assert np.any(ours)
        assert ours.tobytes() == each.tobytes() == again.tobytes()


def test_printout_in_memory_equals_the_one_through_a_file(monkeypatch):
    # the JSON printout written to a memfd, and where that is missing to a temporary file
    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    ops.node(1, 0.0, 0.0)
    ops.node(2, 0.0, 0.0)
    ops.fix(1, 1, 1, 1)
    ops.mass(2, 1.0, 1.0, 0.0)
    ops.uniaxialMaterial("Steel01", 1, 2.0, 40.0, 0.1)
    ops.uniaxialMaterial("Elastic", 2, 1e6)
    ops.element("zeroLength", 1, 1, 2, "-mat", 1, 2, 2, "-dir", 1, 2, 3)
    from duhamel.opensees import _read

    memory = _read._json_memfd(ops)
    assert memory is not None and '"uniaxialMaterials"' in memory
    a = _read.printout(ops)
    monkeypatch.delattr(_read.os, "memfd_create")
    assert _read._json_memfd(ops) is None
    b = _read.printout(ops)
    assert (a.materials, a.elements, a.transforms) == (b.materials, b.elements, b.transforms)
    assert a.materials[1]["type"] == "Steel01" and a.elements[1]["type"] == "ZeroLength"

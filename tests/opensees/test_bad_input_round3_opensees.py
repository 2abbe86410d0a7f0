"""Models that OpenSees cannot number (issue 38): ``from_opensees`` refuses them with a
``ValueError`` naming the nodes or the constraint before OpenSees' ``analyze`` runs — which
ends the Python process (exit status 255, no message) on a model whose every dof is fixed
and on ``equalDOF`` constraints that loop. Each model is built and imported in a subprocess
that must end with that ``ValueError``, not a dead interpreter.
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

pytest.importorskip("openseespy.opensees")

PYTHON = Path(__file__).resolve().parents[2] / "python"

#: The head of every script: a 1-D model of four nodes, node 1 fixed, springs to the others.
HEAD = """
import openseespy.opensees as ops
import duhamel.opensees
ops.wipe()
ops.model("basic", "-ndm", 1, "-ndf", 1)
ops.uniaxialMaterial("Elastic", 1, 4.0)
for node in (1, 2, 3, 4):
    ops.node(node, 0.0)
ops.fix(1, 1)
for node in (2, 3, 4):
    ops.mass(node, 1.0)
    ops.element("zeroLength", node - 1, 1, node, "-mat", 1, "-dir", 1)
"""

#: The tail: the import, and what it ended with on stdout.
TAIL = """
try:
    system = duhamel.opensees.from_opensees()
except ValueError as exc:
    print("ValueError:", exc, flush=True)
else:
    print("imported", system.n_dof, system.dof_labels, flush=True)
"""


def _run(model: str) -> tuple[int, str]:
    """Runs HEAD + `model` + TAIL in a fresh interpreter: (exit status, stdout)."""
    script = HEAD + textwrap.dedent(model) + TAIL
    env = {**os.environ, "PYTHONPATH": str(PYTHON), "OPENBLAS_NUM_THREADS": "1"}
    done = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, env=env, timeout=120
    )
    return done.returncode, done.stdout


@pytest.mark.parametrize(
    ("model", "said"),
    [
        # every node fixed
        ("ops.fix(2, 1); ops.fix(3, 1); ops.fix(4, 1)", "nodes (1, 2, 3, 4) is fixed"),
        # the free dofs tied to the fixed node
        (
            "ops.equalDOF(1, 2, 1); ops.equalDOF(1, 3, 1); ops.equalDOF(1, 4, 1)",
            "nodes (1, 2, 3, 4) is fixed or tied",
        ),
        ("ops.fix(2, 1); ops.fix(3, 1); ops.equalDOF(1, 4, 1)", "is fixed or tied"),
    ],
)
def test_a_model_without_a_free_dof_is_refused(model, said):
    status, out = _run(model)
    assert status == 0, f"the interpreter ended with status {status}: {out!r}"
    assert out.startswith("ValueError: every dof of the model's nodes"), out
    assert said in out and "free a dof" in out, out


@pytest.mark.parametrize(
    ("model", "chain", "pairs"),
    [
        (
            "ops.equalDOF(2, 3, 1); ops.equalDOF(3, 2, 1)",
            "node 2 ux is tied to node 3 ux, node 3 ux is tied to node 2 ux",
            "3 -> 2 and 2 -> 3",
        ),
        (
            "ops.equalDOF(2, 3, 1); ops.equalDOF(3, 4, 1); ops.equalDOF(4, 2, 1)",
            "node 2 ux is tied to node 4 ux, node 4 ux is tied to node 3 ux, node 3 ux is "
            "tied to node 2 ux",
            "4 -> 2 and 3 -> 4 and 2 -> 3",
        ),
        ("ops.equalDOF(2, 2, 1)", "node 2 ux is tied to node 2 ux", "2 -> 2"),
    ],
)
def test_constraints_that_loop_are_refused_naming_them(model, chain, pairs):
    status, out = _run(model)
    assert status == 0, f"the interpreter ended with status {status}: {out!r}"
    assert out.startswith("ValueError: the multi-point constraints form a loop: "), out
    assert chain in out and f"retained node -> constrained node {pairs}" in out, out
    assert "remove one of them" in out, out


def test_a_chain_and_a_two_way_tie_of_different_dofs_still_import():
    # equalDOF chains (2 -> 3 -> 4) and two nodes tied both ways on different dofs are no
    # loops: OpenSees numbers them, and so they are imported
    status, out = _run("ops.equalDOF(2, 3, 1); ops.equalDOF(3, 4, 1)")
    assert status == 0 and out.startswith("imported 1 ('2:ux',)"), (status, out)
    script = """
    ops.wipe(); ops.model("basic", "-ndm", 2, "-ndf", 2)
    ops.uniaxialMaterial("Elastic", 1, 4.0)
    for node in (1, 2, 3):
        ops.node(node, 0.0, 0.0)
    ops.fix(1, 1, 1); ops.mass(2, 1.0, 1.0); ops.mass(3, 1.0, 1.0)
    ops.element("zeroLength", 1, 1, 2, "-mat", 1, 1, "-dir", 1, 2)
    ops.element("zeroLength", 2, 1, 3, "-mat", 1, 1, "-dir", 1, 2)
    ops.equalDOF(2, 3, 1); ops.equalDOF(3, 2, 2)
    """
    status, out = _run(script)
    assert status == 0 and out.startswith("imported 2 ('2:ux', '3:uy')"), (status, out)


@pytest.mark.parametrize("coordinate", ["float('nan')", "float('inf')"])
def test_a_non_finite_node_coordinate_names_the_node(coordinate):
    # said "`K` contains NaN or inf at index (0, 0)"
    script = f"""
    ops.wipe(); ops.model("basic", "-ndm", 2, "-ndf", 3)
    ops.node(1, 0.0, 0.0); ops.node(2, {coordinate}, 3.0)
    ops.fix(1, 1, 1, 1); ops.mass(2, 1.0, 1.0, 0.1)
    ops.geomTransf("Linear", 1)
    ops.element("elasticBeamColumn", 1, 1, 2, 0.01, 2e11, 1e-4, 1)
    """
    status, out = _run(script)
    assert status == 0, f"the interpreter ended with status {status}: {out!r}"
    assert out.startswith("ValueError: node 2 has the coordinates ["), out
    assert "must be finite" in out, out

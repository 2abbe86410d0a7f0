"""The multi-point constraints of the running openseespy session (``equalDOF``,
``equalDOF_Mixed``, ``rigidLink``, ``rigidDiaphragm``): which dofs each ties and its matrix,
read through openseespy's queries where the dofs alone say the matrix (the identity) and
from the model's text printout where they do not, and the refusals of the constraints
OpenSees' numbering ends the Python process on."""

from __future__ import annotations

import contextlib
import io
import itertools
import math
import re
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel.opensees._read import Constraint, components, listed, printed, quiet

__all__ = ["check_model", "constraints"]


def _parse(text: str) -> list[Constraint]:
    out = []
    pattern = re.compile(
        r"Node Constrained:\s*(-?\d+)\s*node Retained:\s*(-?\d+)\s*"
        r"constrained dof:([^\n]*)\n\s*retained dof:([^\n]*)\n\s*constraint matrix:\s*\n"
        r"((?:[^\n]*\S[^\n]*\n)*)"
    )
    for m in pattern.finditer(text):
        cdofs = [int(v) - 1 for v in m.group(3).split()]  # printed from 1
        rdofs = [int(v) - 1 for v in m.group(4).split()]
        rows = [[float(v) for v in line.split()] for line in m.group(5).splitlines()]
        rows = [r for r in rows if r][: len(cdofs)]
        matrix = np.array(rows, dtype=np.float64).reshape(len(cdofs), len(rdofs))
        out.append(Constraint(int(m.group(1)), int(m.group(2)), cdofs, rdofs, matrix))
    return out


def _text(ops: Any) -> str:
    """The text printout, which only the multi-point constraints are read from: OpenSees'
    ``printModel()`` without a file writes it through Python's ``sys.stderr`` (captured:
    one Python call per piece instead of one system call to a file, 2.0 against 2.7 ms on
    the 6-storey frame); through a temporary file where nothing that reads as a constraint
    came through (an openseespy writing elsewhere)."""
    buf = io.StringIO()
    with quiet(), contextlib.redirect_stderr(buf):
        ops.printModel()
    text = buf.getvalue()
    if "Node Constrained" in text:
        return text
    return printed(ops)


#: openseespy's queries of the multi-point constraints (an older openseespy lacks them).
_QUERIES = ("getRetainedNodes", "getConstrainedNodes", "getRetainedDOFs", "getConstrainedDOFs")


def _ties(ops: Any) -> list[tuple[int, int, list[int], list[int]]] | None:
    """The multi-point constraints as ``(cnode, rnode, cdofs, rdofs)`` (dofs from 0), one
    per pair of nodes (the constraints between two nodes in OpenSees' order, their dofs
    one after the other), read through openseespy's queries; None where those are
    missing (an older openseespy)."""
    if not all(hasattr(ops, q) for q in _QUERIES):
        return None
    out = []
    for r in ops.getRetainedNodes():
        for c in ops.getConstrainedNodes(int(r)):
            cdofs = [int(d) - 1 for d in ops.getConstrainedDOFs(int(c), int(r))]
            rdofs = [int(d) - 1 for d in ops.getRetainedDOFs(int(r), int(c))]
            out.append((int(c), int(r), cdofs, rdofs))
    return out


def _identities(
    ops: Any, ties: list[tuple[int, int, list[int], list[int]]]
) -> list[Constraint] | None:
    """`ties` as :class:`Constraint` with the identity as matrix when each ties its dofs
    one to one and all of one kind (translations to translations, or rotations to
    rotations), else None. Those are exact: ``equalDOF``, ``equalDOF_Mixed`` and
    ``rigidLink('bar')`` tie with the identity; the two that do not, ``rigidLink('beam')``
    and ``rigidDiaphragm`` (the retained node's rotation times the offset added to the
    translations), tie translations and rotations together (or, without rotations
    (``rigidLink('beam')`` between nodes of translations only), with the identity too)."""
    ndm = int(np.atleast_1d(ops.getNDM())[0])
    out = []
    for cnode, rnode, cdofs, rdofs in ties:
        kinds: set[str] = set()
        for node, dofs in ((cnode, cdofs), (rnode, rdofs)):
            comps = components(ndm, int(listed(ops.getNDF(node))[0]))
            kinds.update(comps[d][0] if 0 <= d < len(comps) else "?" for d in dofs)
        one_to_one = len(cdofs) == len(rdofs) and len(set(cdofs)) == len(cdofs)
        if not (one_to_one and kinds in ({"u"}, {"r"})):  # "d": a dof without a name
            return None
        out.append(Constraint(cnode, rnode, cdofs, rdofs, np.eye(len(cdofs))))
    return out


def constraints(ops: Any) -> list[Constraint]:
    """The session's multi-point constraints with their matrices: from openseespy's
    queries where every one is an identity (:func:`_identities`: the text printout, 2 ms
    on the 6-storey frame, is not printed), else from the text printout (one per OpenSees
    constraint, its matrix to the six digits OpenSees prints)."""
    ties = _ties(ops)
    if ties is not None:
        if not ties:
            return []
        known = _identities(ops, ties)
        if known is not None:
            return known
    return _parse(_text(ops))


def _loop(edges: dict[tuple[int, int], set[tuple[int, int]]]) -> list[tuple[int, int]] | None:
    """A cycle of the directed graph `edges` (its nodes in order, the first repeated at the
    end), or None."""
    state: dict[tuple[int, int], int] = {}  # 1: on the current path, 2: done
    for start in sorted(edges):
        if start in state:
            continue
        path, stack = [start], [iter(sorted(edges.get(start, ())))]
        state[start] = 1
        while stack:
            nxt = next(stack[-1], None)
            if nxt is None:
                state[path.pop()] = 2
                stack.pop()
            elif state.get(nxt) == 1:
                return [*path[path.index(nxt) :], nxt]
            elif nxt not in state:
                state[nxt] = 1
                path.append(nxt)
                stack.append(iter(sorted(edges.get(nxt, ()))))
    return None


def check_model(ops: Any, printed: list[Constraint]) -> None:
    """Refuses, naming the nodes or the constraint, what OpenSees' numbering of the model
    (its ``analyze``) ends the Python process on (exit status 255, no message): a model
    whose every dof is fixed or tied to another node, and multi-point constraints that tie
    a dof back to itself (``equalDOF`` 2 -> 3 and 3 -> 2). Also a node coordinate that is
    not finite (the matrices would be NaN). Read through openseespy's query functions,
    before any analysis runs; `printed` (the printout's constraints, with their matrices)
    says which retained dofs each constrained dof depends on."""
    nodes = sorted(int(v) for v in ops.getNodeTags())
    for node in nodes:
        xyz = [float(c) for c in listed(ops.nodeCoord(node))]
        if not all(math.isfinite(c) for c in xyz):
            raise ValueError(
                f"node {node} has the coordinates {xyz}: OpenSees node coordinates must be "
                "finite (check the model's `node` commands)"
            )
    ndm = int(np.atleast_1d(ops.getNDM())[0])
    ndf = {node: int(listed(ops.getNDF(node))[0]) for node in nodes}
    fixed = {int(v): {int(d) - 1 for d in ops.getFixedDOFs(int(v))} for v in ops.getFixedNodes()}
    queried = _ties(ops)  # an older openseespy: the printed ones
    ties = (
        queried if queried is not None else [(c.cnode, c.rnode, c.cdofs, c.rdofs) for c in printed]
    )
    edges: dict[tuple[int, int], set[tuple[int, int]]] = {}
    matrices: dict[tuple[int, int, tuple[int, ...], tuple[int, ...]], NDArray[np.float64]] = {}
    for p in printed:  # the first of those alike, by what they tie
        matrices.setdefault((p.cnode, p.rnode, tuple(p.cdofs), tuple(p.rdofs)), p.matrix)
    for cnode, rnode, cdofs, rdofs in ties:
        matrix = matrices.get((cnode, rnode, tuple(cdofs), tuple(rdofs)))
        for a, cd in enumerate(cdofs):
            for b, rd in enumerate(rdofs):
                if matrix is None or matrix.shape != (len(cdofs), len(rdofs)) or matrix[a, b]:
                    edges.setdefault((cnode, cd), set()).add((rnode, rd))
    cycle = _loop(edges)
    if cycle is not None:

        def name(key: tuple[int, int]) -> str:
            node, d = key
            comps = components(ndm, ndf.get(node, d + 1))
            return f"node {node} {comps[d] if d < len(comps) else f'dof{d + 1}'}"

        steps = list(itertools.pairwise(cycle))
        chain = ", ".join(f"{name(c)} is tied to {name(r)}" for c, r in steps)
        pairs = " and ".join(f"{r} -> {c}" for (c, _), (r, _) in steps)
        first = steps[0]
        raise ValueError(
            f"the multi-point constraints form a loop: {chain} (the constraints of retained "
            f"node -> constrained node {pairs}, e.g. `equalDOF({first[1][0]}, {first[0][0]}, "
            "...)`); OpenSees cannot number such a model (its analysis ends the Python "
            "process): remove one of them"
        )
    tied = {(c, d) for c, _, cdofs, _ in ties for d in cdofs}
    free = [
        (node, d)
        for node in nodes
        for d in range(ndf[node])
        if d not in fixed.get(node, set()) and (node, d) not in tied
    ]
    if not free:
        shown = ", ".join(map(str, nodes[:10])) + (", ..." if len(nodes) > 10 else "")
        raise ValueError(
            f"every dof of the model's nodes ({shown}) is fixed or tied to another node by a "
            "constraint: the model has no equation to solve, and OpenSees' analysis of it "
            "ends the process; free a dof (remove a `fix` or a constraint)"
        )

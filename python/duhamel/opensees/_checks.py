"""The models OpenSees cannot analyse, refused before the import runs OpenSees' ``analyze()``
(which ends the Python process on them, exit 255 without a message): a node coordinate that
is not finite, a multi-point constraint that loops back onto a dof it retains, and a model
without a free dof."""

from __future__ import annotations

from typing import Any

import numpy as np

from duhamel.opensees._read import Printout, components

__all__ = ["refuse_unanalysable"]


def refuse_unanalysable(ops: Any, pr: Printout) -> None:
    """Raises ``ValueError`` naming the nodes or constraints of a model OpenSees cannot
    analyse: coordinates NaN or inf, constraint loops (``equalDOF`` 2 -> 3 and 3 -> 2, or
    longer), no free dof (every dof fixed or constrained)."""
    nodes = [int(n) for n in ops.getNodeTags()]
    bad = [n for n in nodes if not np.all(np.isfinite(np.asarray(ops.nodeCoord(n), float)))]
    if bad:
        coords = ", ".join(f"node {n} at {list(ops.nodeCoord(n))}" for n in bad[:5])
        raise ValueError(
            f"the openseespy model has node coordinates that are not finite: {coords}"
            + (f" (and {len(bad) - 5} more)" if len(bad) > 5 else "")
        )
    _refuse_loops(pr)
    ndm = int(np.atleast_1d(ops.getNDM())[0])
    fixed = {int(n): {int(d) - 1 for d in ops.getFixedDOFs(int(n))} for n in ops.getFixedNodes()}
    tied: dict[int, set[int]] = {}
    for c in pr.constraints:
        tied.setdefault(c.cnode, set()).update(c.cdofs)
    free = sum(
        1
        for n in nodes
        for d in range(len(components(ndm, len(ops.nodeDisp(n)))))
        if d not in fixed.get(n, set()) and d not in tied.get(n, set())
    )
    if free == 0:
        raise ValueError(
            f"the openseespy model has no free dof: every dof of its {len(nodes)} nodes "
            f"(nodes {nodes[:5]}{'...' if len(nodes) > 5 else ''}) is fixed or constrained; "
            "there is nothing to analyse"
        )


def _refuse_loops(pr: Printout) -> None:
    """A constrained dof must not retain itself through a chain of constraints: the
    dependency graph ``(cnode, cdof) -> (rnode, rdof)`` (entries of the constraint matrix
    that are not zero) has no cycle."""
    edges: dict[tuple[int, int], list[tuple[tuple[int, int], Any]]] = {}
    for c in pr.constraints:
        for a, cd in enumerate(c.cdofs):
            for b, rd in enumerate(c.rdofs):
                if c.matrix[a, b] != 0.0:
                    edges.setdefault((c.cnode, cd), []).append(((c.rnode, rd), c))
    state: dict[tuple[int, int], int] = {}  # 1: on the current path, 2: done
    for start in edges:
        if state.get(start):
            continue
        path: list[tuple[tuple[int, int], Any]] = []
        stack = [(start, iter(edges.get(start, [])))]
        state[start] = 1
        while stack:
            here, it = stack[-1]
            step = next(it, None)
            if step is None:
                state[here] = 2
                stack.pop()
                if path:
                    path.pop()
                continue
            there, c = step
            if state.get(there) == 1:
                cycle = [*(p[1] for p in path), c]
                pairs = ", ".join(f"node {k.cnode} -> node {k.rnode}" for k in cycle)
                raise ValueError(
                    "the openseespy model's multi-point constraints form a loop (a "
                    f"constrained dof retains itself): {pairs} (constrained -> retained); "
                    "OpenSees cannot analyse it: tie each dof to one retained dof"
                )
            if not state.get(there):
                state[there] = 1
                path.append(step)
                stack.append((there, iter(edges.get(there, []))))

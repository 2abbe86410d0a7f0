"""What the running openseespy session holds: the matrices at the current state (through
``GimmeMCK``), the equations and the node dofs they belong to (with the multi-point
constraints of :mod:`duhamel.opensees._constraints`) and the model's printout (materials
and elements as OpenSees prints them)."""

from __future__ import annotations

import contextlib
import io
import json
import os
import re
import sys
import tempfile
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any, cast

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "Constraint",
    "DofMap",
    "Printout",
    "components",
    "dof_map",
    "listed",
    "matrices",
    "printed",
    "printout",
]

_COMPONENTS = {
    (1, 1): ("ux",),
    (2, 2): ("ux", "uy"),
    (2, 3): ("ux", "uy", "rz"),
    (3, 3): ("ux", "uy", "uz"),
    (3, 6): ("ux", "uy", "uz", "rx", "ry", "rz"),
}


def components(ndm: int, ndf: int) -> tuple[str, ...]:
    """The component names of a node's dofs in a model of `ndm` dimensions and `ndf` dofs
    per node (``dof1``, ``dof2``... for a combination without names)."""
    names = _COMPONENTS.get((ndm, ndf))
    return names if names is not None else tuple(f"dof{k + 1}" for k in range(ndf))


def listed(value: Any) -> list[Any]:
    """An openseespy query's answer as a list (it returns one value bare, several as a
    list)."""
    return list(value) if isinstance(value, (list, tuple)) else [value]


@contextlib.contextmanager
def quiet() -> Iterator[None]:
    """Silences what OpenSees writes (its warnings when a singular mass matrix cannot be
    factorised, which the extraction does not need): openseespy writes through Python's
    ``sys.stdout``/``sys.stderr`` (swapped for buffers here, after flushing what the caller
    wrote), the C++ side to the process's descriptors 1 and 2 (pointed at /dev/null)."""
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(Exception):
            stream.flush()
    saved = []
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
    except OSError:  # pragma: no cover - no /dev/null
        devnull = -1
    try:
        if devnull >= 0:
            for fd in (1, 2):
                saved.append((fd, os.dup(fd)))
                os.dup2(devnull, fd)
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
            yield
    finally:
        for fd, copy in saved:
            os.dup2(copy, fd)
            os.close(copy)
        if devnull >= 0:
            os.close(devnull)


def matrices(ops: Any) -> tuple[NDArray, NDArray, NDArray, dict[int, list[int]]]:
    """``(M, C, K, equations)`` of the model at its current state, in OpenSees' equation
    numbering (constraints by transformation, plain numbering), with each node's equation
    numbers (``nodeDOFs``): ``GimmeMCK`` forms each matrix, the ``FullGeneral`` system
    returns it. One analysis (of zero length) numbers the model and sizes the system;
    ``printA`` forms the matrix of the integrator in place (``formTangent``) before it
    returns it, so the three integrators are set in turn on that analysis, each matrix
    formed at the same state (the elements' trial state, committed by the analysis). The
    session's analysis objects are removed (``wipeAnalysis``)."""
    ops.wipeAnalysis()
    ops.constraints("Transformation")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    ops.algorithm("Linear")
    ops.integrator("GimmeMCK", 1.0, 0.0, 0.0)
    ops.analysis("Transient")
    with quiet():  # the system is sized even where its solve fails (a singular M)
        ops.analyze(1, 0.0)
    n = int(ops.systemSize())
    out = []
    for factors in ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)):
        if factors[0] != 1.0:  # M's integrator is the analysis' own
            ops.integrator("GimmeMCK", *factors)
        a = np.array(ops.printA("-ret"), dtype=np.float64)
        if a.size != n * n:
            raise RuntimeError(f"OpenSees returned {a.size} matrix entries for {n} equations")
        # FullGeneral holds its matrix column by column (LAPACK's order): printA returns
        # it so (an element's tangent that is not symmetric shows it)
        out.append(a.reshape(n, n, order="F"))
    eqs = {int(v): [int(e) for e in ops.nodeDOFs(int(v))] for v in ops.getNodeTags()}
    ops.wipeAnalysis()
    return out[0], out[1], out[2], eqs


@dataclass
class Constraint:
    """One multi-point constraint: ``u_c[cdofs] = matrix @ u_r[rdofs]`` (dofs from 0)."""

    cnode: int
    rnode: int
    cdofs: list[int]
    rdofs: list[int]
    matrix: NDArray[np.float64]


@dataclass
class Printout:
    """The model as OpenSees prints it: uniaxial materials and elements by tag (from
    ``printModel('-JSON')``, or the key-value text of those that print no JSON), and the
    multi-point constraints (:func:`duhamel.opensees._constraints.constraints`)."""

    materials: dict[int, dict[str, Any]] = field(default_factory=dict)
    elements: dict[int, dict[str, Any]] = field(default_factory=dict)
    constraints: list[Constraint] = field(default_factory=list)
    transforms: dict[str, str] = field(default_factory=dict)


def _number(text: str) -> Any:
    try:
        return float(text)
    except ValueError:
        return text.strip()


def _entries(block: str) -> list[dict[str, Any]]:
    """The entries of a JSON list that OpenSees printed, some of them as plain text: in one
    ``json.loads`` where every entry is JSON (an object on its own line), else line by
    line (:func:`_lines`)."""
    fixed = block.replace(']}"factors"', '], "factors"')  # see _lines
    try:
        whole = json.loads(f"[{fixed}]")
    except json.JSONDecodeError:
        return _lines(block)
    lines = [s for s in (line.strip().rstrip(",") for line in block.splitlines()) if s]
    if len(whole) == len(lines) and all(
        isinstance(e, dict) and s.startswith("{") and s.endswith("}")
        for e, s in zip(whole, lines, strict=True)
    ):
        return cast(list[dict[str, Any]], whole)
    return _lines(block)


def _lines(block: str) -> list[dict[str, Any]]:
    """:func:`_entries` line by line: each JSON object on its line, the key-value text of
    an entry printed without JSON, an entry that does not read as JSON kept as
    ``_unreadable``."""
    out: list[dict[str, Any]] = []
    text: list[str] = []

    def flush() -> None:
        if not any(line.strip() for line in text):
            text.clear()
            return
        entry: dict[str, Any] = {}
        head = text[0]
        tag = re.search(r"tag:?\s*(-?\d+)", head)
        if tag is None and out and out[-1].get("_text"):  # a table after a blank line
            out[-1]["_lines"].extend(line.strip() for line in text)
            text.clear()
            return
        entry["type"] = re.split(r"[\s,:]", head.strip(), maxsplit=1)[0]
        if tag:
            entry["name"] = int(tag.group(1))
        for line in text[1:]:
            if ":" in line:
                key, value = line.split(":", 1)
                entry[key.strip()] = _number(value)
        entry["_text"] = True
        entry["_lines"] = [line.strip() for line in text[1:]]  # a table (MultiLinear's)
        out.append(entry)
        text.clear()

    for line in block.splitlines():
        s = line.strip().rstrip(",")
        if s.startswith("{") and s.endswith("}"):
            flush()
            try:  # OpenSees' Parallel material closes its entry before its factors
                out.append(json.loads(s.replace(']}"factors"', '], "factors"')))
            except json.JSONDecodeError:
                out.append({"_unreadable": s})
        elif s:
            text.append(line)
        else:
            flush()
    flush()
    return out


def _section(text: str, name: str) -> str:
    """The body of the JSON list `name` (OpenSees prints each entry on its own lines and
    closes the list on a line of its own)."""
    start = text.find(f'"{name}": [')
    if start < 0:
        return ""
    start = text.index("[", start) + 1
    end = re.compile(r"\n[ \t]*\],?[ \t]*(?=\n|$)").search(text, start)
    return text[start : end.start() if end else len(text)]


def printed(ops: Any, *flags: str) -> str:
    """OpenSees' ``printModel(*flags)`` written to a temporary file, read back and deleted."""
    with tempfile.TemporaryDirectory(prefix="duhamel-opensees-") as tmp:
        path = os.path.join(tmp, "model")
        with quiet():
            ops.printModel(*flags, "-file", path)
        with open(path, encoding="utf-8", errors="replace") as f:
            return f.read()


def _json_memfd(ops: Any) -> str | None:
    """The JSON printout written to an anonymous file in memory (Linux' ``memfd``, opened
    by OpenSees through ``/proc/self/fd``: 1.4 against 1.8 ms on the 6-storey frame to a
    temporary file, which OpenSees writes piece by piece); None where that is not
    available or OpenSees could not write it."""
    if not hasattr(os, "memfd_create") or not os.path.isdir("/proc/self/fd"):
        return None
    fd = os.memfd_create("duhamel-opensees")
    try:
        with quiet():
            ops.printModel("-JSON", "-file", f"/proc/self/fd/{fd}")
        with open(fd, encoding="utf-8", errors="replace", closefd=False) as f:
            text = f.read()
    except Exception:  # OpenSees could not open it: a temporary file then
        return None
    finally:
        os.close(fd)
    return text if text.strip() else None


def printout(ops: Any) -> Printout:
    """The session's model printout in JSON (in memory, :func:`_json_memfd`, or a temporary
    file, read back and deleted); its multi-point constraints are read apart
    (:func:`duhamel.opensees._constraints.constraints`)."""
    jtext = _json_memfd(ops)
    if jtext is None:
        jtext = printed(ops, "-JSON")
    out = Printout()
    for entry in _entries(_section(jtext, "uniaxialMaterials")):
        if "name" in entry:
            out.materials[int(entry["name"])] = entry
    for entry in _entries(_section(jtext, "crdTransformations")):
        if "name" in entry:
            out.transforms[str(entry["name"])] = str(entry.get("type", ""))
    for entry in _entries(_section(jtext, "elements")):
        if "name" in entry:
            out.elements[int(entry["name"])] = entry
    return out


@dataclass
class DofMap:
    """The equations of the model and the node dofs they are: `labels` (one per equation,
    ``(node, component)``), `aliases` (node dofs tied to an equation one to one, e.g. by
    ``equalDOF``), `absent` (node dofs that are no equation, with the reason), and
    `recovery`: each node dof (fixed ones excluded) as a row of coefficients on the
    equations (the displacement of a node tied by a rigid diaphragm)."""

    labels: list[tuple[int, str]]
    aliases: dict[tuple[int, str], int]
    absent: dict[tuple[int, str], str]
    recovery: dict[tuple[int, str], NDArray[np.float64]]


def _is_fixed(fixed: dict[int, set[int]], comps: tuple[str, ...], node: int, comp: str) -> bool:
    return comps.index(comp) in fixed.get(node, set())


def dof_map(
    ops: Any, n_eq: int, equations: dict[int, list[int]], constraints: list[Constraint]
) -> DofMap:
    """The dof map of the model numbered by :func:`matrices` (its `equations`)."""
    ndm = int(np.atleast_1d(ops.getNDM())[0])
    fixed: dict[int, set[int]] = {}
    for node in ops.getFixedNodes():
        fixed[int(node)] = {int(d) - 1 for d in ops.getFixedDOFs(int(node))}
    tied: dict[int, list[Constraint]] = {}
    for c in constraints:
        tied.setdefault(c.cnode, []).append(c)
    labels: list[tuple[int, str] | None] = [None] * n_eq
    rows: dict[tuple[int, str], NDArray[np.float64]] = {}
    absent: dict[tuple[int, str], str] = {}
    pending: list[tuple[int, int, str]] = []
    none: frozenset[int] = frozenset()
    for node, eqs in equations.items():
        n = len(eqs)
        comps = components(ndm, n)
        fx = fixed.get(node, none)
        cdofs = {d for c in tied[node] for d in c.cdofs} if node in tied else none
        # a constrained node's equations list its own free dofs first (then the retained
        # node's): position by position only for a node without constraints
        order = [d for d in range(n) if d not in cdofs and d not in fx] if cdofs else range(n)
        for k, d in enumerate(order):
            e = eqs[k] if k < n else -1
            key = (node, comps[d])
            if d in fx:
                absent[key] = f"node {node} {comps[d]} is fixed in OpenSees"
                continue
            if e < 0:
                absent[key] = f"node {node} {comps[d]} has no equation in OpenSees"
                continue
            row = np.zeros(n_eq)
            row[e] = 1.0
            rows[key] = row
            if labels[e] is None:
                labels[e] = key
        if cdofs:
            pending.extend((node, d, comps[d]) for d in sorted(cdofs))
    aliases: dict[tuple[int, str], int] = {}
    for _ in range(len(pending) + 1):  # constraints may chain: resolve until nothing moves
        left = []
        for node, d, comp in pending:
            c = next(c for c in tied[node] if d in c.cdofs)
            rcomps = components(ndm, len(equations[c.rnode]))
            terms = [(rcomps[r], c.matrix[c.cdofs.index(d), k]) for k, r in enumerate(c.rdofs)]
            # a fixed retained dof contributes nothing
            terms = [(rc, coef) for rc, coef in terms if not _is_fixed(fixed, rcomps, c.rnode, rc)]
            if any(coef != 0.0 and (c.rnode, rc) not in rows for rc, coef in terms):
                left.append((node, d, comp))
                continue
            row = np.zeros(n_eq)
            for rc, coef in terms:
                if coef != 0.0:
                    row += coef * rows[(c.rnode, rc)]
            rows[(node, comp)] = row
            nz = np.flatnonzero(row)
            if nz.size == 1 and row[nz[0]] == 1.0:
                aliases[(node, comp)] = int(nz[0])
            else:
                absent[(node, comp)] = (
                    f"node {node} {comp} is tied to node {c.rnode} by a constraint that is not "
                    "one to one (rigid diaphragm or link); its displacement is "
                    "OpenSeesModel.recovery"
                )
        if len(left) == len(pending):
            break
        pending = left
    for node, _d, comp in pending:
        absent[(node, comp)] = f"node {node} {comp} is constrained to a dof without an equation"
    missing = [e for e, lab in enumerate(labels) if lab is None]
    if missing:
        raise RuntimeError(f"OpenSees equations {missing[:5]} belong to no node dof")
    return DofMap([lab for lab in labels if lab is not None], aliases, absent, rows)

"""What translating one OpenSees element gives (its duhamel elements, the stiffness to take
out of K, notes, its Rayleigh damping), the refusals, and the small readers shared by the
translations of elements and bearings."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel.elements import Element
from duhamel.opensees._read import DofMap, listed

__all__ = ["Damped", "Made", "Refused", "Translation", "Untranslatable"]


class Untranslatable(Exception):
    """An element (or one of its materials) without a duhamel counterpart."""


class Refused(Exception):
    """An element OpenSees itself cannot analyse: refused also under ``linearize``."""


@dataclass
class Damped:
    """A translated element that OpenSees damps with its Rayleigh factors (``zeroLength``
    ``-doRayleigh 1``, a bearing's ``-doRayleigh``): its type, its materials (or `None` for a
    bearing) and, per translated direction, its initial stiffness (a bearing's: its tangent
    at import) and the damping OpenSees gives it there (``nan`` where it cannot be read)."""

    kind: str
    what: str
    directions: list[tuple[float, float]]


@dataclass
class Translation:
    """The translated elements, by OpenSees tag; the stiffness to take out of K (each
    ``(dofs, k)``); the elements kept linear; notes for the user; the translated elements
    OpenSees damps with its Rayleigh factors, by tag."""

    elements: dict[int, list[Element]] = field(default_factory=dict)
    removed: list[tuple[tuple[int, ...], NDArray[np.float64]]] = field(default_factory=list)
    linearized: dict[int, str] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    damped: dict[int, Damped] = field(default_factory=dict)
    pdelta: list[Any] = field(default_factory=list)  # elastomeric bearings' P-Delta moments


def _eq(dmap: DofMap, node: int, comp: str, index: dict) -> int | None:
    """The equation of a node dof, None when it is fixed; Untranslatable when it is tied to
    others by a constraint that is not one to one."""
    key = (node, comp)
    if key in index:
        return index[key]
    why = dmap.absent.get(key, f"node {node} has no dof {comp}")
    if "fixed" in why:
        return None
    raise Untranslatable(why)


def _pair(i: int | None, j: int | None, k: float) -> tuple[tuple[int, ...], NDArray]:
    dofs = tuple(d for d in (i, j) if d is not None)
    if len(dofs) == 1:
        return dofs, np.array([[k]])
    return dofs, np.array([[k, -k], [-k, k]])


def _resp(ops: Any, tag: int, *args: str) -> list[float]:
    return [float(v) for v in listed(ops.eleResponse(tag, *args))]


#: What translating one element gives: its duhamel elements, the stiffness to take out of K,
#: notes, and its Rayleigh damping when OpenSees gives it one (None: none).
Made = tuple[
    list[Element], list[tuple[tuple[int, ...], NDArray[np.float64]]], list[str], Damped | None
]

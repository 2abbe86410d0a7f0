"""Dof labels: names of degrees of freedom (``"roof"``, or ``(node_tag, "ux")`` for a model
imported from a finite-element program) resolved to dof indices wherever an index is taken
(:meth:`duhamel.System.dof`, elements and loads added to a system, ``solve(..., dofs=)``).

A label is a string or a ``(node, component)`` pair (an int node tag and a component name:
``"ux"``, ``"uy"``, ``"uz"``, ``"rx"``, ``"ry"``, ``"rz"``); a pair's text form, used where
labels must be strings (xarray, pandas, the store), is ``"node:component"``.
"""

from __future__ import annotations

import dataclasses
import numbers
from collections.abc import Hashable, Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["Labels", "direction", "is_label", "resolve", "resolve_fields", "resolve_list", "text"]

#: The element and load fields that hold one dof index (or None for the ground).
DOF_FIELDS = ("i", "j", "dof", "dof_x", "dof_y")
#: The load fields that hold a tuple of them.
DOFS_FIELDS = ("dofs",)


def _is_pair(value: Any) -> bool:
    return (
        isinstance(value, tuple)
        and len(value) == 2
        and isinstance(value[0], numbers.Integral)
        and not isinstance(value[0], bool)
        and isinstance(value[1], str)
    )


def is_label(value: Any) -> bool:
    """Whether `value` is a label (a string or a ``(node, component)`` pair), not an index."""
    return isinstance(value, str) or _is_pair(value)


def text(label: Hashable) -> str:
    """The text form of a label: a string as is, a pair ``(3, "ux")`` as ``"3:ux"``."""
    if _is_pair(label):
        return f"{int(label[0])}:{label[1]}"  # type: ignore[index]
    return str(label)


class Labels:
    """The labels of a system's dofs: one per dof, plus aliases (other names of the same dof,
    e.g. the dofs OpenSees ties with ``equalDOF``) and names that are known but are not dofs
    of the system (with the reason, e.g. a fixed or constrained dof of an imported model)."""

    def __init__(
        self,
        labels: Sequence[Hashable],
        aliases: Mapping[Hashable, int] | None = None,
        absent: Mapping[Hashable, str] | None = None,
        n_dof: int | None = None,
    ) -> None:
        if n_dof is not None and len(labels) != n_dof:
            raise ValueError(f"`labels` must name all {n_dof} dofs, got {len(labels)}")
        keys = [(int(v[0]), str(v[1])) if _is_pair(v) else str(v) for v in labels]
        self.keys: tuple[Hashable, ...] = tuple(keys)
        self.texts: tuple[str, ...] = tuple(text(k) for k in keys)
        if len(set(self.texts)) != len(keys):
            raise ValueError("`labels` must be distinct")
        self._index: dict[Hashable, int] = {}
        for i, (k, t) in enumerate(zip(keys, self.texts, strict=True)):
            self._index[k] = i
            self._index[t] = i
        for k, i in (aliases or {}).items():
            if not 0 <= int(i) < len(keys):
                raise ValueError(f"alias {k!r} names dof {i}, outside [0, {len(keys)})")
            self._index.setdefault(k, int(i))
            self._index.setdefault(text(k), int(i))
        self._absent = {text(k): str(why) for k, why in (absent or {}).items()}

    def __len__(self) -> int:
        return len(self.keys)

    def index(self, label: Hashable, name: str = "dof") -> int:
        """The dof index of `label`, or ValueError naming `name` and the label."""
        key = (int(label[0]), str(label[1])) if _is_pair(label) else label  # type: ignore[index]
        found = self._index.get(key)
        if found is None and not isinstance(key, tuple):
            found = self._index.get(str(key))
        if found is not None:
            return found
        why = self._absent.get(text(key))
        if why is not None:
            raise ValueError(f"`{name}` {label!r} is not a dof of the system: {why}")
        some = ", ".join(repr(k) for k in self.keys[:4])
        raise ValueError(
            f"`{name}` {label!r} names no dof of the system (its labels are {some}"
            f"{', ...' if len(self.keys) > 4 else ''})"
        )

    def component(self, comp: str) -> NDArray[np.intp]:
        """The indices of the dofs whose label is a pair with component `comp`."""
        return np.array(
            [i for i, k in enumerate(self.keys) if isinstance(k, tuple) and k[1] == comp],
            dtype=np.intp,
        )


def resolve(system: Any, value: Any, name: str) -> Any:
    """`value` as a dof index if it is a label of `system` (else unchanged: ints, None)."""
    if not is_label(value):
        return value
    labels = getattr(system, "_label_map", None)
    if labels is None:
        raise ValueError(
            f"`{name}` is the label {value!r}, but the system's dofs are not labelled "
            "(System.label_dofs, or a model from duhamel.opensees.from_opensees)"
        )
    return labels.index(value, name)


def resolve_list(system: Any, value: Any, name: str) -> Any:
    """A sequence of dof indices and/or labels as indices (a single label: a list of one)."""
    if value is None or isinstance(value, np.ndarray):
        return value
    if is_label(value):
        return [resolve(system, value, name)]
    try:
        items = list(value)
    except TypeError:
        return value
    if not any(is_label(v) for v in items):
        return value
    return [resolve(system, v, f"{name}[{k}]") for k, v in enumerate(items)]


def direction(system: Any, comp: str) -> NDArray[np.float64]:
    """The influence vector of a rigid support motion along component `comp` (``"ux"``):
    ones on the dofs labelled ``(node, comp)``."""
    labels = getattr(system, "_label_map", None)
    dofs = np.array([], dtype=np.intp) if labels is None else labels.component(comp)
    if not dofs.size:
        raise ValueError(
            f"`direction_vector` {comp!r} names no dofs: the system has no dofs labelled "
            f"(node, {comp!r})"
        )
    r = np.zeros(system.n_dof)
    r[dofs] = 1.0
    return r


def resolve_fields(system: Any, obj: Any) -> Any:
    """An element or load with the labels in its dof fields replaced by indices (the same
    object when it holds none)."""
    if not dataclasses.is_dataclass(obj):
        return obj
    changes: dict[str, Any] = {}
    for f in dataclasses.fields(obj):
        value = getattr(obj, f.name)
        if f.name in DOF_FIELDS and is_label(value):
            changes[f.name] = resolve(system, value, f.name)
        elif f.name in DOFS_FIELDS and isinstance(value, tuple) and any(map(is_label, value)):
            changes[f.name] = tuple(
                resolve(system, v, f"{f.name}[{k}]") for k, v in enumerate(value)
            )
        elif f.name == "direction_vector" and isinstance(value, str):
            changes[f.name] = direction(system, value)
    return dataclasses.replace(obj, **changes) if changes else obj

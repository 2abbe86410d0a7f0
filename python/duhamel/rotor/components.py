"""The rotor's components: shafts, rigid disks and bearings, checked and placed at nodes.

:class:`~duhamel.rotor.Disk` and :class:`~duhamel.rotor.Bearing` live in
:mod:`duhamel.rotor.disk` and :mod:`duhamel.rotor.bearing` (importable from here too),
:class:`~duhamel.rotor.Shaft` in :mod:`duhamel.rotor.shaft`.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from duhamel.rotor.assembly import Placed
from duhamel.rotor.bearing import Bearing
from duhamel.rotor.disk import Disk
from duhamel.rotor.shaft import Shaft

__all__ = ["Bearing", "Disk", "checked_components", "placements"]

Components = tuple[tuple[Shaft, ...], tuple[Disk, ...], tuple[Bearing, ...]]


def _sequence(items: Any, kind: type, name: str) -> tuple[Any, ...]:
    if isinstance(items, kind):
        items = [items]
    out = tuple(items)
    for i, item in enumerate(out):
        if not isinstance(item, kind):
            raise TypeError(
                f"`{name}[{i}]` must be a duhamel.rotor.{kind.__name__}, got {type(item).__name__}"
            )
    return out


def checked_components(
    shafts: Sequence[Shaft] | Shaft,
    disks: Sequence[Disk] | Disk,
    bearings: Sequence[Bearing] | Bearing,
) -> Components:
    """The components as tuples (a single one is allowed for each), of the right types, with
    every disk and bearing on one of the ``len(shafts) + 1`` nodes.

    Examples
    --------
    >>> from duhamel.rotor import STEEL, Bearing, Shaft
    >>> from duhamel.rotor.components import checked_components
    >>> shafts, disks, bearings = checked_components(
    ...     Shaft(0.5, 0.05, material=STEEL), (), [Bearing(1, 1e6, 1e6)])
    >>> len(shafts), disks, bearings[0].node
    (1, (), 1)
    """
    checked = (
        _sequence(shafts, Shaft, "shafts"),
        _sequence(disks, Disk, "disks"),
        _sequence(bearings, Bearing, "bearings"),
    )
    n_nodes = len(checked[0]) + 1
    for name, items in (("disks", checked[1]), ("bearings", checked[2])):
        for i, item in enumerate(items):
            if item.node >= n_nodes:
                raise ValueError(
                    f"`{name}[{i}]` is at node {item.node}, but the rotor has nodes "
                    f"0..{n_nodes - 1} ({len(checked[0])} shafts)"
                )
    return checked


def placements(
    shafts: Sequence[Shaft], disks: Sequence[Disk], bearings: Sequence[Bearing]
) -> tuple[list[Placed], list[Placed]]:
    """The structure (shaft ``i`` at node ``i``, then the disks) and the supports (the
    bearings), each component at its node, for :class:`~duhamel.rotor.assembly.Assembly`.

    Examples
    --------
    >>> from duhamel.rotor import STEEL, Bearing, Shaft
    >>> from duhamel.rotor.components import placements
    >>> structure, supports = placements([Shaft(0.5, 0.05, material=STEEL)] * 2, [],
    ...                                  [Bearing(2, 1e6, 1e6)])
    >>> structure[1].dofs.tolist(), supports[0].dofs.tolist()
    ([4, 5, 6, 7, 8, 9, 10, 11], [8, 9])
    """
    structure = [Placed.at(s, i) for i, s in enumerate(shafts)]
    structure += [Placed.at(d, d.node) for d in disks]
    return structure, [Placed.at(b, b.node) for b in bearings]

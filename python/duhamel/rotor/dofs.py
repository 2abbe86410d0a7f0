"""The rotor's degrees of freedom: four per node, and each component's local-to-global map.

Node ``i`` owns the global dofs ``4 i + (0, 1, 2, 3)`` = ``(x, y, theta_x, theta_y)``. A
component names its local dofs as ROSS does, ``"<direction>_<local node>"`` (``"x_0"``,
``"theta_y_1"``) in its :meth:`dof_mapping`; placed with its first local node at a rotor node,
:func:`global_dofs` turns that mapping into the global indices its matrices scatter to.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["DIRECTIONS", "dof_index", "global_dofs", "local_dof_mapping", "node_index"]

#: Position of each direction within a node's four dofs.
DIRECTIONS = {"x": 0, "y": 1, "theta_x": 2, "theta_y": 3}
#: Degrees of freedom per node.
DOFS_PER_NODE = len(DIRECTIONS)


def node_index(value: Any, name: str = "node") -> int:
    """`value` as a node number (a non-negative integer; bools are refused)."""
    if isinstance(value, bool | np.bool_) or not isinstance(value, int | np.integer):
        raise TypeError(f"`{name}` must be an integer, got {type(value).__name__}")
    if value < 0:
        raise ValueError(f"`{name}` must be >= 0, got {value}")
    return int(value)


def local_dof_mapping(n_nodes: int, directions: tuple[str, ...]) -> dict[str, int]:
    """Local dof labels of a component on `n_nodes` consecutive nodes, in local order.

    Examples
    --------
    >>> from duhamel.rotor.dofs import local_dof_mapping
    >>> local_dof_mapping(1, ("x", "y"))
    {'x_0': 0, 'y_0': 1}
    """
    labels = [f"{d}_{node}" for node in range(n_nodes) for d in directions]
    return {label: i for i, label in enumerate(labels)}


def global_dofs(mapping: dict[str, int], first_node: int) -> NDArray[np.intp]:
    """Global dof of each local dof of `mapping` (in local order), the component's local node
    0 being rotor node `first_node`.

    Examples
    --------
    >>> from duhamel.rotor.dofs import global_dofs
    >>> global_dofs({"x_0": 0, "y_0": 1, "theta_y_1": 2}, first_node=3).tolist()
    [12, 13, 19]
    """
    out = np.empty(len(mapping), dtype=np.intp)
    for label, local in mapping.items():
        direction, _, node = label.rpartition("_")
        out[local] = DOFS_PER_NODE * (first_node + int(node)) + DIRECTIONS[direction]
    return out


def dof_index(node: Any, direction: Any, n_nodes: int) -> int:
    """Global index of `node`'s dof `direction` (a name of :data:`DIRECTIONS` or 0..3) on a
    rotor of `n_nodes` nodes, both checked.

    Examples
    --------
    >>> from duhamel.rotor.dofs import dof_index
    >>> dof_index(3, "theta_y", n_nodes=5), dof_index(3, 1, n_nodes=5)
    (15, 13)
    """
    if isinstance(node, bool) or not isinstance(node, int | np.integer):
        raise TypeError(f"`node` must be an integer, got {type(node).__name__}")
    if not 0 <= node < n_nodes:
        raise ValueError(f"`node` must be in [0, {n_nodes - 1}], got {node}")
    if isinstance(direction, str):
        if direction not in DIRECTIONS:
            raise ValueError(f"`direction` must be one of {list(DIRECTIONS)}, got {direction!r}")
        k = DIRECTIONS[direction]
    elif isinstance(direction, int | np.integer) and 0 <= direction < 4:
        k = int(direction)
    else:
        raise ValueError(f"`direction` must be a name or 0..3, got {direction!r}")
    return DOFS_PER_NODE * int(node) + k

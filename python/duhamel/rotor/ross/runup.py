"""Run-ups of a ROSS model: its frequency-dependent bearing and seal coefficients follow the
speed law, as a native rotor's tabulated bearings do (:mod:`duhamel.rotor._speed_table`).

Each ROSS ``BearingElement``/``SealElement`` whose coefficients depend on the frequency is
sampled with ROSS's own interpolants (``kxx_interpolated`` ...) at :data:`TABLE_POINTS`
speeds over the range the law reaches and becomes a duhamel :class:`Bearing` table (PCHIP
between the samples: the difference from ROSS's smooth spline is of order ``h^3``, checked
against ROSS below 1e-6 in tests/rotor/test_ross.py); the background carries ROSS's ``K`` and
``C`` at the initial speed, and the change along the law is the Rust ``SpeedTableBearing``
element."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from duhamel.rotor.bearing import Bearing, _speed_table
from duhamel.rotor.dofs import node_index
from duhamel.rotor.ross.dofs import RossDofs

__all__ = ["TABLE_POINTS", "cancelling", "ross_speed_tables"]

#: Samples of ROSS's coefficient curves over the range of a run-up.
TABLE_POINTS = 201
_NAMES = ("kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy")


@dataclass(frozen=True)
class RossTable(Bearing):
    """ROSS's sampled coefficient curves as a :class:`Bearing` table, checked finite only: a
    seal's direct stiffness may be negative (ROSS's compressor), which a duhamel bearing
    refuses."""

    def __post_init__(self) -> None:
        object.__setattr__(self, "node", node_index(self.node))
        object.__setattr__(self, "speeds", _speed_table(self.speeds))
        for name in _NAMES:
            arr = np.asarray(getattr(self, name), dtype=float)
            if not np.all(np.isfinite(arr)):
                raise ValueError(f"ROSS's `{name}` at node {self.node} is not finite")
            object.__setattr__(self, name, tuple(float(v) for v in arr))


def _varies(element: Any) -> bool:
    freq = getattr(element, "frequency", None)
    return freq is not None and np.ndim(freq) == 1 and len(freq) > 1


def ross_speed_tables(rotor: Any, dofs: RossDofs, law: Any, w0: float) -> list[Any]:
    """The frequency-dependent bearings and seals of ROSS's `rotor` as elements following
    `law` (initial speed `w0`), on the System's dofs `dofs`."""
    from duhamel.rotor._speed_table import SpeedTableElement

    t1 = float(getattr(law, "t1", 0.0))
    reach = np.asarray(law.omega(np.array([0.0, t1])), dtype=float)
    lo, hi = float(reach.min()), float(reach.max())
    speeds = np.linspace(lo, hi, TABLE_POINTS)
    out = []
    from duhamel.rotor.ross.magnetic import is_magnetic

    for element in getattr(rotor, "bearing_elements", ()):
        if not _varies(element) or is_magnetic(element):  # a closed loop, not a table
            continue
        if getattr(element, "n_link", None) is not None:
            raise ValueError(
                f"the ROSS bearing at node {element.n} is linked to node {element.n_link}: "
                "run-ups follow only bearings between a shaft node and the ground"
            )
        table = {}
        for name in _NAMES:
            f = getattr(element, f"{name}_interpolated")
            table[name] = [float(v) for v in np.asarray(f(speeds), dtype=float)]
        for name in ("mxx", "myy", "mxy", "myx"):
            f = getattr(element, f"{name}_interpolated", None)
            if f is not None and np.any(np.asarray(f(speeds), dtype=float) != 0.0):
                raise ValueError(
                    f"the ROSS bearing at node {element.n} has mass coefficients, which a "
                    "run-up cannot follow"
                )
        bearing = RossTable(int(element.n), speeds=speeds.tolist(), **table)
        k0, c0 = bearing.stiffness_at(w0), bearing.damping_at(w0)
        out.append(
            SpeedTableElement(
                dofs(int(element.n), "x"),
                dofs(int(element.n), "y"),
                bearing,
                law,
                tuple(map(tuple, k0.tolist())),
                tuple(map(tuple, c0.tolist())),
            )
        )
    return out


def cancelling(tables: Sequence[Any], dof_x: int, dof_y: int) -> Any:
    """The exact negative of the speed-table element on ``(dof_x, dof_y)`` among `tables`
    (the speed-table elements :func:`ross_speed_tables` made; the same table and law, every
    coefficient negated: their forces cancel bit for bit), to take a swapped bearing out of
    a run-up."""
    found = [e for e in tables if tuple(e.dofs) == (dof_x, dof_y)]
    if len(found) != 1:
        raise ValueError(
            f"the run-up has {len(found)} speed tables at dofs ({dof_x}, {dof_y}) to cancel"
        )
    e = found[0]

    def negated(rows: Any) -> Any:
        return None if rows is None else [[-v for v in row] for row in rows]

    return e.replace(
        values=negated(e.values), slopes=negated(e.slopes), k0=negated(e.k0), c0=negated(e.c0)
    )

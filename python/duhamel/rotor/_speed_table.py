"""Speed-dependent bearings in a run-up: the bearing's tabulated coefficients follow the
speed law in time, as an element (Rust ``SpeedTableBearing``: the same PCHIP or linear
interpolation as :meth:`Bearing.stiffness_at`, end values held), minus its coefficients at
the initial speed, which the background carries."""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np

from duhamel._core import SpeedTableBearing
from duhamel.rotor.bearing import Bearing, TableRangeWarning

__all__ = ["SpeedTableElement", "speed_table_elements"]

_NAMES = ("kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy")


def SpeedTableElement(  # the element of that name, from a rotor bearing
    dof_x: int, dof_y: int, bearing: Bearing, law: Any, k0: Any, c0: Any
) -> SpeedTableBearing:
    """A :class:`Bearing` with tabulated coefficients on the dofs ``(dof_x, dof_y)`` at the
    speed law `law`, minus ``k0 x + c0 x'`` (its matrices at the initial speed, 2 x 2): a
    :class:`duhamel.elements.SpeedTableBearing` with the bearing's tables and their PCHIP
    slopes (or none: linear interpolation)."""
    from scipy.interpolate import PchipInterpolator

    speeds = np.asarray(bearing.speeds, dtype=float)
    values, slopes = [], []
    for name in _NAMES:
        v = getattr(bearing, name)
        table = np.asarray(v, float) if isinstance(v, tuple) else np.full(speeds.size, float(v))
        values.append(table.tolist())
        if speeds.size > 1 and isinstance(v, tuple):
            slopes.append(PchipInterpolator(speeds, table).derivative()(speeds).tolist())
        else:
            slopes.append([0.0] * speeds.size)
    return SpeedTableBearing(
        (int(dof_x), int(dof_y)),
        speeds=speeds.tolist(),
        values=values,
        slopes=slopes if bearing.interpolation == "pchip" else None,
        speed=law,
        k0=np.asarray(k0, dtype=float),
        c0=np.asarray(c0, dtype=float),
    )


def speed_table_elements(rotor: Any, law: Any, w0: float) -> list[SpeedTableBearing]:
    """The speed-dependent bearings of `rotor` as elements along the speed law `law` (its
    initial speed `w0`, where the background takes their coefficients), with a
    :class:`TableRangeWarning` when the law leaves a bearing's table."""
    out = []
    t1 = float(getattr(law, "t1", 0.0))
    reach = np.asarray(law.omega(np.array([0.0, t1])), dtype=float)
    lo, hi = float(reach.min()), float(reach.max())
    for b in rotor.bearings:
        if not b.is_speed_dependent:
            continue
        if lo < b.speeds[0] or hi > b.speeds[-1]:
            warnings.warn(
                f"the run-up reaches {lo:g}-{hi:g} rad/s, beyond the table of the bearing at "
                f"node {b.node} ([{b.speeds[0]:g}, {b.speeds[-1]:g}] rad/s): its end values are "
                "held there",
                TableRangeWarning,
                stacklevel=3,
            )
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", TableRangeWarning)
            k0, c0 = b.stiffness_at(w0), b.damping_at(w0)
        out.append(
            SpeedTableElement(
                rotor.dof(b.node, "x"),
                rotor.dof(b.node, "y"),
                b,
                law,
                tuple(map(tuple, k0.tolist())),
                tuple(map(tuple, c0.tolist())),
            )
        )
    return out

"""Speed-dependent bearings in a run-up: the bearing's tabulated coefficients follow the
speed law in time, as an element (Rust ``SpeedTableBearing``: the same PCHIP or linear
interpolation as :meth:`Bearing.stiffness_at`, end values held), minus its coefficients at
the initial speed, which the background carries."""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np

from duhamel.elements.base import Element, TwoAxis
from duhamel.rotor.bearing import Bearing, TableRangeWarning

__all__ = ["SpeedTableElement", "speed_table_elements"]

_NAMES = ("kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy")


@dataclass(frozen=True)
class SpeedTableElement(TwoAxis, Element):
    """A :class:`Bearing` with tabulated coefficients on the dofs ``(dof_x, dof_y)`` at the
    speed law `law`, minus ``k0 x + c0 x'`` (its matrices at the initial speed, 2 x 2)."""

    dof_x: int
    dof_y: int
    bearing: Bearing
    law: Any
    k0: tuple[tuple[float, ...], ...]
    c0: tuple[tuple[float, ...], ...]

    def _tangent_bound(self) -> tuple[float, float] | None:
        # PCHIP and linear interpolation stay within each entry's tabulated values: the
        # entrywise largest difference bounds the Frobenius norm at any speed.
        out = []
        for names, ref in ((("kxx", "kxy", "kyx", "kyy"), self.k0),
                           (("cxx", "cxy", "cyx", "cyy"), self.c0)):  # fmt: skip
            r = np.asarray(ref, dtype=np.float64).ravel()
            worst = [
                np.abs(np.asarray(getattr(self.bearing, name), dtype=np.float64) - r[i]).max()
                for i, name in enumerate(names)
            ]
            out.append(float(np.sqrt(np.sum(np.square(worst)))))
        return out[0], out[1]

    def _spec(self) -> tuple:
        from scipy.interpolate import PchipInterpolator

        b = self.bearing
        speeds = np.asarray(b.speeds, dtype=float)
        values, slopes = [], []
        for name in _NAMES:
            v = getattr(b, name)
            table = np.asarray(v, float) if isinstance(v, tuple) else np.full(speeds.size, float(v))
            values.append(table.tolist())
            if speeds.size > 1 and isinstance(v, tuple):
                slopes.append(PchipInterpolator(speeds, table).derivative()(speeds).tolist())
            else:
                slopes.append([0.0] * speeds.size)
        table_spec = (
            "speed_table", int(self.dof_x), int(self.dof_y), speeds.tolist(), values,
            slopes if b.interpolation == "pchip" else None, self.law._spec(),
        )  # fmt: skip
        return ("shifted", table_spec, np.array(self.k0), np.array(self.c0))


def speed_table_elements(rotor: Any, law: Any, w0: float) -> list[SpeedTableElement]:
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

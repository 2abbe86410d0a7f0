"""A ground-motion record (:class:`GroundMotion`), its units and the quantities read off it;
exported from :mod:`duhamel.records`."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.validate import as_float_array, finite_float, positive_float
from duhamel.loads import BaseAcceleration

__all__ = ["UNITS", "G", "GroundMotion"]

#: Standard gravity, m/s^2.
G = 9.80665

#: Acceleration units understood by the readers, with their factor to m/s^2.
UNITS: dict[str, float] = {
    "g": G,
    "m/s^2": 1.0,
    "cm/s^2": 0.01,
    "gal": 0.01,
    "mm/s^2": 0.001,
    "ft/s^2": 0.3048,
    "in/s^2": 0.0254,
}

_ALIASES = {
    "m/s/s": "m/s^2",
    "m/s2": "m/s^2",
    "m/sec/sec": "m/s^2",
    "m/sec^2": "m/s^2",
    "cm/s/s": "cm/s^2",
    "cm/s2": "cm/s^2",
    "cm/sec/sec": "cm/s^2",
    "cm/sec^2": "cm/s^2",
    "cm/sec2": "cm/s^2",
    "mm/s/s": "mm/s^2",
    "mm/s2": "mm/s^2",
    "mm/sec/sec": "mm/s^2",
    "ft/s/s": "ft/s^2",
    "ft/s2": "ft/s^2",
    "ft/sec/sec": "ft/s^2",
    "in/s/s": "in/s^2",
    "in/s2": "in/s^2",
    "in/sec/sec": "in/s^2",
    "gals": "gal",
}


def _unit(units: str, name: str = "units") -> str:
    """The canonical name of an acceleration unit, or a ValueError naming `name`."""
    if not isinstance(units, str):
        raise TypeError(f"`{name}` must be a string such as 'g' or 'cm/s^2', got {units!r}")
    key = units.strip().lower().replace(" ", "")
    key = _ALIASES.get(key, key)
    if key not in UNITS:
        raise ValueError(f"`{name}` must be one of {sorted(UNITS)} (or an alias), got {units!r}")
    return key


def _finite(values: NDArray[np.float64], what: str) -> NDArray[np.float64]:
    """`values` if finite, else a ValueError: the record's `what` is beyond the double
    range (amplitudes or a duration of no physical record)."""
    if not np.all(np.isfinite(values)):
        raise ValueError(
            f"the record's {what} overflows the double range: rescale its amplitudes (`a`) "
            "or its step (`dt`)"
        )
    return values


@dataclass(frozen=True, eq=False)
class GroundMotion:
    """One component of a ground-motion record, sampled uniformly from ``t = 0``.

    Parameters
    ----------
    a : array_like, shape (n,)
        Acceleration samples in `units` (converted to m/s^2 and stored as ``a``).
    dt : float
        Sampling interval in s.
    units : str, optional
        Units of `a` as given: ``'m/s^2'`` (default), ``'g'``, ``'cm/s^2'`` (``'gal'``),
        ``'mm/s^2'``, ``'ft/s^2'``, ``'in/s^2'``.
    name : str, optional
        A label (the record and component, e.g. ``'RSN6_IMPVALL.I_I-ELC180'``).
    metadata : dict, optional
        Anything else of the source (header lines, station, file path).

    Attributes
    ----------
    a : ndarray
        Acceleration in m/s^2.
    t : ndarray
        Sample times ``k dt`` in s.

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> from duhamel.records import GroundMotion
    >>> gm = GroundMotion([0.0, 0.1, -0.2, 0.0], dt=0.02, units="g")
    >>> gm.scaled(2.0).pga / gm.pga
    2.0
    >>> load = gm.as_load(np.ones(3))  # a BaseAcceleration on a 3-dof shear building
    """

    a: NDArray[np.float64]
    dt: float
    units: str = "m/s^2"
    name: str = ""
    metadata: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        units = _unit(self.units)
        a = as_float_array(self.a, "a", ndim=1)
        if a.size < 2:
            raise ValueError(f"`a` must have at least 2 samples, got {a.size}")
        dt = positive_float(self.dt, "dt")
        if not np.isfinite((a.size - 1) * dt):
            raise ValueError(
                f"`dt` = {dt!r} s: the record's {a.size} samples last beyond the double range"
            )
        a = a * UNITS[units]
        if not np.all(np.isfinite(a)):
            raise ValueError(f"`a` in {units} overflows when converted to m/s^2")
        a.setflags(write=False)
        object.__setattr__(self, "a", a)
        object.__setattr__(self, "dt", dt)
        object.__setattr__(self, "units", units)
        object.__setattr__(self, "name", str(self.name))
        object.__setattr__(self, "metadata", dict(self.metadata))

    def __repr__(self) -> str:
        return (
            f"GroundMotion(name={self.name!r}, n={self.a.size}, dt={self.dt:g} s, "
            f"duration={self.duration:g} s, pga={self.pga / G:.4g} g)"
        )

    @property
    def t(self) -> NDArray[np.float64]:
        """Sample times in s, ``k dt``."""
        return self.dt * np.arange(self.a.size, dtype=np.float64)

    @property
    def duration(self) -> float:
        """Time of the last sample, ``(n - 1) dt``, in s."""
        return float((self.a.size - 1) * self.dt)

    @property
    def pga(self) -> float:
        """Peak ground acceleration ``max |a|`` in m/s^2."""
        return float(np.max(np.abs(self.a)))

    @property
    def velocity(self) -> NDArray[np.float64]:
        """Ground velocity in m/s at the samples: the exact integral of the piecewise-linear
        acceleration from rest (no baseline correction)."""
        v = np.empty_like(self.a)
        v[0] = 0.0
        with np.errstate(over="ignore", invalid="ignore"):
            np.cumsum(0.5 * self.dt * self.a[1:] + 0.5 * self.dt * self.a[:-1], out=v[1:])
        return _finite(v, "velocity")

    @property
    def displacement(self) -> NDArray[np.float64]:
        """Ground displacement in m at the samples, exact for the piecewise-linear
        acceleration from rest: ``d_{k+1} = d_k + v_k dt + dt^2 (2 a_k + a_{k+1}) / 6``."""
        v, a, h = self.velocity, self.a, self.dt
        d = np.empty_like(a)
        d[0] = 0.0
        with np.errstate(over="ignore", invalid="ignore"):
            np.cumsum(v[:-1] * h + h * (h * (2.0 * a[:-1] + a[1:]) / 6.0), out=d[1:])
        return _finite(d, "displacement")

    @property
    def pgv(self) -> float:
        """Peak ground velocity in m/s (of :attr:`velocity`, at the samples)."""
        return float(np.max(np.abs(self.velocity)))

    @property
    def pgd(self) -> float:
        """Peak ground displacement in m (of :attr:`displacement`, at the samples)."""
        return float(np.max(np.abs(self.displacement)))

    def husid(self) -> NDArray[np.float64]:
        """Cumulative Arias intensity at the samples, in m/s (the Husid plot is this divided
        by :attr:`arias_intensity`); the integral of ``a^2`` is exact per segment."""
        scale, unit = self._husid_scaled()
        with np.errstate(over="ignore", invalid="ignore"):
            out = unit * scale
        return _finite(out, "cumulative Arias intensity")

    def _husid_scaled(self) -> tuple[float, NDArray[np.float64]]:
        """``(s, h)`` with the cumulative Arias intensity ``s * h``: ``h`` computed from the
        record divided by its peak, so that no square overflows (records beyond 1e154)."""
        peak = float(np.max(np.abs(self.a)))
        if peak == 0.0:
            return 0.0, np.zeros_like(self.a)
        b = self.a / peak
        b0, b1 = b[:-1], b[1:]
        h = np.empty_like(b)
        h[0] = 0.0
        np.cumsum((b0 * b0 + b0 * b1 + b1 * b1) / 3.0, out=h[1:])
        return np.pi / (2.0 * G) * self.dt * peak * peak, h

    @property
    def arias_intensity(self) -> float:
        """Arias intensity ``pi / (2 g) * integral a^2 dt`` in m/s (a ValueError when it is
        beyond the double range)."""
        scale, h = self._husid_scaled()
        with np.errstate(over="ignore"):
            out = float(h[-1] * scale) if scale else 0.0
        return float(_finite(np.array([out]), "Arias intensity")[0])

    def significant_duration(self, start: float = 0.05, end: float = 0.95) -> float:
        """Time in s between the instants the Husid curve reaches `start` and `end` of the
        Arias intensity (D5-95 by default; D5-75 with ``end=0.75``), linear between samples.

        Examples
        --------
        >>> import numpy as np
        >>> from duhamel.records import GroundMotion
        >>> gm = GroundMotion(np.ones(1001), dt=0.01)  # uniform intensity over 10 s
        >>> round(gm.significant_duration(), 9)
        9.0
        """
        start, end = finite_float(start, "start"), finite_float(end, "end")
        if not (0.0 <= start < end <= 1.0):
            raise ValueError(
                f"`start` and `end` must satisfy 0 <= start < end <= 1, got {start}, {end}"
            )
        _, h = self._husid_scaled()
        if h[-1] <= 0.0:
            raise ValueError(f"record {self.name!r} is zero: it has no significant duration")
        h = h / h[-1]
        t0, t1 = np.interp([start, end], h, self.t)
        return float(t1 - t0)

    def scaled(self, factor: float) -> GroundMotion:
        """The record multiplied by `factor` (name and metadata kept, the factor recorded
        in ``metadata['scale']``)."""
        f = finite_float(factor, "factor")
        meta = dict(self.metadata)
        meta["scale"] = meta.get("scale", 1.0) * f
        with np.errstate(over="ignore"):
            a = self.a * f
        if not np.all(np.isfinite(a)):
            raise ValueError(f"`factor` = {f!r} scales the record beyond the double range")
        return GroundMotion(a, self.dt, "m/s^2", self.name, meta)

    def as_load(self, direction_vector: ArrayLike) -> BaseAcceleration:
        """The :class:`~duhamel.loads.BaseAcceleration` of this record on the dofs moved by
        `direction_vector` (the influence vector ``r``: ones on the horizontal dofs of a
        shear building along this component)."""
        return BaseAcceleration(direction_vector, self.t, self.a)

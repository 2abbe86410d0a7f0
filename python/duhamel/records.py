"""Ground-motion records: reading PEER NGA ``.AT2`` and text files, and the quantities
earthquake engineers read off a record (PGA, PGV, PGD, Arias intensity, significant
duration).

A :class:`GroundMotion` holds the acceleration in m/s^2 at uniform samples ``t = k dt``,
whatever the units of its source (kept in ``units``). Between samples the acceleration is
linear, as everywhere in duhamel (:class:`duhamel.loads.BaseAcceleration`), and every
derived quantity is exact for that piecewise-linear record: velocity and displacement are
its exact integrals, the Arias intensity the exact integral of ``a^2``.

Examples
--------
>>> import numpy as np
>>> from duhamel.records import GroundMotion
>>> gm = GroundMotion(np.sin(np.linspace(0.0, 20.0, 2001)), dt=0.01, units="g", name="demo")
>>> round(gm.pga / 9.80665, 6), gm.duration
(1.0, 20.0)
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.validate import as_float_array
from duhamel.loads import BaseAcceleration

__all__ = ["UNITS", "G", "GroundMotion", "read_at2", "read_text"]

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
        dt = float(self.dt)
        if not (np.isfinite(dt) and dt > 0.0):
            raise ValueError(f"`dt` must be a positive finite number of seconds, got {self.dt!r}")
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
        np.cumsum(0.5 * self.dt * (self.a[1:] + self.a[:-1]), out=v[1:])
        return v

    @property
    def displacement(self) -> NDArray[np.float64]:
        """Ground displacement in m at the samples, exact for the piecewise-linear
        acceleration from rest: ``d_{k+1} = d_k + v_k dt + dt^2 (2 a_k + a_{k+1}) / 6``."""
        v, a, h = self.velocity, self.a, self.dt
        d = np.empty_like(a)
        d[0] = 0.0
        np.cumsum(v[:-1] * h + h * h * (2.0 * a[:-1] + a[1:]) / 6.0, out=d[1:])
        return d

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
        a0, a1 = self.a[:-1], self.a[1:]
        seg = self.dt * (a0 * a0 + a0 * a1 + a1 * a1) / 3.0
        out = np.empty_like(self.a)
        out[0] = 0.0
        np.cumsum(np.pi / (2.0 * G) * seg, out=out[1:])
        return out

    @property
    def arias_intensity(self) -> float:
        """Arias intensity ``pi / (2 g) * integral a^2 dt`` in m/s."""
        return float(self.husid()[-1])

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
        if not (0.0 <= start < end <= 1.0):
            raise ValueError(
                f"`start` and `end` must satisfy 0 <= start < end <= 1, got {start}, {end}"
            )
        h = self.husid()
        if h[-1] <= 0.0:
            raise ValueError(f"record {self.name!r} is zero: it has no significant duration")
        h = h / h[-1]
        t0, t1 = np.interp([start, end], h, self.t)
        return float(t1 - t0)

    def scaled(self, factor: float) -> GroundMotion:
        """The record multiplied by `factor` (name and metadata kept, the factor recorded
        in ``metadata['scale']``)."""
        f = float(factor)
        if not np.isfinite(f):
            raise ValueError(f"`factor` must be finite, got {factor!r}")
        meta = dict(self.metadata)
        meta["scale"] = meta.get("scale", 1.0) * f
        return GroundMotion(self.a * f, self.dt, "m/s^2", self.name, meta)

    def as_load(self, direction_vector: ArrayLike) -> BaseAcceleration:
        """The :class:`~duhamel.loads.BaseAcceleration` of this record on the dofs moved by
        `direction_vector` (the influence vector ``r``: ones on the horizontal dofs of a
        shear building along this component)."""
        return BaseAcceleration(direction_vector, self.t, self.a)


# --- readers ----------------------------------------------------------------------------

#: A Fortran real: optional sign, digits with an optional point, optional E/D exponent.
_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[EeDd][-+]?\d+)?")
_BLANK = re.compile(r"[\s,]*")


def _numbers(line: str, lineno: int, path: str) -> list[float]:
    """The numbers of one data line (fields may touch: ``-.1E-02-.2E-02``), or a ValueError
    naming the file, line and column of the first thing that is not a number."""
    out: list[float] = []
    pos = _BLANK.match(line, 0).end()  # type: ignore[union-attr]
    while pos < len(line):
        m = _NUMBER.match(line, pos)
        if m is None:
            raise ValueError(
                f"{path}, line {lineno}, column {pos + 1}: expected a number, got "
                f"{line[pos:].split()[0]!r}"
            )
        out.append(float(m.group().replace("D", "E").replace("d", "e")))
        pos = _BLANK.match(line, m.end()).end()  # type: ignore[union-attr]
    return out


_NEW_HEADER = re.compile(r"NPTS\s*=\s*(\d+)\s*,?\s*DT\s*=\s*([-+.\dEe]+)", re.IGNORECASE)
_OLD_HEADER = re.compile(r"^\s*(\d+)\s+([-+.\dEe]+)\s+.*NPTS\s*,\s*DT", re.IGNORECASE)
_UNITS = re.compile(r"UNITS\s+OF\s+(\S+)", re.IGNORECASE)


def read_at2(path: str | os.PathLike[str], *, units: str | None = None) -> GroundMotion:
    """Read a PEER NGA acceleration record (``.AT2``).

    Both header styles are read: NGA-West2's ``NPTS=  7998, DT=   .0050 SEC`` and the older
    ``7998   .0050   NPTS, DT``, on the fourth line; the units come from the third line
    (``... IN UNITS OF G``) unless `units` overrides them. Values may be separated by any
    spacing or touch (``-.1E-02-.2E-02``); the last line may be partial.

    Parameters
    ----------
    path : str or path-like
        The file.
    units : str, optional
        Units of the values, for files whose header does not say (``'g'``, ``'cm/s^2'``...).

    Returns
    -------
    GroundMotion
        With ``name`` the file's stem, ``metadata`` the header lines (``'title'``,
        ``'event'``, ``'description'``), ``'npts'`` and ``'path'``.

    Raises
    ------
    ValueError
        A malformed file (the line and column are named), a velocity or displacement file,
        or a number of values different from NPTS.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from duhamel.records import read_at2
    >>> text = ("PEER NGA STRONG MOTION DATABASE RECORD\\nDEMO 1/1/00, STATION, 000\\n"
    ...         "ACCELERATION TIME SERIES IN UNITS OF G\\nNPTS=    3, DT=   .0100 SEC\\n"
    ...         "  .1000E-01 -.2000E-01  .0000E+00\\n")
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "DEMO000.AT2"
    >>> _ = p.write_text(text)
    >>> gm = read_at2(p)
    >>> gm.name, gm.dt, round(gm.pga / 9.80665, 6)
    ('DEMO000', 0.01, 0.02)
    """
    p = os.fspath(path)
    with open(p, encoding="latin-1") as fh:
        lines = fh.read().splitlines()
    if len(lines) < 4:
        raise ValueError(f"{p}: a PEER .AT2 file has 4 header lines, the file has {len(lines)}")
    kind = lines[2].upper()
    if "VELOCITY" in kind or "DISPLACEMENT" in kind:
        raise ValueError(f"{p}, line 3: not an acceleration record ({lines[2].strip()!r})")
    m = _NEW_HEADER.search(lines[3]) or _OLD_HEADER.search(lines[3])
    if m is None:
        raise ValueError(
            f"{p}, line 4: expected 'NPTS= <n>, DT= <dt> SEC' or '<n> <dt> NPTS, DT', got "
            f"{lines[3].strip()!r}"
        )
    npts, dt = int(m.group(1)), float(m.group(2))
    if units is None:
        found = _UNITS.search(lines[2])
        if found is None:
            raise ValueError(
                f"{p}, line 3: the units are not given ('... UNITS OF G'); pass `units`"
            )
        try:
            units = _unit(found.group(1).rstrip(".,"), "units")
        except ValueError:
            raise ValueError(
                f"{p}, line 3: unknown units {found.group(1)!r}; pass `units` (one of "
                f"{sorted(UNITS)})"
            ) from None
    values: list[float] = []
    for lineno, line in enumerate(lines[4:], start=5):
        values.extend(_numbers(line, lineno, p))
    if len(values) != npts:
        raise ValueError(
            f"{p}: the header (line 4) announces NPTS = {npts} values, the file has {len(values)}"
        )
    meta = {
        "title": lines[0].strip(),
        "event": lines[1].strip(),
        "description": lines[2].strip(),
        "npts": npts,
        "path": p,
    }
    return GroundMotion(np.array(values), dt, units, os.path.splitext(os.path.basename(p))[0], meta)


def read_text(
    path: str | os.PathLike[str],
    *,
    units: str,
    dt: float | None = None,
    time_column: int | None = None,
    column: int | None = None,
    skip_rows: int = 0,
    flatten: bool = False,
    name: str | None = None,
) -> GroundMotion:
    """Read an acceleration record from a text file of numbers.

    Lines starting with ``#`` or ``%`` and blank lines are skipped; fields are separated by
    spaces, tabs or commas. Three layouts:

    * one column of values, with `dt`;
    * a table of columns: the acceleration is column `column` (0-based); the time is either
      `dt` or column `time_column`, whose spacing must be uniform (to 1e-6 of ``dt``);
    * ``flatten=True``: values row after row, several per line (as in the body of a PEER
      file), with `dt`.

    Parameters
    ----------
    path : str or path-like
        The file.
    units : str
        Units of the values (``'g'``, ``'m/s^2'``, ``'cm/s^2'``...).
    dt : float, optional
        Sampling interval in s (unless `time_column` is given).
    time_column, column : int, optional
        0-based columns of the time and of the acceleration (`column` defaults to the only
        column, or to the column after `time_column` in a two-column file).
    skip_rows : int, optional
        Header lines to skip before the data.
    flatten : bool, optional
        Read the values row by row as one series.
    name : str, optional
        Defaults to the file's stem.

    Returns
    -------
    GroundMotion

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from duhamel.records import read_text
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "rec.txt"
    >>> _ = p.write_text("# t a\\n0.00 0.0\\n0.01 12.5\\n0.02 -3.0\\n")
    >>> gm = read_text(p, units="cm/s^2", time_column=0)
    >>> gm.dt, gm.a.tolist()
    (0.01, [0.0, 0.125, -0.03])
    """
    p = os.fspath(path)
    units = _unit(units)
    if (dt is None) == (time_column is None):
        raise ValueError("pass exactly one of `dt` and `time_column`")
    if flatten and time_column is not None:
        raise ValueError("`flatten=True` reads values only: pass `dt`, not `time_column`")
    with open(p, encoding="latin-1") as fh:
        lines = fh.read().splitlines()
    rows: list[tuple[int, list[float]]] = []
    for lineno, line in enumerate(lines[skip_rows:], start=skip_rows + 1):
        s = line.strip()
        if not s or s[0] in "#%":
            continue
        rows.append((lineno, _numbers(line, lineno, p)))
    if not rows:
        raise ValueError(f"{p}: no data")
    stem = os.path.splitext(os.path.basename(p))[0] if name is None else name
    meta: dict[str, Any] = {"path": p}
    if flatten:
        values = np.array([v for _, r in rows for v in r])
        return GroundMotion(values, float(dt), units, stem, meta)  # type: ignore[arg-type]
    width = len(rows[0][1])
    for lineno, r in rows:
        if len(r) != width:
            raise ValueError(
                f"{p}, line {lineno}: {len(r)} columns where the first data line "
                f"(line {rows[0][0]}) has {width}"
            )
    table = np.array([r for _, r in rows])
    if column is None:
        others = [c for c in range(width) if c != time_column]
        if len(others) != 1:
            raise ValueError(f"{p} has {width} columns: pass `column`, the acceleration's")
        column = others[0]
    for label, c in (("column", column), ("time_column", time_column)):
        if c is not None and not (0 <= c < width):
            raise ValueError(f"`{label}` = {c} is not a column of {p} (0..{width - 1})")
    if time_column is not None:
        t = table[:, time_column]
        steps = np.diff(t)
        if t.size < 2 or not np.all(steps > 0):
            raise ValueError(f"{p}: column {time_column} (`time_column`) must increase")
        bad = np.flatnonzero(np.abs(steps - steps[0]) > 1e-6 * steps[0])
        if bad.size:
            i = int(bad[0])
            raise ValueError(
                f"{p}, line {rows[i + 1][0]}: time step {steps[i]:g} s differs from the first "
                f"step {steps[0]:g} s: the record must be sampled uniformly (resample it first)"
            )
        dt = float((t[-1] - t[0]) / (t.size - 1))
        if t[0] != 0.0:
            meta["t0"] = float(t[0])
    return GroundMotion(table[:, column], float(dt), units, stem, meta)  # type: ignore[arg-type]

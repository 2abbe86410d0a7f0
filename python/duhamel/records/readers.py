"""Readers of ground-motion records: PEER NGA ``.AT2`` files and text tables (one or more
columns, optionally with a time column); exported from :mod:`duhamel.records`."""

from __future__ import annotations

import os
import re
from typing import Any, overload

import numpy as np

from duhamel._engine.validate import _int_scalar, positive_float
from duhamel.records.motion import UNITS, GroundMotion, _unit
from duhamel.records.pair import GroundMotionPair

PathLike = str | os.PathLike[str]

__all__ = ["read_at2", "read_text"]

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
        value = float(m.group().replace("D", "E").replace("d", "e"))
        if not np.isfinite(value):
            raise ValueError(
                f"{path}, line {lineno}, column {pos + 1}: {m.group()!r} overflows the double range"
            )
        out.append(value)
        pos = _BLANK.match(line, m.end()).end()  # type: ignore[union-attr]
    return out


#: The header's numbers: NPTS an integer, DT a Fortran real (``5.0D-03`` as well as ``.0050``).
_NEW_HEADER = re.compile(r"NPTS\s*=\s*(\d+)\s*,?\s*DT\s*=\s*([-+.\dEeDd]+)", re.IGNORECASE)
_OLD_HEADER = re.compile(r"^\s*(\d+)\s+([-+.\dEeDd]+)\s+.*NPTS\s*,\s*DT", re.IGNORECASE)
_UNITS = re.compile(r"UNITS\s+OF\s+(\S+)", re.IGNORECASE)


def _header_dt(token: str, path: str) -> float:
    """The DT of an AT2 header (a Fortran real, ``D`` exponents included), or a ValueError
    naming the file, line and field."""
    full = _NUMBER.fullmatch(token)
    value = float(token.replace("D", "E").replace("d", "e")) if full else float("nan")
    if not (np.isfinite(value) and value > 0.0):
        raise ValueError(f"{path}, line 4: DT must be a positive number of seconds, got {token!r}")
    return value


def _count(value: Any, name: str) -> int:
    """A non-negative integer argument (a bool, float or negative number refused)."""
    out = _int_scalar(value, name)
    if out < 0:
        raise ValueError(f"`{name}` must be a non-negative integer, got {out}")
    return out


def _column(value: Any, name: str) -> int | None:
    return None if value is None else _count(value, name)


@overload
def read_at2(path: PathLike, second: None = None, *, units: str | None = None) -> GroundMotion: ...


@overload
def read_at2(path: PathLike, second: PathLike, *, units: str | None = None) -> GroundMotionPair: ...


def read_at2(
    path: PathLike, second: PathLike | None = None, *, units: str | None = None
) -> GroundMotion | GroundMotionPair:
    """Read a PEER NGA acceleration record (``.AT2``), or two of them as a
    :class:`~duhamel.records.GroundMotionPair` (``read_at2(h1_path, h2_path)``).

    Both header styles are read: NGA-West2's ``NPTS=  7998, DT=   .0050 SEC`` and the older
    ``7998   .0050   NPTS, DT``, on the fourth line; the units come from the third line
    (``... IN UNITS OF G``) unless `units` overrides them. Values may be separated by any
    spacing or touch (``-.1E-02-.2E-02``); the last line may be partial.

    Parameters
    ----------
    path : str or path-like
        The file.
    second : str or path-like, optional
        The other horizontal component's file: the result is then a pair.
    units : str, optional
        Units of the values, for files whose header does not say (``'g'``, ``'cm/s^2'``...).

    Returns
    -------
    GroundMotion or GroundMotionPair
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
    if second is not None:
        return GroundMotionPair(_read_one(path, units), _read_one(second, units))
    return _read_one(path, units)


def _read_one(path: PathLike, units: str | None) -> GroundMotion:
    """One .AT2 file (see :func:`read_at2`)."""
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
    npts, dt = int(m.group(1)), _header_dt(m.group(2), p)
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
        Header lines to skip before the data (>= 0).
    flatten : bool, optional
        Read the values row by row as one series.
    name : str, optional
        Defaults to the file's stem.

    Returns
    -------
    GroundMotion

    Raises
    ------
    TypeError
        `dt`, `skip_rows`, `column` or `time_column` of the wrong kind (a string, a bool, a
        float for a column), `flatten` not a bool.
    ValueError
        A negative `skip_rows` or column, `column` equal to `time_column`, a column the
        file does not have, a malformed file (its line and column are named).

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
    skip_rows = _count(skip_rows, "skip_rows")
    column, time_column = _column(column, "column"), _column(time_column, "time_column")
    if not isinstance(flatten, bool | np.bool_):
        raise TypeError(f"`flatten` must be True or False, got {flatten!r}")
    if column is not None and column == time_column:
        raise ValueError(f"`column` and `time_column` are both {column}: pass different columns")
    if dt is not None:
        dt = positive_float(dt, "dt")
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
        return GroundMotion(values, dt, units, stem, meta)  # type: ignore[arg-type]
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
    return GroundMotion(table[:, column], dt, units, stem, meta)  # type: ignore[arg-type]

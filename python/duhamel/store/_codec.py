"""Plain data in a zarr store: nested values as JSON with their arrays beside it, and the
checkpoint record.

Nothing read here is code: a tree holds numbers, strings, booleans, None, lists, tuples
(``{"$tuple": [...]}``), dicts and arrays (``{"$array": name}``, a numeric zarr array of the
group; complex arrays as two real ones, ``{"$complex": [re, im]}``). Decoding builds only
those values. zarr itself is imported by the callers (:mod:`duhamel.store._run`).
"""

from __future__ import annotations

import json
import struct
import zlib
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["Checkpoint", "StoreError", "decode", "encode", "pack", "unpack"]


class StoreError(ValueError):
    """A store that cannot be read: missing parts, a damaged record, an unknown format."""


def encode(value: Any, group: Any, prefix: str = "a") -> Any:
    """`value` as JSON-able data; its arrays are written to the zarr `group` (named
    ``prefix0``, ``prefix1``...). Raises TypeError for anything that is not plain data."""
    counter = [0]

    def array(a: NDArray) -> str:
        name = f"{prefix}{counter[0]}"
        counter[0] += 1
        a = np.ascontiguousarray(a)
        chunks = tuple(max(1, s) for s in a.shape) if a.ndim else "auto"
        stored = group.create_array(name, shape=a.shape, dtype=a.dtype, chunks=chunks)
        if a.size:
            stored[...] = a
        return name

    def walk(v: Any) -> Any:
        if v is None or isinstance(v, bool | str):
            return v
        if isinstance(v, np.bool_):
            return bool(v)
        if isinstance(v, int | np.integer):
            return int(v)
        if isinstance(v, float | np.floating):
            return float(v)
        if isinstance(v, np.ndarray):
            if v.dtype.kind == "c":
                return {"$complex": [array(v.real), array(v.imag)]}
            if v.dtype.kind not in "biuf":
                raise TypeError(f"an array of dtype {v.dtype} is not plain data")
            return {"$array": array(v)}
        if isinstance(v, tuple):
            return {"$tuple": [walk(x) for x in v]}
        if isinstance(v, list):
            return [walk(x) for x in v]
        if isinstance(v, dict):
            if not all(isinstance(k, str) and not k.startswith("$") for k in v):
                raise TypeError("dict keys must be strings not starting with '$'")
            return {k: walk(x) for k, x in v.items()}
        raise TypeError(f"a {type(v).__name__} is not plain data (numbers, strings, arrays)")

    return walk(value)


def decode(data: Any, group: Any) -> Any:
    """The value :func:`encode` wrote (tuples, arrays and all); builds only data."""

    def array(name: Any) -> NDArray:
        if not isinstance(name, str) or name not in group:
            raise StoreError(f"the store's model refers to a missing array {name!r}")
        return np.asarray(group[name][...])

    def walk(v: Any) -> Any:
        if isinstance(v, list):
            return [walk(x) for x in v]
        if isinstance(v, dict):
            if "$array" in v:
                return array(v["$array"])
            if "$complex" in v:
                re, im = v["$complex"]
                return array(re) + 1j * array(im)
            if "$tuple" in v:
                return tuple(walk(x) for x in v["$tuple"])
            return {k: walk(x) for k, x in v.items()}
        return v

    return walk(data)


def dumps(value: Any) -> str:
    """JSON text (non-finite floats as JSON5-style ``Infinity``/``NaN``, which
    :func:`json.loads` reads back)."""
    return json.dumps(value, allow_nan=True, separators=(",", ":"))


#: Record layout: magic, then the unsigned counts, the wall time, the state lengths.
_MAGIC = b"DUHCKPT1"
_HEAD = struct.Struct("<8s8Qd2Q")
_NO_STATE = 2**64 - 1


@dataclass(frozen=True)
class Checkpoint:
    """Where a run stands: `step` (grid point) with `rows` saved rows committed before it,
    the modal end state (``q | v``, or ``Re eta | Im eta``), the elements' committed
    variables (None without hysteretic elements) and the counts of the work done so far."""

    seq: int
    step: int
    rows: int
    state: NDArray[np.float64]
    element_state: NDArray[np.float64] | None
    newton_iterations: int = 0
    closed_form_steps: int = 0
    factorizations: int = 0
    subdivided_steps: int = 0
    subdivision_depth: int = 0
    wall_time: float = 0.0


def pack(c: Checkpoint) -> NDArray[np.uint8]:
    """The checkpoint as bytes ending with their CRC-32 (a torn write is detected)."""
    state = np.ascontiguousarray(c.state, dtype="<f8")
    elems = None if c.element_state is None else np.ascontiguousarray(c.element_state, "<f8")
    head = _HEAD.pack(
        _MAGIC,
        c.seq,
        c.step,
        c.rows,
        c.newton_iterations,
        c.closed_form_steps,
        c.factorizations,
        c.subdivided_steps,
        c.subdivision_depth,
        c.wall_time,
        state.size,
        _NO_STATE if elems is None else elems.size,
    )
    body = head + state.tobytes() + (b"" if elems is None else elems.tobytes())
    return np.frombuffer(body + struct.pack("<I", zlib.crc32(body)), dtype=np.uint8).copy()


def unpack(raw: NDArray[np.uint8]) -> Checkpoint | None:
    """The checkpoint in `raw`, or None when it is not a whole, intact record."""
    data = bytes(np.asarray(raw, dtype=np.uint8))
    if len(data) < _HEAD.size + 4:
        return None
    body, (crc,) = data[:-4], struct.unpack("<I", data[-4:])
    if zlib.crc32(body) != crc or not body.startswith(_MAGIC):
        return None
    _magic, seq, step, rows, newton, closed, fact, subd, depth, wall, n_state, n_el = (
        _HEAD.unpack_from(body)
    )
    n_el_real = 0 if n_el == _NO_STATE else n_el
    if len(body) != _HEAD.size + 8 * (n_state + n_el_real):
        return None
    floats = np.frombuffer(body, dtype="<f8", offset=_HEAD.size).astype(np.float64)
    return Checkpoint(
        seq=seq,
        step=step,
        rows=rows,
        state=floats[:n_state].copy(),
        element_state=None if n_el == _NO_STATE else floats[n_state:].copy(),
        newton_iterations=newton,
        closed_form_steps=closed,
        factorizations=fact,
        subdivided_steps=subd,
        subdivision_depth=depth,
        wall_time=wall,
    )

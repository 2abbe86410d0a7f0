"""Plain data in a zarr store: nested values as JSON with their arrays beside it, and the
checkpoint record.

Nothing read here is code: a tree holds numbers, strings, booleans, None, lists, tuples
(``{"$tuple": [...]}``), dicts and arrays (``{"$array": name}``, a numeric zarr array of the
group; complex arrays as two real ones, ``{"$complex": [re, im]}``). Decoding builds only
those values. zarr itself is imported by the callers (:mod:`duhamel.store._run`).
"""

from __future__ import annotations

import hashlib
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


#: Record layouts: magic, then the unsigned counts, the wall time, the state lengths; format 3
#: adds the carry's length, the store's identity and the chain of the rows it commits, and
#: seals the record with a digest keyed by the identity before its CRC-32.
_MAGIC = b"DUHCKPT1"
_HEAD = struct.Struct("<8s8Qd2Q")
_MAGIC2 = b"DUHCKPT2"
_HEAD2 = struct.Struct("<8s8Qd3Q16s16s")
_SEAL = 16
_NO_STATE = 2**64 - 1


@dataclass(frozen=True)
class Checkpoint:
    """Where a run stands: `step` (grid point) with `rows` saved rows committed before it,
    the modal end state (``q | v``, or ``Re eta | Im eta``), the elements' committed
    variables (None without hysteretic elements) and the counts of the work done so far.

    Format 3 ties it to its store: `store` (the store's identity, 16 bytes), `chain` (the
    digest of the manifest rows of the chunks holding its `rows`), `carry` (the energy
    integrals' totals, None without ``energy``); `sealed` says whether the record's seal
    (a digest keyed by `store`) matches: False for a record rewritten by hand with its CRC
    recomputed. A format-2 record has an empty `store` and `chain`."""

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
    store: bytes = b""
    chain: bytes = b""
    carry: NDArray[np.float64] | None = None
    sealed: bool = True


def _seal(body: bytes, key: bytes) -> bytes:
    return hashlib.blake2b(body, key=key, digest_size=_SEAL, person=b"duhamel-ckpt").digest()


def pack(c: Checkpoint) -> NDArray[np.uint8]:
    """The checkpoint as bytes ending with their CRC-32 (a torn write is detected); with a
    `store` identity the format-3 record, sealed, else the format-2 one."""
    state = np.ascontiguousarray(c.state, dtype="<f8")
    elems = None if c.element_state is None else np.ascontiguousarray(c.element_state, "<f8")
    counts = (
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
    parts = [state.tobytes(), b"" if elems is None else elems.tobytes()]
    if not c.store:
        body = _HEAD.pack(_MAGIC, *counts) + b"".join(parts)
    else:
        carry = None if c.carry is None else np.ascontiguousarray(c.carry, dtype="<f8")
        n_carry = _NO_STATE if carry is None else carry.size
        head = _HEAD2.pack(_MAGIC2, *counts, n_carry, c.store, c.chain)
        body = head + b"".join(parts) + (b"" if carry is None else carry.tobytes())
        body += _seal(body, c.store)
    return np.frombuffer(body + struct.pack("<I", zlib.crc32(body)), dtype=np.uint8).copy()


def unpack(raw: NDArray[np.uint8]) -> Checkpoint | None:
    """The checkpoint in `raw`, or None when it is not a whole, intact record."""
    data = bytes(np.asarray(raw, dtype=np.uint8))
    if len(data) < _HEAD.size + 4:
        return None
    body, (crc,) = data[:-4], struct.unpack("<I", data[-4:])
    if zlib.crc32(body) != crc:
        return None
    if body.startswith(_MAGIC):
        head, store, chain, sealed, n_carry = _HEAD.unpack_from(body), b"", b"", True, _NO_STATE
        end = len(body)
    elif body.startswith(_MAGIC2) and len(body) >= _HEAD2.size + _SEAL:
        head = _HEAD2.unpack_from(body)
        n_carry, store, chain = head[-3:]
        head, end = head[:-3], len(body) - _SEAL
        sealed = _seal(body[:end], store) == body[end:]
    else:
        return None
    _magic, seq, step, rows, newton, closed, fact, subd, depth, wall, n_state, n_el = head
    size = _HEAD.size if not store else _HEAD2.size
    lengths = [n_state, 0 if n_el == _NO_STATE else n_el, 0 if n_carry == _NO_STATE else n_carry]
    if end != size + 8 * sum(lengths):
        return None
    floats = np.frombuffer(body[:end], dtype="<f8", offset=size).astype(np.float64)
    at = np.cumsum([0, *lengths])
    return Checkpoint(
        seq=seq,
        step=step,
        rows=rows,
        state=floats[: at[1]].copy(),
        element_state=None if n_el == _NO_STATE else floats[at[1] : at[2]].copy(),
        newton_iterations=newton,
        closed_form_steps=closed,
        factorizations=fact,
        subdivided_steps=subd,
        subdivision_depth=depth,
        wall_time=wall,
        store=store,
        chain=chain,
        carry=None if n_carry == _NO_STATE else floats[at[2] : at[3]].copy(),
        sealed=sealed,
    )

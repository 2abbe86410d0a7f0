"""What a store's reader checks before it trusts the store (docs/store.md, "Damage"): the
root record's checksum over the grid, the model text and the model arrays, a grid that a
run can have, and the committed data chunks (present, whole, their CRC-32C intact)."""

from __future__ import annotations

import json
import os
import zlib
from typing import Any

import numpy as np

from duhamel._engine.output import ROW_BLOCK
from duhamel._engine.validate import MAX_COUNT
from duhamel.store._codec import Checkpoint, StoreError

__all__ = ["check_grid", "checked_chunks", "damaged", "digest", "fits"]


def damaged(path: str, what: str) -> StoreError:
    """The error for a damaged store: names the store and what is damaged."""
    return StoreError(
        f"`path`: the store {path!r} is damaged: {what}; its committed results cannot be "
        "trusted (solve again into a new store)"
    )


def digest(grid: dict, model_text: str, model_group: Any, identity: str | None = None) -> int:
    """CRC-32 of the store's `identity` (format 3), the grid, the model JSON text and every
    model array (name, dtype, shape, bytes): written in the root record, checked when the
    store is opened."""
    crc = 0 if identity is None else zlib.crc32(f"store {identity}|".encode())
    crc = zlib.crc32(json.dumps(grid, sort_keys=True, allow_nan=True).encode(), crc)
    crc = zlib.crc32(model_text.encode(), crc)
    for name in sorted(model_group.array_keys()):
        a = np.ascontiguousarray(model_group[name][...])
        crc = zlib.crc32(f"{name}|{a.dtype.str}|{a.shape}".encode(), crc)
        crc = zlib.crc32(a.tobytes(), crc)
    return crc


def _int(grid: dict, key: str, low: int, high: int = MAX_COUNT) -> int:
    value = grid.get(key)
    if type(value) is not int or not low <= value <= high:
        raise ValueError(f"grid {key!r} = {value!r} is not an integer in [{low}, {high}]")
    return value


def _float(grid: dict, key: str) -> float:
    value = grid.get(key)
    if type(value) not in (int, float) or not np.isfinite(value):
        raise ValueError(f"grid {key!r} = {value!r} is not a finite number")
    return float(value)


def check_grid(grid: dict, n_dof: int) -> None:
    """A ValueError naming the field when `grid` is not one a run can have (a forged
    ``n_steps`` of 1e18 or -1, rows that do not follow from the steps, ...)."""
    n_steps = _int(grid, "n_steps", 1)
    s = _int(grid, "save_every", 1)
    rows = n_steps // s + 1 + (1 if n_steps % s else 0)
    if grid.get("rows") != rows:
        raise ValueError(f"grid 'rows' = {grid.get('rows')!r} where its steps give {rows}")
    seg = _int(grid, "segment_rows", ROW_BLOCK)
    if seg % ROW_BLOCK:
        raise ValueError(f"grid 'segment_rows' = {seg} is not a multiple of {ROW_BLOCK}")
    if grid.get("chunk_rows") != min(seg, rows):
        raise ValueError(
            f"grid 'chunk_rows' = {grid.get('chunk_rows')!r}, expected {min(seg, rows)}"
        )
    _int(grid, "checkpoint_every", 1)
    _int(grid, "substeps", 1)
    if not _float(grid, "dt") > 0.0:
        raise ValueError(f"grid 'dt' = {grid['dt']!r} is not positive")
    t0 = _float(grid, "t0")
    if not np.isfinite(t0 + n_steps * grid["dt"]):
        raise ValueError("grid 't0 + n_steps dt' is beyond the double range")
    dofs = grid.get("dofs")
    if (
        not isinstance(dofs, list)
        or not dofs
        or not all(type(d) is int and 0 <= d < n_dof for d in dofs)
    ):
        raise ValueError(f"grid 'dofs' = {dofs!r} are not dofs of the model's {n_dof}")
    for key, default in (("modal", None), ("elements", True)):
        if not isinstance(grid.get(key, default), bool):
            raise ValueError(f"grid {key!r} = {grid.get(key)!r} is not a bool")
    correction = grid.get("correction", [])
    if not isinstance(correction, list) or not all(type(w) in (int, float) for w in correction):
        raise ValueError("grid 'correction' is not a list of numbers")


def fits(c: Checkpoint, grid: dict, width: int, slot: int) -> bool:
    """Whether checkpoint `c` is one this grid's run can write into slot `slot` (its CRC may
    be intact and its numbers still forged)."""
    n_steps, s = grid["n_steps"], grid["save_every"]
    seg = grid["segment_rows"] * s
    final = c.step == n_steps
    return (
        0 < c.seq < 2**62
        and c.seq % 2 == slot
        and c.state.size == width
        and bool(np.all(np.isfinite(c.state)))
        and (c.element_state is None or bool(np.all(np.isfinite(c.element_state))))
        and (c.carry is None or bool(np.all(np.isfinite(c.carry))))
        and 0 < c.step <= n_steps
        and (final or (c.step % seg == 0 and c.rows == c.step // s))
        and (not final or c.rows == grid["rows"])
        and all(
            0 <= k < 2**62
            for k in (
                c.newton_iterations,
                c.closed_form_steps,
                c.factorizations,
                c.subdivided_steps,
                c.subdivision_depth,
            )
        )
        and np.isfinite(c.wall_time)
        and c.wall_time >= 0.0
    )


def checked_chunks(path: str, root: Any, grid: dict, rows: int, ledger: Any = None) -> None:
    """As :func:`_check_chunks`; any other failure to read the data arrays' metadata (a
    damaged ``zarr.json``) is a damaged store too."""
    try:
        _check_chunks(path, root, grid, rows, ledger)
    except StoreError:
        raise
    except Exception as exc:
        raise damaged(
            path, f"its data arrays cannot be read ({type(exc).__name__}: {exc})"
        ) from None


def _check_chunks(path: str, root: Any, grid: dict, rows: int, ledger: Any) -> None:
    """Checks that every chunk of every data array holding one of the first `rows` rows is
    present, reads back with its CRC-32C intact and (format 3: `ledger`, a
    :class:`~duhamel.store._ledger.Ledger`) is the chunk the manifest records at its place;
    a StoreError naming the store, the array and the rows otherwise. Reads the committed
    data once, a chunk at a time."""
    chunk = grid["chunk_rows"]
    if "data" not in root:
        if rows == 0:
            return  # killed before its first segment: nothing committed
        raise damaged(path, "its 'data' group is missing")
    group = root["data"]
    for required in ("t", "x", "v", "a"):
        if rows and required not in group:
            raise damaged(path, f"the data array {required!r} is missing")
    arrays = {name: group[name] for name in sorted(group.array_keys())}
    for name, arr in arrays.items():
        if arr.shape[0] != grid["rows"] or arr.chunks[0] != chunk:
            raise damaged(path, f"the data array {name!r} has shape {arr.shape}, not the grid's")
    if ledger is not None and rows:
        ledger.load([name for name, arr in arrays.items() if 0 not in arr.shape[1:]])
    for name, arr in arrays.items():
        if 0 in arr.shape[1:]:
            continue  # no columns (a model without loads): no chunk is ever written
        for i in range(-(-rows // chunk)):
            start, stop = i * chunk, min(rows, (i + 1) * chunk)
            key = arr.metadata.encode_chunk_key((i,) + (0,) * (arr.ndim - 1))
            where = os.path.join(path, "data", name, *key.split("/"))
            if not os.path.isfile(where):
                raise damaged(
                    path, f"the chunk of rows {start}:{stop} of {name!r} ({key}) is missing"
                )
            try:
                block = np.asarray(arr[start:stop])
            except Exception as exc:  # a checksum mismatch, a truncated chunk
                raise damaged(
                    path, f"the chunk of rows {start}:{stop} of {name!r} ({key}) is corrupt ({exc})"
                ) from None
            if not np.all(np.isfinite(block)) and name in ("t", "x", "v", "a"):
                raise damaged(path, f"rows {start}:{stop} of {name!r} hold non-finite values")
            if ledger is not None:
                ledger.check(name, arr, i)

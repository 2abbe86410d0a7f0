"""Opening a stored run: its root record (format 3, and format 2 as a legacy format), the
checkpoint to continue from, and the checkpoints' writing (docs/store.md, "Damage")."""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import numpy as np

from duhamel._core import __version__
from duhamel.store._codec import Checkpoint, StoreError, decode, pack, unpack
from duhamel.store._integrity import check_grid, checked_chunks, damaged, digest, fits
from duhamel.store._ledger import Ledger
from duhamel.store._model import Model

__all__ = ["FORMAT", "KEY", "LEGACY", "checkpoint", "latest", "open_store", "start", "zarr"]

#: The store layout this version writes: 3 binds every data chunk and checkpoint to its
#: store and place (an identity, the manifest of chunk digests, sealed checkpoints); 2 added
#: the root record's checksum and the CRC-32C of every data chunk.
FORMAT = 3
#: Formats read as legacy: resumed and read with the checks they allow, continued in their
#: own format.
LEGACY = (2,)
KEY = "duhamel"


def zarr() -> Any:
    """zarr, imported on use (a clear ImportError without it)."""
    try:
        import zarr as module
    except ImportError:
        raise ImportError(
            "`store`: streaming a run to a store needs zarr: pip install 'duhamel[store]'"
        ) from None
    return module


def _format_error(path: str, record: dict) -> StoreError:
    got = record.get("format")
    return StoreError(
        f"`path`: {path!r} has store format {got!r} (written by duhamel "
        f"{record.get('version')}); this duhamel ({__version__}) reads format {FORMAT} (and "
        f"{', '.join(map(str, LEGACY))} as a legacy format)"
        + (
            " (format 2 added checksums to the data chunks): resume it with the duhamel that "
            "wrote it, or solve again"
            if got == 1
            else ""
        )
    )


def open_store(path: str) -> tuple[Any, Model, dict, Ledger | None]:
    """The store's group, model, grid and ledger (None for a legacy format-2 store);
    StoreError when it is not a readable store."""
    z = zarr()
    if not Path(path).exists():
        raise FileNotFoundError(f"`path`: no store at {path!r}")
    try:
        group = z.open_group(path, mode="r+")
        record = group.attrs.get(KEY)
    except Exception as exc:  # zarr raises several types for a damaged or foreign directory
        raise StoreError(f"`path`: {path!r} is not a readable zarr store ({exc})") from None
    if not isinstance(record, dict):
        raise StoreError(
            f"`path`: {path!r} is not a duhamel store (no '{KEY}' record: another zarr "
            "store, or a run killed while its store was being created; solve again)"
        )
    if record.get("format") != FORMAT and record.get("format") not in LEGACY:
        raise _format_error(path, record)
    identity = record.get("store") if record.get("format") == FORMAT else None
    try:
        text, grid = record["model"], record["grid"]
        if not isinstance(text, str) or not isinstance(grid, dict):
            raise TypeError("the model text or the grid is not of its type")
        if record["format"] == FORMAT and not (
            isinstance(identity, str) and re.fullmatch("[0-9a-f]{32}", identity)
        ):
            raise ValueError(f"its store identity {identity!r} is not 32 hexadecimal digits")
        if digest(grid, text, group["model"], identity) != record["checksum"]:
            raise ValueError("the checksum of its grid and model does not match")
    except Exception as exc:  # a missing field, unreadable model arrays, a changed byte
        raise damaged(path, f"its root record (grid and model) ({exc})") from None
    try:
        tree = decode(json.loads(text), group["model"])
        model = Model.from_tree(tree)
        grid = dict(grid)
        check_grid(grid, model.basis.phi.shape[0])
        if model.route not in ("uncoupled", "first-order", "pseudo-force"):
            raise ValueError(f"unknown route {model.route!r}")
        model.core(model.plan())  # builds the engine's model: its shapes and kinds checked
        if not np.all(np.isfinite(model.initial_state())):
            raise ValueError("a non-finite initial state")
    except Exception as exc:  # a forged record with its checksum written again
        raise damaged(path, f"its model or grid record ({type(exc).__name__}: {exc})") from None
    ledger = None if identity is None else Ledger(path, group, grid, identity)
    return group, model, grid, ledger


def start(model: Model) -> Checkpoint:
    """The run's start (no checkpoint)."""
    return Checkpoint(seq=0, step=0, rows=0, state=model.initial_state(), element_state=None)


def _refusal(c: Checkpoint, slot: int, grid: dict, width: int, ledger: Ledger | None) -> str:
    """Why an intact checkpoint record (its CRC-32 matches) cannot be this store's (empty:
    it can). A crash leaves a torn record, never one of these."""
    if ledger is None:
        if c.store:
            return "is of store format 3, not of this format-2 store"
    elif not c.store:
        return "is of store format 2, not this store's (format 3)"
    elif c.store != ledger.key:
        return (
            f"was written by another store (identity {c.store.hex()}, this store's is "
            f"{ledger.key.hex()})"
        )
    elif not c.sealed:
        return "was rewritten after its store wrote it (its seal does not match its content)"
    if not fits(c, grid, width, slot):
        return (
            f"(sequence {c.seq}, step {c.step}, rows {c.rows}) is not a checkpoint this run "
            f"writes into slot {slot}: its step is off the run's segment grid, its rows do "
            "not follow from its step, or its numbers are not finite"
        )
    if ledger is not None and "energy" in grid and (c.carry is None) != (c.step == 0):
        return "lacks the energy totals of its run"
    return ""


def latest(group: Any, model: Model, grid: dict, path: str, ledger: Ledger | None) -> Checkpoint:
    """The newest intact checkpoint (the start of the run when there is none); a StoreError
    naming the store and what is wrong when a checkpoint or the data it commits is not this
    store's or is damaged."""
    found = []
    width = model.initial_state().size
    for slot in (0, 1):
        try:  # a slot that cannot be read is a damaged slot: the other one is used
            slots = group["checkpoints"]
            c = unpack(slots[str(slot)][...]) if str(slot) in slots else None
        except Exception:
            c = None
        if c is None:
            continue  # missing, torn or unreadable: what a kill can leave
        why = _refusal(c, slot, grid, width, ledger)
        if why:
            raise damaged(path, f"its checkpoint 'checkpoints/{slot}' {why}")
        found.append((c, slot))
    c = max(found, key=lambda k: k[0].seq)[0] if found else start(model)
    checked_chunks(path, group, grid, c.rows, ledger)
    if ledger is not None:
        for k, slot in sorted(found, key=lambda k: k[0].rows):
            if ledger.chain(k.rows) != k.chain:
                raise damaged(
                    path,
                    f"its checkpoint 'checkpoints/{slot}' (step {k.step}, rows {k.rows}) does "
                    "not match the rows written before it (its chain of chunk digests differs: "
                    "a checkpoint of another point of the run, or rows rewritten)",
                )
    return c


def checkpoint(group: Any, c: Checkpoint) -> None:
    """Writes `c` into slot ``seq % 2`` (the other slot keeps the previous one)."""
    blob = pack(c)
    try:
        slots = group.require_group("checkpoints")
    except Exception:  # its metadata damaged (no slot was readable): made anew
        slots = group.create_group("checkpoints", overwrite=True)
    name = str(c.seq % 2)
    try:
        fresh = name not in slots or slots[name].shape != blob.shape
    except Exception:  # a damaged slot (its metadata unreadable): written anew
        fresh = True
    if fresh:
        slots.create_array(
            name,
            shape=blob.shape,
            dtype="u1",
            chunks=blob.shape,
            compressors=None,  # the record's own CRC-32 is checked first, nothing to inflate
            overwrite=True,
        )
    slots[name][...] = blob

"""A store that knows its chunks (format 3, docs/store.md "Damage"): an identity created with
the run, and for every chunk of every data array a digest binding the chunk to the store and
to its place, kept in the ``manifest`` array beside the data; each checkpoint carries the
digest of the manifest rows of the chunks it commits (its *chain*).

A chunk's digest is a BLAKE2b keyed by the store's identity over the array's name, the
chunk's index and the chunk's own CRC-32C (the last four bytes zarr's ``crc32c`` codec
writes, and checks against the chunk's bytes whenever it is read). Recording it costs a
four-byte read per chunk written and a small file per segment (the manifest's row);
checking it, a four-byte read per chunk read: the data is never hashed a second time. A
chunk of another store, of another array or of another place in this one, a manifest or a
``data`` folder of another store, all fail the comparison.
"""

from __future__ import annotations

import hashlib
import os
import struct
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel.store._integrity import damaged

__all__ = ["MANIFEST", "Guard", "Ledger", "new_identity"]

#: The manifest array: one row per chunk index, one digest (uint64) per data array, its
#: names in ``attrs["arrays"]``; one zarr chunk per row, so a segment writes only its own.
MANIFEST = "manifest"


def _crc32c(body: bytes) -> bytes:
    """The CRC-32C zarr's ``crc32c`` codec appends to a chunk."""
    import google_crc32c  # zarr's own dependency for its crc32c codec

    return struct.pack("<I", google_crc32c.value(body))


def new_identity() -> str:
    """A new store's identity (128 random bits, as 32 hexadecimal digits)."""
    return os.urandom(16).hex()


class Ledger:
    """The digests of a format-3 store's chunks: recorded as the run writes them, loaded from
    the manifest when the store is opened, and checked against the chunks read."""

    def __init__(self, path: str, root: Any, grid: dict, identity: str) -> None:
        self.path, self.root, self._dir = path, root, os.path.abspath(path)
        self.key = bytes.fromhex(identity)
        self.chunk, self.total = int(grid["chunk_rows"]), int(grid["rows"])
        self.n_chunks = -(-self.total // self.chunk)
        self.names: list[str] | None = None
        self.rows: dict[int, NDArray[np.uint64]] = {}
        self._dims: dict[str, int] = {}  # each data array's number of dimensions
        self._chain = hashlib.blake2b(key=self.key, digest_size=16, person=b"duhamel-chain")
        self._hashed = 0

    # -- digests ---------------------------------------------------------------------------

    def _entry(self, name: str, k: int, crc: bytes) -> int:
        h = hashlib.blake2b(key=self.key, digest_size=8, person=b"duhamel-chunk")
        h.update(f"{name}\x00{k}\x00".encode() + crc)
        return int.from_bytes(h.digest(), "little")

    def _file(self, name: str, arr: Any, k: int) -> tuple[str, str]:
        """Chunk `k`'s key and file (the default key encoding the store's arrays have;
        `arr` is read once per array, for its number of dimensions)."""
        ndim = self._dims.get(name)
        if ndim is None:
            ndim = self._dims[name] = arr.ndim
        key = "/".join(["c", str(k)] + ["0"] * (ndim - 1))
        return key, os.path.join(self._dir, "data", name, *key.split("/"))

    def _span(self, name: str, k: int, key: str) -> str:
        stop = min((k + 1) * self.chunk, self.total)
        return f"the chunk of rows {k * self.chunk}:{stop} of {name!r} ({key})"

    def _crc(self, name: str, arr: Any, k: int) -> bytes:
        """The chunk's CRC-32C as written at its end (a StoreError when it is missing)."""
        key, where = self._file(name, arr, k)
        try:
            with open(where, "rb") as f:
                size = f.seek(0, os.SEEK_END)
                f.seek(max(0, size - 4))
                crc = f.read(4)
        except FileNotFoundError:
            raise damaged(self.path, f"{self._span(name, k, key)} is missing") from None
        if len(crc) != 4:
            raise damaged(self.path, f"{self._span(name, k, key)} is cut short")
        return crc

    # -- writing ---------------------------------------------------------------------------

    def record(self, arrays: dict[str, Any], k: int) -> None:
        """Records chunk `k` of the data `arrays` (just written; name: zarr array) in the
        manifest."""
        names = sorted(n for n, arr in arrays.items() if 0 not in arr.shape[1:])
        if self.names != names:
            self._manifest_for(names)
        row = np.array([self._entry(n, k, self._crc(n, arrays[n], k)) for n in names], "<u8")
        # Written as zarr writes a chunk of the manifest (its bytes, then their CRC-32C),
        # straight to its file: a zarr write costs a millisecond, this a tenth of one.
        body = row.tobytes()
        where = self._row_file(k)
        os.makedirs(os.path.dirname(where), exist_ok=True)
        with open(where, "wb") as f:
            f.write(body + _crc32c(body))
        self.rows[k] = row

    def _row_file(self, k: int) -> str:
        return os.path.join(self._dir, MANIFEST, "c", str(k), "0")

    def _manifest_for(self, names: list[str]) -> None:
        root = self.root
        try:
            m = root[MANIFEST]
            fresh = m.attrs.get("arrays") != names or m.shape != (self.n_chunks, len(names))
        except Exception:  # absent, or its metadata damaged before any row was committed
            fresh = True
        if fresh:
            from zarr.codecs import Crc32cCodec

            m = root.create_array(
                MANIFEST,
                shape=(self.n_chunks, len(names)),
                dtype="<u8",
                chunks=(1, max(1, len(names))),
                fill_value=0,
                compressors=[Crc32cCodec()],
                chunk_key_encoding={"name": "default", "separator": "/"},
                attributes={"arrays": names},
                overwrite=True,
            )
            self.rows.clear()
        self.names = names

    def chain(self, rows: int) -> bytes:
        """The digest of the manifest rows of the chunks holding the first `rows` rows (for
        a checkpoint at `rows`; called with non-decreasing `rows`)."""
        k_end = -(-rows // self.chunk)
        if k_end < self._hashed:
            raise AssertionError("chain() is computed in increasing order of rows")
        while self._hashed < k_end:
            self._chain.update(self._row(self._hashed).tobytes())
            self._hashed += 1
        return self._chain.copy().digest()

    # -- reading ---------------------------------------------------------------------------

    def load(self, names: list[str]) -> None:
        """Checks the manifest's names against the data arrays `names` (those with columns)
        of an opened store; its rows are read when needed."""
        try:
            m = self.root[MANIFEST]
            recorded = m.attrs.get("arrays")
            shape = m.shape
        except Exception as exc:
            raise damaged(
                self.path, f"its manifest of chunk digests cannot be read ({type(exc).__name__})"
            ) from None
        if recorded != sorted(names):
            raise damaged(
                self.path,
                f"its data arrays {sorted(names)} are not those its manifest records "
                f"({recorded}): an array added, removed or renamed",
            )
        if shape != (self.n_chunks, len(names)):
            raise damaged(self.path, f"its manifest has shape {shape}, not the grid's")
        self.names = list(recorded)

    def _row(self, k: int) -> NDArray[np.uint64]:
        """Row `k` of the manifest (read from its chunk file, its CRC-32C checked, as zarr
        reads it)."""
        row = self.rows.get(k)
        if row is None:
            n = 0 if self.names is None else len(self.names)
            try:
                with open(self._row_file(k), "rb") as f:
                    raw = f.read(8 * n + 5)
            except FileNotFoundError:
                raise damaged(self.path, f"the manifest records no digests for chunk {k}") from None
            if len(raw) != 8 * n + 4 or _crc32c(raw[:-4]) != raw[-4:]:
                raise damaged(self.path, f"the manifest row of chunk {k} is corrupt")
            row = np.frombuffer(raw[:-4], dtype="<u8").copy()
            self.rows[k] = row
        return row

    def check(self, name: str, arr: Any, k: int) -> None:
        """A StoreError naming the store and the chunk unless chunk `k` of `name` is the one
        the manifest records at this place."""
        if self.names is None or name not in self.names:
            raise damaged(self.path, f"the data array {name!r} is not in its manifest")
        crc = self._crc(name, arr, k)
        if self._entry(name, k, crc) != int(self._row(k)[self.names.index(name)]):
            key, _ = self._file(name, arr, k)
            raise damaged(
                self.path,
                f"{self._span(name, k, key)} is not the chunk this store wrote there (its "
                f"CRC-32C {crc.hex()} is not the one its manifest records: a chunk of another "
                "store, of another array or of another place in this one, or a damaged chunk)",
            )


class Guard:
    """Reads rows of a stored array chunk-checked: each chunk read is first checked against
    the manifest (format 3; `ledger` None for a format-2 store, which has none), and a chunk
    zarr cannot decode (its CRC-32C) is a StoreError naming the store and the chunk."""

    def __init__(self, path: str, name: str, arr: Any, chunk: int, ledger: Ledger | None) -> None:
        self.path, self.name, self.arr, self.chunk, self.ledger = path, name, arr, chunk, ledger

    def __call__(self, start: int, stop: int, read: Any) -> Any:
        """``read()`` (which reads rows ``start:stop``), after the chunks' check."""
        ks = range(start // self.chunk, -(-stop // self.chunk)) if stop > start else range(0)
        if self.ledger is not None:
            for k in ks:
                self.ledger.check(self.name, self.arr, k)
        try:
            return read()
        except Exception as exc:
            for k in ks:  # which chunk: read them one by one
                try:
                    self.arr[k * self.chunk : (k + 1) * self.chunk]
                except Exception as bad:
                    key = self.arr.metadata.encode_chunk_key((k,) + (0,) * (self.arr.ndim - 1))
                    where = f"rows {k * self.chunk}:{min(self.arr.shape[0], (k + 1) * self.chunk)}"
                    raise damaged(
                        self.path,
                        f"the chunk of {where} of {self.name!r} ({key}) is corrupt ({bad})",
                    ) from None
            raise exc

"""Arrays of a :class:`duhamel.Solution` read from its store on access."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.lib.mixins import NDArrayOperatorsMixin
from numpy.typing import NDArray

__all__ = ["StoredArray"]


class StoredArray(NDArrayOperatorsMixin):
    """The first `rows` rows (and columns `columns`) of a zarr array, read when used.

    Indexing reads only what it selects (``sol.x[-100:, 0]`` reads the chunks of the last
    100 rows); ``np.asarray(sol.x)`` and arithmetic (``sol.x * 2``, ``sol.x @ m``) read the
    whole array. Nothing is kept in memory between accesses. A stored run's arrays read
    through its store's `guard`, which checks each chunk read (docs/store.md, "Damage").

    Attributes
    ----------
    shape, dtype, ndim, size
        As for an ndarray.

    Examples
    --------
    >>> import numpy as np, zarr
    >>> z = zarr.create_array(zarr.storage.MemoryStore(), shape=(4, 3), dtype="f8")
    >>> z[...] = np.arange(12.0).reshape(4, 3)
    >>> a = StoredArray(z, rows=3, columns=slice(1, 3))
    >>> a.shape, a[-1].tolist(), float((a * 2).sum())
    ((3, 2), [7.0, 8.0], 54.0)
    """

    def __init__(
        self, array: Any, rows: int, columns: slice | None = None, guard: Any = None
    ) -> None:
        self._array = array
        self._guard = guard
        self._rows = int(rows)
        self._columns = columns
        shape = list(array.shape)
        shape[0] = self._rows
        if columns is not None:
            shape[1] = len(range(*columns.indices(array.shape[1])))
        self.shape = tuple(shape)
        self.dtype = np.dtype(array.dtype)

    @property
    def ndim(self) -> int:
        return len(self.shape)

    @property
    def size(self) -> int:
        return int(np.prod(self.shape))

    def __len__(self) -> int:
        return self.shape[0]

    def __repr__(self) -> str:
        return f"StoredArray(shape={self.shape}, dtype={self.dtype})"

    def _rows_of(self, start: int, stop: int) -> NDArray:
        """Rows ``start:stop`` (the selected columns), read through the store's guard (its
        chunks checked, docs/store.md) when it has one."""

        def read() -> NDArray:
            if self._columns is None:
                return np.asarray(self._array[start:stop])
            return np.asarray(self._array[start:stop, self._columns])

        return read() if self._guard is None else self._guard(start, stop, read)

    def _read(self) -> NDArray:
        return self._rows_of(0, self._rows)

    def __array__(self, dtype: Any = None, copy: bool | None = None) -> NDArray:
        out = self._read()
        return out if dtype is None else out.astype(dtype, copy=False)

    def copy(self) -> NDArray:
        """The whole array, read into memory."""
        return self._read()

    def astype(self, dtype: Any, copy: bool = True) -> NDArray:
        """The whole array, read and converted."""
        return self._read().astype(dtype, copy=copy)

    def tolist(self) -> list[Any]:
        """The whole array as nested lists."""
        return self._read().tolist()

    def __getitem__(self, key: Any) -> Any:
        key = key if isinstance(key, tuple) else (key,)
        first, rest = key[0], key[1:]
        if (
            isinstance(first, slice)
            and first.step in (None, 1)
            and not any(k is Ellipsis or k is None for k in key)
        ):
            start, stop, _ = first.indices(self._rows)
            block = self._rows_of(start, max(start, stop))
            return block[(slice(None), *rest)]
        if isinstance(first, int | np.integer) and not any(k is Ellipsis or k is None for k in key):
            i = int(first)
            if not -self._rows <= i < self._rows:
                raise IndexError(f"index {i} is out of bounds for {self._rows} rows")
            i %= self._rows
            row = self._rows_of(i, i + 1)[0]
            return row[rest] if rest else row
        return self._read()[key]

    def __array_ufunc__(self, ufunc: Any, method: str, *inputs: Any, **kwargs: Any) -> Any:
        args = [np.asarray(x) if isinstance(x, StoredArray) else x for x in inputs]
        if "out" in kwargs:
            kwargs["out"] = tuple(
                np.asarray(x) if isinstance(x, StoredArray) else x for x in kwargs["out"]
            )
        return getattr(ufunc, method)(*args, **kwargs)

"""Ensemble results as one labelled dataset along ``case``, in memory or appended block by
block to a zarr store as the runs finish (xarray and zarr are optional: imported on use)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from duhamel.results.solution import Solution


def _xarray() -> Any:
    try:
        import xarray as xr
    except ImportError as exc:
        raise ImportError("ensemble datasets need xarray: pip install 'duhamel[xarray]'") from exc
    return xr


def stack(params: Sequence[Any], results: Sequence[Any], first: int = 0) -> Any:
    """`results` (cases ``first, first + 1, ...``) as one ``xarray.Dataset`` along ``case``:
    Solutions as their :meth:`~duhamel.Solution.to_xarray` datasets (same times and dofs),
    dicts of numbers or arrays as one variable per key, numbers or arrays as ``result``.
    Parameters that are dicts of scalars become coordinates along ``case``."""
    xr = _xarray()
    failed = [first + i for i, r in enumerate(results) if isinstance(r, BaseException)]
    if failed:
        raise ValueError(
            f"cases {failed[:10]} failed (their results are the exceptions): select the "
            "others from `results` before stacking"
        )
    n = len(results)
    if n and isinstance(results[0], Solution):
        ds = xr.concat([r.to_xarray() for r in results], dim="case")
    else:
        rows = [r if isinstance(r, dict) else {"result": r} for r in results]
        for i, row in enumerate(rows[1:], start=1):
            if set(row) != set(rows[0]):
                raise ValueError(
                    f"`reduce` returned dicts with different keys: case {first} has "
                    f"{sorted(rows[0])}, case {first + i} has {sorted(row)}; return the same "
                    "keys for every case"
                )
        data = {}
        for key in rows[0] if rows else []:
            values = np.stack([np.asarray(row[key]) for row in rows])
            dims = ("case", *[f"{key}_dim_{i}" for i in range(values.ndim - 1)])
            data[key] = (dims, values)
        ds = xr.Dataset(data)
    ds = ds.assign_coords(case=np.arange(first, first + n))
    if n and all(isinstance(p, dict) for p in params):
        for key in params[0]:
            values = [p.get(key) for p in params]
            if all(np.isscalar(v) for v in values):
                ds = ds.assign_coords({key: ("case", np.asarray(values))})
    return ds


class ZarrWriter:
    """Appends blocks of consecutive cases to a new zarr store at `path` (chunked along
    ``case`` by `block`), in case order; nothing of a written block stays in memory."""

    def __init__(self, path: str | Path, block: int) -> None:
        _xarray()
        try:
            import zarr  # noqa: F401
        except ImportError as exc:
            raise ImportError("`to_zarr` needs zarr: pip install zarr") from exc
        self.path, self.block, self.written = Path(path), int(block), 0

    def write(self, params: Sequence[Any], results: Sequence[Any]) -> None:
        """Cases ``written, ..., written + len(results) - 1``."""
        ds = stack(params, results, self.written)
        if self.written == 0:
            encoding = {
                name: {"chunks": (self.block, *var.shape[1:])} for name, var in ds.data_vars.items()
            }
            ds.to_zarr(self.path, mode="w-", encoding=encoding, consolidated=False)
        else:
            ds.to_zarr(self.path, append_dim="case", consolidated=False)
        self.written += len(results)

    def open(self) -> Any:
        """The store as a lazily read ``xarray.Dataset``."""
        return _xarray().open_zarr(self.path, consolidated=False)

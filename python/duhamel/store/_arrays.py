"""The arrays of a stored run's segments, written into the store's data group with a
CRC-32C per chunk (so that ``resume`` detects a changed or cut chunk)."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray


def _crc32c() -> Any:
    """zarr's CRC-32C codec (zarr is imported on use)."""
    from zarr.codecs import Crc32cCodec

    return Crc32cCodec()


def _columns(
    result: Any, x: NDArray, v: NDArray, a: NDArray, modal: bool, elements: bool = True
) -> dict[str, NDArray]:
    """The arrays of a segment kept in the store, by name (the modal history if `modal`,
    the element histories if `elements`)."""
    out = {"t": result.t, "x": x, "v": v, "a": a}
    if not elements:
        result = _NoElements(result)
    histories = {
        "element_x": result.element_x,
        "element_v": result.element_v,
        "element_force": result.element_force,
    }
    out.update({name: value for name, value in histories.items() if value is not None})
    if not modal:
        return out
    out["load_values"] = result.load_values
    if result.eta is not None:
        out["modal_eta"] = result.eta
    else:
        out["modal_q"], out["modal_v"] = result.q, result.v
    extra = {"pseudo": result.pseudo, "forcing": result.forcing}
    out.update({name: value for name, value in extra.items() if value is not None})
    return out


class _NoElements:
    """A core result read without its element histories."""

    element_x = element_v = element_force = None

    def __init__(self, result: Any) -> None:
        self._result = result

    def __getattr__(self, name: str) -> Any:
        return getattr(self._result, name)


def _write(
    data: Any, grid: dict, arrays: dict[str, NDArray], start: int, keep: int, widths: Any
) -> dict[str, Any]:
    """Rows ``start:start+keep`` of every array (created on first use; the element arrays
    carry the elements' `widths`); returns the zarr arrays written, by name."""
    total, chunk = grid["rows"], grid["chunk_rows"]
    present = set(data.array_keys())
    out = {}
    for name, value in arrays.items():
        value = np.asarray(value)
        shape = (total, *value.shape[1:])
        target = data[name] if name in present else None
        if target is None or target.shape != shape:
            target = data.create_array(
                name,
                shape=shape,
                dtype="f8",
                chunks=(chunk, *(max(1, k) for k in value.shape[1:])),
                fill_value=np.nan,
                compressors=[_crc32c()],  # per chunk: a changed or cut chunk is refused
                chunk_key_encoding={"name": "default", "separator": "/"},  # as _ledger reads
                overwrite=True,
                attributes={"widths": [int(w) for w in widths]}
                if name.startswith("element_") and widths is not None
                else None,
            )
        if keep:
            target[start : start + keep] = value[:keep]
        out[name] = target
    return out

"""Labelled views of a :class:`~duhamel.Solution`: an ``xarray.Dataset`` (dims ``time``,
``dof``) and a ``pandas.DataFrame``; xarray and pandas are optional (imported on use)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

QUANTITIES = ("x", "v", "a")
UNITS = {"x": "displacement", "v": "velocity", "a": "acceleration"}


def _labels(sol: Any, labels: Sequence[str] | None) -> list[str] | None:
    """The labels of the saved dofs, from `labels` given for every dof of the model (default:
    the model's own, :meth:`duhamel.System.label_dofs`)."""
    if labels is None:
        labels = sol.meta.get("labels")
    if labels is None:
        return None
    if isinstance(labels, str | bytes) or not isinstance(labels, Sequence | np.ndarray):
        raise TypeError(
            f"`labels` must be a sequence of names, one per dof, got {type(labels).__name__}"
        )
    if np.ndim(labels) != 1:
        raise ValueError(f"`labels` must be a 1-D sequence of names, got shape {np.shape(labels)}")
    labels = [str(v) for v in labels]
    top = int(sol.dofs.max()) if sol.dofs.size else -1
    if len(labels) <= top:
        raise ValueError(
            f"`labels` must name every degree of freedom of the model (at least {top + 1}), "
            f"got {len(labels)}"
        )
    return [labels[int(d)] for d in sol.dofs]


def to_xarray(sol: Any, labels: Sequence[str] | None = None) -> Any:
    """See :meth:`duhamel.Solution.to_xarray`."""
    try:
        import xarray as xr
    except ImportError as exc:
        raise ImportError(
            "to_xarray needs xarray: pip install 'duhamel[xarray]' (or pip install xarray)"
        ) from exc
    names = _labels(sol, labels)
    coords: dict[str, Any] = {"time": np.asarray(sol.t), "dof": np.asarray(sol.dofs)}
    if names is not None:
        coords["label"] = ("dof", np.array(names, dtype=object))  # variable-length strings
    data = {
        q: (("time", "dof"), np.asarray(getattr(sol, q)), {"quantity": UNITS[q]})
        for q in QUANTITIES
    }
    attrs = {
        "integrator": repr(sol.meta.get("integrator")),
        "dt": float(sol.meta.get("dt", np.nan)),
        "t0": float(sol.meta.get("t0", sol.t[0] if len(sol.t) else 0.0)),
        "steps": int(sol.stats.steps),
        "created_by": "duhamel",
    }
    ds = xr.Dataset(data, coords=coords, attrs=attrs)
    ds["time"].attrs["units"] = "s"
    return ds


def to_dataframe(sol: Any, quantity: str = "x", labels: Sequence[str] | None = None) -> Any:
    """See :meth:`duhamel.Solution.to_dataframe`."""
    if not isinstance(quantity, str) or quantity not in QUANTITIES:
        raise ValueError(f"`quantity` must be one of {QUANTITIES}, got {quantity!r}")
    try:
        import pandas as pd
    except ImportError as exc:
        raise ImportError("to_dataframe needs pandas: pip install pandas") from exc
    names = _labels(sol, labels)
    columns = names if names is not None else [int(d) for d in sol.dofs]
    index = pd.Index(np.asarray(sol.t), name="time")
    return pd.DataFrame(np.asarray(getattr(sol, quantity)), index=index, columns=columns)

"""Shared helpers of the exact solutions."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.validate import as_float_array

__all__ = ["Array", "times"]

Array = NDArray[np.float64]


def times(t: ArrayLike) -> Array:
    """`t` as a float array of non-negative times (since the initial instant ``t = 0``).

    Examples
    --------
    >>> from duhamel.exact._common import times
    >>> times([0.0, 1.5]).tolist()
    [0.0, 1.5]
    """
    arr = as_float_array(t, "t")
    if np.any(arr < 0.0):
        raise ValueError("`t` must be non-negative (times since the initial instant t = 0)")
    return arr

"""Peak tables of a run (:meth:`duhamel.Solution.peaks`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["Peaks", "peak_table"]


@dataclass(frozen=True, eq=False)
class Peaks:
    """Peaks of histories: one row per quantity and column.

    Attributes
    ----------
    quantity, column : list of str
        The quantity (``"x"``, ``"a_absolute"``, a named extra history) and the column
        (``"dof 3"``, or the index of an extra history's column).
    peak : ndarray
        The value of largest magnitude, with its sign.
    time : ndarray
        When it is reached (the first time, on ties).
    """

    quantity: list[str]
    column: list[str]
    peak: NDArray[np.float64]
    time: NDArray[np.float64]

    def __len__(self) -> int:
        return len(self.quantity)

    def to_dataframe(self) -> Any:
        """The table as a ``pandas.DataFrame`` (columns quantity, column, peak, time)."""
        import pandas as pd

        return pd.DataFrame(
            {"quantity": self.quantity, "column": self.column, "peak": self.peak, "time": self.time}
        )

    def __str__(self) -> str:
        rows = [f"{'quantity':<14s}{'column':<10s}{'peak':>14s}{'time':>10s}"]
        for q, c, p, t in zip(self.quantity, self.column, self.peak, self.time, strict=True):
            rows.append(f"{q:<14s}{c:<10s}{p:>14.6g}{t:>10.4g}")
        return "\n".join(rows)


def peak_table(
    t: NDArray[np.float64], series: dict[str, tuple[NDArray[np.float64], list[str]]]
) -> Peaks:
    """The :class:`Peaks` of `series` (name -> (values (n_t, k), column names))."""
    quantity, column, peak, when = [], [], [], []
    for name, (values, names) in series.items():
        if values.shape[0] == 0:
            raise ValueError("peaks need at least one saved instant")
        at = np.argmax(np.abs(values), axis=0)
        for k, label in enumerate(names):
            quantity.append(name)
            column.append(label)
            peak.append(float(values[at[k], k]))
            when.append(float(t[at[k]]))
    return Peaks(quantity, column, np.array(peak), np.array(when))

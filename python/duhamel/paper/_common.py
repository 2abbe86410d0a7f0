"""Shared pieces of the paper examples: the claim record and the order fit."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

Array = NDArray[np.float64]

#: The paper's natural frequency is arbitrary: every quantity is normalised by it.
OMEGA = 1.0
#: The background period ``T = 2 pi / omega``.
PERIOD = 2.0 * math.pi / OMEGA


@dataclass(frozen=True)
class Claim:
    """One statement of the paper, checked against our numbers.

    Attributes
    ----------
    claim : str
        What the paper says (or, marked as such, what NOTES.md says about it).
    paper : str
        The paper's number or wording.
    ours : str
        Our measured numbers.
    holds : bool or None
        Whether the claim holds for our numbers; None for a measurement given for
        information (no claim of the paper to judge).
    note : str
        Why, or under which reading.

    Examples
    --------
    >>> from duhamel.paper import Claim
    >>> Claim("second order", "order 2", "1.99", True).verdict
    'holds'
    """

    claim: str
    paper: str
    ours: str
    holds: bool | None
    note: str = ""

    @property
    def verdict(self) -> str:
        """``"holds"``, ``"does not hold"`` or ``"(information)"``."""
        if self.holds is None:
            return "(information)"
        return "holds" if self.holds else "does not hold"


def fit_order(dts: ArrayLike, errors: ArrayLike) -> float:
    """Least-squares slope of ``log(error)`` against ``log(dt)``.

    Parameters
    ----------
    dts, errors : array_like, shape (k,)
        Steps and positive errors, ``k >= 2``.

    Returns
    -------
    float

    Examples
    --------
    >>> from duhamel.paper import fit_order
    >>> round(fit_order([0.1, 0.05, 0.025], [4e-2, 1e-2, 2.5e-3]), 12)
    2.0
    """
    x = np.log(np.asarray(dts, dtype=np.float64))
    y = np.log(np.asarray(errors, dtype=np.float64))
    if x.size < 2 or x.shape != y.shape:
        raise ValueError("`dts` and `errors` must be two arrays of the same length >= 2")
    return float(np.polyfit(x, y, 1)[0])


def local_orders(steps: Sequence[int], errors: Sequence[float]) -> list[float]:
    """Orders between neighbouring step counts: ``log(e_i / e_{i+1}) / log(n_{i+1} / n_i)``.

    Parameters
    ----------
    steps : sequence of int
        Steps per period, increasing.
    errors : sequence of float
        The errors at those steps.

    Returns
    -------
    list of float

    Examples
    --------
    >>> from duhamel.paper._common import local_orders
    >>> [round(q, 12) for q in local_orders([10, 20, 40], [1.0, 0.25, 0.0625])]
    [2.0, 2.0]
    """
    return [
        math.log(errors[i] / errors[i + 1]) / math.log(steps[i + 1] / steps[i])
        for i in range(len(steps) - 1)
    ]


def fmt(value: float, digits: int = 3) -> str:
    """A number with `digits` significant digits, without an exponent where readable.

    Parameters
    ----------
    value : float
    digits : int

    Returns
    -------
    str

    Examples
    --------
    >>> from duhamel.paper._common import fmt
    >>> fmt(0.034790), fmt(6.5794), fmt(7.2603e-5), fmt(1.06e-6, 2)
    ('0.0348', '6.58', '7.26e-05', '1.1e-06')
    """
    if value == 0.0 or not math.isfinite(value):
        return f"{value:g}"
    if 1e-3 <= abs(value) < 1e5:
        decimals = max(digits - 1 - math.floor(math.log10(abs(value))), 0)
        return f"{value:.{decimals}f}"
    return f"{value:.{digits - 1}e}"

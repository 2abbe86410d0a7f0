"""A code check's outcome (:class:`Check`): the clause, the value, the limit, their ratio and
the verdict, as :mod:`duhamel.design.asce7` returns them and the report prints them."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Check"]

#: Relative slack of a verdict: a value equal to its limit up to round-off passes.
SLACK = 1e-12


@dataclass(frozen=True)
class Check:
    """One code check.

    Attributes
    ----------
    clause : str
        The clause that sets the limit (``"ASCE 7-22 17.6.4.4"``).
    quantity : str
        What is checked, in words.
    value : float
        The design value (SI units).
    limit : float
        The limit it is held against (same units).
    kind : {'maximum', 'minimum'}
        ``'maximum'``: the value must not exceed the limit (a drift limit); ``'minimum'``:
        it must reach it (a lower limit of chapter 17 relative to the ELF values: where it
        fails, the response-history values are scaled up to it, section 17.6.4.3).
    units : str
        Of `value` and `limit`, for the report.
    note : str
        How the value and the limit were formed.

    Examples
    --------
    >>> from duhamel.design import Check
    >>> c = Check("ASCE 7-22 17.6.4.4", "storey drift ratio", 0.012, 0.020, "maximum")
    >>> round(c.ratio, 3), c.passes, c.verdict
    (0.6, True, 'pass')
    """

    clause: str
    quantity: str
    value: float
    limit: float
    kind: str
    units: str = ""
    note: str = ""

    def __post_init__(self) -> None:
        if self.kind not in ("maximum", "minimum"):
            raise ValueError(f"`kind` must be 'maximum' or 'minimum', got {self.kind!r}")

    @property
    def ratio(self) -> float:
        """``value / limit`` (inf for a zero limit and a positive value)."""
        if self.limit == 0.0:
            return 0.0 if self.value == 0.0 else float("inf")
        return self.value / self.limit

    @property
    def passes(self) -> bool:
        """Whether the value keeps to the limit (within round-off)."""
        if self.kind == "maximum":
            return self.value <= self.limit * (1.0 + SLACK)
        return self.value >= self.limit * (1.0 - SLACK)

    @property
    def verdict(self) -> str:
        """``'pass'`` or ``'fail'``."""
        return "pass" if self.passes else "fail"

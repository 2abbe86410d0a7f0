"""The response-history provisions: design values from a suite of records (ASCE 7-22 section
17.6.3.4), their lower limits relative to the equivalent lateral force values (section
17.6.4), and the acceptance of storey drifts (section 17.6.4.4 for isolated structures,
section 16.4.1.2 with Table 12.12-1 for chapter 16's analyses), each check returned as a
:class:`~duhamel.design.Check` (value, limit, ratio, verdict, clause)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.validate import as_float_array, positive_float
from duhamel.design.checks import Check

if TYPE_CHECKING:
    from duhamel.design.asce7.elf import IsolatedELF

__all__ = [
    "MIN_RECORDS",
    "TABLE_12_12_1",
    "allowable_drift",
    "drift_acceptance",
    "isolated_drift_check",
    "lower_limit_checks",
    "suite_value",
]

#: Records from which the suite's mean may be used for design (fewer: the maximum).
MIN_RECORDS = 7

#: ASCE 7-22 Table 12.12-1, the allowable storey drift ``Delta_a / h_sx`` for Risk Category
#: (I or II, III, IV): ``"other"`` all other structures; ``"low-rise"`` structures other than
#: masonry shear-wall ones, 4 storeys or less above the base, with interior walls, partitions,
#: ceilings and exterior walls designed to accommodate the drifts; ``"masonry cantilever"``
#: masonry cantilever shear-wall structures; ``"masonry"`` other masonry shear-wall ones.
TABLE_12_12_1: dict[str, tuple[float, float, float]] = {
    "other": (0.020, 0.015, 0.010),
    "low-rise": (0.025, 0.020, 0.015),
    "masonry cantilever": (0.010, 0.010, 0.010),
    "masonry": (0.007, 0.007, 0.007),
}
_CATEGORIES = {"I": 0, "II": 0, "III": 1, "IV": 2}


def suite_value(per_record: ArrayLike, *, min_records: int = MIN_RECORDS) -> NDArray[np.float64]:
    """The design value of a response quantity from a suite, ASCE 7-22 section 17.6.3.4: the
    mean over the records when at least seven were analysed, else the largest. Each record's
    value is its peak (for a pair applied in turn along each axis, or in two orientations,
    the larger: take it before calling).

    Parameters
    ----------
    per_record : array_like, shape (n_records, ...)
        One value per record (per storey, isolator ... along further axes).
    min_records : int, optional
        Seven in the code.

    Returns
    -------
    ndarray, shape (...)

    Examples
    --------
    >>> from duhamel.design.asce7 import suite_value
    >>> round(float(suite_value([0.30, 0.32, 0.28, 0.35, 0.31, 0.29, 0.33])), 12)  # the mean
    0.311428571429
    >>> float(suite_value([0.30, 0.32, 0.28]))  # fewer: the largest
    0.32
    """
    v = as_float_array(per_record, "per_record")
    if v.ndim == 0 or v.shape[0] == 0 or not np.all(np.isfinite(v)):
        raise ValueError("`per_record` must hold finite values for at least one record")
    return v.mean(axis=0) if v.shape[0] >= int(min_records) else v.max(axis=0)


def allowable_drift(risk_category: str = "II", structure: str = "other") -> float:
    """The allowable storey drift ratio ``Delta_a / h_sx`` of ASCE 7-22 Table 12.12-1
    (section 12.12.1; the reduction by the redundancy factor of section 12.12.1.1 for moment
    frames in Seismic Design Categories D to F is left to the caller).

    Parameters
    ----------
    risk_category : {'I', 'II', 'III', 'IV'}
    structure : {'other', 'low-rise', 'masonry cantilever', 'masonry'}
        The table's rows (:data:`TABLE_12_12_1`).

    Examples
    --------
    >>> from duhamel.design.asce7 import allowable_drift
    >>> allowable_drift("II"), allowable_drift("IV"), allowable_drift("III", "low-rise")
    (0.02, 0.01, 0.02)
    """
    if risk_category not in _CATEGORIES:
        raise ValueError(
            f"`risk_category` must be one of {sorted(_CATEGORIES)}, got {risk_category!r}"
        )
    if structure not in TABLE_12_12_1:
        raise ValueError(f"`structure` must be one of {sorted(TABLE_12_12_1)}, got {structure!r}")
    return TABLE_12_12_1[structure][_CATEGORIES[risk_category]]


def _storey(values: NDArray[np.float64]) -> tuple[float, int]:
    k = int(np.argmax(values))
    return float(values[k]), k


def drift_acceptance(
    drift_ratios: ArrayLike,
    *,
    risk_category: str = "II",
    structure: str = "other",
    factor: float = 2.0,
) -> Check:
    """Chapter 16's acceptance of storey drifts, ASCE 7-22 section 16.4.1.2: the mean over
    the suite of the absolute peak storey drift ratios must not exceed `factor` (two) times
    the limit of section 12.12.1 (Table 12.12-1, :func:`allowable_drift`).

    Parameters
    ----------
    drift_ratios : array_like, shape (n_records, n_storeys)
        Each record's peak absolute drift ratio per storey (the larger of the orientations).
    risk_category, structure : str
        The row and column of Table 12.12-1.
    factor : float, optional
        The multiple of the table's limit (2.0).

    Returns
    -------
    Check
        The storey with the largest mean against the limit.

    Examples
    --------
    >>> from duhamel.design.asce7 import drift_acceptance
    >>> c = drift_acceptance([[0.010, 0.020], [0.014, 0.030]], risk_category="II")
    >>> c.value, c.limit, c.verdict, c.clause
    (0.025, 0.04, 'pass', 'ASCE 7-22 16.4.1.2')
    """
    d = as_float_array(drift_ratios, "drift_ratios", ndim=2)
    if d.shape[0] == 0 or not np.all(np.isfinite(d)) or np.any(d < 0):
        raise ValueError("`drift_ratios` must be finite, >= 0, one row per record")
    limit = positive_float(factor, "factor") * allowable_drift(risk_category, structure)
    value, k = _storey(np.abs(d).mean(axis=0))
    return Check(
        "ASCE 7-22 16.4.1.2",
        f"storey drift ratio, mean over {d.shape[0]} records (storey {k + 1})",
        value,
        limit,
        "maximum",
        "",
        f"{factor:g} x Table 12.12-1 (Risk Category {risk_category}, {structure})",
    )


def isolated_drift_check(drift_ratios: ArrayLike, *, limit: float = 0.020) -> Check:
    """The drift limit of an isolated structure analysed by response history, ASCE 7-22
    section 17.6.4.4: the storey drift of the structure above the isolation system
    (computed as section 12.8.6 does with ``C_d = R_I``: from an MCE_R analysis the drift
    itself) must not exceed ``0.020 h_sx``. The design value is the suite's (section
    17.6.3.4: the mean of seven or more records, else the largest).

    Parameters
    ----------
    drift_ratios : array_like, shape (n_records, n_storeys)
        Each record's peak absolute drift ratio per storey above the base level.
    limit : float, optional
        0.020.

    Examples
    --------
    >>> from duhamel.design.asce7 import isolated_drift_check
    >>> c = isolated_drift_check([[0.004, 0.003]] * 7)
    >>> round(c.value, 6), c.limit, round(c.ratio, 6), c.passes
    (0.004, 0.02, 0.2, True)
    """
    d = as_float_array(drift_ratios, "drift_ratios", ndim=2)
    if d.shape[0] == 0 or not np.all(np.isfinite(d)) or np.any(d < 0):
        raise ValueError("`drift_ratios` must be finite, >= 0, one row per record")
    value, k = _storey(suite_value(np.abs(d)))
    rule = "mean" if d.shape[0] >= MIN_RECORDS else "largest"
    return Check(
        "ASCE 7-22 17.6.4.4",
        f"storey drift ratio above the isolation system, {rule} of {d.shape[0]} records "
        f"(storey {k + 1})",
        value,
        positive_float(limit, "limit"),
        "maximum",
        "",
        "0.020 h_sx for the response-history procedure",
    )


def lower_limit_checks(
    values: Mapping[str, float], elf: IsolatedELF, *, regular: bool = True
) -> list[Check]:
    """The lower limits of ASCE 7-22 section 17.6.4 on the response-history design values,
    relative to the equivalent lateral force values (:func:`isolated_elf`'s governing ones):

    * ``isolator_displacement`` (the total maximum displacement) at least 80 % of ``D_TM``
      (section 17.6.4.1; ``D_TM`` of Eq. 17.5-3, without the reduction to ``D'_M`` the
      section permits);
    * ``base_shear_below`` (the isolation system and the elements below it) at least 90 % of
      ``V_b`` (section 17.6.4.1);
    * ``base_shear_above`` (the structure above the base level: the response-history shear
      divided by ``R_I``, as section 17.6.4.2 reduces it) at least 60 % of ``V_s`` for a
      regular structure, 80 % for an irregular one (section 17.6.4.2, the exceptions for the
      response-history procedure; ``V_s`` with the limits of section 17.5.4.3).

    Where a value falls short, the response-history results are scaled up to the limit
    (section 17.6.4.3): the check fails and its limit is the design value.

    Parameters
    ----------
    values : mapping
        The suite's design values by those names (m, N; the shear above unreduced); missing
        names are skipped.
    elf : IsolatedELF
        Its governing ``D_TM``, ``V_b``, ``V_s`` and its ``r_i``.
    regular : bool, optional
        Whether the structure above the isolation system is regular.

    Examples
    --------
    >>> from duhamel.design.asce7 import ELFBound, IsolatedELF, lower_limit_checks
    >>> bound = ELFBound("nominal", d_m=0.43, t_m=3.0, beta_m=0.2, b_m=1.5, k_m=1e7,
    ...                  d_tm=0.5, v_b=2e6, v_st=1.5e6, v_s=6e5, activation=1e5,
    ...                  isolators=(), evaluations=1, amplitude=0.43, residual=0.0)
    >>> elf = IsolatedELF({"nominal": bound}, sm1=1.0, weight=1e7, weight_above=9e6, r_i=2.0)
    >>> checks = lower_limit_checks({"isolator_displacement": 0.45, "base_shear_above": 6e5}, elf)
    >>> [(c.value, round(c.limit, 6), c.verdict) for c in checks]  # V_s: 6e5 / R_I, 0.6 V_s
    [(0.45, 0.4, 'pass'), (300000.0, 360000.0, 'fail')]
    """
    share_above = 0.6 if regular else 0.8
    r_i = float(elf.r_i)
    rows = [
        ("isolator_displacement", "total isolator displacement", 1.0, 0.8, "d_tm", "D_TM",
         "ASCE 7-22 17.6.4.1"),
        ("base_shear_below", "shear below the isolation interface", 1.0, 0.9, "v_b", "V_b",
         "ASCE 7-22 17.6.4.1"),
        ("base_shear_above", "shear above the base level / R_I", r_i, share_above, "v_s",
         "V_s", "ASCE 7-22 17.6.4.2"),
    ]  # fmt: skip
    out = []
    for key, quantity, divisor, share, attr, symbol, clause in rows:
        if key not in values:
            continue
        units = "m" if attr == "d_tm" else "N"
        elf_value = float(getattr(elf, attr))
        shown = f"{elf_value:.4f} m" if units == "m" else f"{elf_value / 1e3:.1f} kN"
        out.append(
            Check(
                clause,
                quantity,
                float(values[key]) / divisor,
                share * elf_value,
                "minimum",
                units,
                f"{100 * share:g} % of the ELF {symbol} = {shown}",
            )
        )
    return out

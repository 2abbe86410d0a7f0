"""The equations of ASCE 7-22 section 17.5 (equivalent lateral force procedure for isolated
structures), one function each: the damping coefficient of Table 17.5-1, the displacement
and period at the maximum displacement, the total displacement with torsion, the shears
above and below the isolation system and their distribution over the height.

Units: spectral values in g, lengths in m, forces in N, damping ratios as fractions (like
``zeta``); ``g`` is :data:`duhamel.constants.STANDARD_GRAVITY` unless given."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.validate import as_float_array, finite_float, positive_float
from duhamel.constants import STANDARD_GRAVITY

__all__ = [
    "TABLE_17_5_1",
    "base_shear",
    "damping_coefficient",
    "effective_period",
    "isolation_displacement",
    "structure_shear",
    "torsion_period_ratio",
    "total_displacement",
    "unreduced_shear",
    "vertical_distribution",
]

#: ASCE 7-22 Table 17.5-1: effective damping beta_M (fraction of critical) and the damping
#: coefficient B_M, linear between the rows; 0.8 below 2 %, 2.0 from 50 % on.
TABLE_17_5_1: tuple[tuple[float, float], ...] = (
    (0.02, 0.8),
    (0.05, 1.0),
    (0.10, 1.2),
    (0.20, 1.5),
    (0.30, 1.7),
    (0.40, 1.9),
    (0.50, 2.0),
)


def _nonneg(value: Any, name: str) -> float:
    out = finite_float(value, name)
    if out < 0.0:
        raise ValueError(f"`{name}` must be >= 0, got {value!r}")
    return out


def damping_coefficient(beta: ArrayLike) -> Any:
    """The damping coefficient ``B_M`` of ASCE 7-22 Table 17.5-1 (section 17.5.3.1) for the
    effective damping `beta` (a fraction of critical: 0.2 for 20 %), interpolated linearly
    between the table's rows; 0.8 at and below 2 %, 2.0 at and above 50 %.

    Parameters
    ----------
    beta : float or array_like
        Effective damping ratio(s), finite and >= 0.

    Returns
    -------
    float or ndarray
        ``B_M`` (a float for a scalar `beta`).

    Examples
    --------
    >>> from duhamel.design.asce7 import damping_coefficient
    >>> round(damping_coefficient(0.15), 12), damping_coefficient(0.01), damping_coefficient(0.6)
    (1.35, 0.8, 2.0)
    """
    b = as_float_array(beta, "beta")
    if not np.all(np.isfinite(b)) or np.any(b < 0.0):
        raise ValueError(f"`beta` must be finite damping ratios >= 0 (0.2 for 20 %), got {beta!r}")
    rows = np.array(TABLE_17_5_1)
    out = np.interp(b, rows[:, 0], rows[:, 1])
    return float(out) if out.ndim == 0 else out


def isolation_displacement(
    sm1: float, period: float, beta: float, *, g: float = STANDARD_GRAVITY
) -> float:
    """The maximum displacement of the isolation system, ASCE 7-22 Eq. 17.5-1 (section
    17.5.3.1): ``D_M = g S_M1 T_M / (4 pi^2 B_M)``, ``B_M`` from Table 17.5-1 at `beta`.

    Parameters
    ----------
    sm1 : float
        ``S_M1``, the MCE_R spectral acceleration at 1 s (g).
    period : float
        ``T_M``, the effective period at the maximum displacement (s).
    beta : float
        ``beta_M``, the effective damping at the maximum displacement (fraction).
    g : float, optional
        m/s^2 (standard gravity).

    Returns
    -------
    float
        ``D_M`` in m.

    Examples
    --------
    >>> from duhamel.design.asce7 import isolation_displacement
    >>> round(isolation_displacement(0.9, 3.0, 0.15), 6)  # 9.80665 * 0.9 * 3 / (4 pi^2 1.35)
    0.496811
    """
    s = positive_float(sm1, "sm1")
    t = positive_float(period, "period")
    b = damping_coefficient(_nonneg(beta, "beta"))
    return positive_float(g, "g") * s * t / (4.0 * math.pi**2 * b)


def effective_period(weight: float, stiffness: float, *, g: float = STANDARD_GRAVITY) -> float:
    """The effective period of the isolated structure at the maximum displacement, ASCE 7-22
    Eq. 17.5-2 (section 17.5.3.2): ``T_M = 2 pi sqrt(W / (k_M g))``.

    Parameters
    ----------
    weight : float
        ``W``, the seismic weight above the isolation interface (N).
    stiffness : float
        ``k_M``, the isolation system's effective stiffness at ``D_M`` (N/m).

    Examples
    --------
    >>> from duhamel.design.asce7 import effective_period
    >>> round(effective_period(9.80665e6, 1e6 * 4 * 3.141592653589793**2 / 9.0), 12)
    3.0
    """
    w = positive_float(weight, "weight")
    k = positive_float(stiffness, "stiffness")
    return 2.0 * math.pi * math.sqrt(w / (k * positive_float(g, "g")))


def torsion_period_ratio(x: ArrayLike, y: ArrayLike, b: float, d: float) -> float:
    """``P_T``, the ratio of the effective translational to the effective torsional period
    of the isolation system (ASCE 7-22 section 17.5.3.3, Eq. 17.5-4), for ``N`` isolators
    of equal stiffness at ``(x_i, y_i)`` from the centre of mass: ``P_T = sqrt(sum (x_i^2 +
    y_i^2) / N) / r_I``, ``r_I = sqrt((b^2 + d^2) / 12)`` the radius of gyration of the
    plan ``b x d``.

    Examples
    --------
    >>> from duhamel.design.asce7 import torsion_period_ratio
    >>> round(torsion_period_ratio([-10, 10, -10, 10], [-5, -5, 5, 5], 20.0, 10.0), 6)
    1.732051
    """
    xs = as_float_array(x, "x", ndim=1)
    ys = as_float_array(y, "y", ndim=1)
    if xs.shape != ys.shape or xs.size == 0 or not np.all(np.isfinite(xs) & np.isfinite(ys)):
        raise ValueError("`x` and `y` must be the same number (>= 1) of finite coordinates")
    r = math.sqrt((positive_float(b, "b") ** 2 + positive_float(d, "d") ** 2) / 12.0)
    return math.sqrt(float(np.mean(xs**2 + ys**2))) / r


def total_displacement(
    d_m: float,
    *,
    y: float = 0.0,
    eccentricity: float = 0.0,
    b: float | None = None,
    d: float | None = None,
    p_t: float = 1.0,
) -> float:
    """The total maximum displacement with torsion, ASCE 7-22 Eq. 17.5-3 (section
    17.5.3.3): ``D_TM = D_M [1 + (y / P_T^2) 12 e / (b^2 + d^2)]``, and not less than
    ``1.15 D_M``.

    Parameters
    ----------
    d_m : float
        ``D_M`` (m).
    y : float, optional
        Distance of the isolator from the centre of rigidity, perpendicular to the direction
        (m).
    eccentricity : float, optional
        ``e``, the actual eccentricity plus the accidental 5 % of the longest plan dimension
        perpendicular to the direction (m).
    b, d : float, optional
        The plan dimensions (m); needed when ``y e`` is not 0.
    p_t : float, optional
        ``P_T`` (:func:`torsion_period_ratio`; 1 when not computed).

    Examples
    --------
    >>> from duhamel.design.asce7 import total_displacement
    >>> total_displacement(0.4)  # no torsion given: the lower limit 1.15 D_M
    0.45999999999999996
    >>> round(total_displacement(0.4, y=15.0, eccentricity=2.0, b=30.0, d=20.0, p_t=1.1), 6)
    0.491545
    """
    dm = _nonneg(d_m, "d_m")
    yy, e = _nonneg(y, "y"), _nonneg(eccentricity, "eccentricity")
    factor = 1.0
    if yy * e > 0.0:
        if b is None or d is None:
            raise ValueError("`b` and `d` (the plan dimensions) are needed with `y` and `e`")
        pt = positive_float(p_t, "p_t")
        bb, dd = positive_float(b, "b"), positive_float(d, "d")
        factor = 1.0 + (yy / pt**2) * 12.0 * e / (bb**2 + dd**2)
    return dm * max(factor, 1.15)


def base_shear(k_m: float, d_m: float) -> float:
    """The shear on the isolation system and the elements below it, ASCE 7-22 Eq. 17.5-5
    (section 17.5.4.1): ``V_b = k_M D_M`` (N).

    Examples
    --------
    >>> from duhamel.design.asce7 import base_shear
    >>> base_shear(2.0e6, 0.3)
    600000.0
    """
    return _nonneg(k_m, "k_m") * _nonneg(d_m, "d_m")


def unreduced_shear(
    v_b: float, weight: float, weight_above: float, beta_m: float, *, abrupt: bool = False
) -> float:
    """The unreduced shear above the base level, ASCE 7-22 Eq. 17.5-7 (section 17.5.4.2):
    ``V_st = V_b (W_s / W)^(1 - 2.5 beta_M)``; for an isolation system whose hysteresis has
    an abrupt transition from pre-yield (pre-sliding) to post-yield (sliding) behaviour, the
    exponent is ``1 - 3.5 beta_M`` (the section's exception).

    Examples
    --------
    >>> from duhamel.design.asce7 import unreduced_shear
    >>> round(unreduced_shear(1e6, 10e6, 8e6, 0.2), 6)  # (0.8)^0.5
    894427.191
    """
    vb = _nonneg(v_b, "v_b")
    w, ws = positive_float(weight, "weight"), _nonneg(weight_above, "weight_above")
    if ws > w:
        raise ValueError(f"`weight_above` ({ws:g}) exceeds `weight` ({w:g})")
    beta = _nonneg(beta_m, "beta_m")
    return vb * (ws / w) ** (1.0 - (3.5 if abrupt else 2.5) * beta)


def structure_shear(v_st: float, r_i: float) -> float:
    """The design shear of the structure above the base level, ASCE 7-22 Eq. 17.5-6
    (section 17.5.4.2): ``V_s = V_st / R_I``, with ``1 <= R_I = 3 R / 8 <= 2``.

    Examples
    --------
    >>> from duhamel.design.asce7 import structure_shear
    >>> structure_shear(9e5, 2.0)
    450000.0
    """
    ri = positive_float(r_i, "r_i")
    if not 1.0 <= ri <= 2.0:
        raise ValueError(f"`r_i` must be 3 R / 8 within [1, 2] (section 17.5.4.2), got {ri}")
    return _nonneg(v_st, "v_st") / ri


def vertical_distribution(
    v_s: float,
    v_b: float,
    v_st: float,
    r_i: float,
    weights: ArrayLike,
    heights: ArrayLike,
    beta_m: float,
    t_fb: float,
) -> NDArray[np.float64]:
    """The lateral forces over the height, ASCE 7-22 section 17.5.5: at the base level
    ``F_1 = (V_b - V_st) / R_I`` (Eq. 17.5-8), above it ``F_x = C_vx V_s`` (Eq. 17.5-9) with
    ``C_vx = w_x h_x^k / sum_i w_i h_i^k`` (Eq. 17.5-10) and ``k = 14 beta_M T_fb``
    (Eq. 17.5-11).

    Parameters
    ----------
    v_s, v_b, v_st, r_i : float
        ``V_s``, ``V_b``, ``V_st`` (N) and ``R_I``.
    weights, heights : array_like
        Per level above the base level: ``w_x`` (N) and ``h_x``, the height above the base
        level (m).
    beta_m : float
        ``beta_M``.
    t_fb : float
        ``T_fb``, the fixed-base period of the structure above the isolation system (s).

    Returns
    -------
    ndarray
        ``[F_1, F_2, ...]``: the base level's force, then one per level above (N).

    Examples
    --------
    >>> from duhamel.design.asce7 import vertical_distribution
    >>> f = vertical_distribution(4e5, 1e6, 8e5, 2.0, [1e6, 1e6], [3.0, 6.0], 0.2, 0.5)
    >>> [round(float(v), 3) for v in f]  # k = 1.4: F_x in proportion to h_x^1.4
    [100000.0, 109919.83, 290080.17]
    """
    w = as_float_array(weights, "weights", ndim=1)
    h = as_float_array(heights, "heights", ndim=1)
    if w.shape != h.shape or w.size == 0:
        raise ValueError("`weights` and `heights` must give one value per level above the base")
    if not (np.all(np.isfinite(w)) and np.all(w >= 0) and np.all(np.isfinite(h))):
        raise ValueError("`weights` must be finite and >= 0, `heights` finite")
    if np.any(h <= 0):
        raise ValueError("`heights` must be > 0 (above the base level)")
    ri = positive_float(r_i, "r_i")
    k = 14.0 * _nonneg(beta_m, "beta_m") * _nonneg(t_fb, "t_fb")
    share = w * h**k
    if share.sum() <= 0.0:
        raise ValueError("`weights` must not all be 0")
    f1 = (_nonneg(v_b, "v_b") - _nonneg(v_st, "v_st")) / ri
    return np.concatenate([[f1], _nonneg(v_s, "v_s") * share / share.sum()])

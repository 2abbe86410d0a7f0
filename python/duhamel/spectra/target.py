"""Target (design) spectra: :class:`TargetSpectrum` for any table, and the code spectra of
ASCE 7-22 (:func:`asce7`, :func:`asce7_multi_period`) and Eurocode 8 (:func:`eurocode8`);
exported from :mod:`duhamel.spectra`."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from itertools import pairwise
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.validate import as_float_array, finite_float, flag
from duhamel.records.motion import G

__all__ = ["TargetSpectrum", "asce7", "asce7_multi_period", "eurocode8"]

Formula = Callable[[NDArray[np.float64]], NDArray[np.float64]]


def _positive(value: Any, name: str) -> float:
    """`value` as a positive finite float; a string or another non-number is a TypeError."""
    v = finite_float(value, name)
    if not v > 0.0:
        raise ValueError(f"`{name}` must be a positive finite number, got {value!r}")
    return v


def _ratio(value: Any, name: str) -> float:
    """A damping ratio in [0, 1)."""
    z = finite_float(value, name)
    if not 0.0 <= z < 1.0:
        raise ValueError(f"`{name}` must be a ratio in [0, 1), got {value!r}")
    return z


def check_target(target: Any, name: str = "target") -> None:
    """TypeError unless `target` is a :class:`TargetSpectrum` (a string such as ``'asce7'``
    names no spectrum: the code spectra are built by their functions)."""
    if not isinstance(target, TargetSpectrum):
        raise TypeError(
            f"`{name}` must be a duhamel.spectra.TargetSpectrum (e.g. asce7(sds, sd1, tl), "
            f"eurocode8(ag, ground_type) or a table), got {type(target).__name__}"
        )


@dataclass(frozen=True, eq=False)
class TargetSpectrum:
    """A target pseudo-acceleration spectrum.

    Parameters
    ----------
    periods : array_like
        Periods in s, >= 0 and increasing (at least 2).
    sa : array_like
        Spectral (pseudo-)accelerations in m/s^2 at `periods`, > 0.
    damping : float, optional
        The damping ratio the spectrum is for (default 0.05).
    name : str, optional
        A label.
    formula : callable, optional
        ``periods -> sa`` (m/s^2) evaluating the spectrum exactly (the code spectra pass
        their formula); without it, :meth:`__call__` interpolates the table linearly in
        log-period and log-Sa (linearly in Sa below the first positive period).

    Attributes
    ----------
    sa_g : ndarray
        `sa` in g.

    Examples
    --------
    >>> from duhamel.spectra import TargetSpectrum
    >>> ts = TargetSpectrum([0.1, 1.0, 2.0], [9.80665, 4.903325, 2.4516625])
    >>> float(ts(1.0)), float(ts.sa_g[0])
    (4.903325, 1.0)
    """

    periods: NDArray[np.float64]
    sa: NDArray[np.float64]
    damping: float = 0.05
    name: str = ""
    formula: Formula | None = None
    metadata: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        p = as_float_array(self.periods, "periods", ndim=1)
        s = as_float_array(self.sa, "sa", ndim=1)
        if p.size < 2 or p.shape != s.shape:
            raise ValueError(
                f"`periods` and `sa` must have the same length >= 2, got {p.size} and {s.size}"
            )
        if not (np.all(np.isfinite(p)) and np.all(np.isfinite(s))):
            raise ValueError("`periods` and `sa` must be finite")
        if p[0] < 0.0 or np.any(np.diff(p) <= 0.0):
            raise ValueError("`periods` must be >= 0 and strictly increasing")
        if np.any(s <= 0.0):
            raise ValueError("`sa` must be > 0 at every period")
        z = _ratio(self.damping, "damping")
        for a in (p, s):
            a.setflags(write=False)
        object.__setattr__(self, "periods", p)
        object.__setattr__(self, "sa", s)
        object.__setattr__(self, "damping", z)
        object.__setattr__(self, "metadata", dict(self.metadata))

    def __repr__(self) -> str:
        return (
            f"TargetSpectrum(name={self.name!r}, periods {self.periods[0]:g}-"
            f"{self.periods[-1]:g} s, peak {self.sa.max() / G:.4g} g)"
        )

    @property
    def sa_g(self) -> NDArray[np.float64]:
        """`sa` in g."""
        return self.sa / G

    def __call__(self, periods: ArrayLike) -> NDArray[np.float64]:
        """The spectrum (m/s^2) at `periods` (s), which must lie within the table's range:
        the exact formula of a code spectrum, or the table interpolated in log-log."""
        p = np.asarray(as_float_array(periods, "periods"), dtype=np.float64)
        lo, hi = self.periods[0], self.periods[-1]
        if p.size and (np.any(~np.isfinite(p)) or p.min() < lo or p.max() > hi * (1 + 1e-12)):
            raise ValueError(
                f"`periods` must lie in the target's range [{lo:g}, {hi:g}] s, got "
                f"[{np.nanmin(p):g}, {np.nanmax(p):g}]"
            )
        if self.formula is not None:
            return np.asarray(self.formula(p), dtype=np.float64)
        return _loglog(self.periods, self.sa, p)

    def plot(self, ax: Any = None, *, units: str = "g", **kwargs: Any) -> Any:
        """Plot the spectrum against period (linear axes); returns the matplotlib Axes."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(6.5, 4.5))
        p = _dense(self.periods)
        scale = 1.0 / G if units == "g" else 1.0
        ax.plot(p, scale * self(p), label=kwargs.pop("label", self.name or "target"), **kwargs)
        ax.set_xlabel("Period [s]")
        ax.set_ylabel("Sa [g]" if units == "g" else "Sa [m/s^2]")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize="small")
        return ax


def _dense(p: NDArray[np.float64]) -> NDArray[np.float64]:
    """The table's periods with 20 points between neighbours (for plots)."""
    return np.unique(np.concatenate([np.linspace(a, b, 21) for a, b in pairwise(p)]))


def _loglog(p: NDArray[np.float64], s: NDArray[np.float64], q: NDArray[np.float64]) -> Any:
    """Interpolation of the table (p, s) at q: log-log between positive periods, linear
    between period 0 and the first positive period."""
    out = np.empty_like(q, dtype=np.float64)
    pos = p > 0.0
    lp, ls = np.log(p[pos]), np.log(s[pos])
    big = q >= p[pos][0]
    out[big] = np.exp(np.interp(np.log(q[big]), lp, ls))
    out[~big] = np.interp(q[~big], p, s)
    return out


def _asce7_formula(sds: float, sd1: float, tl: float, factor: float) -> Formula:
    t0, ts = 0.2 * sd1 / sds, sd1 / sds

    def formula(t: NDArray[np.float64]) -> NDArray[np.float64]:
        t = np.asarray(t, dtype=np.float64)
        safe = np.where(t > 0.0, t, 1.0)
        sa = np.select(
            [t < t0, t <= ts, t <= tl],
            [sds * (0.4 + 0.6 * t / t0), np.full_like(t, sds), sd1 / safe],
            sd1 * tl / (safe * safe),
        )
        return factor * G * sa

    return formula


def asce7(
    sds: float,
    sd1: float,
    tl: float,
    mce: bool = False,
    *,
    t_max: float = 10.0,
) -> TargetSpectrum:
    """The ASCE 7-22 two-period design response spectrum (section 11.4.5.2).

    With ``T0 = 0.2 SD1 / SDS`` and ``TS = SD1 / SDS``::

        Sa = SDS (0.4 + 0.6 T / T0)   T < T0
        Sa = SDS                      T0 <= T <= TS
        Sa = SD1 / T                  TS < T <= TL
        Sa = SD1 TL / T^2             T > TL

    ``mce=True`` gives the MCE_R spectrum, 1.5 times the design spectrum (section 11.4.6).

    Parameters
    ----------
    sds, sd1 : float
        Design spectral accelerations at short periods and at 1 s, in g.
    tl : float
        Long-period transition period in s.
    mce : bool, optional
        The risk-targeted maximum considered earthquake spectrum instead of the design one.
    t_max : float, optional
        Longest period of the table (default 10 s); :meth:`TargetSpectrum.__call__`
        evaluates the formula exactly at any period up to it.

    Returns
    -------
    TargetSpectrum
        In m/s^2; ``metadata`` holds ``sds``, ``sd1``, ``tl``, ``t0``, ``ts``, ``mce``.

    Examples
    --------
    >>> from duhamel.spectra import asce7
    >>> ts = asce7(sds=1.0, sd1=0.6, tl=8.0)
    >>> ts.metadata["t0"], ts.metadata["ts"], round(float(ts(1.2)) / 9.80665, 12)
    (0.12, 0.6, 0.5)
    """
    sds, sd1, tl = _positive(sds, "sds"), _positive(sd1, "sd1"), _positive(tl, "tl")
    t_max = _positive(t_max, "t_max")
    mce = flag(mce, "mce")
    t0, ts = 0.2 * sd1 / sds, sd1 / sds
    if tl < ts:
        raise ValueError(f"`tl` ({tl:g} s) must be >= TS = SD1/SDS = {ts:g} s")
    factor = 1.5 if mce else 1.0
    formula = _asce7_formula(sds, sd1, tl, factor)
    p = np.unique(np.concatenate([[0.0, t0, ts], np.geomspace(0.01, t_max, 200), [tl]]))
    p = p[p <= t_max]
    meta = {"sds": sds, "sd1": sd1, "tl": tl, "t0": t0, "ts": ts, "mce": bool(mce)}
    name = f"ASCE 7-22 {'MCE_R' if mce else 'design'} (SDS={sds:g} g, SD1={sd1:g} g)"
    return TargetSpectrum(p, formula(p), 0.05, name, formula, meta)


def asce7_multi_period(
    periods: ArrayLike, sa_mce: ArrayLike, mce: bool = False, *, name: str = ""
) -> TargetSpectrum:
    """The ASCE 7-22 multi-period spectrum (section 11.4.5.1) from its table of MCE_R
    values in g (as the USGS Seismic Design Geodatabase gives them for a site): the MCE_R
    spectrum with ``mce=True``, the design spectrum (two thirds of it) otherwise.

    Between the table's periods the spectrum is interpolated linearly in log-period and
    log-Sa (linearly from period 0 to the first positive period); the standard leaves the
    interpolation to the user, and this is the usual choice for spectra.

    Examples
    --------
    >>> from duhamel.spectra import asce7_multi_period
    >>> ts = asce7_multi_period([0.0, 0.2, 1.0, 5.0], [0.6, 1.5, 0.9, 0.15])
    >>> round(float(ts.sa_g[1]), 12)
    1.0
    """
    p = as_float_array(periods, "periods", ndim=1)
    s = as_float_array(sa_mce, "sa_mce", ndim=1)
    mce = flag(mce, "mce")
    factor = 1.0 if mce else 2.0 / 3.0
    label = name or f"ASCE 7-22 multi-period {'MCE_R' if mce else 'design'}"
    return TargetSpectrum(p, factor * G * s, 0.05, label, None, {"mce": bool(mce)})


#: EN 1998-1:2004 tables 3.2 (type 1) and 3.3 (type 2): S, TB, TC, TD per ground type.
EC8_GROUND = {
    1: {
        "A": (1.0, 0.15, 0.4, 2.0),
        "B": (1.2, 0.15, 0.5, 2.0),
        "C": (1.15, 0.20, 0.6, 2.0),
        "D": (1.35, 0.20, 0.8, 2.0),
        "E": (1.4, 0.15, 0.5, 2.0),
    },
    2: {
        "A": (1.0, 0.05, 0.25, 1.2),
        "B": (1.35, 0.05, 0.25, 1.2),
        "C": (1.5, 0.10, 0.25, 1.2),
        "D": (1.8, 0.10, 0.30, 1.2),
        "E": (1.6, 0.05, 0.25, 1.2),
    },
}


def eurocode8(
    ag: float,
    ground_type: str,
    spectrum_type: int = 1,
    importance: float = 1.0,
    damping: float = 0.05,
) -> TargetSpectrum:
    """The horizontal elastic response spectrum of EN 1998-1:2004, section 3.2.2.2.

    With ``a_g = importance * ag``, ``eta = sqrt(10 / (5 + xi)) >= 0.55`` (xi in percent)
    and S, TB, TC, TD of tables 3.2 (type 1) or 3.3 (type 2)::

        Se = a_g S (1 + T / TB (2.5 eta - 1))   0 <= T <= TB
        Se = a_g S eta 2.5                      TB <= T <= TC
        Se = a_g S eta 2.5 TC / T               TC <= T <= TD
        Se = a_g S eta 2.5 TC TD / T^2          TD <= T <= 4 s

    Parameters
    ----------
    ag : float
        Reference peak ground acceleration on type A ground, a_gR, in g.
    ground_type : {'A', 'B', 'C', 'D', 'E'}
    spectrum_type : {1, 2}, optional
    importance : float, optional
        Importance factor gamma_I (default 1).
    damping : float, optional
        Viscous damping ratio (default 0.05; eta = 1).

    Returns
    -------
    TargetSpectrum
        Up to 4 s (the code's range), in m/s^2.

    Examples
    --------
    >>> from duhamel.spectra import eurocode8
    >>> ts = eurocode8(0.25, "C")
    >>> round(float(ts(0.4)) / 9.80665, 12)  # plateau: 0.25 * 1.15 * 2.5
    0.71875
    """
    ag = _positive(ag, "ag")
    importance = _positive(importance, "importance")
    xi = _ratio(damping, "damping")
    if (
        isinstance(spectrum_type, bool)
        or not isinstance(spectrum_type, int | np.integer)
        or int(spectrum_type) not in EC8_GROUND
    ):
        raise ValueError(f"`spectrum_type` must be 1 or 2, got {spectrum_type!r}")
    key = str(ground_type).strip().upper()
    spectrum_type = int(spectrum_type)
    if key not in EC8_GROUND[spectrum_type]:
        raise ValueError(
            f"`ground_type` must be one of 'A'..'E' (S1 and S2 need a site study), got "
            f"{ground_type!r}"
        )
    s, tb, tc, td = EC8_GROUND[spectrum_type][key]
    eta = max(np.sqrt(10.0 / (5.0 + 100.0 * xi)), 0.55)
    a = importance * ag * G

    def formula(t: NDArray[np.float64]) -> NDArray[np.float64]:
        t = np.asarray(t, dtype=np.float64)
        safe = np.where(t > 0.0, t, 1.0)
        return (
            a
            * s
            * np.select(
                [t <= tb, t <= tc, t <= td],
                [
                    1.0 + t / tb * (2.5 * eta - 1.0),
                    np.full_like(t, 2.5 * eta),
                    2.5 * eta * tc / safe,
                ],
                2.5 * eta * tc * td / (safe * safe),
            )
        )

    p = np.unique(np.concatenate([[0.0, tb, tc, td], np.geomspace(0.01, 4.0, 200)]))
    meta = {"ag": ag, "S": s, "TB": tb, "TC": tc, "TD": td, "eta": float(eta)}
    meta.update(ground_type=key, spectrum_type=spectrum_type, importance=importance)
    name = f"EN 1998-1 type {spectrum_type}, ground {key}, ag={importance * ag:g} g"
    return TargetSpectrum(p, formula(p), xi, name, formula, meta)

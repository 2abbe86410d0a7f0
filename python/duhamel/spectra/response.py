"""Response spectra (:func:`response_spectrum`), RotD spectra (:func:`rotd`) and
constant-ductility spectra (:func:`ductility_spectrum`) with their result classes;
exported from :mod:`duhamel.spectra`, plotted by :mod:`.plot`."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.output import _physical_memory
from duhamel._engine.validate import as_float_array, finite_float, positive_int
from duhamel.records.motion import G, GroundMotion
from duhamel.spectra import _batches
from duhamel.spectra.elastic import ResponseSpectrum, _omega

__all__ = [
    "DuctilitySpectrum",
    "ResponseSpectrum",
    "RotDSpectrum",
    "ductility_spectrum",
    "response_spectrum",
    "rotd",
]

Motions = GroundMotion | tuple[ArrayLike, ArrayLike] | Sequence[Any]


def _motion(m: Any, i: int | None = None) -> GroundMotion:
    """A GroundMotion from a GroundMotion or a ``(t, a)`` pair (a in m/s^2, t uniform)."""
    where = "`motions`" if i is None else f"`motions[{i}]`"
    if isinstance(m, GroundMotion):
        return m
    if _is_pair(m) or (isinstance(m, list) and len(m) == 2):
        t = as_float_array(m[0], "t", ndim=1)
        a = as_float_array(m[1], "a", ndim=1)
        if t.shape != a.shape or t.size < 2:
            raise ValueError(
                f"{where}: `t` and `a` must have the same length >= 2, got {t.size} and {a.size}"
            )
        steps = np.diff(t)
        dt = float((t[-1] - t[0]) / (t.size - 1))
        if not (dt > 0.0) or np.any(np.abs(steps - dt) > 1e-6 * dt):
            raise ValueError(f"{where}: `t` must be uniformly spaced and increasing")
        return GroundMotion(a, dt, "m/s^2")
    raise TypeError(
        f"{where} must be a GroundMotion or a (t, a) pair of arrays, got {type(m).__name__}"
    )


def _is_pair(m: Any) -> bool:
    """A ``(t, a)`` tuple: two arrays (or lists of numbers), not motions or pairs."""
    return (
        isinstance(m, tuple)
        and len(m) == 2
        and not any(isinstance(x, GroundMotion | tuple) for x in m)
        and all(np.ndim(x) == 1 for x in m)
    )


def _motions(motions: Motions) -> list[GroundMotion]:
    """The records of `motions`: a GroundMotion, a ``(t, a)`` tuple, or a list of them."""
    if isinstance(motions, GroundMotion) or _is_pair(motions):
        return [_motion(motions)]
    if isinstance(motions, Sequence) and not isinstance(motions, str):
        if len(motions) == 0:
            raise ValueError("`motions` is empty")
        return [_motion(m, i) for i, m in enumerate(motions)]
    return [_motion(motions)]


#: The shortest positive period (s) of a spectrum: below it ``omega^2`` approaches the
#: double range (``psa = omega^2 sd`` would be ``inf * 0``); period 0 is the rigid oscillator.
MIN_PERIOD = 1e-100
#: The shortest period of a ductility spectrum, relative to the record's step: below it
#: ``omega dt`` exceeds 6e12 and locating the yield events within a step costs without end.
RIGID_RATIO = 1e-12
#: Most directions of a RotD spectrum (a 0.0018-degree step).
MAX_ANGLES = 100_000
#: Most worker threads (as `threads` of duhamel.solve).
MAX_THREADS = 1024


def _threads(threads: Any) -> int | None:
    """`threads` checked as :func:`duhamel.solve` checks it: None or an int in [1, 1024]."""
    return None if threads is None else positive_int(threads, "threads", MAX_THREADS)


def _periods(periods: ArrayLike, positive: bool = False) -> NDArray[np.float64]:
    p = as_float_array(periods, "periods")
    p = np.atleast_1d(p)
    if p.ndim != 1 or p.size == 0:
        raise ValueError(f"`periods` must be a non-empty 1-D array, got shape {p.shape}")
    if np.any(p < 0.0) or (positive and np.any(p == 0.0)):
        bound = "> 0" if positive else ">= 0"
        raise ValueError(f"`periods` must be {bound} (s), got {p.min()}")
    tiny = p[(p > 0.0) & (p < MIN_PERIOD)]
    if tiny.size:
        rigid = "" if positive else "; use 0 for the rigid oscillator"
        raise ValueError(
            f"`periods` must be 0 or at least {MIN_PERIOD:g} s (omega^2 would leave the double "
            f"range), got {tiny[0]!r}{rigid}"
        )
    return p


def _dampings(damping: float | ArrayLike) -> NDArray[np.float64]:
    z = np.atleast_1d(as_float_array(damping, "damping"))
    if z.ndim != 1 or z.size == 0 or np.any(z < 0.0):
        raise ValueError(f"`damping` must be a ratio >= 0 or a 1-D array of them, got {damping}")
    return z


def response_spectrum(
    motions: Motions,
    periods: ArrayLike,
    damping: float | ArrayLike = 0.05,
    *,
    threads: int | None = None,
    peaks: str = "sampled",
) -> ResponseSpectrum:
    """Elastic response spectra of one or several records.

    Parameters
    ----------
    motions : GroundMotion, (t, a) pair, or list of them
        Records (``a`` in m/s^2, ``t`` uniform), linear between samples.
    periods : array_like
        Periods in s, >= 0.
    damping : float or array_like, optional
        Damping ratio(s), >= 0 (default 0.05).
    threads : int, optional
        Worker threads, 1 to 1024 (default: all cores), checked as by :func:`duhamel.solve`.
    peaks : {"sampled", "exact"}
        ``"sampled"`` (default, as every reference implementation): the peaks at the
        record's samples. ``"exact"``: the true peaks of the response to the
        piecewise-linear record, between the samples too (where the derivative of each
        quantity vanishes inside a step; damping < 1). They are never smaller; for periods
        near the sampling interval they are markedly larger (docs/events.md).

    Returns
    -------
    ResponseSpectrum

    Raises
    ------
    TypeError
        A parameter of the wrong kind (`threads` not an int, a complex record...).
    ValueError
        Negative periods or periods in ``(0, 1e-100)`` s, negative damping, non-uniform
        times, a response beyond the double range (the message names the period).
        Arrays of shape ``(n_motions, n_dampings, n_periods)`` whatever was passed.

    Examples
    --------
    >>> import numpy as np
    >>> from duhamel.spectra import response_spectrum
    >>> t = np.arange(0.0, 10.0, 0.005)
    >>> rs = response_spectrum((t, np.sin(6.0 * t)), periods=np.logspace(-2, 1, 50))
    >>> rs.sd.shape
    (1, 1, 50)
    >>> top = response_spectrum((t, np.sin(6.0 * t)), [0.02, 1.0], peaks="exact")
    >>> bool(np.all(top.sd >= response_spectrum((t, np.sin(6.0 * t)), [0.02, 1.0]).sd))
    True
    """
    if not isinstance(peaks, str) or peaks not in ("sampled", "exact"):
        raise ValueError(f"`peaks` must be 'sampled' or 'exact', got {peaks!r}")
    ms = _motions(motions)
    p, z = _periods(periods), _dampings(damping)
    if peaks == "exact" and np.any(z >= 1.0):
        raise ValueError(f"`damping` must be < 1 with peaks='exact', got {z.max():g}")
    threads = _threads(threads)
    sd, sv, sa = _batches.elastic(
        [m.a for m in ms], [m.dt for m in ms], p, z, threads, exact=peaks == "exact"
    )
    return ResponseSpectrum(p, z, sd, sv, sa, [m.name for m in ms])


@dataclass(frozen=True, eq=False)
class RotDSpectrum:
    """RotDnn spectra of a pair of components; arrays ``(n_dampings, n_percentiles,
    n_periods)``; ``peaks`` is the peak displacement per direction ``(n_dampings, n_periods,
    n_angles)`` for directions ``theta = j * 180 / n_angles`` degrees."""

    periods: NDArray[np.float64]
    damping: NDArray[np.float64]
    percentiles: NDArray[np.float64]
    sd: NDArray[np.float64]
    peaks: NDArray[np.float64]

    @property
    def psa(self) -> NDArray[np.float64]:
        """Pseudo-acceleration ``omega^2 sd`` (m/s^2); 0 at period 0."""
        return _omega(self.periods) ** 2 * self.sd

    @property
    def psv(self) -> NDArray[np.float64]:
        """Pseudo-velocity ``omega sd`` (m/s)."""
        return _omega(self.periods) * self.sd


def rotd(
    motion_1: GroundMotion | tuple[ArrayLike, ArrayLike],
    motion_2: GroundMotion | tuple[ArrayLike, ArrayLike],
    periods: ArrayLike,
    percentiles: ArrayLike = (50, 100),
    damping: float | ArrayLike = 0.05,
    *,
    n_angles: int = 180,
    threads: int | None = None,
) -> RotDSpectrum:
    """Orientation-independent spectra RotDnn (Boore 2010) of two horizontal components.

    The oscillator's displacements under both components are combined along every direction
    ``theta_j = j * 180 / n_angles`` degrees; RotDnn is the nn-th percentile over directions
    of the peak of that projection (RotD50 the median, RotD100 the largest).

    Parameters
    ----------
    motion_1, motion_2 : GroundMotion or (t, a) pair
        Orthogonal components with the same sampling interval (the shorter is padded with
        zeros to the longer's length).
    periods : array_like
        Periods in s.
    percentiles : array_like, optional
        Percentiles in [0, 100] (default RotD50 and RotD100).
    damping : float or array_like, optional
        Damping ratio(s) (default 0.05).
    n_angles : int, optional
        Directions over 180 degrees, 1 to 100,000 (default 180: 1-degree steps); refused
        when their peaks would not fit in memory.
    threads : int, optional
        Worker threads (default: all cores).

    Returns
    -------
    RotDSpectrum

    Examples
    --------
    >>> import numpy as np
    >>> from duhamel.spectra import rotd
    >>> t = np.arange(0.0, 10.0, 0.01)
    >>> r = rotd((t, np.sin(5 * t)), (t, np.cos(5 * t)), periods=[0.5, 1.0])
    >>> r.psa.shape  # (dampings, percentiles, periods)
    (1, 2, 2)
    """
    m1, m2 = _motion(motion_1), _motion(motion_2)
    if abs(m1.dt - m2.dt) > 1e-9 * m1.dt:
        raise ValueError(f"`motion_2` has dt = {m2.dt} s, `motion_1` has {m1.dt} s: resample")
    n = max(m1.a.size, m2.a.size)
    a1, a2 = (np.pad(m.a, (0, n - m.a.size)) for m in (m1, m2))
    p, z = _periods(periods), _dampings(damping)
    q = np.atleast_1d(as_float_array(percentiles, "percentiles"))
    if q.ndim != 1 or np.any((q < 0) | (q > 100)):
        raise ValueError(f"`percentiles` must be in [0, 100], got {percentiles}")
    n_angles = positive_int(n_angles, "n_angles", MAX_ANGLES)
    threads = _threads(threads)
    # the peaks, their sorted copy for the percentiles and the angles' cosines and sines
    need = 8.0 * (2 * z.size * p.size + 2) * n_angles
    if need > _physical_memory():
        raise ValueError(
            f"`n_angles` = {n_angles:,} directions of {z.size * p.size:,} oscillators need "
            f"{need / 2**30:.3g} GiB, more than the machine's memory: take fewer directions"
        )
    peaks = _batches.rotd_peaks((a1, a2), m1.dt, p, z, n_angles, threads)
    sd = np.moveaxis(np.percentile(peaks, q, axis=2), 0, 1)  # (damping, percentile, period)
    return RotDSpectrum(p, z, q, sd, peaks)


@dataclass(frozen=True, eq=False)
class DuctilitySpectrum:
    """Constant-ductility spectra of the bilinear oscillator; arrays of shape
    ``(n_motions, n_ductilities, n_periods)``.

    Attributes
    ----------
    uy : ndarray
        Yield displacement (m).
    fy : ndarray
        Yield force per unit mass, ``omega^2 uy`` (m/s^2); ``cy = fy / g`` is the yield
        strength coefficient.
    sd : ndarray
        Peak inelastic displacement ``ductility * uy`` (m).
    r : ndarray
        Strength reduction factor: elastic force over yield force.
    """

    periods: NDArray[np.float64]
    ductility: NDArray[np.float64]
    damping: float
    alpha: float
    uy: NDArray[np.float64]
    elastic_sd: NDArray[np.float64]
    names: list[str]

    @property
    def fy(self) -> NDArray[np.float64]:
        w = _omega(self.periods)
        return w * w * self.uy

    @property
    def cy(self) -> NDArray[np.float64]:
        """Yield strength coefficient ``fy / g``."""
        return self.fy / G

    @property
    def sd(self) -> NDArray[np.float64]:
        return self.ductility[None, :, None] * self.uy

    @property
    def r(self) -> NDArray[np.float64]:
        return self.elastic_sd[:, None, :] / self.uy


def ductility_spectrum(
    motions: Motions,
    periods: ArrayLike,
    ductility: ArrayLike,
    damping: float = 0.05,
    *,
    alpha: float = 0.0,
    threads: int | None = None,
) -> DuctilitySpectrum:
    """Constant-ductility spectra: per period, the largest yield strength of the bilinear
    oscillator whose peak displacement is `ductility` times its yield displacement.

    The oscillator (elastic stiffness ``m omega^2``, post-yield ``alpha`` times that,
    kinematic hardening, viscous damping on the elastic frequency) is integrated exactly
    on each branch, yielding and unloading instants located inside the steps. The strength
    ratio is scanned down from the elastic strength and the first bracket bisected to 1e-10
    (the largest strength when several reach the ductility, the usual convention).

    Parameters
    ----------
    motions : GroundMotion, (t, a) pair, or list of them
    periods : array_like
        Periods in s, at least ``1e-12`` times each record's `dt`.
    ductility : array_like
        Target ductility factors, >= 1 (1 is the elastic spectrum).
    damping : float, optional
        Damping ratio (default 0.05).
    alpha : float, optional
        Post-yield stiffness ratio in [0, 1) (default 0: elastic-perfectly-plastic).
    threads : int, optional
        Worker threads (default: all cores).

    Returns
    -------
    DuctilitySpectrum

    Examples
    --------
    >>> import numpy as np
    >>> from duhamel.spectra import ductility_spectrum
    >>> t = np.arange(0.0, 10.0, 0.01)
    >>> ds = ductility_spectrum((t, 3 * np.sin(4 * t)), [0.5, 1.0], ductility=[1, 2, 4])
    >>> bool(np.all(np.diff(ds.cy[0], axis=0) < 0))  # more ductility, less strength
    True
    """
    ms = _motions(motions)
    p = _periods(periods, positive=True)
    mu = np.atleast_1d(as_float_array(ductility, "ductility"))
    if mu.ndim != 1 or mu.size == 0 or np.any(mu < 1.0):
        raise ValueError(f"`ductility` must be factors >= 1, got {ductility}")
    if np.ndim(damping) != 0:
        raise ValueError("`damping` must be one ratio for a ductility spectrum")
    zeta = float(_dampings(damping)[0])
    alpha = finite_float(alpha, "alpha")
    if not 0.0 <= alpha < 1.0:
        raise ValueError(f"`alpha` must be in [0, 1), got {alpha!r}")
    threads = _threads(threads)
    for i, m in enumerate(ms):
        if p.min() < RIGID_RATIO * m.dt:
            raise ValueError(
                f"`periods` must be at least {RIGID_RATIO:g} dt = {RIGID_RATIO * m.dt:g} s for "
                f"record {i} (shorter, the oscillator is rigid to double precision), got "
                f"{p.min()!r}"
            )
        if not np.any(m.a):
            raise ValueError(
                f"`motions`: record {i} ({m.name!r}) is zero: no yield strength reaches a "
                "ductility under it"
            )
    uy = np.stack([_batches.ductility(m.a, m.dt, p, (zeta, alpha), mu, threads) for m in ms])
    el = response_spectrum(ms, p, zeta, threads=threads).sd[:, 0, :]
    if not (np.all(np.isfinite(uy)) and np.all(uy > 0.0)):
        bad = np.argwhere(~(np.isfinite(uy) & (uy > 0.0)))[0]
        raise ValueError(
            f"`motions`: no positive yield displacement found for record {bad[0]} at "
            f"ductility {mu[bad[1]]:g} and period {p[bad[2]]:g} s (a response below the "
            "double precision of the record's scale)"
        )
    return DuctilitySpectrum(p, mu, zeta, float(alpha), uy, el, [m.name for m in ms])

"""Response spectra (:func:`response_spectrum`), RotD spectra (:func:`rotd`) and
constant-ductility spectra (:func:`ductility_spectrum`) with their result classes;
exported from :mod:`duhamel.spectra`, plotted by :mod:`.plot`."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel import _core
from duhamel._engine.validate import as_float_array
from duhamel.records.motion import G, GroundMotion
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


def _periods(periods: ArrayLike, positive: bool = False) -> NDArray[np.float64]:
    p = as_float_array(periods, "periods")
    p = np.atleast_1d(p)
    if p.ndim != 1 or p.size == 0:
        raise ValueError(f"`periods` must be a non-empty 1-D array, got shape {p.shape}")
    if np.any(p < 0.0) or (positive and np.any(p == 0.0)):
        bound = "> 0" if positive else ">= 0"
        raise ValueError(f"`periods` must be {bound} (s), got {p.min()}")
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
        Worker threads (default: all cores).
    peaks : {"sampled", "exact"}
        ``"sampled"`` (default, as every reference implementation): the peaks at the
        record's samples. ``"exact"``: the true peaks of the response to the
        piecewise-linear record, between the samples too (where the derivative of each
        quantity vanishes inside a step; damping < 1). They are never smaller; for periods
        near the sampling interval they are markedly larger (docs/events.md).

    Returns
    -------
    ResponseSpectrum
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
    if peaks not in ("sampled", "exact"):
        raise ValueError(f"`peaks` must be 'sampled' or 'exact', got {peaks!r}")
    ms = _motions(motions)
    p, z = _periods(periods), _dampings(damping)
    if peaks == "exact" and np.any(z >= 1.0):
        raise ValueError(f"`damping` must be < 1 with peaks='exact', got {z.max():g}")
    sd, sv, sa = _core.elastic_spectra(
        [m.a for m in ms], [m.dt for m in ms], p, z, threads, peaks == "exact"
    )
    shape = (len(ms), z.size, p.size)
    return ResponseSpectrum(
        p, z, sd.reshape(shape), sv.reshape(shape), sa.reshape(shape), [m.name for m in ms]
    )


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
        Directions over 180 degrees (default 180: 1-degree steps).
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
    if int(n_angles) < 1:
        raise ValueError(f"`n_angles` must be >= 1, got {n_angles}")
    peaks = _core.rotd_peaks((a1, a2), m1.dt, p, z, int(n_angles), threads)
    peaks = peaks.reshape(z.size, p.size, int(n_angles))
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
        Periods in s, > 0.
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
    uy = np.stack(
        [
            _core.ductility_spectrum(m.a, m.dt, p, (zeta, float(alpha)), mu, threads).reshape(
                mu.size, p.size
            )
            for m in ms
        ]
    )
    el = response_spectrum(ms, p, zeta, threads=threads).sd[:, 0, :]
    return DuctilitySpectrum(p, mu, zeta, float(alpha), uy, el, [m.name for m in ms])

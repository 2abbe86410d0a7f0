"""Two horizontal components of one record as one object (:class:`GroundMotionPair`):
rotation, RotDnn spectra and the maximum-direction (RotD100) spectrum of ASCE 7-22
chapter 16; exported from :mod:`duhamel.records`."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.validate import finite_float
from duhamel.records.motion import GroundMotion

__all__ = ["GroundMotionPair"]


@dataclass(frozen=True, eq=False)
class GroundMotionPair:
    """Two orthogonal horizontal components of one record.

    Parameters
    ----------
    first, second : GroundMotion
        The components (e.g. the 000 and 090 files of a PEER record), with the same
        sampling interval; the shorter is padded with zeros to the longer's length.
    name : str, optional
        Defaults to the components' common name prefix (or the first's name).

    Examples
    --------
    >>> import numpy as np
    >>> from duhamel.records import GroundMotion, GroundMotionPair
    >>> t = np.arange(0.0, 10.0, 0.01)
    >>> pair = GroundMotionPair(GroundMotion(np.sin(5 * t), 0.01), GroundMotion(0 * t, 0.01))
    >>> turned = pair.rotated(90.0)
    >>> bool(np.allclose(turned.second.a, -pair.first.a))
    True
    """

    first: GroundMotion
    second: GroundMotion
    name: str = ""

    def __post_init__(self) -> None:
        if not isinstance(self.name, str):
            raise TypeError(f"`name` must be a string, got {type(self.name).__name__}")
        for label, m in (("first", self.first), ("second", self.second)):
            if not isinstance(m, GroundMotion):
                raise TypeError(f"`{label}` must be a GroundMotion, got {type(m).__name__}")
        a, b = self.first, self.second
        if abs(a.dt - b.dt) > 1e-9 * a.dt:
            raise ValueError(
                f"`second` has dt = {b.dt:g} s, `first` has {a.dt:g} s: resample one "
                "(GroundMotion.resampled)"
            )
        n = max(a.a.size, b.a.size)
        if a.a.size < n:
            a = GroundMotion(np.pad(a.a, (0, n - a.a.size)), a.dt, "m/s^2", a.name, a.metadata)
        if b.a.size < n:
            b = GroundMotion(np.pad(b.a, (0, n - b.a.size)), a.dt, "m/s^2", b.name, b.metadata)
        object.__setattr__(self, "first", a)
        object.__setattr__(self, "second", b)
        if not self.name:
            prefix = _common_prefix(a.name, b.name)
            object.__setattr__(self, "name", prefix or a.name)

    def __iter__(self) -> Iterator[GroundMotion]:
        return iter((self.first, self.second))

    def __repr__(self) -> str:
        return f"GroundMotionPair(name={self.name!r}, {self.first!r}, {self.second!r})"

    @property
    def dt(self) -> float:
        """The sampling interval in s."""
        return self.first.dt

    @property
    def t(self) -> NDArray[np.float64]:
        """Sample times in s."""
        return self.first.t

    def rotated(self, angle: float) -> GroundMotionPair:
        """The components along axes turned by `angle` degrees (counter-clockwise from
        `first` towards `second`): ``a1' = a1 cos + a2 sin``, ``a2' = -a1 sin + a2 cos``.

        Examples
        --------
        >>> from duhamel.records import GroundMotion, GroundMotionPair
        >>> p = GroundMotionPair(GroundMotion([0.0, 1.0], 0.1), GroundMotion([0.0, 0.0], 0.1))
        >>> [round(float(x), 12) for x in p.rotated(30.0).first.a]
        [0.0, 0.866025403784]
        """
        angle = finite_float(angle, "angle")  # degrees
        th = np.deg2rad(angle)
        c, s = np.cos(th), np.sin(th)
        a1, a2 = self.first.a, self.second.a
        m1 = {**self.first.metadata, "rotated": angle}
        m2 = {**self.second.metadata, "rotated": angle}
        return GroundMotionPair(
            GroundMotion(c * a1 + s * a2, self.dt, "m/s^2", self.first.name, m1),
            GroundMotion(-s * a1 + c * a2, self.dt, "m/s^2", self.second.name, m2),
            self.name,
        )

    def scaled(self, factor: float) -> GroundMotionPair:
        """Both components multiplied by `factor` (one factor per pair, as ASCE 7-22
        section 16.2.3.2 scales pairs)."""
        return GroundMotionPair(self.first.scaled(factor), self.second.scaled(factor), self.name)

    def map(self, fn: Callable[[GroundMotion], GroundMotion]) -> GroundMotionPair:
        """`fn` applied to both components (``pair.map(lambda m: m.baseline_corrected())``)."""
        return GroundMotionPair(fn(self.first), fn(self.second), self.name)

    def rotd(
        self,
        periods: ArrayLike,
        percentiles: ArrayLike = (50, 100),
        damping: float | ArrayLike = 0.05,
        *,
        n_angles: int = 180,
        threads: int | None = None,
    ) -> Any:
        """RotDnn spectra of the pair (:func:`duhamel.spectra.rotd`); ``.psa`` has shape
        ``(n_dampings, n_percentiles, n_periods)``.

        Examples
        --------
        >>> import numpy as np
        >>> from duhamel.records import GroundMotion, GroundMotionPair
        >>> t = np.arange(0.0, 10.0, 0.01)
        >>> h1, h2 = GroundMotion(np.sin(5 * t), 0.01), GroundMotion(np.cos(5 * t), 0.01)
        >>> p = GroundMotionPair(h1, h2)
        >>> p.rotd([0.5, 1.0]).psa.shape
        (1, 2, 2)
        """
        from duhamel.spectra.response import rotd

        return rotd(
            self.first, self.second, periods, percentiles, damping, n_angles=n_angles,
            threads=threads,
        )  # fmt: skip

    def rotd100(
        self,
        periods: ArrayLike,
        damping: float = 0.05,
        *,
        n_angles: int = 180,
        threads: int | None = None,
    ) -> NDArray[np.float64]:
        """The maximum-direction (RotD100) pseudo-acceleration spectrum in m/s^2, shape
        ``(n_periods,)``: the spectrum ASCE 7-22 section 16.2.3.2 scales to the target.

        Examples
        --------
        >>> import numpy as np
        >>> from duhamel.records import GroundMotion, GroundMotionPair
        >>> t = np.arange(0.0, 10.0, 0.01)
        >>> p = GroundMotionPair(GroundMotion(np.sin(5 * t), 0.01), GroundMotion(0 * t, 0.01))
        >>> from duhamel.spectra import response_spectrum
        >>> one = response_spectrum(p.first, [1.0]).psa[0, 0]  # one component: RotD100 = it
        >>> bool(np.allclose(p.rotd100([1.0]), one, rtol=1e-12))
        True
        """
        if np.ndim(damping) != 0:
            raise ValueError("`damping` must be one ratio for rotd100")
        r = self.rotd(periods, (100,), damping, n_angles=n_angles, threads=threads)
        return np.asarray(r.psa[0, 0], dtype=np.float64)

    def write_at2(self, first: Any, second: Any, *, units: str = "g") -> None:
        """Both components as PEER ``.AT2`` files (see :meth:`GroundMotion.write_at2`)."""
        self.first.write_at2(first, units=units)
        self.second.write_at2(second, units=units)


def _common_prefix(a: str, b: str) -> str:
    """The common start of two component names up to its last separator (``R0_000`` and
    ``R0_090`` give ``R0``), without trailing separators."""
    n = 0
    while n < min(len(a), len(b)) and a[n] == b[n]:
        n += 1
    p = a[:n]
    if n < max(len(a), len(b)):
        cut = max(p.rfind(c) for c in "_-. ")
        p = p[:cut] if cut > 0 else p
    return p.rstrip("_-. ")

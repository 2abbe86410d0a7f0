"""A ground-motion record (:class:`GroundMotion`), its units and the quantities read off it;
exported from :mod:`duhamel.records`."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.validate import as_float_array, finite_float, positive_float
from duhamel.loads import BaseAcceleration
from duhamel.records.units import UNITS, G, _unit

__all__ = ["UNITS", "G", "GroundMotion"]


def _finite(values: NDArray[np.float64], what: str) -> NDArray[np.float64]:
    """`values` if finite, else a ValueError: the record's `what` is beyond the double
    range (amplitudes or a duration of no physical record)."""
    if not np.all(np.isfinite(values)):
        raise ValueError(
            f"the record's {what} overflows the double range: rescale its amplitudes (`a`) "
            "or its step (`dt`)"
        )
    return values


@dataclass(frozen=True, eq=False)
class GroundMotion:
    """One component of a ground-motion record, sampled uniformly from ``t = 0``.

    Parameters
    ----------
    a : array_like, shape (n,)
        Acceleration samples in `units` (converted to m/s^2 and stored as ``a``).
    dt : float
        Sampling interval in s.
    units : str, optional
        Units of `a` as given: ``'m/s^2'`` (default), ``'g'``, ``'cm/s^2'`` (``'gal'``),
        ``'mm/s^2'``, ``'ft/s^2'``, ``'in/s^2'``.
    name : str, optional
        A label (the record and component, e.g. ``'RSN6_IMPVALL.I_I-ELC180'``).
    metadata : dict, optional
        Anything else of the source (header lines, station, file path).

    Attributes
    ----------
    a : ndarray
        Acceleration in m/s^2.
    t : ndarray
        Sample times ``k dt`` in s.

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> from duhamel.records import GroundMotion
    >>> gm = GroundMotion([0.0, 0.1, -0.2, 0.0], dt=0.02, units="g")
    >>> gm.scaled(2.0).pga / gm.pga
    2.0
    >>> load = gm.as_load(np.ones(3))  # a BaseAcceleration on a 3-dof shear building
    """

    a: NDArray[np.float64]
    dt: float
    units: str = "m/s^2"
    name: str = ""
    metadata: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        units = _unit(self.units)
        a = as_float_array(self.a, "a", ndim=1)
        if a.size < 2:
            raise ValueError(f"`a` must have at least 2 samples, got {a.size}")
        dt = positive_float(self.dt, "dt")
        if not np.isfinite((a.size - 1) * dt):
            raise ValueError(
                f"`dt` = {dt!r} s: the record's {a.size} samples last beyond the double range"
            )
        a = a * UNITS[units]
        if not np.all(np.isfinite(a)):
            raise ValueError(f"`a` in {units} overflows when converted to m/s^2")
        a.setflags(write=False)
        object.__setattr__(self, "a", a)
        object.__setattr__(self, "dt", dt)
        object.__setattr__(self, "units", units)
        object.__setattr__(self, "name", str(self.name))
        object.__setattr__(self, "metadata", dict(self.metadata))

    def __repr__(self) -> str:
        return (
            f"GroundMotion(name={self.name!r}, n={self.a.size}, dt={self.dt:g} s, "
            f"duration={self.duration:g} s, pga={self.pga / G:.4g} g)"
        )

    @property
    def t(self) -> NDArray[np.float64]:
        """Sample times in s, ``k dt``."""
        return self.dt * np.arange(self.a.size, dtype=np.float64)

    @property
    def duration(self) -> float:
        """Time of the last sample, ``(n - 1) dt``, in s."""
        return float((self.a.size - 1) * self.dt)

    @property
    def pga(self) -> float:
        """Peak ground acceleration ``max |a|`` in m/s^2."""
        return float(np.max(np.abs(self.a)))

    @property
    def velocity(self) -> NDArray[np.float64]:
        """Ground velocity in m/s at the samples: the exact integral of the piecewise-linear
        acceleration from rest (no baseline correction)."""
        v = np.empty_like(self.a)
        v[0] = 0.0
        with np.errstate(over="ignore", invalid="ignore"):
            np.cumsum(0.5 * self.dt * self.a[1:] + 0.5 * self.dt * self.a[:-1], out=v[1:])
        return _finite(v, "velocity")

    @property
    def displacement(self) -> NDArray[np.float64]:
        """Ground displacement in m at the samples, exact for the piecewise-linear
        acceleration from rest: ``d_{k+1} = d_k + v_k dt + dt^2 (2 a_k + a_{k+1}) / 6``."""
        v, a, h = self.velocity, self.a, self.dt
        d = np.empty_like(a)
        d[0] = 0.0
        with np.errstate(over="ignore", invalid="ignore"):
            np.cumsum(v[:-1] * h + h * (h * (2.0 * a[:-1] + a[1:]) / 6.0), out=d[1:])
        return _finite(d, "displacement")

    @property
    def pgv(self) -> float:
        """Peak ground velocity in m/s (of :attr:`velocity`, at the samples)."""
        return float(np.max(np.abs(self.velocity)))

    @property
    def pgd(self) -> float:
        """Peak ground displacement in m (of :attr:`displacement`, at the samples)."""
        return float(np.max(np.abs(self.displacement)))

    def husid(self) -> NDArray[np.float64]:
        """Cumulative Arias intensity at the samples, in m/s (the Husid plot is this divided
        by :attr:`arias_intensity`); the integral of ``a^2`` is exact per segment."""
        scale, unit = self._husid_scaled()
        with np.errstate(over="ignore", invalid="ignore"):
            out = unit * scale
        return _finite(out, "cumulative Arias intensity")

    def _husid_scaled(self) -> tuple[float, NDArray[np.float64]]:
        """``(s, h)`` with the cumulative Arias intensity ``s * h``: ``h`` computed from the
        record divided by its peak, so that no square overflows (records beyond 1e154)."""
        peak = float(np.max(np.abs(self.a)))
        if peak == 0.0:
            return 0.0, np.zeros_like(self.a)
        b = self.a / peak
        b0, b1 = b[:-1], b[1:]
        h = np.empty_like(b)
        h[0] = 0.0
        np.cumsum((b0 * b0 + b0 * b1 + b1 * b1) / 3.0, out=h[1:])
        return np.pi / (2.0 * G) * self.dt * peak * peak, h

    @property
    def arias_intensity(self) -> float:
        """Arias intensity ``pi / (2 g) * integral a^2 dt`` in m/s (a ValueError when it is
        beyond the double range)."""
        scale, h = self._husid_scaled()
        with np.errstate(over="ignore"):
            out = float(h[-1] * scale) if scale else 0.0
        return float(_finite(np.array([out]), "Arias intensity")[0])

    def significant_duration(self, start: float = 0.05, end: float = 0.95) -> float:
        """Time in s between the instants the Husid curve reaches `start` and `end` of the
        Arias intensity (D5-95 by default; D5-75 with ``end=0.75``), linear between samples.

        Examples
        --------
        >>> import numpy as np
        >>> from duhamel.records import GroundMotion
        >>> gm = GroundMotion(np.ones(1001), dt=0.01)  # uniform intensity over 10 s
        >>> round(gm.significant_duration(), 9)
        9.0
        """
        start, end = finite_float(start, "start"), finite_float(end, "end")
        if not (0.0 <= start < end <= 1.0):
            raise ValueError(
                f"`start` and `end` must satisfy 0 <= start < end <= 1, got {start}, {end}"
            )
        _, h = self._husid_scaled()
        if h[-1] <= 0.0:
            raise ValueError(f"record {self.name!r} is zero: it has no significant duration")
        h = h / h[-1]
        t0, t1 = np.interp([start, end], h, self.t)
        return float(t1 - t0)

    def scaled(self, factor: float) -> GroundMotion:
        """The record multiplied by `factor` (name and metadata kept, the factor recorded
        in ``metadata['scale']``)."""
        f = finite_float(factor, "factor")
        meta = dict(self.metadata)
        meta["scale"] = meta.get("scale", 1.0) * f
        with np.errstate(over="ignore"):
            a = self.a * f
        if not np.all(np.isfinite(a)):
            raise ValueError(f"`factor` = {f!r} scales the record beyond the double range")
        return GroundMotion(a, self.dt, "m/s^2", self.name, meta)

    def as_load(self, direction_vector: ArrayLike) -> BaseAcceleration:
        """The :class:`~duhamel.loads.BaseAcceleration` of this record on the dofs moved by
        `direction_vector` (the influence vector ``r``: ones on the horizontal dofs of a
        shear building along this component)."""
        return BaseAcceleration(direction_vector, t=self.t, values=self.a)

    # --- processing (python/duhamel/records/processing.py) ---------------------------------

    def baseline_corrected(self, order: int = 3, *, zero_end: bool = True) -> GroundMotion:
        """The record with a polynomial baseline removed.

        The acceleration polynomial ``c_0 + c_1 t + ... + c_{order-2} t^(order-2)`` whose
        displacement (a polynomial of degree `order` from rest) best fits the record's
        displacement in least squares is subtracted; with `zero_end` (default) the fit is
        constrained so that the corrected record ends at rest: zero velocity and
        displacement, as field processing does. A drift of that form is removed exactly.

        Examples
        --------
        >>> import numpy as np
        >>> from duhamel.records import GroundMotion
        >>> gm = GroundMotion(np.sin(np.linspace(0, 30, 3001)) + 0.01, dt=0.01)
        >>> bc = gm.baseline_corrected()
        >>> ends = abs(bc.velocity[-1]) / bc.pgv, abs(bc.displacement[-1]) / bc.pgd
        >>> bool(max(ends) < 1e-12)
        True
        """
        from duhamel.records.processing import baseline_corrected

        return baseline_corrected(self, order, zero_end)  # type: ignore[no-any-return]

    def filtered(
        self,
        low: float | None = None,
        high: float | None = None,
        order: int = 4,
        zero_phase: bool = True,
        *,
        keep_padding: bool = False,
    ) -> GroundMotion:
        """Butterworth filter: high-pass at `low` Hz, low-pass at `high` Hz, or band-pass.

        The record is padded with zeros at both ends (``1.5 order / f`` seconds for the
        lowest corner f, Converse and Brady 1992) so that the filter's transients stay in
        the pads, filtered with second-order sections (forward and backward with
        `zero_phase`: ``scipy.signal.sosfiltfilt``, the order doubled; causal otherwise),
        and the pads removed unless `keep_padding` (Boore 2005 recommends keeping them:
        the filtered record's motion extends into them).

        Examples
        --------
        >>> import numpy as np
        >>> from duhamel.records import GroundMotion
        >>> t = np.arange(0, 20, 0.01)
        >>> gm = GroundMotion(np.sin(2 * np.pi * t) + np.sin(2 * np.pi * 30 * t), dt=0.01)
        >>> lp = gm.filtered(high=10.0)
        >>> bool(np.abs(lp.a - np.sin(2 * np.pi * t))[500:-500].max() < 1e-2)
        True
        """
        from duhamel.records.processing import filtered

        return filtered(self, low, high, order, zero_phase, keep_padding)  # type: ignore[no-any-return]

    def resampled(self, dt: float, *, antialias: bool = True) -> GroundMotion:
        """The record at a new sampling interval `dt` (s): the piecewise-linear record read
        at ``k dt`` (exact for a divisor of the old step); a coarser step is first
        low-passed at 0.8 of its Nyquist frequency unless ``antialias=False``.

        Examples
        --------
        >>> from duhamel.records import GroundMotion
        >>> GroundMotion([0.0, 1.0, 0.0], dt=0.02).resampled(0.01).a.tolist()
        [0.0, 0.5, 1.0, 0.5, 0.0]
        """
        from duhamel.records.processing import resampled

        return resampled(self, dt, antialias)  # type: ignore[no-any-return]

    def padded(self, before: float = 0.0, after: float = 0.0) -> GroundMotion:
        """Zeros added `before` and `after` the record (seconds, whole samples).

        Examples
        --------
        >>> from duhamel.records import GroundMotion
        >>> GroundMotion([1.0, 2.0], dt=0.5).padded(0.5, 1.0).a.tolist()
        [0.0, 1.0, 2.0, 0.0, 0.0]
        """
        from duhamel.records.processing import padded

        return padded(self, before, after)  # type: ignore[no-any-return]

    def fourier(self, smoothing: float | None = None, *, n_fft: int | None = None) -> Any:
        """The Fourier amplitude spectrum ``dt |FFT(a)|`` (m/s) at frequencies
        ``k / (n_fft dt)``, and its Konno-Ohmachi (1998) smoothing of bandwidth `smoothing`
        (``b``, typically 20 to 40) in ``.smoothed``.

        Examples
        --------
        >>> import numpy as np
        >>> from duhamel.records import GroundMotion
        >>> fas = GroundMotion(np.ones(100), dt=0.01).fourier(smoothing=40)
        >>> round(float(fas.amplitude[0]), 12)  # integral of a over 100 samples
        1.0
        """
        from duhamel.records.processing import fourier

        return fourier(self, smoothing, n_fft)

    def cav(self) -> float:
        """Cumulative absolute velocity ``integral |a| dt`` (m/s), exact for the
        piecewise-linear record.

        Examples
        --------
        >>> from duhamel.records import GroundMotion
        >>> GroundMotion([1.0, -1.0], dt=1.0).cav()  # two triangles of area 1/4
        0.5
        """
        from duhamel.records.processing import cav

        return cav(self)

    def bracketed_duration(self, threshold: float, units: str = "g") -> float:
        """Time (s) between the first and last instants ``|a|`` reaches `threshold` (in
        `units`, default g; 0.05 g is usual), located on the piecewise-linear record.

        Examples
        --------
        >>> from duhamel.records import GroundMotion
        >>> GroundMotion([0.0, 1.0, 0.0, 0.0, 1.0, 0.0], dt=1.0).bracketed_duration(0.5, "m/s^2")
        4.0
        """
        from duhamel.records.processing import bracketed_duration

        return bracketed_duration(self, threshold, units)

    def write_at2(self, path: Any, *, units: str = "g") -> None:
        """Write the record as a PEER NGA-West2 ``.AT2`` file in `units` (default g), with 17
        significant digits so that :func:`~duhamel.records.read_at2` reads it back to
        round-off; the processing steps are listed on the third header line.

        Examples
        --------
        >>> import tempfile, pathlib
        >>> from duhamel.records import GroundMotion, read_at2
        >>> p = pathlib.Path(tempfile.mkdtemp()) / "X.AT2"
        >>> GroundMotion([0.0, 0.1, -0.2], dt=0.01, units="g").write_at2(p)
        >>> round(read_at2(p).pga / 9.80665, 15)
        0.2
        """
        from duhamel.records.processing import write_at2

        write_at2(self, path, units)

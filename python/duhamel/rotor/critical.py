"""Critical speeds as API 684 reports them: each crossing of a Campbell branch with the
excitation line with its mode's damping, the amplification factor by the half-power method
on the unbalance response, and the separation margin from a stated operating range; heavily
damped modes (critically damped in API 684's sense) left out of the list and listed apart.

API RP 684 (2nd ed., 2005) and API 617 identify a critical speed from the peak of the
unbalance response, ``AF = N_c / (N_2 - N_1)`` with ``N_1, N_2`` the half-power speeds
(amplitude ``peak / sqrt 2``); a mode with ``AF < 2.5`` is critically damped and needs no
separation margin. For a lightly damped mode ``AF`` is about ``1 / (2 zeta)``, so damping
ratios above 0.2 (``AF`` about 2.5 and below; log decrement above 1.28) are *heavily
damped*: such a crossing is no resonance a machine has to keep away from (ROSS's
compressor has one with log decrement 24.7 and mixed whirl), and it is reported apart.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel._engine.validate import finite_float
from duhamel.rotor._crossings import Crossing, Memo, crossings
from duhamel.rotor.unbalance import _margins

__all__ = ["HEAVY_DAMPING", "CriticalSpeed", "CriticalSpeeds", "critical_speeds"]

#: Damping ratio above which a critical speed is heavily damped: ``AF ~ 1 / (2 zeta) < 2.5``,
#: API 684's critically damped limit.
HEAVY_DAMPING = 0.2
#: Unbalance (kg m) put at the node of a mode's largest translation when none is given (the
#: response is linear in it: the amplification factor does not depend on it).
PROBE_UNBALANCE = 1e-4
#: Samples of the unbalance response around a critical speed, over ``+-`` this many damping
#: ratios (at least 5 %, at most 90 % of the speed), before the peak and half-power speeds
#: are refined on the response itself.
WINDOW_SAMPLES = 41
WINDOW_ZETAS = 8.0


@dataclass(frozen=True)
class CriticalSpeed:
    """One critical speed (a crossing of a Campbell branch with the excitation line).

    Attributes
    ----------
    speed : float
        Where the damped natural frequency equals the harmonic of the spin speed (rad/s),
        refined on the eigenproblem.
    damping_ratio, log_dec : float
        Of the mode at that speed (``-Re(lambda) / |lambda|``; ``-2 pi Re / Im``).
    whirl : str
        ``"forward"``, ``"backward"``, ``"mixed"`` or ``"planar"`` (:attr:`Modes.whirl`).
    node : int or None
        Where the unbalance response is read (the node of the mode's largest translation,
        or the given `probe`); None when no response was computed.
    peak_speed : float
        ``N_c``: the speed of the unbalance response's peak near this critical speed (rad/s;
        the zero of the response's derivative, to about 1e-9); NaN without one (also when
        the nearest peak is nearer to another critical speed: a backward mode next to a
        forward one).
    amplitude : float
        The peak's major semi-axis at `node` (m), for the unbalance used (NaN without one).
    half_power : (float, float)
        ``N_1 < N_c < N_2``: amplitude ``peak / sqrt 2`` (refined on the response); NaN
        where the response does not fall that low near the peak.
    amplification_factor : float
        ``N_c / (N_2 - N_1)`` (NaN without both half-power speeds; infinite for an
        undamped mode, whose half-power speeds are one to round-off).
    margin : float
        Separation margin from the operating range: ``(N_min - N) / N`` below it,
        ``(N - N_max) / N_max`` above it, negative inside it, with ``N`` the peak speed (the
        crossing speed without a peak); NaN without an operating range.
    required_margin : float
        API 684 / API 617: 0 for ``AF < 2.5`` and for heavily damped modes; else
        ``min(0.16, 0.17 (1 - 1 / (AF - 1.5)))`` below the minimum operating speed,
        ``min(0.26, 0.10 + 0.17 (1 - 1 / (AF - 1.5)))`` above the maximum continuous speed;
        NaN without an operating range, inside it, or without an amplification factor.
    heavily_damped : bool
        Whether the damping ratio is above the limit (listed apart).
    """

    speed: float
    damping_ratio: float
    log_dec: float
    whirl: str
    node: int | None = None
    peak_speed: float = np.nan
    amplitude: float = np.nan
    half_power: tuple[float, float] = (np.nan, np.nan)
    amplification_factor: float = np.nan
    margin: float = np.nan
    required_margin: float = np.nan
    heavily_damped: bool = False

    @property
    def meets_margin(self) -> bool:
        """Whether the margin is at least the required one (True without an operating
        range or a requirement; False inside the operating range)."""
        if np.isnan(self.margin):
            return True
        return bool(self.margin >= 0.0 and self.margin >= np.nan_to_num(self.required_margin))


@dataclass(frozen=True, eq=False)
class CriticalSpeeds:
    """The critical speeds of :meth:`Rotor.critical_speeds
    <duhamel.rotor.Rotor.critical_speeds>`.

    As an array (``np.asarray``, indexing, ``len``, iteration) it is :attr:`speeds`, the
    critical speeds that are not heavily damped, ascending.

    Attributes
    ----------
    critical : tuple of CriticalSpeed
        The critical speeds, ascending, each with its damping, amplification factor and
        margins.
    heavily_damped : tuple of CriticalSpeed
        The crossings whose mode's damping ratio is above `max_damping` (overdamped modes
        never cross: they have no natural frequency), listed apart.
    operating : (float, float) or None
        The operating range the margins are taken from.
    max_damping : float
        The damping ratio above which a crossing is heavily damped.
    harmonic : float
        The excitation order.
    """

    critical: tuple[CriticalSpeed, ...]
    heavily_damped: tuple[CriticalSpeed, ...] = ()
    operating: tuple[float, float] | None = None
    max_damping: float = HEAVY_DAMPING
    harmonic: float = 1.0
    _speeds: NDArray[np.float64] = field(init=False, repr=False)

    def __post_init__(self) -> None:
        speeds = np.array([c.speed for c in self.critical], dtype=float)
        speeds.setflags(write=False)
        object.__setattr__(self, "_speeds", speeds)

    @property
    def speeds(self) -> NDArray[np.float64]:
        """The critical speeds (rad/s) that are not heavily damped, ascending."""
        return self._speeds

    @property
    def amplification_factors(self) -> NDArray[np.float64]:
        """``AF`` of each of :attr:`critical`."""
        return np.array([c.amplification_factor for c in self.critical], dtype=float)

    @property
    def margins(self) -> NDArray[np.float64]:
        """Separation margin of each of :attr:`critical`."""
        return np.array([c.margin for c in self.critical], dtype=float)

    @property
    def required_margins(self) -> NDArray[np.float64]:
        """Required separation margin of each of :attr:`critical`."""
        return np.array([c.required_margin for c in self.critical], dtype=float)

    @property
    def size(self) -> int:
        """Number of critical speeds listed."""
        return int(self._speeds.size)

    def __repr__(self) -> str:
        speeds = ", ".join(f"{w:.6g}" for w in self._speeds)
        return f"CriticalSpeeds([{speeds}], heavily_damped={len(self.heavily_damped)})"

    def __array__(self, dtype: Any = None, copy: Any = None) -> NDArray[Any]:
        return np.array(self._speeds, dtype=dtype)

    def __len__(self) -> int:
        return self.size

    def __iter__(self) -> Iterator[float]:
        return iter(self._speeds.tolist())

    def __getitem__(self, index: Any) -> Any:
        return self._speeds[index]

    def summary(self) -> str:
        """A table: each critical speed (rad/s and rpm), its whirl, damping ratio, log
        decrement, amplification factor, peak speed, margin and required margin; then the
        heavily damped crossings.

        Examples
        --------
        >>> import numpy as np
        >>> from duhamel.rotor import STEEL, Bearing, Disk, Rotor, Shaft
        >>> rotor = Rotor([Shaft(0.25, 0.05, material=STEEL)] * 4, [Disk(2, 30.0, 0.6, 0.3)],
        ...               [Bearing(0, 1e7, 1e7, cxx=500.0, cyy=500.0),
        ...                Bearing(4, 1e7, 1e7, cxx=500.0, cyy=500.0)], zeta=0.02)
        >>> crit = rotor.critical_speeds(np.linspace(0.0, 1000.0, 21), operating=(300, 450))
        >>> print(crit.summary())
        speed [rad/s]    [rpm]  whirl        zeta  log dec      AF   N_c [rad/s]  margin  required
               264.98   2530.3  forward    0.0210   0.1320   23.77        265.15  0.1314    0.1600
        heavily damped (zeta > 0.2): none
        """
        head = (
            f"{'speed [rad/s]':>13}  {'[rpm]':>7}  {'whirl':<8}  {'zeta':>7}  {'log dec':>7}  "
            f"{'AF':>6}  {'N_c [rad/s]':>12}  {'margin':>6}  {'required':>8}"
        )
        lines = [head]
        for c in self.critical:
            lines.append(
                f"{c.speed:>13.2f}  {c.speed * 30 / np.pi:>7.1f}  {c.whirl:<8}  "
                f"{c.damping_ratio:>7.4f}  {c.log_dec:>7.4f}  {c.amplification_factor:>6.2f}  "
                f"{c.peak_speed:>12.2f}  {c.margin:>6.4f}  {c.required_margin:>8.4f}"
            )
        heavy = ", ".join(
            f"{c.speed:.2f} rad/s ({c.whirl}, zeta {c.damping_ratio:.3f}, log dec {c.log_dec:.3g})"
            for c in self.heavily_damped
        )
        lines.append(f"heavily damped (zeta > {self.max_damping:g}): {heavy or 'none'}")
        return "\n".join(lines)


def critical_speeds(
    analyses: Any,
    speeds: Any,
    *,
    harmonic: float,
    whirl: str | None,
    n_modes: int | None,
    operating: tuple[float, float] | None,
    unbalances: Sequence[tuple[int, float, float]] | None,
    probe: int | None,
    max_damping: float,
) -> CriticalSpeeds:
    """The report of :meth:`duhamel.rotor.Rotor.critical_speeds` (see there)."""
    span = _operating(operating)
    limit = finite_float(max_damping, "max_damping")
    if not 0.0 < limit <= 1.0:
        raise ValueError(f"`max_damping` must be a damping ratio in (0, 1], got {limit!r}")
    if probe is not None and (isinstance(probe, bool) or not isinstance(probe, int | np.integer)):
        raise TypeError(f"`probe` must be a node number, got {probe!r}")
    analyses = Memo(analyses)
    n_modes, window = _windows(analyses, speeds, harmonic, n_modes)
    found = crossings(analyses, speeds, harmonic, whirl, n_modes, window)
    h = float(harmonic)
    listed, heavy = [], []
    for c in found:
        lam = c.eigenvalue
        zeta = float(-lam.real / abs(lam))
        dec = float(-2.0 * np.pi * lam.real / lam.imag)
        if zeta > limit:
            margin = _margins(c.speed, np.nan, span)[1]
            required = np.nan if span is None else 0.0
            heavy.append(CriticalSpeed(c.speed, zeta, dec, c.whirl, margin=margin,
                                       required_margin=required, heavily_damped=True))  # fmt: skip
            continue
        if h == 1.0 and c.speed > 0.0:
            listed.append(_with_response(analyses, c, zeta, dec, span, unbalances, probe))
        else:
            margin = _margins(c.speed, np.nan, span)[1]
            listed.append(CriticalSpeed(c.speed, zeta, dec, c.whirl, margin=margin))
    return CriticalSpeeds(tuple(_own_peaks(listed, span)), tuple(heavy), span, limit, h)


def _own_peaks(
    listed: list[CriticalSpeed], span: tuple[float, float] | None
) -> list[CriticalSpeed]:
    """A response peak belongs to the crossing nearest to it: a crossing whose nearest peak
    is nearer to another critical speed (a backward mode, which unbalance hardly excites,
    next to a forward one) keeps no peak, amplification factor or required margin."""
    out = []
    for c in listed:
        nearer = np.isfinite(c.peak_speed) and any(
            abs(o.speed - c.peak_speed) < abs(c.speed - c.peak_speed) for o in listed
        )
        if nearer:
            margin = _margins(c.speed, np.nan, span)[1]
            c = CriticalSpeed(c.speed, c.damping_ratio, c.log_dec, c.whirl, c.node, margin=margin)
        out.append(c)
    return out


def _windows(
    analyses: Any, speeds: Any, harmonic: Any, n_modes: int | None
) -> tuple[int | None, int | None]:
    """`n_modes` and the modes taken at each speed: for a large model without `n_modes`,
    the modes below 1.25 harmonic times the highest speed at both ends of the range (the
    only ones that can cross the excitation line there), from the shift-invert path."""
    below = getattr(analyses, "_modes_below", None)
    if below is None:
        return n_modes, None
    try:
        ws = np.asarray(speeds, dtype=float).ravel()
        h = float(harmonic)
    except (TypeError, ValueError):
        return n_modes, None  # the crossings' own checks name what is wrong
    if n_modes is None and ws.size and np.all(np.isfinite(ws)) and h > 0.0:
        top = 1.25 * h * float(np.max(np.abs(ws)))
        counts = [below(float(w), top, analyses.modes) for w in (float(ws.min()), float(ws.max()))]
        if all(c is not None for c in counts):
            n_modes = max(counts)  # type: ignore[type-var]
    return n_modes, analyses._window(n_modes)


def _operating(operating: Any) -> tuple[float, float] | None:
    if operating is None:
        return None
    try:
        lo, hi = operating
    except (TypeError, ValueError):
        raise ValueError(
            f"`operating` must be (minimum operating, maximum continuous) speeds, got {operating!r}"
        ) from None
    lo, hi = finite_float(lo, "operating"), finite_float(hi, "operating")
    if not 0.0 <= lo <= hi:
        raise ValueError(f"`operating` must be (min, max) with 0 <= min <= max, got {operating}")
    return (lo, hi)


def _largest_translation(analyses: Any, shape: NDArray[np.complex128]) -> int:
    """The node whose translation ``sqrt(|x|^2 + |y|^2)`` is largest in `shape`."""
    best, node = -1.0, 0
    for label in analyses.dof_labels:
        direction, _, number = label.rpartition("_")
        if direction != "x":
            continue
        n = int(number)
        size = float(np.hypot(abs(shape[analyses.dof(n, "x")]), abs(shape[analyses.dof(n, "y")])))
        if size > best:
            best, node = size, n
    return node


def _vertex(
    amp: Any, ws: NDArray[np.float64], a: NDArray[np.float64], k: int, w0: float
) -> tuple[float, float]:
    """The peak of the response `amp` near the sample ``ws[k]`` (a local maximum of `a`):
    the zero of its derivative by Newton's method, the derivative by fourth-order central
    differences of step ``2e-3`` of the sample spacing (five speeds per call; the step
    keeps the response's rounding, about 1e-12 relative, and the differences' truncation
    both small), started
    from the parabola through the three samples. A flat maximum read by comparing values
    is located only to about the square root of that rounding times its width (1e-7 of the
    speed on ROSS's compressor, varying from run to run); the derivative's zero to about
    1e-9 of the speed."""
    h = 2e-3 * float(ws[k + 1] - ws[k - 1]) / 2.0
    d2 = float(a[k + 1] - 2.0 * a[k] + a[k - 1])
    w = (
        float(ws[k])
        if d2 >= 0.0
        else float(ws[k]) - 500.0 * h * float(a[k + 1] - a[k - 1]) / (2.0 * d2)
    )
    w = min(max(w, float(ws[k - 1])), float(ws[k + 1]))
    for _ in range(8):
        f2m, fm, f0, fp, f2p = (float(v) for v in amp(w + h * np.arange(-2.0, 3.0)))
        curvature = fp - 2.0 * f0 + fm
        if not curvature < 0.0:
            break
        slope = (8.0 * (fp - fm) - (f2p - f2m)) / 12.0  # fourth order: no bias to speak of
        step = -h * slope / curvature
        w = min(max(w + step, float(ws[k - 1])), float(ws[k + 1]))
        if abs(step) <= 1e-10 * w0:
            break
    peak = float(amp(w)[0])
    if not peak >= a[k]:  # the search cannot lose the sample it started from
        return float(ws[k]), float(a[k])
    return w, peak


def _with_response(
    analyses: Any,
    c: Crossing,
    zeta: float,
    dec: float,
    span: tuple[float, float] | None,
    unbalances: Sequence[tuple[int, float, float]] | None,
    probe: int | None,
) -> CriticalSpeed:
    """`c` with the peak, half-power speeds and amplification factor of the unbalance
    response near it, and its margins."""
    from scipy.optimize import brentq

    node = _largest_translation(analyses, c.shape) if probe is None else int(probe)
    cases = [(node, PROBE_UNBALANCE, 0.0)] if unbalances is None else list(unbalances)

    def amp(ws: Any) -> NDArray[np.float64]:
        res = analyses.unbalance_response(np.atleast_1d(np.asarray(ws, dtype=float)), cases)
        return np.asarray(res.major_axis(node), dtype=float)

    w0 = c.speed
    half = min(max(WINDOW_ZETAS * zeta, 0.05), 0.9) * w0
    ws = np.linspace(w0 - half, w0 + half, WINDOW_SAMPLES)
    with np.errstate(all="ignore"):
        try:
            a = amp(ws)
        except ValueError:  # an undamped resonance on the grid: no finite peak
            a = np.full(ws.size, np.nan)
    inner = np.flatnonzero((a[1:-1] >= a[:-2]) & (a[1:-1] >= a[2:])) + 1
    if not np.all(np.isfinite(a)) or inner.size == 0:
        margin = _margins(w0, np.nan, span)[1]
        return CriticalSpeed(w0, zeta, dec, c.whirl, node=node, margin=margin)
    k = int(inner[np.argmin(np.abs(ws[inner] - w0))])
    nc, peak = _vertex(amp, ws, a, k, w0)
    level = peak / np.sqrt(2.0)

    def above(w: float) -> float:
        return float(amp(w)[0]) - level

    def side(step: int) -> float:
        i = k
        while 0 <= i + step < ws.size and a[i + step] > level:
            i += step
        j = i + step
        if not 0 <= j < ws.size:  # the response does not fall to half power near here
            return np.nan
        inner = max(float(ws[i]), nc) if step > 0 else min(float(ws[i]), nc)
        if not above(inner) > 0.0:  # a sample next to the level, re-evaluated on the other
            inner = nc  # side of it by rounding: bracket from the peak (above the level)
        outer = float(ws[j])
        while above(outer) > 0.0:  # the same at the outer sample: the next one out
            j += step
            if not 0 <= j < ws.size:
                return np.nan
            outer = float(ws[j])
        lo, hi = sorted((inner, outer))
        return float(brentq(above, lo, hi, xtol=1e-13 * w0, rtol=1e-13))

    n1, n2 = side(-1), side(1)
    af = nc / (n2 - n1) if np.isfinite(n1) and np.isfinite(n2) and n2 > n1 else np.nan
    if np.isfinite(n1) and np.isfinite(n2) and n2 <= n1:
        af = np.inf  # an undamped resonance: half-power speeds one (rounded) speed
    required, margin = _margins(nc, min(af, 1e300), span)
    return CriticalSpeed(w0, zeta, dec, c.whirl, node, nc, peak, (n1, n2), af, margin, required)

"""Critical speeds: the crossings of a rotor's Campbell diagram with an excitation line,
bracketed on a grid and refined on the eigenproblem (:meth:`RotorAnalyses.critical_speeds`;
what is reported of each, :mod:`duhamel.rotor.critical`)."""

from __future__ import annotations

import itertools
from dataclasses import replace
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.validate import as_float_array, positive_float

__all__ = ["Crossing", "Memo", "crossings"]

#: A refinement step follows its branch among the few modes nearest the branch's last
#: eigenvalue (shift-invert with that shift) when one of them has at least this MAC with the
#: branch's shape at the bracket's start; else among the whole window.
NEAR_MAC = 0.9
#: How many eigenvalues nearest the shift a refinement step takes.
NEAR_MODES = 6


class Crossing(NamedTuple):
    """A crossing of a Campbell branch with the excitation line: the speed, and the mode
    there (eigenvalue, whirl, shape)."""

    speed: float
    eigenvalue: complex
    whirl: str
    shape: NDArray[np.complex128]


def crossings(
    analyses: Any,
    speeds: ArrayLike,
    harmonic: float,
    whirl: str | None,
    n_modes: int | None,
    window: int | None = None,
) -> list[Crossing]:
    """The critical speeds of `analyses` (a rotor with ``campbell`` and ``modes``) on the
    grid `speeds`, ascending, each with its mode: see
    :meth:`duhamel.rotor.Rotor.critical_speeds`; `window`: the modes taken at each speed
    (the lowest `window`; None: all)."""
    from scipy.optimize import brentq

    if whirl not in ("forward", "backward", None):
        raise ValueError(f"`whirl` must be 'forward', 'backward' or None, got {whirl!r}")
    h = positive_float(harmonic, "harmonic")
    grid = np.unique(as_float_array(speeds, "speeds"))
    try:
        first = analyses.campbell(grid[:1], n_modes).frequencies[0]
        diagram = analyses.campbell(_refined(grid, first, h), n_modes)
    except np.linalg.LinAlgError as exc:
        raise ValueError(
            f"`speeds`: the rotor's eigenproblem fails on this grid (up to {grid[-1]:g} "
            f"rad/s, gyroscopic terms beyond the double range?): {exc}"
        ) from None
    ws, freq = diagram.speeds, diagram.frequencies
    found = []
    for j in range(freq.shape[1]):
        g = freq[:, j] - h * ws
        for p in range(ws.size - 1):
            if not (np.isfinite(g[p]) and np.isfinite(g[p + 1]) and g[p] * g[p + 1] <= 0):
                continue
            if whirl is not None and whirl not in (
                diagram.whirl[p, j],
                diagram.whirl[p + 1, j],
            ):
                continue
            a, b = float(ws[p]), float(ws[p + 1])
            here = analyses.modes(a, window)
            # the branch's mode there: nearest in frequency, of the branch's whirl within a
            # degenerate pair (equal frequencies, forward and backward)
            gap = np.abs(here.frequencies - freq[p, j])
            other = np.asarray(here.whirl) != diagram.whirl[p, j]
            ref = here.shapes[:, int(np.lexsort((other, gap))[0])]

            last = [complex(here.eigenvalues[int(np.lexsort((other, gap))[0])])]

            def branch(w: float, ref: NDArray = ref, f0: float = freq[p, j],
                       last: list[complex] = last) -> float:  # fmt: skip
                m = _following(analyses, w, last[0], ref, window)
                score = m.mac_with(ref) - 1e-9 * np.abs(m.frequencies - f0) / max(abs(f0), 1.0)
                k = int(np.argmax(score))
                last[0] = complex(m.eigenvalues[k])
                return float(m.frequencies[k]) - h * w

            if g[p] == 0.0:
                root = a
            elif g[p + 1] != 0.0:
                root = _crossing(brentq, branch, a, b)
            else:
                continue
            found.append(_mode_at(analyses, root, ref, float(freq[p, j]), window))
    out: list[Crossing] = []
    for c in sorted(found, key=lambda c: (c.speed, c.whirl != "forward")):
        if not out or c.speed != out[-1].speed:  # two branches at one speed (a degenerate
            # pair): listed once, as the forward one that unbalance excites
            out.append(c)
    return out


def _following(
    analyses: Any, w: float, sigma: complex, ref: NDArray[np.complex128], window: int | None
) -> Any:
    """The modes at `w` among which a refinement step follows its branch: the few nearest
    the branch's last eigenvalue `sigma` (large models), or the whole window when none of
    those is the branch (MAC with `ref` below :data:`NEAR_MAC`) or that path does not apply."""
    near = getattr(analyses, "_modes_near", None)
    if window is not None and near is not None:
        m = near(w, sigma, NEAR_MODES)
        if m is not None and m.n_modes and float(np.max(m.mac_with(ref))) >= NEAR_MAC:
            return m
    return analyses.modes(w, window)


class Memo:
    """`analyses` whose modes at each speed are kept for one critical-speed search (the
    bracketing Campbell diagram, the window's sizing and the brackets' starts ask for the
    same speeds); fewer modes than kept are the kept ones' lowest."""

    def __init__(self, analyses: Any):
        self._analyses = analyses
        self._kept: dict[float, list[tuple[int | None, Any]]] = {}

    def __getattr__(self, name: str) -> Any:
        return getattr(self._analyses, name)

    def modes(self, speed: float, n: int | None = None) -> Any:
        w = float(speed)
        for have, m in self._kept.get(w, ()):
            if have == n:
                return m
            if n is not None and have is not None and have >= n and m.n_modes >= n:
                return replace(m, eigenvalues=m.eigenvalues[:n], shapes=m.shapes[:, :n],
                               whirl=m.whirl[:n])  # fmt: skip
        m = self._analyses.modes(w, n)
        self._kept.setdefault(w, []).append((n, m))
        return m

    def campbell(self, speeds: ArrayLike, n_modes: int | None = None) -> Any:
        window = getattr(self._analyses, "_window", None)
        if window is None:
            return self._analyses.campbell(speeds, n_modes)
        from duhamel.rotor.campbell import campbell

        return campbell(self.modes, speeds, n_modes, window=window(n_modes))


def _mode_at(
    analyses: Any, w: float, ref: NDArray[np.complex128], f0: float, window: int | None
) -> Crossing:
    """The mode at speed `w` of the branch whose shape is `ref` (as the refinement follows
    it)."""
    m = analyses.modes(w, window)
    score = m.mac_with(ref) - 1e-9 * np.abs(m.frequencies - f0) / max(abs(f0), 1.0)
    j = int(np.argmax(score))
    return Crossing(float(w), complex(m.eigenvalues[j]), m.whirl[j], m.shapes[:, j])


def _refined(speeds: NDArray, frequencies: NDArray, harmonic: float) -> NDArray:
    """`speeds` with speeds inserted wherever two neighbours differ by more than a factor
    of 2 above a quarter of the lowest crossing speed possible (the lowest frequency at the
    first speed over `harmonic`): a grid such as ``[0, 1e20]`` would bracket many crossings
    of a branch at once (and miss them); about 2 log2(b / a) points are added."""
    positive = frequencies[np.isfinite(frequencies) & (frequencies > 0.0)]
    if positive.size == 0 or speeds.size < 2:
        return speeds
    floor = float(positive.min()) / harmonic / 4.0
    extra: list[float] = []
    for a, b in itertools.pairwise(speeds):
        lo = max(float(a), floor)
        if a < floor < b:
            extra.append(floor)
        while b > 2.0 * lo:
            lo *= 2.0
            extra.append(lo)
    return np.unique(np.concatenate([speeds, np.asarray(extra, dtype=float)]))


def _crossing(brentq: Any, branch: Any, a: float, b: float) -> float:
    """The zero of `branch` between the grid speeds `a` and `b` that bracket a crossing on
    the tracked Campbell diagram, to 1e-14 relative (Brent, with an absolute tolerance
    that does not grow with the bracket: a grid ``[0, 1e20]`` still finds 265 rad/s).
    Following the branch by its shape may pick another mode at an end of the bracket (modes
    that swap between grid points); the bracket is then searched on 16 inner speeds, and a
    ValueError asks for a finer grid when no sign change is found."""
    fa, fb = branch(a), branch(b)
    if fa == 0.0:
        return a
    if fb == 0.0:
        return b
    if fa * fb > 0.0:
        inner = np.linspace(a, b, 18)[1:-1]
        values = [branch(w) for w in inner]
        points, signs = [a, *inner.tolist(), b], [fa, *values, fb]
        for k in range(len(points) - 1):
            if signs[k] * signs[k + 1] <= 0.0:
                a, b = points[k], points[k + 1]
                break
        else:
            raise ValueError(
                f"`speeds`: the Campbell diagram crosses the excitation line between {a:g} and "
                f"{b:g} rad/s, but the branch followed by its mode shape does not (modes swap "
                "between these grid speeds); pass a finer grid of `speeds` there"
            )
        if branch(a) == 0.0:
            return a
    root = float(brentq(branch, a, b, xtol=1e-300, rtol=1e-14, maxiter=500))
    if abs(branch(root)) > 1e-8 * max(abs(root), 1.0):
        raise ValueError(
            f"`speeds`: between {a:g} and {b:g} rad/s the branch followed by its mode shape "
            f"jumps from one mode to another (at {root:g} rad/s) instead of crossing the "
            "excitation line; pass a finer grid of `speeds` there"
        )
    return root

"""The response between the steps of a run (dense output): ``Solution.at``, ``t_eval`` and
the location of events inside a step.

Two interpolants of step ``[t_n, t_n+1]``:

* **exact** (linear modal routes, ``"uncoupled"`` and ``"first-order"`` without elements):
  the core takes one step of the fraction ``tau`` from the state saved at ``t_n``, with the
  same loads and the same exact transition and load matrices the run used (evaluated at
  ``tau``). For loads linear between grid points (a record sampled on the grid) this is
  the exact response at ``t_n + tau``, as ``scipy.signal.lsim`` with first-order hold gives
  it.
* **Hermite** (every other route: elements, mass laws, run-ups, the direct integrators):
  the cubic Hermite polynomial through the saved ``(x, v)`` at both ends for ``x``, and
  through ``(v, a)`` for ``v`` (local error ``O(dt^4)``); it converges at the scheme's own
  order (second for the pseudo-force and direct schemes), as the steps do.

Both need every step saved (``save_every=1``).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["Dense", "ExactSteps", "State"]

State = tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]


class ExactSteps:
    """Fractional steps of a linear modal run from its saved states (see the module
    docstring). `run` is ``(grid, state, eta) -> core result``; `physical` maps a core
    result to ``(x, v, a)`` of its last row and the modal row."""

    def __init__(
        self,
        run: Callable[[float, float, int], Any],
        physical: Callable[[Any], tuple[State, dict[str, NDArray[np.float64]]]],
    ) -> None:
        self._run = run
        self._physical = physical

    def state(self, t_n: float, tau: float, n: int) -> tuple[State, dict[str, NDArray[np.float64]]]:
        """``(x, v, a)`` at ``t_n + tau`` (``0 < tau < dt``) and the modal row there."""
        return self._physical(self._run(t_n, tau, n))


class Dense:
    """The response of a run at any instant of its span (see the module docstring).

    Parameters
    ----------
    t, x, v : ndarray
        The saved rows of every step.
    a : callable
        The accelerations of those rows (computed on first use by the Hermite interpolant).
    exact : ExactSteps or None
        The exact interpolant of a linear route; None: Hermite.
    """

    def __init__(
        self,
        t: NDArray[np.float64],
        x: NDArray[np.float64],
        v: NDArray[np.float64],
        a: Callable[[], NDArray[np.float64]],
        exact: ExactSteps | None,
    ) -> None:
        self.t, self.x, self.v = t, x, v
        self._a = a
        self.exact = exact
        self.kind = "exact" if exact is not None else "hermite"
        self.end = float(t[-1])  # where the run ended (a terminal event: its instant)

    @property
    def a(self) -> NDArray[np.float64]:
        return self._a()

    def locate(self, time: float) -> tuple[int, float]:
        """The step ``n`` holding `time` and the time ``tau`` into it (``0 <= tau <= h``)."""
        t = self.t
        n = int(np.searchsorted(t, time, side="right")) - 1
        n = min(max(n, 0), t.size - 2)
        return n, float(time - t[n])

    def in_step(self, n: int, tau: float) -> tuple[State, dict[str, NDArray[np.float64]] | None]:
        """``(x, v, a)`` at ``t_n + tau`` and, for the exact interpolant, the modal row."""
        t = self.t
        h = float(t[n + 1] - t[n])
        if tau <= 0.0:
            return (self.x[n], self.v[n], self.a[n]), None
        if tau >= h:
            return (self.x[n + 1], self.v[n + 1], self.a[n + 1]), None
        if self.exact is not None:
            return self.exact.state(float(t[n]), tau, n)
        s = tau / h
        return hermite(self.x, self.v, self.a, n, s, h), None

    def at(self, times: NDArray[np.float64]) -> State:
        """``(x, v, a)`` at each of `times` (1-D, within the span), one row each."""
        m = self.x.shape[1]
        out = [np.empty((times.size, m)) for _ in range(3)]
        for k, time in enumerate(times):
            n, tau = self.locate(float(time))
            state, _ = self.in_step(n, tau)
            for arr, value in zip(out, state, strict=True):
                arr[k] = value
        return out[0], out[1], out[2]


def hermite(
    x: NDArray[np.float64],
    v: NDArray[np.float64],
    a: NDArray[np.float64],
    n: int,
    s: float,
    h: float,
) -> State:
    """Cubic Hermite interpolation between rows `n`, `n+1` at the fraction `s` of the step
    `h`: ``x`` from ``(x, v)``, ``v`` from ``(v, a)``; ``a`` linearly."""
    s2, s3 = s * s, s * s * s
    h00, h10, h01, h11 = 2 * s3 - 3 * s2 + 1, s3 - 2 * s2 + s, -2 * s3 + 3 * s2, s3 - s2
    xs = h00 * x[n] + h10 * h * v[n] + h01 * x[n + 1] + h11 * h * v[n + 1]
    vs = h00 * v[n] + h10 * h * a[n] + h01 * v[n + 1] + h11 * h * a[n + 1]
    acc = (1.0 - s) * a[n] + s * a[n + 1]
    return xs, vs, acc

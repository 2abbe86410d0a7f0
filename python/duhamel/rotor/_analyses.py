"""The rotor's analyses at constant speed: complex modes, natural frequencies and the
Campbell diagram (a mixin of :class:`~duhamel.rotor.Rotor`, which owns the model)."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel.rotor._speed import constant_speed
from duhamel.rotor.campbell import Campbell, campbell
from duhamel.rotor.modes import Modes, complex_modes

__all__ = ["RotorAnalyses"]


class RotorAnalyses:
    """Analyses of a rotor model: needs ``matrices(speed)`` and ``shafts``."""

    shafts: tuple[Any, ...]
    matrices: Any  # the Rotor's method: speed -> RotorMatrices

    # ------------------------------------------------------------------ eigenvalues
    def modes(self, speed: float = 0.0, n: int | None = None) -> Modes:
        """Complex modes at constant `speed` from the first-order eigenproblem.

        ``(lambda^2 M + lambda (C + speed G) + K) u = 0`` with the full ``K`` and ``C`` (all
        bearing terms), linearised as ``[[0, s I], [-K/s, -(C + speed G)]] z = lambda
        [[I, 0], [0, M]] z`` (``s`` a frequency scale) and solved by the QZ algorithm, so
        that massless degrees of freedom (``rho = 0`` shafts, Jeffcott models) are allowed:
        they give infinite eigenvalues, which are dropped. Only oscillatory modes are kept
        (``Im(lambda) > 1e-6 max|lambda|``: rigid-body and overdamped modes are left out).

        Parameters
        ----------
        speed : float
            Spin speed (rad/s); speed-dependent bearings take their coefficients there.
        n : int, optional
            Keep the lowest `n` modes (default: all oscillatory ones).

        Returns
        -------
        Modes
        """
        w = constant_speed(speed)
        M, K, C, G = self.matrices(w)
        lengths = [s.L for s in self.shafts]
        ell = float(np.mean(lengths)) if lengths else 1.0
        return complex_modes(M, C + w * G, K, speed=w, n=n, length_scale=ell)

    def natural_frequencies(self, speed: float = 0.0, n: int | None = None) -> NDArray[np.float64]:
        """Damped natural frequencies (rad/s, ascending) at constant `speed`:
        ``Im(lambda)`` of :meth:`modes`."""
        return self.modes(speed, n).frequencies

    def campbell(
        self, speeds: ArrayLike, n_modes: int | None = None, *, track: bool = True
    ) -> Campbell:
        """Damped natural frequencies at each of `speeds` (rad/s), modes tracked by shape.

        With ``track=True`` (the default) the modes at each speed are matched to those at the
        next lower speed by their shapes: the cost ``1 - MAC`` (:meth:`Modes.mac`: rotations
        weighted by the mean element length) of every pair is minimised over one-to-one
        assignments (``scipy.optimize.linear_sum_assignment``; the relative eigenvalue
        distance, weighted ``1e-6``, only breaks ties). Column ``j`` then follows one branch
        through crossings: where a forward whirl branch crosses a backward one, the columns
        do not swap. All oscillatory modes are tracked; `n_modes` then selects what is shown.
        With ``track=False``, column ``j`` is the ``j``-th lowest frequency at each speed.

        Parameters
        ----------
        speeds : array_like
            Spin speeds (rad/s), in any order: the tracking walks them in ascending order and
            the rows come back in the order given (repeated speeds are allowed). Across zero
            speed a branch keeps its orbit sense, so its whirl label (relative to the spin)
            changes from backward to forward there.
        n_modes : int, optional
            Show the lowest `n_modes` modes at each speed (default: all oscillatory modes).
            Untracked: ``n_modes`` columns. Tracked: one column per branch that is among the
            lowest ``n_modes`` at some speed, NaN where it is not (so a branch may enter or
            leave the window where it crosses the ``n_modes``-th mode, and there may be more
            than ``n_modes`` columns); every row shows the same frequencies as untracked.
        track : bool
            Keyword only. Track modes through crossings (default), or sort them by
            frequency at each speed (the behaviour before tracking existed).

        Returns
        -------
        Campbell
            Tracked columns are ordered by where their branch enters: first the branches at
            the lowest speed, ascending, then branches that appear (modes that become
            oscillatory, or enter the ``n_modes`` window) at higher speeds. A mode that stops
            being oscillatory ends its branch (NaN from there); ``Campbell.mac`` flags poorly
            resolved crossings.

        Examples
        --------
        A disk at mid-span: the backward whirl of the tilt mode falls through the forward
        whirl of the translational mode near 4000 rad/s.

        >>> import numpy as np
        >>> from duhamel.rotor import STEEL, Bearing, Disk, Rotor, Shaft
        >>> rotor = Rotor([Shaft(0.25, 0.05, material=STEEL)] * 4, [Disk(2, 30.0, 0.6, 0.3)],
        ...               [Bearing(0, 1e7, 1e7), Bearing(4, 1e7, 1e7)])
        >>> speeds = np.linspace(0.0, 5000.0, 26)
        >>> tracked = rotor.campbell(speeds, n_modes=4)
        >>> tracked.frequencies.shape
        (26, 4)
        >>> [np.unique(tracked.whirl[:, j]).tolist() for j in range(4)]
        [['backward'], ['forward'], ['backward'], ['forward']]
        >>> np.round(tracked.frequencies[-1], 1).tolist()    # at 5000 rad/s
        [263.9, 266.1, 216.1, 2167.8]
        >>> untracked = rotor.campbell(speeds, n_modes=4, track=False)
        >>> np.unique(untracked.whirl[1:, 1]).tolist()       # the second lowest: two branches
        ['backward', 'forward']
        >>> round(float(np.nanmin(tracked.mac)), 3)          # every matched pair
        0.993
        """
        return campbell(self.modes, speeds, n_modes, track=track)

    def plot_campbell(
        self,
        speeds: ArrayLike,
        n_modes: int | None = None,
        *,
        track: bool = True,
        **kwargs: Any,
    ) -> Any:
        """:meth:`campbell` then :func:`duhamel.rotor.plot_campbell`; returns the Axes."""
        return self.campbell(speeds, n_modes, track=track).plot(**kwargs)

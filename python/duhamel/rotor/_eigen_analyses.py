"""A rotor's eigenvalue analyses at constant speed: complex modes, natural frequencies, the
Campbell diagram, critical speeds and API 684 Level I stability (a mixin of
:class:`~duhamel.rotor._analyses.RotorAnalyses`). With magnetic bearings the modes are the
closed loop's (:mod:`duhamel.rotor._amb_linear`)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel.rotor._speed import constant_speed
from duhamel.rotor.campbell import Campbell, campbell
from duhamel.rotor.critical import HEAVY_DAMPING, CriticalSpeeds, critical_speeds
from duhamel.rotor.modes import Modes, complex_modes, modes_of
from duhamel.rotor.stability import Level1Stability, level1_stability

__all__ = ["LEVEL1_MODES", "EigenAnalyses"]

#: Level I follows the first forward mode among the lowest ``LEVEL1_MODES + 4`` modes of a
#: large model (shift-invert; all modes of a small one).
LEVEL1_MODES = 6


class EigenAnalyses:
    """Eigenvalue analyses of a rotor model: needs ``matrices(speed)``, ``shafts``, ``dof``
    and ``magnetic`` (its magnetic bearings)."""

    shafts: tuple[Any, ...]
    matrices: Any
    dof: Any
    magnetic: tuple[Any, ...]
    n_dof: int
    #: Per node its dofs (x, y, theta_x, theta_y), -1 where absent (point masses); None: 4
    #: per node in order.
    layout: Any = None

    def _length_scale(self) -> float:
        lengths = [s.L for s in self.shafts]
        return float(np.mean(lengths)) if lengths else 1.0

    def _window(self, n_modes: int | None) -> int | None:
        """The modes a tracking needs of a large model (``n_modes + 4``: two pairs more
        than shown, from the shift-invert path), None for all (small models, or all
        asked)."""
        from duhamel.rotor._sparse_modes import sparse_worth

        if n_modes is None or isinstance(n_modes, bool) or not isinstance(n_modes, int):
            return None
        window = int(n_modes) + 4
        return window if sparse_worth(int(self.n_dof), window) else None

    def _modes_below(self, speed: float, frequency: float, modes: Any = None) -> int | None:
        """How many modes of a large model lie below `frequency` at `speed`, plus two (the
        shift-invert path asked for more until one is above it); None for small models.
        `modes`: where the modes come from (default :meth:`modes`)."""
        from duhamel.rotor._sparse_modes import sparse_worth

        modes_at = self.modes if modes is None else modes
        n = 5  # probes 9, 14, 24, ... modes; 9 is the Campbell window (count + 6) of 3 below
        while sparse_worth(int(self.n_dof), n + 4):
            f = modes_at(speed, n + 4).frequencies
            if f.size < n + 4 or f[-1] > frequency:
                return int(np.count_nonzero(f <= frequency)) + 2
            n *= 2
        return None

    def _modes_near(self, speed: float, sigma: complex, k: int = 6) -> Modes | None:
        """The oscillatory modes among the `k` eigenvalues nearest `sigma` at `speed` (a
        large model's shift-invert path, :func:`~duhamel.rotor._sparse_modes.modes_near`),
        ascending; None where that path does not apply (magnetic bearings' closed loops,
        small or massless models)."""
        from duhamel.rotor._sparse_modes import modes_near, sparse_worth

        if self.magnetic or not sparse_worth(int(self.n_dof), k):
            return None
        w = constant_speed(speed)
        M, K, C, G = self.matrices(w)
        found = modes_near(M, C + w * G, K, sigma, k)
        if found is None:
            return None
        lam, vec = found
        up = lam.imag > 0.0
        order = np.argsort(lam.imag[up], kind="stable")
        if not order.size:
            return None
        return modes_of(lam[up][order], vec[:, up][:, order], np.zeros(0, dtype=complex),
                        speed=w, length_scale=self._length_scale(), layout=self.layout)  # fmt: skip

    def _modes_of(
        self, M: NDArray, D: NDArray, K: NDArray, speed: float, n: int | None = None
    ) -> Modes:
        """The modes of ``(M, D, K)`` at `speed`, with the magnetic bearings' closed loop."""
        ell = self._length_scale()
        if self.magnetic:
            from duhamel.rotor._amb_linear import amb_axes, loop_modes

            axes = amb_axes(self.magnetic, self.dof)
            return loop_modes(M, D, K, axes, speed=speed, n=n, length_scale=ell,
                              layout=self.layout)  # fmt: skip
        return complex_modes(M, D, K, speed=speed, n=n, length_scale=ell, layout=self.layout)

    def level1_stability(
        self,
        speed: float,
        *,
        location: int | Sequence[int],
        q_range: ArrayLike | None = None,
        q_a: float | None = None,
    ) -> Level1Stability:
        """API 684 / API 617 Level I stability screening at `speed` (rad/s).

        A cross-coupled stiffness ``k_xy = q``, ``k_yx = -q`` (split equally among the
        nodes of `location`) is added to ``K``; at each ``q`` of `q_range` the complex modes
        (:meth:`modes`) give the log decrement of the first forward mode (the lowest one not
        in backward whirl). The threshold ``Q_0`` where it reaches zero is refined on the
        eigenproblem by Brent's method.

        Parameters
        ----------
        speed : float
            Spin speed (rad/s): the maximum continuous speed in API 617.
        location : int or sequence of int
            Keyword only. Node(s): mid-span for a between-bearing rotor, the impellers
            (their centre) for an overhung one.
        q_range : array_like, optional
            Keyword only. Increasing applied cross-couplings (N/m), from 0 or more; default
            31 values from 0 to the largest direct bearing stiffness ``K[x, x]`` at the
            location's node.
        q_a : float, optional
            Keyword only. The anticipated cross-coupling ``Q_A`` (N/m), e.g. from
            :func:`duhamel.rotor.stability.anticipated_cross_coupling`.

        Returns
        -------
        Level1Stability
            ``q``, ``log_dec``, ``threshold``, ``q_a``, ``ratio``, ``requires_level2``,
            :meth:`~Level1Stability.plot`.

        Examples
        --------
        >>> import numpy as np
        >>> from duhamel.rotor import STEEL, Bearing, Disk, Rotor, Shaft
        >>> rotor = Rotor([Shaft(0.25, 0.05, material=STEEL)] * 4, [Disk(2, 30.0, 0.6, 0.3)],
        ...               [Bearing(0, 1e7, 1e7, cxx=1e4, cyy=1e4),
        ...                Bearing(4, 1e7, 1e7, cxx=1e4, cyy=1e4)])
        >>> res = rotor.level1_stability(600.0, location=2, q_range=np.linspace(0, 4e5, 9),
        ...                              q_a=5e4)
        >>> bool(res.log_dec[0] > 0 > res.log_dec[-1]), round(res.threshold)
        (True, 102033)
        >>> round(res.ratio, 2), round(res.log_dec_at_q_a, 3), res.requires_level2
        (2.04, 0.061, True)
        """
        w = constant_speed(speed)
        nodes = (location,) if isinstance(location, int | np.integer) else tuple(location)
        if not nodes:
            raise ValueError("`location` is empty")
        xs, ys = self._location_dofs(nodes)
        M, K, C, G = self.matrices(w)
        if q_range is None:
            q_range = np.linspace(0.0, float(np.max(np.diag(K)[xs])), 31)
        D = C + w * G
        window = self._window(LEVEL1_MODES)  # large models: the lowest modes, shift-invert

        def modes_with(q: float) -> Modes:
            Kq = np.array(K, dtype=float)
            Kq[xs, ys] += q / len(nodes)
            Kq[ys, xs] -= q / len(nodes)
            return self._modes_of(M, D, Kq, w, window)

        location_nodes = tuple(int(n) for n in nodes)
        return level1_stability(modes_with, w, location_nodes, q_range, q_a)  # type: ignore[arg-type]

    def _location_dofs(self, nodes: tuple[Any, ...]) -> tuple[list[int], list[int]]:
        """The x and y dofs of the Level I `location` nodes (errors name `location`)."""
        xs, ys = [], []
        for n in nodes:
            if isinstance(n, bool) or not isinstance(n, int | np.integer):
                raise TypeError(f"`location` must hold node numbers, got {n!r}")
            try:
                xs.append(self.dof(int(n), "x"))
                ys.append(self.dof(int(n), "y"))
            except ValueError:
                raise ValueError(f"`location`: the rotor has no node {int(n)}") from None
        return xs, ys

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
        return self._modes_of(M, C + w * G, K, w, n)

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
        return campbell(self.modes, speeds, n_modes, track=track, window=self._window(n_modes))

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

    def critical_speeds(
        self,
        speeds: ArrayLike,
        *,
        harmonic: float = 1.0,
        whirl: str | None = "forward",
        n_modes: int | None = None,
        operating: tuple[float, float] | None = None,
        unbalances: Sequence[tuple[int, float, float]] | None = None,
        probe: int | None = None,
        max_damping: float = HEAVY_DAMPING,
    ) -> CriticalSpeeds:
        """Critical speeds as API 684 reports them: where a damped natural frequency equals
        `harmonic` times the spin speed (the crossings of the Campbell diagram with the
        excitation line), each with its damping, amplification factor and separation margin;
        heavily damped modes listed apart (:mod:`duhamel.rotor.critical`).

        The tracked :meth:`campbell` on `speeds` brackets each crossing; each is then refined
        on the eigenproblem itself (Brent's method to 1e-12 relative, following the branch by
        its shape: on a large model among the few modes nearest the branch's last
        eigenvalue, by a complex shift-invert), so the result does not depend on the grid
        once the grid separates the crossings. A crossing whose mode's damping ratio
        exceeds `max_damping` (0.2: ``AF`` about ``1 / (2 zeta) = 2.5``, API 684's
        critically damped limit) is not a critical speed to keep away from: it goes to
        ``heavily_damped``. For each other synchronous
        one (``harmonic = 1``) the unbalance response near it (an unbalance at the node of
        the mode's largest translation, read there; or `unbalances` read at `probe`) gives
        the peak speed ``N_c`` (Newton's method on the response's derivative) and the
        half-power speeds ``N_1, N_2`` (Brent's method on the response),
        ``AF = N_c / (N_2 - N_1)``, and with `operating` the
        separation margin and the one API 684 requires.

        Parameters
        ----------
        speeds : array_like
            Spin speeds (rad/s) spanning the range searched.
        harmonic : float
            Keyword only. Excitation order (1: unbalance, synchronous; other orders get no
            amplification factor).
        whirl : {'forward', 'backward'} or None
            Keyword only. Only branches of this whirl (default forward, which unbalance
            excites in an isotropic rotor); None: all.
        n_modes : int, optional
            Keyword only. Branches among the lowest `n_modes` modes.
        operating : (float, float), optional
            Keyword only. Minimum operating and maximum continuous speeds (rad/s), for the
            separation margins.
        unbalances : list of (node, m_e, phase), optional
            Keyword only. The unbalance of the responses (default: 1e-4 kg m at the node of
            each mode's largest translation; the amplification factor does not depend on
            its size).
        probe : int, optional
            Keyword only. The node whose orbit (major semi-axis) is read (default: the node
            of each mode's largest translation).
        max_damping : float
            Keyword only. Damping ratio above which a crossing is heavily damped.

        Returns
        -------
        CriticalSpeeds
            As an array the critical speeds (rad/s, ascending); ``critical`` (each a
            :class:`~duhamel.rotor.critical.CriticalSpeed`), ``heavily_damped``,
            ``amplification_factors``, ``margins``, ``required_margins``, ``summary()``.

        Examples
        --------
        >>> import numpy as np
        >>> from duhamel.rotor import STEEL, Bearing, Disk, Rotor, Shaft
        >>> rotor = Rotor([Shaft(0.25, 0.05, material=STEEL)] * 4, [Disk(2, 30.0, 0.6, 0.3)],
        ...               [Bearing(0, 1e7, 1e7, cxx=500.0, cyy=500.0),
        ...                Bearing(4, 1e7, 1e7, cxx=500.0, cyy=500.0)])
        >>> crit = rotor.critical_speeds(np.linspace(0.0, 1000.0, 21), operating=(300, 450))
        >>> np.round(crit, 3).tolist()
        [265.035]
        >>> c = crit.critical[0]
        >>> round(c.amplification_factor, 1), round(c.margin, 3), c.meets_margin
        (501.7, 0.132, False)
        """
        return critical_speeds(
            self, speeds, harmonic=harmonic, whirl=whirl, n_modes=n_modes,
            operating=operating, unbalances=unbalances, probe=probe, max_damping=max_damping,
        )  # fmt: skip

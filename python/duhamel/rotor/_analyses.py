"""The rotor's analyses at constant speed: complex modes, natural frequencies and the
Campbell diagram (a mixin of :class:`~duhamel.rotor.Rotor`, which owns the model)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel.rotor._plot_response import plot_mode_shape
from duhamel.rotor._speed import constant_speed
from duhamel.rotor.campbell import Campbell, campbell
from duhamel.rotor.critical import HEAVY_DAMPING, CriticalSpeeds, critical_speeds
from duhamel.rotor.frequency import (
    DofSpec,
    FrequencyResponse,
    FrequencyResponseMap,
    frequency_response,
    frequency_response_map,
    resolve_dofs,
)
from duhamel.rotor.modes import Modes, complex_modes
from duhamel.rotor.stability import Level1Stability, level1_stability
from duhamel.rotor.unbalance import UnbalanceResponse, unbalance_response

__all__ = ["RotorAnalyses"]


class RotorAnalyses:
    """Analyses of a rotor model: needs ``matrices(speed)`` and ``shafts``."""

    shafts: tuple[Any, ...]
    matrices: Any  # the Rotor's method: speed -> RotorMatrices
    dof: Any  # the Rotor's method: (node, direction) -> dof
    nodes_z: Any
    has_speed_dependent_bearings: bool
    journals: tuple[Any, ...]
    dof_labels: tuple[str, ...]
    n_dof: int

    def _matrices_source(self) -> Any:
        """The matrices, or ``speed -> matrices`` when they depend on the speed."""
        if self.has_speed_dependent_bearings or self.journals:
            return self.matrices  # the coefficients (linearisations) of each speed
        return self.matrices(0.0)

    def _dofs(self, items: Sequence[DofSpec] | DofSpec, name: str) -> tuple[int, ...]:
        return resolve_dofs(items, name, n_dof=self.n_dof, labels=self.dof_labels, dof=self.dof)

    def frequency_response(
        self,
        speed: float | str,
        frequencies: ArrayLike,
        inputs: Sequence[DofSpec] | DofSpec,
        outputs: Sequence[DofSpec] | DofSpec,
    ) -> FrequencyResponse:
        """Receptances between force/moment `inputs` and displacement `outputs` at a constant
        spin `speed`, exact in the frequency domain.

        ``(K - w^2 M + i w (C + speed G)) H(w) = B`` per frequency ``w`` (``B``: unit
        forces on the inputs), with the bearing coefficients (and journal linearisations) at
        `speed`; a force ``Re(F e^{i w t})`` on input ``i`` gives
        ``x_o(t) = Re(H[o, i] F e^{i w t})``, the convention of :meth:`unbalance_response`.
        Large banded models use its banded LU (``gbsv``), the others a batched dense LU.

        Parameters
        ----------
        speed : float or "synchronous"
            Spin speed (rad/s); ``"synchronous"``: the spin speed equals each frequency (the
            coefficients follow it), as ROSS's ``run_freq_response``.
        frequencies : array_like
            Excitation frequencies (rad/s).
        inputs, outputs : dof or sequence of dofs
            Each a global dof index, a label of :attr:`dof_labels` (``"x_2"``) or
            ``(node, direction)``.

        Returns
        -------
        FrequencyResponse
            ``response`` of shape ``(n_frequencies, n_outputs, n_inputs)``; Bode and
            Nyquist plots.

        Examples
        --------
        >>> import numpy as np
        >>> from duhamel.rotor import STEEL, Bearing, Disk, Rotor, Shaft
        >>> rotor = Rotor([Shaft(0.25, 0.05, material=STEEL)] * 4, [Disk(2, 30.0, 0.6, 0.3)],
        ...               [Bearing(0, 1e7, 1e7, cxx=500.0, cyy=500.0),
        ...                Bearing(4, 1e7, 1e7, cxx=500.0, cyy=500.0)])
        >>> frf = rotor.frequency_response(300.0, np.linspace(10.0, 600.0, 60),
        ...                                inputs=[(2, "x"), (2, "y")], outputs=["x_2"])
        >>> frf.response.shape
        (60, 1, 2)
        """
        return frequency_response(
            self._matrices_source(),
            speed,
            frequencies,
            self._dofs(inputs, "inputs"),
            self._dofs(outputs, "outputs"),
            labels=self.dof_labels,
        )

    def frequency_response_map(
        self,
        speeds: ArrayLike,
        frequencies: ArrayLike,
        inputs: Sequence[DofSpec] | DofSpec,
        outputs: Sequence[DofSpec] | DofSpec,
    ) -> FrequencyResponseMap:
        """:meth:`frequency_response` at each of `speeds` (rad/s): ``response`` of shape
        ``(n_speeds, n_frequencies, n_outputs, n_inputs)`` and a magnitude map over speed
        and frequency (:meth:`FrequencyResponseMap.plot_map`).

        Examples
        --------
        >>> import numpy as np
        >>> from duhamel.rotor import STEEL, Bearing, Rotor, Shaft
        >>> rotor = Rotor([Shaft(0.5, 0.05, material=STEEL)] * 2,
        ...               bearings=[Bearing(0, 1e7, 1e7, cxx=1e3, cyy=1e3), Bearing(2, 1e7, 1e7)])
        >>> fmap = rotor.frequency_response_map([0.0, 500.0], np.linspace(10, 900, 30),
        ...                                     "x_1", "x_1")
        >>> fmap.response.shape
        (2, 30, 1, 1)
        """
        return frequency_response_map(
            self._matrices_source(),
            speeds,
            frequencies,
            self._dofs(inputs, "inputs"),
            self._dofs(outputs, "outputs"),
            labels=self.dof_labels,
        )

    def unbalance_response(
        self, speeds: ArrayLike, unbalances: Sequence[tuple[int, float, float]]
    ) -> UnbalanceResponse:
        """Steady-state unbalance response at each of `speeds`, exact in the frequency
        domain: ``(K - Omega^2 M + i Omega (C + Omega G)) X = F`` per speed, with the bearing
        coefficients (and Rayleigh/modal structural damping) at that speed.

        Parameters
        ----------
        speeds : array_like
            Spin speeds (rad/s).
        unbalances : list of (node, m_e, phase)
            Unbalance (kg m) at a node and its angle at ``t = 0`` (rad, from x towards y):
            the force ``m_e Omega^2 (cos(Omega t + phase), sin(Omega t + phase))`` of
            :class:`~duhamel.rotor.Unbalance`.

        Returns
        -------
        UnbalanceResponse
            ``response`` of shape ``(n_speeds, n_dof)``, ``x(t) = Re(X e^{i Omega t})``;
            amplitudes, phases, orbit axes, :meth:`~UnbalanceResponse.peaks` (critical speeds,
            amplification factors, API 684 separation margins), Bode and polar plots.

        Examples
        --------
        >>> import numpy as np
        >>> from duhamel.rotor import STEEL, Bearing, Disk, Rotor, Shaft
        >>> rotor = Rotor([Shaft(0.25, 0.05, material=STEEL)] * 4, [Disk(2, 30.0, 0.6, 0.3)],
        ...               [Bearing(0, 1e7, 1e7, cxx=500.0, cyy=500.0),
        ...                Bearing(4, 1e7, 1e7, cxx=500.0, cyy=500.0)], zeta=0.02)
        >>> res = rotor.unbalance_response(np.linspace(100.0, 500.0, 401), [(2, 1e-4, 0.0)])
        >>> res.response.shape
        (401, 20)
        >>> peak = res.peaks(2, operating=(300.0, 450.0))[0]
        >>> round(peak.speed, 1), round(peak.amplification_factor, 1), round(peak.margin, 3)
        (265.2, 23.7, 0.131)
        """
        return unbalance_response(self._matrices_source(), speeds, unbalances, dof=self.dof)

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
        lengths = [s.L for s in self.shafts]
        ell = float(np.mean(lengths)) if lengths else 1.0
        D = C + w * G

        def modes_with(q: float) -> Modes:
            Kq = np.array(K, dtype=float)
            Kq[xs, ys] += q / len(nodes)
            Kq[ys, xs] -= q / len(nodes)
            return complex_modes(M, D, Kq, speed=w, length_scale=ell)

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

    def closed_loop(self, speed: float, magnetic_bearings: Sequence[Any]) -> Any:
        """The rotor at constant `speed` with active magnetic bearings (on top of its
        bearings) and their controllers as one linear first-order system
        (:class:`duhamel.rotor.magnetic.ClosedLoop`): closed-loop eigenvalues and stability,
        receptances, the sensitivity function and its peak, exact transients.

        Examples
        --------
        >>> import numpy as np
        >>> from duhamel.rotor import STEEL, Disk, Rotor, Shaft
        >>> from duhamel.rotor.magnetic import PID, MagneticBearing
        >>> rotor = Rotor([Shaft(0.25, 0.05, material=STEEL)] * 4, [Disk(2, 20.0, 0.3, 0.15)])
        >>> amb = [MagneticBearing(n, k_i=100.0, k_s=1e6, controller=PID(3e4, 1e5, 30.0, 1e-4))
        ...        for n in (0, 4)]
        >>> loop = rotor.closed_loop(300.0, amb)
        >>> loop.stable, loop.A.shape
        (True, (48, 48))
        """
        from duhamel.rotor.magnetic import closed_loop

        w = constant_speed(speed)
        return closed_loop(self.matrices(w), magnetic_bearings, w, dof=self.dof)

    def static_equilibrium(self, speed: float, g: float = 9.81) -> NDArray[np.float64]:
        """The static state under the rotor's own weight (along ``-y``) at spin `speed`:
        the linear structure and bearings and the journal bearings' film forces (at rest)
        in balance, found by Newton's method on their exact tangents (backtracking keeps
        every journal inside its clearance) to 1e-12 of the weight. Without journal
        bearings it is :meth:`static_deflection`.

        Examples
        --------
        >>> import numpy as np
        >>> from duhamel.rotor import STEEL, Disk, Rotor, Shaft, ShortJournalBearing
        >>> journals = [ShortJournalBearing(n, 0.05, 0.02, 5e-5, 0.02) for n in (0, 2)]
        >>> rotor = Rotor([Shaft(0.3, 0.05, material=STEEL)] * 2, [Disk(1, 20.0, 0.1, 0.05)],
        ...               journals)
        >>> x = rotor.static_equilibrium(500.0)
        >>> e = np.hypot(x[0], x[1]) / 5e-5          # eccentricity ratio at bearing 0
        >>> bool(0.0 < e < 1.0), bool(x[1] < 0.0)
        (True, True)
        """
        from duhamel.rotor._equilibrium import static_equilibrium

        return static_equilibrium(self, constant_speed(speed), g)

    def plot_mode(self, speed: float, j: int, **kwargs: Any) -> Any:
        """Mode `j` at `speed` along the axis (:func:`duhamel.rotor.plot_mode_shape`:
        ``kind='3d'`` orbits or ``'2d'`` major semi-axis); returns the Axes."""
        return plot_mode_shape(self.nodes_z, self.modes(speed), j, **kwargs)

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
        its shape), so the result does not depend on the grid once the grid separates the
        crossings. A crossing whose mode's damping ratio exceeds `max_damping` (0.2: ``AF``
        about ``1 / (2 zeta) = 2.5``, API 684's critically damped limit) is not a critical
        speed to keep away from: it goes to ``heavily_damped``. For each other synchronous
        one (``harmonic = 1``) the unbalance response near it (an unbalance at the node of
        the mode's largest translation, read there; or `unbalances` read at `probe`) gives
        the peak speed ``N_c`` and the half-power speeds ``N_1, N_2`` (each refined on the
        response by Brent's method), ``AF = N_c / (N_2 - N_1)``, and with `operating` the
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

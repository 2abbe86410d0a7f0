"""The rotor's analyses at constant speed (a mixin of :class:`~duhamel.rotor.Rotor`, which
owns the model): frequency and unbalance responses, the closed loop with magnetic bearings,
static equilibrium; the eigenvalue analyses (modes, Campbell diagram, critical speeds, Level
I stability) in :mod:`duhamel.rotor._eigen_analyses`. Magnetic bearings among the model's
bearings (``magnetic``) enter every analysis exactly (:mod:`duhamel.rotor._amb_linear`)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel.constants import STANDARD_GRAVITY
from duhamel.rotor._eigen_analyses import EigenAnalyses
from duhamel.rotor._plot_response import plot_mode_shape
from duhamel.rotor._speed import constant_speed
from duhamel.rotor.frequency import (
    DofSpec,
    FrequencyResponse,
    FrequencyResponseMap,
    frequency_response,
    frequency_response_map,
    resolve_dofs,
)
from duhamel.rotor.unbalance import UnbalanceResponse, unbalance_response

__all__ = ["RotorAnalyses"]


class RotorAnalyses(EigenAnalyses):
    """Analyses of a rotor model: needs ``matrices(speed)`` and ``shafts``."""

    shafts: tuple[Any, ...]
    matrices: Any  # the Rotor's method: speed -> RotorMatrices
    dof: Any  # the Rotor's method: (node, direction) -> dof
    nodes_z: Any
    has_speed_dependent_bearings: bool
    journals: tuple[Any, ...]
    dof_labels: tuple[str, ...]
    n_dof: int
    #: The active magnetic bearings (closed loops with their controllers).
    magnetic: tuple[Any, ...] = ()

    def _matrices_source(self) -> Any:
        """The matrices, or ``speed -> matrices`` when they depend on the speed (with
        magnetic bearings: their dynamic stiffness at an excitation frequency equal to the
        speed, as an unbalance response needs)."""
        if self.magnetic:
            from duhamel.rotor._amb_linear import amb_axes, with_bearings_at

            return with_bearings_at(self.matrices, amb_axes(self.magnetic, self.dof))
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
        ins, outs = self._dofs(inputs, "inputs"), self._dofs(outputs, "outputs")
        if self.magnetic and not isinstance(speed, str):
            from duhamel.rotor._amb_linear import amb_axes, loop_frequency_response

            axes = amb_axes(self.magnetic, self.dof)
            w = constant_speed(speed)
            return loop_frequency_response(
                self.matrices(w), axes, w, frequencies, ins, outs, labels=self.dof_labels
            )
        return frequency_response(
            self._matrices_source(), speed, frequencies, ins, outs, labels=self.dof_labels
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
        if self.magnetic:
            from duhamel.rotor._amb_linear import stacked

            parts = [
                self.frequency_response(float(v), frequencies, inputs, outputs)
                for v in np.atleast_1d(np.asarray(speeds, dtype=float))
            ]
            return stacked(speeds, parts)
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

    def closed_loop(self, speed: float, magnetic_bearings: Sequence[Any] = ()) -> Any:
        """The rotor at constant `speed` with active magnetic bearings (its own, :attr:`magnetic`,
        and `magnetic_bearings` on top of its bearings) and their controllers as one linear
        first-order system
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
        every = (*self.magnetic, *magnetic_bearings)
        return closed_loop(self.matrices(w), every, w, dof=self.dof)

    def static_equilibrium(self, speed: float, g: float = STANDARD_GRAVITY) -> NDArray[np.float64]:
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

"""The elastic response spectrum as a result (:class:`ResponseSpectrum`), apart from the
functions that compute it (:mod:`.response`) so that a run's floor spectra
(:meth:`duhamel.Solution.floor_spectra`) can return one without importing them."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["ResponseSpectrum"]


def _omega(periods: NDArray[np.float64]) -> NDArray[np.float64]:
    """``2 pi / T``, with 0 in place of the rigid oscillator's infinite frequency (the
    pseudo-quantities are defined apart there)."""
    safe = np.where(periods > 0.0, periods, 1.0)
    return np.where(periods > 0.0, 2.0 * np.pi / safe, 0.0)


@dataclass(frozen=True, eq=False)
class ResponseSpectrum:
    """Elastic response spectra; arrays of shape ``(n_motions, n_dampings, n_periods)``.

    Attributes
    ----------
    periods : ndarray
        Periods in s (0 is the rigid oscillator: ``sa`` the PGA).
    damping : ndarray
        Damping ratios.
    sd, sv, sa : ndarray
        Peak relative displacement (m), relative velocity (m/s), absolute acceleration
        (m/s^2).
    names : list of str
        The motions' names.
    """

    periods: NDArray[np.float64]
    damping: NDArray[np.float64]
    sd: NDArray[np.float64]
    sv: NDArray[np.float64]
    sa: NDArray[np.float64]
    names: list[str]

    @property
    def psv(self) -> NDArray[np.float64]:
        """Pseudo-velocity ``omega sd`` (m/s); 0 at period 0."""
        return _omega(self.periods) * self.sd

    @property
    def psa(self) -> NDArray[np.float64]:
        """Pseudo-acceleration ``omega^2 sd`` (m/s^2); the PGA at period 0."""
        w = _omega(self.periods)
        return np.where(self.periods > 0.0, w * w * self.sd, self.sa)

    def plot(self, quantity: str = "psa", *, tripartite: bool = False, ax: Any = None) -> Any:
        """Plot one quantity against period (log axes), one line per motion and damping;
        ``tripartite=True`` draws ``psv`` with lines of constant ``sd`` and ``psa``.
        Returns the matplotlib Axes."""
        from duhamel.spectra.plot import plot_spectrum

        return plot_spectrum(self, quantity, tripartite, ax)

    def to_xarray(self) -> Any:
        """An ``xarray.Dataset`` with dims (motion, damping, period) and variables sd, sv, sa,
        psv, psa (needs xarray: ``pip install 'duhamel[xarray]'``)."""
        from duhamel.spectra.plot import dataset

        return dataset(self, ("sd", "sv", "sa", "psv", "psa"))

"""The time-domain stage of spectral matching (:func:`duhamel.records.match`): tapered
cosine wavelets added at the times of the oscillators' peaks, in the manner of RspMatch
(Abrahamson 1992; Hancock et al. 2006; the improved tapered cosine wavelet of Al Atik and
Abrahamson 2010).

For oscillators ``i`` at the matching periods, the peak pseudo-acceleration ``R_i`` occurs at
``t_i`` along the direction ``d_i`` (the sign of the response for one record; the direction
of the largest horizontal response, RotD100, for a pair). A wavelet ``w_j`` placed so that
oscillator ``j``'s response to it peaks at ``t_j`` is added along ``d_j`` with amplitude
``b_j``; to first order the peak of oscillator ``i`` changes by ``sum_j (d_i . d_j) C_ij
b_j``, where ``C_ij`` is oscillator ``i``'s response at ``t_i`` to ``w_j``. The amplitudes
solve ``C b = dR`` (least squares) for the misfit ``dR_i = R_i (target_i / S_i - 1)``, with
``S_i`` the record's exact spectrum; the responses and ``C`` are evaluated by FFT on the
zero-padded record (``C`` as one matrix product over the frequencies the oscillators and
wavelets reach).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["TimeDomainStep"]


class TimeDomainStep:
    """The linearised wavelet adjustment at fixed matching periods for records of ``n``
    samples at ``dt`` (one or two components)."""

    def __init__(self, periods: NDArray[np.float64], n: int, dt: float, zeta: float) -> None:
        self.periods, self.n, self.dt, self.zeta = periods, n, dt, zeta
        self.regularisation = 0.1
        self.relaxation = 0.5
        tmax = float(periods.max())
        self.pad = int(np.ceil(3.0 * tmax / dt))
        self.n_fft = n + 2 * self.pad
        freqs = np.fft.rfftfreq(self.n_fft, dt)
        # frequencies the oscillators and the wavelets reach: up to 2.5 times the highest
        # oscillator frequency (their response beyond it is below 1e-3 of the peak's), or
        # the Nyquist frequency when that lies beyond it
        self.keep = min(int(np.searchsorted(freqs, 2.5 / periods.min())) + 1, freqs.size)
        self.omega = 2.0 * np.pi * freqs[: self.keep]
        w = self.omega[None, :]
        wi = 2.0 * np.pi / periods[:, None]
        # pseudo-acceleration per unit ground acceleration: -wi^2 / (wi^2 - w^2 + 2i zeta wi w)
        self.h = -(wi * wi) / (wi * wi - w * w + 2j * zeta * wi * w)
        self.wi = wi[:, 0]
        self.t = dt * (np.arange(n))
        f = 1.0 / periods
        self.gamma = 1.178 * f**-0.93
        wd = self.wi * np.sqrt(1.0 - zeta * zeta)
        self.wd = wd
        self.shift = np.arctan(np.sqrt(1.0 - zeta * zeta) / zeta) / wd
        # irfft weights: 1 at 0 and Nyquist, 2 between, over n_fft
        c = np.full(self.keep, 2.0)
        c[0] = 1.0
        if self.n_fft % 2 == 0 and self.keep == self.n_fft // 2 + 1:
            c[-1] = 1.0
        self.c = c / self.n_fft

    def responses(self, comps: list[NDArray[np.float64]]) -> NDArray[np.float64]:
        """Pseudo-acceleration histories ``(n_components, n_periods, n)``."""
        out = []
        for a in comps:
            spec = np.fft.rfft(np.pad(a, (self.pad, self.pad)))[: self.keep]
            full = np.zeros((self.periods.size, self.n_fft // 2 + 1), dtype=complex)
            full[:, : self.keep] = self.h * spec[None, :]
            out.append(np.fft.irfft(full, self.n_fft, axis=1)[:, self.pad : self.pad + self.n])
        return np.stack(out)

    def wavelets(self, times: NDArray[np.float64], amplitudes: NDArray[np.float64]) -> Any:
        """``sum_j amplitudes_j w_j(t)`` at the record's samples: the tapered cosine
        wavelets ``cos(wd_j s) exp(-(s / gamma_j)^2)``, ``s = t - t_j + shift_j``, each
        evaluated where its envelope exceeds 1e-7 (4 gamma_j either side)."""
        out = np.zeros(self.n)
        for j in range(times.size):
            centre = times[j] - self.shift[j]
            lo = max(0, int(np.floor((centre - 4.0 * self.gamma[j]) / self.dt)))
            hi = min(self.n, int(np.ceil((centre + 4.0 * self.gamma[j]) / self.dt)) + 1)
            if hi <= lo:
                continue
            s = self.t[lo:hi] - centre
            out[lo:hi] += (
                amplitudes[j] * np.cos(self.wd[j] * s) * np.exp(-((s / self.gamma[j]) ** 2))
            )
        return out

    def step(
        self, comps: list[NDArray[np.float64]], ratio: NDArray[np.float64]
    ) -> list[NDArray[np.float64]]:
        """The components after one adjustment towards ``target / S = ratio`` at the
        matching periods."""
        hist = self.responses(comps)  # (c, p, n)
        mag = np.sqrt(np.sum(hist * hist, axis=0))  # (p, n): the largest horizontal response
        k = np.argmax(mag, axis=1)
        rows = np.arange(self.periods.size)
        peak = mag[rows, k]
        if np.any(peak <= 0.0):
            raise ValueError("a matching period has no response: the record is zero there")
        d = hist[:, rows, k] / peak[None, :]  # (c, p) unit directions
        times = self.t[k]
        # C_ij, oscillator i's response at t_i to wavelet j, as a sum over frequencies of
        # the oscillator's transfer function and the wavelet's (analytic) Fourier transform
        # ``sqrt(pi) gamma / 2 [exp(-gamma^2 (w - wd)^2 / 4) + exp(-gamma^2 (w + wd)^2 / 4)]
        # exp(-i w centre)`` (over dt: the DFT of its samples)
        w = self.omega[None, :]
        g = self.gamma[:, None]
        wd = self.wd[:, None]
        centre = (self.pad * self.dt + times - self.shift)[:, None]
        spec = (
            (0.5 * np.sqrt(np.pi) / self.dt)
            * g
            * (np.exp(-0.25 * (g * (w - wd)) ** 2) + np.exp(-0.25 * (g * (w + wd)) ** 2))
        )
        wf = spec * np.exp(-1j * w * centre)
        e = self.h * self.c[None, :] * np.exp(1j * w * (self.pad * self.dt + times)[:, None])
        cij = np.real(e @ wf.T) * (d.T @ d)
        dr = self.relaxation * peak * (ratio - 1.0)
        # Tikhonov-regularised least squares: neighbouring oscillators that peak at the
        # same instant make C nearly singular; the regularisation keeps the wavelets small
        lam = (self.regularisation * np.mean(np.abs(np.diag(cij)))) ** 2
        b = np.linalg.solve(cij.T @ cij + lam * np.eye(cij.shape[0]), cij.T @ dr)
        return [a + self.wavelets(times, b * d[c]) for c, a in enumerate(comps)]

"""Matplotlib plots of frequency response functions: Bode, Nyquist and the speed-frequency
magnitude map."""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["plot_frf_bode", "plot_frf_map", "plot_frf_nyquist"]


def _names(frf: Any, output: int, input: int) -> str:
    labels = frf.labels
    o, i = frf.outputs[int(output)], frf.inputs[int(input)]
    return f"{labels[o] if labels else o} / {labels[i] if labels else i}"


def plot_frf_bode(frf: Any, output: int = 0, input: int = 0, *, axes: Any = None) -> Any:
    """Magnitude (log scale) and phase (degrees) of one receptance against frequency.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import numpy as np
    >>> from duhamel.rotor import STEEL, Bearing, Rotor, Shaft
    >>> rotor = Rotor([Shaft(0.5, 0.05, material=STEEL)] * 2,
    ...               bearings=[Bearing(0, 1e7, 1e7, cxx=1e3, cyy=1e3), Bearing(2, 1e7, 1e7)])
    >>> frf = rotor.frequency_response(100.0, np.linspace(10, 3000, 50), ["x_1"], ["x_1"])
    >>> mag, ph = frf.plot_bode()
    >>> mag.get_yscale()
    'log'
    """
    import matplotlib.pyplot as plt

    if axes is None:
        _, axes = plt.subplots(2, 1, sharex=True)
    mag, ph = axes
    w = frf.frequencies
    mag.semilogy(w, frf.magnitude(output, input))
    ph.plot(w, np.degrees(frf.phase(output, input)))
    mag.set_ylabel("|H|")
    ph.set_ylabel("phase (deg)")
    ph.set_xlabel("frequency (rad/s)")
    speed = frf.speed if isinstance(frf.speed, str) else f"{frf.speed:g} rad/s"
    mag.set_title(f"{_names(frf, output, input)} at {speed}")
    return mag, ph


def plot_frf_nyquist(frf: Any, output: int = 0, input: int = 0, *, ax: Any = None) -> Any:
    """The receptance in the complex plane over the frequencies (a Nyquist plot)."""
    import matplotlib.pyplot as plt

    ax = ax if ax is not None else plt.subplots()[1]
    h = frf.response[:, int(output), int(input)]
    ax.plot(h.real, h.imag)
    ax.plot(h.real[:1], h.imag[:1], "o", color="k", label=f"{frf.frequencies[0]:g} rad/s")
    ax.set_xlabel("Re H")
    ax.set_ylabel("Im H")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_title(_names(frf, output, input))
    ax.legend()
    return ax


def plot_frf_map(frf_map: Any, output: int = 0, input: int = 0, *, ax: Any = None) -> Any:
    """``log10 |H|`` over spin speed and frequency, with the synchronous (1x) line."""
    import matplotlib.pyplot as plt

    ax = ax if ax is not None else plt.subplots()[1]
    mag = np.abs(frf_map.response[:, :, int(output), int(input)])
    s, w = frf_map.speeds, frf_map.frequencies
    mesh = ax.pcolormesh(s, w, np.log10(mag.T), shading="auto")
    plt.colorbar(mesh, ax=ax, label="log10 |H|")
    top = min(float(s.max()), float(w.max()))
    ax.plot([0.0, top], [0.0, top], "w--", lw=1, label="1x")
    ax.set_xlim(float(s.min()), float(s.max()))
    ax.set_ylim(float(w.min()), float(w.max()))
    ax.set_xlabel("speed (rad/s)")
    ax.set_ylabel("frequency (rad/s)")
    ax.set_title(_names(frf_map, output, input))
    ax.legend(loc="upper left")
    return ax

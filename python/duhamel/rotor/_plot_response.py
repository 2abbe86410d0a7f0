"""Matplotlib plots of frequency-domain results: mode shapes (orbits along the axis), Bode
and polar plots of an unbalance response."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from duhamel.rotor._orbit import circular_parts

__all__ = ["plot_bode", "plot_mode_shape", "plot_polar", "plot_spectrogram", "spectrogram"]

_COLOURS = {"forward": "tab:red", "backward": "tab:blue"}


def plot_mode_shape(
    z: ArrayLike, modes: Any, j: int, *, kind: str = "3d", ax: Any = None, n_orbit: int = 60
) -> Any:
    """The deflected shape of mode `j` of `modes` along the rotor axis.

    ``kind='3d'``: each node's orbit ``(x, y)`` at its axial position ``z`` (the start of
    each orbit marked, so its sense shows), and the shaft line at ``t = 0``. ``kind='2d'``:
    the major semi-axis of each node's orbit along ``z``, with the x and y deflections at
    ``t = 0``. The title gives the frequency, damping ratio and whirl.

    Parameters
    ----------
    z : array_like
        Axial position of each node (m), ``Rotor.nodes_z``.
    modes : Modes
        From ``Rotor.modes(speed)``.
    j : int
        Mode index.
    kind : {'3d', '2d'}
        Keyword only.
    ax : matplotlib Axes, optional
        Keyword only (a 3-D Axes for ``'3d'``).
    n_orbit : int
        Keyword only. Points per orbit.

    Returns
    -------
    matplotlib Axes

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from duhamel.rotor import STEEL, Bearing, Disk, Rotor, Shaft, plot_mode_shape
    >>> rotor = Rotor([Shaft(0.25, 0.05, material=STEEL)] * 4, [Disk(2, 30.0, 0.6, 0.3)],
    ...               [Bearing(0, 1e7, 1e7), Bearing(4, 1e7, 1e7)])
    >>> ax = plot_mode_shape(rotor.nodes_z, rotor.modes(500.0), 1, kind="2d")
    >>> ax.get_xlabel()
    'z (m)'
    """
    import matplotlib.pyplot as plt

    if kind not in ("3d", "2d"):
        raise ValueError(f"`kind` must be '3d' or '2d', got {kind!r}")
    if not 0 <= int(j) < modes.n_modes:
        raise ValueError(f"`j` must be in [0, {modes.n_modes}), got {j}")
    zs = np.asarray(z, dtype=float)
    shape = modes.shapes[:, int(j)].reshape(-1, 4)[: zs.size]
    X, Y = shape[:, 0], shape[:, 1]
    whirl = modes.whirl[int(j)]
    colour = _COLOURS.get(whirl, "tab:gray")
    lam = modes.eigenvalues[int(j)]
    title = (
        f"mode {j}: {lam.imag:.4g} rad/s ({lam.imag / (2 * np.pi):.4g} Hz), "
        f"zeta = {modes.damping_ratios[int(j)]:.3g}, {whirl}"
    )
    if kind == "2d":
        ax = ax if ax is not None else plt.subplots()[1]
        major = sum(circular_parts(X, Y))
        ax.plot(zs, major, color=colour, lw=2, label="major semi-axis")
        ax.plot(zs, X.real, "--", color="0.4", label="x at t = 0")
        ax.plot(zs, Y.real, ":", color="0.4", label="y at t = 0")
        ax.axhline(0.0, color="k", lw=0.5)
        ax.set_xlabel("z (m)")
        ax.set_ylabel("deflection (normalised)")
        ax.legend(fontsize="small")
        ax.set_title(title, fontsize="medium")
        return ax
    if ax is None:
        ax = plt.figure().add_subplot(projection="3d")
    tau = np.linspace(0.0, 2.0 * np.pi, int(n_orbit))
    rot = np.exp(1j * tau)
    for k in range(zs.size):
        ax.plot(np.full(tau.size, zs[k]), (X[k] * rot).real, (Y[k] * rot).real, color=colour, lw=1)
        ax.plot([zs[k]], [X[k].real], [Y[k].real], "o", color=colour, ms=3)
    ax.plot(zs, X.real, Y.real, color="k", lw=1.5)
    ax.set_xlabel("z (m)")
    ax.set_ylabel("x")
    ax.set_zlabel("y")
    ax.set_title(title, fontsize="medium")
    return ax


def plot_bode(response: Any, node: int, direction: str | None = None, *, axes: Any = None) -> Any:
    """Amplitude (log scale) and phase against speed for one node of an
    :class:`~duhamel.rotor.UnbalanceResponse`: the major semi-axis of the orbit (default) or
    one direction's amplitude and phase; peaks marked with their amplification factors.

    Returns
    -------
    (Axes, Axes)
        Amplitude and phase axes (the phase only for a direction).

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import numpy as np
    >>> from duhamel.rotor import STEEL, Bearing, Disk, Rotor, Shaft, plot_bode
    >>> rotor = Rotor([Shaft(0.25, 0.05, material=STEEL)] * 4, [Disk(2, 30.0, 0.6, 0.3)],
    ...               [Bearing(0, 1e7, 1e7), Bearing(4, 1e7, 1e7)], zeta=0.02)
    >>> res = rotor.unbalance_response(np.linspace(100.0, 500.0, 101), [(2, 1e-4, 0.0)])
    >>> amplitude, phase = plot_bode(res, 2, "x")
    >>> amplitude.get_yscale()
    'log'
    """
    import matplotlib.pyplot as plt

    if axes is None:
        _, axes = plt.subplots(2, 1, sharex=True, figsize=(6.5, 5.5))
    ax_a, ax_p = axes
    w = response.speeds
    if direction is None:
        amp, label = response.major_axis(node), f"node {node}, major semi-axis"
    else:
        amp, label = response.amplitude(node, direction), f"node {node}, {direction}"
        ax_p.plot(w, np.degrees(np.unwrap(response.phase(node, direction))), color="tab:blue")
    ax_a.semilogy(w, amp, color="tab:blue", label=label)
    for peak in response.peaks(node, direction):
        text = f"{peak.speed:.4g} rad/s" + (
            f", AF {peak.amplification_factor:.3g}"
            if np.isfinite(peak.amplification_factor)
            else ""
        )
        ax_a.annotate(text, (peak.speed, peak.amplitude), fontsize="small", ha="center",
                      xytext=(0, 6), textcoords="offset points")  # fmt: skip
    ax_a.set_ylabel("amplitude (m)")
    ax_a.legend(fontsize="small")
    ax_a.grid(True, which="both", alpha=0.3)
    ax_p.set_ylabel("phase (deg)")
    ax_p.set_xlabel("speed (rad/s)")
    ax_p.grid(True, alpha=0.3)
    return ax_a, ax_p


def plot_polar(response: Any, node: int, direction: str = "x", *, ax: Any = None) -> Any:
    """The complex amplitude ``X`` of one dof traced over the speeds (polar / Nyquist plot,
    speed increasing along the curve, its ends marked); returns the Axes.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import numpy as np
    >>> from duhamel.rotor import STEEL, Bearing, Disk, Rotor, Shaft, plot_polar
    >>> rotor = Rotor([Shaft(0.25, 0.05, material=STEEL)] * 4, [Disk(2, 30.0, 0.6, 0.3)],
    ...               [Bearing(0, 1e7, 1e7), Bearing(4, 1e7, 1e7)], zeta=0.02)
    >>> res = rotor.unbalance_response(np.linspace(100.0, 500.0, 101), [(2, 1e-4, 0.0)])
    >>> plot_polar(res, 2, "y").get_title()
    'node 2, y'
    """
    import matplotlib.pyplot as plt

    ax = ax if ax is not None else plt.subplots()[1]
    x = response.response[:, int(response.dof(node, direction))]
    ax.plot(x.real, x.imag, color="tab:blue")
    ax.plot(x.real[:1], x.imag[:1], "o", color="tab:green", label=f"{response.speeds[0]:.4g} rad/s")
    ax.plot(
        x.real[-1:], x.imag[-1:], "s", color="tab:red", label=f"{response.speeds[-1]:.4g} rad/s"
    )
    ax.axhline(0.0, color="k", lw=0.5)
    ax.axvline(0.0, color="k", lw=0.5)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("Re X (m)")
    ax.set_ylabel("Im X (m)")
    ax.set_title(f"node {node}, {direction}")
    ax.legend(fontsize="small")
    return ax


def spectrogram(
    t: ArrayLike, x: ArrayLike, speed: Any, *, window: float | None = None, overlap: float = 0.75
) -> tuple[Any, Any, Any, Any]:
    """Short-time amplitude spectra of a signal `x` sampled at the uniform times `t`, with
    the spin speed at each window's centre: ``(times, speeds, frequencies, amplitudes)``
    (rad/s; amplitudes of shape ``(n_frequencies, n_times)``, in the units of `x`, peak
    amplitude of a sinusoid). `speed` is a number or a :mod:`duhamel.speed` law; `window`
    the window length (s; default an eighth of the record), Hann-windowed.

    Examples
    --------
    >>> import numpy as np
    >>> from duhamel.rotor import spectrogram
    >>> t = np.arange(0.0, 2.0, 1e-3)
    >>> times, speeds, freqs, amps = spectrogram(t, 3e-6 * np.sin(200.0 * t), 400.0)
    >>> k = np.unravel_index(np.argmax(amps), amps.shape)
    >>> round(float(freqs[k[0]])), round(float(amps[k]) * 1e6, 1), float(speeds[0])
    (201, 3.0, 400.0)
    """
    import scipy.signal

    ts, xs = np.asarray(t, dtype=float), np.asarray(x, dtype=float)
    if ts.ndim != 1 or xs.shape != ts.shape or ts.size < 16:
        raise ValueError("`t` and `x` must be 1-D of the same length (at least 16 samples)")
    dt = float(ts[1] - ts[0])
    length = (ts[-1] - ts[0]) / 8.0 if window is None else float(window)
    nperseg = max(16, min(ts.size, round(length / dt)))
    f, tc, Z = scipy.signal.stft(
        xs - xs.mean(), fs=1.0 / dt, window="hann", nperseg=nperseg,
        noverlap=int(overlap * nperseg), boundary=None, padded=False,
    )  # fmt: skip
    tc = tc + ts[0]
    law = getattr(speed, "omega", None)
    w = np.asarray(law(tc), dtype=float) if law is not None else np.full(tc.size, float(speed))
    return tc, w, 2.0 * np.pi * f, 2.0 * np.abs(Z)


def plot_spectrogram(
    t: ArrayLike,
    x: ArrayLike,
    speed: Any,
    *,
    orders: tuple[float, ...] = (0.5, 1.0),
    window: float | None = None,
    ax: Any = None,
) -> Any:
    """A run-up's spectrogram against the spin speed (a waterfall seen from above):
    amplitude (log colour scale) over speed and frequency, with the lines of the given
    `orders` (frequency = order x speed). Returns the Axes.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import numpy as np, duhamel
    >>> from duhamel.rotor import plot_spectrogram
    >>> law = duhamel.speed.LinearRunUp(omega0=100.0, omega1=300.0, t1=2.0)
    >>> t = np.arange(0.0, 2.0, 1e-3)
    >>> plot_spectrogram(t, np.sin(law.theta(t)), law).get_ylabel()
    'frequency (rad/s)'
    """
    import matplotlib.pyplot as plt
    from matplotlib.colors import LogNorm

    _, w, f, A = spectrogram(t, x, speed, window=window)
    ax = ax if ax is not None else plt.subplots(figsize=(6.5, 4.5))[1]
    top = float(A.max()) if A.size and A.max() > 0 else 1.0
    mesh = ax.pcolormesh(w, f, np.maximum(A, 1e-6 * top), shading="nearest",
                         norm=LogNorm(vmin=1e-5 * top, vmax=top), cmap="viridis")  # fmt: skip
    plt.colorbar(mesh, ax=ax, label="amplitude (units of x)")
    for order in orders:
        ax.plot(w, order * w, "--", color="w", lw=1)
        ax.annotate(f"{order:g}x", (w[-1], order * w[-1]), color="w", fontsize="small",
                    ha="right", va="bottom")  # fmt: skip
    ax.set_ylim(0.0, 1.5 * max(orders) * float(w.max()))
    ax.set_xlabel("speed (rad/s)")
    ax.set_ylabel("frequency (rad/s)")
    return ax

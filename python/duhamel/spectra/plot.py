"""Plots and labelled arrays of response spectra (matplotlib and xarray, imported on use)."""

from __future__ import annotations

from typing import Any

import numpy as np

from duhamel.constants import STANDARD_GRAVITY

_LABELS = {
    "sd": ("Sd [m]", 1.0),
    "sv": ("Sv [m/s]", 1.0),
    "sa": ("Sa [g]", 1.0 / STANDARD_GRAVITY),
    "psv": ("PSV [m/s]", 1.0),
    "psa": ("PSA [g]", 1.0 / STANDARD_GRAVITY),
}


def plot_spectrum(spec: Any, quantity: str, tripartite: bool, ax: Any) -> Any:
    """One line per motion and damping of `quantity` against period, log axes; the
    tripartite form draws psv with lines of constant sd and psa."""
    try:
        import matplotlib.pyplot as plt
    except ImportError as exc:  # pragma: no cover - matplotlib is in the test extras
        raise ImportError("plotting needs matplotlib: pip install 'duhamel[plot]'") from exc
    if tripartite:
        quantity = "psv"
    if quantity not in _LABELS:
        raise ValueError(f"`quantity` must be one of {sorted(_LABELS)}, got {quantity!r}")
    label, scale = _LABELS[quantity]
    if ax is None:
        _, ax = plt.subplots(figsize=(6.5, 4.5))
    keep = spec.periods > 0.0
    values = getattr(spec, quantity)
    for i, name in enumerate(spec.names):
        for j, zeta in enumerate(spec.damping):
            tag = f"{name or f'motion {i}'}, {100 * zeta:g} %"
            ax.plot(spec.periods[keep], scale * values[i, j, keep], label=tag)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("Period [s]")
    ax.set_ylabel(label)
    if tripartite:
        _tripartite_grid(ax, spec.periods[keep])
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize="small")
    return ax


def _tripartite_grid(ax: Any, periods: np.ndarray) -> None:
    """Lines of constant sd (slope -1: psv = 2 pi sd / T) and of constant psa (slope +1:
    psv = psa T / 2 pi) across the axes, one per decade, labelled."""
    ax.autoscale(False)
    t = np.array([periods.min(), periods.max()])
    lo, hi = ax.get_ylim()
    for e in range(-6, 3):
        sd = 10.0**e
        ax.plot(t, 2 * np.pi * sd / t, color="0.7", lw=0.6, zorder=0)
        psa = 10.0**e * STANDARD_GRAVITY
        ax.plot(t, psa * t / (2 * np.pi), color="0.7", lw=0.6, ls="--", zorder=0)
    ax.set_ylim(lo, hi)
    ax.set_title("tripartite: solid lines Sd = 10^k m, dashed PSA = 10^k g", fontsize="small")


def dataset(spec: Any, names: tuple[str, ...]) -> Any:
    """The spectra as an ``xarray.Dataset`` over (motion, damping, period)."""
    try:
        import xarray as xr
    except ImportError as exc:
        raise ImportError(
            "to_xarray needs xarray: pip install 'duhamel[xarray]' (or pip install xarray)"
        ) from exc
    dims = ("motion", "damping", "period")
    units = {"sd": "m", "sv": "m/s", "sa": "m/s^2", "psv": "m/s", "psa": "m/s^2"}
    coords = {"motion": list(spec.names), "damping": spec.damping, "period": spec.periods}
    data = {n: (dims, getattr(spec, n), {"units": units[n]}) for n in names}
    ds = xr.Dataset(data, coords=coords)
    ds["period"].attrs["units"] = "s"
    return ds

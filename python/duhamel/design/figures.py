"""The figures of a study's report (matplotlib, Agg), each returned as PNG bytes: the suite's
spectra against the target, drift profiles, isolator hysteresis and orbits, the energy
balance and the floor spectra (:func:`figures`)."""

from __future__ import annotations

import io
from typing import Any

import numpy as np

from duhamel.constants import STANDARD_GRAVITY

__all__ = ["FIGURES", "figures", "governing_run"]

#: The report's figures: id -> caption.
FIGURES = {
    "figure-spectra": "The scaled suite's spectra (RotD100 of the pairs), their mean and the "
    "target, the scaling range shaded",
    "figure-drift": "Storey drift ratios per record (the larger orientation, thin) and the "
    "suite mean (thick), per model, against the limits",
    "figure-hysteresis": "Isolator force against deformation in the governing run",
    "figure-orbits": "Isolator displacements in the governing run (in plan for a 3-D model)",
    "figure-energy": "Energy balance of the governing run",
    "figure-floor-spectra": "Floor spectra (5 %), the suite mean per level, governing model",
}


def _subplots(*args: Any, figsize: tuple[float, float], **kwargs: Any) -> tuple[Any, Any]:
    """A figure outside pyplot (no global state: safe in threads, no window)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize)
    return fig, fig.subplots(*args, **kwargs)


def _png(fig: Any) -> bytes:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=80)
    return buf.getvalue()


def governing_run(study: Any) -> tuple[int, int, int]:
    """(model, record, orientation) indices of the run with the largest isolator
    displacement, in the model that governs it."""
    ds = study.dataset
    values = ds["isolator_displacement_max"].values
    return tuple(int(i) for i in np.unravel_index(int(np.argmax(values)), values.shape))


def _spectra(study: Any) -> bytes:
    fig, ax = _subplots(figsize=(8, 4.5))
    if study.scaled is not None:
        study.scaled.plot(ax=ax, periods=np.geomspace(0.05, 8.0, 80))
    else:
        ax.text(0.5, 0.5, "no target spectrum (an unscaled Suite)", ha="center")
    fig.tight_layout()
    return _png(fig)


def _drift(study: Any) -> bytes:
    from duhamel.design.asce7 import history

    stats = study.statistics
    models = list(stats)
    fig, axes = _subplots(1, len(models), figsize=(3.6 * len(models) + 1, 4.5), sharey=True)
    axes = np.atleast_1d(axes)
    storeys = np.arange(1, len(study.building.levels))
    limit_iso = 0.020
    limit_16 = 2.0 * history.allowable_drift(study.risk_category, study.structure)
    for ax, model in zip(axes, models, strict=True):
        s = stats[model]["storey_drift_ratio"]
        for row in s["per_record"]:
            ax.plot(100 * row, storeys, color="0.65", lw=0.8, marker=".")
        ax.plot(100 * s["design"], storeys, "k", lw=2.0, marker="o", label="suite mean")
        ax.axvline(100 * limit_iso, color="C3", ls="--", label="17.6.4.4: 2.0 %")
        if limit_16 != limit_iso:
            ax.axvline(100 * limit_16, color="C1", ls=":", label=f"16.4.1.2: {100 * limit_16:g} %")
        ax.set_title(f"{model} properties", fontsize="small")
        ax.set_xlabel("storey drift ratio [%]")
        ax.set_xlim(0.0, 110 * max(limit_iso, float(s["max"].max())))
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("storey above the base level")
    axes[0].set_yticks(storeys)
    axes[0].legend(fontsize="x-small", loc="lower right")
    fig.tight_layout()
    return _png(fig)


def _hysteresis(study: Any) -> bytes:
    ds = study.dataset
    m, r, o = governing_run(study)
    u = ds["isolator_deformation"].values[m, r, o]
    f = ds["isolator_force"].values[m, r, o]
    fig, ax = _subplots(figsize=(6.5, 4.5))
    for k, iso in enumerate(ds["isolator"].values):
        ax.plot(u[:, k, 0], f[:, k, 0] / 1e3, lw=0.9, label=f"isolator {iso}")
    ax.set_xlabel("deformation along x [m]")
    ax.set_ylabel("force [kN]")
    ax.set_title(_run_name(study, m, r, o), fontsize="small")
    ax.grid(alpha=0.3)
    ax.legend(fontsize="x-small")
    fig.tight_layout()
    return _png(fig)


def _run_name(study: Any, m: int, r: int, o: int) -> str:
    ds = study.dataset
    return (
        f"{ds['record'].values[r]}, {ds['orientation'].values[o]:g} deg, "
        f"{ds['model'].values[m]} properties"
    )


def _orbits(study: Any) -> bytes:
    ds = study.dataset
    m, r, o = governing_run(study)
    u = ds["isolator_deformation"].values[m, r, o]
    t = ds["time"].values
    fig, ax = _subplots(figsize=(6.5, 4.5))
    for k, iso in enumerate(ds["isolator"].values):
        if u.shape[2] > 1:
            ax.plot(u[:, k, 0], u[:, k, 1], lw=0.8, label=f"isolator {iso}")
        else:
            ax.plot(t, u[:, k, 0], lw=0.8, label=f"isolator {iso}")
    if u.shape[2] > 1:
        ax.set_aspect("equal")
        ax.set_xlabel("u_x [m]")
        ax.set_ylabel("u_y [m]")
    else:
        ax.set_xlabel("t [s]")
        ax.set_ylabel("isolator displacement [m]")
    ax.set_title(_run_name(study, m, r, o), fontsize="small")
    ax.grid(alpha=0.3)
    ax.legend(fontsize="x-small")
    fig.tight_layout()
    return _png(fig)


def _energy(study: Any) -> bytes:
    ds = study.dataset
    m, r, o = governing_run(study)
    e = ds["energy"].values[m, r, o] / 1e3
    t = ds["time"].values
    fig, ax = _subplots(figsize=(8, 4))
    ax.stackplot(t, e[:, 1], e[:, 2], e[:, 3], labels=list(ds["term"].values[1:]), alpha=0.8)
    ax.plot(t, e[:, 0], "k", lw=1.0, label="input")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("energy [kJ]")
    ax.set_title(_run_name(study, m, r, o), fontsize="small")
    ax.legend(loc="upper left", fontsize="x-small")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return _png(fig)


def _floor_spectra(study: Any) -> bytes:
    ds = study.dataset
    m, _, _ = governing_run(study)
    sa = ds["floor_spectrum"].values[m].max(axis=1).mean(axis=0) / STANDARD_GRAVITY
    fig, ax = _subplots(figsize=(7, 4.5))
    for level in range(sa.shape[0]):
        name = "base level" if level == 0 else f"level {level}"
        ax.plot(ds["period"].values, sa[level], lw=1.2, label=name)
    ax.set_xscale("log")
    ax.set_xlabel("period [s]")
    ax.set_ylabel("Sa [g]")
    ax.set_title(f"{ds['model'].values[m]} properties", fontsize="small")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize="x-small")
    fig.tight_layout()
    return _png(fig)


def figures(study: Any) -> dict[str, bytes]:
    """Every figure of :data:`FIGURES` as PNG bytes, by id."""
    makers = {
        "figure-spectra": _spectra,
        "figure-drift": _drift,
        "figure-hysteresis": _hysteresis,
        "figure-orbits": _orbits,
        "figure-energy": _energy,
        "figure-floor-spectra": _floor_spectra,
    }
    return {name: make(study) for name, make in makers.items()}

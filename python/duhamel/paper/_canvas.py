"""Where the paper's figures go: their file names, resolution and matplotlib's Figure class
(imported only when a figure is drawn)."""

from __future__ import annotations

from typing import Any

__all__ = ["DPI", "FIGURES", "figure_class"]

#: File name of each figure.
FIGURES = {
    "fig1": "fig1_spectral_radius.png",
    "fig2": "fig2_eq25_spectral_radius.png",
    "fig3": "fig3_duffing_error_phase_plane.png",
    "fig4": "fig4_pendulum_decaying_mass.png",
    "fig5": "fig5_mass_ratio.png",
    "fig6": "fig6_displacement_velocity.png",
    "fig7": "fig7_phase_plane.png",
    "fig8": "fig8_convergence.png",
    "fig9": "fig9_rotor_model.png",
    "fig10": "fig10_orbit_left_bearing.png",
    "fig11": "fig11_orbit_right_bearing.png",
    "fig12": "fig12_orbit_left_rotor.png",
    "fig13": "fig13_orbit_right_rotor.png",
}

DPI = 110


def figure_class() -> Any:
    """``matplotlib.figure.Figure``, or an ImportError saying how to install matplotlib.

    Examples
    --------
    >>> from duhamel.paper.figures import figure_class
    >>> figure_class().__name__
    'Figure'
    """
    try:
        from matplotlib.figure import Figure
    except ImportError as exc:
        raise ImportError(
            "the paper's figures need matplotlib: pip install 'duhamel[plot]'"
        ) from exc
    return Figure

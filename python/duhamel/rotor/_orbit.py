"""Elliptical orbits of harmonic motion as sums of two circular ones."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["circular_parts"]


def circular_parts(x: Any, y: Any) -> tuple[NDArray, NDArray]:
    """Radii ``|F|``, ``|B|`` of the forward and backward circular orbits whose sum is the
    elliptical orbit ``(Re(x e^{iwt}), Re(y e^{iwt}))``: ``F = (x + i y) / 2``, ``B = (conj x
    + i conj y) / 2``; the semi-axes are ``|F| + |B|`` and ``||F| - |B||``."""
    x, y = np.asarray(x), np.asarray(y)
    return np.abs(x + 1j * y) / 2.0, np.abs(np.conj(x) + 1j * np.conj(y)) / 2.0

"""What a run returns: the :class:`Solution` with its :class:`SolveStats` and
:class:`ModalHistory` (:mod:`.solution`), the structural outputs — element histories,
absolute accelerations, drifts (:mod:`.structural`) — and the labelled views, xarray and
pandas (:mod:`.labelled`, imported on use)."""

from __future__ import annotations

from duhamel.results.solution import ModalHistory, Solution, SolveStats
from duhamel.results.structural import ElementHistory

__all__ = ["ElementHistory", "ModalHistory", "Solution", "SolveStats"]

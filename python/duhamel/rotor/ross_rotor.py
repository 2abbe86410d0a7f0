"""A ROSS model with the analyses of a native :class:`~duhamel.rotor.Rotor`
(``from_ross(...).rotor``): modes, Campbell diagram, critical speeds, frequency and unbalance
responses, Level I stability, critical speed map, all on ROSS's lateral matrices re-evaluated
at each speed (``K(frequency=speed)``, ``C(frequency=speed)``, as ROSS's ``run_modal``,
``run_campbell`` and ``run_freq_response`` evaluate them)."""

from __future__ import annotations

import inspect
from functools import lru_cache
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel.rotor._analyses import RotorAnalyses
from duhamel.rotor._ross_matrices import COUPLING_RTOL, RossDofs
from duhamel.rotor._speed import constant_speed
from duhamel.rotor.assembly import RotorMatrices
from duhamel.rotor.modes import Modes

__all__ = ["RossRotor"]


def _parameters(method: Any) -> tuple[str, ...]:
    try:
        return tuple(inspect.signature(method).parameters)
    except (TypeError, ValueError):  # no method, or a builtin without a signature
        return ()


class RossRotor(RotorAnalyses):
    """A ROSS ``Rotor``'s lateral model with a native :class:`~duhamel.rotor.Rotor`'s analyses.

    Made by :attr:`RossModel.rotor <duhamel.rotor.RossModel.rotor>`; nodes and dofs are
    ROSS's (``dof(node, direction)`` is :class:`~duhamel.rotor.RossDofs`, the labels ROSS's
    ``"x_3"``, ``"alpha_3"``...).

    Parameters
    ----------
    source : ross.Rotor or None
        The ROSS model, asked for ``K`` and ``C`` at each speed; None: the fixed `matrices`.
    dofs : RossDofs
    matrices : RotorMatrices
        The matrices :func:`~duhamel.rotor.from_ross` read (used when `source` is None).

    Examples
    --------
    Anything with ROSS's interface (here one rigid disk on two springs):

    >>> import numpy as np
    >>> from duhamel.rotor import from_ross
    >>> class Disk:
    ...     dof_global_index = {"x_0": 0, "y_0": 1, "alpha_0": 2, "beta_0": 3}
    >>> class Toy:
    ...     elements = [Disk()]
    ...     def M(self, f=None): return np.diag([2.0, 2.0, 0.1, 0.1])
    ...     def K(self, f): return np.diag([8e4, 8e4, 1e4, 1e4])
    ...     def C(self, f): return np.zeros((4, 4))
    ...     def G(self): return np.zeros((4, 4))
    >>> model = from_ross(Toy(), speed=0.0)
    >>> np.round(model.rotor.natural_frequencies(0.0), 6).tolist()
    [200.0, 200.0, 316.227766, 316.227766]
    """

    journals: tuple[Any, ...] = ()
    has_speed_dependent_bearings = True

    def __init__(self, source: Any, dofs: RossDofs, matrices: RotorMatrices) -> None:
        self.source = source
        self.dofs = dofs
        self._fixed = matrices
        self.shafts = tuple(getattr(source, "shaft_elements", ()) or ())
        self._at = lru_cache(maxsize=64)(self._read)
        keep = dofs.ross_index
        dropped = np.setdiff1d(np.arange(dofs.n_ross), keep)
        self._blocks = (np.ix_(keep, keep), np.ix_(keep, dropped), np.ix_(dropped, keep))
        self._speed_kw = {
            name: "speed" in _parameters(getattr(source, name, None)) for name in ("M", "K", "C")
        }

    @property
    def n_dof(self) -> int:  # type: ignore[override]
        """Number of lateral dofs."""
        return self.dofs.n_dof

    @property
    def dof_labels(self) -> tuple[str, ...]:  # type: ignore[override]
        """ROSS's name of each dof (``"x_0"``, ``"y_0"``, ``"alpha_0"``, ``"beta_0"``...)."""
        return self.dofs.labels

    @property
    def nodes_z(self) -> NDArray[np.float64]:  # type: ignore[override]
        """Axial positions of ROSS's nodes (``nodes_pos``)."""
        return np.asarray(getattr(self.source, "nodes_pos", []), dtype=float)

    def dof(self, node: int, direction: str) -> int:
        """System dof of ROSS node `node` (:meth:`RossDofs.index`)."""
        return self.dofs.index(node, direction)

    def _read(self, w: float) -> RotorMatrices:
        """ROSS's ``M``, ``K``, ``C`` at ``frequency = speed = w`` (``G`` from from_ross),
        the lateral block, with from_ross's check that nothing couples it to the rest."""
        keep, cross, back = self._blocks
        out = []
        for name in ("M", "K", "C"):
            method = getattr(self.source, name)
            a = np.asarray(method(w, speed=w) if self._speed_kw[name] else method(w), dtype=float)
            if a.shape != (self.dofs.n_ross, self.dofs.n_ross):
                raise ValueError(f"ROSS's `{name}` at {w:g} rad/s has shape {a.shape}")
            c = max(np.abs(a[cross]).max(initial=0.0), np.abs(a[back]).max(initial=0.0))
            if c > COUPLING_RTOL * float(np.max(np.abs(a))):
                raise ValueError(
                    f"ROSS's `{name}` at {w:g} rad/s couples the lateral dofs to axial or "
                    "torsional ones; from_ross keeps only the lateral dofs"
                )
            out.append(a[keep])
        M, K, C = out
        return RotorMatrices((M + M.T) / 2.0, K, C, self._fixed.G)

    def matrices(self, speed: float = 0.0) -> RotorMatrices:  # type: ignore[override]
        """ROSS's lateral ``(M, K, C, G)`` with ``K`` and ``C`` at ``frequency = speed``."""
        w = constant_speed(speed)
        if self.source is None:
            return self._fixed
        return self._at(w)

    def modes(self, speed: float = 0.0, n: int | None = None) -> Modes:
        """:meth:`Rotor.modes <duhamel.rotor.Rotor.modes>` (needs 4 dofs at every node;
        models with 2-dof point-mass nodes are refused)."""
        labels = self.dofs.labels
        regular = len(labels) % 4 == 0 and all(
            labels[4 * k + d] == f"{name}_{labels[4 * k].split('_')[1]}"
            for k in range(len(labels) // 4)
            for d, name in enumerate(("x", "y", "alpha", "beta"))
        )
        if not regular:
            raise ValueError(
                "modes need (x, y, alpha, beta) at every node; this ROSS model has nodes "
                "with only x and y (point masses): use its matrices directly"
            )
        return super().modes(speed, n)

    def __repr__(self) -> str:
        return f"RossRotor(n_dof={self.n_dof}, source={type(self.source).__name__})"

"""The result of :func:`duhamel.solve`."""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["ModalHistory", "Solution", "SolveStats"]


@dataclass(frozen=True)
class ModalHistory:
    """Modal coordinates of the response (mass-normalised modes).

    The time loop stores the modal coordinates and velocities; the modal accelerations follow
    exactly from the modal equations, ``a = p(t) - c v - omega^2 q``, and are computed on
    first access.

    Attributes
    ----------
    q, v : ndarray, shape (n_saved, n_modes)
        Modal coordinates and velocities.
    omega : ndarray, shape (n_modes,)
        Natural frequencies of the retained modes (rad/s).
    c : ndarray, shape (n_modes,)
        Modal damping ``2 zeta omega`` per unit modal mass.
    p : ndarray, shape (n_saved, n_modes)
        Modal load at the saved instants (the value just after each instant); computed on
        first access.
    a : ndarray, shape (n_saved, n_modes)
        Modal accelerations; computed on first access.
    """

    q: NDArray[np.float64]
    v: NDArray[np.float64]
    omega: NDArray[np.float64]
    c: NDArray[np.float64]
    load_values: NDArray[np.float64] = field(repr=False)
    patterns: NDArray[np.float64] = field(repr=False)
    forcing: NDArray[np.float64] | None = field(default=None, repr=False)
    pseudo: NDArray[np.float64] | None = field(default=None, repr=False)

    @cached_property
    def p(self) -> NDArray[np.float64]:
        """Modal external load at the saved instants."""
        p = self.load_values @ self.patterns.T
        return p if self.forcing is None else p + self.forcing

    @cached_property
    def pseudo_force(self) -> NDArray[np.float64]:
        """Modal pseudo-force (elements, couplings, mass change) at the saved states."""
        return np.zeros_like(self.q) if self.pseudo is None else self.pseudo

    @cached_property
    def a(self) -> NDArray[np.float64]:
        """Modal accelerations from the modal equations of motion."""
        return self.p + self.pseudo_force - self.c * self.v - self.omega**2 * self.q


@dataclass(frozen=True)
class SolveStats:
    """Cost of a run.

    Attributes
    ----------
    steps : int
        Time steps taken.
    wall_time : float
        Seconds spent in the time loop (Rust, GIL released).
    total_time : float
        Seconds for the whole call, modal analysis and back-transformation included.
    modes : int
        Modal coordinates integrated (0 for the direct integrators, which step the physical
        coordinates).
    newton_iterations : int
        Newton iterations over the run (nonlinear problems).
    closed_form_steps : int
        Steps solved by the closed-form cubic (single-mode polynomial problems).
    factorizations : int
        Direct integrators: LU factorisations of the iteration (effective stiffness)
        matrix over the run; 1 for a linear problem with constant mass (the mass matrix,
        factorised once for the initial acceleration, is not counted). 0 for the
        semi-analytic integrator.
    """

    steps: int
    wall_time: float
    total_time: float
    modes: int
    newton_iterations: int = 0
    closed_form_steps: int = 0
    factorizations: int = 0

    @property
    def mode_steps_per_second(self) -> float:
        """Throughput of the time loop: ``steps * modes / wall_time``."""
        return self.steps * self.modes / self.wall_time if self.wall_time > 0 else float("inf")


@dataclass(frozen=True)
class Solution:
    """Response history of a structural model.

    Attributes
    ----------
    t : ndarray, shape (n_saved,)
        Saved times.
    x, v, a : ndarray, shape (n_saved, n_out)
        Displacements, velocities and accelerations of the output degrees of freedom
        (all, or those passed as ``dofs``).
    dofs : ndarray of int, shape (n_out,)
        Which degrees of freedom the columns of `x`, `v`, `a` are.
    modal : ModalHistory or None
        The modal history the physical response was recovered from (semi-analytic
        integrator); None for the direct integrators, which step the physical coordinates.
    stats : SolveStats
        Steps and timings.

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> sys = duhamel.System(np.eye(1), np.eye(1))
    >>> sol = duhamel.solve(sys, duhamel.Semianalytic(), t_end=1.0, dt=0.1, x0=[1.0])
    >>> sol.x.shape, sol.t[-1]
    ((11, 1), np.float64(1.0))
    """

    t: NDArray[np.float64]
    x: NDArray[np.float64]
    v: NDArray[np.float64]
    a: NDArray[np.float64]
    dofs: NDArray[np.int64]
    modal: ModalHistory | None
    stats: SolveStats
    meta: dict[str, Any] = field(default_factory=dict)

    def __repr__(self) -> str:
        return (
            f"Solution(n_saved={self.t.size}, dofs={self.dofs.size}, modes={self.stats.modes}, "
            f"t=[{self.t[0] if self.t.size else 0.0:g}, {self.t[-1] if self.t.size else 0.0:g}])"
        )

    def plot(self, dofs: Any = None, quantity: str = "x", ax: Any = None) -> Any:
        """Plot the history of some output degrees of freedom with matplotlib.

        Parameters
        ----------
        dofs : sequence of int, optional
            Degrees of freedom (model numbering) to draw; default: up to the first four
            output dofs.
        quantity : {"x", "v", "a"}
            Displacement, velocity or acceleration.
        ax : matplotlib Axes, optional
            Where to draw; a new figure otherwise.

        Returns
        -------
        matplotlib.axes.Axes

        Examples
        --------
        >>> import numpy as np, duhamel
        >>> sys = duhamel.System(np.eye(1), np.eye(1))
        >>> sol = duhamel.solve(sys, duhamel.Semianalytic(), t_end=6.0, dt=0.1, x0=[1.0])
        >>> ax = sol.plot()
        """
        try:
            import matplotlib.pyplot as plt
        except ImportError as exc:  # pragma: no cover - depends on the install
            raise ImportError("plotting needs matplotlib: pip install 'duhamel[plot]'") from exc
        if quantity not in ("x", "v", "a"):
            raise ValueError(f"`quantity` must be 'x', 'v' or 'a', got {quantity!r}")
        data = getattr(self, quantity)
        wanted = list(self.dofs[:4]) if dofs is None else list(np.atleast_1d(dofs))
        cols = []
        for d in wanted:
            hits = np.flatnonzero(self.dofs == d)
            if hits.size == 0:
                raise ValueError(
                    f"`dofs`: dof {d} is not among the saved dofs {self.dofs.tolist()}"
                )
            cols.append(int(hits[0]))
        if ax is None:
            _, ax = plt.subplots(figsize=(8, 4))
        label = {"x": "displacement", "v": "velocity", "a": "acceleration"}[quantity]
        for d, c in zip(wanted, cols, strict=True):
            ax.plot(self.t, data[:, c], label=f"dof {d}")
        ax.set_xlabel("t")
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
        ax.legend()
        return ax

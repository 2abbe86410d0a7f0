"""Structural outputs of a run: element histories (hysteresis loops), absolute accelerations
of base-excited systems and inter-storey drifts."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["ElementHistory", "drifts", "element_histories"]


@dataclass(frozen=True, eq=False)
class ElementHistory:
    """One element along a run: its local displacements, velocities and restoring force.

    A hysteretic element's force is the one of the path the run followed (its committed
    state at each saved instant).

    Attributes
    ----------
    element : duhamel.elements.Element
        The element, as added to the system.
    t : ndarray, shape (n_t,)
        Saved times.
    x, v : ndarray, shape (n_t, n_local)
        Displacements and velocities of the element's degrees of freedom, in its own order
        (``(i, j)`` for a two-node element).
    force : ndarray, shape (n_t, n_local)
        The restoring force the element applies at those dofs (left-hand side: the force on
        the structure is its negative); ``force[:, 1] = -force[:, 0]`` for a two-node
        element.

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> system = duhamel.System(np.eye(1), 4.0 * np.eye(1), zeta=0.02)
    >>> system.add(duhamel.elements.Cubic(0, k3=1.0))
    System(n_dof=1, damping='zeta', loads=0, elements=1)
    >>> sol = duhamel.solve(system, duhamel.Semianalytic(), t_end=1.0, dt=0.01, x0=[0.1])
    >>> spring = sol.elements[0]
    >>> bool(np.allclose(spring.force[:, 0], spring.x[:, 0] ** 3))
    True
    """

    element: Any
    t: NDArray[np.float64]
    x: NDArray[np.float64]
    v: NDArray[np.float64]
    force: NDArray[np.float64]

    @property
    def deformation(self) -> NDArray[np.float64]:
        """The element's deformation: ``x_i - x_j`` for a two-node element, ``x_i`` for a
        grounded one (shape ``(n_t,)``); the local displacements ``x`` otherwise."""
        if self.x.shape[1] == 2 and getattr(self.element, "j", None) is not None:
            return self.x[:, 0] - self.x[:, 1]
        if self.x.shape[1] == 1:
            return self.x[:, 0]
        return self.x

    @property
    def axial_force(self) -> NDArray[np.float64]:
        """The force along the deformation of a one- or two-node element (the force on
        dof ``i``, shape ``(n_t,)``); the local forces otherwise."""
        if self.x.shape[1] == 1 or getattr(self.element, "j", None) is not None:
            return self.force[:, 0]
        return self.force

    def plot(self, ax: Any = None, dof: int = 0) -> Any:
        """Force against deformation (the hysteresis loop) on matplotlib axes.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Axes to draw on (new figure otherwise).
        dof : int
            For an element with several independent local dofs (a bidirectional isolator):
            which one.

        Returns
        -------
        matplotlib.axes.Axes
        """
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots()
        u, f = self.deformation, self.axial_force
        if u.ndim == 2:
            u, f = u[:, dof], f[:, dof]
        ax.plot(u, f)
        ax.set_xlabel("deformation")
        ax.set_ylabel("force")
        ax.set_title(type(self.element).__name__)
        return ax


def element_histories(
    elements: Sequence[Any],
    t: NDArray[np.float64],
    result: Any,
    kept: int,
    linear: Sequence[Any] = (),
) -> tuple[ElementHistory, ...]:
    """The histories of `elements` (the system's force elements, couplings left out, in
    order) from a run's saved element rows; empty when the route kept none. `linear`: per
    element, the linear part the run's background took over (added back to the force)."""
    if result.element_force is None or not elements:
        return ()
    xs, vs, fs = (
        np.asarray(a)[:kept] for a in (result.element_x, result.element_v, result.element_force)
    )
    widths = list(result.element_widths)
    if len(widths) != len(elements):
        return ()
    out, at = [], 0
    for element, width in zip(elements, widths, strict=True):
        cut = slice(at, at + width)
        force = fs[:, cut]
        part = linear[len(out)] if len(out) < len(linear) else None
        if part is not None:
            force = force + part.force(xs[:, cut], vs[:, cut])
        out.append(ElementHistory(element, t, xs[:, cut], vs[:, cut], force))
        at += width
    return tuple(out)


def drifts(
    x: NDArray[np.float64],
    dofs: NDArray[np.int64],
    floors: Sequence[Any],
    heights: Sequence[float] | float | None = None,
) -> NDArray[np.float64]:
    """Inter-storey drifts ``x[floor k] - x[floor k-1]`` (the first storey's against the
    ground), as ratios when `heights` are given; `x` holds the dofs `dofs`. A floor given as
    a sequence of dofs (one per column line; every floor the same number, or one) gives, per
    storey and instant, the drift of largest magnitude over the column lines (signed)."""
    from duhamel.results.forces import columns, floor_groups

    groups = floor_groups(floors)
    lines = max(len(g) for g in groups)
    if any(len(g) not in (1, lines) for g in groups):
        raise ValueError(
            "`floors`: every floor must list the same number of column lines (or one dof), "
            f"got {[len(g) for g in groups]}"
        )
    u = np.stack(
        [x[:, columns(dofs, g, "floors")] * np.ones(lines) for g in groups], axis=1
    )  # (n_t, n_floors, lines)
    below = np.concatenate([np.zeros((u.shape[0], 1, lines)), u[:, :-1]], axis=1)
    d = u - below
    pick = np.argmax(np.abs(d), axis=2)
    out = np.take_along_axis(d, pick[:, :, None], axis=2)[:, :, 0]
    if heights is None:
        return out
    from duhamel.results.forces import real_array

    h = real_array(heights, "heights")
    if h.ndim > 1 or h.size not in (1, len(groups)):
        raise ValueError(
            f"`heights` must be one storey height or one per floor ({len(groups)}), got shape "
            f"{h.shape}"
        )
    h = np.broadcast_to(h, (len(groups),))
    if not np.all(np.isfinite(h)) or np.any(h <= 0):
        raise ValueError(f"`heights` must be positive storey heights, got {heights!r}")
    return out / h

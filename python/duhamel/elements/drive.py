"""An element driven through a deformation history, as OpenSees' ``testUniaxialMaterial``
with ``setStrain`` drives a material: at each instant the element is evaluated at the state
and its internal variables committed there. For calibration, checking against a reference,
and effective properties (the loop at an amplitude)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel import _core
from duhamel._engine.validate import as_float_array

__all__ = ["Hysteresis", "drive"]


@dataclass(frozen=True, eq=False)
class Hysteresis:
    """An element's response along a deformation history (:func:`drive`).

    Attributes
    ----------
    t : ndarray, shape (n,)
        The instants.
    deformation : ndarray, shape (n,) or (n, n_local)
        The deformation driven (as given).
    force : ndarray, shape like `deformation`
        The element force: for a uniaxial element on ``x_i - x_j`` the force ``F`` on ``i``
        (``-F`` on ``j``); else the local forces.
    tangent : ndarray, shape (n,) or (n, n_local, n_local)
        The consistent tangent ``dF/du`` (or the local matrix ``dr/dx``).
    """

    t: NDArray[np.float64]
    deformation: NDArray[np.float64]
    force: NDArray[np.float64]
    tangent: NDArray[np.float64]

    @property
    def dissipated(self) -> float:
        """The work done on the element along the path, ``int F . du`` (trapezoids): over a
        closed loop, the energy the loop dissipates."""
        u = self.deformation.reshape(self.deformation.shape[0], -1)
        f = self.force.reshape(u.shape)
        return float((0.5 * (f[1:] + f[:-1]) * np.diff(u, axis=0)).sum())

    def plot(self, ax: Any = None, **kwargs: Any) -> Any:
        """The hysteresis loop, force against deformation (the first local dof of a
        multi-dof element); returns the matplotlib Axes."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(5, 4))
        u = self.deformation.reshape(self.deformation.shape[0], -1)[:, 0]
        f = self.force.reshape(self.deformation.shape[0], -1)[:, 0]
        ax.plot(u, f, **kwargs)
        ax.set_xlabel("deformation")
        ax.set_ylabel("force")
        ax.grid(True, alpha=0.3)
        return ax


def drive(
    element: _core.Element,
    deformation: ArrayLike,
    *,
    velocity: ArrayLike | None = None,
    t: ArrayLike | None = None,
) -> Hysteresis:
    """Drive `element` from its virgin state through `deformation`, committing its internal
    variables after each instant (OpenSees' ``setStrain`` + ``commitState``).

    Parameters
    ----------
    element : duhamel.elements.Element
        Any element (its dofs are not used: the history is of its local displacements).
    deformation : array_like, shape (n,) or (n, n_local)
        For an element on one deformation ``x_i - x_j`` (or a dof and the ground), the
        deformation; otherwise the local displacements of its dofs, in their order.
    velocity : array_like, optional
        The rates, of the same shape (default: zero, as OpenSees' material tests).
    t : array_like, shape (n,), optional
        The instants (default ``0, 1, 2, ...``): they matter to elements whose internal
        variables evolve in time (a damper in series with its brace).

    Returns
    -------
    Hysteresis
        The forces and tangents at each instant.

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> steel = duhamel.elements.Bilinear(0, k=100.0, fy=1.0, alpha=0.0)
    >>> loop = duhamel.elements.drive(steel, [0.0, 0.02, 0.0, -0.02, 0.0, 0.02])
    >>> loop.force.tolist()
    [0.0, 1.0, -1.0, -1.0, 1.0, 1.0]

    A material with an ``initial_deformation`` ``d0`` (a hinge after a gravity analysis) is
    the virgin one driven from rest to ``d0`` along ``numpy.linspace(0, d0, 101)`` and on,
    its force measured from the force there:

    >>> hinge = duhamel.elements.Steel02(0, fy=1.0, E=100.0, b=0.02, initial_deformation=0.02)
    >>> virgin = duhamel.elements.Steel02(0, fy=1.0, E=100.0, b=0.02)
    >>> rest = np.linspace(0.0, 0.02, 101)
    >>> d = np.array([0.0, 0.01, -0.03, 0.0])
    >>> whole = duhamel.elements.drive(virgin, np.concatenate([rest, 0.02 + d])).force
    >>> bool((duhamel.elements.drive(hinge, d).force == whole[101:] - whole[100]).all())
    True
    """
    if not isinstance(element, _core.Element):
        raise TypeError(
            f"`element` must be a duhamel.elements element, got {type(element).__name__}"
        )
    nl = len(element._dofs)
    u = as_float_array(deformation, "deformation")
    if u.ndim not in (1, 2) or u.shape[0] == 0:
        raise ValueError(
            f"`deformation` must be a non-empty (n,) or (n, {nl}) array, got {u.shape}"
        )
    uniaxial = u.ndim == 1
    if uniaxial and nl > 2:
        raise ValueError(
            f"`deformation` of this {type(element).__name__} (on {nl} dofs) must be (n, {nl})"
        )
    if not uniaxial and u.shape[1] != nl:
        raise ValueError(f"`deformation` must have the element's {nl} local dofs, got {u.shape}")
    n = u.shape[0]
    rate = np.zeros_like(u) if velocity is None else as_float_array(velocity, "velocity")
    if rate.shape != u.shape:
        raise ValueError(
            f"`velocity` must have the shape of `deformation` {u.shape}, got {rate.shape}"
        )
    times = np.arange(n, dtype=np.float64) if t is None else as_float_array(t, "t")
    if times.shape != (n,):
        raise ValueError(f"`t` must have shape ({n},), got {times.shape}")

    def local(a: NDArray[np.float64]) -> NDArray[np.float64]:
        if not uniaxial:
            return np.ascontiguousarray(a).ravel()
        out = np.zeros((n, nl))
        out[:, 0] = a
        return out.ravel()

    force, kx, _ = _core.drive_element(element, local(u), local(rate), np.ascontiguousarray(times))
    force = force.reshape(n, nl)
    kx = kx.reshape(n, nl, nl)
    if uniaxial:
        return Hysteresis(times, u, force[:, 0].copy(), kx[:, 0, 0].copy())
    return Hysteresis(times, u, force, kx)

"""Effective stiffness and damping of an isolator at an amplitude, from the element's own
hysteresis loop (:func:`effective_properties`): the element is driven through cycles of that
amplitude (:func:`duhamel.elements.drive`, its state committed at every point) and the last
cycle is measured as a prototype test is (ASCE 7-22 section 17.8.5)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["EffectiveProperties", "cycle", "effective_properties"]


@dataclass(frozen=True, eq=False)
class EffectiveProperties:
    """An element's loop at one amplitude, measured as ASCE 7-22 section 17.8.5 measures a
    prototype's.

    Attributes
    ----------
    displacement : float
        The amplitude ``D`` (m): the loop's ``(|D+| + |D-|) / 2``.
    stiffness : float
        ``k_eff = (|F+| + |F-|) / (|D+| + |D-|)`` (Eq. 17.8-1), N/m.
    damping : float
        ``beta_eff = (2 / pi) E_loop / (k_eff (|D+| + |D-|)^2)`` (Eq. 17.8-2), a fraction
        of critical like ``zeta``.
    energy : float
        ``E_loop``, the work of the last cycle ``oint F du`` (J): the energy dissipated per
        cycle.
    force_positive, force_negative : float
        ``F+`` and ``F-``, the forces at ``+D`` and ``-D`` on the last cycle.
    deformation, force : ndarray, shape (n,)
        The last cycle, from ``+D`` through ``-D`` back to ``+D`` (along the element's
        first axis).
    """

    displacement: float
    stiffness: float
    damping: float
    energy: float
    force_positive: float
    force_negative: float
    deformation: NDArray[np.float64]
    force: NDArray[np.float64]


def cycle(displacement: float, cycles: int, points: int) -> NDArray[np.float64]:
    """The deformation path of :func:`effective_properties`: from 0 up to ``+D``, then
    `cycles` full cycles ``+D -> -D -> +D``, `points` equal increments per half cycle.

    Examples
    --------
    >>> from duhamel.design.effective import cycle
    >>> [round(u, 12) for u in cycle(0.1, 1, 4).tolist()]
    [0.0, 0.05, 0.1, 0.05, 0.0, -0.05, -0.1, -0.05, 0.0, 0.05, 0.1]
    """
    d = float(displacement)
    up = np.linspace(0.0, d, points // 2 + 1)
    down = np.linspace(d, -d, points + 1)[1:]
    back = np.linspace(-d, d, points + 1)[1:]
    return np.concatenate([up, *([down, back] * cycles)])


def _local_axes(element: Any) -> int:
    """How many deformation components the element takes (1 or 2: a bidirectional
    bearing), or TypeError for an element without a hysteresis loop to measure."""
    from duhamel.elements import Element

    if not isinstance(element, Element) or not element._path_dependent:
        raise TypeError(
            "`element` must be an isolator or hysteretic device of duhamel.elements (a "
            f"friction pendulum, lead-rubber bearing, Bilinear, BoucWen ...), got "
            f"{type(element).__name__}"
        )
    dofs = getattr(element, "dofs", None)
    return len(element._dofs) if dofs is not None else 1


def horizontal_bearing(element: Any) -> Any:
    """A friction pendulum with its vertical dof as the bearing on its horizontal dofs under
    its axial force at ``x = 0`` (``initial_axial_force``, else its nominal ``weight``), with
    the same initial stiffness ``k_i = mu W / u_y``; any other element unchanged."""
    from duhamel.elements import FrictionPendulum

    if not isinstance(element, FrictionPendulum) or len(element.dofs) != 3:
        return element
    weight = element.initial_axial_force or element.weight
    k_i = element.mu * element.weight / element.yield_displacement
    return FrictionPendulum(
        tuple(d for d in element.dofs[:2] if d is not None),
        radius=element.radius,
        mu=element.mu,
        weight=weight,
        yield_displacement=element.mu * weight / (k_i - weight / element.radius),
    )


#: Parts an increment holding a kink of the loop is split into.
REFINE = 256


def _kinks(path: NDArray[np.float64], force: NDArray[np.float64]) -> NDArray[np.bool_]:
    """The increments of `path` that may hold a kink of the force inside them: the slope
    changes both into and out of the increment by more than 1e-4 of the largest slope (a
    kink at a point of the path, as at a reversal, costs the trapezoidal rule nothing; one
    near a point costs in proportion to the smaller change). None when more than 1 % are
    flagged: a smooth loop, whose trapezoidal area is accurate as it is."""
    slope = np.diff(force) / np.diff(path)
    change = np.abs(np.diff(slope))  # change[k]: from increment k to k + 1
    both = np.zeros(slope.size)
    both[1:-1] = np.minimum(change[:-1], change[1:])
    kinked = both > 1e-4 * np.abs(slope).max()
    return kinked if kinked.sum() <= 0.01 * kinked.size else np.zeros_like(kinked)


def _refined(
    path: NDArray[np.float64], kinked: NDArray[np.bool_]
) -> tuple[NDArray[np.float64], NDArray[np.intp]]:
    """`path` with each increment flagged in `kinked` split in :data:`REFINE` equal parts,
    and where each original point lands in it."""
    parts = np.where(kinked, REFINE, 1)
    marks = np.concatenate([[0], np.cumsum(parts)])
    which = np.repeat(np.arange(path.size - 1), parts)
    step = np.arange(1, marks[-1] + 1) - np.repeat(marks[:-1], parts)
    out = np.empty(marks[-1] + 1)
    out[0] = path[0]
    out[1:] = path[which] + (path[which + 1] - path[which]) * (step / parts[which])
    out[marks[1:]] = path[1:]  # the original points exactly
    return out, marks


def _forces(
    element: Any, path: NDArray[np.float64], axes: int, d: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The element's deformation and force along its first axis on `path` (a
    bidirectional one driven along x)."""
    drive_path = path if axes == 1 else np.column_stack([path, np.zeros_like(path)])
    force, reached = _drive(element, drive_path)
    force = force.reshape(path.size, -1)[:, 0]
    if not np.all(np.isfinite(force)):
        raise ValueError(f"`element` gave non-finite forces when driven to {d:g}")
    return reached.reshape(path.size, -1)[:, 0], force


def _drive(
    element: Any, deformation: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The element's forces along `deformation` (n,) or (n, n_local), committed point by
    point (:func:`duhamel.elements.drive`), and the deformations they are at."""
    from duhamel.elements import drive

    return np.asarray(drive(element, deformation).force, dtype=np.float64), deformation


def effective_properties(
    element: Any, displacement: float, *, cycles: int = 2, points: int = 4000
) -> EffectiveProperties:
    """Effective stiffness and damping of `element` at the amplitude `displacement`, from its
    own hysteresis loop: the element is driven quasi-statically from rest to ``+D`` and
    through `cycles` full cycles ``+D -> -D -> +D`` (committed at every point; a
    bidirectional bearing along its x axis), and the last cycle is measured as ASCE 7-22
    section 17.8.5 measures a prototype's:

    * ``k_eff = (|F+| + |F-|) / (|D+| + |D-|)`` (Eq. 17.8-1),
    * ``beta_eff = (2 / pi) E_loop / (k_eff (|D+| + |D-|)^2)`` (Eq. 17.8-2), ``E_loop``
      the loop's area (trapezoidal rule over the path).

    No textbook formula is used: a friction pendulum's loop gives ``k_eff = W / R + mu W /
    D`` exactly and ``beta_eff = 2 mu / (pi (mu + D / R)) (1 - u_y / D)``, the idealised
    rigid-plastic value times ``1 - u_y / D`` (its pre-sliding displacement ``u_y``); a
    Bilinear's the bilinear formulas; a lead-rubber bearing's its smooth Bouc-Wen loop.

    Parameters
    ----------
    element : duhamel.elements element
        A hysteretic element: ``FrictionPendulum`` (with its vertical dof: measured on its
        horizontal dofs under its initial axial force, the gravity state it starts from),
        ``TripleFrictionPendulum``, ``LeadRubberBearing``, ``Bilinear``, ``BoucWen``.
        Velocity-dependent friction is measured at the driver's pace (one point per unit
        time: the slow coefficient).
    displacement : float
        The amplitude ``D`` (m), > 0.
    cycles : int, optional
        Full cycles after the first loading (default 2: a Bouc-Wen loop settles).
    points : int, optional
        Increments per half cycle (default 4000). The trapezoidal area is exact on straight
        branches; a kink inside an increment would cost up to ``k_jump h^2 / 8`` (``h = 2 D /
        points``), so the increments where the slope jumps are split in 256 and the path
        driven again: for a friction pendulum the kinks then cost below
        ``D / (8 (256 points)^2 u_y)`` of ``E_loop`` (1e-9 at ``D / u_y = 1000``).

    Returns
    -------
    EffectiveProperties

    Examples
    --------
    >>> import duhamel
    >>> from duhamel.design import effective_properties
    >>> fp = duhamel.elements.FrictionPendulum(0, radius=2.0, mu=0.05, weight=1e6)
    >>> p = effective_properties(fp, 0.2)
    >>> round(p.stiffness / (1e6 / 2.0 + 0.05 * 1e6 / 0.2), 6)  # W/R + mu W/D
    1.0
    >>> round(p.damping, 4)  # 2 mu / (pi (mu + D/R)) (1 - uy/D)
    0.2119
    """
    d = float(displacement)
    if not (math.isfinite(d) and d > 0.0):
        raise ValueError(f"`displacement` must be a finite amplitude > 0, got {displacement!r}")
    if isinstance(cycles, bool) or not isinstance(cycles, int) or cycles < 1:
        raise ValueError(f"`cycles` must be an integer >= 1, got {cycles!r}")
    if isinstance(points, bool) or not isinstance(points, int) or points < 8 or points % 2:
        raise ValueError(f"`points` must be an even integer >= 8, got {points!r}")
    element = horizontal_bearing(element)
    axes = _local_axes(element)
    path = cycle(d, cycles, points)
    reached, force = _forces(element, path, axes, d)
    # increments holding a kink (a yield, a stick-slip change) are split in REFINE equal
    # parts and the path driven again: the trapezoidal area of a straight-branched loop
    # becomes exact but for REFINE^-2 of the kinks' share (a smooth loop is left alone)
    kinked = _kinks(path, force)
    marks = np.arange(path.size)
    if kinked.any():
        path, marks = _refined(path, kinked)
        reached, force = _forces(element, path, axes, d)
    start, middle = marks[-(2 * points + 1)], marks[-(points + 1)]
    u, f = reached[start:], force[start:]
    middle -= start
    f_pos, f_neg = float(f[-1]), float(f[middle])
    stroke = abs(float(u[-1])) + abs(float(u[middle]))
    energy = float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(u)))
    k_eff = (abs(f_pos) + abs(f_neg)) / stroke
    if -1e-9 * k_eff * stroke**2 < energy < 0.0:
        energy = 0.0  # an elastic cycle's round-off
    beta = 2.0 / math.pi * energy / (k_eff * stroke**2) if k_eff > 0 else 0.0
    return EffectiveProperties(stroke / 2, k_eff, beta, energy, f_pos, f_neg, u.copy(), f.copy())

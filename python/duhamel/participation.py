"""Modal participation: participation factors, effective modal masses and their ratios.

For the influence vector ``r`` of a direction (ones on the dofs that move with a unit
support displacement in it) and mass-normalised modes ``phi_i`` (``phi^T M phi = I``), the
participation factor is ``Gamma_i = phi_i^T M r``, the effective modal mass
``m_i = Gamma_i^2``, its ratio ``m_i / (r^T M r)`` and the cumulative ratio over the modes in
order. With every mode the effective masses sum to the direction's total mass ``r^T M r``
(massless dofs included: they carry none). A corrected (Ritz) basis is M-orthonormal too, so
the same numbers hold for it; FNA users check that the modes kept carry 90 % of the mass in
the loaded direction (:data:`MASS_TARGET`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["MASS_TARGET", "Participation", "direction_vector", "participation"]

#: The share of a direction's mass a reduced basis should carry (FNA's, ASCE 7's 90 %).
MASS_TARGET = 0.9


@dataclass(frozen=True)
class Participation:
    """Participation of the modes of a basis in one direction (one value per mode).

    Attributes
    ----------
    direction : ndarray, shape (n_dof,)
        The influence vector ``r``.
    factors : ndarray
        Participation factors ``Gamma_i = phi_i^T M r`` (mass-normalised modes).
    effective_mass : ndarray
        Effective modal masses ``Gamma_i^2``.
    ratio : ndarray
        ``effective_mass / total_mass``.
    cumulative : ndarray
        Cumulative sum of `ratio` over the modes, in order.
    total_mass : float
        ``r^T M r``, the mass that moves in the direction.
    """

    direction: NDArray[np.float64]
    factors: NDArray[np.float64]
    effective_mass: NDArray[np.float64]
    ratio: NDArray[np.float64]
    cumulative: NDArray[np.float64]
    total_mass: float


def _matches(label: Any, name: str) -> bool:
    if isinstance(label, tuple):
        return len(label) > 0 and str(label[-1]) == name
    return str(label).endswith(name)


def labelled(labels: Sequence[Any] | None, name: str) -> bool:
    """Whether some dof label names the direction `name`."""
    return labels is not None and any(_matches(lab, name) for lab in labels)


def direction_vector(
    direction: ArrayLike | str, n_dof: int, labels: Sequence[Any] | None
) -> NDArray[np.float64]:
    """The influence vector of `direction`: a vector over the dofs as given, or, for a
    label such as ``"ux"``, ones on the dofs labelled ``(node, "ux")`` or with a name ending
    in ``"ux"`` (the system's :attr:`~duhamel.System.dof_labels`)."""
    if isinstance(direction, str):
        if labels is None:
            raise ValueError(
                f"`direction` = {direction!r} names a direction, but the dofs have no labels: "
                "label them (System.label_dofs) or pass a vector over the dofs"
            )
        r = np.array([1.0 if _matches(lab, direction) else 0.0 for lab in labels])
        if not r.any():
            raise ValueError(f"`direction` = {direction!r} matches no dof label")
        return r
    from duhamel._engine.validate import as_float_array

    r = as_float_array(direction, "direction", ndim=1)
    if r.shape != (n_dof,):
        raise ValueError(f"`direction` must have length n_dof = {n_dof}, got {r.shape[0]}")
    return r


def participation(
    phi: NDArray[np.float64], M: Any, direction: ArrayLike | str, labels: Sequence[Any] | None
) -> Participation:
    """The :class:`Participation` of the M-orthonormal modes `phi` in `direction`."""
    r = direction_vector(direction, phi.shape[0], labels)
    mr = np.asarray(M @ r, dtype=np.float64)
    total = float(r @ mr)
    factors = phi.T @ mr
    eff = factors**2
    ratio = eff / total if total > 0.0 else np.zeros_like(eff)  # no mass: no share
    return Participation(r, factors, eff, ratio, np.cumsum(ratio), total)


def summary_table(
    omega: NDArray[np.float64],
    zeta: NDArray[np.float64],
    parts: dict[str, Participation],
) -> str:
    """A text table of the modes: circular frequency, period, damping ratio and, per
    direction, the mass ratio and its cumulative value (in %)."""
    head = f"{'mode':>4} {'omega (rad/s)':>14} {'T (s)':>10} {'zeta':>7}"
    for name in parts:
        head += f" {name + ' %':>9} {'cum %':>7}"
    lines = [head]
    for i, w in enumerate(omega):
        period = 2 * np.pi / w if w > 0 else np.inf
        row = f"{i:>4} {w:>14.6g} {period:>10.4g} {zeta[i]:>7.4f}"
        for p in parts.values():
            row += f" {100 * p.ratio[i]:>9.2f} {100 * p.cumulative[i]:>7.2f}"
        lines.append(row)
    return "\n".join(lines)

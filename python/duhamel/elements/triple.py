"""The triple friction pendulum isolator (OpenSees ``TripleFrictionPendulum``).

Evaluated in Rust (``crates/duhamel-core/src/elements/hysteretic/triple.rs``): the series
model of the bearing's four sliding surfaces with their effective radii and friction as
OpenSees writes it (Dao et al. 2013 after Fenz & Constantinou 2008), with the exact tangent
and committed and trial internal variables. Exported from :mod:`duhamel.elements`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel._engine.protocols import Model
from duhamel._engine.validate import as_float_array, dof_index
from duhamel.elements.base import Element, TwoAxis, positive

__all__ = ["TripleFrictionPendulum"]


def _three(value: Any, name: str) -> tuple[float, float, float]:
    """`value` as three finite values > 0, or ValueError naming `name`."""
    a = as_float_array(value, name)
    if a.shape != (3,):
        raise ValueError(f"`{name}` must hold three values, got shape {a.shape}")
    if not np.all(a > 0):
        raise ValueError(f"`{name}` must be > 0, got {tuple(a.tolist())}")
    return (float(a[0]), float(a[1]), float(a[2]))


@dataclass(frozen=True)
class TripleFrictionPendulum(TwoAxis, Element):
    """Triple friction pendulum isolator, bidirectional (coupled) on two horizontal dofs or
    uniaxial on `dof_x` alone (``dof_y=None``: a plane model), to the ground, under a
    constant vertical load `weight` ``W``.

    The series model of OpenSees' ``TripleFrictionPendulum`` element (Dao, Ryan, Sato &
    Sasaki 2013, after Fenz & Constantinou 2008): `mu` ``= (mu1, mu2, mu3)`` the friction
    coefficients of the two inner surfaces (equal) and of the two outer ones, ordered
    ``mu1 <= mu2 <= mu3``; `radius` ``= (L1, L2, L3)`` their effective radii (radius of
    curvature minus the height of the pivot, ``L1 < L2, L3``); `displacement_capacity`
    ``= (d1, d2, d3)`` the actual displacement capacity of each surface (OpenSees' ``d1,
    d2, d3``; the bearing's is ``2 d1 + d2 + d3 + L1 d3 / L3 - L1 d2 / L2``). Sliding
    starts at ``mu1 W`` after the elastic displacement `yield_displacement` (OpenSees'
    ``uy``; 2.5e-4, in metres, by default). Under increasing displacement the force passes
    Fenz & Constantinou's five regimes: stiffness ``W / (2 L1)`` from ``mu1 W``,
    ``W / (L1 + L2)`` from ``mu2 W``, ``W / (L2 + L3)`` from ``mu3 W``, ``W / (L1 + L3)``
    from ``W (mu2 + d2 / L2)`` (surface 2 on its stop) and ``W / (2 L1)`` from
    ``W (mu3 + d3 / L3)`` (surface 3 on its stop), then the stiff stop of the inner
    slider. Constant (Coulomb) friction, no uplift, no change of ``W`` with the
    overturning (docs/structural.md).

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> tfp = duhamel.elements.TripleFrictionPendulum(
    ...     0, mu=(0.02, 0.06, 0.10), radius=(0.3, 2.0, 2.0),
    ...     displacement_capacity=(0.05, 0.3, 0.3), weight=1e6)
    >>> s = duhamel.System(1e6 / 9.81 * np.eye(1), np.zeros((1, 1))).add(tfp)
    >>> sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=2.0, dt=0.01, v0=[0.5])
    >>> bool(abs(sol.elements[0].force).max() > 0.02e6)
    True
    """

    dof_x: int
    dof_y: int | None = None  # type: ignore[assignment]
    mu: tuple[float, float, float] = field(default=(0.02, 0.06, 0.1), kw_only=True)
    radius: tuple[float, float, float] = field(default=(0.3, 2.0, 2.0), kw_only=True)
    displacement_capacity: tuple[float, float, float] = field(
        default=(0.05, 0.3, 0.3), kw_only=True
    )
    weight: float = field(default=1.0, kw_only=True)
    yield_displacement: float = field(default=2.5e-4, kw_only=True)
    _path_dependent = True

    def __post_init__(self) -> None:
        mu = _three(self.mu, "mu")
        if not mu[0] <= mu[1] <= mu[2]:
            raise ValueError(
                f"`mu` must be ordered mu1 <= mu2 <= mu3 (the inner surfaces' first), got {mu}"
            )
        radius = _three(self.radius, "radius")
        if not (radius[1] > radius[0] and radius[2] > radius[0]):
            raise ValueError(
                f"`radius` (L1, L2, L3): the inner L1 must be below L2 and L3, got {radius}"
            )
        capacity = _three(self.displacement_capacity, "displacement_capacity")
        positive(self.weight, "weight")
        uy = positive(self.yield_displacement, "yield_displacement")
        limit = 3 * mu[0] * min(2 * radius[0], radius[1] - radius[0], radius[2] - radius[0])
        if uy >= limit:
            raise ValueError(
                f"`yield_displacement` must be below 3 mu1 min(2 L1, L2 - L1, L3 - L1) = "
                f"{limit:.6g} (each sliding element's elastic stiffness must exceed its "
                f"sliding stiffness), got {uy}"
            )
        object.__setattr__(self, "mu", mu)
        object.__setattr__(self, "radius", radius)
        object.__setattr__(self, "displacement_capacity", capacity)

    def _validate(self, system: Model) -> None:
        if self.dof_y is None:
            dof_index(self.dof_x, "dof_x", system.n_dof)
        else:
            TwoAxis._validate(self, system)

    def _dofs(self) -> tuple[int, ...]:
        return (int(self.dof_x),) if self.dof_y is None else (int(self.dof_x), int(self.dof_y))

    def _passive(self) -> bool:
        return True

    def _spec(self) -> tuple:
        return (
            "device",
            "triple_friction_pendulum",
            (
                int(self.dof_x),
                None if self.dof_y is None else int(self.dof_y),
                self.mu,
                self.radius,
                self.displacement_capacity,
                float(self.weight),
                float(self.yield_displacement),
            ),
        )

    def _linear(self) -> tuple[tuple[int, ...], NDArray[np.float64]]:
        # The softest sliding stiffness W / (L2 + L3) (regime III) in each direction: the
        # remainder's tangent stays positive semidefinite in every regime.
        dofs = self._dofs()
        k = float(self.weight) / (self.radius[1] + self.radius[2])
        return dofs, k * np.eye(len(dofs))

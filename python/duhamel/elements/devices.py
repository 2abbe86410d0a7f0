"""Hysteretic and device elements of earthquake engineering: isolators, dampers, gaps.

Evaluated in Rust (``crates/duhamel-core/src/elements/hysteretic``) with their consistent
tangents. The path-dependent ones (:class:`Bilinear`, :class:`BoucWen`,
:class:`FrictionPendulum`) carry committed and trial internal variables: the trial state
follows the Newton iterations inside a step, the integrator commits it once per accepted
step (docs/structural.md). Exported from :mod:`duhamel.elements`.

A two-node element acts on the deformation ``u = x_i - x_j`` (``x_i`` when ``j=None``:
to ground) with force ``+F`` on ``i`` and ``-F`` on ``j`` (a restoring force, left-hand
side of the equation of motion).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from duhamel._engine.validate import _int_scalar, finite_float
from duhamel.elements.base import Deformation, Element, TwoAxis, nonneg, pair_stiffness, positive

__all__ = ["Bilinear", "BoucWen", "FrictionPendulum", "Gap", "ViscousDamper"]


def _j(j: int | None) -> int | None:
    return None if j is None else _int_scalar(j, "j")


def _alpha(value: float) -> float:
    a = finite_float(value, "alpha")
    if a > 1:
        raise ValueError(f"`alpha` must be <= 1 (post-yield over elastic stiffness), got {a}")
    return a


@dataclass(frozen=True)
class Bilinear(Deformation, Element):
    """Bilinear elastoplastic spring with kinematic hardening (OpenSees ``Steel01`` without
    isotropic hardening): elastic stiffness `k`, yield force `fy`, post-yield stiffness
    ``alpha k`` (0: elastic-perfectly plastic). The force stays between the lines
    ``alpha k u +- (1 - alpha) fy``; the return mapping is exact for any increment. The
    element starts virgin at ``u = 0`` (an initial deformation is taken as reached
    monotonically). A symmetric cycle of amplitude ``u_max > fy / k`` dissipates
    ``4 (1 - alpha) fy (u_max - fy / k)``.

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> sdof = duhamel.System(np.eye(1), 10.0 * np.eye(1), zeta=0.02)
    >>> sdof = sdof.add(duhamel.elements.Bilinear(0, k=100.0, fy=1.0, alpha=0.05))
    >>> sol = duhamel.solve(sdof, duhamel.Semianalytic(), t_end=2.0, dt=0.01, v0=[1.0])
    >>> bool(abs(sol.elements[0].axial_force).max() <= 1.0 + 0.05 * 100 * 0.2)
    True
    """

    i: int
    j: int | None = None
    k: float = 1.0
    fy: float = 1.0
    alpha: float = 0.0
    _path_dependent = True

    def __post_init__(self) -> None:
        positive(self.k, "k")
        positive(self.fy, "fy")
        _alpha(self.alpha)

    def _spec(self) -> tuple:
        return (
            "bilinear",
            int(self.i),
            _j(self.j),
            float(self.k),
            float(self.fy),
            float(self.alpha),
        )

    def _linear(self) -> tuple[tuple[int, ...], NDArray[np.float64]]:
        return pair_stiffness(self.i, self.j, float(self.k))  # the initial stiffness


@dataclass(frozen=True)
class BoucWen(Deformation, Element):
    """Bouc-Wen smooth hysteretic spring, ``F = alpha k u + (1 - alpha) fy z`` with
    ``dz/du = (k / fy) [1 - |z|^n (beta sgn(du z) + gamma)]`` (OpenSees ``BoucWen`` with
    ``z`` in displacement units ``fy / k``). For ``n = 1`` the update of ``z`` over a step is
    exact; for other ``n`` it is integrated to about 1e-11 (integer ``n``) or 1e-8.

    Examples
    --------
    >>> import duhamel
    >>> isolator = duhamel.elements.BoucWen(0, k=2e6, fy=5e4, alpha=0.1)
    >>> isolator.n, isolator.beta, isolator.gamma
    (1.0, 0.5, 0.5)
    """

    i: int
    j: int | None = None
    k: float = 1.0
    fy: float = 1.0
    alpha: float = 0.0
    n: float = 1.0
    beta: float = 0.5
    gamma: float = 0.5
    _path_dependent = True

    def __post_init__(self) -> None:
        positive(self.k, "k")
        positive(self.fy, "fy")
        _alpha(self.alpha)
        n = finite_float(self.n, "n")
        if n < 1:
            raise ValueError(f"`n` must be >= 1, got {n}")
        beta = positive(self.beta, "beta")
        gamma = finite_float(self.gamma, "gamma")
        if gamma <= -beta:
            raise ValueError(f"`gamma` must be > -beta = {-beta} (bounded z), got {gamma}")
        for name in ("n", "beta", "gamma"):
            object.__setattr__(self, name, float(getattr(self, name)))

    def _spec(self) -> tuple:
        return (
            "bouc_wen",
            int(self.i),
            _j(self.j),
            float(self.k),
            float(self.fy),
            float(self.alpha),
            self.n,
            self.beta,
            self.gamma,
        )

    def _linear(self) -> tuple[tuple[int, ...], NDArray[np.float64]]:
        return pair_stiffness(self.i, self.j, float(self.k))  # the initial stiffness


@dataclass(frozen=True)
class FrictionPendulum(TwoAxis, Element):
    """Single friction pendulum isolator on two horizontal dofs (bidirectional, coupled):
    restoring force ``(weight / radius) u`` plus Coulomb friction bounded by the circle
    ``|f| <= mu weight``, with a pre-sliding (elastic) stiffness ``mu weight /
    yield_displacement`` and a radial return mapping. The isolated period is
    ``2 pi sqrt(radius / g)``. Constant `weight` and `mu` (no vertical coupling, no velocity
    dependence of the friction coefficient). Units: `yield_displacement` defaults to
    2.5e-4 (m).

    Examples
    --------
    >>> import duhamel
    >>> fps = duhamel.elements.FrictionPendulum(0, 1, radius=2.0, mu=0.05, weight=5e6)
    >>> fps.yield_displacement
    0.00025
    """

    dof_x: int
    dof_y: int
    radius: float = 1.0
    mu: float = 0.05
    weight: float = 1.0
    yield_displacement: float = 2.5e-4
    _path_dependent = True

    def __post_init__(self) -> None:
        positive(self.radius, "radius")
        nonneg(self.mu, "mu")
        positive(self.weight, "weight")
        positive(self.yield_displacement, "yield_displacement")

    def _spec(self) -> tuple:
        return (
            "friction_pendulum",
            int(self.dof_x),
            int(self.dof_y),
            float(self.radius),
            float(self.mu),
            float(self.weight),
            float(self.yield_displacement),
        )

    def _linear(self) -> tuple[tuple[int, ...], NDArray[np.float64]]:
        # The pendulum's gravity stiffness W / R, on both directions (friction stays).
        return (int(self.dof_x), int(self.dof_y)), (self.weight / self.radius) * np.eye(2)


@dataclass(frozen=True)
class ViscousDamper(Deformation, Element):
    """Fluid viscous damper ``F = c |v|^exponent sgn(v)`` on ``v = v_i - v_j`` (including
    ``exponent < 1``, the usual nonlinear dampers: below the speed `v0` an odd cubic matching
    the power law's force and slope at `v0` keeps the force smooth and its slope finite, so
    Newton converges; `v0` defaults to 1e-4, 0.1 mm/s in SI units).

    Examples
    --------
    >>> import duhamel
    >>> damper = duhamel.elements.ViscousDamper(2, 1, c=3e5, exponent=0.35)
    """

    i: int
    j: int | None = None
    c: float = 0.0
    exponent: float = 1.0
    v0: float = 1e-4

    def __post_init__(self) -> None:
        nonneg(self.c, "c")
        positive(self.exponent, "exponent")
        positive(self.v0, "v0")

    def _spec(self) -> tuple:
        return (
            "viscous_damper",
            int(self.i),
            _j(self.j),
            float(self.c),
            float(self.exponent),
            float(self.v0),
        )


@dataclass(frozen=True)
class Gap(Deformation, Element):
    """Compression-only contact (pounding, a stop): ``F = k (u + gap)`` once the
    deformation closes the opening, ``u < -gap``, else 0 (node `i` on the positive side of
    `j`, or of a fixed stop at ``-gap`` when ``j=None``).

    Examples
    --------
    >>> import duhamel
    >>> moat = duhamel.elements.Gap(0, None, gap=0.3, k=1e9)
    """

    i: int
    j: int | None = None
    gap: float = 0.0
    k: float = 1.0

    def __post_init__(self) -> None:
        nonneg(self.gap, "gap")
        positive(self.k, "k")

    def _spec(self) -> tuple:
        return ("gap", int(self.i), _j(self.j), float(self.gap), float(self.k))

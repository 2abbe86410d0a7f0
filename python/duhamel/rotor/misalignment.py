"""Coupling misalignment: the reaction force of a misaligned flexible coupling, ROSS's
``MisalignmentFlex`` model (ross-rotordynamics 2.3.0, after Xia et al. 2019), evaluated in
Rust (``crates/duhamel-core/src/loads/misalignment.rs``) at the exact angle of a speed law.

The force is a function of the rotor's angle only (no feedback from the response), so it is a
load: :meth:`CouplingMisalignment.loads` expands it into two :mod:`duhamel.loads` terms, the
force ``+F`` on the coupling's first node and ``-F`` on its second, in x and in y. Its
Fourier coefficients over one turn are given in closed form by
:meth:`CouplingMisalignment.harmonics` (see docs/rotor.md, "Coupling misalignment").
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel import _core
from duhamel._engine.protocols import Model
from duhamel._engine.validate import (
    _int_scalar,
    as_float_array,
    finite_float,
    nonneg_float,
    positive_float,
)
from duhamel.loads import Load
from duhamel.rotor._protocols import RotorModel
from duhamel.rotor._speed import speed_or_law
from duhamel.rotor.loads import RotorLoad
from duhamel.speed import SpeedLaw, as_speed_law

__all__ = ["CouplingMisalignment"]

_TYPES = ("parallel", "angular", "combined")
# ROSS's three bolt terms: the rim angle's offset, the force direction's offset, the sign
_ALPHA = np.array([-np.pi / 2, np.pi / 6, 5 * np.pi / 6])
_BETA = np.array([0.0, 2 * np.pi / 3, 4 * np.pi / 3])
_SIGN = np.array([1.0, 1.0, -1.0])


@dataclass(frozen=True, eq=False)
class _CouplingForce(Load):
    """One component (`axis`) of the coupling's force, ``+F`` on `dof_a`, ``-F`` on `dof_b`,
    at the angle of the speed law `law` (`radius`, `parallel`, `angular`: the core's
    coupling, :meth:`CouplingMisalignment._parts`)."""

    dof_a: int
    dof_b: int
    law: SpeedLaw
    radius: float
    parallel: tuple[float, float, float]
    angular: tuple[float, float]
    axis: str

    def _pattern(self, system: Model) -> NDArray[np.float64]:
        p = np.zeros(system.n_dof)
        p[self.dof_a], p[self.dof_b] = 1.0, -1.0
        return p

    def _time(self) -> _core.TimeFunction:
        return _core.TimeFunction.misalignment(
            self.law._law(), self.radius, self.parallel, self.angular, self.axis
        )

    def _scalar(self, t: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.asarray(self._time().values(np.ascontiguousarray(t, float)))


@dataclass(frozen=True)
class CouplingMisalignment(RotorLoad):
    """A misaligned flexible coupling at shaft element `n`: the reaction force of ROSS's
    ``MisalignmentFlex`` (parallel, angular or combined), driven by the rotor's angle.

    With the parallel offset ``(dx, dy)`` (`mis_distance_x`, `mis_distance_y`),
    ``d = |(dx, dy)|``, the shaft radius ``r`` at the coupling, ``psi = theta +
    atan2(dx, dy)`` and ``g(u) = sqrt(r^2 + d^2 + 2 r d cos u) - r``, the parallel force is
    ``F_x = k_d [g(psi - pi/2) sin(theta) + g(psi + pi/6) sin(theta + 2 pi/3) - g(psi + 5 pi/6)
    sin(theta + 4 pi/3)]`` (``F_y``: cos in place of those sin), ``k_d`` the
    `radial_stiffness`: mainly a static part and a 2x (twice per turn) force, with small 1x
    and 3x terms of order ``d / r`` smaller. The angular misalignment `mis_angle` ``alpha``
    with the `bending_stiffness` ``k_b`` gives, with ``a = 2 k_b r |sin(alpha/2) sin(alpha)|``
    and ``u_j = theta + 2 pi j / 3``, ``F_x = -a sum_j |sin u_j| cos u_j``, ``F_y = -a sum_j
    |sin u_j| sin u_j``: the 3x, 9x, 15x... of the three bolt pairs. ``theta`` is the angle of
    the speed law (``theta = Omega t`` at constant speed, exact along a run-up).

    The force acts ``+F`` on the element's first node and ``-F`` on its second, on the x and
    y translations, as ROSS applies it. Within a step the run takes the load's parabola
    (fourth order) and integrates the angular force's kinks exactly (one per step at most:
    steps shorter than a sixth of a turn). ROSS's driving and load torques act on torsional dofs,
    which duhamel's rotors do not have; they are not modelled.

    Parameters
    ----------
    n : int
        Shaft element of the coupling (a :class:`~duhamel.rotor.Rotor`'s shaft ``n`` joins
        nodes ``n`` and ``n + 1``; for a ROSS model, the shaft element numbered ``n``).
    mis_type : {"parallel", "angular", "combined"}
        Which misalignment (``"combined"``: the sum of both forces).
    mis_distance_x, mis_distance_y : float
        Parallel offset between the driving and the driven shaft along x and y (m).
    mis_angle : float
        Angular misalignment (rad).
    radial_stiffness : float
        Radial stiffness of the coupling (N/m), ``> 0`` for a parallel or combined one.
    bending_stiffness : float
        Bending stiffness of the coupling (as ROSS), ``> 0`` for an angular or combined one.
    radius : float, optional
        Shaft radius at the coupling (m); default: half the outer diameter of shaft `n`
        (ROSS: ``odl / 2``).
    speed : float or speed law, optional
        Spin speed (rad/s) or a :mod:`duhamel.speed` law; default: the rotor's speed given to
        :meth:`~duhamel.rotor.Rotor.system`.

    Examples
    --------
    >>> import numpy as np
    >>> from duhamel.rotor import CouplingMisalignment
    >>> fault = CouplingMisalignment(0, "parallel", mis_distance_x=2e-4, mis_distance_y=2e-4,
    ...                              radial_stiffness=40e3, radius=0.0095)
    >>> c = fault.harmonics([0, 1, 2, 3])  # F_x = sum over m of c[m, 0] exp(i m theta)
    >>> amplitudes = np.abs(c[:, 0]) * [1, 2, 2, 2]  # static, then 1x, 2x, 3x (N)
    >>> np.round(amplitudes, 4).tolist()
    [3.9996, 0.1883, 11.3125, 0.0421]
    >>> fx, fy = fault.force([0.0, np.pi / 2])  # at two angles of the rotor
    >>> np.round(fx, 4).tolist()
    [-6.7831, 15.0828]
    """

    n: int
    mis_type: str
    mis_distance_x: float = 0.0
    mis_distance_y: float = 0.0
    mis_angle: float = 0.0
    radial_stiffness: float = 0.0
    bending_stiffness: float = 0.0
    radius: float | None = None
    speed: Any = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "n", _int_scalar(self.n, "n"))
        if self.mis_type not in _TYPES:
            raise ValueError(
                f"`mis_type` must be 'parallel', 'angular' or 'combined', got {self.mis_type!r}"
            )
        for name in ("mis_distance_x", "mis_distance_y", "mis_angle"):
            object.__setattr__(self, name, finite_float(getattr(self, name), name))
        for name in ("radial_stiffness", "bending_stiffness"):
            object.__setattr__(self, name, nonneg_float(getattr(self, name), name))
        if self.mis_type != "angular" and self.radial_stiffness == 0.0:
            raise ValueError(f"a {self.mis_type} misalignment needs `radial_stiffness` > 0")
        if self.mis_type != "parallel" and self.bending_stiffness == 0.0:
            raise ValueError(f"an {self.mis_type} misalignment needs `bending_stiffness` > 0")
        if self.radius is not None:
            object.__setattr__(self, "radius", positive_float(self.radius, "radius"))
        if self.speed is not None:
            object.__setattr__(self, "speed", speed_or_law(self.speed))

    def _parts(
        self, radius: float
    ) -> tuple[float, tuple[float, float, float], tuple[float, float]]:
        """The core's `(radius, parallel, angular)` with the unused part zeroed."""
        parallel = (self.mis_distance_x, self.mis_distance_y, self.radial_stiffness)
        angular = (self.mis_angle, self.bending_stiffness)
        if self.mis_type == "angular":
            parallel = (0.0, 0.0, 0.0)
        if self.mis_type == "parallel":
            angular = (0.0, 0.0)
        return radius, parallel, angular

    def _radius(self, rotor: RotorModel | None) -> float:
        if rotor is not None:
            return self.nodes(rotor)[2]
        if self.radius is None:
            raise ValueError("give `radius` (the shaft radius at the coupling, m) or a `rotor`")
        return self.radius

    def nodes(self, rotor: RotorModel) -> tuple[int, int, float]:
        """The coupling's two nodes on `rotor` and its shaft radius (`radius`, or half the
        outer diameter of shaft element `n`)."""
        shafts = tuple(getattr(rotor, "shafts", ()) or ())
        native = [s for s in shafts if hasattr(s, "outer_diameter")]
        if native:
            if not 0 <= self.n < len(shafts):
                raise ValueError(
                    f"`n` must be a shaft element, 0 <= n < {len(shafts)}, got {self.n}"
                )
            left, right, odl = self.n, self.n + 1, shafts[self.n].outer_diameter
        else:  # a ROSS model: its shaft elements carry n, n_l, n_r, odl
            match = [s for s in shafts if getattr(s, "n", None) == self.n]
            if not match:
                raise ValueError(f"`n` = {self.n} is not a shaft element of the rotor")
            left, right, odl = int(match[0].n_l), int(match[0].n_r), float(match[0].odl)
        radius = self.radius if self.radius is not None else 0.5 * float(odl)
        return left, right, radius

    def loads(self, rotor: RotorModel, speed: Any = None) -> list[Load]:
        """The force on the coupling's nodes: two loads (x and y), ``+F`` on the first node,
        ``-F`` on the second, evaluated in Rust at the angle of the speed law."""
        left, right, radius = self.nodes(rotor)
        own = self.speed
        given = None if speed is None else speed_or_law(speed)
        if own is None and given is None:
            raise ValueError(
                "the misalignment needs a speed: give `speed` to CouplingMisalignment or to "
                "Rotor.system"
            )
        if own is not None and given is not None and own != given:
            raise ValueError(
                f"the misalignment's speed {own!r} differs from the rotor's {given!r} (rad/s); "
                "give the speed once (CouplingMisalignment(speed=None) takes the rotor's)"
            )
        law = as_speed_law(own if own is not None else given, "speed")
        parts = self._parts(radius)
        return [
            _CouplingForce(rotor.dof(left, d), rotor.dof(right, d), law, *parts, d) for d in "xy"
        ]

    def force(
        self, theta: ArrayLike, rotor: RotorModel | None = None
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The force ``(F_x, F_y)`` (N) at the rotor angles `theta` (rad), as the core
        evaluates it during a run (the radius: `radius`, or shaft `n`'s of `rotor`)."""
        th = np.ascontiguousarray(as_float_array(theta, "theta", ndim=1))
        law = as_speed_law(1.0, "speed")._law()
        radius, parallel, angular = self._parts(self._radius(rotor))
        time = _core.TimeFunction.misalignment
        fx, fy = (np.asarray(time(law, radius, parallel, angular, a).values(th)) for a in "xy")
        return fx, fy

    def harmonics(
        self, orders: ArrayLike, rotor: RotorModel | None = None
    ) -> NDArray[np.complex128]:
        """The force's Fourier coefficients in closed form, ``c[k] = (c_x, c_y)`` of
        ``F = sum_m c_m exp(i m theta)`` over all integers ``m`` at the `orders` ``m``
        (``c_-m = conj(c_m)``; the amplitude of order ``m > 0`` is ``2 |c_m|``); the radius:
        `radius`, or shaft `n`'s of `rotor`.

        The parallel part: ``g(u) = r (|1 + q e^(iu)| - 1)``, ``q = d / r < 1``, has the
        coefficients ``G_n = r q^|n| binom(1/2, |n|) 2F1(-1/2, |n| - 1/2; |n| + 1; q^2)``
        (minus ``r`` at ``n = 0``; Gauss's hypergeometric function), so order ``m`` takes
        ``G_{m-1}`` and ``G_{m+1}`` of the three bolt terms with their phases. The angular
        part: ``|sin u| = sum_k A_2k e^(2iku)``, ``A_2k = -2 / (pi (4 k^2 - 1))``: odd orders
        of ``|sin u| cos u``, the three bolt pairs keep the multiples of 3.
        """
        from scipy.special import binom, hyp2f1

        m = np.asarray(as_float_array(orders, "orders", ndim=1)).astype(np.int64)
        radius, (dx, dy, kd), (alpha, kb) = self._parts(self._radius(rotor))
        out = np.zeros((m.size, 2), dtype=np.complex128)
        d = float(np.hypot(dx, dy))
        if d > 0.0 and kd > 0.0:
            q = d / radius
            if q >= 1.0:
                raise ValueError(f"the closed form needs the offset {d} below the radius {radius}")

            def g(k: NDArray[np.int64]) -> NDArray[np.float64]:
                k = np.abs(k)
                out = radius * q**k * binom(0.5, k) * hyp2f1(-0.5, k - 0.5, k + 1.0, q * q)
                return out - radius * (k == 0)

            gamma = np.arctan2(dx, dy) + _ALPHA
            for s, gk, b in zip(_SIGN, gamma, _BETA, strict=True):
                lo = s * g(m - 1) * np.exp(1j * ((m - 1) * gk + b))
                hi = s * g(m + 1) * np.exp(1j * ((m + 1) * gk - b))
                out[:, 0] += kd * (lo - hi) / 2j
                out[:, 1] += kd * (lo + hi) / 2
        a = 2.0 * kb * radius * abs(np.sin(alpha / 2) * np.sin(alpha))
        if a > 0.0:

            def abs_sin(k: NDArray[np.int64]) -> NDArray[np.float64]:
                even = k % 2 == 0
                return np.where(even, -2.0 / (np.pi * np.where(even, k * k - 1.0, 1.0)), 0.0)

            bolts = np.exp(1j * np.outer(m, _BETA)).sum(axis=1)
            out[:, 0] -= a * bolts * (abs_sin(m - 1) + abs_sin(m + 1)) / 2
            out[:, 1] -= a * bolts * (abs_sin(m - 1) - abs_sin(m + 1)) / 2j
        return out

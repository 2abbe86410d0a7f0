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
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel._engine.protocols import Model
from duhamel._engine.validate import _int_scalar, dof_index, finite_float
from duhamel.elements.base import Deformation, Element, TwoAxis, nonneg, pair_stiffness, positive

__all__ = ["Bilinear", "BoucWen", "FrictionPendulum", "Gap", "LeadRubberBearing", "ViscousDamper"]


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

    def _passive(self) -> bool:
        return float(self.alpha) >= 0.0

    def _tangent_bound(self) -> tuple[float, float] | None:  # elastic k, post-yield alpha k
        return abs(float(self.k)) * max(1.0, abs(float(self.alpha))), 0.0

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
        _bouc_wen_fields(self, "n")

    def _passive(self) -> bool:
        # the hysteretic loop dissipates for beta >= |gamma| (Bouc-Wen's passivity condition)
        return float(self.alpha) >= 0.0 and float(self.beta) >= abs(float(self.gamma))

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
    """Single friction pendulum isolator, bidirectional (coupled) on two horizontal dofs or
    uniaxial on `dof_x` alone (``dof_y=None``: a plane model): restoring force
    ``(weight / radius) u`` plus friction bounded by ``|f| <= mu weight`` (a circle in two
    directions), with a pre-sliding (elastic) stiffness ``mu weight / yield_displacement``
    and a radial return mapping. The isolated period is ``2 pi sqrt(radius / g)``.

    Velocity-dependent friction (OpenSees' ``VelDependent`` model): with `mu_slow` and
    ``rate > 0``, ``mu(s) = mu - (mu - mu_slow) exp(-rate s)`` at the sliding speed ``s``
    (`mu` is then the high-speed coefficient ``mu_fast``; the pre-sliding stiffness stays
    ``mu weight / yield_displacement``). Units: `yield_displacement` defaults to 2.5e-4 (m).

    With a vertical dof (``dof_z``, upward, to the ground; uniaxial with ``dof_y=None`` or
    bidirectional) and the bearing's axial stiffness `vertical_stiffness` ``k_v``, the
    normal force comes from the model (OpenSees ``singleFPBearing``, 2-D and 3-D): the
    bearing carries ``P = -k_v u_z`` in compression and nothing in tension (uplift: zero
    shear, zero axial force); the shear is ``V = (N / R) u + f`` with the normal force
    ``N = P + V . u / R``, friction ``|f| <= mu N`` (a circle in two directions) and the
    pre-sliding stiffness ``k_i - N / R`` (``k_i = mu weight / yield_displacement``,
    `weight` the nominal load: it sets only this stiffness). The weight itself is a load on
    ``dof_z`` (start from the static state, e.g. ``x0`` with ``u_z = -W / k_v``). There the
    sliding speed of `mu_slow`/`rate` is the speed on the surface,
    ``sqrt(|u'|^2 + (u . u' / R)^2)`` (as OpenSees), and friction may also depend on the
    contact pressure ``N / A`` (OpenSees ``VelPressureDep``): with `contact_area` ``A``,
    `delta_mu` and `pressure_alpha`, the high-speed coefficient is
    ``mu - delta_mu tanh(pressure_alpha N / A)``.

    Examples
    --------
    >>> import duhamel
    >>> fps = duhamel.elements.FrictionPendulum(0, 1, radius=2.0, mu=0.05, weight=5e6)
    >>> fps.yield_displacement
    0.00025
    >>> plane = duhamel.elements.FrictionPendulum(0, radius=2.0, mu=0.06, mu_slow=0.03,
    ...                                           rate=20.0, weight=5e6)
    >>> plane.dof_y is None
    True
    >>> spatial = duhamel.elements.FrictionPendulum(0, 1, radius=2.0, mu=0.06, mu_slow=0.03,
    ...                                             rate=20.0, weight=5e6, dof_z=2,
    ...                                             vertical_stiffness=5e9)
    >>> (spatial.dof_y, spatial.dof_z)
    (1, 2)
    """

    dof_x: int
    dof_y: int | None = None
    radius: float = 1.0
    mu: float = 0.05
    weight: float = 1.0
    yield_displacement: float = 2.5e-4
    mu_slow: float | None = None
    rate: float = 0.0
    dof_z: int | None = None
    vertical_stiffness: float | None = None
    contact_area: float | None = None
    delta_mu: float = 0.0
    pressure_alpha: float = 0.0
    _path_dependent = True

    def __post_init__(self) -> None:
        _pendulum_vertical_checks(self)
        positive(self.radius, "radius")
        mu = nonneg(self.mu, "mu")
        positive(self.weight, "weight")
        positive(self.yield_displacement, "yield_displacement")
        nonneg(self.rate, "rate")
        if self.mu_slow is not None:
            slow = nonneg(self.mu_slow, "mu_slow")
            if slow > mu:
                raise ValueError(
                    f"`mu_slow` must be <= mu (the fast coefficient) = {mu}, got {slow}"
                )

    def _validate(self, system: Model) -> None:
        if getattr(self, "dof_z", None) is not None:
            _pendulum_vertical_dofs(self, system)
        elif self.dof_y is None:
            dof_index(self.dof_x, "dof_x", system.n_dof)
        else:
            TwoAxis._validate(self, system)

    def _dofs(self) -> tuple[int, ...]:
        if getattr(self, "dof_z", None) is not None:
            y = () if self.dof_y is None else (int(self.dof_y),)
            return (int(self.dof_x), *y, int(self.dof_z))
        return (int(self.dof_x),) if self.dof_y is None else (int(self.dof_x), int(self.dof_y))

    def _passive(self) -> bool:
        return True

    def _spec(self) -> tuple:
        if self.dof_z is not None:
            return _pendulum_vertical_spec(self)
        slow = None if self.mu_slow is None else float(self.mu_slow)
        return (
            "friction_pendulum",
            int(self.dof_x),
            None if self.dof_y is None else int(self.dof_y),
            float(self.radius),
            float(self.mu),
            float(self.weight),
            float(self.yield_displacement),
            slow,
            float(self.rate),
        )

    def _linear(self) -> tuple[tuple[int, ...], NDArray[np.float64]]:
        # The pendulum's gravity stiffness W / R, in each direction (friction stays); with
        # the vertical dof, W / R and the axial stiffness.
        dofs = self._dofs()
        if self.dof_z is not None:
            kp = [self.weight / self.radius] * (len(dofs) - 1)
            return dofs, np.diag([*kp, float(self.vertical_stiffness)])  # type: ignore[arg-type]
        return dofs, (self.weight / self.radius) * np.eye(len(dofs))


@dataclass(frozen=True)
class LeadRubberBearing(TwoAxis, Element):
    """Lead-rubber (elastomeric) bearing with coupled bidirectional Bouc-Wen hysteresis
    (OpenSees ``ElastomericBearingBoucWen`` without nonlinear hardening), on two horizontal
    dofs or uniaxial on `dof_x` (``dof_y=None``): ``r = alpha k u + (1 - alpha) fy z`` with
    ``(fy / k) dz = [I - |z|^(eta - 2) (gamma + beta sgn(z . du)) z z^T] du``. The
    parameters are those of :class:`Bilinear`: initial stiffness `k`, yield force `fy`
    (characteristic strength ``Qd = (1 - alpha) fy``), post-yield stiffness ratio `alpha`;
    `eta` sharpens the yielding (1: smooth). The increment of a step is integrated by the
    trapezoidal rule (second order) in substeps of at most a quarter of the yield
    displacement, with the exact tangent of that update (docs/structural.md).

    Examples
    --------
    >>> import duhamel
    >>> lrb = duhamel.elements.LeadRubberBearing(0, 1, k=2e7, fy=2e5, alpha=0.1)
    >>> lrb.eta, lrb.beta, lrb.gamma
    (1.0, 0.5, 0.5)
    """

    dof_x: int
    dof_y: int | None = None
    k: float = 1.0
    fy: float = 1.0
    alpha: float = 0.0
    eta: float = 1.0
    beta: float = 0.5
    gamma: float = 0.5
    _path_dependent = True

    def __post_init__(self) -> None:
        _bouc_wen_fields(self, "eta")

    def _validate(self, system: Model) -> None:
        if self.dof_y is None:
            dof_index(self.dof_x, "dof_x", system.n_dof)
        else:
            TwoAxis._validate(self, system)

    def _dofs(self) -> tuple[int, ...]:
        return (int(self.dof_x),) if self.dof_y is None else (int(self.dof_x), int(self.dof_y))

    def _passive(self) -> bool:
        # the coupled Bouc-Wen loop dissipates for beta >= |gamma|, as the uniaxial one
        return float(self.alpha) >= 0.0 and float(self.beta) >= abs(float(self.gamma))

    def _spec(self) -> tuple:
        return (
            "lead_rubber",
            int(self.dof_x),
            None if self.dof_y is None else int(self.dof_y),
            (float(self.k), float(self.fy), float(self.alpha)),
            (self.eta, self.beta, self.gamma),
        )

    def _linear(self) -> tuple[tuple[int, ...], NDArray[np.float64]]:
        dofs = self._dofs()  # the initial stiffness, in each direction
        return dofs, float(self.k) * np.eye(len(dofs))


@dataclass(frozen=True)
class ViscousDamper(Deformation, Element):
    """Fluid viscous damper ``F = c |v|^exponent sgn(v)`` on ``v = v_i - v_j`` (including
    ``exponent < 1``, the usual nonlinear dampers: below the speed `v0` an odd cubic matching
    the power law's force and slope at `v0` keeps the force smooth and its slope finite, so
    Newton converges; `v0` defaults to 1e-4, 0.1 mm/s in SI units).

    With `brace_stiffness` ``k_b`` the damper acts in series with its brace (Maxwell model,
    OpenSees ``ViscousDamper`` material with ``K``): ``F = k_b (u - u_d) = c |u_d'|^exponent
    sgn(u_d')`` with the damper's own deformation ``u_d`` an internal variable, integrated
    over each step by the trapezoidal rule (second order) and solved per evaluation by a
    safeguarded Newton iteration, with the consistent tangent. The element starts
    unstressed and stores ``F^2 / (2 k_b)`` in the brace. None (default): a rigid brace.

    Examples
    --------
    >>> import duhamel
    >>> damper = duhamel.elements.ViscousDamper(2, 1, c=3e5, exponent=0.35)
    >>> braced = duhamel.elements.ViscousDamper(2, 1, c=3e5, exponent=0.35, brace_stiffness=2e7)
    """

    i: int
    j: int | None = None
    c: float = 0.0
    exponent: float = 1.0
    v0: float = 1e-4
    brace_stiffness: float | None = None

    def __post_init__(self) -> None:
        nonneg(self.c, "c")
        positive(self.exponent, "exponent")
        positive(self.v0, "v0")
        if self.brace_stiffness is not None:
            positive(self.brace_stiffness, "brace_stiffness")

    def _passive(self) -> bool:
        return True

    def _spec(self) -> tuple:
        base = (int(self.i), _j(self.j), float(self.c), float(self.exponent), float(self.v0))
        if self.brace_stiffness is None:
            return ("viscous_damper", *base)
        return ("maxwell_damper", *base, float(self.brace_stiffness))


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

    def _passive(self) -> bool:
        return True

    def _tangent_bound(self) -> tuple[float, float] | None:  # closed: k, open: 0
        return float(self.k), 0.0

    def _spec(self) -> tuple:
        return ("gap", int(self.i), _j(self.j), float(self.gap), float(self.k))


def _bouc_wen_fields(element: Any, exponent: str) -> None:
    """Checks and stores as floats the fields of a Bouc-Wen device (`BoucWen`, whose
    exponent is `n`, and `LeadRubberBearing`, whose exponent is `eta`): `k`, `fy` positive,
    `alpha`, the exponent >= 1, `beta` > 0 and `gamma` > -beta (bounded z)."""
    positive(element.k, "k")
    positive(element.fy, "fy")
    _alpha(element.alpha)
    value = finite_float(getattr(element, exponent), exponent)
    if value < 1:
        raise ValueError(f"`{exponent}` must be >= 1, got {value}")
    beta = positive(element.beta, "beta")
    gamma = finite_float(element.gamma, "gamma")
    if gamma <= -beta:
        raise ValueError(f"`gamma` must be > -beta = {-beta} (bounded z), got {gamma}")
    for name in (exponent, "beta", "gamma"):
        object.__setattr__(element, name, float(getattr(element, name)))


def _pendulum_vertical_checks(fp: FrictionPendulum) -> None:
    """The checks of a `FrictionPendulum`'s vertical dof and pressure-dependent friction."""
    if fp.dof_z is not None:
        if fp.vertical_stiffness is None:
            raise ValueError("`vertical_stiffness` is required with `dof_z`")
        positive(fp.vertical_stiffness, "vertical_stiffness")
    elif fp.vertical_stiffness is not None:
        raise ValueError("`vertical_stiffness` needs the vertical dof `dof_z`")
    if fp.contact_area is None:
        if fp.delta_mu or fp.pressure_alpha:
            raise ValueError("`delta_mu` and `pressure_alpha` need `contact_area`")
        return
    if fp.dof_z is None:
        raise ValueError(
            "`contact_area` (pressure-dependent friction) needs the vertical dof `dof_z`"
        )
    positive(fp.contact_area, "contact_area")
    delta = nonneg(fp.delta_mu, "delta_mu")
    nonneg(fp.pressure_alpha, "pressure_alpha")
    if delta > 0 and delta >= finite_float(fp.mu, "mu"):
        raise ValueError(f"`delta_mu` must be < mu (the fast coefficient) = {fp.mu}, got {delta}")


def _pendulum_vertical_dofs(fp: FrictionPendulum, system: Model) -> None:
    """`dof_x`, `dof_y` (if any) and `dof_z` in range and distinct."""
    named = [("dof_x", fp.dof_x), ("dof_y", fp.dof_y), ("dof_z", fp.dof_z)]
    seen: dict[int, str] = {}
    for name, dof in named:
        if dof is None:
            continue
        k = dof_index(dof, name, system.n_dof)
        if k in seen:
            raise ValueError(f"`{name}` must differ from {seen[k]} (both are {k})")
        seen[k] = name


def _pendulum_vertical_spec(fp: FrictionPendulum) -> tuple:
    """The core spec of a `FrictionPendulum` with its vertical dof."""
    velocity = None
    if fp.mu_slow is not None and fp.rate > 0:
        velocity = (float(fp.mu_slow), float(fp.rate))
    pressure = None
    if fp.contact_area is not None:
        pressure = (float(fp.contact_area), float(fp.delta_mu), float(fp.pressure_alpha))
    return (
        "friction_pendulum_axial",
        fp._dofs(),
        float(fp.radius),
        float(fp.mu),
        float(fp.weight),
        float(fp.yield_displacement),
        float(fp.vertical_stiffness),  # type: ignore[arg-type]
        velocity,
        pressure,
    )

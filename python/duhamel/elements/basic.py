"""The basic force elements: polynomial and cubic springs, linear springs and dampers, the
linear coupling, the contact and the Python callable; exported from :mod:`duhamel.elements`.
"""

from __future__ import annotations

from collections.abc import Callable as CallableT
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.protocols import Model
from duhamel._engine.validate import (
    as_float_array,
    as_square_matrix,
    dof_index,
    finite_float,
    issparse,
)
from duhamel.elements.base import Deformation, Element, TwoAxis, nonneg, pair_stiffness

__all__ = [
    "Callable",
    "Contact",
    "Cubic",
    "Damper",
    "LinearCoupling",
    "Polynomial",
    "Spring",
]


_nonneg = nonneg


@dataclass(frozen=True)
class Polynomial(Element):
    """``r = sum_k coefficients[k] x^k`` at one degree of freedom.

    Examples
    --------
    >>> import duhamel
    >>> softening = duhamel.elements.Polynomial(0, [0.0, 0.0, 0.0, -0.5])
    """

    dof: int
    coefficients: tuple[float, ...]

    def __post_init__(self) -> None:
        c = as_float_array(self.coefficients, "coefficients", ndim=1)
        object.__setattr__(self, "coefficients", tuple(float(v) for v in c))

    def _validate(self, system: Model) -> None:
        dof_index(self.dof, "dof", system.n_dof)

    def _passive(self) -> bool:
        # a potential bounded below: odd powers with non-negative coefficients only
        c = np.asarray(self.coefficients, dtype=np.float64)
        return bool(np.all(c[0::2] == 0.0) and np.all(c[1::2] >= 0.0))

    def _tangent_bound(self) -> tuple[float, float] | None:
        c = np.asarray(self.coefficients, dtype=np.float64)
        return (abs(float(c[1])), 0.0) if np.all(c[2:] == 0.0) and c.size > 1 else None

    def _spec(self) -> tuple:
        return ("polynomial", int(self.dof), np.array(self.coefficients, dtype=np.float64))

    def _linear(self) -> tuple[tuple[int, ...], NDArray[np.float64]] | None:
        k = self.coefficients[1] if len(self.coefficients) > 1 else 0.0
        return ((int(self.dof),), np.array([[k]])) if k > 0 else None

    def _remainder_spec(self) -> tuple:
        c = np.array(self.coefficients, dtype=np.float64)
        c[1] = 0.0
        return ("polynomial", int(self.dof), c)


@dataclass(frozen=True)
class Cubic(Element):
    """Duffing spring to ground, ``r = k3 x^3`` (``k3 < 0`` softens).

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> duffing = duhamel.System(np.eye(1), np.eye(1)).add(duhamel.elements.Cubic(0, 4.0))
    """

    dof: int
    k3: float

    def __post_init__(self) -> None:
        finite_float(self.k3, "k3")

    def _validate(self, system: Model) -> None:
        dof_index(self.dof, "dof", system.n_dof)

    def _passive(self) -> bool:
        return float(self.k3) >= 0.0

    def _spec(self) -> tuple:
        return ("polynomial", int(self.dof), np.array([0.0, 0.0, 0.0, float(self.k3)]))


@dataclass(frozen=True)
class Spring(Deformation, Element):
    """Spring ``s = k d + k3 d^3`` on ``d = x_i - x_j`` (``j=None``: to ground).

    Examples
    --------
    >>> import duhamel
    >>> link = duhamel.elements.Spring(3, 4, k=0.0, k3=2e9)
    """

    i: int
    j: int | None = None
    k: float = 0.0
    k3: float = 0.0

    def __post_init__(self) -> None:
        finite_float(self.k, "k")
        finite_float(self.k3, "k3")

    def _passive(self) -> bool:
        return float(self.k) >= 0.0 and float(self.k3) >= 0.0

    def _tangent_bound(self) -> tuple[float, float] | None:
        return (abs(float(self.k)), 0.0) if self.k3 == 0.0 else None

    def _spec(self) -> tuple:
        j = None if self.j is None else int(self.j)
        return ("spring", int(self.i), j, float(self.k), float(self.k3))

    def _linear(self) -> tuple[tuple[int, ...], NDArray[np.float64]] | None:
        return pair_stiffness(self.i, self.j, float(self.k)) if self.k > 0 else None

    def _remainder_spec(self) -> tuple:
        j = None if self.j is None else int(self.j)
        return ("spring", int(self.i), j, 0.0, float(self.k3))


@dataclass(frozen=True)
class Damper(Deformation, Element):
    """Linear viscous damper ``c (v_i - v_j)`` (``j=None``: to ground).

    Examples
    --------
    >>> import duhamel
    >>> dashpot = duhamel.elements.Damper(0, c=0.2)
    """

    i: int
    j: int | None = None
    c: float = 0.0

    def __post_init__(self) -> None:
        _nonneg(self.c, "c")

    def _passive(self) -> bool:
        return float(self.c) >= 0.0

    def _tangent_bound(self) -> tuple[float, float] | None:
        return 0.0, abs(float(self.c))

    def _spec(self) -> tuple:
        j = None if self.j is None else int(self.j)
        return ("damper", int(self.i), j, float(self.c))


@dataclass(frozen=True, eq=False)
class LinearCoupling(Element):
    """Any linear stiffness ``K`` and/or damping ``C`` (n_dof x n_dof, dense or sparse, need
    not be symmetric) that the modes do not diagonalise: cross-coupled bearing stiffness
    (``k12 = -k21``), non-classical damping, gyroscopic ``speed * G``. Projected on the
    modes once; enters as a modal pseudo-force ``-(Phi^T K Phi q + Phi^T C Phi q')``.

    ``scale`` (optional) multiplies both by a speed law ``s(t)`` (:mod:`duhamel.speed`; a
    number is a constant factor): the force ``s(t) (K x + C x')``, e.g. the gyroscopic term
    ``omega(t) G x'`` of a run-up as ``LinearCoupling(C=G, scale=LinearRunUp(...))``. A
    constant scale is folded into the matrices; a time-varying one is evaluated wherever the
    integrator evaluates the force (the direct integrators assemble ``s(t) K`` and
    ``s(t) C`` into their iteration matrix at every step).

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> cross = duhamel.elements.LinearCoupling(K=np.array([[0.0, 1e7], [-1e7, 0.0]]))
    >>> G = np.array([[0.0, 0.4], [-0.4, 0.0]])
    >>> gyro = duhamel.elements.LinearCoupling(C=G, scale=duhamel.speed.LinearRunUp(0, 300, 5))
    """

    K: Any = None
    C: Any = None
    scale: Any = None

    def __post_init__(self) -> None:
        if self.K is None and self.C is None:
            raise ValueError("`LinearCoupling` needs `K`, `C` or both")
        for name in ("K", "C"):
            m = getattr(self, name)
            if m is not None and not issparse(m):
                object.__setattr__(self, name, as_float_array(m, name, ndim=2))
        if self.scale is not None:
            from duhamel.speed import as_speed_law

            object.__setattr__(self, "scale", as_speed_law(self.scale, "scale"))

    def constant_factor(self) -> float | None:
        """The factor multiplying ``K`` and ``C`` when it does not change with time (1 without
        a scale), else None."""
        return 1.0 if self.scale is None else self.scale.constant_value()

    def _validate(self, system: Model) -> None:
        for name in ("K", "C"):
            m = getattr(self, name)
            if m is not None and m.shape != (system.n_dof, system.n_dof):
                raise ValueError(
                    f"`{name}` of LinearCoupling must be ({system.n_dof}, {system.n_dof}), "
                    f"got {m.shape}"
                )
            if m is not None and issparse(m):
                as_square_matrix(m, name, n=system.n_dof)

    def modal(self, phi: NDArray[np.float64]) -> tuple[NDArray | None, NDArray | None]:
        """The modal matrices ``Phi^T K Phi`` and ``Phi^T C Phi`` (None where absent), without
        the scale."""
        return tuple(  # type: ignore[return-value]
            None if m is None else np.ascontiguousarray(phi.T @ (m @ phi)) for m in (self.K, self.C)
        )

    def _spec(self) -> tuple:  # projected in solve()
        return ("coupling",)


@dataclass(frozen=True)
class Contact(TwoAxis, Element):
    """Radial rub/impact of a shaft centre ``(x, y)`` in a stator of radial ``clearance``.

    Normal force ``stiffness * (rho - clearance)`` beyond the clearance (``rho`` the radial
    displacement), smoothed over ``smoothing`` (a length; default ``1e-3 * clearance``) so
    that Newton converges; Coulomb friction ``friction * F_n`` opposing the tangential
    (whirl) velocity, smoothed with ``tanh(v_t / velocity_smoothing)`` (default 1e-3 m/s).

    Examples
    --------
    >>> import duhamel
    >>> rub = duhamel.elements.Contact(0, 1, clearance=2e-4, stiffness=5e7, friction=0.2)
    """

    dof_x: int
    dof_y: int
    clearance: float
    stiffness: float
    friction: float = 0.0
    smoothing: float | None = None
    velocity_smoothing: float | None = None

    def __post_init__(self) -> None:
        g = _nonneg(self.clearance, "clearance")
        if finite_float(self.stiffness, "stiffness") <= 0:
            raise ValueError(f"`stiffness` must be positive, got {self.stiffness}")
        _nonneg(self.friction, "friction")
        if self.smoothing is None:
            # (at least the smallest normal number: a subnormal clearance must not give 0)
            object.__setattr__(
                self, "smoothing", max(1e-3 * g, np.finfo(float).tiny) if g > 0 else 1e-9
            )
        if self.velocity_smoothing is None:
            object.__setattr__(self, "velocity_smoothing", 1e-3)
        for name in ("smoothing", "velocity_smoothing"):
            if finite_float(getattr(self, name), name) <= 0:
                raise ValueError(f"`{name}` must be positive, got {getattr(self, name)}")

    def _passive(self) -> bool:
        # friction at a spinning shaft's surface can drive whirl: passive only without it
        return float(self.friction) == 0.0

    def _spec(self) -> tuple:
        return (
            "contact",
            int(self.dof_x),
            int(self.dof_y),
            float(self.clearance),
            float(self.stiffness),
            float(self.friction),
            float(self.smoothing),  # type: ignore[arg-type]
            float(self.velocity_smoothing),  # type: ignore[arg-type]
        )


@dataclass(frozen=True, eq=False)
class Callable(Element):
    """Escape hatch: ``fn(x, v, t)`` returns the restoring force at `dofs` (whole arrays of
    the local displacements and velocities); ``jacobian(x, v, t)`` may return
    ``(dr/dx, dr/dv)`` (square matrices), otherwise tangents come from finite differences.
    Called with the GIL once per evaluation, never per degree of freedom.

    **Your own hysteresis** (internal variables, OpenSees' trial/commit protocol): give
    `state`, the initial values of the element's internal variables (a 1-D array: plastic
    deformation, back force, the deformation they were committed at, ...). Then
    ``fn(x, v, t, state)`` receives the variables *committed at the start of the current
    step* (a copy: do not keep it) and returns ``(r, trial_state)``: the force at the trial
    state ``(x, v)`` reached from them, and the variables there. ``jacobian(x, v, t,
    state)`` likewise. The integrator calls `fn` as often as its Newton iterations need,
    always from the committed variables, and commits the trial variables of the step's end
    state once per accepted step (also after every substep of a subdivided step); so `fn`
    must be a pure function of its arguments. The committed force history is in
    ``Solution.elements`` (docs/structural.md).

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> hysteretic = duhamel.elements.Callable(lambda x, v, t: 0.1 * np.tanh(x / 1e-3), [0])
    >>> def elastoplastic(x, v, t, state, k=100.0, fy=1.0):
    ...     x_c, plastic = state                    # committed deformation and plastic part
    ...     trial = k * (x[0] - plastic)            # elastic predictor
    ...     if abs(trial) > fy:                     # return to the yield surface
    ...         plastic = x[0] - np.sign(trial) * fy / k
    ...         trial = np.sign(trial) * fy
    ...     return np.array([trial]), np.array([x[0], plastic])
    >>> epp = duhamel.elements.Callable(elastoplastic, [0], state=[0.0, 0.0])
    """

    fn: CallableT[[NDArray, NDArray, float], ArrayLike]
    dofs: tuple[int, ...]
    jacobian: CallableT[..., tuple[ArrayLike, ArrayLike]] | None = None
    state: ArrayLike | None = None

    def __post_init__(self) -> None:
        if self.state is not None:
            state = as_float_array(self.state, "state", ndim=1)
            if not state.size:
                raise ValueError("`state` must have at least one internal variable (or be None)")
            object.__setattr__(self, "state", tuple(float(s) for s in state))
        if not callable(self.fn):
            raise TypeError(f"`fn` must be callable, got {type(self.fn).__name__}")
        if self.jacobian is not None and not callable(self.jacobian):
            raise TypeError(f"`jacobian` must be callable, got {type(self.jacobian).__name__}")
        dofs = np.atleast_1d(np.asarray(self.dofs, dtype=object))
        if dofs.ndim != 1 or not dofs.size:
            raise ValueError(f"`dofs` must be a non-empty list of integers, got {self.dofs!r}")
        for d in dofs:
            if isinstance(d, bool | np.bool_) or not isinstance(d, int | np.integer):
                raise TypeError(f"`dofs` must contain integers, got {d!r}")
        object.__setattr__(self, "dofs", tuple(int(d) for d in dofs))

    def _validate(self, system: Model) -> None:
        for d in self.dofs:
            dof_index(d, "dofs", system.n_dof)
        if len(set(self.dofs)) != len(self.dofs):
            raise ValueError(f"`dofs` has duplicates: {list(self.dofs)}")

    def _spec(self) -> tuple:
        state = None if self.state is None else list(self.state)
        return ("callable", list(self.dofs), self.fn, self.jacobian, state)

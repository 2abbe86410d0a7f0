"""Linear couplings: any linear stiffness and/or damping the modes do not diagonalise
(cross-coupled bearing stiffness, non-classical damping, a gyroscopic ``omega(t) G``), held
by a system apart from its force elements (:attr:`duhamel.System.couplings`): projected on
the modes once, a modal pseudo-force of their own or a part of the first-order background.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel._engine.protocols import Model
from duhamel._engine.validate import as_float_array, as_square_matrix, issparse

__all__ = ["LinearCoupling"]


@dataclass(frozen=True, eq=False)
class LinearCoupling:
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

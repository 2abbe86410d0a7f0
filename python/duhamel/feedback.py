"""Linear feedback with states of its own (the controllers of active magnetic bearings):
first-order states ``z`` driven by the displacements that push back on the dofs,

    M x'' + C x' + K x + K_d x + F z = f,      z' = A z + B x.

A :class:`Feedback` added to a :class:`duhamel.System` joins its states to the model: the
semi-analytic integrator steps the closed loop — the system's modal coordinates and the
states together — exactly in its first-order modes (docs/coupled.md), and nonlinear elements
(a touchdown bearing's contact) act on it as pseudo-forces. It is a coupling, not a force
element: ``K_d`` is projected on the modes like a :class:`~duhamel.elements.LinearCoupling`'s
``K``, and the states enter the first-order modes (``duhamel._engine.coupled``).

Only :class:`duhamel.Semianalytic` integrates it (the direct integrators step second-order
equations); the states start at zero.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from duhamel._engine.protocols import Model
from duhamel._engine.validate import as_float_array
from duhamel.couplings import LinearCoupling

__all__ = ["Feedback"]


@dataclass(frozen=True, eq=False)
class Feedback(LinearCoupling):
    """States ``z`` (``n_z``) with ``z' = A z + B x`` that add ``K_d x + F z`` to the left-hand
    side of the equations of motion (see the module docstring).

    Parameters
    ----------
    K : array_like, shape (n_dof, n_dof)
        ``K_d``, the direct (static) feedback: a stiffness, need not be symmetric.
    A : array_like, shape (n_z, n_z)
        The states' dynamics.
    B : array_like, shape (n_z, n_dof)
        Their input: the displacements.
    F : array_like, shape (n_dof, n_z)
        Their force on the dofs (on the left-hand side: ``-F z`` pushes the dofs).

    Examples
    --------
    A damped mass on a spring held by a proportional-integral controller on its
    displacement: ``m x'' + c x' + k x + k_p x + k_i z = f``, ``z' = x``.

    >>> import numpy as np, duhamel
    >>> from duhamel.feedback import Feedback
    >>> system = duhamel.System(np.eye(1), np.array([[100.0]]), np.array([[20.0]]))
    >>> _ = system.add(Feedback(K=[[50.0]], A=[[0.0]], B=[[1.0]], F=[[400.0]]))
    >>> _ = system.add_load(duhamel.loads.Step(0, amplitude=1.0))
    >>> sol = duhamel.solve(system, duhamel.Semianalytic(), t_end=30.0, dt=0.01)
    >>> bool(abs(sol.x[-1, 0]) < 1e-6)   # the integrator removes the static offset
    True
    """

    A: Any = None
    B: Any = None
    F: Any = None

    def __post_init__(self) -> None:
        if self.K is None:
            raise ValueError("`K` of Feedback is required (the direct feedback; zeros if none)")
        if self.C is not None or self.scale is not None:
            raise ValueError("Feedback takes `K`, `A`, `B` and `F` (no `C`, no `scale`)")
        super().__post_init__()
        A = as_float_array(self.A, "A", ndim=2)
        n_z = A.shape[0]
        if A.shape != (n_z, n_z) or n_z == 0:
            raise ValueError(f"`A` must be square with at least one state, got {A.shape}")
        B = as_float_array(self.B, "B", ndim=2)
        F = as_float_array(self.F, "F", ndim=2)
        n = self.K.shape[0]
        if B.shape != (n_z, n):
            raise ValueError(f"`B` must have shape (n_z, n_dof) = {(n_z, n)}, got {B.shape}")
        if F.shape != (n, n_z):
            raise ValueError(f"`F` must have shape (n_dof, n_z) = {(n, n_z)}, got {F.shape}")
        for name, m in (("A", A), ("B", B), ("F", F)):
            m.setflags(write=False)
            object.__setattr__(self, name, m)

    @property
    def n_states(self) -> int:
        """Number of feedback states."""
        return int(self.A.shape[0])

    def __repr__(self) -> str:
        return f"Feedback(n_dof={self.K.shape[0]}, n_states={self.n_states})"

    def _validate(self, system: Model) -> None:
        super()._validate(system)

    def _passive(self) -> bool:
        return False

    def modal_states(self, phi: Any) -> tuple[Any, Any, Any]:
        """``(A, B Phi, Phi^T F)``: the states' coupling to the modal coordinates."""
        phi = np.asarray(phi, dtype=float)
        return self.A, np.ascontiguousarray(self.B @ phi), np.ascontiguousarray(phi.T @ self.F)

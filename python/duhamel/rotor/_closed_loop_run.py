"""A closed loop's transient with duhamel elements on top (a rub :class:`~duhamel.elements.
Contact`, a cubic bearing, any element): the Rust core's first-order route, its background
the closed loop's own first-order modes (rotor and controller states), the elements'
forces its pseudo-forces (the corrector of ``pseudo/first_order/``, scheme b, trapezoid).

The closed loop ``s' = A s + B_f f`` (``B_f`` the ``M^-1`` columns in the velocity rows) is
balanced (``A_b = T^-1 A T``, ``T`` diagonal, ``scipy.linalg.matrix_balance``) and
decomposed, ``A_b = V diag(lambda) V^-1``; one of each conjugate pair is kept, so that
``s = T sum_k w_k Re(V_k eta_k)`` (``w_k`` 2 for a pair, 1 for a real eigenvalue). The core
sees a modal model with the rotor's dofs as its "modes" (``phi = I``): the gains
``V^-1 T^-1 B_f`` drive ``eta`` by the physical forces, and ``back`` maps ``eta`` to
``(x, x')``, where the elements are evaluated. The linear closed loop is stepped exactly;
only the elements' forces are approximated (second order in the step).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel import _core
from duhamel._core import Element
from duhamel._engine.run import raise_failure
from duhamel._engine.validate import positive_float, positive_int

__all__ = ["CONDITION_LIMIT", "transient_with_elements"]

#: Largest condition number of the balanced eigenvector matrix accepted (about ``1e-16
#: kappa^2`` relative error: 1e-8 here).
CONDITION_LIMIT = 1e4


def transient_with_elements(
    A: NDArray[np.float64],
    B_f: NDArray[np.float64],
    s0: NDArray[np.float64],
    t: NDArray[np.float64],
    forces: NDArray[np.float64],
    dofs: Sequence[int],
    elements: Sequence[Any],
    *,
    tol: float,
    max_iter: int,
) -> NDArray[np.float64]:
    """States ``(len(t), n_states)`` of ``s' = A s + B_f (f_elements + f)``, `forces`
    ``(len(t), len(dofs))`` linear between the samples `t` (equally spaced)."""
    import scipy.linalg

    tol = positive_float(tol, "tol")
    max_iter = positive_int(max_iter, "max_iter")
    n = B_f.shape[1]
    for e in elements:
        if not isinstance(e, Element):
            raise TypeError(f"`elements` must hold duhamel elements, got {type(e).__name__}")
    core_elements = list(elements)
    _, (scale, _) = scipy.linalg.matrix_balance(A, permute=False, separate=True)
    Ab = A * scale[None, :] / scale[:, None]
    lam, V = scipy.linalg.eig(Ab, check_finite=False)
    try:
        W = scipy.linalg.inv(V, check_finite=False)
    except (np.linalg.LinAlgError, ValueError):
        W = np.full_like(V, np.nan)
    condition = (
        float(np.linalg.norm(V, 1) * np.linalg.norm(W, 1)) if np.all(np.isfinite(W)) else np.inf
    )
    if condition > CONDITION_LIMIT or int((lam.imag > 0).sum()) != int((lam.imag < 0).sum()):
        raise ValueError(
            f"the closed loop's first-order modes are ill-conditioned (condition number "
            f"{condition:.3g} > {CONDITION_LIMIT:g}: a nearly defective closed loop); "
            "transients with elements need well-separated closed-loop modes"
        )
    keep = np.flatnonzero(lam.imag >= 0.0)
    Vk = (V[:, keep] * np.where(lam.imag[keep] == 0.0, 1.0, 2.0)) * scale[:, None]
    Wk = W[keep] / scale[None, :]
    back = np.concatenate([Vk.real.T[:, : 2 * n], -Vk.imag.T[:, : 2 * n]])
    gain = Wk @ B_f
    c = np.ascontiguousarray
    corrector = _core.Corrector(core_elements, c(back), tol, max_iter, None)
    route = _core.FirstOrderRoute(
        c(lam[keep].real), c(lam[keep].imag), c(gain.real), c(gain.imag), corrector
    )
    loads = []
    for k, j in enumerate(dofs):
        pattern = np.zeros(n)
        pattern[int(j)] = 1.0
        values = np.ascontiguousarray(forces[:, k], dtype=np.float64)
        time = _core.TimeFunction.table(np.ascontiguousarray(t, dtype=np.float64), values, True)
        loads.append(_core.Load(pattern, time))
    model = _core.ModalModel(np.ones(n), np.zeros(n), np.eye(n), loads, route)
    h = float(t[1] - t[0])
    eta = Wk @ s0
    spec = _core.RunSpec(
        _core.Grid(float(t[0]), h, t.size - 1, 1, 0, 1),
        c(s0[:n]),
        c(s0[n : 2 * n]),
        c(np.concatenate([eta.real, eta.imag])),
    )
    result = model.run(spec, None, None, None, None)
    r = keep.size
    eta_t = result.eta[:, :r] + 1j * result.eta[:, r:]
    states = np.asarray((eta_t @ Vk.T).real, dtype=np.float64)
    if result.error is not None:
        raise_failure(result.error, states)
    return states

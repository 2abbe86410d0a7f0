"""Modes with force elements whose initial tangent is not symmetric (issue 36: the P-Delta
moments of an imported elastomeric bearing): ``System.modal(elements="initial")`` solves the
general eigenproblem of ``(K + the elements' tangent at x = 0, M)`` as OpenSees' ``eigen``
does on its tangent (tests/opensees/test_opensees_isolated.py compares the two); here
against an independent route, the static condensation of the massless dof and the
eigenvalues of ``M^-1 K_condensed``."""

from __future__ import annotations

import numpy as np
import pytest

import duhamel
from duhamel.elements import Callable

M = np.diag([2.0, 1.0, 0.0])  # the third dof massless (a rotation, as in a frame)
K = np.array([[300.0, -100.0, 20.0], [-100.0, 100.0, -10.0], [20.0, -10.0, 50.0]])
SKEW = np.array([[0.0, 0.0], [-8.0, 0.0]])  # moment on dof 2 from the shear at dof 0


def _system(
    jacobian: bool = True, skew: np.ndarray = SKEW, dofs: tuple[int, int] = (0, 2)
) -> duhamel.System:
    s = duhamel.System(M, K, zeta=0.02)
    s.add(
        Callable(
            list(dofs),
            lambda x, v, t: skew @ x,
            (lambda x, v, t: (skew.copy(), np.zeros((2, 2)))) if jacobian else None,
        )
    )
    return s


def test_periods_equal_the_condensed_general_problem() -> None:
    total = K.copy()
    total[np.ix_([0, 2], [0, 2])] += SKEW
    # condense the massless dof 2: K_mm - K_ms K_ss^-1 K_sm (not symmetric)
    condensed = total[:2, :2] - np.outer(total[:2, 2], total[2, :2]) / total[2, 2]
    want = np.sort(np.linalg.eigvals(np.linalg.solve(M[:2, :2], condensed)).real)
    basis = _system().modal(elements="initial")
    np.testing.assert_allclose(basis.omega2, want, rtol=1e-12)
    assert "not symmetric" in basis.summary()
    # each mode satisfies (K + k) phi = omega^2 M phi and is mass-normalised
    for i in range(2):
        phi = basis.phi[:, i]
        np.testing.assert_allclose(total @ phi, basis.omega2[i] * (M @ phi), atol=1e-9 * 300)
        assert phi @ M @ phi == pytest.approx(1.0, rel=1e-12)
    # the modes of K alone (the default) are unchanged by the element
    np.testing.assert_allclose(
        _system().modal().omega2, duhamel.System(M, K, zeta=0.02).modal().omega2, rtol=0
    )


def test_a_callable_without_jacobian_or_with_circulatory_tangent_is_refused() -> None:
    with pytest.raises(ValueError, match="`jacobian`"):
        _system(jacobian=False).modal(elements="initial")
    with pytest.raises(ValueError, match="Callable defines no effective stiffness"):
        _system().modal(elements="effective", displacement=0.1)
    circulatory = np.array([[0.0, 400.0], [-400.0, 0.0]])  # complex modes (flutter)
    with pytest.raises(ValueError, match="not real and positive"):
        _system(skew=circulatory, dofs=(0, 1)).modal(elements="initial")

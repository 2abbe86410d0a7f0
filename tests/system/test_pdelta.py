"""P-Delta: the geometric stiffness of gravity loads, exact in the linear part."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg
import scipy.sparse as sp
from _frames import moment_frame

import duhamel

H = 3.2


def _shear_building(n: int = 4):
    m = 5e4 * np.ones(n)
    k = 6e7 * np.ones(n)
    K = np.diag(k + np.r_[k[1:], 0.0]) - np.diag(k[1:], 1) - np.diag(k[1:], -1)
    return np.diag(m), K


def _storey_loads(n: int) -> np.ndarray:
    """The gravity load each storey carries: the weight of the floors above it."""
    return 9.81 * 5e4 * np.arange(n, 0, -1)


def _hand_kg(n: int, P: np.ndarray) -> np.ndarray:
    """K_g assembled independently: storey s (between floors s-1 and s) adds P_s / H on the
    2x2 block of its two floors (only the top floor's entry at the ground storey)."""
    Kg = np.zeros((n, n))
    for s in range(n):
        g = P[s] / H
        Kg[s, s] += g
        if s > 0:
            Kg[s - 1, s - 1] += g
            Kg[s, s - 1] -= g
            Kg[s - 1, s] -= g
    return Kg


@pytest.mark.parametrize("sparse", [False, True])
def test_pdelta_storeys_equal_an_independently_assembled_k_minus_kg(sparse):
    n = 4
    M, K = _shear_building(n)
    P = _storey_loads(n)
    t = np.arange(0.0, 5.0, 0.01)
    ag = 3.0 * np.sin(2 * np.pi * 0.9 * t)
    mats = (sp.csr_array(M), sp.csr_array(K)) if sparse else (M, K)
    system = duhamel.System(*mats, zeta=0.05)
    for s in range(n):
        system.add(duhamel.elements.PDelta(s, None if s == 0 else s - 1, P=P[s], height=H))
    reference = duhamel.System(M, K - _hand_kg(n, P), zeta=0.05)
    for sys_ in (system, reference):
        sys_.add_load(duhamel.loads.BaseAcceleration(np.ones(n), t=t, values=ag))
    K_now = system.K.toarray() if sparse else system.K
    assert np.allclose(K_now, K - _hand_kg(n, P), rtol=0, atol=1e-6)
    assert system.is_sparse == sparse
    w_ref = np.sqrt(scipy.linalg.eigh(K - _hand_kg(n, P), M, eigvals_only=True))
    assert np.allclose(system.modal().omega, w_ref, rtol=1e-12)
    a = duhamel.solve(system, duhamel.Semianalytic(), t_end=5.0, dt=0.01)
    b = duhamel.solve(reference, duhamel.Semianalytic(), t_end=5.0, dt=0.01)
    assert np.abs(a.x - b.x).max() <= 1e-12 * np.abs(b.x).max()
    # and it softens: the periods lengthen, the drifts grow
    plain = duhamel.System(M, K, zeta=0.05)
    assert np.all(system.modal().omega < plain.modal().omega)


def test_add_geometric_stiffness_on_direct_and_massless_models():
    M, K, sway = moment_frame(3, 2)
    Kg = np.zeros_like(K)
    P = 2e6
    for s, i in enumerate(sway):  # storey leaning columns on the sway dofs
        Kg[i, i] += P / H
        if s > 0:
            j = sway[s - 1]
            Kg[j, j] += P / H
            Kg[i, j] -= P / H
            Kg[j, i] -= P / H
    system = duhamel.System(M, K, zeta=0.05).add_geometric_stiffness(Kg)
    assert np.allclose(system.K, K - Kg)
    reference = duhamel.System(M, K - Kg, zeta=0.05)
    assert np.allclose(system.modal().omega, reference.modal().omega, rtol=1e-12)
    x0 = np.zeros(M.shape[0])
    x0[sway] = 0.01 * np.arange(1, 4)
    a = duhamel.solve(system, duhamel.Newmark(), t_end=1.0, dt=0.001, x0=x0)
    b = duhamel.solve(reference, duhamel.Newmark(), t_end=1.0, dt=0.001, x0=x0)
    assert np.abs(a.x - b.x).max() <= 1e-12 * np.abs(b.x).max()


def test_buckling_and_bad_input_refused():
    M, K = _shear_building(2)
    system = duhamel.System(M, K)
    with pytest.raises(ValueError, match=r"`Kg`.*buckling"):
        system.add_geometric_stiffness(1e9 * np.eye(2))
    with pytest.raises(ValueError, match="`Kg` must be symmetric"):
        system.add_geometric_stiffness(np.array([[0.0, 1.0], [0.0, 0.0]]))
    with pytest.raises(ValueError, match="`height` must be > 0"):
        duhamel.elements.PDelta(0, None, P=1.0, height=0.0)
    with pytest.raises(ValueError, match="`j` must differ"):
        system.add(duhamel.elements.PDelta(1, 1, P=1.0, height=1.0))

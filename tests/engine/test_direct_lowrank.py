"""Reference integrators on sparse models with elements (issue 12): the linear part is
factorised once and the elements' tangents enter as a low-rank (Woodbury) update. The
iterates are those of full Newton, so a sparse run equals the same run on dense matrices
(refactorised every step) to round-off, for elastic, contact and velocity elements and
every method of the family (hysteretic elements are not yet committed by these integrators)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from _models import grounded_chain

import duhamel
from duhamel import elements as E
from duhamel import loads as L

N = 40


def chain(n: int = N, k: float = 4e4) -> np.ndarray:
    return grounded_chain(n, k)


def model(sparse: bool) -> duhamel.System:
    M, K = np.diag(np.linspace(1.0, 2.0, N)), chain()
    if sparse:
        M, K = sp.csr_array(M), sp.csr_array(K)
    s = duhamel.System(M, K, rayleigh=(0.1, 1e-4))
    s.add(E.Spring(5, k=2e4, k3=4e10))
    s.add(E.Spring(12, 11, k=3e4, k3=1e12))
    s.add(E.Gap(20, gap=1e-3, k=5e4))
    s.add(E.ViscousDamper(30, 29, c=200.0, exponent=0.6))
    t = np.linspace(0.0, 3.0, 601)
    s.add_load(
        L.BaseAcceleration(np.ones(N), t=t, values=60.0 * np.sin(9.0 * t) * np.minimum(t, 1.0))
    )
    return s


@pytest.mark.parametrize(
    "integrator",
    [duhamel.Newmark(), duhamel.HHT(alpha=-0.1), duhamel.GeneralizedAlpha(rho_inf=0.8)],
    ids=["newmark", "hht", "generalized-alpha"],
)
def test_sparse_low_rank_equals_dense_refactorisation(integrator) -> None:
    kw = {"t_end": 3.0, "dt": 0.005}
    sparse = duhamel.solve(model(True), integrator, **kw)
    dense = duhamel.solve(model(False), integrator, **kw)
    scale = np.abs(dense.x).max()
    x5 = np.abs(dense.x[:, 5]).max()
    assert 4e10 * x5**3 > 2e4 * x5  # the cubic term dominates: well into the nonlinear range
    assert np.abs(sparse.x - dense.x).max() <= 1e-10 * scale
    assert np.abs(sparse.v - dense.v).max() <= 1e-10 * np.abs(dense.v).max()
    assert sparse.stats.factorizations == 1  # the linear part, once
    assert dense.stats.factorizations >= sparse.stats.steps
    # the same Newton iterations: the update is exact, not a modified Newton
    assert sparse.stats.newton_iterations == dense.stats.newton_iterations
    assert np.abs(dense.x[:, 20]).max() > 1e-3  # the gap closed


def test_many_element_dofs_fall_back_to_refactorisation() -> None:
    """Elements on more than a quarter of the dofs: the full matrix is refactorised."""
    M, K = sp.identity(8, format="csr"), sp.csr_array(chain(8))
    s = duhamel.System(M, K, zeta=0.02)
    for d in range(4):
        s.add(E.Spring(d, k=1e3, k3=1e9))
    sol = duhamel.solve(s, duhamel.Newmark(), t_end=0.2, dt=0.01, x0=np.full(8, 1e-3))
    assert sol.stats.factorizations >= sol.stats.steps

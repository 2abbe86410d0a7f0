"""Tests for duhamel.system (System, ModalBasis) and the duhamel._engine.validate helpers."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from duhamel._engine import validate as v
from duhamel.system import ModalBasis, System

# ------------------------------------------------------------------------------ fixtures


def chain_k(springs: np.ndarray, grounded: bool = True) -> np.ndarray:
    """Stiffness of a spring chain; springs[0] goes to ground if `grounded`."""
    springs = np.asarray(springs, dtype=float)
    n = springs.size if grounded else springs.size + 1
    K = np.zeros((n, n))
    for i, k in enumerate(springs):
        a, b = (i - 1, i) if grounded else (i, i + 1)
        if a >= 0:
            K[a, a] += k
            K[a, b] -= k
            K[b, a] -= k
        K[b, b] += k
    return K


def sparse_chain(n: int, grounded: bool, masses: np.ndarray | None = None):
    k = 1e4 * (1.0 + 0.3 * np.sin(np.arange(n)))  # non-uniform springs
    K = chain_k(k if grounded else k[: n - 1], grounded=grounded)
    m = np.linspace(1.0, 2.0, n) if masses is None else masses
    return sp.csr_array(np.diag(m)), sp.csr_array(K)


@pytest.fixture
def chain3() -> tuple[np.ndarray, np.ndarray]:
    M = np.diag([1.0, 2.0, 3.0])
    K = chain_k([100.0, 200.0, 300.0])
    return M, K


# ------------------------------------------------------------------------------ eigenvalues


def test_chain_eigenvalues_match_numpy(chain3):
    M, K = chain3
    basis = System(M, K).modal()
    ref = np.sort(np.linalg.eigvals(np.linalg.solve(M, K)).real)
    np.testing.assert_allclose(basis.omega2, ref, rtol=1e-12)
    np.testing.assert_allclose(basis.omega, np.sqrt(ref), rtol=1e-12)
    assert isinstance(basis, ModalBasis) and basis.n_modes == 3


def test_uniform_chain_closed_form():
    n, k, m = 3, 50.0, 2.0
    basis = System(m * np.eye(n), chain_k([k] * n)).modal()
    j = np.arange(1, n + 1)
    exact = 4 * k / m * np.sin((2 * j - 1) * np.pi / (2 * (2 * n + 1))) ** 2
    np.testing.assert_allclose(basis.omega2, exact, rtol=1e-13)


def test_mass_normalisation_and_orthogonality(chain3):
    M, K = chain3
    basis = System(M, K).modal()
    phi = basis.phi
    assert phi.shape == (3, 3) and phi.dtype == np.float64 and phi.flags.c_contiguous
    np.testing.assert_allclose(phi.T @ M @ phi, np.eye(3), atol=1e-12)
    np.testing.assert_allclose(phi.T @ K @ phi, np.diag(basis.omega2), atol=1e-12 * K.max())


def test_sign_convention_and_readonly(chain3):
    basis = System(*chain3).modal()
    for col in basis.phi.T:
        assert col[np.argmax(np.abs(col))] > 0
    for arr in (basis.phi, basis.omega2, basis.omega, basis.c, basis.zeta):
        assert not arr.flags.writeable


def test_modal_cache_and_subset(chain3):
    system = System(*chain3)
    assert system.modal() is system.modal(3)
    two = system.modal(2)
    assert two.phi.shape == (3, 2)
    np.testing.assert_allclose(two.omega2, system.modal().omega2[:2], rtol=1e-12)
    np.testing.assert_allclose(two.phi, system.modal().phi[:, :2], atol=1e-12)


def test_free_free_rigid_body_mode_with_rayleigh():
    alpha, beta = 0.3, 2e-3
    M = np.diag([1.0, 2.0, 1.5])
    K = chain_k([100.0, 250.0], grounded=False)
    basis = System(M, K, rayleigh=(alpha, beta)).modal()
    assert basis.omega2[0] == 0.0 and basis.omega[0] == 0.0
    assert basis.omega2[1] > 0
    assert basis.c[0] == alpha and basis.zeta[0] == 0.0
    np.testing.assert_allclose(basis.c, alpha + beta * basis.omega2, rtol=1e-14)
    np.testing.assert_allclose(basis.zeta[1:], basis.c[1:] / (2 * basis.omega[1:]), rtol=1e-14)
    rigid = basis.phi[:, 0]
    np.testing.assert_allclose(rigid, rigid[0] * np.ones(3), rtol=1e-10)  # translation
    np.testing.assert_allclose(basis.phi.T @ M @ basis.phi, np.eye(3), atol=1e-12)


# ------------------------------------------------------------------------------ sparse input


@pytest.mark.parametrize("grounded", [True, False])
def test_sparse_reduced_matches_dense(grounded):
    M, K = sparse_chain(200, grounded)
    system = System(M, K)
    assert system.is_sparse and sp.issparse(system.M) and sp.issparse(system.K)
    assert system.M.format == "csr" and system.K.dtype == np.float64
    sparse_basis = system.modal(6)
    dense_basis = System(M.toarray(), K.toarray()).modal()
    ref = dense_basis.omega2[:6]
    if grounded:
        np.testing.assert_allclose(sparse_basis.omega2, ref, rtol=1e-8)
    else:
        assert sparse_basis.omega2[0] == 0.0 and dense_basis.omega2[0] == 0.0
        np.testing.assert_allclose(sparse_basis.omega2[1:], ref[1:], rtol=1e-8)
    phi = sparse_basis.phi
    assert phi.shape == (200, 6) and phi.flags.c_contiguous
    np.testing.assert_allclose(phi.T @ (M @ phi), np.eye(6), atol=1e-12)
    np.testing.assert_allclose(phi, dense_basis.phi[:, :6], atol=1e-7)


def test_sparse_full_basis_uses_dense_solver():
    M, K = sparse_chain(20, grounded=False)
    basis = System(M, K, zeta=0.02).modal(19)  # n_modes >= n_dof - 1 -> dense eigh
    np.testing.assert_allclose(basis.omega2, System(M.toarray(), K.toarray()).modal(19).omega2)
    assert basis.omega2[0] == 0.0 and basis.c[0] == 0.0


def test_sparse_coo_and_matrix_flavours_are_kept():
    Md, Kd = sparse_chain(10, grounded=True)
    system = System(sp.coo_matrix(Md.toarray()), sp.csc_array(Kd))
    assert isinstance(system.M, sp.spmatrix) and system.M.format == "csr"
    assert isinstance(system.K, sp.sparray) and system.K.format == "csr"


def test_large_sparse_mass_uses_lu_check():
    n = v.DENSE_CHOLESKY_MAX_N + 500
    main, off = 4.0 * np.ones(n), np.ones(n - 1)
    M = sp.diags_array([off, main, off], offsets=[-1, 0, 1], format="csr")  # consistent-like
    K = sp.diags_array([-off, 2 * main, -off], offsets=[-1, 0, 1], format="csr")
    System(M, K)  # positive definite: accepted
    bad = M - sp.diags_array([np.r_[np.zeros(n - 1), 3.9]], offsets=[0])  # last pivot < 0
    with pytest.raises(ValueError, match=r"`M`.*positive definite"):
        System(bad, K)


def test_sparse_indefinite_k_detected_in_reduced_solve():
    M, K = sparse_chain(50, grounded=True)
    K = K.tolil()
    K[0, 1] = K[1, 0] = -1e5  # diagonal stays positive, K becomes indefinite
    system = System(M, K.tocsr())
    with pytest.raises(ValueError, match="`K` must be positive semidefinite"):
        system.modal(4)


# ------------------------------------------------------------------------------ damping


def test_undamped(chain3):
    system = System(*chain3)
    basis = system.modal()
    assert system.damping == "none" and system.C is None
    assert np.all(basis.c == 0.0) and np.all(basis.zeta == 0.0)


def test_scalar_zeta(chain3):
    system = System(*chain3, zeta=0.05)
    basis = system.modal()
    assert system.damping == "zeta" and system.zeta == 0.05
    np.testing.assert_allclose(basis.zeta, 0.05, rtol=1e-14)
    np.testing.assert_allclose(basis.c, 0.1 * basis.omega, rtol=1e-14)


def test_negative_zeta_allowed(chain3):
    basis = System(*chain3, zeta=-0.01).modal()
    np.testing.assert_allclose(basis.zeta, -0.01, rtol=1e-14)


def test_zeta_array_per_mode(chain3):
    zeta = [0.01, 0.02, 0.03]
    basis = System(*chain3, zeta=zeta).modal()
    np.testing.assert_allclose(basis.zeta, zeta, rtol=1e-14)
    reduced = System(*chain3, zeta=[0.01, 0.02]).modal(2)
    np.testing.assert_allclose(reduced.zeta, [0.01, 0.02], rtol=1e-14)


def test_rayleigh(chain3):
    system = System(*chain3, rayleigh=(0.5, 1e-3))
    basis = system.modal()
    assert system.damping == "rayleigh" and system.rayleigh == (0.5, 1e-3)
    np.testing.assert_allclose(basis.c, 0.5 + 1e-3 * basis.omega2, rtol=1e-14)
    np.testing.assert_allclose(basis.zeta, basis.c / (2 * basis.omega), rtol=1e-14)


@pytest.mark.parametrize("as_sparse", [False, True])
def test_proportional_damping_matrix(chain3, as_sparse):
    M, K = chain3
    C = 0.5 * M + 1e-3 * K
    system = System(M, K, sp.csr_array(C) if as_sparse else C)
    assert system.damping == "matrix" and system.C is not None
    np.testing.assert_allclose(
        system.modal().c, System(M, K, rayleigh=(0.5, 1e-3)).modal().c, rtol=1e-12
    )


def test_general_classical_damping_matrix(chain3):
    M, K = chain3
    phi = System(M, K).modal().phi
    d = np.array([0.7, 0.1, 3.0])  # not Rayleigh-shaped
    C = M @ phi @ np.diag(d) @ phi.T @ M
    np.testing.assert_allclose(System(M, K, C).modal().c, d, rtol=1e-10)


def test_degenerate_modes_are_rotated_to_diagonalise_c():
    C = np.array([[1.0, 0.5], [0.5, 2.0]])  # commutes with K = M = I: classical
    basis = System(np.eye(2), np.eye(2), C).modal()
    np.testing.assert_allclose(np.sort(basis.c), np.linalg.eigvalsh(C), rtol=1e-12)
    np.testing.assert_allclose(basis.phi.T @ C @ basis.phi, np.diag(basis.c), atol=1e-12)
    np.testing.assert_allclose(basis.omega2, [1.0, 1.0], rtol=1e-14)


def test_rigid_body_mode_with_mass_proportional_c_matrix():
    M = np.diag([1.0, 2.0, 1.5])
    K = chain_k([100.0, 250.0], grounded=False)
    basis = System(M, K, 0.3 * M).modal()
    assert basis.omega2[0] == 0.0
    np.testing.assert_allclose(basis.c, 0.3, rtol=1e-12)
    assert basis.zeta[0] == 0.0


def test_non_classical_c_splits_into_background_and_coupling(chain3):
    M, K = chain3
    C = np.zeros((3, 3))
    C[0, 0] = 5.0  # single dashpot at dof 0: not diagonalised by the modes
    for n in (None, 2):  # the split uses the retained modes
        basis = System(M, K, C).modal(n)
        cm = basis.phi.T @ C @ basis.phi
        np.testing.assert_allclose(basis.c, np.diag(cm), rtol=1e-12)
        assert basis.c_coupling is not None
        np.testing.assert_allclose(basis.c_coupling, cm - np.diag(np.diag(cm)), atol=1e-12)
    classical = System(M, K, 0.1 * np.asarray(M) + 0.01 * np.asarray(K)).modal()
    assert classical.c_coupling is None


# ------------------------------------------------------------------------------ loads, repr


def test_add_load_chains_and_validates(chain3):
    from duhamel.loads import Harmonic, Step

    system = System(*chain3, rayleigh=(0.1, 0.0))
    assert (
        system.add_load(Step(0, amplitude=1.0)).add_load(Harmonic(2, amplitude=1.0, omega=3.0))
        is system
    )
    assert len(system.loads) == 2 and isinstance(system.loads, list)
    assert repr(system) == "System(n_dof=3, damping='rayleigh', loads=2)"
    with pytest.raises(ValueError, match=r"`dof` must be .*\[0, 2\]"):
        system.add_load(Step(3, amplitude=1.0))
    with pytest.raises(ValueError, match="`dof`"):
        system.add_load(Step(-1, amplitude=1.0))
    assert len(system.loads) == 2
    with pytest.raises(TypeError, match="`load`"):
        system.add_load(object())
    assert len(system.loads) == 2


def test_attributes(chain3):
    M, K = chain3
    system = System(M.astype(np.int64), K.astype(np.float32), zeta=[0.1, 0.2, 0.3])
    assert system.n_dof == 3
    assert system.M.dtype == np.float64 and system.K.dtype == np.float64
    np.testing.assert_array_equal(system.M, M)
    assert not system.M.flags.writeable
    assert system.rayleigh is None and system.C is None
    np.testing.assert_array_equal(system.zeta, [0.1, 0.2, 0.3])


# ------------------------------------------------------------------------------ bad input

M3 = np.diag([1.0, 2.0, 3.0])
K3 = chain_k([100.0, 200.0, 300.0])


@pytest.mark.parametrize(
    ("kwargs", "exc", "pattern"),
    [
        ({"M": np.ones(3)}, ValueError, "`M` must be a 2-D"),
        ({"M": np.ones((3, 4))}, ValueError, r"`M` must be a square matrix, got shape \(3, 4\)"),
        ({"K": np.eye(4)}, ValueError, r"`K` must have shape \(3, 3\) to match `M`"),
        ({"K": np.ones((3, 2))}, ValueError, "`K` must be a square matrix"),
        ({"M": np.zeros((0, 0)), "K": np.zeros((0, 0))}, ValueError, "`M`"),
        ({"M": M3 + np.triu(np.ones((3, 3)), 1)}, ValueError, "`M` must be symmetric"),
        ({"K": K3 + np.triu(np.ones((3, 3)), 1)}, ValueError, "`K` must be symmetric"),
        ({"C": np.triu(np.ones((3, 3)))}, ValueError, "`C` must be symmetric"),
        ({"C": np.eye(2)}, ValueError, r"`C` must have shape \(3, 3\)"),
        ({"M": np.diag([1.0, -2.0, 3.0])}, ValueError, "`M` must be positive definite"),
        # a zero diagonal entry is a massless dof (issue 25), but not with a nonzero row
        (
            {"M": np.array([[1, 0.5, 0], [0.5, 0, 0], [0, 0, 3.0]])},
            ValueError,
            "`M` must be positive",
        ),
        ({"M": np.array([[1, 2, 0], [2, 1, 0], [0, 0, 1.0]])}, ValueError, "`M` must be positive"),
        ({"M": np.array([[1, 1, 0], [1, 1, 0], [0, 0, 1.0]])}, ValueError, "`M` must be positive"),
        ({"K": -K3}, ValueError, "`K` must be positive semidefinite"),
        ({"M": np.where(M3 == 2.0, np.nan, M3)}, ValueError, r"`M` contains NaN or inf at index"),
        ({"K": np.where(K3 == 300.0, np.inf, K3)}, ValueError, r"`K` contains NaN or inf"),
        ({"C": np.full((3, 3), np.nan)}, ValueError, r"`C` contains NaN or inf at index \(0, 0\)"),
        ({"M": M3.astype(complex)}, TypeError, "`M` must contain real numbers.*complex"),
        ({"K": sp.csr_array(K3.astype(complex))}, TypeError, "`K`.*complex"),
        ({"M": "mass"}, TypeError, "`M`"),
        ({"K": [["a", "b"], ["c", "d"]]}, TypeError, "`K`"),
        ({"M": M3.astype(bool)}, TypeError, "`M`.*bool"),
        ({"M": [[1.0, 0.0], [0.0]]}, ValueError, "`M`"),
        ({"zeta": 0.05, "rayleigh": (0.1, 0.0)}, ValueError, "`zeta` and `rayleigh`"),
        ({"C": M3, "zeta": 0.05}, ValueError, "`C` and `zeta`"),
        ({"zeta": "0.05"}, TypeError, "`zeta`"),
        ({"zeta": True}, TypeError, "`zeta`"),
        ({"zeta": np.nan}, ValueError, "`zeta` must be finite"),
        ({"zeta": [0.1, np.inf]}, ValueError, "`zeta` contains NaN or inf at index 1"),
        ({"zeta": [0.1, 0.1, 0.1, 0.1]}, ValueError, "`zeta` must have one entry per mode"),
        ({"zeta": [[0.1]]}, ValueError, "`zeta` must be a 1-D"),
        ({"zeta": 0.1j}, TypeError, "`zeta`"),
        ({"rayleigh": (0.1,)}, ValueError, r"`rayleigh` must have shape \(2,\)"),
        ({"rayleigh": (0.1, np.nan)}, ValueError, "`rayleigh` contains NaN"),
        ({"rayleigh": ("a", 1.0)}, TypeError, "`rayleigh`"),
    ],
)
def test_bad_construction(kwargs, exc, pattern):
    args = {"M": M3, "K": K3} | kwargs
    with pytest.raises(exc, match=pattern):
        System(args.pop("M"), args.pop("K"), **args)


def test_bad_sparse_construction():
    with pytest.raises(ValueError, match="`M` must be symmetric"):
        System(sp.csr_array(M3 + np.triu(np.ones((3, 3)), 1)), K3)
    bad = sp.csr_array(K3)
    bad.data[2] = np.nan
    with pytest.raises(ValueError, match=r"`K` contains NaN or inf at index \(1, 0\)"):
        System(M3, bad)
    with pytest.raises(ValueError, match="`M` must be positive definite"):
        System(sp.csr_array(np.diag([1.0, -1.0, 1.0])), K3)


def test_zeta_array_wrong_length_for_modes(chain3):
    system = System(*chain3, zeta=[0.01, 0.02])
    with pytest.raises(ValueError, match="`zeta` has 2 entries but the modal basis has 3 modes"):
        system.modal()
    system.modal(2)


def test_indefinite_k_with_positive_diagonal_raises_in_modal():
    system = System(np.eye(2), [[1.0, 2.0], [2.0, 1.0]])
    with pytest.raises(ValueError, match="`K` must be positive semidefinite"):
        system.modal()


@pytest.mark.parametrize(
    ("n_modes", "exc"), [(0, ValueError), (4, ValueError), (-1, ValueError), (1.5, TypeError)]
)
def test_bad_n_modes(chain3, n_modes, exc):
    with pytest.raises(exc, match="`modes`"):
        System(*chain3).modal(n_modes)


def test_n_modes_rejects_bool(chain3):
    with pytest.raises(TypeError, match="`modes`"):
        System(*chain3).modal(True)


# ------------------------------------------------------------------------------ _validate


def test_as_float_array():
    out = v.as_float_array([1, 2, 3], "x0", ndim=1, shape=(3,))
    assert out.dtype == np.float64 and out.flags.c_contiguous
    strided = np.arange(12.0).reshape(3, 4)[:, ::2]
    assert v.as_float_array(strided, "y").flags.c_contiguous
    assert v.as_float_array(np.float32(2.5), "s").shape == ()
    with pytest.raises(ValueError, match="`x0` contains NaN or inf at index 3"):
        v.as_float_array([0.0, 1.0, 2.0, np.nan], "x0")
    with pytest.raises(ValueError, match=r"`a` contains NaN or inf at index \(1, 0\)"):
        v.as_float_array([[0.0, 1.0], [np.inf, 2.0]], "a")
    v.as_float_array([np.nan], "x", finite=False)
    with pytest.raises(ValueError, match="`x0` must be a 1-D array"):
        v.as_float_array([[1.0]], "x0", ndim=1)
    with pytest.raises(ValueError, match=r"`x0` must have shape \(\?, 2\), got \(3,\)"):
        v.as_float_array([1.0, 2.0, 3.0], "x0", shape=(None, 2))
    for bad in ([1 + 2j], ["a"], [True], [None], "abc", sp.eye(2)):
        with pytest.raises(TypeError, match="`x0`"):
            v.as_float_array(bad, "x0")


def test_scalar_helpers():
    assert v.positive_float(2, "dt") == 2.0 and isinstance(v.positive_float(2, "dt"), float)
    assert v.nonneg_float(np.float32(0.0), "t0") == 0.0
    assert v.finite_float(np.array(-1.5), "a") == -1.5
    assert v.positive_int(np.int64(3), "n") == 3
    with pytest.raises(ValueError, match="`dt` must be positive"):
        v.positive_float(0.0, "dt")
    with pytest.raises(ValueError, match="`t0` must be non-negative"):
        v.nonneg_float(-1.0, "t0")
    with pytest.raises(ValueError, match="`dt` must be finite"):
        v.positive_float(np.inf, "dt")
    for bad in ("1.0", True, None, 1j, [1.0]):
        with pytest.raises(TypeError, match="`dt`"):
            v.positive_float(bad, "dt")
    with pytest.raises(ValueError, match="`n` must be a positive integer"):
        v.positive_int(0, "n")
    for bad in (2.0, "2", False):
        with pytest.raises(TypeError, match="`n`"):
            v.positive_int(bad, "n")


def test_dof_helpers():
    assert v.dof_index(np.int32(4), "dof", 5) == 4
    with pytest.raises(ValueError, match=r"`dof` must be .* in \[0, 4\] \(negative"):
        v.dof_index(-1, "dof", 5)
    with pytest.raises(ValueError, match="`dof`"):
        v.dof_index(5, "dof", 5)
    with pytest.raises(TypeError, match="`dof`"):
        v.dof_index(1.0, "dof", 5)
    out = v.dof_list([3, 0, 1], "dofs", 5)
    assert out.dtype == np.intp and out.tolist() == [3, 0, 1]
    with pytest.raises(ValueError, match="`dofs` contains duplicate dof index 1"):
        v.dof_list([1, 2, 1], "dofs", 5)
    with pytest.raises(ValueError, match=r"`dofs\[1\]` must be .*got -2"):
        v.dof_list([1, -2], "dofs", 5)
    with pytest.raises(ValueError, match="`dofs`"):
        v.dof_list([], "dofs", 5)
    with pytest.raises(ValueError, match="`dofs` must be a 1-D"):
        v.dof_list(3, "dofs", 5)
    for bad in ([1.0, 2.0], [True], "01"):
        with pytest.raises(TypeError, match="`dofs`"):
            v.dof_list(bad, "dofs", 5)
    assert v.mode_count(None, "modes", 7) == 7
    with pytest.raises(ValueError, match=r"`modes` must be an integer in \[1, n_dof\] = \[1, 7\]"):
        v.mode_count(8, "modes", 7)

"""Reusable and supplied modal bases: ModalBasis.from_modes, save/load, System.use_basis,
growth of a computed basis, one factorisation per sparse system, and MatrixMarket input."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.io
import scipy.sparse as sp

import duhamel
import duhamel._engine.eigen as eigen
import duhamel._engine.validate as validate
from duhamel import ModalBasis, System

FIELDS = ("phi", "omega2", "omega", "c", "zeta")


def chain(n: int, *, grounded: bool = True, sparse: bool = False):
    """A spring-mass chain with unequal masses (fixed at one end, or free-free)."""
    k = 1e4 * (1.0 + 0.5 * np.sin(np.arange(n + 1)))
    main = k[:-1] + k[1:]
    if not grounded:
        main[0] = k[1]
    main[-1] = k[n - 1]
    off = -k[1:n]
    K = sp.diags_array([off, main, off], offsets=[-1, 0, 1], format="csr")
    m = 1.0 + 0.3 * np.cos(np.arange(n))
    M = sp.diags_array(
        [0.1 * m[1:], 0.8 * m, 0.1 * m[1:]], offsets=[-1, 0, 1], format="csr"
    )  # consistent-like
    return (M, K) if sparse else (M.toarray(), K.toarray())


def twin(n: int):
    """Two identical uncoupled chains: every frequency is double."""
    M, K = chain(n, sparse=True)
    return sp.block_diag([M, M], format="csr"), sp.block_diag([K, K], format="csr")


def count_factorisations(monkeypatch) -> list[int]:
    calls = [0]
    original = validate.symmetric_lu

    def counted(mat):
        calls[0] += 1
        return original(mat)

    monkeypatch.setattr(validate, "symmetric_lu", counted)
    monkeypatch.setattr(eigen, "symmetric_lu", counted)
    return calls


def assert_same_modes(got: ModalBasis, ref: ModalBasis, *, rtol=1e-10, atol=1e-7):
    np.testing.assert_allclose(got.omega2, ref.omega2, rtol=rtol, atol=1e-12)
    np.testing.assert_allclose(got.phi, ref.phi, atol=atol * np.abs(ref.phi).max())


# ------------------------------------------------------------------------- from_modes


def test_top_level_export():
    assert duhamel.ModalBasis is ModalBasis
    from duhamel.modal import ModalBasis as from_module
    from duhamel.system import ModalBasis as from_system

    assert from_module is from_system is ModalBasis


@pytest.mark.parametrize("sparse", [False, True], ids=["dense", "sparse"])
def test_supplied_basis_equals_the_computed_one(sparse):
    M, K = chain(40, sparse=sparse)
    computed = System(M, K).modal(8)
    supplied = ModalBasis.from_modes(computed.phi, computed.omega, M)
    assert np.array_equal(supplied.phi, computed.phi)
    assert np.array_equal(supplied.omega, computed.omega)
    np.testing.assert_allclose(supplied.omega2, computed.omega2, rtol=4e-16)
    assert not supplied.c.any() and not supplied.zeta.any() and supplied.c_coupling is None
    assert supplied.n_modes == 8 and supplied.n_dof == 40
    for name in FIELDS:
        assert not getattr(supplied, name).flags.writeable
    # unsorted, negated input comes out sorted and signed by the convention
    shuffled = ModalBasis.from_modes(-computed.phi[:, ::-1], computed.omega[::-1], M)
    assert np.array_equal(shuffled.phi, computed.phi)
    assert np.array_equal(shuffled.omega, computed.omega)


@pytest.mark.parametrize(
    "damping",
    [{}, {"zeta": 0.03}, {"zeta": np.linspace(0.01, 0.05, 6)}, {"rayleigh": (0.2, 1e-4)}, "C"],
    ids=["none", "zeta", "zeta per mode", "rayleigh", "C"],
)
def test_a_system_derives_its_own_damping_from_supplied_modes(damping):
    M, K = chain(30)
    if damping == "C":
        damping = {"C": 0.1 * M + 2e-4 * K + np.diag(np.r_[5.0, np.zeros(29)])}  # non-classical
    basis = ModalBasis.from_modes(*_modes(System(M, K).modal(6)), M)
    own = System(M, K, **damping).modal(6)
    shared = System(M, K, **damping).use_basis(basis).modal(6)
    np.testing.assert_allclose(shared.omega2, own.omega2, rtol=1e-14)
    np.testing.assert_allclose(shared.phi, own.phi, atol=1e-12)
    np.testing.assert_allclose(shared.c, own.c, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(shared.zeta, own.zeta, rtol=1e-12, atol=1e-14)
    if own.c_coupling is None:
        assert shared.c_coupling is None
    else:
        np.testing.assert_allclose(shared.c_coupling, own.c_coupling, atol=1e-12)


def _modes(basis: ModalBasis):
    return basis.phi, basis.omega


def test_a_run_on_a_supplied_basis_equals_one_on_the_computed_basis():
    M, K = chain(30, sparse=True)

    def run(system):
        system.add_load(duhamel.loads.Harmonic(29, amplitude=10.0, omega=40.0))
        return duhamel.solve(system, duhamel.Semianalytic(modes=10), t_end=0.5, dt=1e-3)

    basis = ModalBasis.from_modes(*_modes(System(M, K).modal(10)), M)
    ref = run(System(M, K, zeta=0.02))
    got = run(System(M, K, zeta=0.02).use_basis(basis))
    np.testing.assert_allclose(got.x, ref.x, rtol=0, atol=1e-13 * np.abs(ref.x).max())


@pytest.mark.parametrize(
    ("change", "exc", "pattern"),
    [
        (lambda p, w, M: (p[:, 0], w[:1], M), ValueError, "`phi` must be a 2-D array"),
        (lambda p, w, M: (p, w[:-1], M), ValueError, "`omega` must have one entry per mode"),
        (lambda p, w, M: (p, -w, M), ValueError, r"`omega` must be >= 0 .*omega\[0\]"),
        (lambda p, w, M: (np.where(p == p[3, 1], np.nan, p), w, M), ValueError, "`phi` contains"),
        (lambda p, w, M: (p + 0j, w, M), TypeError, "`phi` must contain real numbers"),
        (lambda p, w, M: (p, w, M[:-1, :-1]), ValueError, "`M` must have shape"),
        (lambda p, w, M: (2 * p, w, M), ValueError, "`phi` must be mass-orthonormal"),
        (lambda p, w, M: (p, w, 1.1 * M), ValueError, "`rtol`"),
        (lambda p, w, M: (np.zeros((12, 0)), w[:0], M), ValueError, "between 1 and n_dof"),
        (lambda p, w, M: (sp.csr_array(p), w, M), TypeError, "`phi` must be a dense array"),
    ],
)
def test_from_modes_refuses_bad_input(change, exc, pattern):
    M, K = chain(12)
    phi, omega = _modes(System(M, K).modal(4))
    with pytest.raises(exc, match=pattern):
        ModalBasis.from_modes(*change(phi, omega, M))


def test_from_modes_rtol():
    M, K = chain(12)
    phi, omega = _modes(System(M, K).modal(4))
    rough = phi * (1 + 1e-4)
    with pytest.raises(ValueError, match=r"off by 0\.0002"):
        ModalBasis.from_modes(rough, omega, M)
    assert ModalBasis.from_modes(rough, omega, M, rtol=1e-3).n_modes == 4
    for bad in (0.0, -1.0, np.nan):
        with pytest.raises(ValueError, match="`rtol`"):
            ModalBasis.from_modes(phi, omega, M, rtol=bad)


# ------------------------------------------------------------------------- save / load


def _non_classical():
    M, K = chain(20)
    C = 0.05 * M + np.diag(np.r_[3.0, np.zeros(19)])
    return System(M, K, C).modal(7)


@pytest.mark.parametrize(
    "make",
    [
        lambda: System(*chain(20), rayleigh=(0.1, 1e-4)).modal(),
        lambda: System(*chain(300, grounded=False, sparse=True), zeta=0.02).modal(9),
        _non_classical,
        lambda: ModalBasis.from_modes(*_modes(System(*chain(20)).modal(5)), chain(20)[0]),
    ],
    ids=["dense rayleigh", "sparse free-free zeta", "non-classical C", "from_modes"],
)
def test_a_saved_basis_round_trips_bit_for_bit(tmp_path, make):
    basis = make()
    path = tmp_path / "basis.npz"
    basis.save(path)
    back = ModalBasis.load(path)
    for name in FIELDS:
        got, ref = getattr(back, name), getattr(basis, name)
        assert got.dtype == ref.dtype and got.shape == ref.shape
        assert got.tobytes() == ref.tobytes(), name
        assert not got.flags.writeable and got.flags.c_contiguous
    if basis.c_coupling is None:
        assert back.c_coupling is None
    else:
        assert back.c_coupling.tobytes() == basis.c_coupling.tobytes()
    # the name is used as given (numpy would append ".npz" to a bare name)
    bare = tmp_path / "modes"
    basis.save(str(bare))
    assert bare.exists() and ModalBasis.load(bare).phi.tobytes() == basis.phi.tobytes()


def test_a_loaded_basis_serves_a_system(tmp_path):
    M, K = chain(50, sparse=True)
    System(M, K).modal(6).save(tmp_path / "b.npz")
    damped = System(M, K, zeta=0.05).use_basis(ModalBasis.load(tmp_path / "b.npz"))
    assert damped.modal(6).zeta.tolist() == pytest.approx([0.05] * 6, rel=1e-14)


def _npz(path, **arrays):
    with open(path, "wb") as f:
        np.savez(f, **arrays)
    return path


def test_load_refuses_what_is_not_a_basis(tmp_path):
    basis = System(*chain(6)).modal()
    good = {name: getattr(basis, name) for name in FIELDS}
    header = {"format": np.array("duhamel.ModalBasis"), "version": np.array(1)}
    text = tmp_path / "notes.txt"
    text.write_text("not an archive\n")
    npy = tmp_path / "phi.npy"
    np.save(npy, basis.phi)
    cases = {
        text: "numpy cannot read it",
        npy: "a single array",
        _npz(tmp_path / "plain.npz", **good): "no 'format' entry",
        _npz(
            tmp_path / "other.npz", **good, format=np.array("x"), version=np.array(1)
        ): "no 'format' entry",
        _npz(tmp_path / "nover.npz", **good, format=header["format"]): "no integer 'version'",
        _npz(tmp_path / "partial.npz", **header, phi=basis.phi): "lacks the array",
        _npz(tmp_path / "shape.npz", **header, **{**good, "zeta": np.zeros(2)}): "'zeta' has shape",
        _npz(
            tmp_path / "dtype.npz", **header, **{**good, "c": np.zeros(6, np.float32)}
        ): "'c' has dtype float32",
        _npz(
            tmp_path / "nan.npz", **header, **{**good, "omega": np.full(6, np.nan)}
        ): "'omega' contains NaN",
        _npz(tmp_path / "neg.npz", **header, **{**good, "omega2": -good["omega2"]}): "negative",
    }
    for path, why in cases.items():
        with pytest.raises(ValueError, match="is not a duhamel ModalBasis file") as info:
            ModalBasis.load(path)
        assert why in str(info.value), (path.name, str(info.value))
    future = _npz(tmp_path / "v2.npz", **good, format=header["format"], version=np.array(2))
    with pytest.raises(ValueError, match="format version 2, newer than this duhamel reads"):
        ModalBasis.load(future)
    with pytest.raises(FileNotFoundError):
        ModalBasis.load(tmp_path / "missing.npz")


# ------------------------------------------------------------------------- use_basis


def test_use_basis_checks_the_basis_belongs_to_the_system():
    M, K = chain(20)
    basis = System(M, K).modal(5)
    with pytest.raises(TypeError, match=r"`basis` must be a duhamel\.ModalBasis"):
        System(M, K).use_basis(basis.phi)
    with pytest.raises(TypeError, match="`extend` must be a bool"):
        System(M, K).use_basis(basis, extend=1)
    with pytest.raises(ValueError, match="holds modes of 20 degrees of freedom, the system has 19"):
        System(M[:-1, :-1], K[:-1, :-1]).use_basis(basis)
    with pytest.raises(ValueError, match="not mass-orthonormal with this system's `M`"):
        System(1.01 * M, K).use_basis(basis)
    with pytest.raises(ValueError, match=r"not hold modes of this system's `K` .* mode \d"):
        System(M, 1.01 * K).use_basis(basis)
    relaxed = System(M, 1.0000001 * K).use_basis(basis, rtol=1e-4)
    assert relaxed.modal(5).omega2 is not basis.omega2


def test_more_modes_than_supplied_raise_unless_extended():
    M, K = chain(60, sparse=True)
    basis = System(M, K).modal(5)
    system = System(M, K, zeta=0.01).use_basis(basis)
    assert system.modal(3).n_modes == 3
    with pytest.raises(ValueError, match=r"`modes` = 8 asks for more modes than the basis"):
        system.modal(8)
    with pytest.raises(ValueError, match=r"`modes` = 60 \(every mode\)"):
        system.modal()
    with pytest.raises(ValueError, match="use_basis holds"):
        duhamel.solve(system, duhamel.Semianalytic(modes=8), t_end=0.01, dt=1e-3)
    extended = System(M, K, zeta=0.01).use_basis(basis, extend=True)
    assert_same_modes(extended.modal(12), System(M, K, zeta=0.01).modal(12))
    assert np.array_equal(extended.modal(12).phi[:, :5], basis.phi)


# ------------------------------------------------------------------------- growth


@pytest.mark.parametrize("grounded", [True, False], ids=["grounded", "free-free"])
def test_sparse_growth_equals_a_fresh_computation_on_one_factorisation(monkeypatch, grounded):
    M, K = chain(400, grounded=grounded, sparse=True)
    calls = count_factorisations(monkeypatch)
    system = System(M, K)
    before = calls[0]  # the mass check of the constructor (none below 2000 dofs)
    six = system.modal(6)
    grown = system.modal(15)
    more = system.modal(30)
    assert calls[0] - before == 1  # one K - sigma M, also answering the semidefinite check
    fresh = System(M, K).modal(30)
    assert_same_modes(more, fresh)
    assert_same_modes(grown, System(M, K).modal(15))
    assert np.array_equal(grown.phi[:, :6], six.phi) and np.array_equal(more.phi[:, :15], grown.phi)
    phi = more.phi
    np.testing.assert_allclose(phi.T @ (M @ phi), np.eye(30), atol=1e-12)
    assert (more.omega2[0] == 0.0) is not grounded


def test_dense_growth_equals_a_fresh_computation():
    M, K = chain(25, grounded=False)
    system = System(M, K, rayleigh=(0.1, 1e-4))
    small = system.modal(3)
    grown = system.modal(10)
    assert_same_modes(grown, System(M, K, rayleigh=(0.1, 1e-4)).modal(10), atol=1e-10)
    assert np.array_equal(grown.phi[:, :3], small.phi)
    np.testing.assert_allclose(grown.c, 0.1 + 1e-4 * grown.omega2)
    everything = system.modal()
    np.testing.assert_allclose(everything.omega2, System(M, K).modal().omega2, rtol=1e-10)


@pytest.mark.parametrize("sparse", [False, True], ids=["dense", "sparse"])
def test_growth_through_a_degenerate_pair(sparse):
    M, K = twin(60)  # frequencies come in equal pairs: 3 modes cut a pair in two
    if not sparse:
        M, K = M.toarray(), K.toarray()
    system = System(M, K)
    system.modal(3)
    grown = system.modal(10)
    fresh = System(M, K).modal(10)
    np.testing.assert_allclose(grown.omega2, fresh.omega2, rtol=1e-10)
    phi = grown.phi
    np.testing.assert_allclose(phi.T @ (M @ phi), np.eye(10), atol=1e-12)
    residual = K @ phi - (M @ phi) * grown.omega2
    assert np.abs(residual).max() < 1e-8 * np.abs(K @ phi).max()


@pytest.mark.parametrize("sparse", [False, True], ids=["dense", "sparse"])
def test_supplied_modes_of_a_skipped_mode_are_completed_in_order(sparse):
    M, K = chain(50, sparse=sparse)
    full = System(M, K).modal(8)
    keep = [0, 1, 3, 4]  # mode 2 missing
    partial = ModalBasis.from_modes(full.phi[:, keep], full.omega[keep], M)
    system = System(M, K).use_basis(partial, extend=True)
    assert_same_modes(system.modal(6), System(M, K).modal(6))


def test_lumped_free_free_lattice_needs_one_factorisation(monkeypatch):
    # a 3-D lattice (3 n^3 = 2187 dofs > DENSE_CHOLESKY_MAX_N) with rigid-body modes
    n = 9
    main, off = np.full(n, 2.0), -np.ones(n - 1)
    main[0] = main[-1] = 1.0
    lap = sp.diags_array([off, main, off], offsets=[-1, 0, 1])
    eye = sp.identity(n)
    lap3 = sp.kron(sp.kron(lap, eye), eye) + sp.kron(sp.kron(eye, lap), eye)
    lap3 = lap3 + sp.kron(sp.kron(eye, eye), lap)
    K = sp.kron(lap3, np.array([[2.0, 0.5, 0.3], [0.5, 2.0, 0.4], [0.3, 0.4, 2.0]]), "csr")
    M = sp.identity(3 * n**3, format="csr")
    calls = count_factorisations(monkeypatch)
    system = System(M, K)
    assert calls[0] == 1  # the constructor's check of M
    basis = system.modal(12)
    assert calls[0] == 2
    assert np.count_nonzero(basis.omega2 == 0.0) == 3


# ------------------------------------------------------------------------- MatrixMarket


@pytest.mark.parametrize("flavour", ["coo_matrix", "coo_array"])
def test_matrix_market_input_works_directly(tmp_path, flavour):
    M, K = chain(80, sparse=True)
    scipy.io.mmwrite(tmp_path / "M.mtx", M, symmetry="symmetric")
    scipy.io.mmwrite(tmp_path / "K.mtx", K, symmetry="symmetric")
    kwargs = {} if flavour == "coo_matrix" else {"spmatrix": False}
    m_read = scipy.io.mmread(tmp_path / "M.mtx", **kwargs)
    k_read = scipy.io.mmread(tmp_path / "K.mtx", **kwargs)
    assert type(m_read).__name__ == flavour
    system = System(m_read, k_read, zeta=0.02)
    assert system.M.format == "csr" and system.K.format == "csr"
    assert abs(system.K - K).max() == 0.0 and abs(system.M - M).max() == 0.0
    assert_same_modes(system.modal(5), System(M, K, zeta=0.02).modal(5))
    system.add_load(duhamel.loads.Step(dof=79, amplitude=1.0))
    sol = duhamel.solve(system, duhamel.Semianalytic(modes=5), t_end=0.05, dt=1e-3)
    assert np.isfinite(sol.x).all()


def test_a_one_triangle_export_is_named_in_the_error(tmp_path):
    M, K = chain(30, sparse=True)
    scipy.io.mmwrite(tmp_path / "K.mtx", sp.tril(K), symmetry="general")
    lower = scipy.io.mmread(tmp_path / "K.mtx")
    with pytest.raises(ValueError, match=r"`K` must be symmetric.*one triangle only"):
        System(M, lower)
    full = lower + lower.T - sp.diags(lower.diagonal())
    np.testing.assert_array_equal(System(M, full).K.toarray(), K.toarray())


def test_docs_example_runs():
    import re
    from pathlib import Path

    text = (Path(__file__).resolve().parents[2] / "docs" / "basis.md").read_text()
    code = re.findall(r"```python\n(.*?)```", text, re.S)[0]
    namespace: dict = {}
    exec(compile(code, "docs/basis.md", "exec"), namespace)
    sol, more = namespace["sol"], namespace["more"]
    assert np.isfinite(sol.x).all() and sol.modal.q.shape[1] == 40
    assert namespace["saved"].phi.tobytes() == more.phi.tobytes()
    np.testing.assert_allclose(namespace["rayleigh"].modal(40).c, 0.1 + 1e-5 * more.omega2)

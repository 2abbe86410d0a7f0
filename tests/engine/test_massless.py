"""Massless dofs (a positive semidefinite ``M``): exact static condensation on the modal route,
the direct integrators on the singular-mass model, and the refusals."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.io
import scipy.linalg
import scipy.signal
import scipy.sparse as sp
from _frames import condensed, moment_frame

import duhamel

DT, T_END = 0.01, 6.0
ZETA = 0.05


def _record() -> tuple[np.ndarray, np.ndarray]:
    t = np.arange(0.0, T_END + DT / 2, DT)
    rng = np.random.default_rng(7)
    a = np.convolve(rng.standard_normal(t.size), np.ones(5) / 5, mode="same") * 3.0
    return t, a * np.minimum(1.0, t) * np.exp(-0.3 * t)


def _lsim_reference(M, K, sway, t, ag):
    """The response of every dof from scipy.signal.lsim on the condensed model with the
    modal damping formed from its own eigenvectors."""
    M_mm, K_c, T, m = condensed(M, K)
    w2, phi = scipy.linalg.eigh(K_c, M_mm)
    mphi = M_mm @ phi
    C_c = (mphi * (2 * ZETA * np.sqrt(w2))) @ mphi.T
    r = np.zeros(M.shape[0])
    r[sway] = 1.0
    n = m.size
    A = np.block(
        [[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M_mm, K_c), -np.linalg.solve(M_mm, C_c)]]
    )
    B = np.concatenate([np.zeros(n), -r[m]])[:, None]  # M_mm^-1 (-M_mm r_m a_g)
    out = scipy.signal.lsim((A, B, np.eye(2 * n), np.zeros((2 * n, 1))), ag, t)[2]
    return out[:, :n] @ T.T, out[:, n:] @ T.T


def _system(M, K, sway, kind, tmp_path, ag, t):
    if kind == "dense":
        mats = (M, K)
    elif kind == "sparse":
        mats = (sp.csr_array(M), sp.csr_array(K))
    else:
        scipy.io.mmwrite(tmp_path / "M.mtx", sp.coo_matrix(M))
        scipy.io.mmwrite(tmp_path / "K.mtx", sp.coo_matrix(K))
        mats = (scipy.io.mmread(tmp_path / "M.mtx"), scipy.io.mmread(tmp_path / "K.mtx"))
    system = duhamel.System(*mats, zeta=ZETA)
    r = np.zeros(M.shape[0])
    r[sway] = 1.0
    return system.add_load(duhamel.loads.BaseAcceleration(r, t=t, values=ag))


@pytest.mark.parametrize("kind", ["dense", "sparse", "mmread"])
def test_linear_response_equals_lsim_on_condensed_model(kind, tmp_path):
    M, K, sway = moment_frame(4, 3)
    t, ag = _record()
    system = _system(M, K, sway, kind, tmp_path, ag, t)
    assert system.massless_dofs.size == M.shape[0] - sway.size
    assert system.is_sparse == (kind != "dense")
    sol = duhamel.solve(system, duhamel.Semianalytic(), t_end=T_END, dt=DT)
    x_ref, v_ref = _lsim_reference(M, K, sway, t, ag)
    assert np.abs(sol.x - x_ref).max() <= 1e-10 * np.abs(x_ref).max()
    assert np.abs(sol.v - v_ref).max() <= 1e-10 * np.abs(v_ref).max()


def test_newmark_on_singular_mass_converges_at_second_order():
    M, K, sway = moment_frame(3, 2)
    t, ag = _record()
    system = _system(M, K, sway, "dense", None, ag, t)
    # every grid holds the record's samples, where the exact step takes its kinks
    ref = duhamel.solve(system, duhamel.Semianalytic(), t_end=2.0, dt=0.01)
    errors = []
    steps = [DT / 4, DT / 8, DT / 16]
    for dt in steps:
        sol = duhamel.solve(system, duhamel.Newmark(), t_end=2.0, dt=dt, save_every=round(DT / dt))
        assert np.allclose(sol.t, ref.t)
        errors.append(np.abs(sol.x - ref.x).max() / np.abs(ref.x).max())
    slopes = np.diff(np.log(errors)) / np.diff(np.log(steps))
    assert errors[-1] < 1e-3
    assert np.all(np.abs(slopes - 2.0) < 0.1), slopes


def test_loads_at_massless_dofs_are_exact():
    """A moment at a massless joint: its static part K_ss^-1 f_s at the massless dofs, and
    the rest through the modes, against lsim on the condensed model with T^T f."""
    M, K, _sway = moment_frame(3, 1)
    s = np.flatnonzero(np.diag(M) == 0)
    t = np.arange(0.0, 3.2, DT)  # beyond the run's end: the table's end is not sampled
    moment = 5e4 * np.sin(4.0 * t)
    system = duhamel.System(M, K, zeta=ZETA)
    system.add_load(duhamel.loads.Tabulated(int(s[2]), t=t, values=moment))
    sol = duhamel.solve(system, duhamel.Semianalytic(), t_end=3.0, dt=DT)
    M_mm, K_c, T, m = condensed(M, K)
    w2, phi = scipy.linalg.eigh(K_c, M_mm)
    mphi = M_mm @ phi
    C_c = (mphi * (2 * ZETA * np.sqrt(w2))) @ mphi.T
    f = np.zeros(M.shape[0])
    f[s[2]] = 1.0
    n = m.size
    A = np.block(
        [[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M_mm, K_c), -np.linalg.solve(M_mm, C_c)]]
    )
    B = np.concatenate([np.zeros(n), np.linalg.solve(M_mm, T.T @ f)])[:, None]
    out = scipy.signal.lsim((A, B, np.eye(2 * n), np.zeros((2 * n, 1))), moment, t)[2]
    K_ss = K[np.ix_(s, s)]
    x_ref = out[:, :n] @ T.T
    x_ref[:, s] += np.outer(moment, np.linalg.solve(K_ss, f[s]))
    x_ref = x_ref[: sol.t.size]
    assert np.allclose(sol.t, t[: sol.t.size])
    assert np.abs(sol.x - x_ref).max() <= 1e-10 * np.abs(x_ref).max()


def test_modes_are_the_condensed_models():
    M, K, _ = moment_frame(6, 3)
    M_mm, K_c, _T, _ = condensed(M, K)
    w2 = scipy.linalg.eigh(K_c, M_mm, eigvals_only=True)
    dense = duhamel.System(M, K).modal()
    assert dense.n_modes == M_mm.shape[0]
    assert np.allclose(dense.omega2, w2, rtol=1e-10, atol=0)
    big_M, big_K, _ = moment_frame(30, 2)
    w2_big = scipy.linalg.eigh(*condensed(big_M, big_K)[1::-1], eigvals_only=True)[:5]
    sparse = duhamel.System(sp.csr_array(big_M), sp.csr_array(big_K)).modal(5)
    assert np.allclose(sparse.omega2, w2_big, rtol=1e-9, atol=0)
    phi = sparse.phi
    assert np.allclose(phi.T @ big_M @ phi, np.eye(5), atol=1e-10)


def test_mechanism_is_refused_naming_the_dofs():
    M, K, _ = moment_frame(2, 1)
    K = K.copy()
    # a pin: dof 2 (a rotation) loses every stiffness
    K[2, :] = 0.0
    K[:, 2] = 0.0
    with pytest.raises(ValueError, match=r"mechanism.*\[2\]"):
        duhamel.System(M, K)
    with pytest.raises(ValueError, match=r"mechanism.*\[2\]"):
        duhamel.System(sp.csr_array(M), sp.csr_array(K))


@pytest.mark.parametrize(
    "M, pattern",
    [
        (np.diag([1.0, -1.0, 0.0]), "`M` must be positive definite on the dofs with mass"),
        (
            np.array([[1.0, 0.5, 0], [0.5, 0.0, 0], [0, 0, 1.0]]),
            "`M` must be positive semidefinite",
        ),
        (
            np.array([[1.0, 1.0, 0], [1.0, 1.0, 0], [0, 0, 0.0]]),
            "`M` must be positive definite on its dofs with mass",
        ),
        (np.zeros((3, 3)), "`M` must have mass"),
    ],
)
def test_indefinite_or_negative_mass_refused(M, pattern):
    K = np.array([[2.0, -1, 0], [-1, 2, -1], [0, -1, 1]])
    with pytest.raises(ValueError, match=pattern):
        duhamel.System(M, K)
    with pytest.raises(ValueError, match=pattern):
        duhamel.System(sp.csr_array(M), K)


def test_explicit_integrator_refused():
    M, K, _ = moment_frame(2, 1)
    system = duhamel.System(M, K)
    with pytest.raises(ValueError, match="massless"):
        duhamel.solve(system, duhamel.CentralDifference(), t_end=0.1, dt=0.001)


def _hinged_frame():
    M, K, sway = moment_frame(3, 2)
    s = np.flatnonzero(np.diag(M) == 0)
    t = np.arange(0.0, 4.0, DT)
    ag = 6.0 * np.sin(2 * np.pi * 1.2 * t) * np.exp(-0.2 * t)
    r = np.zeros(M.shape[0])
    r[sway] = 1.0
    system = duhamel.System(M, K, zeta=ZETA)
    system.add_load(duhamel.loads.BaseAcceleration(r, t=t, values=ag))
    hinge = duhamel.elements.Bilinear(int(s[0]), k=5e7, fy=2e5, alpha=0.02)
    return system.add(hinge), hinge, K, s


def test_rotational_hinge_at_massless_dof_on_newmark_converges():
    """A Bilinear hinge at a massless base rotation: Newmark on the singular-mass model
    converges at second order, and the hinge yields (its moment reaches fy)."""
    system, hinge, _, _ = _hinged_frame()
    runs = [0.01 / k for k in (4, 8, 16, 32)]
    sols = [
        duhamel.solve(system, duhamel.Newmark(), t_end=3.0, dt=dt, save_every=round(DT / dt))
        for dt in runs
    ]
    ref = sols[-1]
    errors = [np.abs(s.x - ref.x).max() / np.abs(ref.x).max() for s in sols[:-1]]
    slopes = np.diff(np.log(errors)) / np.diff(np.log(runs[:-1]))
    assert np.all(slopes > 1.8), slopes
    assert np.abs(ref.x[:, hinge.i]).max() * hinge.k > 1.5 * hinge.fy  # beyond yield


def test_rotational_hinge_at_massless_dof_semianalytic_against_newmark():
    """The acceptance case: the Bilinear hinge at a massless rotation on Semianalytic
    (quasi-static coordinates) against Newmark on the full singular-mass model at a small
    step, to 1e-4 of the peak displacement."""
    system, hinge, _, _ = _hinged_frame()
    ref = duhamel.solve(system, duhamel.Newmark(), t_end=3.0, dt=DT / 64, save_every=64)
    assert np.abs(ref.x[:, hinge.i]).max() * hinge.k > 1.5 * hinge.fy  # it yields
    # ("background" would put zeta on the modes of K plus the hinge: another damping matrix
    # than the Newmark model's, which is formed on the modes of K)
    for linear_parts in ("auto", "pseudo-force"):
        sol = duhamel.solve(
            system, duhamel.Semianalytic(linear_parts=linear_parts), t_end=3.0, dt=DT
        )
        assert np.abs(sol.x - ref.x).max() <= 1e-4 * np.abs(ref.x).max()


def test_linear_element_at_massless_dof_with_a_load_there():
    """A linear Spring at a massless rotation, stepped as a pseudo-force, with a moment
    applied at that rotation: the same as the spring in K (exact route), to the
    quasi-static coordinate's bias (omega_max / omega_f = 1e-6)."""
    M, K, _ = moment_frame(3, 1)
    s = np.flatnonzero(np.diag(M) == 0)
    t = np.arange(0.0, 3.2, DT)
    moment = duhamel.loads.Tabulated(int(s[1]), t=t, values=4e4 * np.sin(5.0 * t))
    k = 3e7
    stiff = K.copy()
    stiff[s[1], s[1]] += k
    exact = duhamel.System(M, stiff, zeta=ZETA).add_load(moment)
    spring = duhamel.System(M, K, zeta=ZETA).add_load(moment)
    spring.add(duhamel.elements.Spring(int(s[1]), None, k=k))
    # zeta fixes the modes of K: the spring's stiffness in the background changes them, so
    # compare with a damping that does not depend on the modes
    exact = duhamel.System(M, stiff, rayleigh=(0.4, 0.0)).add_load(moment)
    spring = duhamel.System(M, K, rayleigh=(0.4, 0.0)).add_load(moment)
    spring.add(duhamel.elements.Spring(int(s[1]), None, k=k))
    a = duhamel.solve(exact, duhamel.Semianalytic(), t_end=3.0, dt=DT)
    b = duhamel.solve(
        spring, duhamel.Semianalytic(linear_parts="pseudo-force"), t_end=3.0, dt=DT / 4,
        save_every=4,
    )  # fmt: skip
    assert np.abs(a.x - b.x).max() <= 1e-4 * np.abs(a.x).max()


@pytest.mark.parametrize("linear_parts", ["auto", "background"])
def test_element_linear_part_in_background_counts_in_the_massless_static_part(linear_parts):
    """Regression: with the element's linear part moved into the background (the default),
    the static part of a load at a massless dof was taken with K_ss WITHOUT the element's
    stiffness (a Spring k = 50 at a massless dof loaded there gave 0.636 instead of the
    exact 100 u / (100 + 50) = 0.424, silently). Against the closed form of the static dof
    and against the spring written into K."""
    t = np.linspace(0.0, 1.0, 2001)
    u = 0.9 * np.sin(1.5 * np.pi * t)
    for k in (1.0, 50.0):
        load = duhamel.loads.Tabulated(0, t=t, values=100.0 * u, hold=True)
        s = duhamel.System(np.diag([0.0, 1.0]), np.diag([100.0, 1.0])).add_load(load)
        s.add(duhamel.elements.Spring(0, None, k=k))
        sol = duhamel.solve(s, duhamel.Semianalytic(linear_parts=linear_parts), t_end=1.0, dt=5e-4)
        closed = 100.0 * u / (100.0 + k)
        assert np.abs(sol.x[:, 0] - closed).max() <= 1e-4 * np.abs(closed).max()
    # a coupled frame: the spring at a massless rotation, against the spring in K
    M, K, _ = moment_frame(3, 1)
    r = np.flatnonzero(np.diag(M) == 0)
    tt = np.arange(0.0, 3.2, DT)
    moment = duhamel.loads.Tabulated(int(r[1]), t=tt, values=4e4 * np.sin(5.0 * tt))
    kr = 3e7
    stiff = K.copy()
    stiff[r[1], r[1]] += kr
    exact = duhamel.System(M, stiff, rayleigh=(0.4, 0.0)).add_load(moment)
    spring = duhamel.System(M, K, rayleigh=(0.4, 0.0)).add_load(moment)
    spring.add(duhamel.elements.Spring(int(r[1]), None, k=kr))
    a = duhamel.solve(exact, duhamel.Semianalytic(), t_end=3.0, dt=DT)
    b = duhamel.solve(spring, duhamel.Semianalytic(linear_parts=linear_parts), t_end=3.0, dt=DT)
    assert np.abs(a.x - b.x).max() <= 1e-4 * np.abs(a.x).max()


def test_streamed_run_with_a_massless_load_refused(tmp_path):
    pytest.importorskip("zarr")
    M, K, _ = moment_frame(2, 1)
    s = np.flatnonzero(np.diag(M) == 0)
    system = duhamel.System(M, K).add_load(duhamel.loads.Step(int(s[0]), amplitude=1e3))
    with pytest.raises(ValueError, match=r"`store`.*massless"):
        duhamel.solve(
            system, duhamel.Semianalytic(), t_end=0.1, dt=0.01, store=str(tmp_path / "r.zarr")
        )

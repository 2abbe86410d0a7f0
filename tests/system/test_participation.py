"""Participation factors, effective modal masses and ratios (ModalBasis.participation)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import scipy.sparse as sp
from _frames import moment_frame

import duhamel

E, A, I_, H, MASS = 2.0e11, 0.01, 1.0e-4, 3.0, 1.0e4


def _column(n_nodes: int = 3) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """A vertical cantilever of 2-D elastic beam-columns, dofs (ux, uy, rz) per node above
    the fixed base, mass on ux only (uy and rz massless)."""
    L = H
    kl = np.zeros((6, 6))
    a, b = E * A / L, E * I_ / L**3
    kl[np.ix_([0, 3], [0, 3])] = a * np.array([[1, -1], [-1, 1]])
    bend = b * np.array(
        [[12, 6 * L, -12, 6 * L], [6 * L, 4 * L * L, -6 * L, 2 * L * L],
         [-12, -6 * L, 12, -6 * L], [6 * L, 2 * L * L, -6 * L, 4 * L * L]]
    )  # fmt: skip
    kl[np.ix_([1, 2, 4, 5], [1, 2, 4, 5])] = bend
    t3 = np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # member along +y
    T = np.kron(np.eye(2), t3)
    kg = T.T @ kl @ T
    n = 3 * (n_nodes + 1)
    K = np.zeros((n, n))
    for e in range(n_nodes):
        d = np.arange(3 * e, 3 * e + 6)
        K[np.ix_(d, d)] += kg
    K, M = K[3:, 3:], np.zeros((n - 3, n - 3))
    M[np.arange(0, n - 3, 3), np.arange(0, n - 3, 3)] = MASS
    labels = [f"{node}_{d}" for node in range(2, n_nodes + 2) for d in ("ux", "uy", "rz")]
    return M, K, labels


@pytest.mark.parametrize("sparse", [False, True])
def test_effective_masses_sum_to_total_mass_with_every_mode(sparse):
    M, K, sway = moment_frame(6, 3)
    mats = (sp.csr_array(M), sp.csr_array(K)) if sparse else (M, K)
    basis = duhamel.System(*mats).modal()
    r = np.zeros(M.shape[0])
    r[sway] = 1.0
    p = basis.participation(r)
    total = float(r @ M @ r)
    assert p.total_mass == pytest.approx(total, rel=1e-15)
    assert abs(p.effective_mass.sum() - total) <= 1e-12 * total
    assert abs(p.cumulative[-1] - 1.0) <= 1e-12
    assert np.allclose(p.effective_mass, p.factors**2)
    assert np.all(np.diff(p.cumulative) >= 0)


def test_corrected_ritz_basis_and_label_direction():
    M, K, labels = _column(6)
    system = duhamel.System(M, K).label_dofs(labels)
    full = system.modal().participation("ux")
    r = np.array([1.0 if lab.endswith("ux") else 0.0 for lab in labels])
    assert np.array_equal(full.direction, r)
    assert abs(full.effective_mass.sum() - 6 * MASS) <= 1e-12 * 6 * MASS
    # two modes and the static correction to the base acceleration's pattern: the Ritz
    # vector carries the rest of the mass up to the static response's share
    from duhamel._engine.correction import corrected

    t = np.linspace(0.0, 1.0, 11)
    system.add_load(duhamel.loads.BaseAcceleration(r, t=t, values=np.ones(11)))
    ritz = corrected(system, system.modal(2))
    p = ritz.participation(r, M=M)
    assert ritz.n_modes == 3
    assert p.cumulative[-1] > system.modal(2).participation(r).cumulative[-1]
    phi = ritz.phi
    assert np.allclose(phi.T @ M @ phi, np.eye(3), atol=1e-12)
    assert "ux %" in system.modal().summary()


def test_against_opensees_modal_properties():
    ops = pytest.importorskip("openseespy.opensees")
    M, K, labels = _column(3)
    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    for i in range(4):
        ops.node(i + 1, 0.0, i * H)
    ops.fix(1, 1, 1, 1)
    for i in range(2, 5):
        ops.mass(i, MASS, 0.0, 0.0)
    ops.geomTransf("Linear", 1)
    for i in range(1, 4):
        ops.element("elasticBeamColumn", i, i, i + 1, A, E, I_, 1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ops.eigen("-fullGenLapack", 3)
        props = ops.modalProperties("-return")
    ops.wipe()
    basis = duhamel.System(M, K).label_dofs(labels).modal()
    p = basis.participation("ux")
    assert np.allclose(basis.omega, props["eigenOmega"], rtol=1e-8)
    assert np.allclose(100 * p.ratio, props["partiMassRatiosMX"], rtol=1e-8, atol=1e-10)
    assert np.allclose(p.effective_mass, props["partiMassMX"], rtol=1e-8)
    assert np.allclose(np.abs(p.factors), np.abs(props["partiFactorMX"]), rtol=1e-8)


def test_bad_direction():
    M, K, labels = _column(2)
    basis = duhamel.System(M, K).modal()
    with pytest.raises(ValueError, match=r"`direction`.*no labels"):
        basis.participation("ux")
    with pytest.raises(ValueError, match="`direction` must have length"):
        basis.participation(np.ones(3))
    labelled = duhamel.System(M, K).label_dofs(labels).modal()
    with pytest.raises(ValueError, match="matches no dof label"):
        labelled.participation("uz")


def test_reduced_run_warns_below_ninety_percent_of_the_mass():
    M, K, sway = moment_frame(8, 2)
    r = np.zeros(M.shape[0])
    r[sway] = 1.0
    system = duhamel.System(M, K, zeta=0.05)
    t = np.linspace(0.0, 1.0, 101)
    system.add_load(duhamel.loads.BaseAcceleration(r, t=t, values=np.sin(10 * t)))
    first = system.modal().participation(r).cumulative
    few = int(np.argmax(first >= 0.5)) + 1  # a basis that keeps 50-90 %
    assert first[few - 1] < 0.9
    with pytest.warns(UserWarning, match=r"carries \d+\.\d % of the mass"):
        duhamel.solve(system, duhamel.Semianalytic(modes=few), t_end=0.1, dt=0.01)
    enough = int(np.argmax(first >= 0.95)) + 1
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        duhamel.solve(system, duhamel.Semianalytic(modes=enough), t_end=0.1, dt=0.01)

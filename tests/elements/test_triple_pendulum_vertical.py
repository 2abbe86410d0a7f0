"""The triple friction pendulum with its vertical dof (issue 36): a rigid mass on one
bearing whose axial force follows the vertical dof, under a record in x, y and z (the
axial force varies by tens of percent). Semianalytic and Newmark() on the same System
converge to the same response within 1e-4 of the peak; with the vertical dof held the
bearing is the one with its constant ``weight``; bad input names the parameter."""

from __future__ import annotations

import numpy as np
import pytest

import duhamel
from duhamel import elements as E
from duhamel import loads as L
from tests.elements.test_triple_pendulum import CAPACITY, MU, RADIUS, G, record

M, KV = 1.0e5, 2.0e9
W = M * G


def vertical(**extra: object) -> E.Element:
    return E.TripleFrictionPendulum(
        (0, 1, 2), mu=MU, radius=RADIUS, displacement_capacity=CAPACITY, weight=W,
        yield_displacement=5e-4, vertical_stiffness=KV, **extra,
    )  # fmt: skip


def system() -> duhamel.System:
    """The mass on the bearing, ``x = 0`` the loaded state (``P0 = W``: no gravity load)."""
    s = duhamel.System(M * np.eye(3), np.zeros((3, 3)))
    s.add(vertical(initial_axial_force=W))
    t, ax = record(6.0, 0.5, seed=13)
    _, ay = record(6.0, 0.4, seed=29)
    _, az = record(6.0, 0.5, seed=41)
    for dof, a in enumerate((ax, ay, az)):
        s.add_load(L.BaseAcceleration(np.eye(3)[dof], t=t, values=a))
    return s


def run(integrator: object, k: int) -> duhamel.Solution:
    return duhamel.solve(system(), integrator, t_end=6.0, dt=0.005 / k, save_every=k)


def test_semianalytic_and_newmark_converge_to_the_same_response() -> None:
    # converged: 4e-5 of the peak between the two (8e-5 at dt / 16 and dt / 64)
    semi = run(duhamel.Semianalytic(), 32)
    xs, xn = semi.x, run(duhamel.Newmark(), 128).x
    peak = np.abs(xs[:, :2]).max()
    assert peak > 100 * 5e-4  # the bearing slides many times over
    axial = W - semi.elements[0].force[:, 2]  # P0 minus the change on the dof
    assert axial.max() > 1.2 * W and axial.min() < 0.8 * W  # N moves with the record
    for j in range(2):
        err = np.abs(xs[:, j] - xn[:, j]).max() / peak
        assert err <= 1e-4, (j, err)
    vertical_peak = np.abs(xs[:, 2]).max()
    assert np.abs(xs[:, 2] - xn[:, 2]).max() <= 1e-4 * vertical_peak


def test_held_vertical_dof_is_the_bearing_under_its_weight() -> None:
    """Driven along a horizontal orbit with the vertical dof held where the spring carries
    ``N``: the bearing with ``weight = N`` (forces and tangents), and the vertical force
    ``-N``; in uplift OpenSees' ``MinFv`` times the same normalised force."""
    n_axial = 1.3 * W
    k = np.arange(600) * 0.03
    orbit = np.column_stack([0.5 * np.sin(k) * np.cos(0.3 * k), 0.3 * np.sin(0.7 * k)])
    flat = E.TripleFrictionPendulum((0, 1), mu=MU, radius=RADIUS, displacement_capacity=CAPACITY,
                                    weight=n_axial, yield_displacement=5e-4)  # fmt: skip
    ref = E.drive(flat, orbit)
    for z, n, extra in [(-n_axial / KV, n_axial, {}), (1e-3, 0.1, {"min_axial_force": 0.1})]:
        held = E.drive(vertical(**extra), np.column_stack([orbit, np.full(len(k), z)]))
        scale = n / n_axial
        np.testing.assert_allclose(held.force[:, :2], scale * ref.force, rtol=1e-12, atol=1e-9)
        np.testing.assert_allclose(held.force[:, 2], -n, rtol=1e-12)
        np.testing.assert_allclose(held.tangent[:, :2, :2], scale * ref.tangent, rtol=1e-12,
                                   atol=1e-6)  # fmt: skip
        # the coupling through N: dV/du_z = f dN/du_z (-kv compressed, 0 in uplift)
        dn = -KV if z < 0 else 0.0
        np.testing.assert_allclose(held.tangent[:, :2, 2], dn * ref.force / n_axial, rtol=1e-12,
                                   atol=1e-6)  # fmt: skip
        assert np.abs(ref.force).max() > 0.1 * n_axial  # into regimes II-III


@pytest.mark.parametrize(
    ("extra", "name"),
    [
        ({"vertical_stiffness": 0.0}, "vertical_stiffness"),
        ({"min_axial_force": -1.0}, "min_axial_force"),
        ({"initial_axial_force": -5.0}, "initial_axial_force"),
    ],
)
def test_bad_vertical_input_names_the_parameter(extra: dict, name: str) -> None:
    params = {"vertical_stiffness": KV, **extra}
    with pytest.raises(ValueError, match=f"`{name}`"):
        E.TripleFrictionPendulum(
            (0, 1, 2), mu=MU, radius=RADIUS, displacement_capacity=CAPACITY, weight=W,
            yield_displacement=5e-4, **params,
        )  # fmt: skip
    with pytest.raises(ValueError, match="`vertical_stiffness`"):
        E.TripleFrictionPendulum((0, 1, 2), mu=MU, radius=RADIUS,
                                 displacement_capacity=CAPACITY, weight=W)  # fmt: skip
    with pytest.raises(ValueError, match="`vertical_stiffness`"):
        E.TripleFrictionPendulum((0, 1), mu=MU, radius=RADIUS, displacement_capacity=CAPACITY,
                                 weight=W, vertical_stiffness=KV)  # fmt: skip


@pytest.mark.parametrize("dofs", [(0, 1, 2, 1), (0, 1, 2, 3, 4, 5, 6), (0, 1, 2, 3, 3)])
def test_bad_rotation_dofs_name_dofs(dofs: tuple) -> None:
    with pytest.raises(ValueError, match="`dofs`"):
        E.TripleFrictionPendulum(
            dofs, mu=MU, radius=RADIUS, displacement_capacity=CAPACITY, weight=W,
            vertical_stiffness=KV,
        )  # fmt: skip


def test_rotations_carry_the_pdelta_moments() -> None:
    """On ``(x, y, z, rx, ry, rz)``: the moments ``N u_y / 2``, ``-N u_x / 2`` and
    ``(V_x u_y - V_y u_x) / 2`` (OpenSees' on the top node), the shear unchanged."""
    k = np.arange(300) * 0.03
    z = -1.2 * W / KV
    orbit = np.column_stack([0.4 * np.sin(k), 0.2 * (1 - np.cos(k)), np.full(k.size, z)])
    plain = E.drive(vertical(), orbit)
    rotated = E.TripleFrictionPendulum(
        (0, 1, 2, 3, 4, 5), mu=MU, radius=RADIUS, displacement_capacity=CAPACITY, weight=W,
        yield_displacement=5e-4, vertical_stiffness=KV,
    )  # fmt: skip
    full = E.drive(rotated, np.column_stack([orbit, np.zeros((k.size, 3))]))
    np.testing.assert_array_equal(full.force[:, :3], plain.force)
    n_axial, (ux, uy) = 1.2 * W, orbit[:, :2].T
    np.testing.assert_allclose(full.force[:, 3], n_axial * uy / 2, rtol=1e-12)
    np.testing.assert_allclose(full.force[:, 4], -n_axial * ux / 2, rtol=1e-12)
    vx, vy = plain.force[:, 0], plain.force[:, 1]
    np.testing.assert_allclose(full.force[:, 5], (vx * uy - vy * ux) / 2, rtol=1e-9, atol=1e-6)

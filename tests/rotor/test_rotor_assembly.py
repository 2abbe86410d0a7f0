"""Rotor components own their matrices and dof mapping; the assembly is one generic loop."""

from __future__ import annotations

import numpy as np
import pytest

from duhamel.rotor import STEEL, Bearing, Disk, Rotor, Shaft
from duhamel.rotor.assembly import Assembly, Placed, assemble
from duhamel.rotor.dofs import DIRECTIONS, dof_index, global_dofs

SHAFT = Shaft(0.3, 0.05, material=STEEL)
DISK = Disk(2, 20.0, 0.2, 0.1)
BEARING = Bearing(1, 1e7, 2e7, kxy=1e5, kyx=-1e5, cxx=300.0, cyx=20.0)
FLUID = Bearing(4, [1e7, 3e7], [1e7, 2e7], cxx=[500.0, 100.0], speeds=[0.0, 200.0])


@pytest.mark.parametrize("component", [SHAFT, DISK, BEARING, FLUID])
def test_component_matrices_live_on_its_dof_mapping(component):
    n = len(component.dof_mapping())
    assert sorted(component.dof_mapping().values()) == list(range(n))
    for matrix in (component.M(), component.K(50.0), component.C(50.0), component.G()):
        assert matrix.shape == (n, n)
    assert np.array_equal(component.G(), -component.G().T)


def test_component_matrices_match_their_older_accessors():
    M, K, G = SHAFT.matrices()
    assert np.array_equal(SHAFT.M(), M) and np.array_equal(SHAFT.K(), K)
    assert np.array_equal(SHAFT.G(), G) and not SHAFT.C().any()
    assert not SHAFT.M().flags.writeable  # the cached copy the rotor assembles
    md, gd = DISK.matrices()
    assert np.array_equal(DISK.M(), md) and np.array_equal(DISK.G(), gd)
    assert np.array_equal(BEARING.K(), BEARING.stiffness)
    assert np.array_equal(FLUID.C(100.0), FLUID.damping_at(100.0))


def test_global_dofs_follow_the_node_numbering():
    assert Placed.at(SHAFT, 3).dofs.tolist() == list(range(12, 20))
    assert Placed.at(DISK, DISK.node).dofs.tolist() == [8, 9, 10, 11]
    assert Placed.at(BEARING, BEARING.node).dofs.tolist() == [4, 5]
    for name, k in DIRECTIONS.items():
        assert global_dofs({f"{name}_1": 0}, 2).tolist() == [4 * 3 + k]
        assert dof_index(3, name, 5) == 12 + k
    with pytest.raises(ValueError, match="node"):
        dof_index(5, "x", 5)


def test_rotor_matrices_are_the_scattered_component_matrices():
    rotor = Rotor([SHAFT] * 4, [DISK], [BEARING, FLUID], rayleigh=(0.0, 0.0))
    speed = 100.0
    n = rotor.n_dof
    M, K, C, G = (np.zeros((n, n)) for _ in range(4))
    for i, shaft in enumerate(rotor.shafts):  # by hand: shaft i on nodes i, i + 1
        s = slice(4 * i, 4 * i + 8)
        M[s, s] += shaft.M()
        K[s, s] += shaft.K()
        G[s, s] += shaft.G()
    s = slice(4 * DISK.node, 4 * DISK.node + 4)
    M[s, s] += DISK.M()
    G[s, s] += DISK.G()
    for b in rotor.bearings:
        ix = np.ix_([4 * b.node, 4 * b.node + 1], [4 * b.node, 4 * b.node + 1])
        K[ix] += b.K(speed)
        C[ix] += b.C(speed)
    got = rotor.matrices(speed)
    for a, b in zip(got, (M, K, C, G), strict=True):
        np.testing.assert_allclose(a, b, rtol=1e-15, atol=0.0)


def test_a_new_component_assembles_without_changing_the_assembly():
    class Spring:  # a grounded spring on one node's x: any object with the five methods
        def dof_mapping(self):
            return {"x_0": 0}

        def M(self):
            return np.zeros((1, 1))

        def K(self, speed=0.0):
            return np.array([[5.0 + speed]])

        def C(self, speed=0.0):
            return np.zeros((1, 1))

        def G(self):
            return np.zeros((1, 1))

    placed = [Placed.at(Spring(), 1), Placed.at(Spring(), 1)]
    K = assemble(placed, 8, "K", speed=1.0)
    assert K[4, 4] == 12.0 and np.count_nonzero(K) == 1
    assembly = Assembly([Placed.at(SHAFT, 0)], placed, 8)
    assert np.array_equal(assembly.supports_at(0.0)[0], K - 2.0 * (K != 0))

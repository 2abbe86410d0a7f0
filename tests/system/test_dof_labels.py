"""Dof labels work wherever a dof index does: System.dof, elements and loads added with
labels, solve(..., dofs=labels), BaseAcceleration along a component, the labelled views."""

from __future__ import annotations

import numpy as np
import pytest

import duhamel
from duhamel import elements as E
from duhamel import loads as L

LABELS = [(1, "ux"), (1, "uy"), (2, "ux"), (2, "uy")]


def _system() -> duhamel.System:
    k = 1e4 * np.array(
        [[2.0, 0, -1, 0], [0, 2.0, 0, -1], [-1, 0, 1.0, 0], [0, -1, 0, 1.0]], dtype=float
    )
    return duhamel.System(np.diag([1.0, 1.0, 2.0, 2.0]), k, zeta=0.02)


def test_pairs_strings_and_aliases() -> None:
    s = _system().label_dofs(LABELS, aliases={(7, "ux"): 2})
    assert s.dof(2, "uy") == s.dof((2, "uy")) == s.dof("2:uy") == 3
    assert s.dof(7, "ux") == 2
    assert s.dof_labels == ("1:ux", "1:uy", "2:ux", "2:uy")
    with pytest.raises(ValueError, match=r"\(9, 'ux'\) names no dof"):
        s.dof(9, "ux")
    with pytest.raises(ValueError, match="not labelled"):
        _system().dof(1, "ux")
    with pytest.raises(ValueError, match="distinct"):
        _system().label_dofs([(1, "ux"), "1:ux", "a", "b"])


def test_elements_and_loads_with_labels_equal_indices() -> None:
    t = np.linspace(0.0, 2.0, 201)
    a = 3.0 * np.sin(5.0 * t)
    by_label = _system().label_dofs(LABELS)
    by_label.add(E.Bilinear((2, "ux"), (1, "ux"), k=5e3, fy=20.0, alpha=0.1))
    by_label.add(E.FrictionPendulum(((1, "ux"), (1, "uy")), radius=2.0, mu=0.05, weight=50.0))
    by_label.add_load(L.Step((2, "uy"), amplitude=10.0, t0=0.5))
    by_label.add_load(L.BaseAcceleration("ux", t=t, values=a))
    by_index = _system()
    by_index.add(E.Bilinear(2, 0, k=5e3, fy=20.0, alpha=0.1))
    by_index.add(E.FrictionPendulum((0, 1), radius=2.0, mu=0.05, weight=50.0))
    by_index.add_load(L.Step(3, amplitude=10.0, t0=0.5))
    by_index.add_load(L.BaseAcceleration(np.array([1.0, 0.0, 1.0, 0.0]), t=t, values=a))
    assert by_label.elements == by_index.elements
    np.testing.assert_array_equal(by_label.loads[1].direction_vector, [1.0, 0.0, 1.0, 0.0])
    run = {"t_end": 2.0, "dt": 0.01}
    ours = duhamel.solve(by_label, duhamel.Semianalytic(), dofs=[(2, "ux"), (1, "uy")], **run)
    ref = duhamel.solve(by_index, duhamel.Semianalytic(), dofs=[2, 1], **run)
    np.testing.assert_array_equal(ours.x, ref.x)
    assert ours.dofs.tolist() == [2, 1]
    assert list(ours.to_xarray().coords["label"].values) == ["2:ux", "1:uy"]


def test_label_errors_name_the_parameter() -> None:
    s = _system().label_dofs(LABELS)
    with pytest.raises(ValueError, match=r"`i` \(5, 'ux'\)"):
        s.add(E.Bilinear((5, "ux"), k=1.0, fy=1.0))
    with pytest.raises(ValueError, match="`direction_vector` 'uz' names no dofs"):
        s.add_load(L.BaseAcceleration("uz", t=[0.0, 1.0], values=[0.0, 1.0]))
    prepared = duhamel.prepare(_system(), duhamel.Semianalytic(), dt=0.01)
    with pytest.raises(ValueError, match="names no dofs"):  # a system without labels
        prepared.run(t_end=0.1, loads=[L.BaseAcceleration("ux", t=[0.0, 1.0], values=[0.0, 1.0])])
    with pytest.raises(ValueError, match=r"`dofs\[1\]`"):
        duhamel.solve(s, duhamel.Semianalytic(), t_end=0.1, dt=0.01, dofs=[0, (3, "rz")])

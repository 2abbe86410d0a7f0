"""A uniaxial material starting loaded (``initial_deformation``, issue 36: a hinge after a
gravity analysis): the element is the same material driven from rest monotonically to the
initial deformation (100 equal increments, ``numpy.linspace(0, d0, 101)``) and on, its
force measured from the force there.

* driven by :func:`duhamel.elements.drive`: the loaded element through ``d`` equals the
  virgin one through ``linspace(0, d0, 101)`` then ``d0 + d``, minus the force at ``d0``,
  bit for bit (force and tangent), for a yielded and an elastic start;
* in a System (the load that held the start taken off under a harmonic force), on the
  semi-analytic and Newmark routes: the element's force along the run equals the virgin
  material driven through the same path (from rest to ``d0``, then ``d0`` plus the run's
  deformation at every step), minus the force at ``d0``;
* refusals: a non-finite initial deformation, and a part of a wrapper with its own.
"""

from __future__ import annotations

import numpy as np
import pytest
from _materials_system import DT, FY, MATERIALS, UY, element, keywords

import duhamel
from duhamel import elements as E
from duhamel import loads as L

N = 100  # the increments of a loaded start (crates/.../materials/uniaxial.rs)


def loaded(kind: str, d0: float) -> E.Element:
    return getattr(E, kind)(0, None, **keywords(MATERIALS[kind][0]), initial_deformation=d0)


def reference(kind: str, d0: float, d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The virgin material from rest to ``d0`` and on along ``d0 + d``: force minus the
    force at ``d0``, and tangent, at the points of ``d``."""
    path = np.concatenate([np.linspace(0.0, d0, N + 1), d0 + d])
    ref = duhamel.elements.drive(element(kind, MATERIALS[kind][0]), path)
    return ref.force[N + 1 :] - ref.force[N], ref.tangent[N + 1 :]


@pytest.mark.parametrize("d0", [1.5 * UY, -0.5 * UY])
@pytest.mark.parametrize("kind", list(MATERIALS))
def test_a_loaded_start_is_the_material_driven_there_from_rest(kind: str, d0: float) -> None:
    d = 2.0 * UY * np.sin(np.linspace(0.0, 5 * np.pi, 301)) * np.linspace(0.2, 1.0, 301)
    got = duhamel.elements.drive(loaded(kind, d0), d)
    force, tangent = reference(kind, d0, d)
    np.testing.assert_array_equal(got.force, force)
    np.testing.assert_array_equal(got.tangent, tangent)
    assert got.force[0] == 0.0  # at x = 0: no force on the equations


C = 0.3  # the SDOF's damping (mass 1, no stiffness but the element's)
OMEGA = 2 * np.pi * 0.9


@pytest.mark.parametrize("route", ["semianalytic", "newmark"])
@pytest.mark.parametrize("kind", list(MATERIALS))
def test_a_loaded_start_in_a_run_continues_the_driven_material(kind: str, route: str) -> None:
    """From the loaded start (yielded at ``d0 = 1.5 UY``) the load that held ``F0`` is
    taken off (a step ``-F0``) under a harmonic force near resonance: the element unloads
    and swings through yield both ways. Its force along the run is the virgin material's
    driven through the same path. The semi-analytic route keeps the element's force (to
    rounding); Newmark's is the equilibrium ``p - a - C v`` (to its Newton tolerance,
    ``tol=1e-13``)."""
    d0 = 1.5 * UY
    f0 = duhamel.elements.drive(element(kind, MATERIALS[kind][0]), np.linspace(0, d0, N + 1))
    s = duhamel.System(np.eye(1), np.zeros((1, 1)), C * np.eye(1))
    s.add(loaded(kind, d0))
    s.add_load(L.Harmonic(0, amplitude=0.8 * FY, omega=OMEGA))
    s.add_load(L.Step(0, amplitude=-f0.force[-1]))
    if route == "semianalytic":
        sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=4.0, dt=DT / 4)
        x, f = sol.elements[0].deformation, sol.elements[0].axial_force
        tol = 1e-14  # measured 7e-17 to 1.4e-16
    else:
        sol = duhamel.solve(s, duhamel.Newmark(tol=1e-13), t_end=4.0, dt=DT / 4)
        p = 0.8 * FY * np.sin(OMEGA * sol.t) - f0.force[-1]
        x, f = sol.x[:, 0], p - np.asarray(sol.a)[:, 0] - C * sol.v[:, 0]
        x, f = x[1:], f[1:]  # the step load's value at t = 0 is a convention
        tol = 1e-12  # measured 7e-16 to 1.6e-15
    assert d0 + x.min() < -1.2 * UY and d0 + x.max() > 2.0 * UY, f"{kind}: no yield both ways"
    force, _ = reference(kind, d0, x)
    err = np.abs(f - force).max() / np.abs(force).max()
    assert err <= tol, f"{kind}, {route}: {err:.2e} of the largest force off"


def test_initial_deformation_must_be_finite() -> None:
    with pytest.raises(ValueError, match="`initial_deformation` must be finite"):
        E.Steel02(0, fy=1.0, E=100.0, b=0.02, initial_deformation=float("inf"))


def test_a_part_of_a_wrapper_starts_where_its_wrapper_starts() -> None:
    part = E.Steel02(0, fy=1.0, E=100.0, b=0.02, initial_deformation=0.01)
    with pytest.raises(ValueError, match="initial_deformation"):
        E.MinMax(0, material=part, min=-1.0, max=1.0)

"""ROSS models with point masses and bearings linked to another node (issue 40): ROSS's
``coaxrotor_example`` (two shafts on linked bearings, two point-mass supports) and ROSS's
example rotor on pedestals (point masses of 20 kg on linked bearings) — their modes,
Campbell diagram, critical speeds and unbalance response against ROSS's ``run_modal`` and
``run_unbalance_response`` (1e-8), their time response against ROSS's matrices integrated
exactly (``expm``).
"""

from __future__ import annotations

import contextlib
import functools
import io
import warnings

import numpy as np
import pytest
import scipy.linalg

import duhamel
from duhamel.rotor import from_ross

REASON = "ROSS (ross-rotordynamics, the duhamel[ross] extra) is not installed"
SPEED = 500.0


@functools.cache
def _ross():
    with warnings.catch_warnings(), contextlib.redirect_stdout(io.StringIO()):
        warnings.simplefilter("ignore")  # ROSS's ccp dependency warns about REFPROP
        return pytest.importorskip("ross", reason=REASON)


def quiet(fn, *args, **kwargs):
    with warnings.catch_warnings(), contextlib.redirect_stdout(io.StringIO()):
        warnings.simplefilter("ignore")
        return fn(*args, **kwargs)


def coaxial():
    return quiet(_ross().coaxrotor_example)


def pedestals():
    """ROSS's example rotor, each bearing on a 20 kg pedestal (a point mass) that sits on
    a stiff, damped support."""
    ross = _ross()
    base = quiet(ross.rotor_example)
    masses = [ross.PointMass(n=7, m=20.0), ross.PointMass(n=8, m=20.0)]
    bearings = [
        ross.BearingElement(0, kxx=1e6, kyy=1.2e6, cxx=100.0, cyy=120.0, n_link=7),
        ross.BearingElement(6, kxx=1e6, kyy=1.2e6, cxx=100.0, cyy=120.0, n_link=8),
        ross.BearingElement(7, kxx=5e7, kyy=6e7, cxx=500.0, cyy=500.0),
        ross.BearingElement(8, kxx=5e7, kyy=6e7, cxx=500.0, cyy=500.0),
    ]
    return quiet(ross.Rotor, base.shaft_elements, base.disk_elements, bearings,
                 point_mass_elements=masses)  # fmt: skip


CASES = {"coaxial": coaxial, "pedestals": pedestals}


def ross_lateral(rr, dofs, speed, count):
    """ROSS's lateral eigenvalues (Im > 0, ascending; its axial and torsional modes, which
    from_ross drops, left out by their shapes)."""
    modal = quiet(rr.run_modal, speed, num_modes=2 * count + 20)
    lam = np.asarray(modal.evalues)[: modal.wd.size]
    shapes = modal.evectors[: rr.ndof, : modal.wd.size]
    lateral = np.linalg.norm(shapes[dofs.ross_index], axis=0) / np.linalg.norm(shapes, axis=0)
    lam = lam[lateral > 0.5]
    return lam[np.argsort(lam.imag)][:count]


@pytest.mark.parametrize("case", list(CASES))
def test_modes_equal_rosss_run_modal(case):
    rr = CASES[case]()
    model = from_ross(rr, 0.0)
    layout = model.rotor.layout
    assert layout is not None and np.any(layout[:, 2:] < 0)  # nodes with x and y only
    for speed in (0.0, SPEED):
        ours = model.modes(speed, n=10)
        theirs = ross_lateral(rr, model.dofs, speed, 10)
        err = float(np.max(np.abs(ours.eigenvalues - theirs) / np.abs(theirs)))
        print(f"\n{case} at {speed:g} rad/s: modes vs ROSS run_modal {err:.1e}")
        assert err < 1e-8
        assert set(ours.whirl) <= {"forward", "backward", "mixed", "planar"}
        # the point masses move in the shapes (their x, y rows are there)
        masses = layout[layout[:, 2] < 0, :2].ravel()
        assert np.abs(ours.shapes[masses]).max() > 1e-6


@pytest.mark.parametrize("case", list(CASES))
def test_campbell_and_critical_speeds_run_on_the_model(case):
    rr = CASES[case]()
    model = from_ross(rr, 0.0)
    diagram = model.campbell(np.linspace(0.0, 800.0, 9), n_modes=4)
    # every row shows the lowest four frequencies (a tracked branch may leave the four)
    assert np.all(np.sum(np.isfinite(diagram.frequencies), axis=1) == 4)
    crit = model.critical_speeds(np.linspace(10.0, 800.0, 40))
    for c in crit.critical:
        assert np.min(np.abs(model.modes(c.speed).frequencies - c.speed)) < 1e-9 * c.speed


@pytest.mark.parametrize("case", list(CASES))
def test_unbalance_response_equals_rosss(case):
    rr = CASES[case]()
    model = from_ross(rr, 0.0)
    node = int(rr.disk_elements[0].n)
    speeds = np.linspace(10.0, 1000.0, 120)
    ours = model.rotor.unbalance_response(speeds, [(node, 1e-3, 0.3)]).response
    theirs = quiet(rr.run_unbalance_response, node, 1e-3, 0.3, speeds).forced_resp.T
    lateral = model.dofs.ross_index
    err = float(np.abs(model.dofs.to_ross(ours)[:, lateral] - theirs[:, lateral]).max()
                / np.abs(theirs[:, lateral]).max())  # fmt: skip
    print(f"\n{case}: unbalance response vs ROSS {err:.1e}")
    assert err < 1e-8


def test_a_transient_on_pedestals_is_the_exact_response():
    """A step force at the disk: duhamel.solve on from_ross's System against ROSS's
    matrices in first order, stepped with expm (exact for a step)."""
    rr = pedestals()
    model = from_ross(rr, SPEED)
    node = int(rr.disk_elements[0].n)
    dx = model.dofs(node, "x")
    model.system.add_load(duhamel.loads.Step(dx, amplitude=100.0))
    sol = duhamel.solve(model.system, duhamel.Semianalytic(), t_end=0.05, dt=5e-4)
    M, K, C, G = model.matrices
    n = M.shape[0]
    A = np.block([[np.zeros((n, n)), np.eye(n)],
                  [-np.linalg.solve(M, K), -np.linalg.solve(M, C + SPEED * G)]])  # fmt: skip
    f = np.zeros(2 * n)
    f[n:] = np.linalg.solve(M, np.eye(n)[dx] * 100.0)
    big = np.zeros((2 * n + 1, 2 * n + 1))
    big[: 2 * n, : 2 * n], big[: 2 * n, 2 * n] = A * 5e-4, f * 5e-4
    step = scipy.linalg.expm(big)
    s, ref = np.zeros(2 * n + 1), []
    s[-1] = 1.0
    for _ in sol.t:
        ref.append(s[:n].copy())
        s = step @ s
    ref = np.array(ref)
    err = float(np.abs(sol.x - ref).max() / np.abs(ref).max())
    masses = [model.dofs(7, "x"), model.dofs(8, "y")]
    assert np.abs(sol.x[:, masses]).max() > 1e-3 * np.abs(sol.x).max()  # the pedestals move
    assert err < 1e-8

"""ROSS's axial and torsional dofs through ``from_ross(..., dofs="all")`` (issue 40): all six
dofs per node kept; the modes — lateral, axial, torsional — against ROSS's ``run_modal``
(1e-8), a two-inertia drive train's torsional frequency against its closed form
(``omega^2 = k_t (J_1 + J_2) / (J_1 J_2)``, 1e-12), and a start-up torque transient through
``duhamel.solve`` against ``solve_ivp`` (DOP853) on ROSS's matrices.
"""

from __future__ import annotations

import contextlib
import functools
import io
import warnings

import numpy as np
import pytest
import scipy.integrate

import duhamel
from duhamel.rotor import from_ross

REASON = "ROSS (ross-rotordynamics, the duhamel[ross] extra) is not installed"


@functools.cache
def _ross():
    with warnings.catch_warnings(), contextlib.redirect_stdout(io.StringIO()):
        warnings.simplefilter("ignore")  # ROSS's ccp dependency warns about REFPROP
        return pytest.importorskip("ross", reason=REASON)


def quiet(fn, *args, **kwargs):
    with warnings.catch_warnings(), contextlib.redirect_stdout(io.StringIO()):
        warnings.simplefilter("ignore")
        return fn(*args, **kwargs)


@pytest.mark.parametrize("speed", [0.0, 500.0])
def test_every_mode_equals_rosss_run_modal(speed):
    rr = quiet(_ross().rotor_example)
    model = from_ross(rr, 0.0, dofs="all")
    assert model.system.n_dof == rr.ndof == 42
    modes = model.modes(speed)
    lam = np.asarray(quiet(rr.run_modal, speed, num_modes=2 * modes.n_modes + 10).evalues)
    lam = lam[lam.imag > 0]
    err = max(float(np.min(np.abs(lam - m)) / abs(m)) for m in modes.eigenvalues[:30])
    print(f"\nall dofs at {speed:g} rad/s: 30 lowest modes vs ROSS run_modal {err:.1e}")
    assert err < 1e-8
    torsional = [f for f, w in zip(modes.frequencies, modes.whirl, strict=True)
                 if w == "torsional"]  # fmt: skip
    assert torsional and abs(torsional[0] - 774.35) < 0.01  # ROSS's example's first one
    lateral = from_ross(rr, 0.0).modes(speed)
    kept = [f for f, w in zip(modes.frequencies, modes.whirl, strict=True)
            if w not in ("torsional", "axial")]  # fmt: skip
    np.testing.assert_allclose(kept[:20], lateral.frequencies[:20], rtol=1e-10)


def two_inertias():
    """A massless shaft (one element) between two disks: a two-inertia drive train."""
    ross = _ross()
    steel = ross.Material(name="massless", rho=1e-30, E=2.1e11, Poisson=0.3)
    shaft = ross.ShaftElement(
        L=0.5, idl=0.0, odl=0.04, material=steel, shear_effects=False, rotary_inertia=False,
        gyroscopic=False,
    )  # fmt: skip
    disks = [ross.DiskElement(n=0, m=30.0, Id=0.2, Ip=0.4),
             ross.DiskElement(n=1, m=10.0, Id=0.05, Ip=0.1)]  # fmt: skip
    bearings = [ross.BearingElement(n, kxx=1e7, cxx=0.0) for n in (0, 1)]
    return quiet(ross.Rotor, [shaft], disks, bearings), steel


def test_two_inertia_drive_train_equals_the_closed_form():
    rr, steel = two_inertias()
    model = from_ross(rr, 0.0, dofs="all")
    modes = model.modes(0.0)
    torsional = [f for f, w in zip(modes.frequencies, modes.whirl, strict=True)
                 if w == "torsional"]  # fmt: skip
    k_t = float(steel.G_s) * np.pi * 0.04**4 / 32.0 / 0.5
    J1, J2 = 0.4, 0.1
    exact = np.sqrt(k_t * (J1 + J2) / (J1 * J2))
    assert len(torsional) == 1
    assert abs(torsional[0] - exact) < 1e-12 * exact


def test_start_up_torque_transient_equals_solve_ivp():
    """A motor torque ramped up on the first disk of the drive train (the shaft twists and
    the train spins up as a rigid body): duhamel.solve against DOP853 on ROSS's matrices."""
    rr, _ = two_inertias()
    model = from_ross(rr, 0.0, dofs="all")
    motor = model.dofs(0, "theta")
    t_ramp, torque, T = 0.01, 50.0, 0.03
    model.system.add_load(
        duhamel.loads.Tabulated(motor, t=[0.0, t_ramp, 1.0], values=[0.0, torque, torque])
    )
    sol = duhamel.solve(model.system, duhamel.Semianalytic(), t_end=T, dt=1e-4)
    M, K, C, _ = model.matrices
    n = M.shape[0]
    Minv = np.linalg.inv(M)

    def rhs(t, s):
        f = np.zeros(n)
        f[motor] = torque * min(t / t_ramp, 1.0)
        return np.concatenate([s[n:], Minv @ (f - K @ s[:n] - C @ s[n:])])

    ref = scipy.integrate.solve_ivp(rhs, (0.0, sol.t[-1]), np.zeros(2 * n), "DOP853", t_eval=sol.t,
                                    rtol=1e-12, atol=1e-16, max_step=t_ramp / 4).y.T  # fmt: skip
    twist = sol.x[:, motor] - sol.x[:, model.dofs(1, "theta")]
    err = float(np.abs(sol.x - ref[:, :n]).max() / np.abs(ref[:, :n]).max())
    print(f"\nstart-up torque: vs DOP853 {err:.1e}, peak twist {np.abs(twist).max():.3e} rad")
    assert np.abs(twist).max() > 0.0 and sol.x[-1, motor] > 0.0  # twists and spins up
    assert err < 1e-8

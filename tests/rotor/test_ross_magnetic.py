"""ROSS's magnetic bearings through ``from_ross`` (issue 40): the mapping of
``MagneticBearingElement`` onto duhamel's ``MagneticBearing`` (the sign of k_s; ROSS's
frequency-domain AMB law ``k_eq + i w c_eq = k_s + k_i k_amp k_sense C(i w)``), the closed
loop of ``rotor_amb_example()`` against a state-space model written out here from ROSS's
own rotor without the bearings and the elements' parameters, its stability judged against
round-off (marginal: ``k_i k_p = -k_s``), its unbalance response against the balanced state
space and against ROSS's ``run_unbalance_response``, and where ROSS's ``run_modal`` differs
(it takes the controller at the spin frequency).
"""

from __future__ import annotations

import contextlib
import functools
import io
import time
import warnings

import numpy as np
import pytest
import scipy.linalg

import duhamel
from duhamel.rotor import from_ross
from duhamel.rotor.magnetic import MarginalWarning
from duhamel.rotor.ross.magnetic import magnetic_bearing

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


@functools.cache
def amb_rotor(kp: float = 1000.0, ki: float = 0.0, frequency: tuple | None = None):
    """ROSS's ``rotor_amb_example`` with its PID gains (and frequency grid) changed."""
    ross = _ross()
    base = quiet(ross.rotor_amb_example)
    bearings = []
    for b in base.bearing_elements:
        kwargs = {"frequency": list(frequency)} if frequency is not None else {}
        f = lambda v: float(np.asarray(v).ravel()[0])  # noqa: E731  (ROSS keeps arrays)
        bearings.append(
            quiet(
                ross.MagneticBearingElement,
                n=b.n,
                g0=f(b.g0),
                i0=f(b.i0),
                ag=f(b.ag),
                nw=f(b.nw),
                alpha=f(b.alpha),
                k_amp=1.0,
                k_sense=1.0,
                kp_pid=kp,
                kd_pid=f(b.kd_pid),
                ki_pid=ki,
                n_f=f(b.n_f),
                **kwargs,
            )
        )
    return quiet(ross.Rotor, base.shaft_elements, base.disk_elements, bearings)


def lateral(rr):
    """ROSS's lateral dof indices (its own names), in its order."""
    names = {}
    for e in rr.elements:
        names.update(e.dof_global_index)
    return np.array(
        sorted(i for s, i in names.items() if s.split("_")[0] in ("x", "y", "alpha", "beta"))
    )


def written_out(rr, speed):
    """The closed loop ``s' = A s`` written out from ROSS: the rotor rebuilt without its
    bearings (its M, K, C, G), and per bearing and axis ROSS's law ``f = -(k_s x + k_i u)``,
    ``u = k_amp k_sense (k_p x + k_i,pid z_i + k_d n_f (x - w))``, ``z_i' = x``,
    ``w' = n_f (x - w)`` (the filtered derivative ``k_d s / (1 + s / n_f)``)."""
    ross = _ross()
    bare = quiet(ross.Rotor, rr.shaft_elements, rr.disk_elements, [])
    keep = lateral(bare)
    M, K, C = (
        np.asarray(f(speed), dtype=float)[np.ix_(keep, keep)] for f in (bare.M, bare.K, bare.C)
    )
    G = np.asarray(bare.G(), dtype=float)[np.ix_(keep, keep)]
    n = keep.size
    pos = {int(g): i for i, g in enumerate(keep)}
    axes = []
    for b in rr.bearing_elements:
        for axis in ("x", "y"):
            axes.append((pos[b.dof_global_index[f"{axis}_{b.n}"]], b))
    per = [(1 if b.ki_pid else 0) + (1 if b.kd_pid else 0) for _, b in axes]
    N = 2 * n + sum(per)
    A = np.zeros((N, N))
    M_inv = np.linalg.inv(M)
    A[:n, n : 2 * n] = np.eye(n)
    A[n : 2 * n, :n] = -M_inv @ K
    A[n : 2 * n, n : 2 * n] = -M_inv @ (C + speed * G)
    row = 2 * n
    for j, b in axes:
        g = b.ki * b.k_amp * b.k_sense
        force = np.zeros(N)  # on dof j
        force[j] -= b.ks + g * b.kp_pid
        if b.ki_pid:
            force[row] -= g * b.ki_pid
            A[row, j] = 1.0
            row += 1
        if b.kd_pid:
            force[j] -= g * b.kd_pid * b.n_f
            force[row] += g * b.kd_pid * b.n_f
            A[row, j], A[row, row] = b.n_f, -b.n_f
            row += 1
        A[n : 2 * n] += np.outer(M_inv[:, j], force)
    return A, M, n


# ------------------------------------------------------------------------------ the mapping
@pytest.mark.parametrize("gains", [(1.0, 1.0), (2.5, 0.4)])
def test_dynamic_stiffness_equals_rosss_equivalent_coefficients(gains):
    """k_i C(i w) - k_s of the mapped bearing is ROSS's ``k_eq + i w c_eq`` on its grid (the
    sign of k_s flips: ROSS's is negative), for its PID and a transfer function."""
    ross = _ross()
    k_amp, k_sense = gains
    ctl = pytest.importorskip("control")
    tf = ctl.TransferFunction([2e-3, 1.0, 800.0], [1e-8, 3e-4, 1.0])
    for extra in ({"kp_pid": 1200.0, "kd_pid": 4.0, "ki_pid": 300.0},
                  {"controller_transfer_function": tf}):  # fmt: skip
        e = quiet(ross.MagneticBearingElement, n=3, g0=1e-3, i0=1.2, ag=1e-4, nw=200,
                  k_amp=k_amp, k_sense=k_sense, **extra)  # fmt: skip
        b = magnetic_bearing(e)
        assert b.node == 3 and b.k_s == -e.ks > 0.0 and b.k_i == e.ki
        w = np.asarray(e.frequency, dtype=float)
        ours = b.k_i * b.controller(1j * w) - b.k_s
        theirs = np.asarray(e.kxx) + 1j * w * np.asarray(e.cxx)
        assert np.abs(ours - theirs).max() < 1e-12 * np.abs(theirs).max()
        assert np.abs(np.asarray(e.kxy)).max() < 1e-9 * np.abs(theirs).max()  # isotropic


def test_refuses_what_it_cannot_map():
    ross = _ross()
    e = quiet(ross.MagneticBearingElement, n=3, g0=1e-3, i0=1.0, ag=1e-4, nw=200, kp_pid=1e3,
              kd_pid=5.0, n_link=7)  # fmt: skip
    with pytest.raises(ValueError, match="linked to node 7"):
        magnetic_bearing(e)


# ------------------------------------------------------------------------------ the closed loop
def test_closed_loop_eigenvalues_equal_the_written_out_state_space_model():
    for rr in (amb_rotor(), amb_rotor(1100.0, 400.0)):
        model = from_ross(rr, SPEED)
        A, _, _ = written_out(rr, SPEED)
        # the reference's eigenvalues with the dense solver's own accuracy on each (its
        # round-off bound: near-degenerate x/y pairs and the marginal loop's near-zero
        # eigenvalues are ill-conditioned)
        from duhamel.rotor._roundoff import spectrum

        spec = spectrum(A)
        modes = model.modes(SPEED)
        worst, plain = 0.0, 0.0
        for v in np.concatenate([modes.eigenvalues, modes.overdamped]):
            k = int(np.argmin(np.abs(spec.eigenvalues - v)))
            gap = abs(spec.eigenvalues[k] - v)
            worst = max(worst, gap / max(1e-8 * abs(v), spec.bounds[k]))
            plain = max(plain, gap / abs(v)) if spec.bounds[k] < 1e-8 * abs(v) else plain
        print(f"\nclosed-loop modes vs written-out state space: well-conditioned ones "
              f"{plain:.1e}, all within {worst:.2f} of max(1e-8, their round-off bound) "
              f"({modes.n_modes} modes)")  # fmt: skip
        assert modes.n_modes > 100 and plain < 1e-8 and worst <= 1.0


def test_rosss_example_is_marginal_not_unstable():
    """k_i k_p = -k_s: zero net bearing stiffness, four eigenvalues zero up to round-off;
    a stiffer PID is stable, a softer one unstable."""
    loop = from_ross(amb_rotor(), SPEED).rotor.closed_loop(SPEED)
    assert loop.stability == "marginal" and not loop.stable
    assert "marginal: 4 eigenvalue(s)" in loop.stability_note
    near = loop.eigenvalues[np.argsort(np.abs(loop.eigenvalues))[:4]]
    assert np.all(np.abs(near) < 1e-4)  # zero to round-off (the solver gives ~1e-5)
    d = [loop.axes[0][0]]
    with pytest.warns(MarginalWarning, match="marginal"):
        loop.frequency_response([100.0, 700.0], d, d)
    assert from_ross(amb_rotor(1100.0), SPEED).rotor.closed_loop(SPEED).stability == "stable"
    soft = from_ross(amb_rotor(950.0), SPEED).rotor.closed_loop(SPEED)
    assert soft.stability == "unstable" and "grow" in soft.stability_note
    with pytest.raises(ValueError, match="unstable"):
        soft.frequency_response([100.0], d, d)


def test_rosss_run_modal_takes_the_controller_at_the_spin_frequency():
    """ROSS's ``run_modal(speed)`` evaluates the bearings at ``frequency = speed``: its
    modes are those of a rotor on springs and dampers ``k_eq(speed), c_eq(speed)``, not of
    the closed loop. They agree with the closed loop's where the controller's value at the
    mode's own frequency is near its value at the speed (the flexible modes, whose motion
    at the bearings is small) and not on the rigid-body modes the loop holds."""
    rr = amb_rotor(1100.0, 400.0)
    model = from_ross(rr, SPEED)
    ours = model.modes(SPEED)
    theirs = quiet(rr.run_modal, SPEED, num_modes=60)
    lam = np.asarray(theirs.evalues)
    lam = lam[lam.imag > 0]
    flexible = ours.eigenvalues[(ours.frequencies > 2000.0) & (ours.frequencies < 3e4)]
    gaps = [float(np.min(np.abs(lam - m)) / abs(m)) for m in flexible]
    low = ours.eigenvalues[0]
    low_gap = float(np.min(np.abs(lam - low)) / abs(low))
    print(f"\nROSS run_modal vs closed loop: flexible modes within {max(gaps):.1e}, "
          f"lowest mode {low_gap:.1e}")  # fmt: skip
    assert max(gaps) < 1e-2 and low_gap > 10 * max(gaps)


# ------------------------------------------------------------------------------ responses
def test_unbalance_response_equals_the_balanced_state_space_and_ross():
    """Exact at each speed: the closed loop's steady state. ROSS's run_unbalance_response
    takes the bearings' coefficients at the speed on their frequency grid (interpolated
    between its 50 points): on a grid that holds the speeds it is exact too."""
    speeds = np.linspace(50.0, 3000.0, 60)
    rr = amb_rotor(1100.0, 400.0, tuple(speeds))
    model = from_ross(rr, 0.0)
    start = time.perf_counter()
    res = model.rotor.unbalance_response(speeds, [(27, 1e-4, 0.0)])
    ours_time = time.perf_counter() - start
    A, M, n = written_out(rr, 0.0)
    dofs = model.dofs
    ref = np.empty_like(res.response)
    _, (scale, _) = scipy.linalg.matrix_balance(A, permute=False, separate=True)
    for k, w in enumerate(speeds):
        Aw, _, _ = written_out(rr, w)
        Ab = Aw * scale[None, :] / scale[:, None]
        F = np.zeros(n, dtype=complex)
        F[dofs(27, "x")], F[dofs(27, "y")] = 1e-4 * w**2, -1j * 1e-4 * w**2
        B = np.zeros(Aw.shape[0], dtype=complex)
        B[n : 2 * n] = np.linalg.solve(M, F)
        ref[k] = (scale * np.linalg.solve(1j * w * np.eye(Aw.shape[0]) - Ab, B / scale))[:n]
    err = float(np.abs(res.response - ref).max() / np.abs(ref).max())
    start = time.perf_counter()
    theirs = quiet(rr.run_unbalance_response, 27, 1e-4, 0.0, speeds).forced_resp.T
    ross_time = time.perf_counter() - start
    err_ross = float(np.abs(dofs.to_ross(res.response)[:, dofs.ross_index]
                            - theirs[:, dofs.ross_index]).max() / np.abs(theirs).max())  # fmt: skip
    # ROSS interpolates its k_eq, c_eq table with a smoothing spline (scipy's
    # UnivariateSpline with its default smoothing): even at its own grid points its
    # coefficients are not the table's, which is the whole difference
    smooth = 0.0
    for b in rr.bearing_elements:
        table = np.asarray(b.kxx) + 1j * speeds * np.asarray(b.cxx)
        spline = b.kxx_interpolated(speeds) + 1j * speeds * b.cxx_interpolated(speeds)
        smooth = max(smooth, float(np.abs(spline - table).max() / np.abs(table).max()))
    # ... so that the passive rotor on ROSS's spline coefficients is ROSS's response
    spline_resp = np.empty_like(res.response)
    for k, w in enumerate(speeds):
        Mw, Kw, Cw, Gw = (np.array(a) for a in model.rotor.matrices(w))
        for b in rr.bearing_elements:
            i = [dofs(int(b.n), "x"), dofs(int(b.n), "y")]
            for m, kind in ((Kw, "k"), (Cw, "c")):
                m[np.ix_(i, i)] += [[float(getattr(b, f"{kind}{a}_interpolated")(w))
                                     for a in (r + "x", r + "y")] for r in ("x", "y")]  # fmt: skip
        F = np.zeros(n, dtype=complex)
        F[dofs(27, "x")], F[dofs(27, "y")] = 1e-4 * w**2, -1j * 1e-4 * w**2
        spline_resp[k] = np.linalg.solve(Kw - w**2 * Mw + 1j * w * (Cw + w * Gw), F)
    err_spline = float(np.abs(spline_resp - theirs[:, dofs.ross_index]).max()
                       / np.abs(theirs).max())  # fmt: skip
    print(f"\nunbalance response: balanced state space {err:.1e}, ROSS {err_ross:.1e} (ROSS's "
          f"spline off its own table by {smooth:.1e}; on the spline's coefficients "
          f"{err_spline:.1e}); {ours_time:.3f} s against ROSS's {ross_time:.3f} s")  # fmt: skip
    assert err < 1e-8
    assert smooth > 1e-6 and err_spline < 1e-8


def test_a_transient_with_a_touchdown_contact_through_solve():
    """``duhamel.solve`` on from_ross's System: the controllers' states are in it; a
    touchdown bearing at the disk holds the rotor pushed against it."""
    rr = amb_rotor(1100.0, 400.0)
    model = from_ross(rr, SPEED)
    dx, dy = model.dofs(27, "x"), model.dofs(27, "y")
    alone = from_ross(rr, SPEED).system
    alone.add_load(duhamel.loads.Step(dx, amplitude=200.0))
    free = duhamel.solve(alone, duhamel.Semianalytic(modes=40), t_end=0.05, dt=2e-5)
    model.system.add(duhamel.elements.Contact((dx, dy), clearance=5e-5, stiffness=1e7))
    model.system.add_load(duhamel.loads.Step(dx, amplitude=200.0))
    sol = duhamel.solve(model.system, duhamel.Semianalytic(modes=40), t_end=0.05, dt=2e-5)
    assert sol.stats.coupling == "exact"
    assert free.x[-1, dx] > 1e-3  # the loop alone lets it go: zero net stiffness near 0 Hz
    assert 5e-5 < sol.x[-1, dx] < 2e-4  # the touchdown bearing holds it

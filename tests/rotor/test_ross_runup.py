"""A from_ross run-up of ROSS's compressor (seal and bearing coefficients re-evaluated along
the speed) against ROSS's own run-up, ``run_time_response`` with a speed array (its Newmark
with ``K(speed[i]) + alpha Ksdt`` and ``C(speed[i]) + speed[i] G`` at every step), on a short,
fast stretch: 200 -> 1000 rad/s in 10 ms, so that the seals' coefficients change a lot.

ROSS's Newmark is second order: at 1e-4 s its own error is about 1e-3 of the peak. The check
"agrees to its accuracy": ROSS's difference from our converged run falls at second order as
its step is halved, and ROSS's Richardson extrapolation from two steps lands on our converged
run far inside ROSS's own error; ROSS's scheme, written out here (equal to ROSS to round-off)
and extrapolated from fine steps, lands on our run to 2.5e-6 of the peak. Also used by
benchmarks/ross_runup.py.
"""

from __future__ import annotations

import contextlib
import functools
import io
import time
import warnings

import numpy as np
import pytest

import duhamel
from duhamel.rotor import from_ross

REASON = "ROSS (ross-rotordynamics, the duhamel[ross] extra) is not installed"
NODE, M_E = 25, 1e-4  # the unbalance (kg m) at the compressor's node 25


@functools.cache
def compressor():
    with warnings.catch_warnings(), contextlib.redirect_stdout(io.StringIO()):
        warnings.simplefilter("ignore")  # ROSS's ccp dependency; the file's ROSS version
        ross = pytest.importorskip("ross", reason=REASON)
        return ross.compressor_example()


def force(rr, t, w0, alpha, ramp=0.002):
    """The unbalance's force on ROSS's dofs along ``omega = w0 + alpha t``, faded in over
    `ramp` seconds from zero (ROSS's Newmark starts from zero acceleration)."""
    theta = w0 * t + 0.5 * alpha * t**2
    w = w0 + alpha * t
    fade = np.minimum(t / ramp, 1.0) if ramp > 0 else np.ones_like(t)
    F = np.zeros((t.size, rr.ndof))
    ix = rr.number_dof * NODE
    F[:, ix] = M_E * (w**2 * np.cos(theta) + alpha * np.sin(theta)) * fade
    F[:, ix + 1] = M_E * (w**2 * np.sin(theta) - alpha * np.cos(theta)) * fade
    return F


def ours(rr, w0, w1, t1, t_end, dt, integrator, *, frozen=False):
    """duhamel's run on ROSS's force samples (linear between them), with alpha Ksdt added
    over the ramp as ROSS does; returns (x in System order, seconds, dofs)."""
    alpha = (w1 - w0) / t1
    t = np.arange(round(t_end / dt) + 1) * dt
    model = from_ross(rr, w0 if frozen else duhamel.speed.LinearRunUp(w0, w1, t1))
    for load in model.dofs.loads(force(rr, t, w0, alpha), t):
        model.system.add_load(load)
    if not frozen:
        model.system.add(duhamel.elements.LinearCoupling(K=alpha * model.acceleration_stiffness()))
    start = time.perf_counter()
    x = duhamel.solve(model.system, integrator, t_end=t[-1], dt=dt).x
    return x, time.perf_counter() - start, model.dofs


def theirs(rr, w0, w1, t1, t_end, dt):
    """ROSS's run_time_response with the speed array; (yout on ROSS's dofs, seconds)."""
    alpha = (w1 - w0) / t1
    t = np.arange(round(t_end / dt) + 1) * dt
    speed = np.minimum(w0 + alpha * t, w1)
    start = time.perf_counter()
    with contextlib.redirect_stdout(io.StringIO()):
        yout = rr.run_time_response(speed, force(rr, t, w0, alpha), t).yout
    return yout, time.perf_counter() - start


W0, W1, T1 = 200.0, 1000.0, 0.01


@functools.cache
def converged():
    """Ours on the 2.5e-5 s grid, Richardson from 2.5e-5 and 1.25e-5 s (the two agree with
    the pair 1.25e-5, 6.25e-6 to 2.4e-6 of the peak); (ref, dofs, diff)."""
    rr = compressor()
    fine = {}
    for dt in (2.5e-5, 1.25e-5):
        fine[dt], _, dofs = ours(rr, W0, W1, T1, T1, dt, duhamel.Semianalytic())
    ref = (4.0 * fine[1.25e-5][::2] - fine[2.5e-5]) / 3.0
    trans = [i for i, label in enumerate(dofs.labels) if label[0] in "xy"]
    scale = np.abs(ref[:, trans]).max()

    def diff(a, b):
        return float(np.abs(a[:, trans] - b[:, trans]).max() / scale)

    return ref, dofs, diff


def rosss_newmark(rr, dofs, dt):
    """ROSS's run-up written out: average-acceleration Newmark from rest on
    ``M x'' + (C(w) + w G) x' + (K(w) + alpha Ksdt) x = F`` with ROSS's own ``K(w)``,
    ``C(w)`` (lateral block) at the end of every step."""
    alpha = (W1 - W0) / T1
    t = np.arange(round(T1 / dt) + 1) * dt
    keep = np.ix_(dofs.ross_index, dofs.ross_index)
    M, G, Ksdt = rr.M()[keep], rr.G()[keep], rr.Ksdt()[keep]
    F = force(rr, t, W0, alpha)[:, dofs.ross_index]
    x, v, a = (np.zeros(M.shape[0]) for _ in range(3))
    out = [x]
    for i in range(1, t.size):
        w = W0 + alpha * t[i]
        K, C = rr.K(w)[keep] + alpha * Ksdt, rr.C(w)[keep] + w * G
        x1, v1 = x + dt * v + 0.25 * dt**2 * a, v + 0.5 * dt * a
        a = np.linalg.solve(M + 0.5 * dt * C + 0.25 * dt**2 * K, F[i] - K @ x1 - C @ v1)
        x, v = x1 + 0.25 * dt**2 * a, v1 + 0.5 * dt * a
        out.append(x)
    return np.array(out)


@pytest.mark.filterwarnings("ignore:File was created with ROSS")
def test_rosss_run_up_converges_onto_ours():
    """ROSS's run-up is Newmark on the ODE with its coefficients at every step (its run
    written out here equals it to round-off); that scheme, extrapolated from fine steps,
    lands on our run: the two solve the same equation."""
    rr = compressor()
    ref, dofs, diff = converged()
    written = rosss_newmark(rr, dofs, 1e-4)
    same = diff(written, dofs.from_ross(theirs(rr, W0, W1, T1, T1, 1e-4)[0]))
    steps = {dt: rosss_newmark(rr, dofs, dt) for dt in (2.5e-5, 1.25e-5)}
    extrapolated = (4.0 * steps[1.25e-5][::2] - steps[2.5e-5]) / 3.0
    gap = diff(extrapolated, ref)
    print(f"\nROSS's Newmark written out vs ROSS: {same:.1e}; extrapolated from 2.5e-5 and "
          f"1.25e-5 s vs ours: {gap:.1e}")  # fmt: skip
    assert same < 1e-12
    assert gap < 1e-5


@pytest.mark.filterwarnings("ignore:File was created with ROSS")
def test_run_up_agrees_with_ross_run_time_response_to_its_accuracy():
    rr = compressor()
    ref, dofs, diff = converged()

    ross = {dt: dofs.from_ross(theirs(rr, W0, W1, T1, T1, dt)[0]) for dt in (1e-4, 5e-5)}
    err = {dt: diff(ross[dt], ref[:: round(dt / 2.5e-5)]) for dt in ross}
    richardson = (4.0 * ross[5e-5][::2] - ross[1e-4]) / 3.0
    agree = diff(richardson, ref[::4])
    ours_1e4, _, _ = ours(rr, W0, W1, T1, T1, 1e-4, duhamel.Semianalytic())
    frozen, _, _ = ours(rr, W0, W1, T1, T1, 1e-4, duhamel.Semianalytic(), frozen=True)
    stale = diff(frozen, ref[::4])
    print(f"\nROSS run-up vs ours (converged): {err[1e-4]:.2e} at 1e-4 s, {err[5e-5]:.2e} at "
          f"5e-5 s (order {np.log2(err[1e-4] / err[5e-5]):.2f}); ROSS extrapolated vs ours "
          f"{agree:.1e}; ours at 1e-4 s {diff(ours_1e4, ref[::4]):.2e}; coefficients frozen "
          f"at 200 rad/s {stale:.2f}")  # fmt: skip
    assert err[1e-4] / err[5e-5] > 3.5  # ROSS converges to our run at second order
    assert agree < 0.1 * err[1e-4]  # ... to far inside its own error at 1e-4 s
    assert diff(ours_1e4, ref[::4]) < 5e-3  # ours at ROSS's step: the same order of error
    assert stale > 0.05  # the coefficients must follow the speed


@pytest.mark.filterwarnings("ignore:File was created with ROSS")
def test_run_up_example():
    """examples/ross_runup.py runs: ROSS's run within its error of ours, frozen far off."""
    import importlib.util
    from pathlib import Path

    compressor()
    path = Path(__file__).resolve().parents[2] / "examples" / "ross_runup.py"
    spec = importlib.util.spec_from_file_location("ross_runup_example", path)
    assert spec is not None and spec.loader is not None
    ex = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ex)
    r = ex.run(dt=1e-4)
    peak = np.abs(r["duhamel"]).max()
    assert np.abs(r["ross"] - r["duhamel"]).max() < 5e-3 * peak
    assert np.abs(r["frozen"] - r["duhamel"]).max() > 0.05 * peak

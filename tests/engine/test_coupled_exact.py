"""Coupled linear systems integrated exactly in their first-order (complex) modes.

``duhamel.Semianalytic(coupling="auto" | "exact")`` integrates a linear system whose modal
couplings are constant (non-classical damping, constant ``LinearCoupling`` elements:
gyroscopic ``speed * G``, cross-coupled bearings) exactly, like an uncoupled one. The
references share nothing with the code under test: the matrix exponential of the full
first-order *physical* system (``scipy.linalg.expm``, augmented with the load's own linear
dynamics: a constant / polynomial / harmonic forcing state), the frequency-domain steady state
of a rotor, and the pseudo-force route of the paper. Measured numbers are printed
(``pytest -s tests/engine/test_coupled_exact.py``).
"""

from __future__ import annotations

import math
import sys
import warnings

import numpy as np
import pytest
import scipy.integrate
import scipy.linalg as sla
import scipy.sparse as sp

import duhamel
from duhamel import elements as E
from duhamel import loads as L
from duhamel._engine.coupled import CONDITION_LIMIT, first_order_modes
from duhamel.rotor import Bearing, Disk, Material, Rotor, Shaft, SuddenForce, Unbalance, rpm


# --------------------------------------------------------------------------------------------
# References
# --------------------------------------------------------------------------------------------
def slopes(dts, errs):
    """Least-squares slope of log(err) vs log(dt), and the pairwise slopes."""
    ld, le = np.log(np.asarray(dts)), np.log(np.asarray(errs))
    return float(np.polyfit(ld, le, 1)[0]), np.diff(le) / np.diff(ld)


def assert_order(label, dts, errs, order, tol):
    fit, pair = slopes(dts, errs)
    shown = np.array2string(np.asarray(errs), formatter={"float_kind": lambda v: f"{v:.3e}"})
    print(f"\n{label}: errors {shown}")
    print(f"{label}: fitted slope {fit:.4f}, pairwise {np.array2string(pair, precision=4)}")
    assert abs(fit - order) <= tol, (label, fit, pair)
    assert np.all(np.abs(pair - order) <= tol), (label, pair)


def first_order(M, C, K):
    """``z' = A z`` for ``z = (x, v)`` of ``M x'' + C x' + K x = 0``."""
    n = M.shape[0]
    return np.block(
        [[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, K), -np.linalg.solve(M, C)]]
    )


def forced(M, C, K, z0, times, P, G, u0):
    """Exact ``(x, v, a)`` at `times` of ``M x'' + C x' + K x = P u(t)``, ``u' = G u``,
    ``u(0) = u0``, from ``z0 = (x0, v0)``: the matrix exponential of the system augmented
    with the forcing's own dynamics (constants, polynomials, harmonics)."""
    n, r = M.shape[0], P.shape[1]
    aug = np.zeros((2 * n + r, 2 * n + r))
    aug[: 2 * n, : 2 * n] = first_order(M, C, K)
    aug[n : 2 * n, 2 * n :] = np.linalg.solve(M, P)
    aug[2 * n :, 2 * n :] = G
    w0 = np.concatenate([z0, u0])
    w = np.array([sla.expm(aug * t) @ w0 for t in np.atleast_1d(times)])
    x, v, u = w[:, :n], w[:, n : 2 * n], w[:, 2 * n :]
    a = np.linalg.solve(M, P @ u.T - C @ v.T - K @ x.T).T
    return x, v, a


# (1, s, s^2): s' = 1, (s^2)' = 2 s
POLY_G = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 2.0, 0.0]])
POLY_U0 = np.array([1.0, 0.0, 0.0])


def piecewise(M, C, K, x0, v0, times, pieces):
    """Exact ``(x, v, a)`` at `times` for a load that is a quadratic polynomial on each piece:
    ``pieces = [(t_start, P)]`` (the first at 0), ``f(t) = P[:, 0] + P[:, 1] s + P[:, 2] s^2``
    with ``s = t - t_start`` on ``[t_start, next t_start)`` (right-continuous)."""
    starts = np.array([p[0] for p in pieces])
    assert starts[0] == 0.0 and np.all(np.diff(starts) > 0)
    z = [np.concatenate([x0, v0])]
    for (t_a, P), t_b in zip(pieces[:-1], starts[1:], strict=True):
        x, v, _ = forced(M, C, K, z[-1], t_b - t_a, P, POLY_G, POLY_U0)
        z.append(np.concatenate([x[0], v[0]]))
    out = []
    for t in np.atleast_1d(times):
        i = int(np.searchsorted(starts, t, side="right")) - 1
        out.append(forced(M, C, K, z[i], t - starts[i], pieces[i][1], POLY_G, POLY_U0))
    return tuple(np.concatenate([o[j] for o in out]) for j in range(3))


def step_pieces(n, steps):
    """Heaviside loads ``[(pattern, t0)]`` as constant pieces."""
    onsets = sorted({0.0, *(float(t0) for _, t0 in steps)})
    pieces = []
    for t in onsets:
        P = np.zeros((n, 3))
        P[:, 0] = sum((p for p, t0 in steps if t0 <= t), np.zeros(n))
        pieces.append((t, P))
    return pieces


def unit(n, dof, value):
    out = np.zeros(n)
    out[dof] = value
    return out


def rel(a, b):
    """Largest difference relative to the largest entry of the reference `b`."""
    return float(np.abs(np.asarray(a) - np.asarray(b)).max() / np.abs(b).max())


# --------------------------------------------------------------------------------------------
# The 5-dof models of tests/elements/test_elements.py (copied: no imports between test files)
# --------------------------------------------------------------------------------------------
N = 5
M5 = np.diag([1.0, 2.0, 1.5, 1.0, 0.8])
K5 = 100.0 * (2.0 * np.eye(N) - np.eye(N, k=1) - np.eye(N, k=-1))
K5[0, 0] += 50.0
C5 = np.zeros((N, N))  # symmetric, not diagonalised by the undamped modes
C5[0, 0] = 2.0
C5[2, 2] = 0.5
C5[np.ix_([1, 3], [1, 3])] += 0.4 * np.array([[1.0, -1.0], [-1.0, 1.0]])
KX5 = np.zeros((N, N))  # cross-coupled (circulatory) stiffness, k12 = -k21
KX5[1, 2], KX5[2, 1] = 20.0, -20.0
F5 = np.array([-3.0, 0.0, 0.0, 0.0, 10.0])
X0_5 = np.array([0.01, 0.0, 0.02, 0.0, -0.01])
V0_5 = np.array([0.0, 0.1, 0.0, -0.2, 0.0])
RAYLEIGH = (0.3, 2e-3)
VARIANTS = [
    "undamped+LinearCoupling(K,C)",
    "rayleigh+LinearCoupling(sparse K,C)",
    "System(C=nonclassical)",
    "System(C=nonclassical)+LinearCoupling(K)",
]


def build_coupled(variant, loads=None):
    """(system, total C, total K); `loads` default: steps F5 at t = 0."""
    if variant == "undamped+LinearCoupling(K,C)":
        s = duhamel.System(M5, K5).add(E.LinearCoupling(K=KX5, C=C5))
        c_tot, k_tot = C5, K5 + KX5
    elif variant == "rayleigh+LinearCoupling(sparse K,C)":
        s = duhamel.System(M5, K5, rayleigh=RAYLEIGH)
        s.add(E.LinearCoupling(K=sp.csr_matrix(KX5), C=C5))
        c_tot, k_tot = RAYLEIGH[0] * M5 + RAYLEIGH[1] * K5 + C5, K5 + KX5
    elif variant == "System(C=nonclassical)":
        s = duhamel.System(M5, K5, C=C5)
        c_tot, k_tot = C5, K5
    elif variant == "System(C=nonclassical)+LinearCoupling(K)":
        s = duhamel.System(M5, K5, C=C5).add(E.LinearCoupling(K=KX5))
        c_tot, k_tot = C5, K5 + KX5
    else:  # pragma: no cover
        raise AssertionError(variant)
    if loads is None:
        loads = [L.Step(int(i), amplitude=float(F5[i])) for i in np.flatnonzero(F5)]
    for load in loads:
        s.add_load(load)
    return s, c_tot, k_tot


def shortest_period(c_tot, k_tot):
    lam = np.linalg.eigvals(first_order(M5, c_tot, k_tot))
    return 2 * math.pi / float(np.abs(lam.imag).max())


STEPS_5 = [(unit(N, i, F5[i]), 0.0) for i in np.flatnonzero(F5)]


# --------------------------------------------------------------------------------------------
# 1. Exact for step loads, whatever the step (several times the shortest period included)
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("variant", VARIANTS)
def test_step_loads_exact_vs_expm_at_any_dt(variant):
    system, c_tot, k_tot = build_coupled(variant)
    t_min = shortest_period(c_tot, k_tot)
    big = 3.3 * t_min
    dts = [big / 16, big / 4, big]
    runs = []
    for dt in dts:
        sol = duhamel.solve(system, duhamel.Semianalytic(), t_end=4 * big, dt=dt, x0=X0_5, v0=V0_5)
        assert sol.stats.coupling == "exact"
        assert sol.t.size == round(4 * big / dt) + 1
        x, v, a = piecewise(M5, c_tot, k_tot, X0_5, V0_5, sol.t, step_pieces(N, STEPS_5))
        ex, ev, ea = rel(sol.x, x), rel(sol.v, v), rel(sol.a, a)
        print(
            f"\n[{variant}] dt = {dt / t_min:.3f} T_min ({sol.t.size - 1} steps): "
            f"error x {ex:.2e}, v {ev:.2e}, a {ea:.2e}; "
            f"eigenvector condition {sol.stats.eigenvector_condition:.3g}"
        )
        assert max(ex, ev, ea) <= 1e-12
        runs.append(sol)
    # the same answer at the common instants, whatever the step
    coarse = runs[-1]
    for sol, dt in zip(runs[:-1], dts[:-1], strict=True):
        every = round(big / dt)
        assert np.allclose(sol.t[::every], coarse.t, rtol=0, atol=1e-12)
        d = max(rel(sol.x[::every], coarse.x), rel(sol.v[::every], coarse.v))
        print(f"[{variant}] dt = {dt / t_min:.3f} T_min vs {big / t_min:.1f} T_min: {d:.2e}")
        assert d <= 1e-12


def test_exact_and_auto_agree_and_report_condition():
    system, _, _ = build_coupled("System(C=nonclassical)+LinearCoupling(K)")
    auto = duhamel.solve(system, duhamel.Semianalytic(), t_end=1.0, dt=0.1, x0=X0_5, v0=V0_5)
    exact = duhamel.solve(
        system, duhamel.Semianalytic(coupling="exact"), t_end=1.0, dt=0.1, x0=X0_5, v0=V0_5
    )
    assert auto.stats.coupling == exact.stats.coupling == "exact"
    cond = exact.stats.eigenvector_condition
    assert cond is not None and 1.0 <= cond <= CONDITION_LIMIT
    assert np.array_equal(auto.x, exact.x)


# --------------------------------------------------------------------------------------------
# 2. A step whose jump falls inside a time step (two of them in one step included)
# --------------------------------------------------------------------------------------------
def test_step_jump_inside_a_step_is_exact():
    t1, t2 = 0.2371, 1.0703
    loads = [
        L.Step(4, amplitude=10.0, t0=t1),
        L.Step(0, amplitude=-3.0, t0=t2),
        L.Step(2, amplitude=1.5),
    ]
    system, c_tot, k_tot = build_coupled("System(C=nonclassical)+LinearCoupling(K)", loads)
    steps = [(unit(N, 4, 10.0), t1), (unit(N, 0, -3.0), t2), (unit(N, 2, 1.5), 0.0)]
    for dt in (0.1, 0.7, 1.2):  # 1.2: both jumps inside the first step
        assert all(abs(t / dt - round(t / dt)) > 0.05 for t in (t1, t2))
        sol = duhamel.solve(system, duhamel.Semianalytic(), t_end=4.8, dt=dt, x0=X0_5, v0=V0_5)
        assert sol.stats.coupling == "exact"
        x, v, a = piecewise(M5, c_tot, k_tot, X0_5, V0_5, sol.t, step_pieces(N, steps))
        ex, ev, ea = rel(sol.x, x), rel(sol.v, v), rel(sol.a, a)
        print(
            f"\nsteps at t = {t1}, {t2} inside steps of {dt}: "
            f"error x {ex:.2e}, v {ev:.2e}, a {ea:.2e}"
        )
        assert max(ex, ev, ea) <= 1e-12


# --------------------------------------------------------------------------------------------
# 3. Harmonic load: fourth order (the per-step parabola), against the augmented expm
# --------------------------------------------------------------------------------------------
def test_harmonic_load_fourth_order():
    amp, w, phase = 10.0, 15.0, 0.4
    loads = [L.Harmonic(4, amplitude=amp, omega=w, phase=phase)]
    system, c_tot, k_tot = build_coupled("undamped+LinearCoupling(K,C)", loads)
    t_end, dt0 = 2.0, 0.04
    times = np.arange(round(t_end / dt0) + 1) * dt0
    # forcing oscillator u = (sin(w t + phase), cos(w t + phase)): u' = [[0, w], [-w, 0]] u
    P = np.zeros((N, 2))
    P[4, 0] = amp
    G = np.array([[0.0, w], [-w, 0.0]])
    x, _, _ = forced(
        M5,
        c_tot,
        k_tot,
        np.concatenate([X0_5, V0_5]),
        times,
        P,
        G,
        [math.sin(phase), math.cos(phase)],
    )
    dts = [dt0 / 2**k for k in range(4)]
    errs = []
    for k, dt in enumerate(dts):
        sol = duhamel.solve(system, duhamel.Semianalytic(), t_end=t_end, dt=dt, x0=X0_5, v0=V0_5)
        assert sol.stats.coupling == "exact"
        errs.append(rel(sol.x[:: 2**k], x))
    assert_order("harmonic load, coupled exact", dts, errs, 4.0, 0.15)


# --------------------------------------------------------------------------------------------
# 4. A gyroscopic rotor with cross-coupled bearings
# --------------------------------------------------------------------------------------------
MAT = Material(E=211e9, rho=7810.0, nu=0.3)
SPEED = rpm(6000)


def make_rotor(**bearing):
    """Two disks, anisotropic bearings with cross-coupled stiffness (kxy = -kyx / 1.5) and
    non-symmetric damping, Rayleigh damping; every mode stable at 6000 rpm
    (tests/rotor/test_rotor.py)."""
    shafts = [Shaft(0.2, 0.04, material=MAT) for _ in range(5)]
    disks = [
        Disk.from_geometry(2, 0.05, 0.25, 0.04, MAT),
        Disk.from_geometry(4, 0.04, 0.2, 0.04, MAT),
    ]
    b = {"kxx": 2e7, "kyy": 3e7, "kxy": 1e6, "kyx": -1.5e6}
    b |= {"cxx": 1500.0, "cyy": 2000.0, "cxy": 150.0, "cyx": -50.0}
    b |= bearing
    return Rotor(shafts, disks, [Bearing(0, **b), Bearing(5, **b)], rayleigh=(40.0, 2e-6))


def plain_rotor():
    """The same rotor with symmetric, undamped bearings: Rayleigh damping only, uncoupled."""
    zero = dict.fromkeys(("kxy", "kyx", "cxx", "cyy", "cxy", "cyx"), 0.0)
    return make_rotor(**zero)


#: Round-off of an expm comparison on this stiff rotor (|lambda| up to 6.5e4 rad/s,
#: cond(M^-1 K) = 3.8e6): the uncoupled engine, exact by construction, measures up to 1.2e-11.
ROTOR_ROUND_OFF = 2e-11


def test_rotor_unbalance_steady_state_matches_frequency_domain():
    """200 revolutions (slowest transient decay e^-39.6 = 6e-18): the response equals
    Re(X e^{i W t}), X = [K - W^2 M + i W (C + W G)]^-1 F, up to the fourth-order error of the
    per-step parabola of the harmonic unbalance force."""
    rotor = make_rotor()
    m_e, phase = 1e-3, 0.3
    M, K, C, G = rotor.matrices(SPEED)
    F = np.zeros(rotor.n_dof, dtype=complex)
    F[rotor.dof(2, "x")] = m_e * SPEED**2 * np.exp(1j * phase)  # m_e W^2 cos(W t + phase)
    F[rotor.dof(2, "y")] = -1j * m_e * SPEED**2 * np.exp(1j * phase)  # ... sin(W t + phase)
    X = np.linalg.solve(K - SPEED**2 * M + 1j * SPEED * (C + SPEED * G), F)
    decay = float(np.min(-np.linalg.eigvals(first_order(M, C + SPEED * G, K)).real))
    period = 2 * math.pi / SPEED
    t_end = 200 * period
    print(
        f"\nrotor: transient left at t_end: "
        f"exp(-{decay:.2f} t_end) = {math.exp(-decay * t_end):.1e}"
    )
    assert math.exp(-decay * t_end) < 1e-15
    per_rev = [40, 80, 160, 320, 640]
    errs = []
    for n in per_rev:
        system = rotor.system(SPEED, [Unbalance(2, m_e, phase=phase)])
        sol = duhamel.solve(
            system, duhamel.Semianalytic(), t_end=t_end, dt=period / n, save_every=n // 20
        )
        assert sol.stats.coupling == "exact" and sol.t[-1] == pytest.approx(t_end, rel=1e-12)
        last = sol.t >= t_end - period * (1 + 1e-9)
        ref = (X[None, :] * np.exp(1j * SPEED * sol.t[last])[:, None]).real
        errs.append(rel(sol.x[last], ref))
    print(f"rotor eigenvector condition {sol.stats.eigenvector_condition:.3g}")
    assert_order("rotor unbalance steady state", [1 / n for n in per_rev[:4]], errs[:4], 4.0, 0.15)
    print(f"rotor unbalance steady state, {per_rev[-1]} steps/rev: {errs[-1]:.2e}")
    assert errs[-1] <= 1e-10


def test_rotor_free_and_step_response_vs_expm():
    """Initial state plus a sudden force inside a step, steps 10 and 40 times the shortest
    period. The yardstick for "round-off" on this stiff model (|lambda| up to 6.5e4 rad/s,
    cond(M^-1 K) = 3.8e6) is the uncoupled exact engine on the same rotor with symmetric
    bearings at rest."""
    rotor = make_rotor()
    n = rotor.n_dof
    x0 = np.zeros(n)
    x0[rotor.dof(2, "x")], x0[rotor.dof(4, "y")] = 1e-5, -2e-5
    v0 = unit(n, rotor.dof(3, "y"), 1e-3)
    t0 = 0.0123
    f = unit(n, rotor.dof(2, "y"), -5e3)
    errs = {}
    for label, model, speed in (
        ("coupled (gyroscopic, cross-coupled)", rotor, SPEED),
        ("uncoupled yardstick", plain_rotor(), 0.0),
    ):
        Mm, Km, Cm, Gm = model.matrices(speed)
        lam = np.linalg.eigvals(first_order(Mm, Cm + speed * Gm, Km))
        t_min = 2 * math.pi / float(np.abs(lam.imag).max())
        for ratio in (10, 40):
            dt = ratio * t_min
            system = model.system(speed, [SuddenForce(2, fy=-5e3, t0=t0)])
            sol = duhamel.solve(system, duhamel.Semianalytic(), t_end=0.06, dt=dt, x0=x0, v0=v0)
            assert sol.stats.coupling == ("exact" if speed else None)
            x, v, _ = piecewise(Mm, Cm + speed * Gm, Km, x0, v0, sol.t, step_pieces(n, [(f, t0)]))
            errs[label, ratio] = (rel(sol.x, x), rel(sol.v, v))
            print(
                f"\nrotor {label}, dt = {ratio} T_min: error x {errs[label, ratio][0]:.2e}, "
                f"v {errs[label, ratio][1]:.2e}"
            )
    # the same bound holds for the (exact by construction) uncoupled engine on this model
    assert max(max(e) for e in errs.values()) <= ROTOR_ROUND_OFF


# --------------------------------------------------------------------------------------------
# 5. Modal reduction: exact for the reduced (projected) system
# --------------------------------------------------------------------------------------------
def test_modal_reduction_exact_for_the_reduced_system():
    system, c_tot, k_tot = build_coupled("System(C=nonclassical)+LinearCoupling(K)")
    w2, phi = sla.eigh(K5, M5)  # M-normalised
    full = duhamel.solve(system, duhamel.Semianalytic(), t_end=4.0, dt=0.8, x0=X0_5, v0=V0_5)
    for k in (2, 3, 4):
        pk = phi[:, :k]
        Mr, Kr, Cr = np.eye(k), pk.T @ k_tot @ pk, pk.T @ c_tot @ pk
        assert np.allclose(np.diag(pk.T @ K5 @ pk), w2[:k])
        sol = duhamel.solve(
            system, duhamel.Semianalytic(modes=k), t_end=4.0, dt=0.8, x0=X0_5, v0=V0_5
        )
        assert sol.stats.coupling == "exact" and sol.stats.modes == k
        q0, qd0 = pk.T @ M5 @ X0_5, pk.T @ M5 @ V0_5
        steps = [(pk.T @ p, t0) for p, t0 in STEPS_5]
        q, qd, qa = piecewise(Mr, Cr, Kr, q0, qd0, sol.t, step_pieces(k, steps))
        ex, ev, ea = rel(sol.x, q @ pk.T), rel(sol.v, qd @ pk.T), rel(sol.a, qa @ pk.T)
        d_full = rel(sol.x, full.x)
        print(
            f"\nmodes={k}: error vs reduced expm x {ex:.2e}, v {ev:.2e}, a {ea:.2e} "
            f"(differs from the full model by {d_full:.2e})"
        )
        assert max(ex, ev, ea) <= 1e-12
        assert d_full > 1e-4  # the reduction matters: the test discriminates


def test_rotor_modal_reduction_exact_for_the_reduced_system():
    """Reduced system: ``q'' + Phi_k^T (C + W G) Phi_k q' + Phi_k^T K Phi_k q = Phi_k^T f``,
    with the full bearing matrices (symmetric background and skew couplings) projected."""
    dofs = make_rotor()
    x0 = unit(dofs.n_dof, dofs.dof(2, "y"), 1e-5)
    f = unit(dofs.n_dof, dofs.dof(3, "x"), 2e3)  # SuddenForce(3, fx=2e3)
    errs = {}
    for label, model, speed in (
        ("coupled", make_rotor(), SPEED),
        ("uncoupled", plain_rotor(), 0.0),
    ):
        system = model.system(speed, [SuddenForce(3, fx=2e3, t0=0.0)])
        M, K, C, G = model.matrices(speed)
        w2, phi = sla.eigh(system.K, system.M)  # the symmetric background's modes
        for k in (6, 10, 16):
            pk = phi[:, :k]
            Kr, Cr = pk.T @ K @ pk, pk.T @ (C + speed * G) @ pk
            dt = 2e-3  # 0.3 to 1.5 periods of the highest retained mode
            sol = duhamel.solve(system, duhamel.Semianalytic(modes=k), t_end=0.04, dt=dt, x0=x0)
            assert sol.stats.coupling == ("exact" if speed else None) and sol.stats.modes == k
            pieces = step_pieces(k, [(pk.T @ f, 0.0)])
            q, qd, _ = piecewise(np.eye(k), Cr, Kr, pk.T @ M @ x0, np.zeros(k), sol.t, pieces)
            errs[label, k] = max(rel(sol.x, q @ pk.T), rel(sol.v, qd @ pk.T))
            print(
                f"\nrotor {label}, modes={k} (highest period / dt "
                f"{2 * math.pi / math.sqrt(w2[k - 1]) / dt:.2f}): error vs reduced expm "
                f"{errs[label, k]:.2e}"
            )
    assert max(errs.values()) <= ROTOR_ROUND_OFF


# --------------------------------------------------------------------------------------------
# 6. A rigid-body mode (free-free, K singular) with couplings
# --------------------------------------------------------------------------------------------
def free_free():
    m = np.diag([1.0, 2.0, 1.5, 1.0])
    k = 100.0 * np.array(
        [[1.0, -1.0, 0, 0], [-1.0, 2.0, -1.0, 0], [0, -1.0, 2.0, -1.0], [0, 0, -1.0, 1.0]]
    )
    return m, k


def test_rigid_body_mode_with_coupling_is_exact():
    """A damper to ground on dof 0 (non-classical) and a gyroscopic-like skew damping between
    dofs 1 and 2: the total stiffness stays singular (eigenvalue 0: the position drifts under
    a constant force), the rigid velocity is damped, so the first-order matrix is
    diagonalisable; the rigid mode's state scaling is the floor 1e-6 omega_max."""
    m, k = free_free()
    cc = np.zeros((4, 4))
    cc[0, 0] = 0.5
    cc[1, 2], cc[2, 1] = 3.0, -3.0
    system = duhamel.System(m, k).add(E.LinearCoupling(C=cc))
    system.add_load(L.Step(3, amplitude=2.0)).add_load(L.Step(1, amplitude=-1.0, t0=0.77))
    basis = system.modal()
    assert basis.omega2[0] == 0.0
    x0, v0 = np.array([0.0, 0.01, 0.0, -0.02]), np.array([0.3, 0.0, 0.0, 0.1])
    steps = [(unit(4, 3, 2.0), 0.0), (unit(4, 1, -1.0), 0.77)]
    lam = np.linalg.eigvals(first_order(m, cc, k))
    t_min = 2 * math.pi / float(np.abs(lam.imag).max())
    print(f"\nfree-free + coupling: smallest |lambda| {np.abs(lam).min():.2e}, T_min {t_min:.3f}")
    for dt in (0.05, 0.5):
        sol = duhamel.solve(system, duhamel.Semianalytic(), t_end=10.0, dt=dt, x0=x0, v0=v0)
        assert sol.stats.coupling == "exact"
        x, v, a = piecewise(m, cc, k, x0, v0, sol.t, step_pieces(4, steps))
        ex, ev, ea = rel(sol.x, x), rel(sol.v, v), rel(sol.a, a)
        print(
            f"free-free + coupling, dt = {dt} ({dt / t_min:.2f} T_min): error x {ex:.2e}, "
            f"v {ev:.2e}, a {ea:.2e}; condition {sol.stats.eigenvector_condition:.3g}"
        )
        assert max(ex, ev, ea) <= 1e-12
    # drift: the mean position grows (a constant net force on a damped free body)
    assert abs(sol.x[-1].mean()) > 10 * abs(sol.x[0].mean())


# --------------------------------------------------------------------------------------------
# 7. Velocities, accelerations, the modal history, a subset of dofs
# --------------------------------------------------------------------------------------------
def test_velocity_acceleration_modal_history_and_dofs():
    loads = [
        L.Step(4, amplitude=10.0),
        L.Step(1, amplitude=-2.0, t0=0.55),
        L.Step(0, amplitude=-3.0),
    ]
    system, c_tot, k_tot = build_coupled("System(C=nonclassical)+LinearCoupling(K)", loads)
    steps = [(unit(N, 4, 10.0), 0.0), (unit(N, 1, -2.0), 0.55), (unit(N, 0, -3.0), 0.0)]
    kw = {"t_end": 3.0, "dt": 0.2, "x0": X0_5, "v0": V0_5}
    sol = duhamel.solve(system, duhamel.Semianalytic(), **kw)
    assert sol.stats.coupling == "exact"
    x, v, a = piecewise(M5, c_tot, k_tot, X0_5, V0_5, sol.t, step_pieces(N, steps))
    ex, ev, ea = rel(sol.x, x), rel(sol.v, v), rel(sol.a, a)
    print(f"\nphysical outputs: error x {ex:.2e}, v {ev:.2e}, a (equation of motion) {ea:.2e}")
    assert max(ex, ev, ea) <= 1e-12

    basis = system.modal()
    phi = basis.phi
    mod = sol.modal
    assert mod.q.shape == mod.v.shape == mod.a.shape == (sol.t.size, N)
    # x = Phi q, v = Phi q', a = Phi q''; and q'' = Phi^T M x'' from the reference
    dq = (rel(mod.q @ phi.T, sol.x), rel(mod.v @ phi.T, sol.v), rel(mod.a @ phi.T, sol.a))
    da = rel(mod.a, a @ M5 @ phi)
    # pseudo-force: -(Phi^T K_c Phi q + (Phi^T C Phi - diag c) q'), K_c the stiffness coupling
    kc = phi.T @ (k_tot - K5) @ phi
    cc = phi.T @ c_tot @ phi - np.diag(basis.c)
    pseudo = -(mod.q @ kc.T + mod.v @ cc.T)
    dp = rel(mod.pseudo_force, pseudo)
    # the modal loads: p = Phi^T f(t) (right-continuous)
    f = np.array([sum((p for p, t0 in steps if t0 <= t), np.zeros(N)) for t in sol.t])
    dl = rel(mod.p, f @ phi)
    print(
        f"modal history: x/v/a = Phi q/q'/q'' {max(dq):.2e}; q'' vs Phi^T M a_ref {da:.2e}; "
        f"pseudo-force {dp:.2e}; p {dl:.2e}"
    )
    assert max(dq) <= 1e-13 and da <= 1e-12 and dp <= 1e-13 and dl <= 1e-15
    assert rel(mod.pseudo_force, np.zeros_like(pseudo) + 1.0) > 1e-6  # not trivially zero

    wanted = [4, 1]
    sub = duhamel.solve(system, duhamel.Semianalytic(), dofs=wanted, **kw)
    assert sub.dofs.tolist() == wanted and sub.x.shape == (sol.t.size, 2)
    ds = max(
        rel(sub.x, sol.x[:, wanted]), rel(sub.v, sol.v[:, wanted]), rel(sub.a, sol.a[:, wanted])
    )
    print(f"dofs={wanted} vs the full run's columns: {ds:.2e}")
    assert ds <= 1e-14
    assert np.array_equal(sub.modal.q, sol.modal.q)


# --------------------------------------------------------------------------------------------
# 8. A Callable load: exact for a quadratic polynomial in time
# --------------------------------------------------------------------------------------------
def test_callable_quadratic_load_is_exact():
    P = np.zeros((N, 3))  # f(t) = P[:, 0] + P[:, 1] t + P[:, 2] t^2
    P[4] = [2.0, -3.0, 1.5]
    P[1] = [0.0, 0.5, 0.0]
    P[0] = [-1.0, 0.0, -0.25]
    calls = []

    def fn(t):
        calls.append(t)
        return P @ np.array([1.0, t, t * t])

    system, c_tot, k_tot = build_coupled("rayleigh+LinearCoupling(sparse K,C)", [L.Callable(fn)])
    t_min = shortest_period(c_tot, k_tot)
    for dt in (0.1, 0.7):
        calls.clear()
        sol = duhamel.solve(system, duhamel.Semianalytic(), t_end=4.2, dt=dt, x0=X0_5, v0=V0_5)
        assert sol.stats.coupling == "exact"
        x, v, a = forced(M5, c_tot, k_tot, np.concatenate([X0_5, V0_5]), sol.t, P, POLY_G, POLY_U0)
        ex, ev, ea = rel(sol.x, x), rel(sol.v, v), rel(sol.a, a)
        print(
            f"\nCallable quadratic load, dt = {dt} ({dt / t_min:.2f} T_min, {len(calls)} calls): "
            f"error x {ex:.2e}, v {ev:.2e}, a {ea:.2e}"
        )
        assert max(ex, ev, ea) <= 1e-12


def test_tabulated_and_base_acceleration_on_the_grid_are_exact():
    """Piecewise-linear records whose samples fall on the step grid: exact."""
    dt = 0.25  # a binary fraction: the knots are exactly on the grid n * dt
    ts, vals = np.array([0.0, 0.5, 1.5, 2.0]), np.array([0.0, 40.0, -20.0, 5.0])
    r = np.array([1.0, 1.0, 0.0, 1.0, 1.0])
    ag_t, ag = np.array([0.0, 0.75, 1.75]), np.array([0.0, 3.0, -1.0])
    loads = [L.Tabulated(4, t=ts, values=vals, hold=True), L.BaseAcceleration(r, t=ag_t, values=ag)]
    system, c_tot, k_tot = build_coupled("undamped+LinearCoupling(K,C)", loads)
    sol = duhamel.solve(system, duhamel.Semianalytic(), t_end=3.0, dt=dt, x0=X0_5, v0=V0_5)
    assert sol.stats.coupling == "exact"
    mr = -M5 @ r
    pieces = []
    for t in sorted({*ts.tolist(), *ag_t.tolist()}):
        P = np.zeros((N, 3))
        i = int(np.searchsorted(ts, t, side="right")) - 1
        if i < ts.size - 1:
            slope = (vals[i + 1] - vals[i]) / (ts[i + 1] - ts[i])
            P[4, :2] = vals[i] + slope * (t - ts[i]), slope
        else:
            P[4, 0] = vals[-1]  # hold
        j = int(np.searchsorted(ag_t, t, side="right")) - 1
        if j < ag_t.size - 1:
            slope = (ag[j + 1] - ag[j]) / (ag_t[j + 1] - ag_t[j])
            P[:, 0] += mr * (ag[j] + slope * (t - ag_t[j]))
            P[:, 1] += mr * slope  # the record ends at its last sample: zero after
        pieces.append((t, P))
    x, v, a = piecewise(M5, c_tot, k_tot, X0_5, V0_5, sol.t, pieces)
    ex, ev, ea = rel(sol.x, x), rel(sol.v, v), rel(sol.a, a)
    print(f"\nTabulated + BaseAcceleration on the grid: error x {ex:.2e}, v {ev:.2e}, a {ea:.2e}")
    assert max(ex, ev, ea) <= 1e-12


# --------------------------------------------------------------------------------------------
# 9. When the exact route does not apply: fallbacks and errors
# --------------------------------------------------------------------------------------------
def _run(system, coupling="auto", **kw):
    kw = {"t_end": 0.5, "dt": 0.05, "x0": X0_5} | kw
    return duhamel.solve(system, duhamel.Semianalytic(coupling=coupling), **kw)


def test_nonlinear_element_on_the_exact_background():
    """Elements on a coupled system: the couplings stay exact (first-order modes), only the
    element forces are pseudo-forces (scheme b, trapezoid); other schemes fall back."""
    system, _, _ = build_coupled("System(C=nonclassical)+LinearCoupling(K)")
    system.add(E.Cubic(0, k3=1e4))
    sol = _run(system)
    assert sol.stats.coupling == "exact" and sol.stats.eigenvector_condition is not None
    assert sol.stats.newton_iterations > 0
    for opts in ({"scheme": "a"}, {"quadrature": "parabolic"}):
        other = duhamel.solve(system, duhamel.Semianalytic(**opts), t_end=0.5, dt=0.05, x0=X0_5)
        assert other.stats.coupling == "pseudo-force"
        with pytest.raises(ValueError, match=r"`coupling`.*scheme='b'"):
            duhamel.solve(
                system,
                duhamel.Semianalytic(coupling="exact", **opts),
                t_end=0.5,
                dt=0.05,
                x0=X0_5,
            )
    # Without couplings there is nothing to integrate exactly: no coupling route, no error.
    only_cubic = duhamel.System(M5, K5, rayleigh=RAYLEIGH).add(E.Cubic(0, k3=1e4))
    for coupling in ("auto", "exact", "pseudo-force"):
        assert _run(only_cubic, coupling).stats.coupling is None


def test_mass_law_falls_back_to_pseudo_force():
    system, _, _ = build_coupled("undamped+LinearCoupling(K,C)")
    system.set_mass_law(duhamel.mass.Exponential(rate=-0.1))
    assert _run(system).stats.coupling == "pseudo-force"
    with pytest.raises(ValueError, match=r"`coupling`.*mass law"):
        _run(system, "exact")


def test_time_varying_scale_falls_back_constant_scale_is_exact():
    G = np.zeros((N, N))
    G[1, 3], G[3, 1] = 0.05, -0.05
    run_up = duhamel.speed.LinearRunUp(omega0=10.0, omega1=300.0, t1=0.4)
    varying = duhamel.System(M5, K5, C=C5).add(E.LinearCoupling(C=G, scale=run_up))
    assert _run(varying).stats.coupling == "pseudo-force"
    with pytest.raises(ValueError, match=r"`coupling`.*speed law"):
        _run(varying, "exact")
    # a constant law (a number, ConstantSpeed, a run-up from omega to omega) is folded in
    ref = _run(duhamel.System(M5, K5, C=C5).add(E.LinearCoupling(C=150.0 * G)), "exact")
    for scale in (
        150.0,
        duhamel.speed.ConstantSpeed(150.0),
        duhamel.speed.LinearRunUp(150.0, 150.0, 1.0),
    ):
        s = duhamel.System(M5, K5, C=C5).add(E.LinearCoupling(C=G, scale=scale))
        sol = _run(s, "exact")
        assert sol.stats.coupling == "exact"
        assert rel(sol.x, ref.x) <= 1e-14, scale


def test_uncoupled_linear_system_reports_no_coupling():
    classical = 0.4 * M5 + 1e-3 * K5
    for system in (
        duhamel.System(M5, K5, rayleigh=RAYLEIGH),
        duhamel.System(M5, K5, C=classical),
        duhamel.System(M5, K5),
    ):
        for coupling in ("auto", "exact", "pseudo-force"):
            sol = _run(system, coupling)
            assert sol.stats.coupling is None and sol.stats.eigenvector_condition is None


def test_defective_system_falls_back_and_exact_raises():
    """A free-free chain with a damper between two of its masses: the coupling leaves the rigid
    mode alone, so its first-order block [[0, sigma], [0, 0]] is a Jordan block (position
    growing like t under a velocity): defective, eigenvector condition ~1e12 or more. The
    fallback (pseudo-force route) is still right: second order."""
    m, k = free_free()
    cc = np.zeros((4, 4))
    cc[np.ix_([0, 2], [0, 2])] = 0.8 * np.array([[1.0, -1.0], [-1.0, 1.0]])  # relative damper
    system = duhamel.System(m, k).add(E.LinearCoupling(C=cc)).add_load(L.Step(3, amplitude=2.0))
    basis = system.modal()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # scipy's ill-conditioned inverse warning
        fo = first_order_modes(
            basis.omega2, basis.c, None, np.asarray(basis.phi.T @ cc @ basis.phi)
        )
    print(
        f"\nfree-free + relative damper: condition {fo.condition:.3g}, "
        f"eigenvalues {np.round(fo.lam, 6)}"
    )
    assert fo.condition > CONDITION_LIMIT
    x0, v0 = np.array([0.0, 0.01, 0.0, -0.02]), np.array([0.3, 0.0, 0.0, 0.1])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(ValueError, match=r"`coupling`.*condition number"):
            _run(system, "exact", x0=x0)
        runs = [_run(system, t_end=5.0, dt=dt, x0=x0, v0=v0) for dt in (0.02, 0.01, 0.005)]
    assert all(r.stats.coupling == "pseudo-force" for r in runs)
    assert all(r.stats.eigenvector_condition is None for r in runs)
    pieces = step_pieces(4, [(unit(4, 3, 2.0), 0.0)])
    x, _, _ = piecewise(m, cc, k, x0, v0, runs[0].t, pieces)
    errs = [rel(r.x[:: 2**i], x) for i, r in enumerate(runs)]
    assert_order(
        "free-free + relative damper, pseudo-force fallback", [0.02, 0.01, 0.005], errs, 2.0, 0.1
    )


def critical_pair(eps):
    """Two equal, critically damped modes (a double Jordan block) coupled by a skew stiffness
    ``eps``: the first-order matrix is defective for eps = 0, nearly so for tiny eps."""
    kx = np.array([[0.0, eps], [-eps, 0.0]])
    system = duhamel.System(np.eye(2), np.eye(2), C=2.0 * np.eye(2)).add(E.LinearCoupling(K=kx))
    return system.add_load(L.Step(0, amplitude=1.0)), (np.eye(2), 2.0 * np.eye(2), np.eye(2) + kx)


def critical_and_gyroscopic(g):
    """Mode 1 critically damped (c = 2 omega_1), mode 2 lightly damped, coupled by a
    gyroscopic (skew) damping ``g``."""
    m, k, c = np.eye(2), np.diag([1.0, 4.0]), np.diag([2.0, 0.2])
    cx = np.array([[0.0, g], [-g, 0.0]])
    system = duhamel.System(m, k, C=c).add(E.LinearCoupling(C=cx))
    return system.add_load(L.Step(0, amplitude=1.0)), (m, c + cx, k)


NEAR_DEFECTIVE = [
    pytest.param(critical_pair, 1e-15, id="critical pair, skew K 1e-15"),
    pytest.param(critical_and_gyroscopic, 1e-6, id="critical + gyroscopic 1e-6"),
    pytest.param(critical_and_gyroscopic, 1e-4, id="critical + gyroscopic 1e-4"),
]
X0_2, V0_2 = np.array([1.0, -0.5]), np.array([0.0, 2.0])


def _near_defective_run(build, value, dt=0.5, **opts):
    """The run and the expm reference at t = 0, 0.5, ..., 8."""
    system, (m, c, k) = build(value)
    sol = duhamel.solve(system, duhamel.Semianalytic(**opts), t_end=8.0, dt=dt, x0=X0_2, v0=V0_2)
    every = round(0.5 / dt)
    pieces = step_pieces(2, [(unit(2, 0, 1.0), 0.0)])
    x, _, _ = piecewise(m, c, k, X0_2, V0_2, sol.t[::every], pieces)
    return sol, sol.x[::every], x


def test_defective_critical_pair_trips_the_limit():
    """A tiny skew coupling of two critically damped modes: a (nearly) defective block. In
    floating point its eigenvectors come out about sqrt(eps_mach) apart (condition ~1e8 from
    skew 1e-15 on, ~1e16 for skew 0): all above the limit, so auto falls back to the
    pseudo-force route and "exact" refuses, naming the condition number."""
    for eps in (0.0, 1e-16, 1e-15, 1e-10):
        system, _ = critical_pair(eps)
        basis = system.modal()
        kc = basis.phi.T @ np.array([[0.0, eps], [-eps, 0.0]]) @ basis.phi
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # no scipy warning leaks to the user
            fo = first_order_modes(basis.omega2, basis.c, kc, None)
            sol = duhamel.solve(system, duhamel.Semianalytic(), t_end=1.0, dt=0.5, x0=X0_2)
        print(
            f"\ncritical pair, skew {eps:g}: condition {fo.condition:.3g} -> {sol.stats.coupling}"
        )
        assert fo.condition > CONDITION_LIMIT
        assert sol.stats.coupling == "pseudo-force"
        with pytest.raises(ValueError, match=r"`coupling`.*condition number"):
            duhamel.solve(system, duhamel.Semianalytic(coupling="exact"), t_end=1.0, dt=0.5)


@pytest.mark.parametrize(("build", "value"), NEAR_DEFECTIVE)
def test_near_defective_reference_is_right(build, value):
    """The expm reference of the near-defective cases below is right: the pseudo-force route
    (whose coupling is tiny here) agrees with it at a small step."""
    sol, xs, x = _near_defective_run(build, value, dt=0.002, coupling="pseudo-force")
    assert sol.stats.coupling == "pseudo-force"
    err = rel(xs, x)
    print(f"\n[{build.__name__}({value:g})] pseudo-force route, dt = 0.002, vs expm: {err:.2e}")
    assert err <= 1e-9


def test_near_defective_error_law_and_limit(monkeypatch):
    """Near a Jordan block the eigenvalues are only accurate to about kappa * eps, so the
    response's error grows like kappa^2 * eps (kappa: the eigenvector condition number). With
    the limit lifted, the measured errors on a sweep of gyroscopic couplings follow that law
    (slope ~2 in log-log); at CONDITION_LIMIT the law predicts <= 1e-8, and with the limit in
    place every accepted run is that accurate while the others fall back."""
    gs = [1e-1, 3e-2, 1e-2, 3e-3, 1e-3, 3e-4]
    conds, errs = [], []
    monkeypatch.setattr(sys.modules["duhamel._engine.plan"], "CONDITION_LIMIT", np.inf)
    for g in gs:
        sol, xs, x = _near_defective_run(critical_and_gyroscopic, g)
        assert sol.stats.coupling == "exact"
        conds.append(sol.stats.eigenvector_condition)
        errs.append(rel(xs, x))
    monkeypatch.undo()
    conds, errs = np.array(conds), np.array(errs)
    eps = np.finfo(float).eps
    ratio = errs / (conds**2 * eps)
    slope = np.polyfit(np.log(conds[2:]), np.log(errs[2:]), 1)[0]
    print(
        f"\ncritical + gyroscopic g = {gs}: conditions {np.round(conds, 1).tolist()}, errors "
        f"{[f'{e:.1e}' for e in errs]}, error / (kappa^2 eps) {np.round(ratio, 3).tolist()}, "
        f"slope {slope:.2f}"
    )
    assert 1.6 <= slope <= 2.4
    assert ratio.max() <= 0.5
    assert ratio.max() * CONDITION_LIMIT**2 * eps <= 1e-8  # the law, at the limit
    for g, cond in zip(gs, conds, strict=True):
        sol, xs, x = _near_defective_run(critical_and_gyroscopic, g)
        expected = "exact" if cond <= CONDITION_LIMIT else "pseudo-force"
        assert sol.stats.coupling == expected
        if expected == "exact":
            assert rel(xs, x) <= 1e-8


# --------------------------------------------------------------------------------------------
# 10. Divergence: a flutter instability (circulatory stiffness) overflows
# --------------------------------------------------------------------------------------------
def flutter():
    """Circulatory (skew) stiffness a = 200 >> |w1^2 - w2^2| / 2 = 10.5 on two light damped
    modes: flutter, Re(lambda) = 7.6 /s, overflow near t = 94."""
    a = 200.0
    kx = np.array([[0.0, a], [-a, 0.0]])
    m, k = np.eye(2), np.diag([100.0, 121.0])
    system = duhamel.System(m, k, zeta=0.01).add(E.LinearCoupling(K=kx))
    basis = system.modal()
    c = np.asarray(basis.phi @ np.diag(basis.c) @ basis.phi.T)  # zeta = 0.01, physical
    return system, (m, c, k + kx)


FLUTTER_RUN = {"t_end": 150.0, "dt": 0.05, "x0": np.array([1e-3, 0.0])}


def _diverge(coupling):
    system, _ = flutter()
    with pytest.raises(duhamel.SolverError) as info:
        duhamel.solve(system, duhamel.Semianalytic(coupling=coupling), **FLUTTER_RUN)
    return info.value


def test_divergence_raises_solver_error_with_partial_history():
    _, (m, c, k) = flutter()
    growth = float(np.linalg.eigvals(first_order(m, c, k)).real.max())
    dt = FLUTTER_RUN["dt"]
    print(f"\nflutter: growth rate {growth:.3f} /s, overflow expected near t = {709 / growth:.1f}")
    err = _diverge("auto")
    part = err.partial
    print(f"flutter: {err}")
    print(f"flutter: partial up to t = {part.t[-1]}, {part.t.size} rows, failed at {err.time}")
    assert err.reason == "nonfinite" and part.stats.coupling == "exact"
    assert 709 / growth - 5.0 < err.time < 745 / growth + 5.0
    # The last instant whose x, v and a are all finite: the accelerations (omega^2 x) reach
    # the end of the double range a few steps before the first-order coordinates do, so the
    # partial history ends where |a| is within one sampling interval's growth of overflow.
    assert part.t[-1] <= err.time - dt + 1e-9
    assert np.all(np.isfinite(part.a))
    edge = np.finfo(float).max * np.exp(-2 * growth * dt)
    assert np.abs(part.a[-1]).max() >= edge
    assert f"the history up to t = {float(part.t[-1])!r} is kept" in str(err)
    # steps completed by the engine (its coordinates finite), at least those kept
    assert part.t.size == round(part.t[-1] / dt) + 1 and part.stats.steps >= part.t.size - 1
    assert part.t[-1] < FLUTTER_RUN["t_end"] - 10.0
    assert np.all(np.isfinite(part.x))
    assert f"t = {err.time!r}" in str(err)
    # while it grows (by 1e66 over t <= 20), the response is exact
    early = part.t <= 20.0
    z0 = np.concatenate([FLUTTER_RUN["x0"], [0.0, 0.0]])
    ref, _, _ = forced(m, c, k, z0, part.t[early], np.zeros((2, 1)), np.zeros((1, 1)), [0.0])
    e = rel(part.x[early], ref)
    growth_seen = np.abs(ref[-1]).max() / 1e-3
    print(f"flutter: error over t <= 20 (growth x{growth_seen:.1e}), relative to the peak: {e:.2e}")
    assert e <= 1e-12


def test_divergence_partial_history_is_finite():
    ref = _diverge("pseudo-force").partial  # the paper's route: x and v finite
    assert np.all(np.isfinite(ref.x)) and np.all(np.isfinite(ref.v))
    part = _diverge("auto").partial
    bad = ~np.isfinite(part.v)
    print(
        f"\nflutter, coupled exact: rows of partial.v not finite: {np.flatnonzero(bad.any(axis=1))}"
    )
    assert np.all(np.isfinite(part.x)) and np.all(np.isfinite(part.v))
    with np.errstate(over="ignore", invalid="ignore"):
        assert np.all(np.isfinite(part.modal.q)) and np.all(np.isfinite(part.modal.v))


# --------------------------------------------------------------------------------------------
# 11. save_every
# --------------------------------------------------------------------------------------------
def test_save_every_keeps_the_same_values_and_the_last_step():
    loads = [L.Step(4, amplitude=10.0), L.Harmonic(2, amplitude=3.0, omega=9.0, phase=0.2)]
    system, _, _ = build_coupled("rayleigh+LinearCoupling(sparse K,C)", loads)
    kw = {"t_end": 2.0, "dt": 0.05, "x0": X0_5, "v0": V0_5}  # 40 steps
    every = duhamel.solve(system, duhamel.Semianalytic(), **kw)
    some = duhamel.solve(system, duhamel.Semianalytic(), save_every=7, **kw)
    idx = [*range(0, 41, 7), 40]
    assert some.stats.coupling == "exact" and some.stats.steps == 40
    assert np.array_equal(some.t, every.t[idx])
    d = max(
        rel(some.x, every.x[idx]),
        rel(some.v, every.v[idx]),
        rel(some.a, every.a[idx]),
        rel(some.modal.q, every.modal.q[idx]),
    )
    print(f"\nsave_every=7 vs every step at the saved instants (last step included): {d:.2e}")
    assert d <= 1e-15


# --------------------------------------------------------------------------------------------
# 12. The pseudo-force route converges (second order) to the exact one
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("variant", [VARIANTS[0], VARIANTS[2]])
def test_pseudo_force_converges_to_exact_at_second_order(variant):
    system, _, _ = build_coupled(variant)
    t_end, dt0 = 2.0, 0.02
    exact = duhamel.solve(system, duhamel.Semianalytic(), t_end=t_end, dt=dt0, x0=X0_5, v0=V0_5)
    dts = [dt0 / 2**k for k in range(5)]
    errs = []
    for k, dt in enumerate(dts):
        sol = duhamel.solve(
            system,
            duhamel.Semianalytic(coupling="pseudo-force"),
            t_end=t_end,
            dt=dt,
            x0=X0_5,
            v0=V0_5,
        )
        assert sol.stats.coupling == "pseudo-force"
        errs.append(rel(sol.x[:: 2**k], exact.x))
    assert_order(f"pseudo-force -> exact [{variant}]", dts, errs, 2.0, 0.1)


# --------------------------------------------------------------------------------------------
# 13. Nonlinear elements on the exact coupled background
# --------------------------------------------------------------------------------------------
def _gyro_cubic():
    """Two 2-dof 'disks' with gyroscopic and circulatory coupling and hardening cubic
    springs on the first one, under a suddenly applied force."""
    m = np.diag([1.0, 1.0, 0.5, 0.5])
    k = np.array([[400.0, 0, -100, 0], [0, 400, 0, -100], [-100, 0, 300, 0], [0, -100, 0, 300]])
    g = np.zeros((4, 4))
    g[0, 1], g[1, 0], g[2, 3], g[3, 2] = 6.0, -6.0, 3.0, -3.0
    kx = np.zeros((4, 4))
    kx[0, 1], kx[1, 0] = 20.0, -20.0

    def build():
        s = duhamel.System(m, k, zeta=0.02)
        s.add(E.LinearCoupling(K=kx, C=g))
        s.add(E.Cubic(0, k3=5e4))
        s.add(E.Cubic(1, k3=5e4))
        return s.add_load(L.Step(0, amplitude=5.0))

    basis = build().modal()
    c = m @ basis.phi @ np.diag(basis.c) @ basis.phi.T @ m + g
    minv = np.linalg.inv(m)

    def rhs(t, y):
        x, v = y[:4], y[4:]
        f = np.array([5.0 - 5e4 * x[0] ** 3, -5e4 * x[1] ** 3, 0.0, 0.0])
        return np.concatenate([v, minv @ (f - c @ v - (k + kx) @ x)])

    return build, rhs


def test_nonlinear_on_exact_background_converges_and_beats_the_pseudo_force_route():
    build, rhs = _gyro_cubic()
    x0 = np.array([0.05, 0.0, 0.0, 0.02])
    t_end, dts = 3.0, [0.02, 0.01, 0.005, 0.0025]
    errs = {"auto": [], "pseudo-force": []}
    for dt in dts:
        t = np.arange(round(t_end / dt) + 1) * dt
        ref = scipy.integrate.solve_ivp(
            rhs,
            (0, t_end),
            np.concatenate([x0, np.zeros(4)]),
            method="DOP853",
            rtol=1e-12,
            atol=1e-14,
            t_eval=t,
        ).y
        for route in errs:
            sol = duhamel.solve(
                build(), duhamel.Semianalytic(coupling=route), t_end=t_end, dt=dt, x0=x0
            )
            assert sol.stats.coupling == ("exact" if route == "auto" else "pseudo-force")
            errs[route].append(rel(sol.x, ref[:4].T))
            if route == "auto" and dt == dts[-1]:
                # accelerations and the modal history satisfy the equations of motion
                i = 77
                y = np.concatenate([sol.x[i], sol.v[i]])
                a_ref = rhs(sol.t[i], y)[4:]
                assert np.abs(sol.a[i] - a_ref).max() <= 1e-12 * np.abs(sol.a).max()
                phi = sol.modal.q @ build().modal().phi.T
                assert np.abs(phi - sol.x).max() <= 1e-13 * np.abs(sol.x).max()
    slope = np.polyfit(np.log(dts), np.log(errs["auto"]), 1)[0]
    ratio = np.array(errs["pseudo-force"]) / np.array(errs["auto"])
    print(
        f"\ngyroscopic + cubic vs DOP853: exact background {np.array(errs['auto'])}, slope "
        f"{slope:.3f}; pseudo-force route {np.array(errs['pseudo-force'])}; ratio {ratio}"
    )
    assert abs(slope - 2.0) < 0.1
    assert np.all(ratio > 5.0)

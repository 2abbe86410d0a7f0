"""duhamel.rotor against references that share nothing with it: textbook beam frequencies
(Euler-Bernoulli closed forms, the Timoshenko frequency equation of a pinned-pinned beam and of
a spinning one, derived here from the continuum equations), the closed-form whirl of a rigid
disk on a massless shaft, the matrix exponential of the full first-order system, the
frequency-domain unbalance response and static deflections from ``numpy.linalg.solve`` /
``scipy.optimize.fsolve``. Measured numbers are printed (``pytest -s tests/rotor/test_rotor.py``).
"""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest
import scipy.linalg
from scipy.integrate import solve_ivp
from scipy.optimize import brentq, fsolve

import duhamel
from duhamel import elements as E
from duhamel.constants import STANDARD_GRAVITY
from duhamel.rotor import (
    STEEL,
    Bearing,
    Disk,
    Gravity,
    Material,
    Rotor,
    Shaft,
    SuddenForce,
    Unbalance,
    cowper_shear_coefficient,
    plot_orbit,
    rpm,
)

E_MOD, RHO, NU = 211e9, 7810.0, 0.3
MAT = Material(E=E_MOD, rho=RHO, nu=NU)
G_MOD = E_MOD / (2 * (1 + NU))


def slopes(h, errs):
    """Least-squares slope of log(error) against log(h), and the pairwise slopes."""
    lh, le = np.log(np.asarray(h)), np.log(np.asarray(errs))
    return float(np.polyfit(lh, le, 1)[0]), np.diff(le) / np.diff(lh)


def assert_order(label, h, errs, order, tol=0.1):
    fit, pair = slopes(h, errs)
    shown = np.array2string(np.asarray(errs), formatter={"float_kind": lambda v: f"{v:.3e}"})
    print(
        f"\n{label}: errors {shown}, slope {fit:.4f}, pairwise {np.array2string(pair, precision=3)}"
    )
    assert abs(fit - order) <= tol, (label, fit, pair)
    assert np.all(np.abs(pair - order) <= tol), (label, pair)


def uniform(n, length, d, **kw):
    return Rotor([Shaft(length / n, d, material=MAT, **kw) for _ in range(n)])


def section(d):
    return math.pi * d**2 / 4, math.pi * d**4 / 64


# --------------------------------------------------------------------------------------------
# 1. The element itself
# --------------------------------------------------------------------------------------------
def test_element_matrices_match_closed_forms():
    shaft = Shaft(0.3, 0.08, 0.02, material=STEEL)
    M, K, G = shaft.matrices()
    L, phi = shaft.L, shaft.phi
    EI = STEEL.E * shaft.second_moment
    # Timoshenko stiffness in closed form (Przemieniecki 1968), x-z plane (x1, ty1, x2, ty2)
    kc = (
        EI
        / ((1 + phi) * L**3)
        * np.array(
            [
                [12, 6 * L, -12, 6 * L],
                [6 * L, (4 + phi) * L**2, -6 * L, (2 - phi) * L**2],
                [-12, -6 * L, 12, -6 * L],
                [6 * L, (2 - phi) * L**2, -6 * L, (4 + phi) * L**2],
            ]
        )
    )
    xz = [0, 3, 4, 7]
    assert np.abs(K[np.ix_(xz, xz)] - kc).max() <= 1e-13 * np.abs(kc).max()
    # y-z plane: the same with theta_x = -dy/dz
    yz, sign = [1, 2, 5, 6], np.array([1.0, -1.0, 1.0, -1.0])
    assert np.abs(K[np.ix_(yz, yz)] - np.outer(sign, sign) * kc).max() <= 1e-13 * np.abs(kc).max()
    # Euler-Bernoulli limit of the mass matrix: the 420 matrix
    eb = Shaft(0.3, 0.08, 0.02, material=STEEL, shear_deformation=False, rotary_inertia=False)
    m420 = (
        eb.mass
        / 420
        * np.array(
            [
                [156, 22 * L, 54, -13 * L],
                [22 * L, 4 * L**2, 13 * L, -3 * L**2],
                [54, 13 * L, 156, -22 * L],
                [-13 * L, -3 * L**2, -22 * L, 4 * L**2],
            ]
        )
    )
    assert np.abs(eb.matrices()[0][np.ix_(xz, xz)] - m420).max() <= 1e-13 * m420.max()
    # rigid-body motions: zero strain energy; exact mass, inertia and gyroscopic coupling
    half = L / 2
    tilt_y = np.array([-half, 0, 0, 1, half, 0, 0, 1.0])  # x = (z - L/2), theta_y = 1
    tilt_x = np.array([0, half, 1, 0, 0, -half, 1, 0.0])  # y = -(z - L/2), theta_x = 1
    shift = np.array([1.0, 0, 0, 0, 1, 0, 0, 0])
    Id = shaft.mass * L**2 / 12 + STEEL.rho * shaft.second_moment * L
    Ip = 2 * STEEL.rho * shaft.second_moment * L
    assert max(abs(v @ K @ v) for v in (tilt_x, tilt_y, shift)) <= 1e-12 * np.abs(K).max()
    assert shift @ M @ shift == pytest.approx(shaft.mass, rel=1e-14)
    assert tilt_y @ M @ tilt_y == pytest.approx(Id, rel=1e-14)
    assert tilt_x @ G @ tilt_y == pytest.approx(Ip, rel=1e-14)  # as a disk's G[tx, ty] = Ip
    assert np.array_equal(G, -G.T) and np.array_equal(M, M.T) and np.array_equal(K, K.T)


def test_section_disk_and_material_properties():
    assert cowper_shear_coefficient(0.3) == pytest.approx(7.8 / 8.8, rel=1e-15)
    assert Shaft(1.0, 0.1, 0.05, material=STEEL).kappa == pytest.approx(
        cowper_shear_coefficient(0.3, 0.5), rel=1e-15
    )
    assert Material(E=2e11, rho=7800.0, nu=0.25).G == 8e10
    assert Material(E=2e11, rho=7800.0, G=8e10).nu == pytest.approx(0.25, rel=1e-15)
    with pytest.raises(ValueError, match="`G` or Poisson"):
        Material(E=2e11, rho=7800.0)
    with pytest.raises(ValueError, match="disagree"):
        Material(E=2e11, rho=7800.0, G=8e10, nu=0.3)
    with pytest.raises(ValueError, match="inner_diameter"):
        Shaft(1.0, 0.05, 0.05, material=STEEL)
    d = Disk.from_geometry(0, width=0.1, outer_diameter=0.4, inner_diameter=0.1, material=MAT)
    m = RHO * math.pi * (0.4**2 - 0.1**2) / 4 * 0.1
    assert (d.mass, d.Ip, d.Id) == pytest.approx(
        (m, m * (0.2**2 + 0.05**2) / 2, m * (3 * (0.2**2 + 0.05**2) + 0.1**2) / 12), rel=1e-14
    )


# --------------------------------------------------------------------------------------------
# 2. Textbook frequencies: free-free and pinned-pinned shafts, mesh convergence
# --------------------------------------------------------------------------------------------
def pinned(rotor):
    """(M, K, G) with the end nodes' translations removed: exact pins."""
    M, K, _, G = rotor.matrices()
    last = 4 * (rotor.n_nodes - 1)
    keep = np.setdiff1d(np.arange(rotor.n_dof), [0, 1, last, last + 1])
    return [X[np.ix_(keep, keep)] for X in (M, K, G)]


def test_free_free_euler_bernoulli_convergence():
    """Slender shaft (L/d = 50), Euler-Bernoulli element, through Rotor.natural_frequencies
    (state-space eigenproblem; the rigid-body modes are dropped): cos(bL) cosh(bL) = 1."""
    L, d = 1.0, 0.02
    A, I2 = section(d)
    roots = [
        brentq(lambda b: math.cos(b) * math.cosh(b) - 1, (k + 0.2) * math.pi, (k + 0.8) * math.pi)
        for k in (1, 2, 3)
    ]
    exact = np.array(roots) ** 2 * math.sqrt(E_MOD * I2 / (RHO * A * L**4))
    meshes = (8, 16, 32, 64)
    errs = []
    for n in meshes:
        f = uniform(n, L, d, shear_deformation=False, rotary_inertia=False).natural_frequencies()
        assert np.allclose(f[0:6:2], f[1:6:2], rtol=1e-8, atol=0)  # x and y planes
        errs.append(np.abs(f[0:6:2] / exact - 1))
    errs = np.array(errs)
    print(f"\nfree-free exact (rad/s): {exact}")
    # mode 1 on 8-32 elements (on 64 its error, 2e-8, nears the eigensolver's accuracy
    # eps (omega_max/omega_1)^2 ~ 1e-9); modes 2 and 3 are pre-asymptotic on 8: 16-64
    for k, rows in ((0, slice(0, 3)), (1, slice(1, 4)), (2, slice(1, 4))):
        h = np.divide(L, meshes)[rows]
        assert_order(f"free-free EB mode {k + 1}", h, errs[rows, k], 4.0)


def test_pinned_pinned_euler_bernoulli_convergence():
    L, d = 1.0, 0.02
    A, I2 = section(d)
    exact = np.array(
        [(k * math.pi / L) ** 2 * math.sqrt(E_MOD * I2 / (RHO * A)) for k in (1, 2, 3)]
    )
    meshes = (8, 16, 32)
    errs = []
    for n in meshes:
        M, K, _ = pinned(uniform(n, L, d, shear_deformation=False, rotary_inertia=False))
        w = np.sqrt(scipy.linalg.eigh(K, M, eigvals_only=True))
        errs.append(np.abs(w[0:6:2] / exact - 1))
    errs = np.array(errs)
    for k in range(3):
        assert_order(f"pinned-pinned EB mode {k + 1}", np.divide(L, meshes), errs[:, k], 4.0)


def spinning_timoshenko(L, d, kappa, n_modes, speed):
    """Pinned-pinned spinning Timoshenko shaft, from the continuum equations.

    With u = U sin kz, v = V sin kz, psi = P cos kz, (-theta_x) = Q cos kz (k = n pi / L)
    the equations of motion reduce exactly to four ODEs per n:
    rho A U'' + kGA (k^2 U - k P) = 0,
    rho I P'' + 2 rho I speed Q' + EI k^2 P + kGA (P - k U) = 0,
    and the same for (V, Q) with -2 rho I speed P'. Their eigenvalues are the frequencies;
    at zero speed this is the classical Timoshenko frequency equation
    (kGA k^2 - rho A w^2)(EI k^2 + kGA - rho I w^2) = (kGA k)^2.
    Returns the (backward, forward) bending frequencies of the first n_modes.
    """
    A, I2 = section(d)
    kga, EI = kappa * G_MOD * A, E_MOD * I2
    out = []
    for n in range(1, n_modes + 1):
        k = n * math.pi / L
        m = np.diag([RHO * A, RHO * A, RHO * I2, RHO * I2])
        g = np.zeros((4, 4))
        g[2, 3], g[3, 2] = 2 * RHO * I2, -2 * RHO * I2
        kk = np.array(
            [
                [kga * k * k, 0, -kga * k, 0],
                [0, kga * k * k, 0, -kga * k],
                [-kga * k, 0, EI * k * k + kga, 0],
                [0, -kga * k, 0, EI * k * k + kga],
            ]
        )
        a = np.block(
            [
                [np.zeros((4, 4)), np.eye(4)],
                [-np.linalg.solve(m, kk), -speed * np.linalg.solve(m, g)],
            ]
        )
        lam = np.linalg.eigvals(a)
        out.append(np.sort(lam.imag[lam.imag > 0])[:2])
    return np.array(out)


def first_order_frequencies(M, K, D):
    n = M.shape[0]
    a = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, K), -np.linalg.solve(M, D)]])
    lam = np.linalg.eigvals(a)
    return np.sort(lam.imag[lam.imag > 0])


def test_stubby_shaft_converges_to_timoshenko_including_spin():
    """L/d = 4: Timoshenko is 6.7 / 20 / 33 % below Euler-Bernoulli for modes 1 / 2 / 3. The
    interdependent-interpolation element converges at order 2 here (its shear parameter grows
    as 1/h^2, so its shape functions tend to linear ones), measured, not assumed."""
    L, d = 0.4, 0.1
    kappa = uniform(1, L, d).shafts[0].kappa
    A, I2 = section(d)
    ref0 = spinning_timoshenko(L, d, kappa, 3, 0.0)[:, 0]
    eb = np.array([(k * math.pi / L) ** 2 * math.sqrt(E_MOD * I2 / (RHO * A)) for k in (1, 2, 3)])
    print(f"\nTimoshenko / Euler-Bernoulli - 1: {ref0 / eb - 1}")
    assert np.all(ref0 < eb)
    meshes = (4, 8, 16, 32)
    errs = []
    for n in meshes:
        M, K, _ = pinned(uniform(n, L, d))
        w = np.sqrt(scipy.linalg.eigh(K, M, eigvals_only=True))
        errs.append(np.abs(w[0:6:2] / ref0 - 1))
    errs = np.array(errs)
    for k in range(3):
        assert_order(
            f"pinned-pinned Timoshenko mode {k + 1}", np.divide(L, meshes), errs[:, k], 2.0
        )
    # spinning at 20000 rad/s: backward/forward split of the first two modes
    speed = 20000.0
    ref = spinning_timoshenko(L, d, kappa, 2, speed).ravel()  # b1, f1, b2, f2
    errs = []
    for n in meshes:
        M, K, G = pinned(uniform(n, L, d))
        errs.append(np.abs(first_order_frequencies(M, K, speed * G)[:4] / ref - 1))
    errs = np.array(errs)
    print(f"spinning reference (rad/s) b1 f1 b2 f2: {ref}; split of mode 1 {ref[1] - ref[0]:.1f}")
    for k, name in enumerate(("backward 1", "forward 1", "backward 2", "forward 2")):
        assert_order(f"spinning Timoshenko {name}", np.divide(L, meshes), errs[:, k], 2.0)


# --------------------------------------------------------------------------------------------
# 3. Jeffcott: a rigid disk on a massless Timoshenko shaft on flexible bearings
# --------------------------------------------------------------------------------------------
def test_disk_on_massless_shaft_whirl_matches_closed_form():
    """Disk (m, Ip, Id) at mid-span of a massless shaft of span L on two bearings k_b.

    Statics of the Timoshenko beam plus the bearings give the disk's translational and tilt
    compliances (exact: the element's shape functions are the static solutions),
    c_t = L^3/(48 EI) + L/(4 kGA) + 1/(2 k_b), c_r = L/(12 EI) + 1/(kGA L) + 2/(k_b L^2);
    by symmetry translation and tilt decouple. Translation: w_t = 1/sqrt(m c_t) at every
    speed. Tilt (Id theta_x'' + Omega Ip theta_y' + theta_x / c_r = 0, ...): a whirl
    e^{i w t} in the sense +-1 gives Id w^2 -+ Ip Omega w - 1/c_r = 0, so
    w_f,b = (+-Ip Omega + sqrt(Ip^2 Omega^2 + 4 Id / c_r)) / (2 Id).
    """
    L, d, m, Ip, Id, kb = 0.8, 0.04, 30.0, 0.3, 0.16, 5e6
    shaft = Shaft(L / 2, d, material=Material(E=E_MOD, rho=0.0, nu=NU))
    rotor = Rotor([shaft, shaft], [Disk(1, m, Ip, Id)], [Bearing(0, kb, kb), Bearing(2, kb, kb)])
    EI, kga = E_MOD * shaft.second_moment, shaft.kappa * G_MOD * shaft.area
    ct = L**3 / (48 * EI) + L / (4 * kga) + 1 / (2 * kb)
    cr = L / (12 * EI) + 1 / (kga * L) + 2 / (kb * L**2)
    wt = 1 / math.sqrt(m * ct)
    worst = 0.0
    for speed in (0.0, 500.0, 2000.0, 8000.0):
        root = math.sqrt((Ip * speed) ** 2 + 4 * Id / cr)
        wf, wb = (Ip * speed + root) / (2 * Id), (-Ip * speed + root) / (2 * Id)
        modes = rotor.modes(speed)
        ref = np.sort([wt, wt, wb, wf])
        err = float(np.max(np.abs(modes.frequencies / ref - 1)))
        worst = max(worst, err)
        print(
            f"\nspeed {speed:6.0f}: FE {modes.frequencies}, closed form {ref}, rel. err {err:.1e}"
        )
        assert modes.n_modes == 4
        assert err <= 1e-12
        if speed > 0:
            whirl = dict(zip(modes.frequencies.round(6), modes.whirl, strict=False))
            assert whirl[round(wf, 6)] == "forward" and whirl[round(wb, 6)] == "backward"
            # the translational pair: one circular forward, one circular backward orbit
            pair = [
                w
                for f, w in zip(modes.frequencies, modes.whirl, strict=True)
                if abs(f - wt) < 1e-6 * wt
            ]
            assert sorted(pair) == ["backward", "forward"]
    print(f"worst relative error {worst:.1e}")
    campbell = rotor.campbell([0.0, 500.0, 2000.0])
    assert campbell.frequencies.shape == (3, 4)
    with pytest.raises(ValueError, match="no mass"):
        rotor.system(100.0)


# --------------------------------------------------------------------------------------------
# 4. Time integration against the full first-order system
# --------------------------------------------------------------------------------------------
def make_rotor():
    """Two disks, anisotropic bearings with cross-coupled stiffness (kxy = -kyx / 1.5) and
    non-symmetric damping, Rayleigh damping; every mode stable at 6000 rpm."""
    shafts = [Shaft(0.2, 0.04, material=MAT) for _ in range(5)]
    disks = [
        Disk.from_geometry(2, 0.05, 0.25, 0.04, MAT),
        Disk.from_geometry(4, 0.04, 0.2, 0.04, MAT),
    ]
    b = {
        "kxx": 2e7,
        "kyy": 3e7,
        "kxy": 1e6,
        "kyx": -1.5e6,
        "cxx": 1500.0,
        "cyy": 2000.0,
        "cxy": 150.0,
        "cyx": -50.0,
    }
    return Rotor(shafts, disks, [Bearing(0, **b), Bearing(5, **b)], rayleigh=(40.0, 2e-6))


SPEED = rpm(6000)


def first_order_matrix(rotor, speed):
    M, K, C, G = rotor.matrices(speed)
    n = rotor.n_dof
    a = np.zeros((2 * n, 2 * n))
    a[:n, n:] = np.eye(n)
    a[n:, :n] = -np.linalg.solve(M, K)
    a[n:, n:] = -np.linalg.solve(M, C + speed * G)
    return a


def translations(n_dof):
    mask = np.zeros(n_dof, dtype=bool)
    mask[0::4] = mask[1::4] = True
    return mask


def test_system_structure():
    rotor = make_rotor()
    system = rotor.system(SPEED)
    _, K, C, G = rotor.matrices(SPEED)
    assert system.damping == "matrix" and len(system.couplings) == 2
    gyro, bearing = system.couplings
    assert np.array_equal(gyro.C, SPEED * G) and gyro.K is None
    assert np.allclose(system.K + bearing.K, K, rtol=0, atol=1e-6)
    assert np.allclose(system.C + bearing.C, C, rtol=0, atol=1e-9)
    assert np.array_equal(bearing.K, -bearing.K.T) and np.array_equal(system.K, system.K.T)
    # symmetric bearings at zero speed: nothing but the exact background
    plain = Rotor(
        rotor.shafts, rotor.disks, [Bearing(0, 1e7, 2e7), Bearing(5, 1e7, 2e7)], zeta=0.02
    )
    assert plain.system(0.0).elements == [] and plain.system(0.0).damping == "zeta"
    assert plain.system(0.0).couplings == []
    # modal damping: the matrix the direct integrators and eigenvalues see is diagonal on the modes
    lam, phi = scipy.linalg.eigh(plain.matrices().K, plain.matrices().M)
    cm = phi.T @ plain.matrices().C @ phi
    assert np.allclose(cm, np.diag(0.04 * np.sqrt(lam)), rtol=0, atol=1e-9 * cm.max())


def test_complex_modes_solve_the_eigenproblem():
    rotor = make_rotor()
    M, K, C, G = rotor.matrices(SPEED)
    modes = rotor.modes(SPEED)
    # backward error of each eigenpair of the quadratic problem (Tisseur 2000)
    D = C + SPEED * G
    norms = [np.linalg.norm(X, 2) for X in (M, D, K)]
    residual = max(
        np.linalg.norm((lam**2 * M + lam * D + K) @ u)
        / ((abs(lam) ** 2 * norms[0] + abs(lam) * norms[1] + norms[2]) * np.linalg.norm(u))
        for lam, u in zip(modes.eigenvalues, modes.shapes.T, strict=True)
    )
    lam = np.linalg.eigvals(first_order_matrix(rotor, SPEED))
    independent = np.sort(lam.imag[lam.imag > 0])
    print(
        f"\neigen residual {residual:.1e}; lowest modes {modes.frequencies[:4]} rad/s, zeta "
        f"{modes.damping_ratios[:4]}, {modes.whirl[:4]}"
    )
    assert residual < 1e-13
    assert np.allclose(modes.frequencies, independent, rtol=1e-9)
    assert np.all(modes.damping_ratios > 0)
    assert np.array_equal(rotor.natural_frequencies(SPEED, n=3), modes.frequencies[:3])


@pytest.mark.parametrize(
    "integrator", [duhamel.Semianalytic(coupling="pseudo-force"), duhamel.Newmark()], ids=repr
)
def test_linear_rotor_matches_matrix_exponential(integrator):
    """Free whirl from the four lowest complex modes (1e-4 m), gyroscopic and cross-coupled
    terms and non-symmetric bearing damping as pseudo-forces (Semianalytic) or in the
    iteration matrix (Newmark), against expm of the first-order system on the same grid."""
    rotor = make_rotor()
    modes = rotor.modes(SPEED, n=4)
    x0 = 1e-4 * modes.shapes.sum(axis=1).real
    v0 = 1e-4 * (modes.shapes * modes.eigenvalues).sum(axis=1).real
    a = first_order_matrix(rotor, SPEED)
    n, t_end, mask = rotor.n_dof, 0.05, translations(rotor.n_dof)
    dts = [2e-4, 1e-4, 5e-5, 2.5e-5]
    errs = []
    for dt in dts:
        step = scipy.linalg.expm(a * dt)
        z, ref = np.concatenate([x0, v0]), [x0]
        for _ in range(round(t_end / dt)):
            z = step @ z
            ref.append(z[:n])
        ref = np.array(ref)
        sol = duhamel.solve(rotor.system(SPEED), integrator, t_end=t_end, dt=dt, x0=x0, v0=v0)
        errs.append(np.abs(sol.x[:, mask] - ref[:, mask]).max() / np.abs(ref[:, mask]).max())
    assert_order(f"linear rotor, {type(integrator).__name__}", dts, errs, 2.0)


def test_classical_rotor_is_exact_at_any_step():
    """At zero speed with symmetric bearings, no bearing damping and modal damping the rotor is
    a classical system: the semi-analytic run is exact (steps of 1/8 of the first period)."""
    base = make_rotor()
    rotor = Rotor(base.shafts, base.disks, [Bearing(0, 2e7, 3e7), Bearing(5, 2e7, 3e7)], zeta=0.02)
    n = rotor.n_dof
    f = SuddenForce(2, fx=1e3, fy=-400.0).loads(rotor)
    system = rotor.system(0.0, f)
    assert system.elements == []
    a = first_order_matrix(rotor, 0.0)
    b = np.zeros(2 * n)
    b[n:] = np.linalg.solve(rotor.matrices().M, sum(load.evaluate(system, 1.0) for load in f))
    dt = 2 * math.pi / rotor.natural_frequencies(0.0)[0] / 8
    sol = duhamel.solve(system, duhamel.Semianalytic(), t_end=40 * dt, dt=dt)
    aug = np.zeros((2 * n + 1, 2 * n + 1))
    aug[: 2 * n, : 2 * n], aug[: 2 * n, -1] = a, b
    step, z, err = scipy.linalg.expm(aug * dt), np.zeros(2 * n + 1), 0.0
    z[-1] = 1.0
    for i in range(1, sol.t.size):
        z = step @ z
        err = max(err, float(np.abs(sol.x[i] - z[:n]).max()))
    err /= np.abs(sol.x).max()
    print(f"\nclassical rotor, dt = T1/8: max error {err:.1e}")
    assert err < 1e-10


def test_unbalance_steady_state_matches_frequency_domain():
    """After 100 revolutions (slowest transient decay e^-19.8 = 2.5e-9) the response to an
    unbalance equals Re(X e^{i Omega t}), X = [K - Omega^2 M + i Omega (C + Omega G)]^-1 F, to
    the integrator's second-order error (translations, last revolution)."""
    rotor = make_rotor()
    m_e, phase = 1e-3, 0.3
    M, K, C, G = rotor.matrices(SPEED)
    F = np.zeros(rotor.n_dof, dtype=complex)
    F[rotor.dof(2, "x")] = m_e * SPEED**2 * np.exp(1j * phase)  # m_e W^2 cos(W t + phase)
    F[rotor.dof(2, "y")] = -1j * m_e * SPEED**2 * np.exp(1j * phase)  # ... sin(W t + phase)
    X = np.linalg.solve(K - SPEED**2 * M + 1j * SPEED * (C + SPEED * G), F)
    decay = float(np.min(-rotor.modes(SPEED).eigenvalues.real))
    period = 2 * math.pi / SPEED
    t_end, mask = 100 * period, translations(rotor.n_dof)
    print(f"\ntransient left at t_end: exp(-{decay:.2f} t_end) = {math.exp(-decay * t_end):.1e}")
    dts = [period / 20, period / 40, period / 80, period / 160]
    errs = []
    for dt in dts:
        system = rotor.system(SPEED, [Unbalance(2, m_e, phase=phase)])
        integrator = duhamel.Semianalytic(coupling="pseudo-force")  # the paper's route
        sol = duhamel.solve(system, integrator, t_end=t_end, dt=dt)
        last = sol.t >= t_end - period * (1 + 1e-9)
        ref = (X[None, :] * np.exp(1j * SPEED * sol.t[last])[:, None]).real
        errs.append(np.abs(sol.x[last][:, mask] - ref[:, mask]).max() / np.abs(X[mask]).max())
    assert_order("unbalance steady state", dts, errs, 2.0)


def test_unbalance_and_sudden_force_loads():
    rotor = make_rotor()
    system = rotor.system(SPEED)
    u = Unbalance(3, 2e-4, phase=1.1)
    t = np.linspace(0.0, 0.01, 7)
    f = sum(load.evaluate(system, t) for load in u.loads(rotor, SPEED))
    ang = SPEED * t + 1.1
    assert np.allclose(f[:, rotor.dof(3, "x")], 2e-4 * SPEED**2 * np.cos(ang), rtol=0, atol=1e-12)
    assert np.allclose(f[:, rotor.dof(3, "y")], 2e-4 * SPEED**2 * np.sin(ang), rtol=0, atol=1e-12)
    assert np.count_nonzero(np.abs(f).max(axis=0)) == 2
    assert Unbalance.from_force(0, 5e4, rpm(1500)).m_e * rpm(1500) ** 2 == pytest.approx(5e4)
    with pytest.raises(ValueError, match="differs"):
        rotor.system(SPEED, [Unbalance(3, 2e-4, speed=SPEED / 2)])
    with pytest.raises(ValueError, match="needs a speed"):
        Unbalance(3, 2e-4).loads(rotor)
    steps = SuddenForce(1, fx=0.0, fy=-5e4, t0=0.01).loads(rotor)
    assert [(s.dof, s.amplitude, s.t0) for s in steps] == [(rotor.dof(1, "y"), -5e4, 0.01)]


def test_constant_speed_unbalance_equals_the_harmonic_loads():
    """A constant-speed Unbalance is now one duhamel.loads.Unbalance on the node's (x, y); it
    is the same force as the two Harmonic loads it replaced (x with phase + pi/2), so the
    responses agree to round-off, with either integrator and with a ConstantSpeed law."""
    rotor = make_rotor()
    m_e, phase = 2e-4, 0.7
    (load,) = Unbalance(3, m_e, phase=phase).loads(rotor, SPEED)
    assert isinstance(load, duhamel.loads.Unbalance)
    assert (load.dof_x, load.dof_y, load.m_e, load.phase) == (12, 13, m_e, phase)
    old = [
        duhamel.loads.Harmonic(
            12, amplitude=m_e * SPEED**2, omega=SPEED, phase=phase + math.pi / 2
        ),
        duhamel.loads.Harmonic(13, amplitude=m_e * SPEED**2, omega=SPEED, phase=phase),
    ]
    for integrator in (duhamel.Semianalytic(), duhamel.Newmark()):
        runs = []
        for speed, loads in (
            (SPEED, [Unbalance(3, m_e, phase=phase)]),
            (duhamel.speed.ConstantSpeed(SPEED), [Unbalance(3, m_e, phase=phase)]),
            (SPEED, old),
        ):
            sol = duhamel.solve(rotor.system(speed, loads), integrator, t_end=0.02, dt=2e-5)
            runs.append(sol.x)
        scale = np.abs(runs[2]).max()
        diff = max(np.abs(run - runs[2]).max() for run in runs[:2]) / scale
        print(f"\n{type(integrator).__name__}: Unbalance load vs two Harmonic loads: {diff:.1e}")
        assert diff < 1e-12


# A small rotor for the run-up: 2 Timoshenko elements, a disk at the middle node, anisotropic
# bearings with cross-coupled stiffness and damping, Rayleigh damping. First critical speeds
# 332 and 351 rad/s; run up from rest to 600 rad/s in 0.4 s, then 0.1 s at constant speed.
RUN_W1, RUN_T1, RUN_TEND, RUN_ME = 600.0, 0.4, 0.5, 1e-4
RUN_GRID = 100  # reference samples over the run


def small_rotor():
    b = {"kxx": 2e6, "kyy": 3e6, "kxy": 2e5, "kyx": -2e5, "cxx": 200.0, "cyy": 200.0}
    return Rotor(
        [Shaft(0.3, 0.03, material=MAT)] * 2,
        [Disk.from_geometry(1, 0.04, 0.2, 0.03, MAT)],
        [Bearing(0, **b), Bearing(2, **b)],
        rayleigh=(5.0, 1e-5),
    )


@functools.lru_cache
def run_up_reference():
    """DOP853 (rtol 1e-11, restarted at t1) on M x'' + (C + omega(t) G) x' + K x = f_u(t),
    with the run-up and the unbalance force of an eccentric mass written out here."""
    rotor = small_rotor()
    M, K, C, G = rotor.matrices()
    minv, n, accel = np.linalg.inv(M), rotor.n_dof, RUN_W1 / RUN_T1
    dx, dy = rotor.dof(1, "x"), rotor.dof(1, "y")

    def rhs(t, z):
        x, v = z[:n], z[n:]
        if t < RUN_T1:
            w, dw, th = accel * t, accel, 0.5 * accel * t * t
        else:
            w, dw, th = RUN_W1, 0.0, 0.5 * RUN_W1 * RUN_T1 + RUN_W1 * (t - RUN_T1)
        f = np.zeros(n)
        f[dx] = RUN_ME * (w * w * math.cos(th) + dw * math.sin(th))
        f[dy] = RUN_ME * (w * w * math.sin(th) - dw * math.cos(th))
        return np.concatenate([v, minv @ (f - (C + w * G) @ v - K @ x)])

    grid = np.linspace(0.0, RUN_TEND, RUN_GRID + 1)
    rows, z = [], np.zeros(2 * n)
    for a, b in ((0.0, RUN_T1), (RUN_T1, RUN_TEND)):
        at = grid[(grid >= a) & (grid <= b)] if a == 0.0 else grid[grid > a]
        r = solve_ivp(rhs, (a, b), z, method="DOP853", rtol=1e-11, atol=1e-16, t_eval=at)
        assert r.success, r.message
        rows.append(r.y.T[:, :n])
        z = r.y[:, -1]
    return grid, np.concatenate(rows)


@pytest.mark.parametrize(
    "integrator", [duhamel.Semianalytic(coupling="pseudo-force"), duhamel.Newmark()], ids=repr
)
def test_run_up_through_the_critical_speed_matches_an_ode_reference(integrator):
    """Rotor.system(LinearRunUp) and Unbalance on the run-up law: the gyroscopic force
    omega(t) G x' and the unbalance with phase theta(t) and the tangential omega' term, through
    the first critical speed, against DOP853 of the same time-varying ODE; second order in dt
    (t1 on the step grid, as the direct integrators need)."""
    rotor = small_rotor()
    assert rotor.natural_frequencies(0.0)[0] < RUN_W1 / 1.5  # the run passes the critical
    law = duhamel.speed.LinearRunUp(0.0, RUN_W1, RUN_T1)
    system = rotor.system(law, [Unbalance(1, RUN_ME)])
    gyro = system.couplings[0]
    assert gyro.scale is law and np.array_equal(gyro.C, rotor.matrices().G) and gyro.K is None
    assert [type(load) for load in system.loads] == [duhamel.loads.Unbalance]
    t, ref = run_up_reference()
    mask = translations(rotor.n_dof)
    # the disk's orbit peaks after the first critical, during the run-up, not at full speed
    amplitude = np.hypot(ref[:, 4], ref[:, 5])
    crossing = rotor.natural_frequencies(0.0)[0] / (RUN_W1 / RUN_T1)
    assert crossing < t[np.argmax(amplitude)] < RUN_T1
    steps = [2000, 4000, 8000, 16000]
    errs = []
    for n in steps:
        sol = duhamel.solve(system, integrator, t_end=RUN_TEND, dt=RUN_TEND / n)
        x = sol.x[:: n // RUN_GRID]
        errs.append(np.abs(x[:, mask] - ref[:, mask]).max() / np.abs(ref[:, mask]).max())
    dts = [RUN_TEND / n for n in steps]
    assert_order(f"run-up through the critical, {type(integrator).__name__}", dts, errs, 2.0)


def test_run_up_speed_checks():
    rotor = make_rotor()
    law = duhamel.speed.LinearRunUp(omega0=0.0, omega1=SPEED, t1=1.0)
    # constant laws are constant speeds: the gyroscopic matrix is folded in
    for constant in (
        duhamel.speed.ConstantSpeed(SPEED),
        duhamel.speed.LinearRunUp(SPEED, SPEED, 1.0),
    ):
        gyro = rotor.system(constant).couplings[0]
        assert gyro.scale is None and np.array_equal(gyro.C, SPEED * rotor.matrices().G)
    # an unbalance with its own law agrees with the rotor's, or is refused
    (load,) = rotor.system(law, [Unbalance(2, 1e-3, speed=law)]).loads
    assert load.speed == law
    with pytest.raises(ValueError, match="differs"):
        rotor.system(SPEED, [Unbalance(2, 1e-3, speed=law)])
    with pytest.raises(ValueError, match="differs"):
        rotor.system(law, [Unbalance(2, 1e-3, speed=SPEED)])
    # what needs one constant speed says so
    with pytest.raises(ValueError, match="`speed` must be a constant speed"):
        rotor.modes(law)
    with pytest.raises(ValueError, match="`speed` must be a constant speed"):
        Unbalance.from_force(2, 5e4, law)
    assert rotor.modes(duhamel.speed.ConstantSpeed(SPEED)).speed == SPEED

    class Varying:  # a duck-typed law the engine cannot evaluate
        def constant_value(self):
            return None

    with pytest.raises(TypeError, match=r"must be a number .* or a duhamel.speed law"):
        rotor.system(Varying())


# --------------------------------------------------------------------------------------------
# 5. Gravity and the cubic bearing law at rest: the static deflection
# --------------------------------------------------------------------------------------------
def test_gravity_static_deflection():
    """Weight = -M r g (r = 1 on the y translations): its resultant is the total weight; the
    response settles on K^-1 f_g (full K: cross-coupled bearings included). With 10 retained
    modes it settles on the static solution of the projected problem."""
    rotor = make_rotor()
    M, K, _, _ = rotor.matrices(SPEED)
    r = np.zeros(rotor.n_dof)
    r[1::4] = 1.0
    fg = -STANDARD_GRAVITY * M @ r
    weight = Gravity().vector(rotor)
    assert np.allclose(weight, fg, rtol=1e-14, atol=1e-14 * np.abs(fg).max())
    assert weight[1::4].sum() == pytest.approx(-STANDARD_GRAVITY * rotor.mass, rel=1e-14)
    assert np.all(weight[0::4] == 0.0)
    static = np.linalg.solve(K, fg)
    assert np.abs(rotor.static_deflection() - static).max() <= 1e-12 * np.abs(static).max()
    # reduced: x = Phi_n (Phi_n^T K Phi_n)^-1 Phi_n^T f_g with the undamped modes of K_sym
    k_sym = (K + K.T) / 2
    phi = scipy.linalg.eigh(k_sym, M)[1][:, :10]
    reduced = phi @ np.linalg.solve(phi.T @ K @ phi, phi.T @ fg)
    t_end = 1.5
    decay = float(np.min(-rotor.modes(SPEED).eigenvalues.real))
    print(f"\ntransient left: {math.exp(-decay * t_end):.1e}")
    for integrator, ref in (
        (duhamel.Semianalytic(), static),
        (duhamel.Semianalytic(modes=10), reduced),
        (duhamel.Newmark(), static),
    ):
        sol = duhamel.solve(
            rotor.system(SPEED, [Gravity()]), integrator, t_end=t_end, dt=1e-4, save_every=500
        )
        err = np.abs(sol.x[-1] - ref).max() / np.abs(ref).max()
        print(f"{integrator!r}: static deflection error {err:.1e}")
        assert err < 1e-9


def test_cubic_bearings_settle_on_the_nonlinear_static_solution():
    """The paper's bearing law r = k_ii x_i beta (x_i / x_stat)^2, beta = 0.1, x_stat = the
    bearing's linear static deflection under the weight (the default): the response to the
    weight settles on the root of K x + r(x) = f_g (fsolve)."""
    base = make_rotor()
    b = {"kxx": 2e7, "kyy": 3e7, "kxy": 1e6, "kyx": -1.5e6, "cxx": 1500.0, "cyy": 2000.0}
    rotor = Rotor(
        base.shafts,
        base.disks,
        [Bearing(0, **b, beta=0.1), Bearing(5, **b, beta=0.1)],
        rayleigh=(40.0, 2e-6),
    )
    K = rotor.matrices(SPEED).K
    fg = Gravity().vector(rotor)
    linear = np.linalg.solve(K, fg)
    cubic = {}
    for node in (0, 5):
        x_stat = abs(linear[rotor.dof(node, "y")])
        cubic[rotor.dof(node, "x")] = 2e7 * 0.1 / x_stat**2
        cubic[rotor.dof(node, "y")] = 3e7 * 0.1 / x_stat**2
    elements = rotor.nonlinear_elements()
    assert {e.dof: e.k3 for e in elements} == pytest.approx(cubic, rel=1e-12)

    def residual(x):
        out = K @ x - fg
        for dof, k3 in cubic.items():
            out[dof] += k3 * x[dof] ** 3
        return out / np.abs(fg).max()

    exact = fsolve(residual, linear, xtol=1e-13)
    assert np.abs(residual(exact)).max() < 1e-12
    shift = np.abs(exact - linear).max() / np.abs(exact).max()
    for integrator in (duhamel.Semianalytic(), duhamel.Newmark()):
        sol = duhamel.solve(
            rotor.system(SPEED, [Gravity()]), integrator, t_end=1.5, dt=1e-4, save_every=500
        )
        err = np.abs(sol.x[-1] - exact).max() / np.abs(exact).max()
        print(f"\n{integrator!r}: nonlinear static error {err:.1e} (nonlinear shift {shift:.1e})")
        assert err < 1e-9


def test_bearing_contact_becomes_a_rub_element():
    """A stator with 0.1 mm clearance at the disk (friction 0.2), unbalance at 1000 rad/s
    (supercritical): the rub element sits on the disk's (x, y); the orbit reaches the stator,
    and the semi-analytic and Newmark runs converge to the same response (their difference
    shrinks at order 2)."""
    bearings = [Bearing(n, 1e7, 1e7, cxx=500.0, cyy=500.0) for n in (0, 2)]
    stator = Bearing(1, 0.0, 0.0, contact=(1e-4, 1e8, 0.2))
    rotor = Rotor(
        [Shaft(0.3, 0.05, material=STEEL)] * 2,
        [Disk(1, 20.0, 0.2, 0.1)],
        [*bearings, stator],
        rayleigh=(0.0, 1e-5),
    )
    (rub,) = rotor.nonlinear_elements()
    assert isinstance(rub, E.Contact)
    got = (rub.dof_x, rub.dof_y, rub.clearance, rub.stiffness, rub.friction)
    assert got == (4, 5, 1e-4, 1e8, 0.2)
    system = rotor.system(1000.0, [Unbalance(1, 1e-3)])
    dts = [4e-5, 2e-5, 1e-5, 5e-6]
    diffs = []
    for dt in dts:
        runs = [
            duhamel.solve(system, integrator, t_end=0.03, dt=dt, dofs=[4, 5]).x
            for integrator in (duhamel.Semianalytic(), duhamel.Newmark())
        ]
        assert np.hypot(*runs[0].T).max() > 1e-4  # in contact
        diffs.append(np.abs(runs[0] - runs[1]).max() / np.abs(runs[1]).max())
    assert_order("rub: Semianalytic - Newmark", dts, diffs, 2.0)


# --------------------------------------------------------------------------------------------
# 6. Campbell diagram
# --------------------------------------------------------------------------------------------
def test_campbell_and_plot():
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    rotor = make_rotor()
    speeds = np.linspace(0.0, 2 * SPEED, 9)
    campbell = rotor.campbell(speeds, n_modes=6)
    assert campbell.frequencies.shape == (9, 6)
    # the disk-dominated pair splits with speed: backward falls, forward rises
    assert np.all(np.diff(campbell.frequencies[:, 2]) < 0) and np.all(
        np.diff(campbell.frequencies[:, 3]) > 0
    )
    assert set(campbell.whirl[1:, 2]) == {"backward"} and set(campbell.whirl[1:, 3]) == {"forward"}
    ax = campbell.plot(units="rpm")
    (one_x,) = [line for line in ax.get_lines() if line.get_label() == "1X"]
    assert np.allclose(one_x.get_xdata(), one_x.get_ydata())
    assert np.allclose(one_x.get_xdata(), speeds * 30 / math.pi)
    sol = duhamel.solve(
        rotor.system(SPEED, [Unbalance(2, 1e-3)]),
        duhamel.Semianalytic(),
        t_end=0.01,
        dt=1e-4,
        dofs=[8, 9],
    )
    orbit = plot_orbit(sol, rotor, node=2, scale=1e-6).get_lines()[-1]
    assert np.array_equal(orbit.get_xdata(), sol.x[:, 0] / 1e-6)
    assert np.array_equal(orbit.get_ydata(), sol.x[:, 1] / 1e-6)
    with pytest.raises(ValueError, match="does not hold dof 12"):
        plot_orbit(sol, rotor, node=3)
    import matplotlib.pyplot as plt

    plt.close("all")

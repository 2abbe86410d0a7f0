"""duhamel.rotor.from_ross against ROSS itself (PyPI ``ross-rotordynamics``, the optional extra
``duhamel[ross]``): its matrices, its ``run_time_response`` (the ``lsim`` path and the Newmark
path) and its ``run_modal``, on ROSS's example rotor (``ross.rotor_example()``: 6 Timoshenko
shaft elements, 2 disks, 2 bearings; 7 nodes, 42 ROSS dofs, 28 lateral) at 500 rad/s, on a
variant with damped, cross-coupled bearings, and on ROSS's compressor (frequency-dependent
seals, 224 lateral dofs). Tests that need ROSS are skipped when it is not installed; the
others use stand-ins with ROSS's interface. Measured numbers are printed
(``pytest -s tests/rotor/test_ross.py``).

Metric of the time responses: the largest difference over all translational dofs and all
samples, divided by the largest translation of the reference (ROSS's ``lsim`` response).
"""

from __future__ import annotations

import contextlib
import functools
import io
import warnings
from types import SimpleNamespace

import numpy as np
import pytest
import scipy.linalg

import duhamel
from duhamel.rotor import Bearing, Disk, Material, Rotor, Shaft, from_ross

SPEED = 500.0  # rad/s, as ROSS's own time-response examples
M_E = 1e-3  # kg m, unbalance at the disk of node 2
NODE = 2
REASON = "ROSS (ross-rotordynamics, the duhamel[ross] extra) is not installed"


@functools.cache
def _ross():
    with warnings.catch_warnings(), contextlib.redirect_stdout(io.StringIO()):
        warnings.simplefilter("ignore")  # ROSS's ccp dependency warns about REFPROP
        return pytest.importorskip("ross", reason=REASON)


@pytest.fixture
def ross():
    return _ross()


def quiet(fn, *args, **kwargs):
    """Call a ROSS function without its prints ("Running direct method")."""
    with contextlib.redirect_stdout(io.StringIO()):
        return fn(*args, **kwargs)


def damped_cross_coupled(ross):
    """ROSS's example rotor on bearings with cross-coupled stiffness and damping."""
    base = ross.rotor_example()
    bearings = [
        ross.BearingElement(
            n, kxx=1e6, kyy=0.8e6, kxy=2e5, kyx=-3e5, cxx=800.0, cyy=600.0, cxy=50.0, cyx=-80.0
        )
        for n in (0, 6)
    ]
    return ross.Rotor(base.shaft_elements, base.disk_elements, bearings)


def unbalance_force(ross_rotor, dofs, t):
    """ROSS's force array of the unbalance at NODE: ``m_e W^2 (cos W t, sin W t)``."""
    F = np.zeros((t.size, ross_rotor.ndof))
    F[:, dofs.ross_index[dofs(NODE, "x")]] = M_E * SPEED**2 * np.cos(SPEED * t)
    F[:, dofs.ross_index[dofs(NODE, "y")]] = M_E * SPEED**2 * np.sin(SPEED * t)
    return F


def translations(dofs):
    return np.array([i for i, s in enumerate(dofs.labels) if s.split("_")[0] in ("x", "y")])


def first_order_frequencies(M, K, C, G, speed):
    """Damped natural frequencies (Im lambda > 0, ascending) of the first-order system."""
    n = M.shape[0]
    A = np.block(
        [
            [np.zeros((n, n)), np.eye(n)],
            [-np.linalg.solve(M, K), -np.linalg.solve(M, C + speed * G)],
        ]
    )
    lam = scipy.linalg.eigvals(A)
    return np.sort(lam.imag[lam.imag > 1e-6 * np.abs(lam).max()])


def ross_lateral_frequencies(ross_rotor, dofs, speed, count):
    """ROSS's run_modal damped frequencies of the lateral modes (axial and torsional modes,
    which from_ross drops, left out by their shapes)."""
    modal = ross_rotor.run_modal(speed, num_modes=2 * count + 16)
    shapes = modal.evectors[: ross_rotor.ndof, : modal.wd.size]
    lateral = np.linalg.norm(shapes[dofs.ross_index], axis=0) / np.linalg.norm(shapes, axis=0)
    return np.asarray(modal.wd)[lateral > 0.5][:count], np.asarray(modal.wd)[lateral <= 0.5]


# ------------------------------------------------------------------------------ matrices
def test_lateral_matrices_are_ross_and_duhamel_rotor_ones(ross):
    """The System's matrices are ROSS's lateral block, ROSS's own 4-dof conversion, and what
    duhamel.rotor builds for the same geometry: so ROSS's (x, y, alpha, beta) are duhamel's
    (x, y, theta_x, theta_y) with no sign change, G included."""
    from ross.utils import convert_6dof_to_4dof

    for rr, bearing_kw in (
        (ross.rotor_example(), {"kxx": 1e6, "kyy": 0.8e6}),
        (
            damped_cross_coupled(ross),
            dict(kxx=1e6, kyy=0.8e6, kxy=2e5, kyx=-3e5, cxx=800.0, cyy=600.0, cxy=50.0, cyx=-80.0),
        ),
    ):
        model = from_ross(rr, SPEED)
        M, K, C, G = model.matrices
        keep = model.dofs.ross_index
        assert model.system.n_dof == 28 and rr.ndof == 42
        assert model.dofs.labels[:4] == ("x_0", "y_0", "alpha_0", "beta_0")
        ix = np.ix_(keep, keep)
        for mine, theirs in zip(
            (M, K, C, G), (rr.M(SPEED), rr.K(SPEED), rr.C(SPEED), rr.G()), strict=True
        ):
            np.testing.assert_array_equal(mine, theirs[ix])
        four = convert_6dof_to_4dof(rr)
        for mine, theirs in zip(
            (M, K, C, G), (four.M(SPEED), four.K(SPEED), four.C(SPEED), four.G()), strict=True
        ):
            np.testing.assert_array_equal(mine, theirs)
        # the same rotor built with duhamel.rotor from ROSS's element data
        sh = rr.shaft_elements[0]
        mat = Material(E=sh.material.E, rho=sh.material.rho, G=sh.material.G_s)
        shafts = [Shaft(s.L, s.odl, s.idl, material=mat) for s in rr.shaft_elements]
        disks = [Disk(d.n, d.m, d.Ip, d.Id) for d in rr.disk_elements]
        bearings = [Bearing(n, **bearing_kw) for n in (0, 6)]
        ours = Rotor(shafts, disks, bearings).matrices(SPEED)
        worst = max(
            float(np.abs(a - b).max() / np.abs(b).max())
            for a, b in zip((M, K, G), (ours.M, ours.K, ours.G), strict=True)
        )
        print(f"\nROSS lateral matrices vs duhamel.rotor, same geometry: {worst:.2e} (relative)")
        assert worst < 1e-13
        np.testing.assert_allclose(C, ours.C, rtol=0, atol=1e-12 * np.abs(C).max())


def test_system_structure(ross):
    """Background M, K_sym (and sym C); speed G and the skew bearing parts as couplings."""
    system, _, (M, K, C, G) = from_ross(ross.rotor_example(), SPEED)
    assert system.damping == "none" and len(system.couplings) == 1  # undamped, gyroscopic only
    np.testing.assert_array_equal(system.M, M)
    np.testing.assert_array_equal(system.K, K)  # symmetric bearings
    np.testing.assert_array_equal(system.couplings[0].C, SPEED * G)
    system0, _, _ = from_ross(ross.rotor_example(), 0.0)
    assert system0.elements == []  # at rest, symmetric bearings: a classical system
    system, _, (M, K, C, G) = from_ross(damped_cross_coupled(ross), SPEED)
    assert system.damping == "matrix"
    np.testing.assert_array_equal(system.M, M)
    np.testing.assert_array_equal(system.K, (K + K.T) / 2)
    np.testing.assert_array_equal(system.C, (C + C.T) / 2)
    gyro, skew = system.couplings
    np.testing.assert_array_equal(gyro.C, SPEED * G)
    np.testing.assert_array_equal(skew.K, (K - K.T) / 2)
    np.testing.assert_array_equal(skew.C, (C - C.T) / 2)
    sparse, _, _ = from_ross(damped_cross_coupled(ross), SPEED, sparse=True)
    assert sparse.is_sparse


def test_dof_map(ross):
    rr = ross.rotor_example()
    _, dofs, _ = from_ross(rr, SPEED)
    assert dofs.n_ross == 42 and dofs.n_dof == 28
    assert (dofs(2, "x"), dofs(2, "y"), dofs(2, "alpha"), dofs(2, "beta")) == (8, 9, 10, 11)
    assert dofs(2, "theta_x") == 10 and dofs.index(6, "theta_y") == 27
    # ROSS's own numbering of each kept dof
    for node in range(7):
        for direction in ("x", "y", "alpha", "beta"):
            ross_dof = rr.shaft_elements[min(node, 5)].dof_global_index[f"{direction}_{node}"]
            assert dofs.system_index(ross_dof) == dofs(node, direction)
    with pytest.raises(ValueError, match="axial/torsional"):
        dofs(2, "theta")
    with pytest.raises(ValueError, match="no dof"):
        dofs(9, "x")
    with pytest.raises(ValueError, match="drops"):
        dofs.system_index(2)  # z of node 0
    x = np.arange(2 * 28.0).reshape(2, 28)
    np.testing.assert_array_equal(dofs.from_ross(dofs.to_ross(x)), x)
    assert not dofs.to_ross(x)[:, [2, 5]].any()
    t = np.linspace(0.0, 1.0, 11)
    F = np.zeros((11, 42))
    F[:, 12] = 1.0  # x of node 2
    (load,) = dofs.loads(F, t)
    assert load.dof == 8
    F[:, 14] = 1.0  # z of node 2
    with pytest.raises(ValueError, match="axial or torsional"):
        dofs.loads(F, t)


# ------------------------------------------------------------------------------ time response
@pytest.mark.parametrize("variant", ["example", "damped_cross_coupled"])
def test_time_response_matches_ross_run_time_response(ross, variant):
    """Unbalance at the disk from rest, 0.1 s (8 revolutions) with dt = 25 us: duhamel's
    Semianalytic and Newmark against ROSS's run_time_response (lsim, its default path, and
    Newmark) on the same force, to plotting accuracy (metric: module docstring)."""
    rr = ross.rotor_example() if variant == "example" else damped_cross_coupled(ross)
    dt, n = 2.5e-5, 4000
    t = np.arange(n + 1) * dt
    system, dofs, _ = from_ross(rr, SPEED)
    system.add_load(dofs.unbalance(NODE, M_E, SPEED))
    F = unbalance_force(rr, dofs, t)
    lsim = dofs.from_ross(quiet(rr.run_time_response, SPEED, F, t).yout)
    newmark = dofs.from_ross(quiet(rr.run_time_response, SPEED, F, t, method="newmark").yout)
    tr = translations(dofs)
    scale = np.abs(lsim[:, tr]).max()

    def diff(a, b):
        return float(np.abs(a[:, tr] - b[:, tr]).max() / scale)

    sa = duhamel.solve(system, duhamel.Semianalytic(), t_end=t[-1], dt=dt).x
    nm = duhamel.solve(system, duhamel.Newmark(), t_end=t[-1], dt=dt).x
    # the same load as ROSS's samples, linear between them (what lsim integrates)
    tabulated, _, _ = from_ross(rr, SPEED)
    for load in dofs.loads(F, t):
        tabulated.add_load(load)
    sa_tab = duhamel.solve(tabulated, duhamel.Semianalytic(), t_end=t[-1], dt=dt).x
    got = {
        "Semianalytic vs lsim": diff(sa, lsim),
        "Semianalytic (ROSS's samples) vs lsim": diff(sa_tab, lsim),
        "Newmark vs lsim": diff(nm, lsim),
        "Newmark vs ROSS Newmark": diff(nm, newmark),
        "ROSS Newmark vs lsim": diff(newmark, lsim),
    }
    print(
        f"\n{variant} (peak {scale * 1e6:.1f} um): "
        + ", ".join(f"{k} {v:.2e}" for k, v in got.items())
    )
    # lsim interpolates the harmonic input linearly (second order): 1.3e-5 of the peak here
    assert got["Semianalytic vs lsim"] < 5e-5
    # on ROSS's own samples both are exact (the rotor in its first-order modes): round-off
    assert got["Semianalytic (ROSS's samples) vs lsim"] < 1e-8
    # both Newmark runs are second order, 0.1-0.5 % off at this step: 1 % of the peak
    assert got["Newmark vs lsim"] < 1e-2
    assert got["Newmark vs ROSS Newmark"] < 1e-2


# ------------------------------------------------------------------------------ modes
@pytest.mark.filterwarnings("ignore:File was created with ROSS")  # the compressor's file
@pytest.mark.parametrize("variant", ["example", "damped_cross_coupled", "compressor"])
def test_natural_frequencies_match_ross_run_modal(ross, variant):
    """Damped natural frequencies of the duhamel model's first-order system against ROSS's
    run_modal (its lateral modes; ROSS also lists axial and torsional ones)."""
    rr = {
        "example": ross.rotor_example,
        "damped_cross_coupled": lambda: damped_cross_coupled(ross),
        "compressor": ross.compressor_example,
    }[variant]()
    speed = SPEED if variant != "compressor" else 1000.0
    system, dofs, (M, K, C, G) = from_ross(rr, speed)
    assert system.n_dof == 4 * len(rr.nodes)
    count = 8
    ours = first_order_frequencies(M, K, C, G, speed)[:count]
    theirs, dropped = ross_lateral_frequencies(rr, dofs, speed, count)
    rel = float(np.max(np.abs(ours - theirs) / theirs))
    print(
        f"\n{variant}: {np.round(ours, 3).tolist()} rad/s, ROSS {np.round(theirs, 3).tolist()}; "
        f"relative difference {rel:.1e}; ROSS's axial/torsional modes left out: "
        f"{np.round(dropped[dropped < ours[-1]], 2).tolist()}"
    )
    assert theirs.size == count
    assert rel < 1e-8


# ------------------------------------------------------------------------------ without ROSS
def fake_rotor(M, K, C=None, G=None, names=None):
    n = M.shape[0]
    names = names or {f"{d}_0": i for i, d in enumerate(("x", "y", "z", "alpha", "beta", "theta"))}
    return SimpleNamespace(
        elements=[SimpleNamespace(dof_global_index=names)],
        M=lambda frequency=None: M,
        K=lambda frequency: K,
        C=lambda frequency: np.zeros((n, n)) if C is None else C,
        G=lambda: np.zeros((n, n)) if G is None else G,
    )


def test_refuses_what_it_cannot_map():
    M, K = np.eye(6), np.diag([1e4, 1e4, 1e3, 10.0, 10.0, 5.0])
    model = from_ross(fake_rotor(M, K), 0.0)
    assert model.dofs.labels == ("x_0", "y_0", "alpha_0", "beta_0")
    coupled = K.copy()
    coupled[0, 2] = coupled[2, 0] = 50.0  # x coupled to z
    with pytest.raises(ValueError, match="couples the lateral dofs"):
        from_ross(fake_rotor(M, coupled), 0.0)
    skew = M.copy()
    skew[0, 1] = 0.1
    with pytest.raises(ValueError, match="mass matrix is not symmetric"):
        from_ross(fake_rotor(skew, K), 0.0)
    with pytest.raises(ValueError, match="cannot map"):
        from_ross(fake_rotor(np.eye(5), np.eye(5)), 0.0)
    with pytest.raises(TypeError, match="ROSS Rotor"):
        from_ross(object(), 0.0)
    run_up = duhamel.speed.LinearRunUp(0.0, 100.0, 1.0)  # accepted since issue 29
    assert from_ross(fake_rotor(M, K), run_up).system.n_dof == 4
    with pytest.raises(ValueError, match="`frequency` is for a constant speed"):
        from_ross(fake_rotor(M, K), run_up, frequency=50.0)


def test_frequency_and_speed_reach_ross():
    """`frequency` (default: the speed) goes to M, K and C; ROSS >= 3 also gets `speed=`."""
    seen = []

    def K(frequency, speed=None):
        seen.append((frequency, speed))
        return np.diag([1e4, 1e4, 1e3, 10.0, 10.0, 5.0])

    rotor = fake_rotor(np.eye(6), None)
    rotor.K = K
    from_ross(rotor, 300.0)
    from_ross(rotor, 300.0, frequency=120.0)
    assert seen == [(300.0, 300.0), (120.0, 300.0)]


def test_unbalance_response_matches_ross_run_unbalance_response(ross):
    """duhamel's steady-state unbalance response on from_ross's matrices equals ROSS's
    ``run_unbalance_response`` at every speed and lateral dof (both solve the same complex
    systems: agreement to round-off, far below plotting accuracy)."""
    from duhamel.rotor import unbalance_response

    rotor = damped_cross_coupled(ross)
    speeds = np.linspace(0.0, 1000.0, 201)
    ref = quiet(rotor.run_unbalance_response, 2, 1e-3, 0.4, speeds).forced_resp
    model = from_ross(rotor, speed=0.0)
    res = unbalance_response(model.matrices, speeds, [(2, 1e-3, 0.4)], dof=model.dofs)
    ours = res.response.T
    theirs = ref[model.dofs.ross_index]
    err = np.abs(ours - theirs).max() / np.abs(theirs).max()
    print(f"\nunbalance response vs ROSS: {err:.1e}")
    assert err < 1e-10
    peaks = res.peaks(2)
    assert peaks and all(np.isfinite(p.amplification_factor) for p in peaks)
    same = model.unbalance_response(speeds, [(2, 1e-3, 0.4)]).response
    np.testing.assert_array_equal(same, res.response)


# ------------------------------------------------------------------------------ first-class
def ross_lateral_eigenvalues(ross_rotor, modal, dofs, count):
    """The eigenvalues (Im > 0, ascending) of the lateral modes among a ROSS run_modal's."""
    lam = np.asarray(modal.evalues)[: modal.wd.size]
    shapes = modal.evectors[: ross_rotor.ndof, : modal.wd.size]
    lateral = np.linalg.norm(shapes[dofs.ross_index], axis=0) / np.linalg.norm(shapes, axis=0)
    lam = lam[lateral > 0.5]  # run_campbell reorders them by its tracking: sort again
    return lam[np.argsort(lam.imag)][:count]


@pytest.mark.filterwarnings("ignore:File was created with ROSS")
@pytest.mark.parametrize("variant", ["example", "compressor"])
def test_modes_and_campbell_equal_ross(ross, variant):
    """A from_ross model's modes() and campbell() (the native Rotor's, on ROSS's K and C at
    each speed) against ROSS's run_modal / run_campbell eigenvalues: the compressor's seals
    and bearings are frequency-dependent, so each speed needs its own coefficients."""
    rr = ross.rotor_example() if variant == "example" else ross.compressor_example()
    model = from_ross(rr, 0.0)
    count = 6
    worst = 0.0
    speeds = np.array([0.0, 400.0, 800.0, 1200.0]) if variant == "example" else (
        np.array([420.0, 700.0, 1050.0]))  # fmt: skip
    diagram = model.campbell(speeds, n_modes=count, track=False)
    if variant == "compressor":
        campbell = quiet(rr.run_campbell, speeds, frequencies=count + 6)
        modal = [campbell.modal_results[w] for w in speeds]
    else:  # ROSS's sparse eigensolver takes 5 s per speed on it: its dense one
        modal = [quiet(rr.run_modal, w, num_modes=2 * count + 16, sparse=False) for w in speeds]
    for k, w in enumerate(speeds):
        ours = model.modes(w, n=count)
        theirs = ross_lateral_eigenvalues(rr, modal[k], model.dofs, count)
        assert theirs.size == count
        worst = max(worst, float(np.max(np.abs(ours.eigenvalues - theirs) / np.abs(theirs))))
        np.testing.assert_array_equal(diagram.frequencies[k], ours.frequencies)
        if variant == "compressor":  # ROSS's Campbell rows hold the same lateral frequencies
            row = np.sort(np.asarray(campbell.wd)[k])
            near = np.min(np.abs(row[:, None] - ours.frequencies[None, :4]), axis=0)
            worst = max(worst, float(np.max(near / ours.frequencies[:4])))
    print(f"\n{variant}: modes and Campbell vs ROSS, largest relative difference {worst:.1e}")
    assert worst < 1e-8
    if variant == "compressor":
        return  # 1 s per eigenproblem of its 448 states: the critical speeds on the example
    crit = model.critical_speeds(np.linspace(50.0, 1500.0, 30))
    assert crit.size
    for c in crit:  # a forward mode's frequency equals the speed there
        m = model.modes(c)
        fwd = [f for f, s in zip(m.frequencies, m.whirl, strict=True) if s == "forward"]
        assert np.min(np.abs(np.asarray(fwd) - c)) < 1e-9 * c


def test_frequency_response_equals_ross_run_freq_response(ross):
    """Receptances of a from_ross model (synchronous: ROSS's convention, the coefficients at
    each frequency) against ROSS's run_freq_response on every lateral dof pair."""
    rr = damped_cross_coupled(ross)
    model = from_ross(rr, 0.0)
    freqs = np.linspace(10.0, 1500.0, 120)
    ref = quiet(rr.run_freq_response, speed_range=freqs).freq_resp
    every = list(range(model.dofs.n_dof))
    frf = model.frequency_response("synchronous", freqs, every, every)
    theirs = np.moveaxis(ref[np.ix_(model.dofs.ross_index, model.dofs.ross_index)], -1, 0)
    err = float(np.abs(frf.response - theirs).max() / np.abs(theirs).max())
    print(f"\nfrequency response vs ROSS run_freq_response: {err:.1e}")
    assert err < 1e-8


# ------------------------------------------------------------------------------ run-up
def frequency_dependent(ross):
    """Three of ROSS's example shaft elements, a disk, and two bearings whose coefficients
    ROSS tabulates against frequency (ROSS interpolates them with a smoothing spline)."""
    base = ross.rotor_example()
    freq = [0.0, 200.0, 400.0, 600.0, 800.0, 1000.0]
    ramp = np.linspace(0.0, 1.0, 6)
    bearings = [
        ross.BearingElement(
            n, kxx=list(1e6 * (1 + 2 * ramp)), kyy=list(0.8e6 * (1 + 2.5 * ramp**2)),
            kxy=list(3e5 * ramp), kyx=list(-3e5 * ramp), cxx=list(500 + 300 * ramp),
            cyy=list(400 + 300 * ramp), frequency=freq,
        )
        for n in (0, 3)
    ]  # fmt: skip
    return ross.Rotor(base.shaft_elements[:3], base.disk_elements[:1], bearings)


def test_run_up_follows_ross_frequency_dependent_coefficients(ross):
    """A run-up 100 -> 900 rad/s in 12 ms of a from_ross model: the bearings follow ROSS's own
    coefficient curves (sampled, PCHIP between) against solve_ivp DOP853 on
    M x'' + (C(w) + w G) x' + K(w) x = f with ROSS's interpolants evaluated at w(t); the
    coefficients frozen at the initial speed (docs/speed.md's route) are far off."""
    rr = frequency_dependent(ross)
    law = duhamel.speed.LinearRunUp(100.0, 900.0, 0.012)
    model = from_ross(rr, law)
    dofs = model.dofs
    system = model.system
    node_y = dofs(2, "y")
    system.add_load(duhamel.loads.Tabulated(node_y, t=[0.0, 1.0], values=[-200.0, -200.0]))
    x0 = np.zeros(system.n_dof)
    x0[dofs(2, "x")] = 1e-5
    dt, t_end = 4e-6, 0.012
    sol = duhamel.solve(system, duhamel.Semianalytic(), t_end=t_end, dt=dt, x0=x0)

    M, K0, C0, G = from_ross(rr, 100.0).matrices
    nodes = [(b, dofs(b.n, "x"), dofs(b.n, "y")) for b in rr.bearing_elements]

    def coeffs(b, w, kind):
        names = [f"{kind}{a}" for a in ("xx", "xy", "yx", "yy")]
        return np.array([float(getattr(b, f"{n}_interpolated")(w)) for n in names]).reshape(2, 2)

    def KC(w):
        K, C = K0.copy(), C0.copy()
        for b, ix, iy in nodes:
            idx = np.ix_([ix, iy], [ix, iy])
            K[idx] += coeffs(b, w, "k") - coeffs(b, 100.0, "k")
            C[idx] += coeffs(b, w, "c") - coeffs(b, 100.0, "c")
        return K, C

    n = M.shape[0]
    M_inv = np.linalg.inv(M)
    f = np.zeros(n)
    f[node_y] = -200.0

    def rhs(t, s):
        w = float(law.omega(np.array([t]))[0])
        K, C = KC(w)
        x, v = s[:n], s[n:]
        return np.concatenate([v, M_inv @ (f - K @ x - (C + w * G) @ v)])

    t_eval = sol.t[::100]
    s0 = np.concatenate([x0, np.zeros(n)])
    ivp = scipy.integrate.solve_ivp(
        rhs, (0.0, t_end), s0, "DOP853", t_eval=t_eval, rtol=1e-10, atol=1e-16
    )
    ref = ivp.y[:n].T
    trans = translations(dofs)
    scale = np.abs(ref[:, trans]).max()
    err = float(np.abs(sol.x[::100][:, trans] - ref[:, trans]).max() / scale)
    frozen = from_ross(rr, 100.0).system  # coefficients of the initial speed, G at 100 rad/s
    frozen.add_load(duhamel.loads.Tabulated(node_y, t=[0.0, 1.0], values=[-200.0, -200.0]))
    stale = duhamel.solve(frozen, duhamel.Semianalytic(), t_end=t_end, dt=dt, x0=x0).x[::100]
    off = float(np.abs(stale[:, trans] - ref[:, trans]).max() / scale)
    print(
        f"\nROSS run-up, coefficients following the speed: {err:.1e} of DOP853 (frozen {off:.2f})"
    )
    assert err < 1e-6 and off > 0.05


def test_journal_swapped_in_at_a_ross_bearing_node(ross):
    """ROSS's example rotor with its two bearings swapped for short journal bearings
    (`swap_bearing`: the film force minus ROSS's bearing, which the background keeps) runs,
    and equals duhamel.rotor's own model of the same rotor on the same journals (whose
    background carries the films' linearisation instead) within the stepping error."""
    from duhamel.rotor import Gravity, ShortJournalBearing

    rr = ross.rotor_example()
    journals = [ShortJournalBearing(n, 0.05, 0.03, 1e-4, 0.03) for n in (0, 6)]
    model = from_ross(rr, SPEED)
    for j in journals:
        element = model.swap_bearing(j)
        assert element.k0 == ((1e6, 0.0), (0.0, 0.8e6))
    sh = rr.shaft_elements[0]
    mat = Material(E=sh.material.E, rho=sh.material.rho, G=sh.material.G_s)
    native = Rotor([Shaft(s.L, s.odl, s.idl, material=mat) for s in rr.shaft_elements],
                   [Disk(d.n, d.m, d.Ip, d.Id) for d in rr.disk_elements], journals)  # fmt: skip
    x_eq = native.static_equilibrium(SPEED)
    weight = Gravity().vector(native)
    for i in np.flatnonzero(weight):
        model.system.add_load(duhamel.loads.Tabulated(int(i), t=[0.0, 1.0], values=[weight[i]] * 2))
    x0 = x_eq.copy()
    x0[native.dof(2, "x")] += 5e-6  # a nudge at the disk
    errs = []
    for dt in (2e-5, 1e-5):
        kw = dict(t_end=0.02, dt=dt, x0=x0)
        ours = duhamel.solve(model.system, duhamel.Semianalytic(), **kw).x
        ref = duhamel.solve(native.system(SPEED, [Gravity()]), duhamel.Semianalytic(), **kw).x
        errs.append(float(np.abs(ours - ref).max() / np.abs(ref - x_eq).max()))
    ecc = np.hypot(ours[:, 0], ours[:, 1]).max() / 1e-4
    print(f"\njournals swapped into ROSS's rotor vs duhamel.rotor's: {errs} (dt 2e-5, 1e-5); "
          f"eccentricity {ecc:.2f}")  # fmt: skip
    assert errs[1] < 1e-2 and errs[0] / errs[1] > 3.0  # the two splits converge together
    assert 0.0 < ecc < 1.0
    with pytest.raises(ValueError, match="no bearing at node 3"):
        model.swap_bearing(ShortJournalBearing(3, 0.05, 0.03, 1e-4, 0.03))


@pytest.mark.filterwarnings("ignore:File was created with ROSS")
def test_compressor_run_up_tables_take_rosss_seals(ross):
    """The compressor's seals (negative direct stiffness at low speed) become speed tables
    whose samples are ROSS's interpolants, and whose initial coefficients the background
    carries (ROSS's K at the initial speed)."""
    rr = ross.compressor_example()
    law = duhamel.speed.LinearRunUp(100.0, 1050.0, 1.0)
    model = from_ross(rr, law)
    tables = [e for e in model.system.elements if isinstance(e, duhamel.elements.SpeedTableBearing)]
    varying = [b for b in rr.bearing_elements if np.ndim(b.frequency) == 1 and len(b.frequency) > 1]
    assert len(tables) == len(varying) > 0
    assert any(min(t.values[0]) < 0.0 for t in tables)  # kxx
    for t, b in zip(tables, varying, strict=True):
        w = np.asarray(t.speeds)
        np.testing.assert_array_equal(t.values[1], b.kxy_interpolated(w))
        assert t.k0[0][0] == pytest.approx(float(b.kxx_interpolated(100.0)), rel=1e-12)
    np.testing.assert_array_equal(model.matrices.K, from_ross(rr, 100.0).matrices.K)

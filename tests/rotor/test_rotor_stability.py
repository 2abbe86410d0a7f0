"""Level I stability (API 684 / 617) against a dense first-order eigenproblem written out here
with the cross-coupling added by hand, its threshold, the Q_A formula, and the undamped
critical speed map against the undamped eigenproblem at each stiffness."""

from __future__ import annotations

import matplotlib
import numpy as np
import pytest
import scipy.linalg

from duhamel.rotor import STEEL, Bearing, Disk, Rotor, Shaft
from duhamel.rotor.stability import Stage, anticipated_cross_coupling

matplotlib.use("Agg")
SPEED = 700.0


def rotor() -> Rotor:
    """Anisotropic damped bearings, an overhung-ish disk: elliptical, non-circular modes."""
    return Rotor(
        [Shaft(0.25, 0.05, material=STEEL)] * 5,
        [Disk(2, 30.0, 0.6, 0.3), Disk(4, 8.0, 0.1, 0.05)],
        [
            Bearing(0, 1.2e7, 8e6, kxy=3e5, kyx=-1e5, cxx=1.5e4, cyy=1.1e4),
            Bearing(5, 1e7, 9e6, cxx=1.2e4, cyy=1e4),
        ],
        rayleigh=(0.0, 2e-6),
    )


def dense_first_forward(model: Rotor, speed: float, node: int, q: float) -> float:
    """Log decrement of the lowest forward-whirling mode of ``[[0, I], [-M^-1 K_q,
    -M^-1 (C + speed G)]]`` (numpy/scipy eig), ``K_q`` = K with ``k_xy = q``, ``k_yx = -q`` at
    `node`; forward: the translational orbit area summed over the nodes is positive."""
    M, K, C, G = model.matrices(speed)
    K = K.copy()
    x, y = 4 * node, 4 * node + 1
    K[x, y] += q
    K[y, x] -= q
    n = M.shape[0]
    A = np.block(
        [
            [np.zeros((n, n)), np.eye(n)],
            [-np.linalg.solve(M, K), -np.linalg.solve(M, C + speed * G)],
        ]
    )
    lam, vec = scipy.linalg.eig(A)
    order = [k for k in np.argsort(lam.imag) if lam[k].imag > 1e-6 * np.abs(lam).max()]
    for k in order:
        X, Y = vec[0:n:4, k], vec[1:n:4, k]
        if np.sum(-np.imag(np.conj(X) * Y)) > 0.0:
            return float(-2.0 * np.pi * lam[k].real / lam[k].imag)
    raise AssertionError("no forward mode")


def test_log_decrement_curve_equals_dense_eigenproblem_and_threshold():
    model = rotor()
    qs = np.linspace(0.0, 1.5e6, 16)
    res = model.level1_stability(SPEED, location=2, q_range=qs, q_a=2e5)
    ref = np.array([dense_first_forward(model, SPEED, 2, q) for q in qs])
    err = float(np.max(np.abs(res.log_dec - ref)))
    print(f"\nLevel I log decrements vs dense eigenproblem: {err:.1e}; Q_0 = {res.threshold:.6g}")
    assert err < 1e-8
    assert res.log_dec[0] > 0.0 > res.log_dec[-1]
    q0 = res.threshold
    assert qs[0] < q0 < qs[-1]
    assert dense_first_forward(model, SPEED, 2, q0 * (1 - 1e-6)) > 0.0
    assert dense_first_forward(model, SPEED, 2, q0 * (1 + 1e-6)) < 0.0
    assert res.q_a == 2e5 and res.ratio == pytest.approx(q0 / 2e5, rel=1e-15)
    assert res.log_dec_at_q_a == pytest.approx(dense_first_forward(model, SPEED, 2, 2e5), abs=1e-8)
    assert res.requires_level2 == (q0 / 2e5 < 2.0 or res.log_dec_at_q_a < 0.1)
    ax = res.plot()
    np.testing.assert_array_equal(ax.lines[0].get_ydata(), res.log_dec)


def test_split_location_and_defaults():
    """Two nodes share q equally; without q_range: 0 .. K[x, x] of the first node; without
    q_a the ratio is NaN and Level II is not called for."""
    model = rotor()
    res = model.level1_stability(SPEED, location=[2, 3], q_range=[0.0, 4e5])
    M, K, C, G = model.matrices(SPEED)
    K[8, 9] += 2e5
    K[9, 8] -= 2e5
    K[12, 13] += 2e5
    K[13, 12] -= 2e5
    top = np.hstack([np.zeros((24, 24)), np.eye(24)])
    bottom = np.hstack([-np.linalg.solve(M, K), -np.linalg.solve(M, C + SPEED * G)])
    lam = scipy.linalg.eigvals(np.vstack([top, bottom]))
    wd = res.frequency[1]
    ours = complex(-res.log_dec[1] * wd / (2 * np.pi), wd)  # the mode at q = 4e5
    assert np.min(np.abs(lam - ours)) < 1e-8 * abs(ours)
    default = model.level1_stability(SPEED, location=2)
    assert default.q.size == 31 and default.q[-1] == model.matrices(SPEED).K[8, 8]
    assert np.isnan(default.q_a) and np.isnan(default.ratio) and not default.requires_level2


def test_anticipated_cross_coupling_formula():
    """Q_A = B T / (D H) (rho_d / rho_s), T = P / Omega: by hand for two impellers, and in
    the standards' US form (HP B C / (D H N), C = 63: klbf/in) for one."""
    stages = [Stage(1.2e6, 0.45, 0.018, 1.4), Stage(0.8e6, 0.42, 0.015, 1.9)]
    w = 1100.0
    by_hand = 3 * 1.2e6 / w / (0.45 * 0.018) * 1.4 + 3 * 0.8e6 / w / (0.42 * 0.015) * 1.9
    assert anticipated_cross_coupling(stages, w) == pytest.approx(by_hand, rel=1e-15)
    axial = anticipated_cross_coupling(stages, w, machine="axial")
    assert axial == pytest.approx(1.5 * (1.2e6 / (w * 0.45 * 0.018) + 0.8e6 / (w * 0.42 * 0.015)))
    hp, d_in, h_in, rpm = 1000.0, 16.0, 0.75, 10000.0  # the US form, klbf/in -> N/m
    us = hp * 3 * 63.0 / (d_in * h_in * rpm) * 1e3 * 4.4482216152605 / 0.0254
    si = anticipated_cross_coupling(
        [Stage(hp * 745.69987158227, d_in * 0.0254, h_in * 0.0254)], rpm * np.pi / 30
    )
    assert si == pytest.approx(us, rel=2e-3)  # C = 63 is 63025 / 1000 rounded
    with pytest.raises(ValueError, match="machine"):
        anticipated_cross_coupling(stages, w, machine="pump")
    with pytest.raises(ValueError, match="width"):
        anticipated_cross_coupling([Stage(1e6, 0.4, 0.0)], w)


def test_refuses_bad_input():
    model = rotor()
    with pytest.raises(ValueError, match="q_range"):
        model.level1_stability(SPEED, location=2, q_range=[1e5, 0.0])
    with pytest.raises(ValueError, match="location"):
        model.level1_stability(SPEED, location=[])
    with pytest.raises(ValueError):
        model.level1_stability(SPEED, location=99)


# ------------------------------------------------------------------------------ critical map
def map_rotor() -> Rotor:
    b = [Bearing(n, [5e6, 2e7], [4e6, 1.6e7], kxy=[1e5, 2e5], cxx=300.0, speeds=[0, 3000])
         for n in (0, 5)]  # fmt: skip
    return Rotor(
        [Shaft(0.25, 0.05, material=STEEL)] * 5,
        [Disk(2, 30.0, 0.6, 0.3), Disk(4, 8.0, 0.3, 0.15)],
        b,
        zeta=0.02,
    )


@pytest.mark.parametrize("gyroscopic", [True, False])
def test_critical_speed_map_equals_undamped_eigenproblem(gyroscopic):
    """At each stiffness: the undamped synchronous eigenproblem (K - w^2 (M - i G)) X = 0 by
    the general (non-Hermitian) eigensolver, the supports written out by hand."""
    model = map_rotor()
    ks = np.logspace(5, 9, 17)
    ucs = model.critical_speed_map(ks, n_modes=4, gyroscopic=gyroscopic)
    M, _, _, G = model.matrices(0.0)
    K_shaft = Rotor(model.shafts, model.disks).matrices().K  # no bearings
    ell = 0.25
    worst = 0.0
    for i, k in enumerate(ks):
        K = K_shaft.copy()
        for node in (0, 5):
            K[4 * node, 4 * node] += k
            K[4 * node + 1, 4 * node + 1] += k
        if gyroscopic:  # forward synchronous whirl: x = Re(X e^{iwt}), spin w
            lam, vec = scipy.linalg.eig(K, M - 1j * G)
            X, Y, Tx, Ty = (vec[d::4] for d in range(4))
            area = np.sum(-np.imag(np.conj(X) * Y) + ell**2 * np.imag(np.conj(Ty) * Tx), axis=0)
            ok = np.isfinite(lam) & (area > 0)
        else:  # at rest: the x-z plane
            plane = np.sort(np.r_[0:24:4, 3:24:4])
            lam = scipy.linalg.eigvals(K[np.ix_(plane, plane)], M[np.ix_(plane, plane)])
            ok = np.isfinite(lam)
        lam = lam[ok]
        w2 = np.sort(lam.real[(lam.real > 0) & (np.abs(lam.imag) < 1e-8 * np.abs(lam))])
        ref = np.sqrt(w2[:4])
        worst = max(worst, float(np.max(np.abs(ucs.critical_speeds[i] - ref) / ref)))
    print(f"\ncritical speed map (gyroscopic={gyroscopic}) vs eigenproblem: {worst:.1e}")
    assert worst < 1e-10


def test_intersections_are_critical_speeds_of_the_rotor():
    """At an intersection the bearings' own stiffness (isotropic here: kxx = kyy) gives a
    forward mode at exactly the spin speed: the critical speed of the undamped rotor with
    those bearings, by the modes at that speed."""
    b = [Bearing(n, [5e6, 2e7], [5e6, 2e7], speeds=[0, 3000]) for n in (0, 5)]
    model = Rotor([Shaft(0.25, 0.05, material=STEEL)] * 5, [Disk(2, 30.0, 0.6, 0.3)], b)
    ucs = model.critical_speed_map(np.logspace(5, 9, 21), n_modes=3)
    assert ucs.intersections
    for p in ucs.intersections:
        modes = model.modes(p.speed)
        fwd = modes.frequencies[np.array(modes.whirl) == "forward"]
        assert np.min(np.abs(fwd - p.speed)) < 1e-9 * p.speed
        assert p.stiffness == pytest.approx(b[0].stiffness_at(p.speed)[0, 0], rel=1e-15)
    ax = ucs.plot()
    np.testing.assert_array_equal(ax.lines[0].get_ydata(), ucs.critical_speeds[:, 0])
    with pytest.raises(ValueError, match="stiffnesses"):
        model.critical_speed_map([1e6, 1e5])
    with pytest.raises(ValueError, match="no bearings"):
        Rotor([Shaft(0.25, 0.05, material=STEEL)]).critical_speed_map([1e6])


def test_the_first_forward_mode_is_followed_by_its_shape():
    """The example's compressor rotor: beyond q = 1.9e6 N/m a heavily damped, nearly real
    pair becomes oscillatory below the first forward mode and is labelled forward; the
    curve stays on the original branch (its frequency moves by less than 2 % per step, the
    log decrement keeps falling), and its values are eigenvalues of the dense problem."""
    import importlib.util
    from pathlib import Path

    path = Path(__file__).resolve().parents[2] / "examples" / "rotor_analyses.py"
    spec = importlib.util.spec_from_file_location("rotor_analyses", path)
    assert spec is not None and spec.loader is not None
    ex = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ex)
    model, mcs = ex.rotor(), ex.MCS
    qs = np.linspace(0.0, 4e6, 21)
    res = model.level1_stability(mcs, location=6, q_range=qs)
    assert np.all(np.diff(res.log_dec) < 0.0)
    assert np.all(np.abs(np.diff(res.frequency)) < 0.02 * res.frequency[1:])
    late = model.level1_stability(mcs, location=6, q_range=[2e6, 2.1e6])  # no history
    assert late.frequency[0] < 0.1 * res.frequency[10]  # the lowest forward one: another
    M, K, C, G = model.matrices(mcs)
    K[24, 25] += 2e6
    K[25, 24] -= 2e6
    n = M.shape[0]
    top = np.hstack([np.zeros((n, n)), np.eye(n)])
    lam = scipy.linalg.eigvals(
        np.vstack([top, np.hstack([-np.linalg.solve(M, K), -np.linalg.solve(M, C + mcs * G)])])
    )
    wd = res.frequency[10]
    ours = complex(-res.log_dec[10] * wd / (2 * np.pi), wd)
    assert np.min(np.abs(lam - ours)) < 1e-8 * abs(ours)

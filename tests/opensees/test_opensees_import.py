"""duhamel.opensees.from_opensees against OpenSees itself, on frames built in openseespy:
a 2-D frame (examples/opensees_frame.py: equalDOF floors, Steel01 isolators, a flat slider)
and a 3-D frame (rigid diaphragms, Steel01 isolators in both directions, flat sliders).

* natural periods equal OpenSees' ``eigen`` (full generalized LAPACK) to 1e-8;
* the linear response to a record equals OpenSees' Newmark converged run (two step sizes,
  Richardson-extrapolated: Newmark is second order) to 1e-4 of the peak;
* the nonlinear response (after a gravity analysis) is within 0.5 % of OpenSees at a step
  where OpenSees has converged (its runs at two step sizes agree to far better than that).
"""

from __future__ import annotations

import importlib.util
import warnings
from pathlib import Path

import numpy as np
import pytest

import duhamel

try:  # the wheel needs the system BLAS/LAPACK (libblas3, liblapack3)
    import openseespy.opensees as ops
except Exception as exc:  # pragma: no cover - depends on the machine
    pytest.skip(reason=f"openseespy cannot be loaded: {exc}", allow_module_level=True)

ROOT = Path(__file__).resolve().parents[2]
_spec = importlib.util.spec_from_file_location(
    "opensees_frame", ROOT / "examples" / "opensees_frame.py"
)
assert _spec is not None and _spec.loader is not None
frame2d = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(frame2d)

G = 9.81
# the 3-D frame: 3 x 2 column lines, 2 storeys, rigid diaphragms, isolated or fixed
BX, BY, H3, ST3 = 6.0, 5.0, 3.0, 2
M3, M3_BASE, ROT = 1.5e4, 8.0e3, 0.0


def _n3(level: int, ix: int, iy: int) -> int:
    return 1000 * (level + 1) + 10 * ix + iy


def build_3d(*, isolated: bool, gravity: bool = True) -> None:
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    grid = [(ix, iy) for ix in range(3) for iy in range(2)]
    for level in range(ST3 + 1):
        for ix, iy in grid:
            n = _n3(level, ix, iy)
            ops.node(n, ix * BX, iy * BY, level * H3)
            m = M3_BASE if level == 0 else M3
            ops.mass(n, *((m, m, m) if level == 0 else (0.0, 0.0, m)), ROT, ROT, ROT)
            if level == 0 and not isolated:
                ops.fix(n, 1, 1, 1, 1, 1, 1)
            if level == 0 and isolated:
                ops.node(n - 1000 + 900, ix * BX, iy * BY, 0.0)
                ops.fix(n - 1000 + 900, 1, 1, 1, 1, 1, 1)
        if level > 0:  # the floor's master node at its centre, with the floor's mass
            master = 1000 * (level + 1) + 999
            ops.node(master, BX, BY / 2, level * H3)
            ops.fix(master, 0, 0, 1, 1, 1, 0)
            r2 = sum((ix * BX - BX) ** 2 + (iy * BY - BY / 2) ** 2 for ix, iy in grid)
            ops.mass(master, 6 * M3, 6 * M3, 0.0, 0.0, 0.0, M3 * r2)
            ops.rigidDiaphragm(3, master, *[_n3(level, ix, iy) for ix, iy in grid])
    ops.geomTransf("Linear", 1, 1.0, 0.0, 0.0)  # columns
    ops.geomTransf("Linear", 2, 0.0, 0.0, 1.0)  # beams
    E, Gs, A, J, Iy, Iz = 2e11, 8e10, 1e-2, 2e-4, 2e-4, 3e-4
    tag = 1
    for level in range(ST3):
        for ix, iy in grid:
            ops.element(
                "elasticBeamColumn",
                tag,
                _n3(level, ix, iy),
                _n3(level + 1, ix, iy),
                A,
                E,
                Gs,
                J,
                Iy,
                Iz,
                1,
            )
            tag += 1
    for level in range(0 if isolated else 1, ST3 + 1):
        for ix, iy in grid:
            for jx, jy in ((ix + 1, iy), (ix, iy + 1)):
                if (jx, jy) in grid:
                    ops.element(
                        "elasticBeamColumn",
                        tag,
                        _n3(level, ix, iy),
                        _n3(level, jx, jy),
                        A,
                        E,
                        Gs,
                        J,
                        Iy,
                        Iz,
                        2,
                    )
                    tag += 1
    ops.rayleigh(0.3, 0.002, 0.0, 0.0)
    if isolated:
        ops.uniaxialMaterial("Elastic", 900, 1e11)
        w = (M3_BASE + ST3 * M3) * G
        ops.uniaxialMaterial("Steel01", 901, 0.05 * w, 0.05 * w / 0.002, 0.1)
        ops.frictionModel("Coulomb", 1, 0.06)
        for ix, iy in grid:
            n = _n3(0, ix, iy)
            if ix == 1:  # sliders under the middle line
                ops.element(
                    "flatSliderBearing",
                    900 + n,
                    n - 100,
                    n,
                    1,
                    4e7,
                    "-P",
                    900,
                    "-T",
                    900,
                    "-My",
                    900,
                    "-Mz",
                    900,
                    "-orient",
                    0,
                    0,
                    1,
                    1,
                    0,
                    0,
                )
            else:
                ops.element(
                    "zeroLength",
                    900 + n,
                    n - 100,
                    n,
                    "-mat",
                    901,
                    901,
                    900,
                    900,
                    900,
                    900,
                    "-dir",
                    1,
                    2,
                    3,
                    4,
                    5,
                    6,
                )
    if gravity:
        ops.timeSeries("Constant", 1)
        ops.pattern("Plain", 1, 1)
        for level in range(ST3 + 1):
            for ix, iy in grid:
                ops.load(_n3(level, ix, iy), 0, 0, -(M3_BASE if level == 0 else M3) * G, 0, 0, 0)
        ops.constraints("Transformation")
        ops.numberer("RCM")
        ops.system("BandGeneral")
        ops.test("NormDispIncr", 1e-12, 20)
        ops.algorithm("Newton")
        ops.integrator("LoadControl", 1.0)
        ops.analysis("Static")
        assert ops.analyze(1) == 0
        ops.loadConst("-time", 0.0)
        ops.wipeAnalysis()


def run_3d(t, ax, ay, substeps, watch):
    dt = float(t[1] - t[0])
    for k, (a, d) in enumerate(((ax, 1), (ay, 2))):
        ops.timeSeries("Path", 10 + k, "-dt", dt, "-values", *a.tolist())
        ops.pattern("UniformExcitation", 10 + k, d, "-accel", 10 + k)
    ops.constraints("Transformation")
    ops.numberer("RCM")
    ops.system("BandGeneral")
    ops.test("NormDispIncr", 1e-12, 50)
    ops.algorithm("Newton")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")
    out = np.zeros((t.size, len(watch)))
    for k in range(1, t.size):
        assert ops.analyze(substeps, dt / substeps) == 0
        out[k] = [ops.nodeDisp(n, d) for n, d in watch]
    return out


def eigen_periods(n: int) -> np.ndarray:
    with warnings.catch_warnings():
        lam = np.array(ops.eigen("-fullGenLapack", n))
    return 2 * np.pi / np.sqrt(lam)


def background_periods(system: duhamel.System) -> np.ndarray:
    """The periods of K plus the translated elements' initial stiffness (what OpenSees'
    tangent holds), from scipy, independent of duhamel's modal code."""
    import scipy.linalg

    K = np.array(system.K, dtype=float)
    for e in system.elements:
        dofs, k0 = e._linear()
        if isinstance(e, duhamel.elements.FrictionPendulum):  # and its pre-sliding stiffness
            k_init = e.mu * e.weight / e.yield_displacement
            if len(e.dofs) == 3:  # with its vertical dof: kInit in shear (N / R and the
                # friction's k_i - N / R), its axial stiffness
                k0 = np.diag([k_init] * (len(dofs) - 1) + [e.vertical_stiffness])
            else:
                k0 = k0 + k_init * np.eye(len(dofs))
        K[np.ix_(dofs, dofs)] += k0
    M = np.array(system.M, dtype=float)
    m = np.flatnonzero(np.diag(M) > 0)  # the massless rotations condensed by hand
    s = np.flatnonzero(np.diag(M) == 0)
    Kc = K[np.ix_(m, m)] - K[np.ix_(m, s)] @ np.linalg.solve(K[np.ix_(s, s)], K[np.ix_(s, m)])
    lam = scipy.linalg.eigh(Kc, M[np.ix_(m, m)], eigvals_only=True)
    return 2 * np.pi / np.sqrt(lam)


def rel_err(ours: np.ndarray, ref: np.ndarray) -> float:
    return float(np.abs(ours - ref).max() / np.abs(ref).max())


# ------------------------------------------------------------------ structure of the import
def test_2d_labels_constraints_and_translated_elements() -> None:
    frame2d.build(isolated=True, gravity=True)
    s = duhamel.opensees.from_opensees()
    base, mid, right = (frame2d.node_tag(0, k) for k in range(3))
    # equalDOF: the floor's nodes share one ux; their own uy and rz are dofs
    assert s.dof(right, "ux") == s.dof(base, "ux") == s.dof((mid, "ux"))
    assert s.dof(right, "uy") != s.dof(base, "uy")
    assert len(s.dof_labels) == s.n_dof == 4 * (1 + 3 * 2)  # 4 levels: ux + 3 x (uy, rz)
    rotations = [s.dof(frame2d.node_tag(k, line), "rz") for k in range(4) for line in range(3)]
    if frame2d.ROT_INERTIA == 0.0:  # massless rotations, condensed by duhamel
        assert sorted(s.massless_dofs.tolist()) == sorted(rotations)
    with pytest.raises(ValueError, match="fixed in OpenSees"):
        s.dof(frame2d.ground_tag(0), "ux")
    # the isolators: Steel01 -> Bilinear (E, fy, b); the flat slider -> a FrictionPendulum
    # with its vertical dof (kInit = mu N / Y, the axial force at import as its initial one)
    (b0,) = s.opensees.elements[900]
    w = (frame2d.M_BASE + frame2d.STOREYS * frame2d.M_NODE) * frame2d.G
    assert (b0.i, b0.j) == (s.dof(base, "ux"), None)
    assert b0.k == pytest.approx(0.04 * w / 0.002, rel=1e-15) and b0.alpha == frame2d.ALPHA_ISO
    (slider,) = s.opensees.elements[950]
    n_axial = -ops.eleResponse(950, "basicForce")[0]
    assert slider.dofs == (s.dof(mid, "ux"), None, s.dof(mid, "uy"))
    assert slider.initial_axial_force == n_axial and slider.mu == frame2d.MU
    assert slider.mu * slider.weight / slider.yield_displacement == pytest.approx(
        frame2d.K_SLIDER, rel=1e-12
    )
    # the middle column carries its tributary weight (independent check of N)
    assert n_axial == pytest.approx(w, rel=0.05)
    # the displaced state after gravity, and C from the frame's Rayleigh damping
    assert s.opensees.x0[s.dof(base, "uy")] < 0 and s.damping == "matrix"


def test_refused_and_linearized_elements() -> None:
    ops.wipe()
    ops.model("basic", "-ndm", 1, "-ndf", 1)
    ops.node(1, 0.0)
    ops.node(2, 0.0)
    ops.fix(1, 1)
    ops.mass(2, 1.0)
    ops.uniaxialMaterial("Concrete01", 1, -1.0, -0.02, -0.5, -0.06)  # no duhamel counterpart
    ops.element("zeroLength", 7, 1, 2, "-mat", 1, "-dir", 1)
    with pytest.raises(ValueError, match=r"element 7 \(ZeroLength\).*Concrete01"):
        duhamel.opensees.from_opensees()
    with pytest.warns(UserWarning, match="element 7"):
        s = duhamel.opensees.from_opensees(nonlinear="linearize")
    assert s.elements == [] and s.opensees.linearized == {7: "ZeroLength"}
    assert s.K[0, 0] == pytest.approx(100.0)  # its initial stiffness 2 * 1.0 / 0.02
    with pytest.raises(ValueError, match="`nonlinear`"):
        duhamel.opensees.from_opensees(nonlinear="ignore")


def test_rigid_diaphragm_slaves_are_recovered() -> None:
    build_3d(isolated=False, gravity=False)
    s = duhamel.opensees.from_opensees()
    master = 2999
    slave = _n3(1, 0, 0)
    with pytest.raises(ValueError, match="rigid diaphragm"):
        s.dof(slave, "ux")
    x = np.zeros((1, s.n_dof))
    x[0, s.dof(master, "ux")] = 1.0
    x[0, s.dof(master, "rz")] = 0.01
    # ux_slave = ux_master - (y_slave - y_master) rz
    assert s.opensees.node_response(x, slave, "ux")[0] == pytest.approx(1.0 + 0.01 * BY / 2)
    assert s.opensees.node_response(x, slave, "uy")[0] == pytest.approx(-0.01 * BX)


# ------------------------------------------------------------------ periods
@pytest.mark.parametrize("isolated", [False, True])
def test_2d_periods_equal_opensees_eigen(isolated: bool) -> None:
    frame2d.build(isolated=isolated, gravity=isolated)
    s = duhamel.opensees.from_opensees()
    ref = eigen_periods(6)
    ours = background_periods(s)[:6] if isolated else 2 * np.pi / s.modal().omega[:6]
    np.testing.assert_allclose(ours, ref, rtol=1e-8)
    # System.modal(elements="initial") is that: the bearings' initial stiffness
    basis = s.modal(6, elements="initial")
    np.testing.assert_allclose(2 * np.pi / basis.omega, ref, rtol=1e-8)
    if isolated:
        assert basis.summary().startswith("modes of K + the force elements' initial")
        assert s.modal(6).summary().startswith("modes of K alone")


def test_pdelta_tangent_after_gravity_carries_the_geometric_stiffness() -> None:
    """With PDelta transformations, the stiffness imported after gravity is the tangent:
    its periods equal OpenSees' eigen at that state, longer than without P-Delta."""
    frame2d.build(isolated=False, gravity=True, transformation="PDelta")
    s = duhamel.opensees.from_opensees()
    ref = eigen_periods(3)
    ours = 2 * np.pi / s.modal().omega[:3]
    np.testing.assert_allclose(ours, ref, rtol=1e-8)
    frame2d.build(isolated=False, gravity=True)
    linear = 2 * np.pi / duhamel.opensees.from_opensees().modal().omega[:3]
    assert ours[0] > linear[0] * 1.003  # measured 0.67 % longer


@pytest.mark.parametrize("isolated", [False, True])
def test_3d_periods_equal_opensees_eigen(isolated: bool) -> None:
    build_3d(isolated=isolated, gravity=isolated)
    s = duhamel.opensees.from_opensees()
    ref = eigen_periods(6)
    ours = background_periods(s)[:6] if isolated else 2 * np.pi / s.modal().omega[:6]
    np.testing.assert_allclose(ours, ref, rtol=1e-8)
    np.testing.assert_allclose(2 * np.pi / s.modal(6, elements="initial").omega, ref, rtol=1e-8)


# ------------------------------------------------------------------ linear response
def _richardson(coarse: np.ndarray, fine: np.ndarray) -> np.ndarray:
    return (4.0 * fine - coarse) / 3.0  # Newmark (average acceleration) is second order


def test_2d_linear_response_equals_opensees_newmark() -> None:
    t, a = frame2d.record(duration=4.0)
    frame2d.build(isolated=False, gravity=False)
    s = duhamel.opensees.from_opensees()
    s.add_load(duhamel.loads.BaseAcceleration("ux", t=t, values=a))
    roof, mid = frame2d.node_tag(frame2d.STOREYS, 0), frame2d.node_tag(1, 1)
    sol = duhamel.solve(
        s, duhamel.Semianalytic(), t_end=float(t[-1]), dt=0.01, dofs=[(roof, "ux"), (mid, "rz")]
    )
    watch = [(roof, 1), (mid, 3)]
    runs = []
    for n in (5, 10):
        frame2d.build(isolated=False, gravity=False)
        runs.append(frame2d.run_opensees(t, a, n, watch))
    ref = _richardson(*runs)
    assert rel_err(runs[1], ref) < 1e-2  # the fine run alone: far from 1e-4
    for k in range(2):
        assert rel_err(sol.x[:, k], ref[:, k]) < 1e-4
    assert list(sol.to_xarray().coords["label"].values) == [f"{roof}:ux", f"{mid}:rz"]


def test_3d_linear_response_equals_opensees_newmark() -> None:
    t, a = frame2d.record(duration=3.0)
    build_3d(isolated=False, gravity=False)
    s = duhamel.opensees.from_opensees()
    s.add_load(duhamel.loads.BaseAcceleration("ux", t=t, values=a))
    s.add_load(duhamel.loads.BaseAcceleration("uy", t=t, values=0.5 * a * np.cos(2.0 * t)))
    roof = 3999
    sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=float(t[-1]), dt=0.01)
    ours = sol.x[:, [s.dof(roof, "ux"), s.dof(roof, "uy"), s.dof(roof, "rz")]]
    runs = []
    for n in (5, 10):
        build_3d(isolated=False, gravity=False)
        runs.append(run_3d(t, a, 0.5 * a * np.cos(2.0 * t), n, [(roof, 1), (roof, 2), (roof, 6)]))
    ref = _richardson(*runs)
    for k in range(2):
        assert rel_err(ours[:, k], ref[:, k]) < 1e-4


# ------------------------------------------------------------------ nonlinear response
def test_2d_isolated_nonlinear_response_within_half_percent() -> None:
    t, a = frame2d.record(duration=6.0)
    frame2d.build(isolated=True, gravity=True)
    s = duhamel.opensees.from_opensees()
    s.add_load(duhamel.loads.BaseAcceleration("ux", t=t, values=a))
    base, roof = frame2d.node_tag(0, 0), frame2d.node_tag(frame2d.STOREYS, 0)
    sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=float(t[-1]), dt=0.005, save_every=2)
    ours = sol.x[:, [s.dof(base, "ux"), s.dof(roof, "ux")]]
    runs = []
    for n in (10, 20):
        frame2d.build(isolated=True, gravity=True)
        runs.append(frame2d.run_opensees(t, a, n, [(base, 1), (roof, 1)]))
    assert rel_err(runs[0], runs[1]) < 1e-3  # OpenSees converged well below 0.5 %
    assert np.abs(ours[:, 0]).max() > 0.05  # the isolators yield (0.002 m) many times over
    for k in range(2):
        assert rel_err(ours[:, k], runs[1][:, k]) < 5e-3


def test_3d_isolated_nonlinear_response_within_half_percent() -> None:
    t, a = frame2d.record(duration=3.0)
    ay = 0.4 * a * np.cos(2.0 * t)  # starts at rest, as OpenSees assumes
    build_3d(isolated=True, gravity=True)
    s = duhamel.opensees.from_opensees()
    kinds = {type(e[0]).__name__ for e in s.opensees.elements.values()}
    assert kinds == {"Bilinear", "FrictionPendulum"}
    s.add_load(duhamel.loads.BaseAcceleration("ux", t=t, values=a))
    s.add_load(duhamel.loads.BaseAcceleration("uy", t=t, values=ay))
    base, roof = _n3(0, 1, 0), 3999
    sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=float(t[-1]), dt=0.005, save_every=2)
    ours = sol.x[:, [s.dof(base, "ux"), s.dof(base, "uy"), s.dof(roof, "ux")]]
    runs = []
    for n in (4, 8):  # about 5 ms a step in OpenSees
        build_3d(isolated=True, gravity=True)
        runs.append(run_3d(t, a, ay, n, [(base, 1), (base, 2), (roof, 1)]))
    assert rel_err(runs[0], runs[1]) < 1e-3
    assert np.abs(ours[:, 0]).max() > 0.02  # the isolators yield (0.002 m) many times over
    for k in range(3):
        assert rel_err(ours[:, k], runs[1][:, k]) < 5e-3


@pytest.mark.parametrize(
    ("ndm", "bearing"), [(2, "singleFPBearing"), (3, "singleFPBearing"), (3, "flatSliderBearing")]
)
def test_friction_bearings_against_opensees(ndm: int, bearing: str) -> None:
    """A mass on one friction bearing (single friction pendulum, R = 2 m; or flat), after
    gravity, under a record (both horizontal directions in 3-D): within 0.5 % of OpenSees.

    duhamel's pendulum keeps the normal force N = W; OpenSees' adds ``V u / R`` (the slope of
    the dish), so the two idealisations part like ``(u/R) (mu + u/R)``: measured 0.2 % at
    u/R = 0.04 (this record at 2 m/s^2), 0.7 % at u/R = 0.09 (at 4 m/s^2). The pendulums are
    compared at the former; the flat slider, without that term, at the latter."""
    pga = 2.0 if bearing == "singleFPBearing" else 4.0
    t, a = frame2d.record(duration=4.0, pga=pga)
    ay = 0.6 * a * np.cos(1.5 * t)
    m, mu, radius, k_init = 2e4, 0.06, 2.0, 2e7

    def build() -> None:
        ops.wipe()
        ops.model("basic", "-ndm", ndm, "-ndf", 3 if ndm == 2 else 6)
        zero = [0.0] * ndm
        ops.node(1, *zero)
        ops.node(2, *zero)
        if ndm == 2:
            ops.fix(1, 1, 1, 1)
            ops.fix(2, 0, 0, 1)
            ops.mass(2, m, m, 0.0)
        else:
            ops.fix(1, 1, 1, 1, 1, 1, 1)
            ops.fix(2, 0, 0, 0, 1, 1, 1)
            ops.mass(2, m, m, m, 0.0, 0.0, 0.0)
        ops.uniaxialMaterial("Elastic", 1, 1e10)
        ops.frictionModel("Coulomb", 1, mu)
        geometry = [radius] if bearing == "singleFPBearing" else []
        if ndm == 2:
            mats, orient = ["-P", 1, "-Mz", 1], [0, 1, 0, -1, 0, 0]
        else:
            mats, orient = ["-P", 1, "-T", 1, "-My", 1, "-Mz", 1], [0, 0, 1, 1, 0, 0]
        ops.element(
            bearing, 5, 1, 2, 1, *geometry, k_init, *mats, "-orient", *orient, "-iter", 50, 1e-8
        )
        ops.timeSeries("Constant", 1)
        ops.pattern("Plain", 1, 1)
        ops.load(2, *([0.0, -m * G, 0.0] if ndm == 2 else [0.0, 0.0, -m * G, 0, 0, 0]))
        ops.constraints("Transformation")
        ops.numberer("Plain")
        ops.system("FullGeneral")
        ops.test("NormDispIncr", 1e-12, 20)
        ops.algorithm("Newton")
        ops.integrator("LoadControl", 1.0)
        ops.analysis("Static")
        assert ops.analyze(1) == 0
        ops.loadConst("-time", 0.0)
        ops.wipeAnalysis()

    build()
    s = duhamel.opensees.from_opensees()
    (element,) = s.opensees.elements[5]
    assert type(element).__name__ == "FrictionPendulum" and len(element.dofs) == 3
    s.add_load(duhamel.loads.BaseAcceleration("ux", t=t, values=a))
    if ndm == 3:
        s.add_load(duhamel.loads.BaseAcceleration("uy", t=t, values=ay))
    sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=float(t[-1]), dt=0.0025, save_every=4)
    comps = ["ux"] if ndm == 2 else ["ux", "uy"]
    ours = sol.x[:, [s.dof(2, c) for c in comps]]
    watch = [(2, 1 + k) for k in range(len(comps))]
    runs = []
    for n in (8, 16):
        build()
        runs.append(
            run_3d(t, a, ay, n, watch) if ndm == 3 else frame2d.run_opensees(t, a, n, watch)
        )
    # the finer run's own error is at most their difference (an order >= 1 in the step)
    assert rel_err(runs[0], runs[1]) < 2e-3
    assert np.abs(ours[:, 0]).max() > 0.02  # slides well beyond mu W / kInit = 0.06 mm
    for k in range(len(comps)):
        assert rel_err(ours[:, k], runs[1][:, k]) < 5e-3


def _sdof(mat: list, *, mass: float = 1e3) -> None:
    """A mass on a zeroLength element of material `mat` (1-D model), nothing else."""
    ops.wipe()
    ops.model("basic", "-ndm", 1, "-ndf", 1)
    ops.node(1, 0.0)
    ops.node(2, 0.0)
    ops.fix(1, 1)
    ops.mass(2, mass)
    ops.uniaxialMaterial(*mat)
    ops.element("zeroLength", 1, 1, 2, "-mat", mat[1], "-dir", 1)


def test_bouc_wen_against_opensees() -> None:
    """OpenSees' BoucWen (z in displacement units) as duhamel's (z in units of fy / k): the
    response of a mass on it within 0.5 % of OpenSees (whose z update converges at first
    order: its runs at 16 and 32 steps per interval agree to 1e-3)."""
    t, a = frame2d.record(duration=4.0, pga=3.0)
    mat = ["BoucWen", 1, 0.1, 4e5, 1.0, 0.4, 0.6, 1.0, 0.0, 0.0, 0.0]  # alpha ko n gamma beta
    _sdof(mat)
    s = duhamel.opensees.from_opensees()
    (bw,) = s.opensees.elements[1]
    assert (bw.k, bw.alpha, bw.n) == (4e5, 0.1, 1.0)
    assert (bw.beta, bw.gamma) == pytest.approx((0.6, 0.4)) and bw.fy == pytest.approx(4e5)
    assert s.K[0, 0] == pytest.approx(0.0, abs=1e-6)  # its tangent taken out of K
    s.add_load(duhamel.loads.BaseAcceleration("ux", t=t, values=a))
    ours = duhamel.solve(s, duhamel.Semianalytic(), t_end=float(t[-1]), dt=0.0025, save_every=4)
    runs = []
    for n in (16, 32):
        _sdof(mat)
        runs.append(frame2d.run_opensees(t, a, n, [(2, 1)]))
    assert rel_err(runs[0], runs[1]) < 1e-3
    assert np.abs(ours.x).max() > 5.0 / 4e5 * 10  # well into the hysteretic range
    assert rel_err(ours.x, runs[1]) < 5e-3


def test_gap_damper_and_elastic_materials_translated() -> None:
    _sdof(["ENT", 1, 2e6])
    (gap,) = duhamel.opensees.from_opensees().opensees.elements[1]
    # contact when OpenSees' strain x2 - x1 < 0, i.e. duhamel's x_i - x_j < -gap
    assert (gap.i, gap.j, gap.gap, gap.k) == (0, None, 0.0, 2e6)
    _sdof(["ElasticPPGap", 1, 3e6, -1e30, -0.02])
    (gap,) = duhamel.opensees.from_opensees().opensees.elements[1]
    assert (gap.i, gap.j, gap.gap, gap.k) == (0, None, 0.02, 3e6)
    _sdof(["ElasticPPGap", 1, 3e6, -1e4, -0.02])  # it yields: no counterpart
    with pytest.raises(ValueError, match="yields"):
        duhamel.opensees.from_opensees()
    _sdof(["Elastic", 1, 5e5, 300.0])  # linear: in K, its eta in C
    s = duhamel.opensees.from_opensees()
    assert s.elements == [] and (s.K[0, 0], s.C[0, 0]) == (5e5, 300.0)
    _sdof(["ViscousDamper", 1, 1e9, 2e4, 0.35])  # in series with its brace K (issue 27)
    s = duhamel.opensees.from_opensees()
    (damper,) = s.opensees.elements[1]
    assert (damper.c, damper.exponent, damper.brace_stiffness) == (2e4, 0.35, 1e9)
    assert s.K[0, 0] == pytest.approx(0.0)
    _sdof(["ViscousDamper", 1, 1e9, 2e4, 0.35, 0.01])  # a gap at the pins: no counterpart
    with pytest.raises(ValueError, match="LGap"):
        duhamel.opensees.from_opensees()
    _sdof(["Steel01", 1, 1e4, 1e6, 0.05, 0.01, 1.0, 0.0, 1.0])  # isotropic hardening
    with pytest.raises(ValueError, match="isotropic hardening"):
        duhamel.opensees.from_opensees()

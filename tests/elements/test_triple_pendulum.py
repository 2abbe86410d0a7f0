"""The triple friction pendulum (issue 27): Fenz & Constantinou's regimes under a slow
cyclic displacement (closed forms), OpenSees ``TripleFrictionPendulum`` on a rigid mass
under a record (uniaxial and bidirectional), convergence with dt and the checked input."""

from __future__ import annotations

import os
import tempfile

import numpy as np
import pytest

import duhamel
from duhamel import elements as E
from duhamel import loads as L

G = 9.81
MU, RADIUS, CAPACITY = (0.02, 0.06, 0.10), (0.3, 2.0, 2.5), (0.05, 0.3, 0.35)
DT = 0.005


def bearing(*dofs: int | None, weight: float = 1.0, uy: float = 5e-4) -> E.Element:
    return E.TripleFrictionPendulum(
        dofs,
        mu=MU,
        radius=RADIUS,
        displacement_capacity=CAPACITY,
        weight=weight,
        yield_displacement=uy,
    )


def series_curve(uy: float) -> list[tuple[float, float]]:
    """The virgin curve ``(u, F / W)`` at its breaks, from the series model's parameters
    (OpenSees: every element's elastic stiffness ``E = 3 mu1 / uy``, sliding stiffnesses
    ``1 / (2 L1)``, ``1 / (L2 - L1)``, ``1 / (L3 - L1)``, stops at ``2 (d1 + d3 L1 / L3)``,
    ``d2 (1 - L1 / L2)``, ``d3 (1 - L1 / L3)`` with stiffness ``E``). An element yields at
    ``mu`` and reaches its stop at ``F = Ep gap + mu (1 - Ep / E)``."""
    (m1, m2, m3), (l1, l2, l3), (d1, d2, d3) = MU, RADIUS, CAPACITY
    e = 3 * m1 / uy
    ep = [1 / (2 * l1), 1 / (l2 - l1), 1 / (l3 - l1)]
    gap = [2 * (d1 + d3 * l1 / l3), d2 * (1 - l1 / l2), d3 * (1 - l1 / l3)]
    stop = [ep[i] * gap[i] + (m1, m2, m3)[i] * (1 - ep[i] / e) for i in range(3)]
    c = [1 / k for k in ep]
    g = [1 / (k + e) for k in ep]
    stages = [  # (force at the stage's end, compliance during it)
        (m1, 3 / e),
        (m2, c[0] + 2 / e),
        (m3, c[0] + c[1] + 1 / e),
        (stop[1], c[0] + c[1] + c[2]),
        (stop[2], c[0] + g[1] + c[2]),
        (stop[0], c[0] + g[1] + g[2]),
        (1e3, g[0] + g[1] + g[2]),
    ]
    points = [(0.0, 0.0)]
    for f, comp in stages:
        u0, f0 = points[-1]
        points.append((u0 + comp * (f - f0), f))
    return points


def driven(u: np.ndarray, t: np.ndarray, uy: float) -> tuple[np.ndarray, np.ndarray]:
    """The bearing (W = 1) on a massless dof pulled through a stiff spring ``kd`` to the
    displacement history `u`: a quasi-static path, ``kd x + F(x) = kd u`` solved at each
    instant (Newmark's Newton iteration on the massless dof). Returns the bearing's
    displacement and force histories."""
    kd = 1e3 * MU[0] / uy
    s = duhamel.System(np.diag([0.0, 1.0]), np.diag([kd, 1.0])).add(bearing(0, uy=uy))
    s.add_load(L.Tabulated(0, t=t, values=kd * u, hold=True))
    sol = duhamel.solve(s, duhamel.Newmark(tol=1e-14), t_end=t[-1], dt=t[1] - t[0])
    x = sol.x[:, 0]
    return x, kd * (u - x)


def test_slow_cycles_pass_the_five_regimes() -> None:
    t = np.linspace(0.0, 1.0, 4001)
    u = 0.78 * np.sin(1.5 * np.pi * t)  # to 0.78 (regime V, the inner stop), back to -0.78
    x, f = driven(u, t, uy=1e-4)
    breaks = series_curve(1e-4)
    bu, bf = np.array(breaks).T
    up = t <= 1 / 3
    np.testing.assert_allclose(f[up], np.interp(x[up], bu, bf), rtol=0, atol=1e-10)
    # the way back from the largest excursion, within the gaps' reach of the far side, is
    # no Masing branch (the stops are elastic); the loading to -0.78 mirrors the virgin curve
    far = (t > 0.9) & (x < -0.2)
    np.testing.assert_allclose(-f[far], np.interp(-x[far], bu, bf), rtol=1e-10, atol=1e-10)
    # Fenz & Constantinou's rigid-plastic forces and stiffnesses (uy -> 0, to O(uy / L))
    rigid = series_curve(1e-7)
    (m1, m2, m3), (l1, l2, l3), (_, d2, d3) = MU, RADIUS, CAPACITY
    forces = [m1, m2, m3, m2 + d2 / l2, m3 + d3 / l3]
    stiffness = [1 / (2 * l1), 1 / (l1 + l2), 1 / (l2 + l3), 1 / (l1 + l3), 1 / (2 * l1)]
    for k in range(5):
        (u0, f0), (u1, f1) = rigid[k + 1], rigid[k + 2]
        assert f0 == pytest.approx(forces[k], rel=1e-4)
        assert (f1 - f0) / (u1 - u0) == pytest.approx(stiffness[k], rel=1e-4)


def test_a_cycle_before_the_stops_is_masing() -> None:
    # amplitude in regime III: the return branch is the virgin curve doubled (kinematic
    # hardening in every element), transitions at force drops 2 mu1, 2 mu2, 2 mu3
    t = np.linspace(0.0, 1.0, 4001)
    amp = 0.3
    u = amp * np.sin(1.5 * np.pi * t)
    x, f = driven(u, t, uy=1e-4)
    bu, bf = np.array(series_curve(1e-4)).T
    assert bu[3] < amp < bu[4]  # in regime III
    peak = np.argmax(x)
    back = (t > t[peak]) & (t <= 1.0)
    masing = f[peak] - 2 * np.interp((x[peak] - x[back]) / 2, bu, bf)
    np.testing.assert_allclose(f[back], masing, rtol=0, atol=1e-10)
    assert x[-1] < -0.99 * amp and f[-1] < -0.99 * f[peak]  # the whole way back


M = 1e5  # the rigid mass on the bearing, kg


def record(seconds: float, pga: float, seed: int = 13) -> tuple[np.ndarray, np.ndarray]:
    import scipy.signal

    n = round(seconds / DT) + 1
    rng = np.random.default_rng(seed)
    t = DT * np.arange(n)
    b, a = scipy.signal.butter(4, [0.1, 4.0], btype="band", fs=1 / DT)
    env = np.minimum(t / 2.0, 1.0) * np.exp(-np.maximum(t - 8.0, 0.0) / 4.0)
    x = env * scipy.signal.lfilter(b, a, rng.normal(size=n))
    return t, pga * G * x / np.abs(x).max()


def ours(k: int, records: list[np.ndarray], t: np.ndarray, method: object = None) -> np.ndarray:
    """The rigid mass on the bearing (uniaxial for one record, bidirectional for two)."""
    n = len(records)
    s = duhamel.System(M * np.eye(n), np.zeros((n, n)))
    s.add(bearing(*range(n), weight=M * G))
    for d, a in enumerate(records):
        s.add_load(L.BaseAcceleration(np.eye(n)[d], t=t, values=a))
    method = method or duhamel.Semianalytic()
    return duhamel.solve(s, method, t_end=t[-1], dt=DT / k, save_every=k).x


def opensees(k: int, records: list[np.ndarray], t: np.ndarray) -> np.ndarray:
    """The same in OpenSees: ``TripleFrictionPendulum`` (Coulomb friction) under the
    gravity load ``W = M g`` on a stiff vertical material, the mass free in x (and y)."""
    ops = pytest.importorskip("openseespy.opensees")
    n = len(records)
    w = M * G
    path = os.path.join(tempfile.mkdtemp(), "disp.out")
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    ops.node(1, 0.0, 0.0, 0.0)
    ops.node(2, 0.0, 0.0, 0.0)
    ops.fix(1, 1, 1, 1, 1, 1, 1)
    ops.fix(2, 0, 1 if n == 1 else 0, 0, 1, 1, 1)
    ops.mass(2, M, M, 0.0, 0.0, 0.0, 0.0)
    for tag, mu in enumerate(MU, start=1):
        ops.frictionModel("Coulomb", tag, mu)
    ops.uniaxialMaterial("Elastic", 1, 1e12)  # axial (compression) stiffness
    ops.uniaxialMaterial("Elastic", 2, 1e10)  # the rotations (fixed)
    ops.element(
        "TripleFrictionPendulum", 1, 1, 2, 1, 2, 3, 1, 2, 2, 2,
        *RADIUS, *CAPACITY, w, 5e-4, 1.0, 0.1, 1e-10,
    )  # fmt: skip
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    ops.load(2, 0.0, 0.0, -w, 0.0, 0.0, 0.0)
    for name, *args in (
        ("constraints", "Plain"),
        ("numberer", "Plain"),
        ("system", "BandGeneral"),
        ("test", "NormDispIncr", 1e-12, 50),
        ("algorithm", "Newton"),
        ("integrator", "LoadControl", 0.1),
        ("analysis", "Static"),
    ):
        getattr(ops, name)(*args)
    ops.analyze(10)
    ops.loadConst("-time", 0.0)
    ops.wipeAnalysis()
    for d, a in enumerate(records):
        ops.timeSeries("Path", 2 + d, "-dt", DT, "-values", *a.tolist())
        ops.pattern("UniformExcitation", 2 + d, 1 + d, "-accel", 2 + d)
    for name, *args in (
        ("constraints", "Plain"),
        ("numberer", "Plain"),
        ("system", "BandGeneral"),
        # the element solves its series model to a relative 1e-10 of the increment: a
        # tighter test than 1e-7 m stalls on it
        ("test", "NormDispIncr", 1e-7, 100),
        ("algorithm", "Newton"),
        ("integrator", "Newmark", 0.5, 0.25),
        ("analysis", "Transient"),
    ):
        getattr(ops, name)(*args)
    ops.recorder("Node", "-file", path, "-node", 2, "-dof", *range(1, n + 1), "disp")
    assert ops.analyze((t.size - 1) * k, DT / k) == 0
    ops.wipe()
    x = np.loadtxt(path).reshape(-1, n)
    return np.concatenate([np.zeros((1, n)), x[k - 1 :: k]])[: t.size]


def test_uniaxial_against_opensees() -> None:
    # 0.5 g: the bearing reaches regime IV (surface 2 on its stop, |u| > 0.61 m). Both runs
    # converged (dt = 0.005 / 4: ours moves by 1e-5 of the peak from dt / 4 to dt / 16,
    # OpenSees' by 4e-4, its Newton tolerance accumulating), within 0.5 % of the peak.
    t, a = record(20.0, 0.5)
    x = ours(4, [a], t)[:, 0]
    ref = opensees(4, [a], t)[:, 0]
    peak = np.abs(x).max()
    assert peak > 0.62
    assert np.abs(x - ref).max() <= 5e-3 * peak


def test_bidirectional_against_opensees() -> None:
    t, ax = record(15.0, 0.4, seed=13)
    _, ay = record(15.0, 0.3, seed=29)
    x = ours(4, [ax, ay], t)
    ref = opensees(4, [ax, ay], t)
    peak = np.hypot(x[:, 0], x[:, 1]).max()
    assert peak > 0.3  # regime III
    assert np.abs(x - ref).max() <= 5e-3 * peak
    # coupled: the same bearing excited along x alone is not the uniaxial response to x
    # plus one to y
    alone = ours(4, [ax], t)[:, 0]
    assert np.abs(alone - x[:, 0]).max() > 0.05 * peak


@pytest.mark.parametrize(
    "method", [duhamel.Semianalytic(), duhamel.Newmark()], ids=["semianalytic", "newmark"]
)
def test_converges_with_dt(method: object) -> None:
    # the error against a run at dt / 64 falls at about second order on average (friction
    # makes the force's rate jump at each stick-slip and stage change: the order per
    # halving varies between 1 and 3)
    t, a = record(20.0, 0.5)
    ref = ours(64, [a], t)[:, 0]
    peak = np.abs(ref).max()
    ks = np.array([1, 2, 4, 8, 16])
    errors = [np.abs(ours(k, [a], t, method)[:, 0] - ref).max() / peak for k in ks]
    slope = np.polyfit(np.log(1.0 / ks), np.log(errors), 1)[0]  # the order
    assert slope > 1.6, (errors, slope)
    assert errors[0] < 2e-4 and errors[-1] < 1e-6


def test_input_is_checked() -> None:
    ok = {"mu": MU, "radius": RADIUS, "displacement_capacity": CAPACITY, "weight": 1.0}
    bad = [
        ({"mu": (0.06, 0.02, 0.1)}, "`mu` must be ordered"),
        ({"mu": (0.02, 0.1, 0.06)}, "`mu` must be ordered"),
        ({"mu": (0.0, 0.02, 0.1)}, "`mu` must be > 0"),
        ({"mu": (0.02, 0.06)}, "`mu` must hold three"),
        ({"radius": (2.0, 1.0, 3.0)}, "`radius`"),
        ({"radius": (0.3, 2.0, float("nan"))}, "`radius`"),
        ({"displacement_capacity": (0.05, -0.3, 0.3)}, "`displacement_capacity` must be > 0"),
        ({"weight": 0.0}, "`weight`"),
        ({"yield_displacement": 0.1}, "`yield_displacement` must be below"),
    ]
    for change, message in bad:
        with pytest.raises(ValueError, match=message):
            E.TripleFrictionPendulum(0, **{**ok, **change})
    with pytest.raises(TypeError):
        E.TripleFrictionPendulum((0, 1), (0.02, 0.06, 0.1))  # the surfaces are keywords
    s = duhamel.System(np.eye(2), np.eye(2))
    with pytest.raises(ValueError, match="`dof_y`"):  # the second axis, dofs[1]
        s.add(E.TripleFrictionPendulum((0, 0), **ok))
    with pytest.raises(ValueError, match="`dofs`"):
        s.add(E.TripleFrictionPendulum(4, **ok))

"""The uniaxial and velocity-dependent friction pendulum (issue 27): the bidirectional
bearing on a line, the friction law, and OpenSees ``singleFPBearing`` (planar, Coulomb and
VelDependent friction) on a rigid mass under a record."""

from __future__ import annotations

import os
import tempfile

import numpy as np
import pytest

import duhamel
from duhamel import elements as E
from duhamel import loads as L

M, G, R, MU, UY = 1e5, 9.81, 2.0, 0.05, 2.5e-4
DT = 0.005


def record(seconds: float) -> tuple[np.ndarray, np.ndarray]:
    import scipy.signal

    n = round(seconds / DT) + 1
    rng = np.random.default_rng(13)
    t = DT * np.arange(n)
    b, a = scipy.signal.butter(4, [0.3, 8.0], btype="band", fs=1 / DT)
    env = np.minimum(t / 2.0, 1.0) * np.exp(-np.maximum(t - 8.0, 0.0) / 4.0)
    x = env * scipy.signal.lfilter(b, a, rng.normal(size=n))
    return t, 0.4 * G * x / np.abs(x).max()


def plane(k: int, seconds: float, **friction: float) -> np.ndarray:
    t, a = record(seconds)
    s = duhamel.System(M * np.eye(1), np.zeros((1, 1)))
    s.add(E.FrictionPendulum(0, radius=R, mu=MU, weight=M * G, yield_displacement=UY, **friction))
    s.add_load(L.BaseAcceleration(np.ones(1), t=t, values=a))
    return duhamel.solve(s, duhamel.Semianalytic(), t_end=t[-1], dt=DT / k, save_every=k).x[:, 0]


def opensees(k: int, seconds: float, friction: tuple) -> np.ndarray:
    ops = pytest.importorskip("openseespy.opensees")
    t, a = record(seconds)
    w = M * G
    path = os.path.join(tempfile.mkdtemp(), "disp.out")
    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    ops.node(1, 0.0, 0.0)
    ops.node(2, 0.0, 0.0)
    ops.fix(1, 1, 1, 1)
    ops.fix(2, 0, 0, 1)
    ops.mass(2, M, M, 0.0)
    ops.frictionModel(*friction)
    ops.uniaxialMaterial("Elastic", 1, 1e12)
    ops.uniaxialMaterial("Elastic", 2, 1e12)
    ops.element(
        "singleFPBearing", 1, 1, 2, 1, R, MU * w / UY, "-P", 1, "-Mz", 2,
        "-orient", 0, 1, 0, -1, 0, 0, "-iter", 100, 1e-8,
    )  # fmt: skip
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    ops.load(2, 0.0, -w, 0.0)
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
    ops.timeSeries("Path", 2, "-dt", DT, "-values", *a.tolist())
    ops.pattern("UniformExcitation", 2, 1, "-accel", 2)
    for name, *args in (
        ("constraints", "Plain"),
        ("numberer", "Plain"),
        ("system", "BandGeneral"),
        ("test", "NormDispIncr", 1e-12, 50),
        ("algorithm", "Newton"),
        ("integrator", "Newmark", 0.5, 0.25),
        ("analysis", "Transient"),
    ):
        getattr(ops, name)(*args)
    ops.recorder("Node", "-file", path, "-node", 2, "-dof", 1, "disp")
    assert ops.analyze((t.size - 1) * k, DT / k) == 0
    ops.wipe()
    x = np.loadtxt(path).reshape(-1)
    return np.concatenate([[0.0], x[k - 1 :: k]])[: t.size]


def test_uniaxial_is_the_bidirectional_bearing_excited_along_x() -> None:
    t, a = record(6.0)
    one = duhamel.System(M * np.eye(1), np.zeros((1, 1)))
    one.add(E.FrictionPendulum(0, radius=R, mu=MU, weight=M * G))
    one.add_load(L.BaseAcceleration(np.ones(1), t=t, values=a))
    two = duhamel.System(M * np.eye(2), np.zeros((2, 2)))
    two.add(E.FrictionPendulum((0, 1), radius=R, mu=MU, weight=M * G))
    two.add_load(L.BaseAcceleration(np.array([1.0, 0.0]), t=t, values=a))
    # The same element either way, compared on the same steps: the accuracy substeps of a
    # stiff element (docs/nonlinear.md) follow the tangent's largest eigenvalue, which the
    # bidirectional bearing keeps large across the slip (friction's tangent normal to it)
    # while the uniaxial one drops to W / R, so the two are subdivided differently; both
    # runs here stay below the stability limit (omega_c dt = 0.22 sticking).
    plain = duhamel.Semianalytic(subdivisions=0)
    x1 = duhamel.solve(one, plain, t_end=6.0, dt=0.005).x[:, 0]
    x2 = duhamel.solve(two, plain, t_end=6.0, dt=0.005).x[:, 0]
    np.testing.assert_allclose(x1, x2, rtol=0, atol=1e-12 * np.abs(x2).max())
    newmark = duhamel.solve(one, duhamel.Newmark(), t_end=6.0, dt=0.001, save_every=5).x[:, 0]
    assert np.abs(newmark - x1).max() < 2e-3 * np.abs(x1).max()


def test_velocity_dependent_friction_force_and_checks() -> None:
    # sliding at speed s: the force is (W / R) u + mu(s) W sgn(u')
    fps = E.FrictionPendulum(0, radius=R, mu=0.06, mu_slow=0.02, rate=10.0, weight=M * G)
    s = duhamel.System(M * np.eye(1), np.zeros((1, 1))).add(fps)
    s.add_load(L.Step(0, amplitude=0.5 * M * G))  # pushes it into sliding
    sol = duhamel.solve(s, duhamel.Semianalytic(), t_end=1.5, dt=0.0005)
    h = sol.elements[0]
    sliding = np.abs(h.v[:, 0]) > 0.05
    speed = np.abs(h.v[sliding, 0])
    mu = 0.06 - 0.04 * np.exp(-10.0 * speed)
    friction = h.force[sliding, 0] - (M * G / R) * h.x[sliding, 0]
    np.testing.assert_allclose(friction, np.sign(h.v[sliding, 0]) * mu * M * G, rtol=1e-9)
    with pytest.raises(ValueError, match="`mu_slow`"):
        E.FrictionPendulum(0, mu=0.02, mu_slow=0.05)
    with pytest.raises(ValueError, match="`rate`"):
        E.FrictionPendulum(0, mu=0.05, mu_slow=0.02, rate=-1.0)
    bad = duhamel.System(np.eye(2), np.eye(2))
    with pytest.raises(ValueError, match="`dof_y`"):  # the second axis, dofs[1]
        bad.add(E.FrictionPendulum((0, 0), radius=1.0, mu=0.05, weight=1.0))
    with pytest.raises(ValueError, match="`dofs`"):
        bad.add(E.FrictionPendulum(5, radius=1.0, mu=0.05, weight=1.0))


@pytest.mark.parametrize(
    "friction, opensees_model",
    [
        ({}, ("Coulomb", 1, MU)),
        ({"mu_slow": 0.025, "rate": 20.0}, ("VelDependent", 1, 0.025, MU, 20.0)),
    ],
)
def test_against_opensees_single_fp_bearing(friction: dict, opensees_model: tuple) -> None:
    # converged runs (dt = 0.005 / 16, discretisation error below 2e-4 of the peak in both
    # codes) within 0.5 % of the peak displacement
    ours = plane(16, 10.0, **friction)
    theirs = opensees(16, 10.0, opensees_model)
    peak = np.abs(ours).max()
    assert peak > 0.02  # it slides
    assert np.abs(ours - theirs).max() <= 5e-3 * peak
